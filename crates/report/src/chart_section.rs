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
        // The title is config text: md_cell makes it one line and escapes what could end
        // the image's text or open a link (`[`, `]`, `\\`, a `(` after `]`). Escaped once:
        // escaping its output again turned `\[` into `\\\[`, a backslash and a bare `[`.
        let title = md_cell(&chart.title);
        let _ = writeln!(out, "![{title}](charts/{})\n", chart.file);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use pulldown_cmark::{Event, Options, Parser, Tag, TagEnd};

    /// Every image of `markdown` as (alt text, destination), read by report.html's parser.
    fn images(markdown: &str) -> Vec<(String, String)> {
        let mut out = Vec::new();
        let mut open: Option<(String, String)> = None;
        for event in Parser::new_ext(markdown, Options::ENABLE_TABLES) {
            match event {
                Event::Start(Tag::Image { dest_url, .. }) => {
                    open = Some((String::new(), dest_url.to_string()))
                }
                Event::End(TagEnd::Image) => out.extend(open.take()),
                Event::Text(t) | Event::Code(t) => {
                    if let Some((alt, _)) = open.as_mut() {
                        alt.push_str(&t);
                    }
                }
                _ => {}
            }
        }
        out
    }

    /// Titles (and paired charts' titles holding a baseline label) with unbalanced brackets,
    /// backslashes, parentheses and markup: each chart is one image whose alt text is the
    /// title as written, and report.html inlines its SVG.
    #[test]
    fn chart_titles_are_the_images_alt_text_exactly() {
        let titles = [
            "Length for weight in [1, 3)",
            "Length for weight in (1, 3]",
            "a ] b",
            "[[x",
            "x]](y)",
            "back\\slash \\[ \\]",
            "A<b>&amp;\"q\" ]]> <!--",
            "Length against A<b>&amp;\"q\" ]]> <!-- per problem",
            "(p) [q](r) ![s](t)",
            "*e* _f_ `c` | ~ $ ^ #",
        ];
        let charts: Vec<Chart> = titles
            .iter()
            .enumerate()
            .map(|(i, t)| Chart {
                file: format!("c{i}.svg"),
                title: (*t).to_string(),
                svg: format!("<svg id=\"c{i}\"></svg>"),
            })
            .collect();
        let markdown = links(&charts);
        let expected: Vec<(String, String)> = titles
            .iter()
            .enumerate()
            .map(|(i, t)| ((*t).to_string(), format!("charts/c{i}.svg")))
            .collect();
        assert_eq!(images(&markdown), expected, "{markdown}");
        let files = crate::charts::files(charts);
        let page = crate::html::report_html("t", &markdown, &files);
        for i in 0..expected.len() {
            assert!(
                page.contains(&format!("<figure><svg id=\"c{i}\"></svg></figure>")),
                "{page}"
            );
        }
        assert!(!page.contains("(missing"), "{page}");
    }
}
