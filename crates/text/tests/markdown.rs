//! `md_cell`'s output parsed back with a CommonMark parser (pulldown-cmark, what report.html
//! renders with, GitHub's extensions on): in a table cell, a heading, a list item and a
//! paragraph, every label shows as its own text and as nothing else.

use planner_text::{md_cell, md_prose, safe_link};
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

/// Every link and image destination and every piece of raw HTML `markdown` holds once
/// parsed, with and without the extensions (wiki links aside: report.html and GitHub
/// read none).
fn links_and_html(markdown: &str) -> Vec<(String, String)> {
    let mut found = Vec::new();
    for options in [extensions() - Options::ENABLE_WIKILINKS, Options::empty()] {
        for event in Parser::new_ext(markdown, options) {
            match event {
                Event::Start(Tag::Link { dest_url, .. }) => {
                    found.push(("link".to_string(), dest_url.to_string()))
                }
                Event::Start(Tag::Image { dest_url, .. }) => {
                    found.push(("image".to_string(), dest_url.to_string()))
                }
                Event::Html(html) | Event::InlineHtml(html) => {
                    found.push(("html".to_string(), html.to_string()))
                }
                _ => {}
            }
        }
    }
    found
}

/// `md_prose`'s output holds no raw HTML and no link or image whose destination (as the
/// parser decodes it) is not `safe_link`.
fn check_prose(text: &str) {
    let prose = md_prose(text);
    for (what, dest) in links_and_html(&prose) {
        assert!(
            what != "html" && safe_link(&dest),
            "{text:?} gives {prose:?}, with {what} {dest:?}"
        );
    }
}

/// The probe's three ways to put a `javascript:` link in summary.md (a reference
/// definition, a numeric and a named character reference in the destination), and the
/// other CommonMark forms of a destination: all show as text.
#[test]
fn prose_keeps_no_unsafe_link() {
    let probe = "[e]: javascript:alert(2)\n\nsee [e] and [g](java&#115;cript:alert(1)) and [h](javascript&colon;alert(3))";
    assert_eq!(
        md_prose(probe),
        "[e]\\: javascript:alert(2)\n\nsee [e] and [g]\\(java&#115;cript:alert(1)) and [h]\\(javascript&colon;alert(3))"
    );
    for text in [
        probe,
        "[e]: javascript:alert(2)\n\nsee [e]",
        "[g](java&#115;cript:alert(1))",
        "[h](javascript&colon;alert(3))",
        // Character references, numeric and named, in every part of the scheme.
        "[a](&#106;avascript:x)",
        "[a](&#x6A;avascript:x)",
        "[a](&#X6a;avascript&#x3a;x)",
        "[a](javascript&#58;x)",
        "[a](javascript&#0000058;x)",
        "[a](java&Tab;script:x)",
        "[a](java&NewLine;script:x)",
        "[a](&#32;javascript:x)",
        "[a](&#9;javascript:x)",
        "[a](javascript&colon;x \"title\")",
        "[a](javascript&CounterClockwiseContourIntegral;x)",
        // Backslash escapes, angle brackets, case, space and a line break before it.
        "[a](javascript\\:x)",
        "[a](\\javascript:x)",
        "[a](<javascript:alert(1)>)",
        "[a](<java&#115;cript:x>)",
        "[a](<javascript\\:x> \"t\")",
        "[a](JaVaScRiPt:x)",
        "[a](  javascript:x)",
        "[a](\njavascript:x)",
        "[a](\r\njavascript:x)",
        "> [a](\n> javascript:x)",
        "- [a](\n  javascript:x)",
        "[a](\u{1}javascript:x)",
        // Other schemes, images, nested links.
        "[a](data:text/html,<script>x</script>)",
        "[a](vbscript:x)",
        "[a](file:///etc/passwd)",
        "![i](javascript:x)",
        "[![i](https://o.org/i.png)](javascript:x)",
        "[a](javascript:alert(1)(2))",
        // Autolinks and raw HTML.
        "<javascript:alert(1)>",
        "<JAVASCRIPT:x>",
        "<a href=\"javascript:x\">a</a>",
        // Reference definitions: indented, in containers, with titles, on two lines.
        "[e]:javascript:x\n\n[e]",
        "   [e]: javascript:x\n\n[e]",
        "[e]: <javascript:x>\n\n[e]",
        "[e]: java&#115;cript:x 'title'\n\n[e][] and [x][e]",
        "[e]:\n  javascript:x\n\n[e]",
        "[e]: \n javascript:x\n\n[e]",
        "> [e]: javascript:x\n\n[e]",
        "- [e]: javascript:x\n\n[e]",
        "1. > [e]: javascript:x\n\n[e]",
        "[e\nf]: javascript:x\n\n[e f]",
        "text\n\n[E]: JavaScript:x\n\n[e]",
        "[e]: javascript&colon;x\n\n[e]",
        "[e]: data:text/html,x\n\n[e]",
    ] {
        check_prose(text);
    }
}

/// Safe links stay links, with the destination as written.
#[test]
fn prose_keeps_safe_links() {
    for (text, dest) in [
        ("[ok](https://o.org)", "https://o.org"),
        ("[ok]( https://o.org \"t\")", "https://o.org"),
        ("[m](mailto:a@b.org)", "mailto:a@b.org"),
        ("[r](charts/a.svg)", "charts/a.svg"),
        ("[f](#s1)", "#s1"),
        ("[q](https://o.org/?a=1&amp;b=2)", "https://o.org/?a=1&b=2"),
        ("[q](https://o.org/?a=1&b=2)", "https://o.org/?a=1&b=2"),
        ("[w](https://o.org/A_(b))", "https://o.org/A_(b)"),
        ("[s](HTTPS&#58;//o.org)", "HTTPS://o.org"),
        ("[r]: https://o.org \"t\"\n\nsee [r]", "https://o.org"),
        ("   [r]:https://o.org\n\nsee [r]", "https://o.org"),
        ("[r]: charts/a.svg\n\nsee [r]", "charts/a.svg"),
    ] {
        let prose = md_prose(text);
        assert_eq!(prose, text);
        let links = links_and_html(&prose);
        assert_eq!(
            links.first(),
            Some(&("link".to_string(), dest.to_string())),
            "{text:?}"
        );
    }
}

/// Random prose from the characters link syntax is made of: no unsafe link survives.
#[test]
fn random_prose_keeps_no_unsafe_link() {
    let mut state = 0x2545_f491_4f6c_dd1d_u64;
    let mut next = move || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        state
    };
    let pieces = [
        "[a](",
        "[e]:",
        "[e]: ",
        "[e]",
        "\n\n",
        "](",
        "]",
        "[",
        "(",
        ")",
        "<",
        ">",
        ":",
        " ",
        "\n",
        "> ",
        "- ",
        "\\",
        "&",
        "#",
        ";",
        "&#58;",
        "&#x3a;",
        "&colon;",
        "&#115;",
        "&Tab;",
        "&amp;",
        "javascript",
        "java",
        "script",
        "JaVa",
        "data",
        "x",
        "\"",
        "!",
        "\t",
        "http",
        "/",
    ];
    for _ in 0..50_000 {
        let len = 1 + (next() % 16) as usize;
        let text: String = (0..len)
            .map(|_| pieces[(next() % pieces.len() as u64) as usize])
            .collect();
        check_prose(&text);
    }
}
