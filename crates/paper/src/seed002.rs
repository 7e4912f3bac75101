//! Seed 002's tables in `summary.md`, comparing the labels that run the planner the config
//! names as the section's `proposed` one (`{ name = "seed002", proposed = "pastar" }`)
//! with every other label: path lengths with `R_length` and `R_time` per scenario (Tables
//! 6-10) and, with three or more repeats, the timing tests (Tables 11-14).
//!
//! - `R_length = (length_PA - length_ref) / length_PA` and `R_time` likewise with the
//!   median times (equations 10-11, the paper's sign: negative when PA-star is shorter or
//!   faster). Each PA-star label is compared with each non-PA-star label. `R_time` is
//!   unbounded below when PA-star's time is near zero (a free line: no search at all).
//! - Per scenario, over all planner labels: the Kruskal-Wallis test of the `plan` times
//!   (H, the paper's "chi-square", with df and p; Table 11); per label the median time
//!   (IQR), Shapiro-Wilk's W and p, and Dunn's z and p against the first PA-star label
//!   (Tables 12-14). `z = (mean rank of the planner - mean rank of PA-star) / SE`, so it is
//!   positive when the planner is slower than PA-star (the paper's sign varies between
//!   its tables). Dunn's p is Bonferroni-adjusted over all `k (k - 1) / 2` pairs of the
//!   `k` labels, as the paper's p-values are (see planner-stats).
//!
//! A scenario is one (map, problem). Lengths come from repeat 0, except for seeded
//! planners (CAPSO), whose length is the mean over the repeats that found a path (the
//! status column then counts them); times come from all repeats.
//!
//! [`Seed002Capso`] (section `seed002_capso`, for the labels running the planner the
//! config names, `{ name = "seed002_capso", planner = "capso" }`)
//! follows seed 002 section 4.2.2 (Fig. 11): per scenario and CAPSO label its control
//! points and the found count, mean, min and max length over the repeats, then the mean
//! over the repeats of the `best_fitness` series (Fig. 11 b) every 10 iterations.

use std::fmt::Write as _;

use planner_stats::{bonferroni, dunn, kruskal_wallis, shapiro_wilk};

use planner_report::md_cell;
use planner_report::{median_iqr, Context, OptionError, Reproduction, Section};
use planner_runner::config::{Experiment, MapEntry, PlannerSpec, ProblemEntry};
use planner_runner::index::ResultsIndex;
use planner_runner::record::{RunRecord, RunStatus};

/// Seed 002's comparison of a proposed planner with its references (section name
/// `seed002`; option `proposed`: the registry name of the proposed planner, every other
/// label is a reference).
pub struct Seed002;

impl Section for Seed002 {
    fn name(&self) -> &'static str {
        "seed002"
    }

    /// Never by itself: a paper layout shows when a config names it.
    fn applies(&self, _context: &Context<'_>) -> bool {
        false
    }

    fn options_schema(&self) -> serde_json::Value {
        serde_json::json!({
            "properties": { "proposed": { "type": "string", "description": "The registry name of the proposed planner (one the config's labels run); every other label is a reference." } },
            "required": ["proposed"]
        })
    }

    fn check(&self, options: &toml::Table) -> Result<(), OptionError> {
        planner_option(self.name(), options, "proposed").map(drop)
    }

    /// `proposed` must be the registry name of one of the config's planners: another
    /// (a typo, or a planner no label runs) drew no table without a word.
    fn check_experiment(
        &self,
        options: &toml::Table,
        experiment: &Experiment,
    ) -> Result<(), OptionError> {
        let name = planner_option(self.name(), options, "proposed")?;
        config_planner(self.name(), "proposed", name, experiment)
    }

    fn render(&self, context: &Context<'_>, out: &mut String, _reproduction: &mut Reproduction) {
        if let Ok(proposed) = planner_option(self.name(), context.options, "proposed") {
            out.push_str(&render(context.experiment, context.index, proposed));
        }
    }
}

/// Seed 002's CAPSO lengths and mean convergence curve (section name `seed002_capso`;
/// option `planner`: the registry name of the planner to show; module docs).
pub struct Seed002Capso;

