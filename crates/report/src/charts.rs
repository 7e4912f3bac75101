//! The sweep's charts as SVG, drawn with plotters' SVG backend (text as `<text>`
//! elements, so no font files are read): box plots of time and expansions per planner
//! label, expansions and time against the scenario bucket (one line per label, the
//! Moving AI picture), success and optimality bars, the parameter-study line charts
//! of `[[charts]]` (or the default one when the labels differ in one numeric parameter),
//! and with two labels or more each label's expansions and time per problem against the
//! baseline's ([`crate::paired`]; log-log scatter charts with the diagonal).
//!
//! Text from the config (labels, map names, chart titles and keys) goes through
//! [`planner_figures::xml_text`], the cleaning the figures use (control characters, which
//! XML 1.0 forbids even escaped, become spaces), before plotters writes it escaped; so
//! every chart is well-formed XML whatever the labels hold.

use std::collections::HashMap;

use planner_figures::xml_text;
use plotters::coord::types::RangedCoordf64;
use plotters::prelude::*;

use crate::optimum::matches_optimum;
use planner_runner::config::{ChartSpec, Experiment};
use planner_runner::output::OutputFile;
use planner_runner::passes::RecordPasses;
use planner_runner::record::RunRecord;
use planner_runner::RunnerError;

/// One chart: its file (under `charts/`), title and SVG text.
#[derive(Debug, Clone, PartialEq)]
pub struct Chart {
    /// File name under `charts/`, e.g. `time-box.svg`.
    pub file: String,
    /// The chart's title.
    pub title: String,
    /// The SVG document.
    pub svg: String,
}

/// A chart's page: its width, and its height unless its key needs more.
const SIZE: (u32, u32) = (1000, 520);

/// The width of the key beside the plot (the plot has the rest of [`SIZE`]'s width).
const KEY_WIDTH: u32 = 330;

/// The height of one line of the key.
const KEY_LINE: u32 = 18;

/// The most characters of a label the key and the x axis show (a key line of a box plot
/// adds its number and median and still fits [`KEY_WIDTH`]); a longer label ends with an
/// ellipsis (summary.md's tables give it whole).
const KEY_CHARS: usize = 26;

/// The most category numbers along x: beyond, every k-th is written.
const MAX_X_TICKS: usize = 20;

/// One line of a chart's key: its series' colour (none for a line of text) and its text.
struct KeyEntry {
    colour: Option<RGBColor>,
    text: String,
}

impl KeyEntry {
    /// A series' line: a swatch of colour `i` and `text`, shortened (to more characters
    /// than a box plot's line, which also gives a number and a median).
    fn series(i: usize, text: &str) -> KeyEntry {
        KeyEntry {
            colour: Some(colour(i)),
            text: shortened_to(text, KEY_CHARS + 16),
        }
    }
}

/// `text` at most [`KEY_CHARS`] characters long, with an ellipsis when cut.
fn shortened(text: &str) -> String {
    shortened_to(text, KEY_CHARS)
}

/// `text` at most `chars` characters long, with an ellipsis when cut.
fn shortened_to(text: &str, chars: usize) -> String {
    match text.chars().count() > chars {
        true => text.chars().take(chars - 1).chain(['…']).collect(),
        false => text.to_string(),
    }
}

/// Whether a chart of one category per name along x numbers its categories (1, 2, ...)
/// and its key says which label each number is: with many labels, or labels too long for
/// their share of the axis, the names overlapped into a smear.
fn numbered(names: &[String]) -> bool {
    let share = (SIZE.0 - KEY_WIDTH - 110) as usize / names.len().max(1);
    names.len() > 12 || names.iter().any(|name| 7 * name.chars().count() > share)
}

/// A label's text in a chart of labels: with its number when the axis is `numbered`.
fn category_text(i: usize, name: &str, numbered: bool) -> String {
    match numbered {
        true => format!("{} {name}", i + 1),
        false => name.to_string(),
    }
}

/// The quantiles of a box plot, in [`BoxStats`]' order.
const BOX: &[f64] = &[0.5, 0.25, 0.75, 0.0, 1.0];

/// A box plot's median, first and third quartiles (type 7), smallest and largest value.
type BoxStats = [f64; 5];

/// Each planner label's counts over its valid runs, from the first pass.
#[derive(Default)]
struct LabelCounts {
    runs: u64,
    expansions: u64,
    found: u64,
    optimal: u64,
    /// Per scenario bucket (ascending): runs with `n_expanded`, and runs.
    buckets: std::collections::BTreeMap<u32, (u64, u64)>,
}

/// One study chart's groups (in order of first appearance), each with its x values (in
/// order of first appearance) and the number of runs measured at each.
type StudyCounts = Vec<(String, Vec<(f64, u64)>)>;

/// Where a valid run's values go: its study group and x per chart.
fn study_place(
    experiment: &Experiment,
    spec: &ChartSpec,
    record: &RunRecord,
    label: Option<usize>,
) -> Option<(String, f64, f64)> {
    let group_key = spec.group.as_deref().unwrap_or("map");
    let (Some(x), Some(y)) = (
        key_value(experiment, record, label, &spec.x).and_then(|v| v.as_f64()),
        metric(record, &spec.y),
    ) else {
        return None;
    };
    let group = match key_value(experiment, record, label, group_key) {
        Some(serde_json::Value::String(s)) => s,
        Some(other) => format!("{group_key} = {other}"),
        None => "-".into(),
    };
    Some((group, x, y))
}

