//! The aggregate, optimum and repeats sections computed in passes over the records, in
//! memory bounded by their groups (label x map, label, map x bucket range x label, label x
//! counter), not by the runs.
//!
//! A first pass sums what needs no order statistic (runs, found, optimal, sums, largest
//! values) per group; then [`crate::exact::quantiles`] selects every median and quartile
//! exactly in a few more passes. This is the sections' only computation, for a sweep of any
//! size: the crate's tests compare it byte for byte with an in-memory one (every group's
//! runs collected and sorted) on 100,000 runs, and every config's summary.md snapshot
//! goes through it. Means are sums of the integer counters,
//! exact while a group's sum stays below 2^53, as the in-memory sum is.

use std::collections::HashMap;
use std::fmt::Write as _;

use planner_runner::config::Experiment;
use planner_runner::passes::RecordPasses;
use planner_runner::record::RunRecord;
use planner_runner::RunnerError;

use crate::aggregate::{
    bucket_ranges, costs_note, format_bytes, format_number, has_costs, parameters, runs_table,
    Measured, COST_HEADER, HEADER, PER_MAP, TIMING_WARNING,
};
use crate::exact::quantiles;
use crate::md_cell;
use crate::optimum::matches_optimum;

/// Where a record belongs: its label and the maps (by position) and bucket rows it is in.
struct Layout<'e> {
    experiment: &'e Experiment,
    labels: HashMap<&'e str, usize>,
    /// Map name -> the maps of that name (by position).
    maps: HashMap<&'e str, Vec<usize>>,
    /// (map, problem index) -> the problem's bucket row (its range's position among all
    /// maps' ranges), if its bucket is in one.
    problems: HashMap<(usize, usize), Option<usize>>,
    /// Per bucket row: its map and range.
    rows: Vec<(usize, (u32, u32))>,
}

