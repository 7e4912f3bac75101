//! The charts section of summary.md: links to the SVG charts of [`crate::charts`].

use std::fmt::Write as _;

use crate::charts::Chart;
use crate::md_cell;
use crate::{Context, Reproduction, Section};
use planner_runner::config::Experiment;
use planner_runner::passes::RecordPasses;
use planner_runner::RunnerError;

/// The charts (section name `charts`).
pub struct Charts;

impl Section for Charts {
    fn name(&self) -> &'static str {
        "charts"
    }

    /// For every sweep (without a valid run the section is empty).
    fn applies(&self, _context: &Context<'_>) -> bool {
        true
    }

    /// From passes over the records ([`crate::charts::charts`]).
    fn table(&self) -> Option<crate::PassesTable> {
        Some(computed_links)
    }

    /// The links of [`Context::charts`] when the charts were computed already, else
    /// [`Section::table`]'s.
    fn render_passes(
        &self,
        context: &Context<'_>,
        out: &mut String,
        _reproduction: &mut Reproduction,
    ) -> Result<(), RunnerError> {
        match context.charts {
            Some(charts) => out.push_str(&links(charts)),
            None => out.push_str(&computed_links(context.experiment, context.passes)?),
        }
        Ok(())
    }
}

/// The section's markdown from charts computed from `passes`.
fn computed_links(
    experiment: &Experiment,
    passes: &dyn RecordPasses,
) -> Result<String, RunnerError> {
    Ok(links(&crate::charts::charts(experiment, passes)?))
}

/// The section's markdown: a heading and a link to every chart (nothing without one).
fn links(charts: &[Chart]) -> String {
    let mut out = String::new();
    if charts.is_empty() {
        return out;
    }
    out.push_str("## Charts\n\n");
    for chart in charts {
        // The title is config text: one line, and no `]` to end the image's text.
        let title = md_cell(&chart.title)
            .replace('[', "\\[")
            .replace(']', "\\]");
        let _ = writeln!(out, "![{title}](charts/{})\n", chart.file);
    }
    out
}
