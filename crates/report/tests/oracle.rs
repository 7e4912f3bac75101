//! The report's tables computed from the records held in memory (every run of a group
//! collected and sorted): the independent computation the tables from passes
//! (planner_report::streamed) are checked against. Formatting (heads, number formats) is
//! the crate's own; the grouping, counting and quantiles are computed here.

#![allow(dead_code)]

use std::fmt::Write as _;

use planner_report::aggregate::{
    bucket_ranges, costs_note, format_bytes, format_number, parameters, runs_table, Measured,
    COST_HEADER, HEADER, MAX_BUCKET_ROWS, PER_MAP, TIMING_WARNING,
};
use planner_report::optimum::matches_optimum;
use planner_report::{md_cell, median_iqr, Context};
use planner_runner::config::PlannerSpec;
use planner_runner::record::RunRecord;

/// The aggregate section's markdown: parameters, the per-map table, the overall rows, the
/// by-bucket medians of scenario maps, counters and the seeds' spread.
pub fn tables(context: &Context<'_>, measured: Measured) -> String {
    let experiment = context.experiment;
    let mut out = String::from("## Aggregates\n\n");
    out.push_str(&parameters(experiment, measured));
    if experiment.repeats == 1 {
        out.push_str(TIMING_WARNING);
    }
    out.push_str(PER_MAP);
    let costs = experiment.maps.iter().any(|m| m.grid.is_weighted());
    if costs {
        out.push_str(&costs_note(runs_table(experiment, context.passes.len())));
    }
    let header = if costs { COST_HEADER } else { HEADER };
    out.push_str(header);
    for planner in &experiment.planners {
        for map in &experiment.maps {
            let runs = runs_of(
                context,
                planner,
                map.problems.iter().map(|p| p.index),
                &map.name,
            );
            row(
                &mut out,
                context,
                (&planner.label, &map.name),
                &runs,
                measured,
                costs,
            );
        }
    }
    out.push('\n');
    out.push_str("Overall, per planner label: every run of a valid problem on every map.\n\n");
    out.push_str(header);
    for planner in &experiment.planners {
        let runs = label_runs(context, planner);
        row(
            &mut out,
            context,
            (&planner.label, "all"),
            &runs,
            measured,
            costs,
        );
    }
    out.push('\n');
    out.push_str(&by_bucket(context, measured));
    out.push_str(&counters(context));
    out.push_str(&seeds(context));
    out
}

/// One row of the by-bucket tables: the map, the bucket range, and each label's runs in it.
type BucketRow<'r> = (&'r str, (u32, u32), Vec<Vec<&'r RunRecord>>);

/// Scenario maps' medians by bucket (Moving AI's picture of effort against path length):
/// one row per map and bucket range, one column per label; median `n_expanded`, then the
/// median search time.
fn by_bucket(context: &Context<'_>, measured: Measured) -> String {
    let experiment = context.experiment;
    let mut rows: Vec<BucketRow<'_>> = Vec::new();
    for map in &experiment.maps {
        let mut buckets: Vec<u32> = map.problems.iter().filter_map(|p| p.bucket).collect();
        buckets.sort_unstable();
        buckets.dedup();
        for range in bucket_ranges(&buckets) {
            let per_label = experiment
                .planners
                .iter()
                .map(|planner| {
                    let problems = map
                        .problems
                        .iter()
                        .filter(|p| p.bucket.is_some_and(|b| range.0 <= b && b <= range.1))
                        .map(|p| p.index);
                    runs_of(context, planner, problems, &map.name)
                })
                .collect();
            rows.push((&map.name, range, per_label));
        }
    }
    if rows.is_empty() {
        return String::new();
    }
    let labels: Vec<String> = experiment
        .planners
        .iter()
        .map(|p| md_cell(&p.label))
        .collect();
    let head = format!(
        "| Map | Bucket | Runs | {} |\n|---|---|---:|{}\n",
        labels.join(" | "),
        "---:|".repeat(labels.len())
    );
    let mut out = format!("By scenario bucket (a `.scen` bucket holds problems of optimal length 4b to 4b + 4; more than {MAX_BUCKET_ROWS} buckets are grouped into ranges of equal width; every bucket is in {}'s `bucket` column). Median `n_expanded` per label:\n\n{head}", runs_table(experiment, context.passes.len()));
    let table = |out: &mut String, cell: &dyn Fn(&[&RunRecord]) -> String| {
        for (map, (lo, hi), per_label) in &rows {
            let bucket = if lo == hi {
                lo.to_string()
            } else {
                format!("{lo}-{hi}")
            };
            let runs = per_label.iter().map(Vec::len).max().unwrap_or(0);
            let cells: Vec<String> = per_label.iter().map(|r| cell(r)).collect();
            let _ = writeln!(
                out,
                "| {} | {bucket} | {runs} | {} |",
                md_cell(map),
                cells.join(" | ")
            );
        }
        out.push('\n');
    };
    table(&mut out, &|runs| {
        let expansions: Vec<f64> = runs
            .iter()
            .filter_map(|r| r.counters.get("n_expanded"))
            .map(|v| v as f64)
            .collect();
        median_iqr(&expansions).map_or("-".into(), |(m, _, _)| format_number(m))
    });
    out.push_str(&format!("Median search time (ms) per label:\n\n{head}"));
    table(&mut out, &|runs| {
        let times: Vec<f64> = runs.iter().map(|r| r.time_ms).collect();
        match (measured, median_iqr(&times)) {
            (Measured::Redacted, _) => "[time]".into(),
            (Measured::Shown, Some((m, _, _))) => format!("{m:.3}"),
            (Measured::Shown, None) => "-".into(),
        }
    });
    out
}

