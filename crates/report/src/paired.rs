//! Planners compared problem by problem against a baseline (section name `paired`).
//!
//! Aggregates per planner hide which planner wins on which problem; a researcher comparing
//! a planner with a baseline wants per-problem ratios. For each label other than the
//! baseline (the config's first label, or the section's `baseline` option), over the
//! problems both ran:
//!
//! - a problem is *solved* by a label when every repeat of it found a path; the table
//!   counts the problems solved by both, by the label only and by the baseline only;
//! - over the problems solved by both, per problem the label's value over the baseline's,
//!   each the median over the repeats (lengths over the found runs): `n_expanded` (where
//!   both report it and both are positive), the search time (both positive) and the path
//!   length; the ratios are summarised by their geometric mean (the usual summary of
//!   per-instance ratios, Fleming and Wallace 1986), with Student's t 95 % interval on the
//!   logarithms for time ([`planner_stats::geometric_mean`]), and by how many problems
//!   the label needs fewer expansions or less time than the baseline, and the largest
//!   length ratio.
//!
//! A ratio below 1 favours the label. Problems solved by only one side are left out of
//! the ratios (a failed run's time is often its budget) and counted instead. The section
//! reads passes over the records, so it renders for a sweep too large to hold in memory;
//! it keeps a few numbers of every run (a median needs every repeat), about 100 bytes a
//! run where the aggregate sections keep a bounded number per group.

use std::collections::BTreeMap;
use std::fmt::Write as _;

use planner_runner::config::Experiment;
use planner_runner::passes::RecordPasses;
use planner_runner::record::RunRecord;
use planner_runner::RunnerError;

use crate::{md_cell, md_code, median_iqr, Context, OptionError, Section};

/// The section (name `paired`).
pub struct Paired;

/// The option naming the baseline label.
const BASELINE: &str = "baseline";

impl Section for Paired {
    fn name(&self) -> &'static str {
        "paired"
    }

    /// When the experiment has two labels or more.
    fn applies(&self, context: &Context<'_>) -> bool {
        context.experiment.planners.len() >= 2
    }

    fn options_schema(&self) -> serde_json::Value {
        serde_json::json!({ "properties": { BASELINE: {
            "type": "string",
            "description": "The label the others are compared with (default: the config's first label)."
        } } })
    }

    /// Takes `baseline`, a label of the experiment.
    fn check(&self, options: &toml::Table) -> Result<(), OptionError> {
        for (key, value) in options {
            if key != BASELINE {
                return Err(OptionError::Unknown {
                    section: self.name().into(),
                    key: key.clone(),
                    only: Some(BASELINE.into()),
                });
            }
            if !value.is_str() {
                return Err(OptionError::NotALabel {
                    section: self.name().into(),
                    key: key.clone(),
                });
            }
        }
        Ok(())
    }

    fn check_experiment(
        &self,
        options: &toml::Table,
        experiment: &Experiment,
    ) -> Result<(), OptionError> {
        self.check(options)?;
        match options.get(BASELINE).and_then(|v| v.as_str()) {
            Some(label) if !experiment.planners.iter().any(|p| p.label == label) => {
                Err(OptionError::UnknownLabel {
                    section: self.name().into(),
                    label: label.into(),
                    labels: experiment
                        .planners
                        .iter()
                        .map(|p| p.label.clone())
                        .collect(),
                })
            }
            _ => Ok(()),
        }
    }

    fn render_passes(
        &self,
        context: &Context<'_>,
        out: &mut String,
        _reproduction: &mut planner_runner::record::Reproduction,
    ) -> Result<(), RunnerError> {
        let baseline = context.options.get(BASELINE).and_then(|v| v.as_str());
        out.push_str(&table(context.experiment, context.passes, baseline)?);
        Ok(())
    }

    fn streams(&self) -> bool {
        true
    }
}

/// One run, as the comparison reads it.
#[derive(Debug, Clone, Copy)]
struct Run {
    time_ms: f64,
    expanded: Option<u64>,
    length: Option<f64>,
    cost: Option<f64>,
    found: bool,
}

/// A label's repeats of one problem, summarised.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Problem {
    solved: bool,
    time_ms: f64,
    expanded: Option<f64>,
    length: Option<f64>,
    cost: Option<f64>,
}

fn median(values: &[f64]) -> Option<f64> {
    median_iqr(values).map(|(m, _, _)| m)
}

