//! xtask's integration tests, one test binary (`cargo test -p xtask --test it`): each
//! module is a file of this directory that used to be a test binary of its own. A new
//! test file here is declared below (`mod NAME;`), or tidy refuses it (ARCHITECTURE.md,
//! "Tests").

mod capso;
mod common;
mod counters;
mod coverage;
mod output;
mod pastar;
mod sweeps;
