//! Seed 000's Tables 3-8: one table per planner and map size, metric rows (Steps, Turns,
//! Score, then every counter in the planner's order), one column per map and problem.
//! With `published` set, each cell shows the measured value and a mark: `✓` when it
//! equals the published one, `✗ (published P)` when not.

use std::fmt::Write as _;

use planner_report::{md_cell, md_code};
use planner_report::{Context, Reproduction, Section, MAX_COLUMNS};
use planner_runner::config::map_stem;
use planner_runner::record::RunRecord;

/// Seed 000's quality and search-effort tables (section name `seed000`).
pub struct Seed000;

impl Section for Seed000 {
    fn name(&self) -> &'static str {
        "seed000"
    }

    /// Never by itself: a paper layout shows when a config names it (maps with too many
    /// problems then get a one-line note instead).
    fn applies(&self, _context: &Context<'_>) -> bool {
        false
    }

    fn render(&self, context: &Context<'_>, out: &mut String, reproduction: &mut Reproduction) {
        let quality = quality_tables(context, reproduction);
        if let Some(published) = &context.experiment.published {
            let _ = writeln!(
                out,
                "**Published numbers reproduced: {} of {}** (from {}; ✓ equal, ✗ different).\n",
                reproduction.matched,
                reproduction.compared,
                md_code(&published.path.display().to_string())
            );
        }
        out.push_str(&quality);
    }
}

fn quality_tables(context: &Context<'_>, reproduction: &mut Reproduction) -> String {
    let experiment = context.experiment;
    let mut out =
        String::from("## Path quality and search effort (seed 000, Tables 3-8 layout)\n\n");
    let mut sizes: Vec<(u32, u32)> = Vec::new();
    for map in &experiment.maps {
        let size = (map.grid.width(), map.grid.height());
        if !sizes.contains(&size) {
            sizes.push(size);
        }
    }
    let mut any = false;
    for planner in &experiment.planners {
        for &(w, h) in &sizes {
            let columns: Vec<(&str, usize)> = experiment
                .maps
                .iter()
                .filter(|m| (m.grid.width(), m.grid.height()) == (w, h))
                .flat_map(|m| m.problems.iter().map(move |p| (m.name.as_str(), p.index)))
                .collect();
            if columns.is_empty() || columns.len() > MAX_COLUMNS {
                continue;
            }
            any = true;
            let single = experiment
                .maps
                .iter()
                .filter(|m| (m.grid.width(), m.grid.height()) == (w, h))
                .all(|m| m.problems.len() == 1);
            let _ = writeln!(
                out,
                "### {} ({}) on {w}x{h} maps\n",
                md_cell(&planner.label),
                planner.name
            );
            out.push_str("| Metric |");
            for (map, problem) in &columns {
                if single {
                    let _ = write!(out, " {} |", md_cell(map_stem(map)));
                } else {
                    let _ = write!(out, " {} #{problem} |", md_cell(map_stem(map)));
                }
            }
            out.push_str("\n|---|");
            out.push_str(&"---:|".repeat(columns.len()));
            out.push('\n');
            let mut metrics: Vec<String> = ["status", "steps", "turns", "score", "length"]
                .map(String::from)
                .to_vec();
            for (map, problem) in &columns {
                if let Some(r) = context.index.first(map, *problem, &planner.label) {
                    for (name, _) in r.counters.iter() {
                        if !metrics.iter().any(|m| m == name) {
                            metrics.push(name.to_string());
                        }
                    }
                }
            }
            for metric in &metrics {
                let _ = write!(out, "| {metric} |");
                for (map, problem) in &columns {
                    let cell = match context.index.first(map, *problem, &planner.label) {
                        Some(r) => {
                            let value = metric_value(r, metric);
                            let published = experiment
                                .published
                                .as_ref()
                                .zip(planner.published_key(metric))
                                .and_then(|(p, key)| {
                                    p.get_problem(map_stem(map), *problem, key, metric)
                                });
                            mark(value, published, metric, reproduction)
                        }
                        None => "-".into(),
                    };
                    let _ = write!(out, " {cell} |");
                }
                out.push('\n');
            }
            out.push('\n');
        }
    }
    if !any {
        out.push_str("(Too many problems per map size for this layout; see runs.csv.)\n\n");
    }
    out
}

/// The value of `metric` in `record` as text: `status`, a path metric or a counter.
fn metric_value(record: &RunRecord, metric: &str) -> Option<String> {
    match metric {
        "status" => Some(record.status.to_string()),
        "steps" => record.steps.map(|v| v.to_string()),
        "turns" => record.turns.map(|v| v.to_string()),
        "score" => record.score.map(|v| v.to_string()),
        "length" => record.length.map(|v| format!("{v:.2}")),
        counter => record.counters.get(counter).map(|v| v.to_string()),
    }
}

fn mark(
    value: Option<String>,
    published: Option<f64>,
    metric: &str,
    reproduction: &mut Reproduction,
) -> String {
    let text = value.clone().unwrap_or_else(|| "-".into());
    let Some(published) = published else {
        return text;
    };
    reproduction.compared += 1;
    let equal = value.and_then(|v| v.parse::<f64>().ok()).is_some_and(|v| {
        (v - published).abs() < 1e-9 || (metric == "length" && (v - published).abs() < 5e-3)
    });
    if equal {
        reproduction.matched += 1;
        format!("{text} ✓")
    } else {
        format!("{text} ✗ ({published})")
    }
}