impl<'e> Layout<'e> {
    fn new(experiment: &'e Experiment) -> Layout<'e> {
        let labels = crate::positions(experiment.planners.iter().map(|p| p.label.as_str()));
        let mut maps: HashMap<&str, Vec<usize>> = HashMap::new();
        let mut problems = HashMap::new();
        let mut rows = Vec::new();
        for (m, map) in experiment.maps.iter().enumerate() {
            maps.entry(map.name.as_str()).or_default().push(m);
            let mut buckets: Vec<u32> = map.problems.iter().filter_map(|p| p.bucket).collect();
            buckets.sort_unstable();
            buckets.dedup();
            let first = rows.len();
            rows.extend(bucket_ranges(&buckets).into_iter().map(|r| (m, r)));
            for p in &map.problems {
                let row = p.bucket.and_then(|b| {
                    (first..rows.len()).find(|&k| rows[k].1 .0 <= b && b <= rows[k].1 .1)
                });
                problems.entry((m, p.index)).or_insert(row);
            }
        }
        Layout {
            experiment,
            labels,
            maps,
            problems,
            rows,
        }
    }

    fn n_labels(&self) -> usize {
        self.experiment.planners.len()
    }

    fn n_maps(&self) -> usize {
        self.experiment.maps.len()
    }

    /// Whether map `m` has cell costs: its scenario optima, unweighted lengths, do not
    /// apply to its least-cost paths.
    fn weighted(&self, m: usize) -> bool {
        self.experiment.maps[m].grid.is_weighted()
    }

    /// Calls `visit(label, map, bucket row)` once per map the valid record `r` counts in
    /// (the in-memory tables look records up by map name, problem and label).
    fn place(&self, r: &RunRecord, visit: &mut impl FnMut(usize, usize, Option<usize>)) {
        if !r.is_invalid() {
            self.place_any(r, visit);
        }
    }

    /// [`Layout::place`] for any record, valid or not.
    fn place_any(&self, r: &RunRecord, visit: &mut impl FnMut(usize, usize, Option<usize>)) {
        let (Some(&l), Some(ms)) = (
            self.labels.get(r.planner.as_str()),
            self.maps.get(r.map.as_str()),
        ) else {
            return;
        };
        for &m in ms {
            if let Some(&row) = self.problems.get(&(m, r.problem)) {
                visit(l, m, row);
            }
        }
    }
}

/// What a group's row needs besides its order statistics.
#[derive(Debug, Clone, Copy)]
struct Acc {
    runs: u64,
    found: u64,
    stated: bool,
    optimal: u64,
    expansions: u64,
    expansions_sum: u128,
    expansions_min: f64,
    expansions_max: f64,
    subopt: u64,
    subopt_max: f64,
    heap: u64,
    lengths: u64,
    length_min: f64,
    length_max: f64,
    costs: u64,
}

impl Default for Acc {
    fn default() -> Acc {
        Acc {
            runs: 0,
            found: 0,
            stated: false,
            optimal: 0,
            expansions: 0,
            expansions_sum: 0,
            expansions_min: f64::MAX,
            expansions_max: f64::MIN,
            subopt: 0,
            subopt_max: 0.0,
            heap: 0,
            lengths: 0,
            length_min: f64::MAX,
            length_max: f64::MIN,
            costs: 0,
        }
    }
}

/// The optimum a run's length is compared with: the stated one, except on a map with cell
/// costs (`weighted`), whose optima are unweighted lengths.
fn optimum(r: &RunRecord, weighted: bool) -> Option<f64> {
    r.optimal_length.filter(|_| !weighted)
}

/// The suboptimality of a run with a length and a stated optimum ([`crate::aggregate`]'s)
/// on a map without cell costs.
fn subopt(r: &RunRecord, weighted: bool) -> Option<f64> {
    let (l, o) = (r.length?, optimum(r, weighted)?);
    Some(if matches_optimum(l, o) {
        0.0
    } else {
        l / o - 1.0
    })
}

impl Acc {
    fn add(&mut self, r: &RunRecord, weighted: bool) {
        self.runs += 1;
        self.found += u64::from(r.is_found());
        self.stated |= optimum(r, weighted).is_some();
        if let (Some(l), Some(o)) = (r.length, optimum(r, weighted)) {
            self.optimal += u64::from(matches_optimum(l, o));
        }
        if let Some(e) = r.counters.get("n_expanded") {
            self.expansions += 1;
            self.expansions_sum += u128::from(e);
            self.expansions_min = self.expansions_min.min(e as f64);
            self.expansions_max = self.expansions_max.max(e as f64);
        }
        if let Some(s) = subopt(r, weighted) {
            self.subopt += 1;
            self.subopt_max = self.subopt_max.max(s);
        }
        self.heap = self.heap.max(r.peak_heap_bytes);
        if let Some(length) = r.length {
            self.lengths += 1;
            self.length_min = self.length_min.min(length);
            self.length_max = self.length_max.max(length);
        }
        self.costs += u64::from(r.cost.is_some());
    }
}

/// One counter of one label.
#[derive(Debug, Clone)]
struct CounterAcc {
    name: String,
    n: u64,
    sum: u128,
    max: f64,
}

/// The quantities with order statistics, per label x map and per label group (sets
/// `QUANTITIES * group + q`).
const EXPANSIONS: usize = 0;
const TIME: usize = 1;
const SUBOPT: usize = 2;
const LENGTH: usize = 3;
const COST: usize = 4;
const QUANTITIES: usize = 5;

/// The aggregate section's groups, summed and with their quantiles selected.
struct Aggregated<'e> {
    experiment: &'e Experiment,
    layout: Layout<'e>,
    groups: Vec<Acc>,
    buckets: Vec<(u64, u64)>,
    counters: Vec<Vec<CounterAcc>>,
    counter_sets: Vec<Vec<usize>>,
    q: Vec<Vec<f64>>,
    n_labels: usize,
    n_maps: usize,
    bucket_base: usize,
    /// The result table summary.md names for a column ([`runs_table`]).
    table: &'static str,
}

