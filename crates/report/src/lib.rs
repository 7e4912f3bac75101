//! `summary.md`: the sweep laid out like the seeds' tables, as a list of [`Section`]s.
//!
//! Each section is one kind of table: seed 000's Tables 3-8 ([`seed000`]), seed 003's
//! Tables I-II ([`seed003`]), the scenario optima ([`optimum`]), repeated runs
//! ([`repeats`]), seed 004's coverage table ([`coverage`]), seed 002's PA-star tables
//! ([`seed002`], registered by the registry with the planner it compares), the aggregates
//! of any sweep ([`aggregate`]) and its charts ([`charts`]). A config names
//! the sections it wants with `sections = [...]`; without the key every section decides
//! from the experiment and its records whether it applies. Deterministic values come from
//! repeat 0; times are medians over repeats.

pub mod aggregate;
pub mod charts;
pub mod coverage;
pub mod optimum;
pub mod repeats;
pub mod seed000;
pub mod seed002;
pub mod seed003;

use std::fmt::Write as _;

use crate::config::Experiment;
use crate::index::ResultsIndex;
use crate::provenance::Provenance;
use crate::record::RunRecord;

/// Largest number of map columns in one seed-000 style table, and of problems per map in
/// the per-problem tables.
pub const MAX_COLUMNS: usize = 12;

/// Counts of compared published numbers.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Reproduction {
    /// Numbers compared.
    pub compared: usize,
    /// Numbers equal to the published value.
    pub matched: usize,
}

/// What a section reads.
pub struct Context<'a> {
    /// The experiment.
    pub experiment: &'a Experiment,
    /// Its records, in the run list's order.
    pub records: &'a [RunRecord],
    /// Lookups into the records.
    pub index: &'a ResultsIndex<'a>,
}

/// One part of summary.md.
pub trait Section: Send + Sync {
    /// The name configs use in `sections = [...]`.
    fn name(&self) -> &'static str;

    /// Whether the section has anything to say about this experiment (used when the
    /// config names no sections).
    fn applies(&self, context: &Context<'_>) -> bool;

    /// Appends the section's markdown to `out` and counts compared published numbers.
    fn render(&self, context: &Context<'_>, out: &mut String, reproduction: &mut Reproduction);
}

/// Every section in the order summary.md places them: the generic ones and the
/// registry's planner-specific ones.
pub fn sections() -> Vec<Box<dyn Section>> {
    let mut all: Vec<Box<dyn Section>> = vec![
        Box::new(coverage::Coverage),
        Box::new(seed000::Seed000),
        Box::new(optimum::Optimum),
        Box::new(seed003::Seed003),
        Box::new(repeats::Repeats),
    ];
    all.extend(crate::registry::planner_sections());
    all.push(Box::new(aggregate::Aggregate));
    all.push(Box::new(charts::Charts));
    all
}

/// The names of every section, for config errors.
pub fn section_names() -> Vec<&'static str> {
    sections().iter().map(|s| s.name()).collect()
}

/// Renders summary.md and returns it with the reproduction counts.
pub fn render(experiment: &Experiment, records: &[RunRecord]) -> (String, Reproduction) {
    render_with(experiment, records, None)
}

/// Renders summary.md with the sweep's provenance at the top, if given.
pub fn render_with(
    experiment: &Experiment,
    records: &[RunRecord],
    provenance: Option<&Provenance>,
) -> (String, Reproduction) {
    let index = ResultsIndex::new(records);
    let context = Context {
        experiment,
        records,
        index: &index,
    };
    let mut out = String::new();
    let mut reproduction = Reproduction::default();
    header(&context, &mut out);
    if let Some(provenance) = provenance {
        out.push_str(&provenance.markdown());
    }
    for section in sections() {
        let wanted = match &experiment.sections {
            Some(names) => names.iter().any(|n| n == section.name()),
            None => section.applies(&context),
        };
        if wanted {
            section.render(&context, &mut out, &mut reproduction);
        }
    }
    (out, reproduction)
}

fn header(context: &Context<'_>, out: &mut String) {
    let experiment = context.experiment;
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
        context.records.len()
    );
    let inadmissible: Vec<String> = experiment
        .planners
        .iter()
        .filter(|p| p.factory.specs().admissible == Some(false))
        .map(|p| format!("`{}`", p.label))
        .collect();
    if !inadmissible.is_empty() {
        let _ = writeln!(
            out,
            "Not optimal by design: {} use a heuristic that can overestimate under their moves (or a weight above 1); their runs are recorded `admissible = false`.\n",
            inadmissible.join(", ")
        );
    }
    let invalid: Vec<&RunRecord> = context
        .records
        .iter()
        .filter(|r| r.is_invalid() && r.planner == experiment.planners[0].label)
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

/// A map's file name without its extension.
pub fn map_stem(name: &str) -> &str {
    name.rsplit_once('.').map_or(name, |(stem, _)| stem)
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
