//! planner-theta_star's integration tests, one test binary (`cargo test -p
//! planner-theta_star --test it`): each module is a file of this directory. A new test file
//! here is declared below (`mod NAME;`), or tidy refuses it (ARCHITECTURE.md, "Tests").

mod bound;
mod events;
mod key;
mod reference;
mod sight;