/// The per-group sums of the first pass: label x map and label groups, bucket rows x labels
/// (runs, expansions), and each label's counters.
type Sums = (Vec<Acc>, Vec<(u64, u64)>, Vec<Vec<CounterAcc>>);

/// The first pass: [`Sums`].
fn accumulate(layout: &Layout<'_>, passes: &dyn RecordPasses) -> Result<Sums, RunnerError> {
    let (n_labels, n_maps) = (layout.n_labels(), layout.n_maps());
    // Groups: label x map (l * n_maps + m), then each label overall (n_labels * n_maps + l).
    let n_groups = n_labels * n_maps + n_labels;
    let mut groups = vec![Acc::default(); n_groups];
    // Bucket rows x labels: (runs, expansions).
    let mut buckets = vec![(0u64, 0u64); layout.rows.len() * n_labels];
    let mut counters: Vec<Vec<CounterAcc>> = vec![Vec::new(); n_labels];
    passes.pass(&mut |r| {
        layout.place(r, &mut |l, m, row| {
            let weighted = layout.weighted(m);
            groups[l * n_maps + m].add(r, weighted);
            groups[n_labels * n_maps + l].add(r, weighted);
            if let Some(k) = row {
                let b = &mut buckets[k * n_labels + l];
                b.0 += 1;
                b.1 += u64::from(r.counters.get("n_expanded").is_some());
            }
            let names = &mut counters[l];
            for (j, (name, _)) in r.counters.iter().enumerate() {
                if r.counters.iter().take(j).any(|(n, _)| n == name) {
                    continue;
                }
                let Some(value) = r.counters.get(name) else {
                    continue;
                };
                let at = match names.get(j) {
                    Some(c) if c.name == name => Some(j),
                    _ => names.iter().position(|c| c.name == name),
                };
                let c = match at {
                    Some(i) => &mut names[i],
                    None => {
                        names.push(CounterAcc {
                            name: name.to_string(),
                            n: 0,
                            sum: 0,
                            max: f64::MIN,
                        });
                        let last = names.len() - 1;
                        &mut names[last]
                    }
                };
                c.n += 1;
                c.sum += u128::from(value);
                c.max = c.max.max(value as f64);
            }
        });
    })?;
    Ok((groups, buckets, counters))
}

/// The aggregate section's markdown (parameters, the per-map table, the overall rows, the
/// by-bucket medians of scenario maps, counters and the seeds' spread), from passes over
/// the records.
pub fn aggregate_tables(
    experiment: &Experiment,
    passes: &dyn RecordPasses,
    measured: Measured,
) -> Result<String, RunnerError> {
    let a = Aggregated::compute(experiment, passes)?;
    let mut out = a.per_map(measured);
    a.by_bucket(&mut out, measured);
    a.counter_table(&mut out);
    a.seed_table(&mut out);
    Ok(out)
}

