//! planner-runner's integration tests, one test binary (`cargo test -p planner-runner --test it`): each
//! module is a file of this directory that used to be a test binary of its own. A new
//! test file here is declared below (`mod NAME;`), or tidy refuses it (ARCHITECTURE.md,
//! "Tests").

mod common;

mod boundary;
mod conformance;
mod frames;
mod interrupt;
mod large;
mod memory;
mod parquet;
mod provenance;
mod reliability;
mod resume;
mod slurm;
mod writes;
