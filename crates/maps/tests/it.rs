//! planner-maps's integration tests, one test binary (`cargo test -p planner-maps --test it`): each
//! module is a file of this directory that used to be a test binary of its own. A new
//! test file here is declared below (`mod NAME;`), or tidy refuses it (ARCHITECTURE.md,
//! "Tests").

mod common;
mod costs;
mod errors;
mod formats;
mod fuzz_regressions;
mod limits;
mod nav2;
mod real;
mod ros;
mod write;