impl Section for Seed002Capso {
    fn name(&self) -> &'static str {
        "seed002_capso"
    }

    /// Never by itself: a paper layout shows when a config names it.
    fn applies(&self, _context: &Context<'_>) -> bool {
        false
    }

    fn options_schema(&self) -> serde_json::Value {
        serde_json::json!({
            "properties": { "planner": { "type": "string", "description": "The registry name of the planner whose lengths and convergence are shown (one the config's labels run)." } },
            "required": ["planner"]
        })
    }

    fn check(&self, options: &toml::Table) -> Result<(), OptionError> {
        planner_option(self.name(), options, "planner").map(drop)
    }

    /// `planner` must be the registry name of one of the config's planners: another
    /// (a typo, or a planner no label runs) drew no table without a word.
    fn check_experiment(
        &self,
        options: &toml::Table,
        experiment: &Experiment,
    ) -> Result<(), OptionError> {
        let name = planner_option(self.name(), options, "planner")?;
        config_planner(self.name(), "planner", name, experiment)
    }

    fn render(&self, context: &Context<'_>, out: &mut String, _reproduction: &mut Reproduction) {
        if let Ok(capso) = planner_option(self.name(), context.options, "planner") {
            out.push_str(&render_capso(context.experiment, context.index, capso));
        }
    }
}

/// Checks that `name`, the section's option `key`, is the registry name of a planner the
/// experiment runs.
fn config_planner(
    section: &str,
    key: &str,
    name: &str,
    experiment: &Experiment,
) -> Result<(), OptionError> {
    if experiment.planners.iter().any(|p| p.name == name) {
        return Ok(());
    }
    let mut planners: Vec<String> = Vec::new();
    for p in &experiment.planners {
        if !planners.iter().any(|q| q == p.name) {
            planners.push(p.name.to_string());
        }
    }
    Err(OptionError::NotAPlanner {
        section: section.to_string(),
        key: key.to_string(),
        name: name.to_string(),
        planners,
    })
}

/// The one option of a section that names a planner: `key`, a string, and nothing else.
fn planner_option<'a>(
    section: &str,
    options: &'a toml::Table,
    key: &str,
) -> Result<&'a str, OptionError> {
    if let Some(other) = options.keys().find(|k| *k != key) {
        return Err(OptionError::Unknown {
            section: section.to_string(),
            key: other.clone(),
            only: Some(key.to_string()),
        });
    }
    match options.get(key) {
        Some(toml::Value::String(name)) => Ok(name),
        Some(_) => Err(OptionError::NotAName {
            section: section.to_string(),
            key: key.to_string(),
        }),
        None => Err(OptionError::Missing {
            section: section.to_string(),
            key: key.to_string(),
        }),
    }
}

/// The seed-002 sections of summary.md, or nothing when no label runs `proposed_name`.
fn render(experiment: &Experiment, index: &ResultsIndex<'_>, proposed_name: &str) -> String {
    let proposed: Vec<&PlannerSpec> = experiment
        .planners
        .iter()
        .filter(|p| p.name == proposed_name)
        .collect();
    let Some(base) = proposed.first() else {
        return String::new();
    };
    let references: Vec<&PlannerSpec> = experiment
        .planners
        .iter()
        .filter(|p| p.name != proposed_name)
        .collect();
    let mut out = String::from("## PA-star and its references (seed 002, Tables 6-10 layout)\n\n");
    out.push_str("Path length of repeat 0 (seeded planners: the mean over the repeats that found a path, their count in the status column); `R_length = (L_PA - L_ref) / L_PA` and `R_time = (t_PA - t_ref) / t_PA` with median times (equations 10-11: negative when PA-star is shorter or faster).\n\n");
    let mut timing = String::new();
    let mut kw_rows = String::new();
    for map in &experiment.maps {
        for problem in map.problems.iter().filter(|p| p.invalid.is_none()) {
            let scenario = Scenario {
                experiment,
                index,
                map,
                problem,
            };
            scenario.lengths(&mut out, &proposed, &references);
            if experiment.repeats >= 3 && experiment.planners.len() >= 2 {
                scenario.timing_tests(&mut kw_rows, &mut timing, base);
            }
        }
    }
    if !kw_rows.is_empty() {
        let _ = writeln!(
            out,
            "## Search time tests (seed 002, section 4.4, Tables 11-14 layout)\n\n{} repeats per planner and scenario; times of `plan` in ms (wall clock: not reproducible to the digit).\n\n### Kruskal-Wallis across planners (Table 11)\n\n| Scenario | H (chi-square) | DF | p |\n|---|---:|---:|---:|\n{kw_rows}",
            experiment.repeats
        );
        out.push_str(&timing);
    }
    out
}

