//! `summary.md`: the sweep laid out like the seeds' tables.
//!
//! - Seed 000's Tables 3-8: one table per planner and map size, metric rows (Steps, Turns,
//!   Score, then every counter), one column per map and problem; with `published` set,
//!   each cell shows the measured value and a mark: `✓` when it equals the published
//!   one, `✗ (published P)` when not.
//! - Seed 003's Tables I-II: per map, one row per planner and problem with time, peak heap
//!   and path length.
//! - With repeats: success rate, median length and median time (IQR) per planner and map.
//!
//! Deterministic values come from repeat 0; times are medians over repeats.

use std::fmt::Write as _;

use crate::config::Experiment;
use crate::run::RunRecord;

/// Largest number of map columns in one seed-000 style table.
const MAX_COLUMNS: usize = 12;

/// Counts of compared published numbers.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Reproduction {
    /// Numbers compared.
    pub compared: usize,
    /// Numbers equal to the published value.
    pub matched: usize,
}

/// The median and interquartile range (quartiles by linear interpolation between order
/// statistics, the "type 7" rule of R and numpy's default) of `values`.
pub fn median_iqr(values: &[f64]) -> Option<(f64, f64, f64)> {
    if values.is_empty() {
        return None;
    }
    let mut sorted = values.to_vec();
    sorted.sort_by(f64::total_cmp);
    let q = |p: f64| {
        let h = (sorted.len() - 1) as f64 * p;
        let lo = h.floor() as usize;
        let hi = h.ceil() as usize;
        sorted[lo] + (h - lo as f64) * (sorted[hi] - sorted[lo])
    };
    Some((q(0.5), q(0.25), q(0.75)))
}

/// Renders summary.md and returns it with the reproduction counts.
pub fn render(experiment: &Experiment, records: &[RunRecord]) -> (String, Reproduction) {
    let mut out = String::new();
    let mut reproduction = Reproduction::default();
    let _ = writeln!(out, "# Experiment `{}`\n", experiment.name);
    if let Some(description) = &experiment.description {
        let _ = writeln!(out, "{}\n", description.trim());
    }
    let n_problems: usize = experiment.maps.iter().map(|m| m.problems.len()).sum();
    let _ = writeln!(
        out,
        "Config `{}`: {} maps, {} problems, {} planner configurations, {} repeat(s), {} runs.\n",
        experiment.source.display(),
        experiment.maps.len(),
        n_problems,
        experiment.planners.len(),
        experiment.repeats,
        records.len()
    );
    let invalid: Vec<&RunRecord> = records
        .iter()
        .filter(|r| r.status == "invalid_problem" && r.planner == experiment.planners[0].label)
        .collect();
    if !invalid.is_empty() {
        let _ = writeln!(out, "Invalid problems (not run):\n");
        for r in invalid {
            let _ = writeln!(
                out,
                "- {} problem {} {} -> {}: {}",
                r.map,
                r.problem,
                r.start,
                r.goal,
                r.error.as_deref().unwrap_or("invalid")
            );
        }
        out.push('\n');
    }

    let quality = quality_tables(experiment, records, &mut reproduction);
    if let Some(published) = &experiment.published {
        let _ = writeln!(
            out,
            "**Published numbers reproduced: {} of {}** (from `{}`; ✓ equal, ✗ different).\n",
            reproduction.matched,
            reproduction.compared,
            published.path.display()
        );
    }
    out.push_str(&quality);
    out.push_str(&time_tables(experiment, records));
    if experiment.repeats > 1 {
        out.push_str(&repeat_table(experiment, records));
    }
    out.push_str(&crate::pastar_summary::render(experiment, records));
    (out, reproduction)
}

fn first<'r>(
    records: &'r [RunRecord],
    map: &str,
    problem: usize,
    planner: &str,
) -> Option<&'r RunRecord> {
    records
        .iter()
        .find(|r| r.map == map && r.problem == problem && r.planner == planner && r.repeat == 0)
}

fn map_stem(name: &str) -> &str {
    name.rsplit_once('.').map_or(name, |(stem, _)| stem)
}

