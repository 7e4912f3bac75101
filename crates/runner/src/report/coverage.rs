//! Seed 004's coverage table: one row per map, problem and coverage planner.

use std::fmt::Write as _;

use super::{Context, Reproduction, Section};
use crate::config::PlannerSpec;

/// The coverage table (section name `coverage`).
pub struct Coverage;

impl Section for Coverage {
    fn name(&self) -> &'static str {
        "coverage"
    }

    /// When the experiment has a coverage planner.
    fn applies(&self, context: &Context<'_>) -> bool {
        context.experiment.planners.iter().any(|p| p.is_coverage())
    }

    fn render(&self, context: &Context<'_>, out: &mut String, _reproduction: &mut Reproduction) {
        out.push_str(&summary(context));
    }
}

/// The coverage table of `summary.md`: one row per map, problem and coverage planner;
/// empty when the experiment has no coverage planner.
fn summary(context: &Context<'_>) -> String {
    let experiment = context.experiment;
    let planners: Vec<&PlannerSpec> = experiment
        .planners
        .iter()
        .filter(|p| p.is_coverage())
        .collect();
    let mut out = String::from("## Coverage (seed 004)\n\n");
    out.push_str("Coverage is covered / reachable free cells (4-connected to the start); backtracking points are the returns to one (seed 004 Fig. 8 counts three for spiral and two for zigzag on its map); marked are all points ever marked; length is the Euclidean length of the whole path; A* expansions are those of the returns.\n\n");
    out.push_str("| Map | Start | Planner | Status | Coverage | Reachable | Backtracking points | Marked | Moves | Length | Turns | Revisits | Return moves | A* expansions |\n|---|---|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n");
    for map in &experiment.maps {
        for problem in &map.problems {
            for planner in &planners {
                let Some(r) = context
                    .index
                    .first(&map.name, problem.index, &planner.label)
                else {
                    continue;
                };
                let c = |name: &str| {
                    r.counters
                        .get(name)
                        .map_or_else(|| "-".to_string(), |v| v.to_string())
                };
                let coverage = match (r.counters.get("n_covered"), r.counters.get("n_reachable")) {
                    (Some(covered), Some(reachable)) if reachable > 0 => {
                        format!("{:.1} %", 100.0 * covered as f64 / reachable as f64)
                    }
                    _ => "-".into(),
                };
                let _ = writeln!(
                    out,
                    "| {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} |",
                    map.name,
                    problem.start,
                    planner.label,
                    r.status.as_str(),
                    coverage,
                    c("n_reachable"),
                    c("n_backtracking_points"),
                    c("n_marked_points"),
                    r.steps.map_or("-".into(), |v| v.to_string()),
                    r.length.map_or("-".into(), |v| format!("{v:.2}")),
                    c("n_turns"),
                    c("n_revisits"),
                    c("n_return_moves"),
                    c("n_return_expansions"),
                );
            }
        }
    }
    out.push('\n');
    out
}