/// The numbered multisets whose quantiles [`crate::exact::quantiles`] selects.
#[derive(Default)]
struct Sets {
    sizes: Vec<u64>,
    wanted: Vec<&'static [f64]>,
}

impl Sets {
    /// A new set of `size` values with quantiles `wanted`; its number.
    fn add(&mut self, size: u64, wanted: &'static [f64]) -> usize {
        self.sizes.push(size);
        self.wanted.push(wanted);
        self.sizes.len() - 1
    }
}

/// Every chart of the sweep, in summary order, from passes over its records: a pass
/// that counts each group (label, label x bucket, study group x x), then exact quantiles
/// per group ([`crate::exact`]); memory bounded by the groups, not the runs.
pub fn charts(
    experiment: &Experiment,
    passes: &dyn RecordPasses,
) -> Result<Vec<Chart>, RunnerError> {
    let labels: Vec<&str> = experiment
        .planners
        .iter()
        .map(|p| p.label.as_str())
        .collect();
    let index = label_index(&labels);
    let label_of = |r: &RunRecord| index.get(r.planner.as_str()).copied();
    let specs: Vec<ChartSpec> = if experiment.charts.is_empty() {
        default_study(experiment).into_iter().collect()
    } else {
        experiment.charts.clone()
    };
    let Counted {
        counts,
        studies,
        indexes,
        valid,
        any_bucket,
        stated,
    } = count_groups(experiment, passes, &labels, &specs)?;
    if !valid {
        return Ok(Vec::new());
    }
    // Sets: per label time and expansions (boxes); per label and bucket expansions and
    // time (medians); per study chart, group and x the metric (medians).
    let mut sets = Sets::default();
    let boxes: Vec<(usize, usize)> = counts
        .iter()
        .map(|c| (sets.add(c.runs, BOX), sets.add(c.expansions, BOX)))
        .collect();
    let bucket_sets: Vec<Vec<(u32, usize, usize)>> = counts
        .iter()
        .map(|c| {
            c.buckets
                .iter()
                .map(|(&b, &(e, n))| (b, sets.add(e, &[0.5]), sets.add(n, &[0.5])))
                .collect()
        })
        .collect();
    let study_sets: Vec<Vec<Vec<usize>>> = studies
        .iter()
        .map(|groups| {
            groups
                .iter()
                .map(|(_, points)| points.iter().map(|&(_, n)| sets.add(n, &[0.5])).collect())
                .collect()
        })
        .collect();
    let q = crate::exact::quantiles(&sets.sizes, &sets.wanted, &mut |emit| {
        passes.pass(&mut |r| {
            if r.is_invalid() {
                return;
            }
            let expansions = r.counters.get("n_expanded").map(|v| v as f64);
            let label = label_of(r);
            if let Some(l) = label {
                emit(boxes[l].0, r.time_ms);
                if let Some(e) = expansions {
                    emit(boxes[l].1, e);
                }
                if let Some(b) = r.bucket {
                    if let Some(&(_, e_set, t_set)) =
                        bucket_sets[l].iter().find(|(k, _, _)| *k == b)
                    {
                        if let Some(e) = expansions {
                            emit(e_set, e);
                        }
                        emit(t_set, r.time_ms);
                    }
                }
            }
            for ((spec, index), group_sets) in specs.iter().zip(&indexes).zip(&study_sets) {
                emit_study(experiment, spec, index, group_sets, r, label, &mut *emit);
            }
        })
    })?;
    let stats = |set: usize| -> Option<BoxStats> { q[set].as_slice().try_into().ok() };
    let median = |set: usize| q[set].first().copied();
    let any_expansions = counts.iter().any(|c| c.expansions > 0);
    let (shown, note) = first_labels(&labels);
    let mut out = box_plots(shown, &boxes, any_expansions, &stats, &note);
    if any_bucket {
        out.extend(bucket_charts(shown, &bucket_sets, &median, &note));
    }
    out.push(success_chart(shown, &counts, stated, &note));
    out.extend(study_charts(&specs, studies, &study_sets, &median));
    if labels.len() >= 2 {
        out.extend(paired_charts(experiment, passes)?);
    }
    Ok(out)
}

/// The most labels a chart of labels draws (box plots, success, buckets, paired): the
/// config's first ones; the title says so. Every label stays in summary.md's tables.
pub const MAX_CHART_LABELS: usize = 100;

/// The labels a chart of labels draws, and what its title adds when they are not all: a
/// chart of every label of a large sweep would be unreadable, its file as large as the
/// sweep.
fn first_labels<'a, 'b>(labels: &'a [&'b str]) -> (&'a [&'b str], String) {
    let note = match labels.len() > MAX_CHART_LABELS {
        true => format!(" (the first {MAX_CHART_LABELS} of {} labels)", labels.len()),
        false => String::new(),
    };
    (&labels[..labels.len().min(MAX_CHART_LABELS)], note)
}