impl<'e> Aggregated<'e> {
    /// Sums the groups in one pass and selects their quantiles in a few more.
    fn compute(
        experiment: &'e Experiment,
        passes: &dyn RecordPasses,
    ) -> Result<Aggregated<'e>, RunnerError> {
        let layout = Layout::new(experiment);
        let (n_labels, n_maps) = (layout.n_labels(), layout.n_maps());
        let n_groups = n_labels * n_maps + n_labels;
        let (groups, buckets, counters) = accumulate(&layout, passes)?;
        // Quantile sets: per group its quantities; per bucket row and label (expansions,
        // time); per label and counter.
        let bucket_base = QUANTITIES * n_groups;
        let counter_base = bucket_base + 2 * buckets.len();
        let mut counter_sets: Vec<Vec<usize>> = Vec::with_capacity(n_labels);
        let mut n_sets = counter_base;
        for names in &counters {
            counter_sets.push((n_sets..n_sets + names.len()).collect());
            n_sets += names.len();
        }
        let mut sizes = vec![0u64; n_sets];
        let mut wanted: Vec<&[f64]> = vec![&[0.5]; n_sets];
        for (g, acc) in groups.iter().enumerate() {
            sizes[QUANTITIES * g + EXPANSIONS] = acc.expansions;
            sizes[QUANTITIES * g + TIME] = acc.runs;
            wanted[QUANTITIES * g + TIME] = &[0.5, 0.25, 0.75];
            sizes[QUANTITIES * g + SUBOPT] = acc.subopt;
            sizes[QUANTITIES * g + LENGTH] = acc.lengths;
            sizes[QUANTITIES * g + COST] = acc.costs;
        }
        for (k, &(runs, expansions)) in buckets.iter().enumerate() {
            sizes[bucket_base + 2 * k] = expansions;
            sizes[bucket_base + 2 * k + 1] = runs;
        }
        for (names, sets) in counters.iter().zip(&counter_sets) {
            for (c, &s) in names.iter().zip(sets) {
                sizes[s] = c.n;
            }
        }
        let q = quantiles(&sizes, &wanted, &mut |emit| {
            passes.pass(&mut |r| {
                layout.place(r, &mut |l, m, row| {
                    let expansions = r.counters.get("n_expanded").map(|v| v as f64);
                    for g in [l * n_maps + m, n_labels * n_maps + l] {
                        if let Some(e) = expansions {
                            emit(QUANTITIES * g + EXPANSIONS, e);
                        }
                        emit(QUANTITIES * g + TIME, r.time_ms);
                        if let Some(s) = subopt(r, layout.weighted(m)) {
                            emit(QUANTITIES * g + SUBOPT, s);
                        }
                        if let Some(length) = r.length {
                            emit(QUANTITIES * g + LENGTH, length);
                        }
                        if let Some(cost) = r.cost {
                            emit(QUANTITIES * g + COST, cost);
                        }
                    }
                    if let Some(k) = row {
                        if let Some(e) = expansions {
                            emit(bucket_base + 2 * (k * n_labels + l), e);
                        }
                        emit(bucket_base + 2 * (k * n_labels + l) + 1, r.time_ms);
                    }
                    let names = &counters[l];
                    for (j, (name, _)) in r.counters.iter().enumerate() {
                        if r.counters.iter().take(j).any(|(n, _)| n == name) {
                            continue;
                        }
                        let Some(value) = r.counters.get(name) else {
                            continue;
                        };
                        let at = match names.get(j) {
                            Some(c) if c.name == name => Some(j),
                            _ => names.iter().position(|c| c.name == name),
                        };
                        if let Some(i) = at {
                            emit(counter_sets[l][i], value as f64);
                        }
                    }
                });
            })
        })?;
        Ok(Aggregated {
            experiment,
            layout,
            groups,
            buckets,
            counters,
            counter_sets,
            q,
            n_labels,
            n_maps,
            bucket_base,
            table: runs_table(experiment, passes.len()),
        })
    }

    /// The parameters, the per-map table and the overall rows.
    fn per_map(&self, measured: Measured) -> String {
        let &Aggregated {
            experiment,
            ref groups,
            ref q,
            n_labels,
            n_maps,
            ..
        } = self;
        let median = |set: usize| q[set].first().copied();
        let mut out = String::from("## Aggregates\n\n");
        out.push_str(&parameters(experiment, measured));
        if experiment.repeats == 1 {
            out.push_str(TIMING_WARNING);
        }
        out.push_str(PER_MAP);
        let costs = has_costs(experiment);
        let header = if costs {
            out.push_str(&costs_note(self.table));
            COST_HEADER
        } else {
            HEADER
        };
        out.push_str(header);
        let row = |out: &mut String, label: &str, map: &str, g: usize| {
            let acc = &groups[g];
            if acc.runs == 0 {
                return;
            }
            let optimal = if acc.stated {
                acc.optimal.to_string()
            } else {
                "-".into()
            };
            let (median_expansions, mean_expansions) = match median(QUANTITIES * g + EXPANSIONS) {
                Some(m) => (
                    format_number(m),
                    format_number(acc.expansions_sum as f64 / acc.expansions as f64),
                ),
                None => ("-".into(), "-".into()),
            };
            let times = &q[QUANTITIES * g + TIME];
            let (time, iqr) = match (measured, times.as_slice()) {
                (Measured::Redacted, _) => ("[time]".to_string(), "[time]".to_string()),
                (Measured::Shown, &[m, q1, q3]) => {
                    (format!("{m:.3}"), format!("{q1:.3} - {q3:.3}"))
                }
                (Measured::Shown, _) => ("-".into(), "-".into()),
            };
            let (median_subopt, max_subopt) = match median(QUANTITIES * g + SUBOPT) {
                Some(m) => (
                    format!("{:.2} %", 100.0 * m),
                    format!("{:.2} %", 100.0 * acc.subopt_max),
                ),
                None => ("-".into(), "-".into()),
            };
            let heap = match measured {
                Measured::Redacted => "[memory]".to_string(),
                Measured::Shown => format_bytes(acc.heap),
            };
            let cost = match (costs, median(QUANTITIES * g + COST)) {
                (false, _) => String::new(),
                (true, m) => format!(" {} |", m.map_or("-".into(), format_number)),
            };
            let _ = writeln!(
            out,
            "| {} | {} | {} | {} | {optimal} | {median_expansions} | {mean_expansions} | {time} | {iqr} | {median_subopt} | {max_subopt} |{cost} {heap} |",
            md_cell(label),
            md_cell(map),
            acc.runs,
            acc.found
        );
        };
        for (l, planner) in experiment.planners.iter().enumerate() {
            for (m, map) in experiment.maps.iter().enumerate() {
                row(&mut out, &planner.label, &map.name, l * n_maps + m);
            }
        }
        out.push('\n');
        out.push_str("Overall, per planner label: every run of a valid problem on every map.\n\n");
        out.push_str(header);
        for (l, planner) in experiment.planners.iter().enumerate() {
            row(&mut out, &planner.label, "all", n_labels * n_maps + l);
        }
        out.push('\n');
        out
    }

    /// The by-bucket tables of scenario maps.
    fn by_bucket(&self, out: &mut String, measured: Measured) {
        let &Aggregated {
            experiment,
            ref layout,
            ref buckets,
            n_labels,
            bucket_base,
            ref q,
            ..
        } = self;
        let median = |set: usize| q[set].first().copied();
        // By bucket.
        if !layout.rows.is_empty() {
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
            let _ = write!(out, "By scenario bucket (a `.scen` bucket holds problems of optimal length 4b to 4b + 4; more than {} buckets are grouped into ranges of equal width; every bucket is in {}'s `bucket` column). Median `n_expanded` per label:\n\n{head}", crate::aggregate::MAX_BUCKET_ROWS, self.table);
            let table = |out: &mut String, cell: &dyn Fn(usize) -> String| {
                for (k, &(m, (lo, hi))) in layout.rows.iter().enumerate() {
                    let bucket = if lo == hi {
                        lo.to_string()
                    } else {
                        format!("{lo}-{hi}")
                    };
                    let runs = (0..n_labels)
                        .map(|l| buckets[k * n_labels + l].0)
                        .max()
                        .unwrap_or(0);
                    let cells: Vec<String> =
                        (0..n_labels).map(|l| cell(k * n_labels + l)).collect();
                    let _ = writeln!(
                        out,
                        "| {} | {bucket} | {runs} | {} |",
                        md_cell(&experiment.maps[m].name),
                        cells.join(" | ")
                    );
                }
                out.push('\n');
            };
            table(out, &|b| {
                median(bucket_base + 2 * b).map_or("-".into(), format_number)
            });
            let _ = write!(out, "Median search time (ms) per label:\n\n{head}");
            table(
                out,
                &|b| match (measured, median(bucket_base + 2 * b + 1)) {
                    (Measured::Redacted, _) => "[time]".into(),
                    (Measured::Shown, Some(m)) => format!("{m:.3}"),
                    (Measured::Shown, None) => "-".into(),
                },
            );
        }
    }

    /// Each counter's median, mean and largest value per label.
    fn counter_table(&self, out: &mut String) {
        let &Aggregated {
            experiment,
            ref counters,
            ref counter_sets,
            ref q,
            ..
        } = self;
        let median = |set: usize| q[set].first().copied();
        // Counters.
        out.push_str("Median of each counter per planner label, over every run:\n\n| Planner | Counter | Median | Mean | Max |\n|---|---|---:|---:|---:|\n");
        for (l, planner) in experiment.planners.iter().enumerate() {
            for (c, &set) in counters[l].iter().zip(&counter_sets[l]) {
                let Some(m) = median(set) else {
                    continue;
                };
                let _ = writeln!(
                    out,
                    "| {} | {} | {} | {} | {} |",
                    md_cell(&planner.label),
                    c.name,
                    format_number(m),
                    format_number(c.sum as f64 / c.n as f64),
                    format_number(c.max)
                );
            }
        }
        out.push('\n');
    }

    /// Seeded planners' spread over their seeds.
    fn seed_table(&self, out: &mut String) {
        let &Aggregated {
            experiment,
            ref groups,
            n_labels,
            n_maps,
            ref q,
            ..
        } = self;
        let median = |set: usize| q[set].first().copied();
        // Seeds.
        let seeded: Vec<usize> = (0..n_labels)
            .filter(|&l| experiment.planners[l].factory.specs().seeded)
            .collect();
        if experiment.repeats >= 2 && !seeded.is_empty() {
            let _ = write!(out, "Seeded planners over their {} seeds per problem: the success rate, and the median, smallest and largest length and `n_expanded` over the seeds (per map, over every problem).\n\n| Planner | Map | Seeds | Success rate | Median length | Length range | Median expansions | Expansions range |\n|---|---|---:|---:|---:|---:|---:|---:|\n", experiment.repeats);
            for l in seeded {
                for (m, map) in experiment.maps.iter().enumerate() {
                    let g = l * n_maps + m;
                    let acc = &groups[g];
                    if acc.runs == 0 {
                        continue;
                    }
                    // Whole-number ranges (digits 0) have medians as the other tables
                    // print them: a median of 57.5 is 57.50, not 58.
                    let spread = |set: usize, lo: f64, hi: f64, digits: usize| match median(set) {
                        Some(median) if digits == 0 => {
                            (format_number(median), format!("{lo:.0} - {hi:.0}"))
                        }
                        Some(median) => (
                            format!("{median:.digits$}"),
                            format!("{lo:.digits$} - {hi:.digits$}"),
                        ),
                        None => ("-".into(), "-".into()),
                    };
                    let (length, length_range) =
                        spread(QUANTITIES * g + LENGTH, acc.length_min, acc.length_max, 2);
                    let (expanded, expanded_range) = spread(
                        QUANTITIES * g + EXPANSIONS,
                        acc.expansions_min,
                        acc.expansions_max,
                        0,
                    );
                    let _ = writeln!(
                    out,
                    "| {} | {} | {} | {:.1} % | {length} | {length_range} | {expanded} | {expanded_range} |",
                    md_cell(&experiment.planners[l].label),
                    md_cell(&map.name),
                    experiment.repeats,
                    100.0 * acc.found as f64 / acc.runs as f64,
                );
                }
            }
            out.push('\n');
        }
    }
}

