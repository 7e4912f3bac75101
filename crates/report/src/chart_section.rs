//! The charts section of summary.md: links to the SVG charts of [`crate::charts`].

use std::fmt::Write as _;

use crate::md_cell;
use crate::{Context, Reproduction, Section};

/// The charts (section name `charts`).
pub struct Charts;

impl Section for Charts {
    fn name(&self) -> &'static str {
        "charts"
    }

    /// For every sweep with a valid run.
    fn applies(&self, context: &Context<'_>) -> bool {
        context.records.iter().any(|r| !r.is_invalid())
    }

    fn render(&self, context: &Context<'_>, out: &mut String, _reproduction: &mut Reproduction) {
        let charts = crate::charts::charts(context.experiment, context.records);
        if charts.is_empty() {
            return;
        }
        out.push_str("## Charts\n\n");
        for chart in charts {
            // The title is config text: one line, and no `]` to end the image's text.
            let title = md_cell(&chart.title)
                .replace('[', "\\[")
                .replace(']', "\\]");
            let _ = writeln!(out, "![{title}](charts/{})\n", chart.file);
        }
    }
}