/// One scenario (map, problem) of a seed-002 comparison and the lookups its tables share.
struct Scenario<'a> {
    experiment: &'a Experiment,
    index: &'a ResultsIndex<'a>,
    map: &'a MapEntry,
    problem: &'a ProblemEntry,
}

impl Scenario<'_> {
    fn runs(&self, label: &str) -> Vec<&RunRecord> {
        self.index.runs(&self.map.name, self.problem.index, label)
    }

    /// Whether `label` runs a seeded planner (its length is a mean over the repeats).
    fn stochastic(&self, label: &str) -> bool {
        self.experiment
            .planners
            .iter()
            .any(|p| p.label == label && p.factory.specs().seeded)
    }

    fn length(&self, label: &str) -> Option<f64> {
        let all = self.runs(label);
        if self.stochastic(label) {
            let found: Vec<f64> = all.iter().filter_map(|r| r.length).collect();
            (!found.is_empty()).then(|| found.iter().sum::<f64>() / found.len() as f64)
        } else {
            all.iter().find(|r| r.repeat == 0).and_then(|r| r.length)
        }
    }

    fn times(&self, label: &str) -> Vec<f64> {
        self.runs(label).iter().map(|r| r.time_ms).collect()
    }

    fn median(&self, label: &str) -> Option<f64> {
        median_iqr(&self.times(label)).map(|(m, _, _)| m)
    }

    /// The scenario's length table (Tables 6-10) and its `R_length`, `R_time` rows.
    fn lengths(&self, out: &mut String, proposed: &[&PlannerSpec], references: &[&PlannerSpec]) {
        let (map, problem) = (self.map, self.problem);
        let _ = writeln!(
            out,
            "### {} problem {}: {} -> {}\n",
            md_cell(&map.name),
            problem.index,
            problem.start,
            problem.goal
        );
        out.push_str("| Planner | Algorithm | Status | Path length | Time ms median (IQR) |\n|---|---|---|---:|---:|\n");
        for planner in &self.experiment.planners {
            let all = self.runs(&planner.label);
            let status = if self.stochastic(&planner.label) {
                let n_found = all.iter().filter(|r| r.status == RunStatus::Found).count();
                format!("found {n_found}/{}", all.len())
            } else {
                all.iter()
                    .find(|r| r.repeat == 0)
                    .map_or("-".into(), |r| r.status.as_str().to_string())
            };
            let _ = writeln!(
                out,
                "| {} | {} | {} | {} | {} |",
                md_cell(&planner.label),
                planner.name,
                status,
                self.length(&planner.label)
                    .map_or("-".into(), |l| format!("{l:.2}")),
                time_cell(&self.times(&planner.label)),
            );
        }
        out.push('\n');
        if !references.is_empty() {
            out.push_str("| PA-star | Reference | R_length | R_time |\n|---|---|---:|---:|\n");
            for pa in proposed {
                for reference in references {
                    let r_length = ratio(self.length(&pa.label), self.length(&reference.label));
                    let r_time = ratio(self.median(&pa.label), self.median(&reference.label));
                    let _ = writeln!(
                        out,
                        "| {} | {} | {} | {} |",
                        md_cell(&pa.label),
                        md_cell(&reference.label),
                        percent(r_length),
                        percent(r_time)
                    );
                }
            }
            out.push('\n');
        }
    }

    /// The scenario's Kruskal-Wallis row (Table 11) and its timing table (Tables 12-14).
    fn timing_tests(&self, kw_rows: &mut String, timing: &mut String, base: &PlannerSpec) {
        let samples: Vec<Vec<f64>> = self
            .experiment
            .planners
            .iter()
            .map(|p| self.times(&p.label))
            .collect();
        let groups: Vec<&[f64]> = samples.iter().map(Vec::as_slice).collect();
        let scenario = format!("{} #{}", md_cell(&self.map.name), self.problem.index);
        match kruskal_wallis(&groups) {
            Ok(kw) => {
                let _ = writeln!(
                    kw_rows,
                    "| {scenario} | {:.2} | {} | {:.3e} |",
                    kw.h, kw.df, kw.p
                );
            }
            Err(e) => {
                let _ = writeln!(kw_rows, "| {scenario} | - | - | {e} |");
            }
        }
        timing.push_str(&timing_table(
            self.experiment,
            &scenario,
            &samples,
            &groups,
            base,
        ));
    }
}

