//! Aggregates for any sweep: per planner label and map (and scenario bucket range), counts,
//! expansions, times, suboptimality and memory; an overall row per label; the spread over
//! seeds of seeded planners; and every label's resolved parameters.

use std::fmt::Write as _;

use crate::md_cell;
use crate::{Context, Section};
use planner_runner::config::Experiment;

/// The aggregate tables (section name `aggregate`).
pub struct Aggregate;

impl Section for Aggregate {
    fn name(&self) -> &'static str {
        "aggregate"
    }

    /// For every sweep.
    fn applies(&self, _context: &Context<'_>) -> bool {
        true
    }

    /// From passes over the records ([`crate::streamed::aggregate_tables`]), in memory
    /// bounded by the groups.
    fn table(&self) -> Option<crate::PassesTable> {
        Some(|experiment, passes| {
            crate::streamed::aggregate_tables(experiment, passes, Measured::Shown)
        })
    }
}

/// Whether the measured (not deterministic) columns, time and memory, are shown.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Measured {
    /// Shown as measured.
    Shown,
    /// Written `[time]` and `[memory]`, for snapshots.
    Redacted,
}

/// The warning of a sweep without repeats.
pub const TIMING_WARNING: &str = "> **Timing warning:** `repeats = 1`, so each run's time is a single measurement; the IQR below spreads over problems, not over repeated measurements of one problem.\n\n";

/// What the per-map table shows.
pub const PER_MAP: &str = "Per planner label and map, over every run of a valid problem, repeats included (the records of invalid problems, listed under \"Invalid problems (not run)\", are not counted here or in the overall rows): runs, runs that found a path, runs whose length equals the stated optimum (relative tolerance 1e-4; `-` without optima), the median and mean `n_expanded`, the median wall time of the search with its interquartile range (type 7 quartiles), the median and largest suboptimality (length / optimum - 1, over found runs with an optimum), and the largest peak heap of a run.\n\n";

/// The head of the per-map and overall tables.
pub const HEADER: &str = "| Planner | Map | Runs | Found | Optimal | Median expansions | Mean expansions | Median time (ms) | Time IQR (ms) | Median subopt. | Largest subopt. | Peak heap |\n|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n";

/// The head of the per-map and overall tables of a sweep with maps with cell costs: a
/// `Median cost` column before `Peak heap`.
pub const COST_HEADER: &str = "| Planner | Map | Runs | Found | Optimal | Median expansions | Mean expansions | Median time (ms) | Time IQR (ms) | Median subopt. | Largest subopt. | Median cost | Peak heap |\n|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n";

/// What the per-map table shows on maps with cell costs, after [`PER_MAP`]; `table` is the
/// result table that holds the `cost` column ([`runs_table`]).
pub fn costs_note(table: &str) -> String {
    format!("Maps with cell costs: their runs are not compared with the scenario optima, which are unweighted lengths (`Optimal` and the suboptimality leave them out, `-` for such a map alone); `Median cost` is the median path `cost` ({table}'s `cost` column) of the runs with one, the measure least-cost planners minimise.\n\n")
}

/// The result table summary.md names for a column of a sweep of `runs` runs: runs.csv, or
/// runs.parquet when runs.csv is not written (a sweep of more than
/// [`crate::HELD_RUNS`] runs, or `outputs` without `"csv"`).
pub fn runs_table(experiment: &Experiment, runs: u64) -> &'static str {
    experiment.outputs.for_runs(runs).table()
}

/// Whether some map of the experiment has cell costs (the tables then show path costs).
pub fn has_costs(experiment: &Experiment) -> bool {
    experiment.maps.iter().any(|m| m.grid.is_weighted())
}

/// At most this many bucket rows per map in the by-bucket tables: more buckets are grouped
/// into ranges of equal width.
pub const MAX_BUCKET_ROWS: u32 = 8;

/// The bucket ranges of a map's `buckets` (sorted, distinct): each bucket alone when there
/// are at most [`MAX_BUCKET_ROWS`], else at most that many ranges of equal width over
/// first..=last, empty ranges left out.
pub fn bucket_ranges(buckets: &[u32]) -> Vec<(u32, u32)> {
    let (Some(&first), Some(&last)) = (buckets.first(), buckets.last()) else {
        return Vec::new();
    };
    if buckets.len() as u32 <= MAX_BUCKET_ROWS {
        return buckets.iter().map(|&b| (b, b)).collect();
    }
    let width = (last - first) / MAX_BUCKET_ROWS + 1;
    (0..MAX_BUCKET_ROWS)
        .map(|k| (first + k * width, (first + (k + 1) * width - 1).min(last)))
        .filter(|&(lo, hi)| lo <= last && buckets.iter().any(|&b| lo <= b && b <= hi))
        .collect()
}