/// Each label's position: a record finds its label through this map, not a scan of the
/// labels (a sweep of 100,000 labels made that 10^10 comparisons).
fn label_index<'a>(labels: &[&'a str]) -> HashMap<&'a str, usize> {
    labels.iter().enumerate().map(|(i, &l)| (l, i)).collect()
}

/// The most points a paired chart draws per label: beyond, every k-th problem (in the
/// problems' order), and the title says so.
pub const PAIRED_POINTS: usize = 2000;

/// Per problem solved by a label and the baseline (the `paired` section's, [`crate::paired`]),
/// the label's median expansions, then time, against the baseline's: log-log scatter
/// charts with the diagonal, one colour per label. No expansions chart when no pair
/// counts them.
fn paired_charts(
    experiment: &Experiment,
    passes: &dyn RecordPasses,
) -> Result<Vec<Chart>, RunnerError> {
    let baseline = crate::paired::configured_baseline(experiment);
    let per_problem = crate::paired::PerProblem::of(experiment, passes, baseline)?;
    let base = per_problem.base;
    let base_label = &experiment.planners[base].label;
    let mut out = Vec::new();
    for (time, file, what) in [
        (false, "paired-expansions.svg", "n_expanded"),
        (true, "paired-time.svg", "time (ms)"),
    ] {
        let mut thinned = false;
        let series: Vec<Scatter> = experiment
            .planners
            .iter()
            .enumerate()
            .filter(|&(l, _)| l != base)
            .take(MAX_CHART_LABELS)
            .map(|(l, p)| {
                let points = per_problem.points(l, time);
                let step = points.len().div_ceil(PAIRED_POINTS).max(1);
                thinned |= step > 1;
                let n = points.len();
                let problems = if n == 1 { "problem" } else { "problems" };
                let label = match step {
                    1 => format!("{} ({n} {problems})", p.label),
                    _ => format!("{} (1 in {step} of {n} {problems})", p.label),
                };
                let kept = points.into_iter().step_by(step).collect();
                (l, label, kept)
            })
            .collect();
        if series.iter().all(|(_, _, points)| points.is_empty()) {
            continue;
        }
        let mut title =
            format!("{what} per problem against {base_label} (below the diagonal: less)");
        if thinned {
            title.push_str(&format!(", at most {PAIRED_POINTS} problems a label drawn"));
        }
        let others = experiment.planners.len() - 1;
        if others > MAX_CHART_LABELS {
            title.push_str(&format!(
                ", the first {MAX_CHART_LABELS} of {others} labels"
            ));
        }
        let x_desc = format!("{what} of {base_label}");
        let y_desc = format!("{what} of each label");
        out.push(scatter_chart(file, &title, &x_desc, &y_desc, &series));
    }
    Ok(out)
}

/// One label's points in a scatter chart: its index (its colour), legend text, points.
type Scatter = (usize, String, Vec<(f64, f64)>);

/// A log-log scatter chart of `(x, y)` points, one colour per series (its label's index),
/// with the diagonal `y = x`.
fn scatter_chart(file: &str, title: &str, x_desc: &str, y_desc: &str, series: &[Scatter]) -> Chart {
    let series: Vec<Scatter> = series
        .iter()
        .map(|(l, label, points)| (*l, xml_text(label), points.clone()))
        .collect();
    let key: Vec<KeyEntry> = series
        .iter()
        .map(|(l, label, _)| KeyEntry::series(*l, label))
        .collect();
    render_chart(file, title, &key, |root, title| {
        draw_scatter_chart(root, title, &xml_text(x_desc), &xml_text(y_desc), &series)
    })
}

fn draw_scatter_chart(
    root: &Area<'_>,
    title: &str,
    x_desc: &str,
    y_desc: &str,
    series: &[Scatter],
) -> DrawResult {
    root.fill(&WHITE)?;
    let values = series
        .iter()
        .flat_map(|(_, _, points)| points.iter().flat_map(|&(x, y)| [x, y]));
    let (lo, hi) = values.fold((f64::MAX, f64::MIN), |(lo, hi), v| (lo.min(v), hi.max(v)));
    // Both axes over the same decades, so that the diagonal is the diagonal.
    let (lo, hi) = match lo < hi {
        true => (lo / 1.5, hi * 1.5),
        false => (lo / 10.0, lo * 10.0),
    };
    let mut chart = ChartBuilder::on(root)
        .caption(title, caption_font(title))
        .margin(14)
        .x_label_area_size(50)
        .y_label_area_size(80)
        .build_cartesian_2d((lo..hi).log_scale(), (lo..hi).log_scale())?;
    // Ticks as plain numbers: 10, 100, 0.01 (plotters writes 10000.0).
    let tick = |v: &f64| {
        let text = format!("{v:.6}");
        text.trim_end_matches('0').trim_end_matches('.').to_string()
    };
    chart
        .configure_mesh()
        .x_desc(x_desc)
        .y_desc(y_desc)
        .x_label_formatter(&tick)
        .y_label_formatter(&tick)
        .draw()?;
    chart.draw_series(std::iter::once(PathElement::new(
        vec![(lo, lo), (hi, hi)],
        BLACK.mix(0.5).stroke_width(1),
    )))?;
    for (l, _, points) in series {
        let c = colour(*l);
        chart.draw_series(
            points
                .iter()
                .map(|&p| Circle::new(p, 2, c.mix(0.6).filled())),
        )?;
    }
    Ok(())
}