/// The CAPSO section (module docs), or nothing without a label running `capso_name`.
fn render_capso(experiment: &Experiment, index: &ResultsIndex<'_>, capso_name: &str) -> String {
    let labels: Vec<&PlannerSpec> = experiment
        .planners
        .iter()
        .filter(|p| p.name == capso_name)
        .collect();
    if labels.is_empty() {
        return String::new();
    }
    let mut out = String::from("## CAPSO: lengths and convergence (seed 002 section 4.2.2, Fig. 11)\n\nLengths over the repeats that found a path; the curve is the mean over all repeats of the best fitness (length + penalty x collision) after each iteration.\n\n");
    for map in &experiment.maps {
        for problem in map.problems.iter().filter(|p| p.invalid.is_none()) {
            let _ = writeln!(
                out,
                "### {} problem {}: {} -> {}\n\n| Planner | Control points | Found | Mean length | Min | Max |\n|---|---:|---:|---:|---:|---:|",
                md_cell(&map.name), problem.index, problem.start, problem.goal
            );
            let mut curves: Vec<Vec<(f64, f64)>> = Vec::new();
            for planner in &labels {
                let all = index.runs(&map.name, problem.index, &planner.label);
                let lengths: Vec<f64> = all.iter().filter_map(|r| r.length).collect();
                let stat = |f: fn(&[f64]) -> f64| {
                    if lengths.is_empty() {
                        "-".to_string()
                    } else {
                        format!("{:.2}", f(&lengths))
                    }
                };
                let control_points = planner
                    .params
                    .get("control_points")
                    .map_or("6 (default)".into(), |v| v.to_string());
                let _ = writeln!(
                    out,
                    "| {} | {control_points} | {}/{} | {} | {} | {} |",
                    md_cell(&planner.label),
                    lengths.len(),
                    all.len(),
                    stat(|v| v.iter().sum::<f64>() / v.len() as f64),
                    stat(|v| v.iter().copied().fold(f64::INFINITY, f64::min)),
                    stat(|v| v.iter().copied().fold(f64::NEG_INFINITY, f64::max)),
                );
                curves.push(mean_curve(&all));
            }
            out.push_str("\n| Iteration |");
            for planner in &labels {
                let _ = write!(out, " {} |", md_cell(&planner.label));
            }
            out.push_str("\n|---:|");
            out.push_str(&"---:|".repeat(labels.len()));
            out.push('\n');
            let last = curves
                .iter()
                .filter_map(|c| c.last().map(|p| p.0))
                .fold(0.0, f64::max);
            let mut iteration = 0.0;
            while iteration <= last {
                let _ = write!(out, "| {iteration} |");
                for curve in &curves {
                    match curve.iter().find(|p| p.0 == iteration) {
                        Some(p) => {
                            let _ = write!(out, " {:.2} |", p.1);
                        }
                        None => out.push_str(" - |"),
                    }
                }
                out.push('\n');
                iteration += 10.0;
            }
            out.push('\n');
        }
    }
    out
}

/// The mean over `runs` of their `best_fitness` series, point by point (x taken from the
/// first run; only as many points as the shortest series has).
fn mean_curve(runs: &[&RunRecord]) -> Vec<(f64, f64)> {
    let series: Vec<&planner_api::Series> = runs
        .iter()
        .filter_map(|r| r.series.iter().find(|s| s.name == "best_fitness"))
        .collect();
    let Some(shortest) = series.iter().map(|s| s.points.len()).min() else {
        return Vec::new();
    };
    (0..shortest)
        .map(|i| {
            let sum: f64 = series.iter().map(|s| s.points[i][1]).sum();
            (series[0].points[i][0], sum / series.len() as f64)
        })
        .collect()
}