/// The optimum section's markdown (`crate::optimum`'s table), from one pass over the
/// records: per label and map, every run (repeats included) of the problems with a stated
/// optimum, as the aggregate tables count runs.
pub fn optimum_table(
    experiment: &Experiment,
    passes: &dyn RecordPasses,
) -> Result<String, RunnerError> {
    let layout = Layout::new(experiment);
    let n_maps = layout.n_maps();
    // Per label x map: runs, found, optimal, largest excess.
    let mut groups = vec![(0u64, 0u64, 0u64, 0.0f64); layout.n_labels() * n_maps];
    passes.pass(&mut |r| {
        if r.optimal_length.is_none() {
            return;
        }
        layout.place_any(r, &mut |l, m, _| {
            if layout.weighted(m) {
                return;
            }
            let g = &mut groups[l * n_maps + m];
            g.0 += 1;
            if let (Some(l), Some(o)) = (r.length, r.optimal_length) {
                g.1 += 1;
                g.2 += u64::from(matches_optimum(l, o));
                g.3 = g.3.max((l - o) / o.max(1.0));
            }
        });
    })?;
    let mut out = String::from(crate::optimum::HEAD);
    if experiment.maps.iter().any(crate::optimum::left_out) {
        out.push_str(crate::optimum::WEIGHTED);
    }
    if groups.iter().all(|g| g.0 == 0) {
        return Ok(out);
    }
    out.push_str(crate::optimum::TABLE_HEAD);
    for (l, planner) in experiment.planners.iter().enumerate() {
        for (m, map) in experiment.maps.iter().enumerate() {
            let (runs, found, optimal, excess) = groups[l * n_maps + m];
            if runs == 0 {
                continue;
            }
            let _ = writeln!(
                out,
                "| {} | {} | {runs} | {found} | {optimal} | {:.2} % |",
                md_cell(&planner.label),
                md_cell(&map.name),
                100.0 * excess
            );
        }
    }
    out.push('\n');
    Ok(out)
}

