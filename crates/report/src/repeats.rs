//! Repeated runs: success rate, median length and median time per planner and map.

use std::fmt::Write as _;

use crate::md_cell;
use crate::{median_iqr, Context, Reproduction, Section};
use planner_runner::record::RunRecord;

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

    fn render(&self, context: &Context<'_>, out: &mut String, _reproduction: &mut Reproduction) {
        out.push_str(&repeat_table(context));
    }

    /// From passes over the records ([`crate::streamed::repeats_table`]).
    fn render_passes(
        &self,
        context: &Context<'_>,
        out: &mut String,
        _reproduction: &mut Reproduction,
    ) -> Result<(), planner_runner::RunnerError> {
        out.push_str(&crate::streamed::repeats_table(
            context.experiment,
            context.passes,
        )?);
        Ok(())
    }

    fn streams(&self) -> bool {
        true
    }
}

/// The section's title, text and table head.
pub(crate) fn head(experiment: &planner_runner::config::Experiment) -> String {
    format!(
        "## Repeats ({} per planner and problem)\n\nSuccess rate over all runs on the map; median path length over the successful runs; median time (IQR) over all runs.\n\n| Algorithm | Map | Runs | Success | Median length | Median time ms (IQR) |\n|---|---|---:|---:|---:|---:|\n",
        experiment.repeats
    )
}

fn repeat_table(context: &Context<'_>) -> String {
    let experiment = context.experiment;
    let mut out = head(experiment);
    for planner in &experiment.planners {
        for map in &experiment.maps {
            let runs: Vec<&RunRecord> = map
                .problems
                .iter()
                .flat_map(|p| context.index.runs(&map.name, p.index, &planner.label))
                .filter(|r| !r.is_invalid())
                .collect();
            if runs.is_empty() {
                continue;
            }
            let found: Vec<f64> = runs
                .iter()
                .filter(|r| r.is_found())
                .filter_map(|r| r.length)
                .collect();
            let times: Vec<f64> = runs.iter().map(|r| r.time_ms).collect();
            let length = median_iqr(&found).map_or("-".into(), |(m, _, _)| format!("{m:.2}"));
            let time = median_iqr(&times).map_or("-".into(), |(m, q1, q3)| {
                format!("{m:.4} ({q1:.4}-{q3:.4})")
            });
            let _ = writeln!(
                out,
                "| {} | {} | {} | {:.1} % | {length} | {time} |",
                md_cell(&planner.label),
                md_cell(&map.name),
                runs.len(),
                100.0 * found.len() as f64 / runs.len() as f64,
            );
        }
    }
    out.push('\n');
    out
}
