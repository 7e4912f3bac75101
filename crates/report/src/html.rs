//! `report.html`: one self-contained page (no network, no scripts) with summary.md's
//! provenance and tables rendered to HTML (pulldown-cmark), the charts and the figures
//! inline as SVG, and a table of contents linking every section.
//!
//! Config text (the description, labels, map names) reaches the page through the markdown
//! and is data, never markup: raw HTML in the markdown (block or inline) is rendered as
//! text, links keep only the safe schemes of [`safe_link`] (`http`, `https`, `mailto`, or
//! none: a relative link or `#fragment`) and any other link becomes its plain text, and
//! every string the page adds itself goes through [`escape`]. The inlined SVG files are
//! gridplan's own, whose text the figure and chart writers escape.

use std::fmt::Write as _;

use pulldown_cmark::{html, Event, HeadingLevel, Options, Parser, Tag, TagEnd};

use planner_runner::output::OutputFile;

/// The page: `summary` (markdown) with every `![title](charts/x.svg)` image replaced by
/// that file's SVG from `files`, then a Figures section with every `figures/*.svg`.
pub fn report_html(title: &str, summary: &str, files: &[OutputFile]) -> String {
    let svg_of = |path: &str| {
        files
            .iter()
            .find(|f| f.path.to_string_lossy() == path)
            .map(|f| strip_prolog(&String::from_utf8_lossy(&f.contents)))
    };
    let mut headings: Vec<(String, String)> = Vec::new();
    let mut in_heading = false;
    let mut heading_text = String::new();
    let mut skip_image = false;
    // For each open link: whether it was kept (a safe scheme).
    let mut links: Vec<bool> = Vec::new();
    // Each parsed event becomes at most one written event, streamed to the writer: a list
    // of every event first took 40 bytes an event, 80 MiB for a summary of 1.6 MB.
    let events = Parser::new_ext(summary, Options::ENABLE_TABLES).filter_map(|event| {
        // Raw HTML is shown as the text it is.
        let event = match event {
            Event::Html(text) | Event::InlineHtml(text) => Event::Text(text),
            other => other,
        };
        match event {
            Event::Start(Tag::Heading {
                level: HeadingLevel::H2,
                ..
            }) => {
                in_heading = true;
                heading_text.clear();
                None
            }
            Event::End(TagEnd::Heading(HeadingLevel::H2)) if in_heading => {
                in_heading = false;
                let id = format!("s{}", headings.len() + 1);
                let html = format!("<h2 id=\"{id}\">{}</h2>\n", escape(&heading_text));
                headings.push((id, heading_text.clone()));
                Some(Event::Html(html.into()))
            }
            Event::Text(text) if in_heading => {
                heading_text.push_str(&text);
                None
            }
            Event::Code(code) if in_heading => {
                heading_text.push_str(&code);
                None
            }
            _ if in_heading => None,
            Event::Start(Tag::Image { dest_url, .. }) => match svg_of(&dest_url) {
                Some(svg) => {
                    skip_image = true;
                    Some(Event::Html(format!("<figure>{svg}</figure>").into()))
                }
                None => Some(Event::Text(format!("(missing {dest_url})").into())),
            },
            Event::End(TagEnd::Image) => {
                skip_image = false;
                None
            }
            _ if skip_image => None,
            Event::Start(Tag::Link { ref dest_url, .. }) => {
                let keep = safe_link(dest_url);
                links.push(keep);
                keep.then_some(event)
            }
            Event::End(TagEnd::Link) => links.pop().unwrap_or(true).then_some(event),
            other => Some(other),
        }
    });
    let mut body = String::new();
    html::push_html(&mut body, events);
    let figures: Vec<&OutputFile> = files
        .iter()
        .filter(|f| {
            let p = f.path.to_string_lossy();
            p.starts_with("figures/") && p.ends_with(".svg")
        })
        .collect();
    if !figures.is_empty() {
        let id = format!("s{}", headings.len() + 1);
        let _ = writeln!(body, "<h2 id=\"{id}\">Figures</h2>");
        headings.push((id, "Figures".into()));
        for f in figures {
            let _ = writeln!(
                body,
                "<figure>{}<figcaption>{}</figcaption></figure>",
                strip_prolog(&String::from_utf8_lossy(&f.contents)),
                escape(&f.path.to_string_lossy())
            );
        }
    }
    let mut nav = String::from("<nav><strong>Sections</strong><ul>");
    for (id, text) in &headings {
        let _ = write!(nav, "<li><a href=\"#{id}\">{}</a></li>", escape(text));
    }
    nav.push_str("</ul></nav>");
    format!(
        "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n<title>{}</title>\n<style>{STYLE}</style>\n</head>\n<body>\n{nav}\n<main>\n{body}</main>\n</body>\n</html>\n",
        escape(title)
    )
}

