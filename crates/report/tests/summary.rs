//! summary.md's header, from a sweep's records: what the report says about the runs.

use std::path::{Path, PathBuf};

use planner_report::Renderer;
use planner_runner::{config, run_all, RunOptions};

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// Seed 002's TA-star (Manhattan with 8 moves) is recorded as inadmissible, and the
/// summary says such runs are not optimal by design, with no section asked for.
#[test]
fn inadmissible_heuristics_are_named_in_the_summary() {
    let experiment = config::load(&root().join("configs/pastar.toml"))
        .unwrap()
        .trimmed_for_test();
    let records = run_all(&experiment, &RunOptions::default()).unwrap();
    let (summary, _) = Renderer::new(Vec::new())
        .summary(&experiment, &records)
        .unwrap();
    assert!(
        summary.contains("Not optimal by design: `TA-star`"),
        "{summary}"
    );
}