/// The time box plot per label, and the expansions one when any run counts expansions,
/// from each label's `(time set, expansions set)`.
fn box_plots(
    labels: &[&str],
    boxes: &[(usize, usize)],
    any_expansions: bool,
    stats: &dyn Fn(usize) -> Option<BoxStats>,
    note: &str,
) -> Vec<Chart> {
    let named = |set: &dyn Fn(usize) -> usize| -> Vec<(String, Option<BoxStats>)> {
        labels
            .iter()
            .enumerate()
            .map(|(l, label)| (label.to_string(), stats(set(l))))
            .collect()
    };
    let mut out = vec![box_plot(
        "time-box.svg",
        &format!("Search time per planner (every run){note}"),
        "time (ms)",
        &named(&|l| boxes[l].0),
    )];
    if any_expansions {
        out.push(box_plot(
            "expansions-box.svg",
            &format!("Expansions per planner (every run){note}"),
            "n_expanded (cells)",
            &named(&|l| boxes[l].1),
        ));
    }
    out
}

/// Sends a valid record's metric to its study group and x value's set, if counted.
fn emit_study(
    experiment: &Experiment,
    spec: &ChartSpec,
    index: &StudyIndex,
    group_sets: &[Vec<usize>],
    record: &RunRecord,
    label: Option<usize>,
    emit: crate::exact::Emit<'_>,
) {
    let Some((group, x, y)) = study_place(experiment, spec, record, label) else {
        return;
    };
    if let Some((k, j)) = index.find(&group, x) {
        emit(group_sets[k][j], y);
    }
}

/// Each study chart: per group, the median metric against x, sorted by x.
fn study_charts(
    specs: &[ChartSpec],
    studies: Vec<StudyCounts>,
    study_sets: &[Vec<Vec<usize>>],
    median: &dyn Fn(usize) -> Option<f64>,
) -> Vec<Chart> {
    let mut out = Vec::new();
    for (i, ((spec, groups), group_sets)) in specs.iter().zip(studies).zip(study_sets).enumerate() {
        let series: Vec<(String, Vec<(f64, f64)>)> = groups
            .into_iter()
            .zip(group_sets)
            .map(|((g, points), sets)| {
                let mut line: Vec<(f64, f64)> = points
                    .iter()
                    .zip(sets)
                    .filter_map(|(&(x, _), &set)| median(set).map(|m| (x, m)))
                    .collect();
                line.sort_by(|a, b| a.0.total_cmp(&b.0));
                (g, line)
            })
            .collect();
        out.push(study_chart(i, spec, &series));
    }
    out
}

/// What the first pass over the records finds: the groups and their sizes.
struct Counted {
    /// Per label.
    counts: Vec<LabelCounts>,
    /// Per chart spec: its groups and their x values, with their sizes.
    studies: Vec<StudyCounts>,
    /// Per chart spec: where its groups and x values are in `studies`.
    indexes: Vec<StudyIndex>,
    /// Whether any record is valid.
    valid: bool,
    /// Whether any valid record has a scenario bucket.
    any_bucket: bool,
    /// Whether any valid record states an optimal length.
    stated: bool,
}

/// Where a study chart's group and x value are in its [`StudyCounts`]: maps, so that a
/// record is placed without scanning the groups and x values (a sweep of 100,000 values).
#[derive(Default)]
struct StudyIndex {
    /// Group name to its position.
    groups: HashMap<String, usize>,
    /// Per group, [`x_key`] of an x value to its position.
    points: Vec<HashMap<u64, usize>>,
}

impl StudyIndex {
    /// The positions of `group` and `x`, if counted.
    fn find(&self, group: &str, x: f64) -> Option<(usize, usize)> {
        let k = *self.groups.get(group)?;
        Some((k, *self.points.get(k)?.get(&x_key(x))?))
    }
}

/// An x value as a key: its bits, with `-0` as `0` (equal as numbers).
fn x_key(x: f64) -> u64 {
    match x == 0.0 {
        true => 0,
        false => x.to_bits(),
    }
}