fn timing_table(
    experiment: &Experiment,
    scenario: &str,
    samples: &[Vec<f64>],
    groups: &[&[f64]],
    base: &PlannerSpec,
) -> String {
    let k = experiment.planners.len();
    let pairs = k * (k - 1) / 2;
    let base_index = experiment
        .planners
        .iter()
        .position(|p| p.label == base.label)
        .unwrap_or(0);
    let mut out = format!(
        "### {scenario}: times and Dunn's test against {} (Tables 12-14)\n\n| Planner | Time ms median (IQR) | Shapiro-Wilk W | Shapiro-Wilk p | Z | p (Bonferroni, {pairs} pairs) |\n|---|---:|---:|---:|---:|---:|\n",
        md_cell(&base.label)
    );
    for (i, planner) in experiment.planners.iter().enumerate() {
        let (w, p_w) = match shapiro_wilk(&samples[i]) {
            Ok(sw) => (format!("{:.4}", sw.w), format!("{:.3e}", sw.p)),
            Err(e) => ("-".into(), e.to_string()),
        };
        let (z, p) = if i == base_index {
            ("-".into(), "-".into())
        } else {
            match dunn(groups, base_index, i) {
                Ok(d) => (
                    format!("{:.2}", d.z),
                    format!("{:.3e}", bonferroni(d.p, pairs)),
                ),
                Err(e) => ("-".into(), e.to_string()),
            }
        };
        let _ = writeln!(
            out,
            "| {} | {} | {w} | {p_w} | {z} | {p} |",
            md_cell(&planner.label),
            time_cell(&samples[i])
        );
    }
    out.push('\n');
    out
}

fn time_cell(times: &[f64]) -> String {
    median_iqr(times).map_or("-".into(), |(m, q1, q3)| {
        format!("{m:.4} ({q1:.4}~{q3:.4})")
    })
}

/// Equations 10-11: `(proposed - reference) / proposed`.
fn ratio(proposed: Option<f64>, reference: Option<f64>) -> Option<f64> {
    match (proposed, reference) {
        (Some(p), Some(r)) if p != 0.0 => Some((p - r) / p),
        _ => None,
    }
}

fn percent(value: Option<f64>) -> String {
    value.map_or("-".into(), |v| format!("{:.2} %", 100.0 * v))
}

#[cfg(test)]
mod tests {
    use super::*;
    use planner_api::{Cell, Counters};

    fn record(planner: &str, algorithm: &str, repeat: u32, length: f64, time_ms: f64) -> RunRecord {
        RunRecord {
            cost: None,
            map: "open-140x120.map".into(),
            problem: 1,
            start: Cell::new(20, 10),
            goal: Cell::new(70, 110),
            planner: planner.into(),
            algorithm: algorithm.into(),
            repeat,
            seed: None,
            status: RunStatus::Found,
            error: None,
            steps: Some(1),
            turns: Some(0),
            score: Some(1),
            length: Some(length),
            optimal_length: None,
            bucket: None,
            valid: Some(true),
            admissible: None,
            counters: Counters::new(),
            time_ms,
            setup_ms: 0.0,
            peak_heap_bytes: 0,
            path: None,
            returns: None,
            marks: Vec::new(),
            series: Vec::new(),
        }
    }

    fn experiment(repeats: u32) -> Experiment {
        let map = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("../../maps/pastar/open-140x120.map");
        let text = format!(
            "name = \"t\"\nrepeats = {repeats}\n[[maps]]\nfiles = [{:?}]\npairs = [{{ start = [20, 10], goal = [70, 110] }}]\n[planners.PA]\nplanner = \"pastar\"\n[planners.TA]\nplanner = \"astar\"\nmoves = 8\n",
            map.display().to_string()
        );
        planner_runner::config::parse(std::path::Path::new("t.toml"), &text).unwrap()
    }

