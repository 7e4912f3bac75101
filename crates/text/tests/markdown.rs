//! `md_cell`'s output parsed back with a CommonMark parser (pulldown-cmark, what report.html
//! renders with, GitHub's extensions on): in a table cell, a heading, a list item and a
//! paragraph, every label shows as its own text and as nothing else.

use planner_text::md_cell;
use pulldown_cmark::{Event, Options, Parser, Tag, TagEnd};

/// Where summary.md and the replanning reports put an `md_cell`: the markdown around it
/// and the text that markdown adds to the label's.
const CONTEXTS: [(&str, &str, &str); 5] = [
    ("| h |\n|---|\n| ", " |\n", "h"),
    ("# ", "\n", ""),
    ("- ", " problem 1\n", ""),
    ("", ": more\n", ""),
    ("Figures of ", ": more\n", "Figures of "),
];

/// The extensions a markdown viewer may have on: GitHub's (tables, strikethrough, task
/// lists, footnotes, math) and pulldown-cmark's others that read inline punctuation.
fn extensions() -> Options {
    Options::ENABLE_TABLES
        | Options::ENABLE_FOOTNOTES
        | Options::ENABLE_STRIKETHROUGH
        | Options::ENABLE_TASKLISTS
        | Options::ENABLE_MATH
        | Options::ENABLE_GFM
        | Options::ENABLE_SUPERSCRIPT
        | Options::ENABLE_SUBSCRIPT
        | Options::ENABLE_WIKILINKS
}

/// The text `markdown` shows, or what else it holds: every event must be text or the
/// context's own block (one table of one column, one heading, one list item, one
/// paragraph).
fn shown(markdown: &str, options: Options) -> Result<String, String> {
    let mut text = String::new();
    let mut blocks = 0;
    for event in Parser::new_ext(markdown, options) {
        match event {
            Event::Text(t) => text.push_str(&t),
            Event::Start(Tag::Table(_)) | Event::Start(Tag::Heading { .. }) => blocks += 1,
            Event::Start(Tag::List(None)) => blocks += 1,
            Event::Start(Tag::Paragraph) => blocks += 1,
            Event::Start(Tag::TableHead | Tag::TableRow | Tag::TableCell | Tag::Item) => {}
            Event::End(
                TagEnd::Table
                | TagEnd::TableHead
                | TagEnd::TableRow
                | TagEnd::TableCell
                | TagEnd::Heading(_)
                | TagEnd::List(false)
                | TagEnd::Item
                | TagEnd::Paragraph,
            ) => {}
            other => return Err(format!("{other:?}")),
        }
    }
    match blocks {
        1 => Ok(text),
        n => Err(format!("{n} blocks")),
    }
}

/// `label` (not blank) through `md_cell` in every context shows as the label, trimmed.
fn check(label: &str) {
    let cell = md_cell(label);
    for (before, after, prefix) in CONTEXTS {
        let markdown = format!("{before}{cell}{after}");
        let expect = format!(
            "{prefix}{}{}",
            label.trim(),
            after.trim_end_matches('\n').trim_end_matches(" |")
        );
        for options in [extensions(), Options::empty()] {
            if before.starts_with('|') && options.is_empty() {
                continue;
            }
            assert_eq!(
                shown(&markdown, options).as_deref(),
                Ok(expect.as_str()),
                "label {label:?} written {cell:?} in {markdown:?}"
            );
        }
    }
}

#[test]
fn every_ascii_punctuation_label_shows_as_itself() {
    let punctuation: Vec<char> = (b'!'..=b'~')
        .map(char::from)
        .filter(char::is_ascii_punctuation)
        .collect();
    assert_eq!(punctuation.len(), 32);
    for &c in &punctuation {
        for label in [
            format!("{c}"),
            format!("{c}{c}"),
            format!("{c}{c}{c}"),
            format!("{c}{c}{c}{c}{c}{c}{c}"),
            format!("a{c}b"),
            format!("{c}a"),
            format!("a{c}"),
            format!("{c}a{c}"),
            format!("{c}{c}a{c}{c}"),
            format!("a {c}b{c} c"),
            format!("x {c}"),
            format!("{c} x"),
            format!("x {c}{c} {c}"),
            format!("1{c} x"),
            format!("12{c}"),
        ] {
            check(&label);
        }
        for &d in &punctuation {
            check(&format!("{c}{d}"));
            check(&format!("{c}x{d}"));
            check(&format!("x{c}{d}y"));
            check(&format!("{c} {d}x{d} {c}"));
        }
    }
}

#[test]
fn random_printable_labels_show_as_themselves() {
    // xorshift64: a fixed sequence of labels from printable ASCII and a few others.
    let mut state = 0x9e37_79b9_7f4a_7c15_u64;
    let mut next = move || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        state
    };
    let alphabet: Vec<char> = (b' '..=b'~')
        .map(char::from)
        .chain("ééß日_*`".chars())
        .collect();
    let mut checked = 0;
    while checked < 20_000 {
        let len = 1 + (next() % 12) as usize;
        let label: String = (0..len)
            .map(|_| alphabet[(next() % alphabet.len() as u64) as usize])
            .collect();
        if label.trim().is_empty() {
            continue;
        }
        check(&label);
        checked += 1;
    }
}

#[test]
fn ordinary_labels_are_written_as_they_are() {
    // The labels and map names of configs/ and the kinds a user writes.
    for label in [
        "astar",
        "astar_octile",
        "astar_high_g",
        "octile_high_g",
        "bfs_ignoring_costs",
        "dstar_lite_4",
        "rrt_star_eight4",
        "PA-star-size",
        "Lazy-Theta-star",
        "CAPSO-3",
        "RA-star1",
        "random512-10-0.map",
        "16room_000.map",
        "Berlin_0_256.map",
        "den520d",
        "C#",
        "seed #1",
        "PA-star 2",
        "moves = 8, heuristic = \"octile\"",
        "{\"max_expansions\":1000}",
        "x/y.map",
        "a.b(c)",
        "f(x) = 2",
        "50% of it!",
        "é_é",
        "日本_語",
    ] {
        assert_eq!(md_cell(label), label);
        check(label);
    }
}

#[test]
fn the_reported_label_shows_as_itself() {
    // A probe's label: emphasis and a javascript: link in report.html.
    let label = "x*y*z [l](javascript:alert(5)) `code`";
    assert_eq!(
        md_cell(label),
        "x\\*y\\*z \\[l\\]\\(javascript:alert(5)) \\`code\\`"
    );
    check(label);
}

#[test]
fn blank_and_control_characters() {
    assert_eq!(md_cell(""), "");
    assert_eq!(md_cell(" \t\n "), "");
    assert_eq!(md_cell("  a\r\nb\u{2028}c  "), "a  b c");
    // Control characters become spaces, which show as spaces.
    let cell = md_cell("a\tb\u{7}c");
    assert_eq!(
        shown(&format!("# {cell}\n"), extensions()).as_deref(),
        Ok("a b c")
    );
}