/// One pass that counts each group (label, label x bucket, study group x x) of the valid
/// records.
fn count_groups(
    experiment: &Experiment,
    passes: &dyn RecordPasses,
    labels: &[&str],
    specs: &[ChartSpec],
) -> Result<Counted, RunnerError> {
    let index = label_index(labels);
    let label_of = |r: &RunRecord| index.get(r.planner.as_str()).copied();
    let mut counts: Vec<LabelCounts> = labels.iter().map(|_| LabelCounts::default()).collect();
    let mut studies: Vec<StudyCounts> = specs.iter().map(|_| Vec::new()).collect();
    let mut indexes: Vec<StudyIndex> = specs.iter().map(|_| StudyIndex::default()).collect();
    let (mut valid, mut any_bucket, mut stated) = (false, false, false);
    // Maps with cell costs: their scenario optima, unweighted lengths, do not apply.
    let weighted: std::collections::HashSet<&str> = experiment
        .maps
        .iter()
        .filter(|m| m.grid.is_weighted())
        .map(|m| m.name.as_str())
        .collect();
    passes.pass(&mut |r| {
        if r.is_invalid() {
            return;
        }
        valid = true;
        any_bucket |= r.bucket.is_some();
        let optimum = r
            .optimal_length
            .filter(|_| !weighted.contains(r.map.as_str()));
        stated |= optimum.is_some();
        if let Some(l) = label_of(r) {
            let c = &mut counts[l];
            let expansions = r.counters.get("n_expanded").is_some();
            c.runs += 1;
            c.expansions += u64::from(expansions);
            c.found += u64::from(r.is_found());
            c.optimal += u64::from(
                r.length
                    .zip(optimum)
                    .is_some_and(|(len, opt)| matches_optimum(len, opt)),
            );
            if let Some(b) = r.bucket {
                let at = c.buckets.entry(b).or_default();
                at.0 += u64::from(expansions);
                at.1 += 1;
            }
        }
        for ((spec, groups), index) in specs.iter().zip(&mut studies).zip(&mut indexes) {
            let Some((group, x, _)) = study_place(experiment, spec, r, label_of(r)) else {
                continue;
            };
            let k = *index.groups.entry(group.clone()).or_insert_with(|| {
                groups.push((group, Vec::new()));
                index.points.push(HashMap::new());
                groups.len() - 1
            });
            let points = &mut groups[k].1;
            let j = *index.points[k].entry(x_key(x)).or_insert_with(|| {
                points.push((x, 0));
                points.len() - 1
            });
            points[j].1 += 1;
        }
    })?;
    Ok(Counted {
        counts,
        studies,
        indexes,
        valid,
        any_bucket,
        stated,
    })
}

/// The median expansions and median time against the scenario bucket, per label, from
/// each label's `(bucket, expansions set, time set)` rows.
fn bucket_charts(
    labels: &[&str],
    bucket_sets: &[Vec<(u32, usize, usize)>],
    median: &dyn Fn(usize) -> Option<f64>,
    note: &str,
) -> [Chart; 2] {
    let by_bucket =
        |pick: &dyn Fn(&(u32, usize, usize)) -> usize| -> Vec<(String, Vec<(f64, f64)>)> {
            labels
                .iter()
                .zip(bucket_sets)
                .map(|(label, rows)| {
                    let points = rows
                        .iter()
                        .filter_map(|row| median(pick(row)).map(|m| (f64::from(row.0), m)))
                        .collect();
                    (label.to_string(), points)
                })
                .collect()
        };
    [
        line_chart(
            "expansions-by-bucket.svg",
            &format!("Median expansions against scenario bucket (optimal length / 4){note}"),
            "scenario bucket",
            "median n_expanded (cells)",
            &by_bucket(&|row| row.1),
        ),
        line_chart(
            "time-by-bucket.svg",
            &format!("Median search time against scenario bucket (optimal length / 4){note}"),
            "scenario bucket",
            "median time (ms)",
            &by_bucket(&|row| row.2),
        ),
    ]
}

/// The share of each label's runs that found a path (and, with stated optima, that
/// found an optimal one).
fn success_chart(labels: &[&str], counts: &[LabelCounts], stated: bool, note: &str) -> Chart {
    let bars: Vec<(String, Vec<f64>)> = labels
        .iter()
        .zip(counts)
        .map(|(l, c)| {
            let n = c.runs.max(1) as f64;
            let mut values = vec![100.0 * c.found as f64 / n];
            if stated {
                values.push(100.0 * c.optimal as f64 / n);
            }
            (l.to_string(), values)
        })
        .collect();
    let series: &[&str] = if stated {
        &["found", "optimal"]
    } else {
        &["found"]
    };
    let title = match stated {
        true => "Success and optimality per planner",
        false => "Success per planner",
    };
    bar_chart(
        "success.svg",
        &format!("{title}{note}"),
        "share of runs (%)",
        series,
        &bars,
    )
}

/// The chart files of the sweep's `charts` ([`charts`]), under `charts/`.
pub fn files(charts: Vec<Chart>) -> Vec<OutputFile> {
    charts
        .into_iter()
        .map(|c| OutputFile {
            path: format!("charts/{}", c.file).into(),
            contents: c.svg.into_bytes(),
        })
        .collect()
}

/// When every label runs one planner and they differ in exactly one parameter, numeric
/// for at least three labels: length against that parameter, one line per map (labels
/// with a non-numeric value, such as PA-star's `radius = "size"`, are left out).
fn default_study(experiment: &Experiment) -> Option<ChartSpec> {
    if experiment.planners.len() < 3 {
        return None;
    }
    let first = experiment.planners[0].name;
    if experiment.planners.iter().any(|p| p.name != first) {
        return None;
    }
    let parameters: Vec<_> = experiment
        .planners
        .iter()
        .map(|p| p.parameters(experiment.seed))
        .collect();
    let objects: Vec<&serde_json::Map<String, serde_json::Value>> =
        parameters.iter().filter_map(|p| p.as_object()).collect();
    let varying: Vec<&String> = objects
        .first()?
        .keys()
        .filter(|k| objects.iter().any(|o| o.get(*k) != objects[0].get(*k)))
        .collect();
    let [key] = varying.as_slice() else {
        return None;
    };
    let numeric = objects
        .iter()
        .filter(|o| o.get(*key).is_some_and(serde_json::Value::is_number))
        .count();
    (numeric >= 3).then(|| ChartSpec {
        x: (*key).clone(),
        y: "length".into(),
        group: None,
        title: None,
    })
}