/// The repeats section's markdown (`crate::repeats`'s table), from passes over the
/// records: per label and map, the success rate, the median length of the found runs and
/// the median time with its quartiles, exact ([`crate::exact`]).
pub fn repeats_table(
    experiment: &Experiment,
    passes: &dyn RecordPasses,
) -> Result<String, RunnerError> {
    let layout = Layout::new(experiment);
    let n_maps = layout.n_maps();
    let n_groups = layout.n_labels() * n_maps;
    // Per label x map: runs, found runs with a length.
    let mut groups = vec![(0u64, 0u64); n_groups];
    let found_length = |r: &RunRecord| r.length.filter(|_| r.is_found());
    passes.pass(&mut |r| {
        layout.place(r, &mut |l, m, _| {
            let g = &mut groups[l * n_maps + m];
            g.0 += 1;
            g.1 += u64::from(found_length(r).is_some());
        });
    })?;
    // Sets: 2g lengths of found runs, 2g + 1 times.
    let sizes: Vec<u64> = groups
        .iter()
        .flat_map(|&(runs, found)| [found, runs])
        .collect();
    let wanted: Vec<&[f64]> = (0..2 * n_groups)
        .map(|s| -> &[f64] {
            if s % 2 == 0 {
                &[0.5]
            } else {
                &[0.5, 0.25, 0.75]
            }
        })
        .collect();
    let q = quantiles(&sizes, &wanted, &mut |emit| {
        passes.pass(&mut |r| {
            layout.place(r, &mut |l, m, _| {
                let g = l * n_maps + m;
                if let Some(length) = found_length(r) {
                    emit(2 * g, length);
                }
                emit(2 * g + 1, r.time_ms);
            });
        })
    })?;
    let mut out = crate::repeats::head(experiment);
    for (l, planner) in experiment.planners.iter().enumerate() {
        for (m, map) in experiment.maps.iter().enumerate() {
            let g = l * n_maps + m;
            let (runs, found) = groups[g];
            if runs == 0 {
                continue;
            }
            let length = q[2 * g].first().map_or("-".into(), |m| format!("{m:.2}"));
            let time = match q[2 * g + 1].as_slice() {
                &[m, q1, q3] => format!("{m:.4} ({q1:.4}-{q3:.4})"),
                _ => "-".into(),
            };
            let _ = writeln!(
                out,
                "| {} | {} | {runs} | {:.1} % | {length} | {time} |",
                md_cell(&planner.label),
                md_cell(&map.name),
                100.0 * found as f64 / runs as f64,
            );
        }
    }
    out.push('\n');
    Ok(out)
}
