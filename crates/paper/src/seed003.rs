//! Seed 003's Tables I-II: per map, one row per planner and problem with time, peak heap
//! and path length.

use std::fmt::Write as _;

use planner_report::md_cell;
use planner_report::{median_iqr, Context, Reproduction, Section, MAX_COLUMNS};

/// Seed 003's time, memory and length tables (section name `seed003`).
pub struct Seed003;

impl Section for Seed003 {
    fn name(&self) -> &'static str {
        "seed003"
    }

    /// Never by itself: a paper layout shows when a config names it (maps with too many
    /// problems then get a one-line note instead).
    fn applies(&self, _context: &Context<'_>) -> bool {
        false
    }

    fn render(&self, context: &Context<'_>, out: &mut String, _reproduction: &mut Reproduction) {
        out.push_str(&time_tables(context));
    }
}

fn time_tables(context: &Context<'_>) -> String {
    let experiment = context.experiment;
    let mut out =
        String::from("## Time, memory and path length (seed 003, Tables I-II layout)\n\n");
    out.push_str("Time is the median (interquartile range) of the search alone (`plan`) over repeats, without building the planner or its per-grid tables (`setup_ms` in runs.csv); peak heap is what the planner held after its setup for the map plus the peak its search added, by a counting allocator.\n\n");
    for map in &experiment.maps {
        if map.problems.len() > MAX_COLUMNS {
            let _ = writeln!(
                out,
                "{}: {} problems, see runs.csv.\n",
                md_cell(&map.name),
                map.problems.len()
            );
            continue;
        }
        let _ = writeln!(
            out,
            "### {} ({}x{})\n",
            md_cell(&map.name),
            map.grid.width(),
            map.grid.height()
        );
        out.push_str("| Algorithm | Problem | Status | Time ms | Peak heap KiB | Path length (steps) | Euclidean length | Expanded |\n|---|---|---|---:|---:|---:|---:|---:|\n");
        for planner in &experiment.planners {
            for problem in &map.problems {
                let runs = context.index.runs(&map.name, problem.index, &planner.label);
                let Some(r0) = runs.first() else { continue };
                let times: Vec<f64> = runs.iter().map(|r| r.time_ms).collect();
                let heap: Vec<f64> = runs
                    .iter()
                    .map(|r| r.peak_heap_bytes as f64 / 1024.0)
                    .collect();
                let time = median_iqr(&times)
                    .map(|(m, q1, q3)| format!("{m:.4} ({q1:.4}-{q3:.4})"))
                    .unwrap_or_default();
                let heap = median_iqr(&heap)
                    .map(|(m, _, _)| format!("{m:.1}"))
                    .unwrap_or_default();
                let _ = writeln!(
                    out,
                    "| {} | {} {} -> {} | {} | {} | {} | {} | {} | {} |",
                    md_cell(&planner.label),
                    problem.index,
                    problem.start,
                    problem.goal,
                    r0.status.as_str(),
                    if r0.is_invalid() { "-".into() } else { time },
                    if r0.is_invalid() { "-".into() } else { heap },
                    r0.steps.map_or("-".into(), |v| v.to_string()),
                    r0.length.map_or("-".into(), |v| format!("{v:.2}")),
                    r0.counters
                        .get("n_expanded")
                        .map_or("-".into(), |v| v.to_string()),
                );
            }
        }
        out.push('\n');
    }
    out
}