/// The value of `x` or `group` for a run of label number `label`: a resolved parameter,
/// `bucket`, `map` or `planner`.
fn key_value(
    experiment: &Experiment,
    record: &RunRecord,
    label: Option<usize>,
    key: &str,
) -> Option<serde_json::Value> {
    match key {
        "bucket" => record.bucket.map(serde_json::Value::from),
        "map" => Some(record.map.clone().into()),
        "planner" => Some(record.algorithm.clone().into()),
        _ => experiment
            .planners
            .get(label?)?
            .parameters(experiment.seed)
            .get(key)
            .cloned(),
    }
}

/// The metric `y` of a run: a record field or a counter.
pub fn metric(record: &RunRecord, y: &str) -> Option<f64> {
    match y {
        "length" => record.length,
        "optimal_length" => record.optimal_length,
        "steps" => record.steps.map(|v| v as f64),
        "turns" => record.turns.map(|v| v as f64),
        "score" => record.score.map(|v| v as f64),
        "time_ms" => Some(record.time_ms),
        counter => record.counters.get(counter).map(|v| v as f64),
    }
}

/// The parameter-study chart `i` of `spec`: each group's median metric against x.
fn study_chart(i: usize, spec: &ChartSpec, series: &[(String, Vec<(f64, f64)>)]) -> Chart {
    let mut title = spec
        .title
        .clone()
        .unwrap_or_else(|| format!("{} against {}", spec.y, spec.x));
    // `y` may name a counter no planner of the config reports (the config cannot tell
    // before the runs): the empty chart says so rather than looking like missing data.
    if series.iter().all(|(_, line)| line.is_empty()) {
        title.push_str(&format!(" (no run has both {} and {})", spec.y, spec.x));
    }
    let file = format!(
        "study-{}-{}-{}.svg",
        i + 1,
        file_safe(&spec.y),
        file_safe(&spec.x)
    );
    line_chart(&file, &title, &spec.x, &axis_label(&spec.y), series)
}

fn axis_label(y: &str) -> String {
    match y {
        "length" | "optimal_length" => format!("{y} (cells, Euclidean)"),
        "time_ms" => "time (ms)".into(),
        "steps" => "steps D (moves)".into(),
        "turns" => "turns T".into(),
        other => format!("median {other}"),
    }
}

fn file_safe(text: &str) -> String {
    text.chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || c == '-' {
                c
            } else {
                '_'
            }
        })
        .collect()
}

/// `data` with every series name cleaned for XML.
fn cleaned<T: Clone>(data: &[(String, T)]) -> Vec<(String, T)> {
    data.iter()
        .map(|(name, values)| (xml_text(name), values.clone()))
        .collect()
}

fn colour(i: usize) -> RGBColor {
    let hex = planner_figures::colour(i);
    let byte = |k: usize| u8::from_str_radix(hex.get(k..k + 2).unwrap_or("00"), 16).unwrap_or(0);
    RGBColor(byte(1), byte(3), byte(5))
}

/// A range `[lo, hi]` padded by 5 % (or 1 when flat) for an axis.
fn padded(lo: f64, hi: f64, from_zero: bool) -> std::ops::Range<f64> {
    let lo = if from_zero { lo.min(0.0) } else { lo };
    let span = if hi > lo { hi - lo } else { 1.0 };
    let low = if from_zero && lo >= 0.0 {
        0.0
    } else {
        lo - 0.05 * span
    };
    low..hi + 0.05 * span
}

fn finish(file: &str, title: &str, svg: String) -> Chart {
    Chart {
        file: file.to_string(),
        title: title.to_string(),
        svg,
    }
}

/// The drawing area of one chart.
type Area<'b> = DrawingArea<SVGBackend<'b>, plotters::coord::Shift>;

/// A chart's coordinates over an [`Area`]: f64 on both axes.
type Plot<'a, 'b> = ChartContext<'a, SVGBackend<'b>, Cartesian2d<RangedCoordf64, RangedCoordf64>>;

type DrawResult = Result<(), Box<dyn std::error::Error>>;

/// The chart `file` titled `title` (cleaned for XML): `draw` on the plot area of an SVG
/// page of [`SIZE`], given the cleaned title, and `key` beside it, one line per entry
/// (the page taller when the key needs it), so that no key covers the data. A drawing
/// error leaves the page as far as it got.
fn render_chart(
    file: &str,
    title: &str,
    key: &[KeyEntry],
    draw: impl FnOnce(&Area<'_>, &str) -> DrawResult,
) -> Chart {
    let title = &xml_text(title);
    let height = SIZE.1.max(70 + KEY_LINE * key.len() as u32);
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, (SIZE.0, height)).into_drawing_area();
        let (plot, side) = root.split_horizontally(SIZE.0 - KEY_WIDTH);
        let _ = draw(&plot, &shortened_to(title, TITLE_CHARS));
        let _ = draw_key(&side, key);
        let _ = root.present();
    }
    finish(file, title, svg)
}

