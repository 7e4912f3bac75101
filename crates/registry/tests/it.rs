//! planner-registry's integration tests, one binary.

mod ranges;
