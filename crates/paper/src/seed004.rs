//! Seed 004's coverage table: one row per map, problem and coverage planner.

use std::fmt::Write as _;

use planner_report::md_cell;
use planner_report::{Context, Reproduction, Section};
use planner_runner::config::PlannerSpec;

/// The coverage table (section name `coverage`).
pub struct Coverage;

impl Section for Coverage {
    fn name(&self) -> &'static str {
        "coverage"
    }

    /// Never by itself: a paper layout shows when a config names it.
    fn applies(&self, _context: &Context<'_>) -> bool {
        false
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
                    md_cell(&map.name),
                    problem.start,
                    md_cell(&planner.label),
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
    out.push_str(&means(context, &planners));
    out
}

/// One row per coverage planner: its metrics averaged over every map and problem
/// (repeat 0), so spiral and zigzag compare at a glance.
fn means(context: &Context<'_>, planners: &[&PlannerSpec]) -> String {
    let experiment = context.experiment;
    let mut out = String::from("Mean per planner over every map (repeat 0):

| Planner | Maps | Coverage | Backtracking points | Marked | Moves | Length | Turns | Revisits | Return moves | A* expansions |\n|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n");
    for planner in planners {
        let runs: Vec<&planner_runner::record::RunRecord> = experiment
            .maps
            .iter()
            .flat_map(|m| {
                m.problems
                    .iter()
                    .filter_map(|p| context.index.first(&m.name, p.index, &planner.label))
            })
            .filter(|r| !r.is_invalid())
            .collect();
        if runs.is_empty() {
            continue;
        }
        let mean = |value: &dyn Fn(&planner_runner::record::RunRecord) -> Option<f64>| {
            let values: Vec<f64> = runs.iter().filter_map(|r| value(r)).collect();
            if values.is_empty() {
                "-".to_string()
            } else {
                format!("{:.2}", values.iter().sum::<f64>() / values.len() as f64)
            }
        };
        let counter = |name: &'static str| {
            mean(&move |r: &planner_runner::record::RunRecord| {
                r.counters.get(name).map(|v| v as f64)
            })
        };
        let coverage = mean(
            &|r| match (r.counters.get("n_covered"), r.counters.get("n_reachable")) {
                (Some(covered), Some(reachable)) if reachable > 0 => {
                    Some(100.0 * covered as f64 / reachable as f64)
                }
                _ => None,
            },
        );
        let _ = writeln!(
            out,
            "| {} | {} | {} % | {} | {} | {} | {} | {} | {} | {} | {} |",
            md_cell(&planner.label),
            runs.len(),
            coverage,
            counter("n_backtracking_points"),
            counter("n_marked_points"),
            mean(&|r| r.steps.map(|v| v as f64)),
            mean(&|r| r.length),
            counter("n_turns"),
            counter("n_revisits"),
            counter("n_return_moves"),
            counter("n_return_expansions"),
        );
    }
    out.push('\n');
    out
}