/// The most characters of a title drawn: beyond, it ends with an ellipsis (report.html's
/// heading gives it whole).
const TITLE_CHARS: usize = 110;

/// The caption's font: 22 px, smaller for a long title so that it fits the plot's width.
fn caption_font(title: &str) -> (&'static str, u32) {
    let chars = title.chars().count().max(1) as u32;
    ("sans-serif", (22 * 52 / chars).clamp(11, 22))
}

/// The key: per entry, its colour's swatch and its text (cleaned for XML).
fn draw_key(side: &Area<'_>, key: &[KeyEntry]) -> DrawResult {
    side.fill(&WHITE)?;
    let style = ("sans-serif", 13).into_font().color(&BLACK);
    for (row, entry) in key.iter().enumerate() {
        let y = 56 + (KEY_LINE * row as u32) as i32;
        if let Some(c) = entry.colour {
            side.draw(&Rectangle::new([(4, y - 5), (16, y + 6)], c.filled()))?;
        }
        let text = xml_text(&entry.text);
        side.draw(&Text::new(text, (22, y - 7), style.clone()))?;
    }
    Ok(())
}

/// A white chart titled `title` with one category per name along x (at 0, 1, ...,
/// labelled "planner label", by name, or by number when [`numbered`]) and `y` up the y
/// axis, described by `y_desc`; its mesh is drawn.
fn by_label<'a, 'b>(
    root: &'a Area<'b>,
    title: &str,
    names: &[String],
    y: std::ops::Range<f64>,
    y_desc: &str,
) -> Result<Plot<'a, 'b>, Box<dyn std::error::Error>> {
    let numbered = numbered(names);
    root.fill(&WHITE)?;
    let n = names.len();
    let mut chart = ChartBuilder::on(root)
        .caption(title, caption_font(title))
        .margin(14)
        .x_label_area_size(60)
        .y_label_area_size(80)
        .build_cartesian_2d(-0.5f64..(n as f64 - 0.5), y)?;
    let label_of = |x: &f64| -> String {
        let k = x.round();
        if (x - k).abs() < 1e-9 && k >= 0.0 {
            let every = names.len().div_ceil(MAX_X_TICKS).max(1);
            let number = k as usize + 1;
            match (numbered, names.get(k as usize)) {
                (true, Some(_)) if number % every == 0 || number == 1 => format!("{number}"),
                (true, Some(_)) => String::new(),
                (false, Some(name)) => shortened(name),
                (_, None) => String::new(),
            }
        } else {
            String::new()
        }
    };
    chart
        .configure_mesh()
        .x_labels(n.max(1))
        .x_label_formatter(&label_of)
        .x_desc("planner label")
        .y_desc(y_desc)
        .disable_x_mesh()
        .draw()?;
    Ok(chart)
}

/// Box plots (median, quartiles by type 7, whiskers to the extremes), one per label
/// (none for a label without values).
fn box_plot(file: &str, title: &str, y_desc: &str, data: &[(String, Option<BoxStats>)]) -> Chart {
    let data = &cleaned(data);
    let names: Vec<String> = data.iter().map(|(l, _)| l.clone()).collect();
    let numbered = numbered(&names);
    let key: Vec<KeyEntry> = data
        .iter()
        .enumerate()
        .map(|(i, (label, stats))| {
            let text = category_text(i, &shortened(label), numbered);
            let text = match stats {
                Some(b) => format!("{text} (median {:.3})", b[0]),
                None => format!("{text} (no values)"),
            };
            KeyEntry {
                colour: Some(colour(i)),
                text,
            }
        })
        .collect();
    render_chart(file, title, &key, |root, title| {
        draw_box_plot(root, title, &xml_text(y_desc), data)
    })
}

fn draw_box_plot(
    root: &Area<'_>,
    title: &str,
    y_desc: &str,
    data: &[(String, Option<BoxStats>)],
) -> DrawResult {
    let boxes = || data.iter().filter_map(|(_, b)| *b);
    let hi = boxes().map(|b| b[4]).fold(f64::MIN, f64::max).max(0.0);
    let lo = boxes().map(|b| b[3]).fold(f64::MAX, f64::min).min(hi);
    let names: Vec<String> = data.iter().map(|(l, _)| l.clone()).collect();
    let mut chart = by_label(root, title, &names, padded(lo, hi, true), y_desc)?;
    for (i, (_, stats)) in data.iter().enumerate() {
        let Some([median, q1, q3, min, max]) = *stats else {
            continue;
        };
        let x = i as f64;
        let c = colour(i);
        chart.draw_series(std::iter::once(Rectangle::new(
            [(x - 0.3, q1), (x + 0.3, q3)],
            c.mix(0.35).filled(),
        )))?;
        chart.draw_series(std::iter::once(Rectangle::new(
            [(x - 0.3, q1), (x + 0.3, q3)],
            c.stroke_width(2),
        )))?;
        for segment in [
            vec![(x - 0.3, median), (x + 0.3, median)],
            vec![(x, q3), (x, max)],
            vec![(x, q1), (x, min)],
            vec![(x - 0.15, max), (x + 0.15, max)],
            vec![(x - 0.15, min), (x + 0.15, min)],
        ] {
            chart.draw_series(std::iter::once(PathElement::new(
                segment,
                c.stroke_width(2),
            )))?;
        }
    }
    Ok(())
}