/// Every label's resolved parameters (defaults included) and budget, with the memory
/// limit that applies ([`budget_cell`]; `measured`: whether the machine's default is
/// shown or, for snapshots, written `[memory]`).
pub fn parameters(experiment: &Experiment, measured: Measured) -> String {
    let mut out = String::from("Planner parameters, as resolved (defaults included):\n\n| Label | Planner | Parameters | Budget |\n|---|---|---|---|\n");
    for planner in &experiment.planners {
        let params = match &*planner.parameters(experiment.seed) {
            serde_json::Value::Object(map) => map
                .iter()
                .map(|(k, v)| format!("{k} = {v}"))
                .collect::<Vec<_>>()
                .join(", "),
            other => other.to_string(),
        };
        let budget = budget_cell(planner, measured);
        let _ = writeln!(
            out,
            "| {} | {} | {} | {} |",
            md_cell(&planner.label),
            planner.name,
            md_cell(&params),
            // Numbers and fixed words only (no text of the config): written as is, so
            // that a redacted `[memory]` stays as the other tables write it.
            budget
        );
    }
    if experiment.planners.iter().any(|p| p.factory.specs().seeded) {
        out.push_str(
            "\nA seeded planner's `seed` is the base seed of its runs: repeat r runs with seed + r.\n",
        );
    }
    out.push('\n');
    out
}

/// A label's budget as the parameters table shows it: `max_expansions = N` or `no
/// expansion limit`, `max_time_ms = N` or `no time limit`, and the memory limit that
/// applies: its own `max_memory_mb = N`, else the runner's default
/// ([`planner_runner::run::default_max_memory_mb`], half the machine's memory), else `no
/// memory limit`; redacted (`measured`), the default is `[memory]` on every machine, as it
/// depends on the machine.
pub fn budget_cell(planner: &planner_runner::config::PlannerSpec, measured: Measured) -> String {
    let budget = &planner.budget;
    let expansions = match budget.max_expansions {
        Some(n) => format!("max_expansions = {n}"),
        None => "no expansion limit".to_string(),
    };
    let time = match budget.max_time {
        Some(t) => format!("max_time_ms = {}", t.as_millis()),
        None => "no time limit".to_string(),
    };
    let default = planner_runner::run::default_max_memory_mb();
    let memory = match (budget.max_memory_mb, default, measured) {
        (Some(mb), _, _) => format!("max_memory_mb = {mb}"),
        (None, Some(mb), Measured::Shown) => {
            format!("max_memory_mb = {mb} (default: half the machine's memory)")
        }
        // Redacted whether or not this machine's memory could be read: a snapshot's text
        // is the same on every machine.
        (None, _, Measured::Redacted) => {
            "max_memory_mb = [memory] (default: half the machine's memory)".to_string()
        }
        (None, None, Measured::Shown) => "no memory limit".to_string(),
    };
    format!("{expansions}, {time}, {memory}")
}

/// An integer as is, else two decimals.
pub fn format_number(value: f64) -> String {
    if value.fract() == 0.0 && value.abs() < 1e15 {
        format!("{value:.0}")
    } else {
        format!("{value:.2}")
    }
}

/// A byte count in B, KiB or MiB with one decimal.
pub fn format_bytes(bytes: u64) -> String {
    if bytes >= 1 << 20 {
        format!("{:.1} MiB", bytes as f64 / f64::from(1u32 << 20))
    } else if bytes >= 1 << 10 {
        format!("{:.1} KiB", bytes as f64 / 1024.0)
    } else {
        format!("{bytes} B")
    }
}

#[cfg(test)]
mod tests {
    use super::{bucket_ranges, format_bytes, format_number};

    #[test]
    fn buckets_are_grouped_into_at_most_eight_ranges() {
        assert_eq!(bucket_ranges(&[]), vec![]);
        assert_eq!(bucket_ranges(&[0, 3, 5]), vec![(0, 0), (3, 3), (5, 5)]);
        let sixteen: Vec<u32> = (0..16).collect();
        assert_eq!(
            bucket_ranges(&sixteen),
            vec![
                (0, 1),
                (2, 3),
                (4, 5),
                (6, 7),
                (8, 9),
                (10, 11),
                (12, 13),
                (14, 15)
            ]
        );
        // 0..=99: width 13; the last range is cut at the last bucket.
        let hundred: Vec<u32> = (0..100).collect();
        let ranges = bucket_ranges(&hundred);
        assert_eq!(ranges.len(), 8);
        assert_eq!(ranges[0], (0, 12));
        assert_eq!(ranges[7], (91, 99));
        // Ranges with no bucket are left out.
        assert_eq!(
            bucket_ranges(&[0, 1, 2, 3, 4, 5, 6, 7, 80]),
            vec![(0, 10), (77, 80)]
        );
    }

    #[test]
    fn numbers_and_bytes_are_formatted_for_tables() {
        assert_eq!(format_number(12.0), "12");
        assert_eq!(format_number(12.345), "12.35");
        assert_eq!(format_bytes(512), "512 B");
        assert_eq!(format_bytes(2048), "2.0 KiB");
        assert_eq!(format_bytes(3 << 20), "3.0 MiB");
    }
}
