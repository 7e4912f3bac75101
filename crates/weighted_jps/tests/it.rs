//! planner-weighted_jps's integration tests, one test binary (`cargo test -p
//! planner-weighted_jps --test it`): each module is a file of this directory. A new test
//! file here is declared below (`mod NAME;`), or tidy refuses it (ARCHITECTURE.md, "Tests").

mod events;
mod oracle;
mod reference;