/// A line chart, one line (with point markers) per series.
fn line_chart(
    file: &str,
    title: &str,
    x_desc: &str,
    y_desc: &str,
    series: &[(String, Vec<(f64, f64)>)],
) -> Chart {
    let series = &cleaned(series);
    let key: Vec<KeyEntry> = series
        .iter()
        .enumerate()
        .map(|(i, (label, _))| KeyEntry::series(i, label))
        .collect();
    render_chart(file, title, &key, |root, title| {
        draw_line_chart(root, title, &xml_text(x_desc), &xml_text(y_desc), series)
    })
}

fn draw_line_chart(
    root: &Area<'_>,
    title: &str,
    x_desc: &str,
    y_desc: &str,
    series: &[(String, Vec<(f64, f64)>)],
) -> DrawResult {
    root.fill(&WHITE)?;
    let points: Vec<(f64, f64)> = series.iter().flat_map(|(_, p)| p.iter().copied()).collect();
    let fold = |f: fn(f64, f64) -> f64, init: f64, pick: fn(&(f64, f64)) -> f64| {
        points.iter().map(pick).fold(init, f)
    };
    let (x_lo, x_hi) = (
        fold(f64::min, f64::MAX, |p| p.0),
        fold(f64::max, f64::MIN, |p| p.0),
    );
    let (y_lo, y_hi) = (
        fold(f64::min, f64::MAX, |p| p.1),
        fold(f64::max, f64::MIN, |p| p.1),
    );
    let (x_range, y_range) = if points.is_empty() {
        (0.0..1.0, 0.0..1.0)
    } else {
        (padded(x_lo, x_hi, false), padded(y_lo, y_hi, false))
    };
    let mut chart = ChartBuilder::on(root)
        .caption(title, caption_font(title))
        .margin(14)
        .x_label_area_size(50)
        .y_label_area_size(80)
        .build_cartesian_2d(x_range, y_range)?;
    chart
        .configure_mesh()
        .x_desc(x_desc)
        .y_desc(y_desc)
        .draw()?;
    for (i, (_, line)) in series.iter().enumerate() {
        let c = colour(i);
        chart.draw_series(LineSeries::new(line.iter().copied(), c.stroke_width(2)))?;
        chart.draw_series(line.iter().map(|&p| Circle::new(p, 3, c.filled())))?;
    }
    Ok(())
}

/// Grouped bars: per label, one bar per named series.
fn bar_chart(
    file: &str,
    title: &str,
    y_desc: &str,
    series: &[&str],
    data: &[(String, Vec<f64>)],
) -> Chart {
    let data = &cleaned(data);
    let names: Vec<String> = data.iter().map(|(l, _)| l.clone()).collect();
    let mut key: Vec<KeyEntry> = series
        .iter()
        .enumerate()
        .map(|(s, name)| KeyEntry::series(s, name))
        .collect();
    // With numbered categories, which label each number is.
    if numbered(&names) {
        key.extend(names.iter().enumerate().map(|(i, name)| KeyEntry {
            colour: None,
            text: category_text(i, &shortened(name), true),
        }));
    }
    render_chart(file, title, &key, |root, title| {
        draw_bar_chart(root, title, &xml_text(y_desc), series, data)
    })
}

fn draw_bar_chart(
    root: &Area<'_>,
    title: &str,
    y_desc: &str,
    series: &[&str],
    data: &[(String, Vec<f64>)],
) -> DrawResult {
    let names: Vec<String> = data.iter().map(|(l, _)| l.clone()).collect();
    let mut chart = by_label(root, title, &names, 0f64..115f64, y_desc)?;
    let width = 0.8 / series.len().max(1) as f64;
    for s in 0..series.len() {
        let c = colour(s);
        let bars = data.iter().enumerate().filter_map(|(i, (_, values))| {
            let v = *values.get(s)?;
            let x0 = i as f64 - 0.4 + s as f64 * width;
            Some(Rectangle::new(
                [(x0, 0.0), (x0 + width * 0.9, v)],
                c.filled(),
            ))
        });
        chart.draw_series(bars)?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::{study_chart, ChartSpec};

    /// A chart without a point (its `y` a counter no planner reports) says so in its title.
    #[test]
    fn an_empty_study_chart_says_why() {
        let spec = ChartSpec {
            x: "weight".into(),
            y: "n_nothing".into(),
            group: None,
            title: None,
        };
        let empty = study_chart(0, &spec, &[("map01".into(), Vec::new())]);
        assert_eq!(
            empty.title,
            "n_nothing against weight (no run has both n_nothing and weight)"
        );
        let drawn = study_chart(0, &spec, &[("map01".into(), vec![(1.0, 2.0)])]);
        assert_eq!(drawn.title, "n_nothing against weight");
    }
}
