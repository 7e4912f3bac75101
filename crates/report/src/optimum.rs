//! Lengths against the optima a Moving AI scenario file states.

use crate::{Context, Section};

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

    /// From one pass over the records ([`crate::streamed::optimum_table`]).
    fn table(&self) -> Option<crate::PassesTable> {
        Some(crate::streamed::optimum_table)
    }
}

/// The section's title and text.
pub const HEAD: &str = "## Lengths against the scenario optima

Per planner and map, over every run, repeats included: runs with a stated optimum, how many found a path, how many of those have the optimal Euclidean length (relative tolerance 1e-4), and the largest excess over the optimum. Only 8-connected octile planners without corner cutting solve the problem the optima are for.

";

/// The section's note when some map with stated optima has cell costs (its runs are left
/// out of the table).
pub const WEIGHTED: &str =
    "Maps with cell costs are not compared: the scenario optima are unweighted lengths.

";

/// Whether map `map` has stated optima and cell costs, so that the table leaves it out.
pub fn left_out(map: &planner_runner::config::MapEntry) -> bool {
    map.grid.is_weighted() && map.problems.iter().any(|p| p.optimal_length.is_some())
}

/// The table's head.
pub const TABLE_HEAD: &str = "| Algorithm | Map | Runs | Found | Optimal | Largest excess |
|---|---|---:|---:|---:|---:|
";