fn quality_tables(
    experiment: &Experiment,
    records: &[RunRecord],
    reproduction: &mut Reproduction,
) -> String {
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
                planner.label, planner.name
            );
            out.push_str("| Metric |");
            for (map, problem) in &columns {
                if single {
                    let _ = write!(out, " {} |", map_stem(map));
                } else {
                    let _ = write!(out, " {} #{problem} |", map_stem(map));
                }
            }
            out.push_str("\n|---|");
            out.push_str(&"---:|".repeat(columns.len()));
            out.push('\n');
            let mut metrics: Vec<String> = ["status", "steps", "turns", "score", "length"]
                .map(String::from)
                .to_vec();
            for (map, problem) in &columns {
                if let Some(r) = first(records, map, *problem, &planner.label) {
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
                    let cell = match first(records, map, *problem, &planner.label) {
                        Some(r) => {
                            let value = metric_value(r, metric);
                            let published = experiment
                                .published
                                .as_ref()
                                .and_then(|p| p.get(map_stem(map), planner.name, metric));
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
        "status" => Some(record.status.clone()),
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

fn time_tables(experiment: &Experiment, records: &[RunRecord]) -> String {
    let mut out =
        String::from("## Time, memory and path length (seed 003, Tables I-II layout)\n\n");
    out.push_str("Time is the median (interquartile range) of `plan` over repeats; peak heap is the largest heap use of building the planner and planning, by a counting allocator.\n\n");
    for map in &experiment.maps {
        if map.problems.len() > MAX_COLUMNS {
            let _ = writeln!(
                out,
                "{}: {} problems, see runs.csv.\n",
                map.name,
                map.problems.len()
            );
            continue;
        }
        let _ = writeln!(
            out,
            "### {} ({}x{})\n",
            map.name,
            map.grid.width(),
            map.grid.height()
        );
        out.push_str("| Algorithm | Problem | Status | Time ms | Peak heap KiB | Path length (steps) | Euclidean length | Expanded |\n|---|---|---|---:|---:|---:|---:|---:|\n");
        for planner in &experiment.planners {
            for problem in &map.problems {
                let runs: Vec<&RunRecord> = records
                    .iter()
                    .filter(|r| {
                        r.map == map.name
                            && r.problem == problem.index
                            && r.planner == planner.label
                    })
                    .collect();
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
                    planner.label,
                    problem.index,
                    problem.start,
                    problem.goal,
                    r0.status,
                    if r0.status == "invalid_problem" {
                        "-".into()
                    } else {
                        time
                    },
                    if r0.status == "invalid_problem" {
                        "-".into()
                    } else {
                        heap
                    },
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

fn repeat_table(experiment: &Experiment, records: &[RunRecord]) -> String {
    let mut out = format!(
        "## Repeats ({} per planner and problem)\n\nSuccess rate over all runs on the map; median path length over the successful runs; median time (IQR) over all runs.\n\n",
        experiment.repeats
    );
    out.push_str("| Algorithm | Map | Runs | Success | Median length | Median time ms (IQR) |\n|---|---|---:|---:|---:|---:|\n");
    for planner in &experiment.planners {
        for map in &experiment.maps {
            let runs: Vec<&RunRecord> = records
                .iter()
                .filter(|r| {
                    r.map == map.name && r.planner == planner.label && r.status != "invalid_problem"
                })
                .collect();
            if runs.is_empty() {
                continue;
            }
            let found: Vec<f64> = runs
                .iter()
                .filter(|r| r.status == "found")
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
                planner.label,
                map.name,
                runs.len(),
                100.0 * found.len() as f64 / runs.len() as f64,
            );
        }
    }
    out.push('\n');
    out
}

#[cfg(test)]
mod tests {
    use super::median_iqr;

    #[test]
    fn quartiles_follow_type_7() {
        // numpy.percentile([1, 2, 3, 4], [25, 50, 75]) = [1.75, 2.5, 3.25].
        assert_eq!(median_iqr(&[4.0, 1.0, 3.0, 2.0]), Some((2.5, 1.75, 3.25)));
        assert_eq!(median_iqr(&[7.0]), Some((7.0, 7.0, 7.0)));
        assert_eq!(median_iqr(&[]), None);
    }
}