/// The valid runs of `planner` on the given problems of `map`, every repeat.
fn runs_of<'r>(
    context: &Context<'r>,
    planner: &PlannerSpec,
    problems: impl Iterator<Item = usize>,
    map: &str,
) -> Vec<&'r RunRecord> {
    problems
        .flat_map(|p| context.index.runs(map, p, &planner.label))
        .filter(|r| !r.is_invalid())
        .collect()
}

fn label_runs<'r>(context: &Context<'r>, planner: &PlannerSpec) -> Vec<&'r RunRecord> {
    context
        .experiment
        .maps
        .iter()
        .flat_map(|m| {
            runs_of(
                context,
                planner,
                m.problems.iter().map(|p| p.index),
                &m.name,
            )
        })
        .collect()
}

/// A run's stated optimum, except on a map with cell costs (a run with a `cost`, or any run
/// of such a map), whose optima are unweighted lengths.
fn optimum(context: &Context<'_>, r: &RunRecord) -> Option<f64> {
    let weighted = context
        .experiment
        .maps
        .iter()
        .any(|m| m.name == r.map && m.grid.is_weighted());
    r.optimal_length.filter(|_| !weighted)
}

fn row(
    out: &mut String,
    context: &Context<'_>,
    (label, map): (&str, &str),
    runs: &[&RunRecord],
    measured: Measured,
    costs: bool,
) {
    if runs.is_empty() {
        return;
    }
    let found = runs.iter().filter(|r| r.is_found()).count();
    let with_optimum: Vec<(f64, f64)> = runs
        .iter()
        .filter_map(|r| Some((r.length?, optimum(context, r)?)))
        .collect();
    let stated = runs.iter().any(|r| optimum(context, r).is_some());
    let optimal = if stated {
        with_optimum
            .iter()
            .filter(|(l, o)| matches_optimum(*l, *o))
            .count()
            .to_string()
    } else {
        "-".into()
    };
    let expansions: Vec<f64> = runs
        .iter()
        .filter_map(|r| r.counters.get("n_expanded"))
        .map(|v| v as f64)
        .collect();
    let (median_expansions, mean_expansions) = match median_iqr(&expansions) {
        Some((median, _, _)) => (
            format_number(median),
            format_number(expansions.iter().sum::<f64>() / expansions.len() as f64),
        ),
        None => ("-".into(), "-".into()),
    };
    let times: Vec<f64> = runs.iter().map(|r| r.time_ms).collect();
    let (time, iqr) = match (measured, median_iqr(&times)) {
        (Measured::Redacted, _) => ("[time]".to_string(), "[time]".to_string()),
        (Measured::Shown, Some((median, q1, q3))) => {
            (format!("{median:.3}"), format!("{q1:.3} - {q3:.3}"))
        }
        (Measured::Shown, None) => ("-".into(), "-".into()),
    };
    let subopt: Vec<f64> = with_optimum
        .iter()
        .map(|(l, o)| {
            if matches_optimum(*l, *o) {
                0.0
            } else {
                l / o - 1.0
            }
        })
        .collect();
    let (median_subopt, max_subopt) = match median_iqr(&subopt) {
        Some((median, _, _)) => (
            format!("{:.2} %", 100.0 * median),
            format!(
                "{:.2} %",
                100.0 * subopt.iter().copied().fold(0.0, f64::max)
            ),
        ),
        None => ("-".into(), "-".into()),
    };
    let heap = match measured {
        Measured::Redacted => "[memory]".to_string(),
        Measured::Shown => format_bytes(runs.iter().map(|r| r.peak_heap_bytes).max().unwrap_or(0)),
    };
    let path_costs: Vec<f64> = runs.iter().filter_map(|r| r.cost).collect();
    let cost = match costs {
        true => format!(
            " {} |",
            median_iqr(&path_costs).map_or("-".into(), |(m, _, _)| format_number(m))
        ),
        false => String::new(),
    };
    let _ = writeln!(
        out,
        "| {} | {} | {} | {found} | {optimal} | {median_expansions} | {mean_expansions} | {time} | {iqr} | {median_subopt} | {max_subopt} |{cost} {heap} |",
        md_cell(label),
        md_cell(map),
        runs.len()
    );
}