const STYLE: &str = "body{font-family:sans-serif;margin:0;display:flex}nav{position:sticky;top:0;height:100vh;overflow:auto;width:14em;padding:1em;background:#f3f3f3;flex:none}main{padding:1em 2em;overflow-x:auto;min-width:0}table{border-collapse:collapse;margin:1em 0;font-size:0.85em}th,td{border:1px solid #bbb;padding:2px 6px}th{background:#eee}figure{margin:1em 0}figure svg{max-width:100%;height:auto}";

/// An SVG file's `<svg ...>` element without its XML declaration or doctype.
fn strip_prolog(svg: &str) -> String {
    svg.find("<svg")
        .map_or_else(|| svg.to_string(), |i| svg[i..].to_string())
}

/// `text` escaped for HTML text and double-quoted attribute values (planner-text's).
pub use planner_text::xml_escape as escape;

/// Whether a link may stay a link (planner-text's rule, which summary.md's prose follows too).
pub use planner_text::safe_link;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tables_charts_and_sections_are_inlined() {
        let files = vec![OutputFile {
            path: "charts/a.svg".into(),
            contents: b"<?xml version=\"1.0\"?>\n<svg width=\"1\"></svg>".to_vec(),
        }];
        let page = report_html(
            "t",
            "# T\n\n## One `x`\n\n| a | b |\n|---|---|\n| 1 | 2 |\n\n![c](charts/a.svg)\n",
            &files,
        );
        assert!(page.contains("<h2 id=\"s1\">One x</h2>"), "{page}");
        assert!(page.contains("<a href=\"#s1\">One x</a>"));
        assert!(page.contains("<td>1</td>"));
        assert!(page.contains("<figure><svg width=\"1\"></svg></figure>"));
        assert!(!page.contains("<img") && !page.contains("<?xml") && !page.contains("<script"));
    }

    #[test]
    fn raw_html_is_text_and_unsafe_links_are_plain_text() {
        let page = report_html(
            "t",
            "<script>alert(1)</script>\n\nA <b onclick=\"x()\">b</b> [c](javascript:alert(2)) \
             [d](https://example.org) <javascript:alert(3)>\n",
            &[],
        );
        assert!(!page.contains("<script") && !page.contains("<b "), "{page}");
        assert!(
            page.contains("&lt;script&gt;alert(1)&lt;/script&gt;"),
            "{page}"
        );
        assert!(
            !page.to_ascii_lowercase().contains("href=\"javascript"),
            "{page}"
        );
        assert!(
            page.contains("<a href=\"https://example.org\">d</a>"),
            "{page}"
        );
        assert!(page.contains(" c "), "{page}");
    }

    /// planner-text's code spans, read back by this page's markdown parser: the one code
    /// span of each, holding the text as written (line breaks as spaces).
    #[test]
    fn code_spans_hold_the_text_as_written() {
        for text in [
            "astar",
            "a`b",
            "``x``",
            "`",
            " lead and trail ",
            "<script>alert(1)</script> &amp; |",
            "a\n# h\n\nb",
            "[x](javascript:y)",
            "*e* _f_",
        ] {
            let markdown = format!("Label {} here.", crate::md_code(text));
            let codes: Vec<String> = Parser::new_ext(&markdown, Options::ENABLE_TABLES)
                .filter_map(|event| match event {
                    Event::Code(code) => Some(code.to_string()),
                    _ => None,
                })
                .collect();
            let expected = text.replace('\n', " ");
            assert_eq!(codes, [expected], "{markdown:?}");
        }
    }
}
