//! Lengths against the optima a Moving AI scenario file states.

use std::fmt::Write as _;

use crate::md_cell;
use crate::{Context, Reproduction, Section};
use planner_runner::record::RunRecord;

/// Relative tolerance for comparing a length with a scenario file's stated optimum: the
/// older Moving AI files round it to 5-6 significant digits.
pub const OPTIMUM_TOLERANCE: f64 = 1e-4;

/// Whether `length` equals the scenario optimum `optimal` within [`OPTIMUM_TOLERANCE`].
pub fn matches_optimum(length: f64, optimal: f64) -> bool {
    (length - optimal).abs() <= OPTIMUM_TOLERANCE * optimal.abs().max(1.0)
}

/// The optimum table (section name `optimum`).
pub struct Optimum;

impl Section for Optimum {
    fn name(&self) -> &'static str {
        "optimum"
    }

    /// When some problem states an optimal length.
    fn applies(&self, context: &Context<'_>) -> bool {
        context
            .experiment
            .maps
            .iter()
            .flat_map(|m| &m.problems)
            .any(|p| p.optimal_length.is_some())
    }

    fn render(&self, context: &Context<'_>, out: &mut String, _reproduction: &mut Reproduction) {
        out.push_str(&optimum_table(context));
    }

    /// From one pass over the records ([`crate::streamed::optimum_table`]).
    fn render_passes(
        &self,
        context: &Context<'_>,
        out: &mut String,
        _reproduction: &mut Reproduction,
    ) -> Result<(), planner_runner::RunnerError> {
        out.push_str(&crate::streamed::optimum_table(
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
pub(crate) const HEAD: &str = "## Lengths against the scenario optima

Per planner and map: runs with a stated optimum, how many found a path, how many of those have the optimal Euclidean length (relative tolerance 1e-4), and the largest excess over the optimum. Only 8-connected octile planners without corner cutting solve the problem the optima are for.

| Algorithm | Map | Runs | Found | Optimal | Largest excess |
|---|---|---:|---:|---:|---:|
";

fn optimum_table(context: &Context<'_>) -> String {
    let experiment = context.experiment;
    let mut out = String::from(HEAD);
    for planner in &experiment.planners {
        for map in &experiment.maps {
            let runs: Vec<&RunRecord> = map
                .problems
                .iter()
                .filter_map(|p| context.index.first(&map.name, p.index, &planner.label))
                .filter(|r| r.optimal_length.is_some())
                .collect();
            if runs.is_empty() {
                continue;
            }
            let found: Vec<(f64, f64)> = runs
                .iter()
                .filter_map(|r| Some((r.length?, r.optimal_length?)))
                .collect();
            let optimal = found
                .iter()
                .filter(|(l, o)| matches_optimum(*l, *o))
                .count();
            let excess = found
                .iter()
                .map(|(l, o)| (l - o) / o.max(1.0))
                .fold(0.0f64, f64::max);
            let _ = writeln!(
                out,
                "| {} | {} | {} | {} | {} | {:.2} % |",
                md_cell(&planner.label),
                md_cell(&map.name),
                runs.len(),
                found.len(),
                optimal,
                100.0 * excess
            );
        }
    }
    out.push('\n');
    out
}
