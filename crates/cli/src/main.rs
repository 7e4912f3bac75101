//! `gridplan`: the installable command line (`cargo install --path crates/cli`).

use std::process::ExitCode;

use clap::Parser as _;

#[global_allocator]
static ALLOCATOR: planner_runner::alloc::Counting = planner_runner::alloc::Counting;

fn main() -> ExitCode {
    gridplan::init_logging();
    // The lock files this process takes name it (the runner reads no process state).
    planner_runner::outdir::set_lock_holder(std::process::id());
    gridplan::exit(gridplan::run(gridplan::Cli::parse().command))
}
