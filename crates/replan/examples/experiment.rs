//! Runs a `navigate` or `dynamic` experiment config (planner-replan's experiment kinds)
//! and writes its results directory; what the CLI's and xtask's command will call.
//!
//! ```text
//! cargo run --release -p planner-replan --example experiment -- configs/replan/navigate.toml \
//!     [--output results/navigate] [--timing] [--test] [--threads 0]
//! ```
//!
//! Exits with status 1 when a replan failed its check.

use std::path::PathBuf;

use planner_replan::args::Args;
use planner_replan::experiment::{run, RunOptions};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let first = std::env::args().nth(1);
    let args = Args::from_env();
    let Some(config) = first.filter(|a| !a.starts_with("--")) else {
        return Err(
            "usage: experiment <config.toml> [--output DIR] [--timing] [--test] [--threads N]"
                .into(),
        );
    };
    let config = PathBuf::from(config);
    let output = match args.value("--output", "") {
        "" => PathBuf::from("results").join(
            config
                .file_stem()
                .map_or_else(|| "replan".into(), |s| s.to_string_lossy().into_owned()),
        ),
        dir => PathBuf::from(dir),
    };
    let options = RunOptions {
        test: args.flag("--test"),
        timing: args.flag("--timing"),
        threads: args.parsed("--threads", "0")?,
        stop: None,
    };
    let done = run(&config, &output, &options)?;
    println!(
        "{}: {} runs, {} replans checked, {} mismatches; wrote {}",
        done.name,
        done.runs,
        done.replans,
        done.mismatches,
        output.display()
    );
    if done.mismatches > 0 {
        std::process::exit(1);
    }
    Ok(())
}
