//! The charts section of summary.md: links to the SVG charts of [`crate::charts`].

use std::fmt::Write as _;

use crate::md_cell;
use crate::{Context, Section};
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
        Some(links)
    }
}

/// The section's markdown: a heading and a link to every chart (nothing without one).
fn links(experiment: &Experiment, passes: &dyn RecordPasses) -> Result<String, RunnerError> {
    let charts = crate::charts::charts(experiment, passes)?;
    let mut out = String::new();
    if charts.is_empty() {
        return Ok(out);
    }
    out.push_str("## Charts\n\n");
    for chart in charts {
        // The title is config text: one line, and no `]` to end the image's text.
        let title = md_cell(&chart.title)
            .replace('[', "\\[")
            .replace(']', "\\]");
        let _ = writeln!(out, "![{title}](charts/{})\n", chart.file);
    }
    Ok(out)
}