/// Medians of every counter per label, over its valid runs.
fn counters(context: &Context<'_>) -> String {
    let mut out = String::from("Median of each counter per planner label, over every run:\n\n| Planner | Counter | Median | Mean | Max |\n|---|---|---:|---:|---:|\n");
    for planner in &context.experiment.planners {
        let runs = label_runs(context, planner);
        let mut names: Vec<&str> = Vec::new();
        for r in &runs {
            for (name, _) in r.counters.iter() {
                if !names.contains(&name) {
                    names.push(name);
                }
            }
        }
        for name in names {
            let values: Vec<f64> = runs
                .iter()
                .filter_map(|r| r.counters.get(name))
                .map(|v| v as f64)
                .collect();
            let Some((median, _, _)) = median_iqr(&values) else {
                continue;
            };
            let mean = values.iter().sum::<f64>() / values.len() as f64;
            let max = values.iter().copied().fold(f64::MIN, f64::max);
            let _ = writeln!(
                out,
                "| {} | {name} | {} | {} | {} |",
                md_cell(&planner.label),
                format_number(median),
                format_number(mean),
                format_number(max)
            );
        }
    }
    out.push('\n');
    out
}

/// Success rate and spread over seeds, for seeded planners with more than one repeat.
fn seeds(context: &Context<'_>) -> String {
    let experiment = context.experiment;
    if experiment.repeats < 2 {
        return String::new();
    }
    let seeded: Vec<&PlannerSpec> = experiment
        .planners
        .iter()
        .filter(|p| p.factory.specs().seeded)
        .collect();
    if seeded.is_empty() {
        return String::new();
    }
    let mut out = format!("Seeded planners over their {} seeds per problem: the success rate, and the median, smallest and largest length and `n_expanded` over the seeds (per map, over every problem).\n\n| Planner | Map | Seeds | Success rate | Median length | Length range | Median expansions | Expansions range |\n|---|---|---:|---:|---:|---:|---:|---:|\n", experiment.repeats);
    for planner in seeded {
        for map in &experiment.maps {
            let runs = runs_of(
                context,
                planner,
                map.problems.iter().map(|p| p.index),
                &map.name,
            );
            if runs.is_empty() {
                continue;
            }
            let found = runs.iter().filter(|r| r.is_found()).count();
            let lengths: Vec<f64> = runs.iter().filter_map(|r| r.length).collect();
            let expansions: Vec<f64> = runs
                .iter()
                .filter_map(|r| r.counters.get("n_expanded"))
                .map(|v| v as f64)
                .collect();
            let spread = |values: &[f64], digits: usize| match median_iqr(values) {
                Some((median, _, _)) => {
                    let lo = values.iter().copied().fold(f64::MAX, f64::min);
                    let hi = values.iter().copied().fold(f64::MIN, f64::max);
                    let median = match digits {
                        0 => format_number(median),
                        _ => format!("{median:.digits$}"),
                    };
                    (median, format!("{lo:.digits$} - {hi:.digits$}"))
                }
                None => ("-".into(), "-".into()),
            };
            let (length, length_range) = spread(&lengths, 2);
            let (expanded, expanded_range) = spread(&expansions, 0);
            let _ = writeln!(
                out,
                "| {} | {} | {} | {:.1} % | {length} | {length_range} | {expanded} | {expanded_range} |",
                md_cell(&planner.label),
                md_cell(&map.name),
                experiment.repeats,
                100.0 * found as f64 / runs.len() as f64,
            );
        }
    }
    out.push('\n');
    out
}

pub fn optimum_table(context: &Context<'_>) -> String {
    let experiment = context.experiment;
    let mut out = String::from(planner_report::optimum::HEAD);
    let compared = |m: &&planner_runner::config::MapEntry| !m.grid.is_weighted();
    if experiment
        .maps
        .iter()
        .any(|m| m.grid.is_weighted() && m.problems.iter().any(|p| p.optimal_length.is_some()))
    {
        out.push_str(planner_report::optimum::WEIGHTED);
    }
    let any = experiment.maps.iter().filter(compared).any(|map| {
        map.problems.iter().any(|p| {
            experiment.planners.iter().any(|planner| {
                context
                    .index
                    .runs(&map.name, p.index, &planner.label)
                    .iter()
                    .any(|r| r.optimal_length.is_some())
            })
        })
    });
    if !any {
        return out;
    }
    out.push_str(planner_report::optimum::TABLE_HEAD);
    for planner in &experiment.planners {
        for map in experiment.maps.iter().filter(compared) {
            let runs: Vec<&RunRecord> = map
                .problems
                .iter()
                .flat_map(|p| context.index.runs(&map.name, p.index, &planner.label))
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

pub fn repeat_table(context: &Context<'_>) -> String {
    let experiment = context.experiment;
    let mut out = planner_report::repeats::head(experiment);
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