impl Problem {
    fn of(runs: &[Run]) -> Problem {
        let times: Vec<f64> = runs.iter().map(|r| r.time_ms).collect();
        let expanded: Option<Vec<f64>> =
            runs.iter().map(|r| r.expanded.map(|e| e as f64)).collect();
        let lengths: Vec<f64> = runs
            .iter()
            .filter(|r| r.found)
            .filter_map(|r| r.length)
            .collect();
        let costs: Vec<f64> = runs
            .iter()
            .filter(|r| r.found)
            .filter_map(|r| r.cost)
            .collect();
        Problem {
            solved: !runs.is_empty() && runs.iter().all(|r| r.found),
            time_ms: median(&times).unwrap_or(0.0),
            expanded: expanded.and_then(|e| median(&e)),
            length: median(&lengths),
            cost: median(&costs),
        }
    }
}

/// One label against the baseline, over the problems both ran.
#[derive(Debug, Default, PartialEq)]
struct Comparison {
    problems: u64,
    both: u64,
    only_label: u64,
    only_baseline: u64,
    /// (label / baseline) per problem solved by both.
    expanded: Vec<f64>,
    time: Vec<f64>,
    length: Vec<f64>,
    cost: Vec<f64>,
}

impl Comparison {
    fn add(&mut self, label: &Problem, baseline: &Problem) {
        self.problems += 1;
        match (label.solved, baseline.solved) {
            (true, true) => self.both += 1,
            (true, false) => self.only_label += 1,
            (false, true) => self.only_baseline += 1,
            (false, false) => {}
        }
        if !(label.solved && baseline.solved) {
            return;
        }
        let positive = |a: Option<f64>, b: Option<f64>| match (a, b) {
            (Some(a), Some(b)) if a > 0.0 && b > 0.0 => Some(a / b),
            _ => None,
        };
        self.expanded
            .extend(positive(label.expanded, baseline.expanded));
        self.time
            .extend(positive(Some(label.time_ms), Some(baseline.time_ms)));
        self.length.extend(positive(label.length, baseline.length));
        self.cost.extend(positive(label.cost, baseline.cost));
    }
}

/// The runs of each problem (map, problem index, start, goal), per label.
type Runs = BTreeMap<(usize, usize, (u32, u32), (u32, u32)), Vec<Vec<Run>>>;

/// Every problem's repeats, summarised per label, with the baseline label's index.
pub struct PerProblem {
    /// The baseline's index among the experiment's labels.
    pub base: usize,
    /// Per problem (valid, run by the baseline) the summary of each label that ran it.
    problems: Vec<Vec<Option<Problem>>>,
}

impl PerProblem {
    /// One pass over the records: each valid problem's runs per label, summarised, with
    /// `baseline` (a label; default the first) as the baseline.
    pub fn of(
        experiment: &Experiment,
        passes: &dyn RecordPasses,
        baseline: Option<&str>,
    ) -> Result<PerProblem, RunnerError> {
        let labels = crate::positions(experiment.planners.iter().map(|p| p.label.as_str()));
        let maps = crate::positions(experiment.maps.iter().map(|m| m.name.as_str()));
        let n_labels = experiment.planners.len();
        let base = baseline.and_then(|b| labels.get(b).copied()).unwrap_or(0);
        let mut runs: Runs = BTreeMap::new();
        let mut invalid = std::collections::HashSet::new();
        passes.pass(&mut |r: &RunRecord| {
            let (Some(&l), Some(&m)) = (labels.get(r.planner.as_str()), maps.get(r.map.as_str()))
            else {
                return;
            };
            let key = (m, r.problem, (r.start.x, r.start.y), (r.goal.x, r.goal.y));
            if r.is_invalid() {
                invalid.insert(key);
                return;
            }
            runs.entry(key)
                .or_insert_with(|| vec![Vec::new(); n_labels])[l]
                .push(Run {
                    time_ms: r.time_ms,
                    expanded: r.counters.get("n_expanded"),
                    length: r.length,
                    cost: r.cost,
                    found: r.is_found(),
                });
        })?;
        let problems = runs
            .into_iter()
            .filter(|(key, per_label)| !invalid.contains(key) && !per_label[base].is_empty())
            .map(|(_, per_label)| {
                per_label
                    .iter()
                    .map(|label_runs| (!label_runs.is_empty()).then(|| Problem::of(label_runs)))
                    .collect()
            })
            .collect();
        Ok(PerProblem { base, problems })
    }

    /// Label `l` against the baseline over the problems both ran.
    fn compare(&self, l: usize) -> Comparison {
        let mut comparison = Comparison::default();
        for per_label in &self.problems {
            if let (Some(label), Some(baseline)) = (&per_label[l], &per_label[self.base]) {
                comparison.add(label, baseline);
            }
        }
        comparison
    }

