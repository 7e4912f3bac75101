//! planner-report's integration tests, one test binary (`cargo test -p planner-report --test it`): each
//! module is a file of this directory that used to be a test binary of its own. A new
//! test file here is declared below (`mod NAME;`), or tidy refuses it (ARCHITECTURE.md,
//! "Tests").

mod compare;
mod effort;
mod ompl;
mod oracle;
mod paired;
mod scale;
mod streamed;
mod summary;
