//! Repeated runs: success rate, median length and median time per planner and map.

use crate::{Context, Section};

/// The repeats table (section name `repeats`).
pub struct Repeats;

impl Section for Repeats {
    fn name(&self) -> &'static str {
        "repeats"
    }

    /// When the experiment repeats its runs.
    fn applies(&self, context: &Context<'_>) -> bool {
        context.experiment.repeats > 1
    }

    /// From passes over the records ([`crate::streamed::repeats_table`]).
    fn table(&self) -> Option<crate::PassesTable> {
        Some(crate::streamed::repeats_table)
    }
}

/// The section's title, text and table head.
pub fn head(experiment: &planner_runner::config::Experiment) -> String {
    format!(
        "## Repeats ({} per planner and problem)\n\nSuccess rate over all runs of the map's valid problems (the records of invalid problems, listed under \"Invalid problems (not run)\", are not counted here); median path length over the successful runs; median time (IQR) over all those runs.\n\n| Algorithm | Map | Runs | Success | Median length | Median time ms (IQR) |\n|---|---|---:|---:|---:|---:|\n",
        experiment.repeats
    )
}
