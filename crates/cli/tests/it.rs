//! gridplan's integration tests, one test binary (`cargo test -p gridplan --test it`): each
//! module is a file of this directory that used to be a test binary of its own. A new
//! test file here is declared below (`mod NAME;`), or tidy refuses it (ARCHITECTURE.md,
//! "Tests").

mod careless;
mod common;
mod costs;
mod exit_codes;
mod frame;
mod install;
mod published;
mod schema;
mod security;