    #[test]
    fn r_length_and_r_time_follow_equations_10_11() {
        let experiment = experiment(1);
        let records = [
            record("PA", "pastar", 0, 100.0, 2.0),
            record("TA", "astar", 0, 125.0, 1.0),
        ];
        let text = render(&experiment, &ResultsIndex::new(&records), "pastar");
        // (100 - 125) / 100 = -25 %; (2 - 1) / 2 = +50 %.
        assert!(text.contains("| PA | TA | -25.00 % | 50.00 % |"), "{text}");
        assert!(text.contains("| TA | astar | found | 125.00 | 1.0000 (1.0000~1.0000) |"));
        assert!(!text.contains("Kruskal"), "one repeat: no timing tests");
        // Without PA-star, nothing.
        let mut plain = experiment.clone();
        plain.planners.retain(|p| p.name != "pastar");
        assert_eq!(render(&plain, &ResultsIndex::new(&records), "pastar"), "");
    }

    #[test]
    fn timing_tests_with_repeats() {
        let experiment = experiment(4);
        // PA always faster: ranks 1-4 vs 5-8. Mean ranks 2.5 and 6.5, N = 8, no ties:
        // SE = sqrt(8 * 9 / 12 * (1/4 + 1/4)) = sqrt 3, z = 4 / sqrt 3 = 2.31;
        // H = 12 / 72 * (10^2 / 4 + 26^2 / 4) - 27 = 5.33 on 1 df.
        let mut records = Vec::new();
        for r in 0..4 {
            records.push(record("PA", "pastar", r, 100.0, 1.0 + f64::from(r)));
            records.push(record("TA", "astar", r, 125.0, 10.0 + f64::from(r * r)));
        }
        let text = render(&experiment, &ResultsIndex::new(&records), "pastar");
        assert!(
            text.contains("| open-140x120.map #1 | 5.33 | 1 | 2.092e-2 |"),
            "{text}"
        );
        assert!(text.contains("| 2.31 | 2.092e-2 |"), "{text}");
        // Shapiro-Wilk of 1, 2, 3, 4: W = 0.9929 (SciPy: 0.9929, p = 0.9719).
        assert!(
            text.contains("| PA | 2.5000 (1.7500~3.2500) | 0.9929 | 9.719e-1 | - | - |"),
            "{text}"
        );
    }

    #[test]
    fn seeded_planners_report_the_mean_length_and_capso_its_curve() {
        let map = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("../../maps/pastar/open-140x120.map");
        let text = format!(
            "name = \"t\"\nrepeats = 3\n[[maps]]\nfiles = [{:?}]\npairs = [{{ start = [20, 10], goal = [70, 110] }}]\n[planners.PA]\nplanner = \"pastar\"\n[planners.C4]\nplanner = \"capso\"\ncontrol_points = 4\n",
            map.display().to_string()
        );
        let experiment =
            planner_runner::config::parse(std::path::Path::new("t.toml"), &text).unwrap();
        let mut records = Vec::new();
        for r in 0..3 {
            records.push(record("PA", "pastar", r, 100.0, 1.0));
            let mut capso = record("C4", "capso", r, 95.0 + 10.0 * f64::from(r), 50.0);
            capso.seed = Some(u64::from(r));
            let mut curve = planner_api::Series::new("best_fitness", "iteration");
            for k in 0..=10 {
                curve
                    .points
                    .push([f64::from(k), 200.0 - f64::from(k) + f64::from(r)]);
            }
            capso.series.push(curve);
            records.push(capso);
        }
        // Repeat 2 found nothing: the mean is over 95 and 105.
        records[5].status = RunStatus::NoPath;
        records[5].length = None;
        let index = ResultsIndex::new(&records);
        let text = render(&experiment, &index, "pastar");
        assert!(
            text.contains("| C4 | capso | found 2/3 | 100.00 |"),
            "{text}"
        );
        assert!(text.contains("| PA | C4 | 0.00 % | -4900.00 % |"), "{text}");
        let text = render_capso(&experiment, &index, "capso");
        assert!(
            text.contains("| C4 | 4 | 2/3 | 100.00 | 95.00 | 105.00 |"),
            "{text}"
        );
        // Mean of 200 + r over r = 0, 1, 2 at iteration 0, and of 190 + r at 10.
        assert!(text.contains("| 0 | 201.00 |\n| 10 | 191.00 |"), "{text}");
        assert_eq!(render_capso(&experiment, &index, "rrt"), "");
    }
}
