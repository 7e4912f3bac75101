//! planner-lexastar's integration tests, one test binary (`cargo test -p planner-lexastar --test it`): each
//! module is a file of this directory that used to be a test binary of its own. A new
//! test file here is declared below (`mod NAME;`), or tidy refuses it (ARCHITECTURE.md,
//! "Tests").

mod brute_force;
mod counters;
mod heuristic;
mod memory;
mod paper_maps;
mod reference;
mod weighted;
