//! `gridplan`: the installable command line (`cargo install --path crates/cli`).

use std::process::ExitCode;

#[global_allocator]
static ALLOCATOR: planner_runner::alloc::Counting = planner_runner::alloc::Counting;

fn main() -> ExitCode {
    gridplan::init_logging();
    // The lock files this process takes name it (the runner reads no process state).
    planner_runner::outdir::set_lock_holder(std::process::id());
    // `--help` and `--version` are written as every output is, their write errors said.
    match gridplan::parse() {
        Ok(command) => gridplan::exit(gridplan::run(command)),
        Err(code) => code,
    }
}