    /// Per problem solved by both label `l` and the baseline, `(baseline's, label's)`
    /// median expansions (`time` false) or time (`time` true), where both are positive.
    pub fn points(&self, l: usize, time: bool) -> Vec<(f64, f64)> {
        let value = |p: &Problem| match time {
            true => Some(p.time_ms),
            false => p.expanded,
        };
        self.problems
            .iter()
            .filter_map(|per_label| {
                let (label, baseline) = (per_label[l].as_ref()?, per_label[self.base].as_ref()?);
                if !(label.solved && baseline.solved) {
                    return None;
                }
                let (b, v) = (value(baseline)?, value(label)?);
                (b > 0.0 && v > 0.0).then_some((b, v))
            })
            .collect()
    }
}

/// The baseline label a config's `paired` section names, if it does.
pub fn configured_baseline(experiment: &Experiment) -> Option<&str> {
    let request = experiment.sections.as_ref()?.get("paired")?;
    request.options.get(BASELINE)?.as_str()
}

/// The section's markdown: one row per label other than `baseline` (default: the first).
pub fn table(
    experiment: &Experiment,
    passes: &dyn RecordPasses,
    baseline: Option<&str>,
) -> Result<String, RunnerError> {
    let per_problem = PerProblem::of(experiment, passes, baseline)?;
    let comparisons: Vec<Comparison> = (0..experiment.planners.len())
        .map(|l| per_problem.compare(l))
        .collect();
    Ok(render(experiment, per_problem.base, &comparisons))
}

fn render(experiment: &Experiment, base: usize, comparisons: &[Comparison]) -> String {
    let baseline = &experiment.planners[base].label;
    let costs = crate::aggregate::has_costs(experiment);
    let mut out = format!(
        "## Planners compared problem by problem\n\nEach label against {}, over the problems both ran: the problems solved (a path in every repeat) by both, by the label only and by the baseline only; then, over the problems solved by both, the geometric mean of the label's value over the baseline's (each the median over the repeats; below 1 favours the label), with the problems where the label needs fewer expansions or less time. Time: the geometric mean with its 95 % interval (Student's t on the logarithms); it compares times measured in this sweep, on its machine and threads.{}\n\n| Planner | Problems | Solved by both | Only planner | Only baseline | Expansions ratio | Fewer expansions | Time ratio (95 % interval) | Less time | Length ratio | Largest length ratio |{}\n|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|{}\n",
        md_code(baseline),
        if costs { COSTS } else { "" },
        if costs { " Cost ratio |" } else { "" },
        if costs { "---:|" } else { "" },
    );
    for (l, c) in comparisons.iter().enumerate() {
        if l == base || c.problems == 0 {
            continue;
        }
        let geo = |ratios: &[f64]| {
            planner_stats::geometric_mean(ratios, 0.95).map_or("-".to_string(), |g| ratio(g.mean))
        };
        let below = |ratios: &[f64]| {
            let n = ratios.iter().filter(|&&r| r < 1.0).count();
            match ratios.len() {
                0 => "-".to_string(),
                all => format!("{n} of {all}"),
            }
        };
        let time = match planner_stats::geometric_mean(&c.time, 0.95) {
            Ok(g) => match g.interval {
                Some((low, high)) => {
                    format!("{} ({} to {})", ratio(g.mean), ratio(low), ratio(high))
                }
                None => ratio(g.mean),
            },
            Err(_) => "-".into(),
        };
        let largest = c
            .length
            .iter()
            .copied()
            .reduce(f64::max)
            .map_or("-".into(), ratio);
        let cost = match costs {
            true => format!(" {} |", geo(&c.cost)),
            false => String::new(),
        };
        let _ = writeln!(
            out,
            "| {} | {} | {} | {} | {} | {} | {} | {time} | {} | {} | {largest} |{cost}",
            md_cell(&experiment.planners[l].label),
            c.problems,
            c.both,
            c.only_label,
            c.only_baseline,
            geo(&c.expanded),
            below(&c.expanded),
            below(&c.time),
            geo(&c.length),
        );
    }
    out.push('\n');
    out
}

/// The section's note on a sweep with maps with cell costs.
const COSTS: &str = " Length: the Euclidean length, unweighted; on maps with cell costs least-cost planners minimise the path `cost` instead, and the cost ratio compares it, over the problems solved by both where both runs have a cost.";

/// A ratio with three decimals, or three significant digits below 0.01 (`1.50e-4`).
fn ratio(r: f64) -> String {
    match r >= 0.01 {
        true => format!("{r:.3}"),
        false => format!("{r:.2e}"),
    }
}
