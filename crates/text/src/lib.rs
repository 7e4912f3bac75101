//! What users write (planner labels, map names, chart titles, a config's description) made
//! into data in gridplan's outputs, never code: a CSV field that cannot end its record or
//! open as a spreadsheet formula, a
//! markdown table cell (or heading, or list item) that shows as its own text, never as
//! HTML, a link or any other markdown, markdown prose whose raw HTML and unsafe links show
//! as text, a markdown code span that shows its text as written, XML or HTML text that
//! cannot open a tag, and terminal text that cannot send the terminal a control sequence
//! (nor, for a user's path or name, end the message's line).
//!
//! The main design decision is that there is one of each: the runner's tables, the reports,
//! the seeds' layouts, the replanning experiments and the command line's messages all write
//! through these functions. Two copies of the CSV rule had drifted apart (one quoted a bare
//! `\r`, the other did not, so a label holding one split its rows for pandas), and so had
//! two copies of the prose rule (one escaped `javascript:` links, the other did not).
//!
//! ```
//! use planner_text::{csv_field, md_cell, md_code, md_prose, safe_link, terminal, xml_escape};
//! assert_eq!(csv_field("g\rh"), "\"g\rh\"");
//! assert_eq!(md_cell("<b>|[x](y)"), "&lt;b&gt;\\|\\[x\\]\\(y)");
//! assert_eq!(md_prose("[j](javascript:x) a <-> b"), "[j]\\(javascript:x) a <-> b");
//! assert_eq!(md_code("x`<b>\ny"), "``x`<b> y``");
//! assert!(safe_link("https://example.org") && !safe_link("java\tscript:x"));
//! assert_eq!(xml_escape("a<'b'>&\""), "a&lt;&#39;b&#39;&gt;&amp;&quot;");
//! assert_eq!(terminal("\u{1b}[2J"), "\\u{1b}[2J");
//! ```

#![deny(missing_docs)]

use std::borrow::Cow;

/// `text` as one CSV field: quoted, its quotes doubled, when it holds a comma, a quote or a
/// line break (RFC 4180), a bare `\r` included, which pandas and Python's csv module end a
/// record at as they do at `\n`; else as it is.
///
/// A field that starts with `=`, `+`, `-`, `@`, a tab or a carriage return, which a
/// spreadsheet (Excel, LibreOffice Calc, Google Sheets) would take for a formula, gets a
/// leading `'` (OWASP's rule against CSV injection), so a label such as `=HYPERLINK(..)`
/// opens as its text. Only text goes through this function, so numbers (`-1.5`) are never
/// touched; the tables that carry types (`runs.json`, `runs.parquet/`) keep such a text as
/// it was written.
///
/// ```
/// use planner_text::csv_field;
/// assert_eq!(csv_field("astar"), "astar");
/// assert_eq!(csv_field("a,\"b\""), "\"a,\"\"b\"\"\"");
/// assert_eq!(csv_field("p\nq"), "\"p\nq\"");
/// assert_eq!(csv_field("=cmd|' /C calc'!A0"), "'=cmd|' /C calc'!A0");
/// assert_eq!(csv_field("@x,y"), "\"'@x,y\"");
/// assert_eq!(csv_field("random512-10-0"), "random512-10-0");
/// ```
pub fn csv_field(text: &str) -> Cow<'_, str> {
    let formula = text.starts_with(['=', '+', '-', '@', '\t', '\r']);
    let guarded: Cow<'_, str> = match formula {
        true => Cow::Owned(format!("'{text}")),
        false => Cow::Borrowed(text),
    };
    if guarded.contains([',', '"', '\n', '\r']) {
        Cow::Owned(format!("\"{}\"", guarded.replace('"', "\"\"")))
    } else {
        guarded
    }
}

/// `c` as text on one line: a control character or a line or paragraph separator
/// (U+2028, U+2029) becomes a space, anything else stays.
fn line_char(c: char) -> char {
    match c.is_control() || matches!(c, '\u{2028}' | '\u{2029}') {
        true => ' ',
        false => c,
    }
}

/// `text` for one cell of a markdown table, a heading or a list item: it shows as itself
/// (the same characters, as text) in CommonMark and GitHub's markdown, so it cannot end the
/// row, add a column or become emphasis, code, a link, an image, math or HTML. What it does:
///
/// - line breaks and other control characters become spaces, and leading and trailing
///   spaces go (no context shows them), so it is one line and cannot start an indented
///   code block;
/// - `<`, `>` and `&` become character references (`&lt;`, `&gt;`, `&amp;`), so that no
///   markdown viewer takes a label for HTML (a `<script>` or an `<img onerror>`);
/// - the characters that open or close inline syntax are backslash-escaped: `\`,
///   `` ` ``, `*`, `[`, `]`, `|`, `~`, `$` and `^` everywhere, and `_` except between two
///   letters or digits, where CommonMark never reads it as emphasis (`high_g` stays as it
///   is); the `(` after a `]` is escaped too, so no `](` is left for a link;
/// - what would start a block when the text starts a line (`#`, `-`, `+`, `=`, and the
///   `.` or `)` of an ordered-list marker such as `1.`), and a `#` run that would close a
///   heading (`x #`), are escaped.
///
/// Ordinary labels (`astar_octile`, `random512-10-0.map`, `C#`, `PA-star 2`) are written as
/// they are.
///
/// ```
/// use planner_text::md_cell;
/// assert_eq!(md_cell("a|b\nc"), "a\\|b c");
/// assert_eq!(md_cell("<b>&"), "&lt;b&gt;&amp;");
/// assert_eq!(md_cell("[x](y) *a* `c`"), "\\[x\\]\\(y) \\*a\\* \\`c\\`");
/// assert_eq!(md_cell("astar_octile _x_"), "astar_octile \\_x\\_");
/// assert_eq!(md_cell("1. x #"), "1\\. x \\#");
/// ```
pub fn md_cell(text: &str) -> String {
    let chars: Vec<char> = text.chars().map(line_char).collect();
    let first = chars.iter().position(|c| !c.is_whitespace());
    let last = chars.iter().rposition(|c| !c.is_whitespace());
    let chars = match (first, last) {
        (Some(first), Some(last)) => &chars[first..=last],
        _ => &[][..],
    };
    // From here to the end only `#` and spaces: a heading's closing sequence if a space
    // comes before it.
    let tail = chars
        .iter()
        .rposition(|&c| c != '#' && !c.is_whitespace())
        .map_or(0, |i| i + 1);
    // The `.` or `)` of an ordered-list marker: one to nine digits first, then a space or
    // the end.
    let digits = chars.iter().take_while(|c| c.is_ascii_digit()).count();
    let marker = (1..=9).contains(&digits)
        && matches!(chars.get(digits), Some('.' | ')'))
        && chars.get(digits + 1).is_none_or(|c| c.is_whitespace());
    let alphanumeric = |i: Option<usize>| {
        i.and_then(|i| chars.get(i))
            .is_some_and(|c| c.is_alphanumeric())
    };
    let mut out = String::with_capacity(text.len() + 8);
    for (i, &c) in chars.iter().enumerate() {
        let escape = match c {
            '<' | '>' | '&' => {
                out.push_str(match c {
                    '<' => "&lt;",
                    '>' => "&gt;",
                    _ => "&amp;",
                });
                continue;
            }
            '\\' | '`' | '*' | '[' | ']' | '|' | '~' | '$' | '^' => true,
            '(' => out.ends_with(']'),
            '_' => !(alphanumeric(i.checked_sub(1)) && alphanumeric(Some(i + 1))),
            '#' => i == 0 || (i >= tail && chars[i - 1].is_whitespace()),
            '-' | '+' | '=' => i == 0,
            '.' | ')' => marker && i == digits,
            _ => false,
        };
        if escape {
            out.push('\\');
        }
        out.push(c);
    }
    out
}

/// `text` as one inline code span of markdown prose (a label or a path shown as written):
/// line breaks and other control characters as spaces, so it cannot end the paragraph or
/// start a heading; fenced with one backtick more than the longest run of backticks in it,
/// and padded with a space when it begins or ends with a backtick or a space, so that it
/// cannot close the span early (CommonMark 6.1). Nothing in a code span is HTML or a link,
/// and character references are not decoded there, so `<` and `&` are written as they are.
/// Not for a table cell, where `|` ends the cell even inside a code span: use [`md_cell`].
///
/// ```
/// use planner_text::md_code;
/// assert_eq!(md_code("astar"), "`astar`");
/// assert_eq!(md_code("a`b"), "``a`b``");
/// assert_eq!(md_code("`x"), "`` `x ``");
/// assert_eq!(md_code("<img>\n# h"), "`<img> # h`");
/// ```
pub fn md_code(text: &str) -> String {
    let text: String = text.chars().map(line_char).collect();
    let longest_run = text.split(|c| c != '`').map(str::len).max().unwrap_or(0);
    let fence = "`".repeat(longest_run + 1);
    let pad = text.starts_with('`')
        || text.ends_with('`')
        || (text.starts_with(' ') && text.ends_with(' '))
        || text.is_empty();
    match pad {
        true => format!("{fence} {text} {fence}"),
        false => format!("{fence}{text}{fence}"),
    }
}

/// `text` as markdown prose (a config's description): kept as written, markdown included,
/// except that a `<` that could open raw HTML or an autolink (before a letter, `/`, `!` or
/// `?`: a tag, a comment, a declaration, `<javascript:x>`) becomes `&lt;`, and a link
/// whose destination is not [`safe_link`] is escaped, so that no markdown viewer runs or
/// draws them (report.html keeps the same links): the `(` of an inline link or image
/// (`[t](dest)`) and the `:` of a reference definition (`[t]: dest`, which `[t]` then
/// links to). They show as themselves; `a <-> b`, `x < y`, `[ok](https://example.org)`
/// and `[r]: https://example.org` stay as they are.
///
/// The destination is judged as a CommonMark renderer reads it: in angle brackets or up
/// to a space or an unbalanced `)`, its backslash escapes and its character references
/// decoded (`java&#115;cript:` is `javascript:`, `&colon;` a `:`). A destination with a
/// named character reference outside the few it knows (`&amp;`, `&colon;`, `&Tab;`, ...)
/// or on the line after its `](` or `]:` is escaped whatever it holds.
///
/// ```
/// use planner_text::md_prose;
/// assert_eq!(
///     md_prose("<script>x</script> *a* <-> b [j](javascript:x) [ok](https://o.org)"),
///     "&lt;script>x&lt;/script> *a* <-> b [j]\\(javascript:x) [ok](https://o.org)"
/// );
/// // Case, a space, character references and escapes do not hide a scheme.
/// assert_eq!(md_prose("[t]( JavaScript:x)"), "[t]\\( JavaScript:x)");
/// assert_eq!(md_prose("[g](java&#115;cript:x)"), "[g]\\(java&#115;cript:x)");
/// assert_eq!(md_prose("[h](javascript&colon;x)"), "[h]\\(javascript&colon;x)");
/// // A reference definition is judged as an inline link is.
/// assert_eq!(md_prose("[e]: javascript:x\n\n[e]"), "[e]\\: javascript:x\n\n[e]");
/// assert_eq!(md_prose("[r]: https://o.org \"t\"\n\n[r]"), "[r]: https://o.org \"t\"\n\n[r]");
/// ```
pub fn md_prose(text: &str) -> String {
    // Raw HTML first, so that links are judged as they are written.
    let mut written = String::with_capacity(text.len());
    for (at, c) in text.char_indices() {
        match c == '<' && opens_html(&text[at + 1..]) {
            true => written.push_str("&lt;"),
            false => written.push(c),
        }
    }
    // A `\` added before a `(` or `:` only ever ends an earlier destination sooner, never
    // changes its scheme: judging each on `written` holds for the output.
    let mut out = String::with_capacity(written.len() + 8);
    for (at, c) in written.char_indices() {
        let rest = &written[at + c.len_utf8()..];
        if matches!(c, '(' | ':') && out.ends_with(']') && !safe_destination(rest) {
            out.push('\\');
        }
        out.push(c);
    }
    out
}

/// Whether a `<` before `rest` could open raw HTML or an autolink: [`md_prose`] writes
/// it as `&lt;`.
fn opens_html(rest: &str) -> bool {
    rest.chars()
        .next()
        .is_some_and(|n| n.is_ascii_alphabetic() || matches!(n, '/' | '!' | '?'))
}

/// Whether the link destination that `rest` (what follows an inline link's `](` or a
/// reference definition's `]:`) starts with is [`safe_link`] once decoded
/// ([`decoded_destination`]). One on the next line is not judged (the line may start
/// with a block quote's `>` or a list item's indent, which are not part of it): unsafe.
fn safe_destination(rest: &str) -> bool {
    let dest = rest.trim_start_matches([' ', '\t']);
    if dest.starts_with(['\n', '\r']) {
        return false;
    }
    decoded_destination(dest).is_some_and(|url| safe_link(&url))
}

/// The link destination `text` starts with, as a CommonMark renderer hands it to the
/// browser: up to the closing `>` when written in angle brackets, else up to a space, a
/// control character or a `)` that closes no `(`; backslash escapes of ASCII punctuation
/// and character references decoded. `None` when it holds a named character reference
/// this function does not know (it cannot tell what it decodes to).
fn decoded_destination(text: &str) -> Option<String> {
    let (body, bracketed) = match text.strip_prefix('<') {
        Some(body) => (body, true),
        None => (text, false),
    };
    let mut out = String::new();
    let mut depth = 0usize;
    let mut at = 0;
    while let Some(c) = body[at..].chars().next() {
        at += c.len_utf8();
        match c {
            '\\' => match body[at..].chars().next() {
                Some(next) if next.is_ascii_punctuation() => {
                    out.push(next);
                    at += 1;
                }
                _ => out.push('\\'),
            },
            '&' => match character_reference(&body[at..]) {
                Reference::Decoded(decoded, len) => {
                    out.push_str(&decoded);
                    at += len;
                }
                Reference::Unknown => return None,
                Reference::Literal => out.push('&'),
            },
            '>' | '<' | '\n' | '\r' if bracketed => break,
            _ if bracketed => out.push(c),
            c if c.is_ascii_whitespace() || c.is_ascii_control() => break,
            '(' => {
                depth += 1;
                out.push(c);
            }
            ')' if depth == 0 => break,
            ')' => {
                depth -= 1;
                out.push(c);
            }
            c => out.push(c),
        }
    }
    Some(out)
}

/// What follows a `&` in a link destination.
enum Reference {
    /// A character reference: what it decodes to and its length after the `&`.
    Decoded(String, usize),
    /// A named reference (`&name;`) not in [`NAMED_REFERENCES`].
    Unknown,
    /// No reference: the `&` is itself.
    Literal,
}

/// The named character references [`decoded_destination`] decodes: HTML's for ASCII
/// punctuation, whitespace and `&nbsp;`. Any other `&name;` makes a destination unsafe.
const NAMED_REFERENCES: [(&str, &str); 33] = [
    ("amp", "&"),
    ("lt", "<"),
    ("gt", ">"),
    ("quot", "\""),
    ("apos", "'"),
    ("colon", ":"),
    ("sol", "/"),
    ("quest", "?"),
    ("num", "#"),
    ("Tab", "\t"),
    ("NewLine", "\n"),
    ("nbsp", "\u{a0}"),
    ("period", "."),
    ("lpar", "("),
    ("rpar", ")"),
    ("excl", "!"),
    ("commat", "@"),
    ("equals", "="),
    ("plus", "+"),
    ("percnt", "%"),
    ("dollar", "$"),
    ("ast", "*"),
    ("comma", ","),
    ("lowbar", "_"),
    ("semi", ";"),
    ("bsol", "\\"),
    ("lsqb", "["),
    ("rsqb", "]"),
    ("lcub", "{"),
    ("rcub", "}"),
    ("verbar", "|"),
    ("Hat", "^"),
    ("grave", "`"),
];

/// The character reference (CommonMark 2.5) that `text`, what follows a `&`, starts
/// with: `#` and 1 to 7 decimal digits, `#x` and 1 to 6 hex digits (0 and what is not a
/// character decode to U+FFFD), or a name of letters and digits, each ended by `;`.
fn character_reference(text: &str) -> Reference {
    let Some(end) = text.find(';') else {
        return Reference::Literal;
    };
    let (inside, len) = (&text[..end], end + 1);
    let numeric = match inside.strip_prefix('#') {
        Some(hex) if hex.starts_with(['x', 'X']) => {
            let digits = &hex[1..];
            ((1..=6).contains(&digits.len()) && digits.bytes().all(|b| b.is_ascii_hexdigit()))
                .then(|| u32::from_str_radix(digits, 16).ok())
                .flatten()
        }
        Some(digits) => ((1..=7).contains(&digits.len())
            && digits.bytes().all(|b| b.is_ascii_digit()))
        .then(|| digits.parse::<u32>().ok())
        .flatten(),
        None => {
            let is_name = inside.starts_with(|c: char| c.is_ascii_alphabetic())
                && inside.bytes().all(|b| b.is_ascii_alphanumeric());
            if !is_name {
                return Reference::Literal;
            }
            return match NAMED_REFERENCES.iter().find(|(name, _)| *name == inside) {
                Some((_, decoded)) => Reference::Decoded((*decoded).to_string(), len),
                None => Reference::Unknown,
            };
        }
    };
    match numeric {
        Some(code) => {
            let c = char::from_u32(code)
                .filter(|&c| c != '\0')
                .unwrap_or('\u{fffd}');
            Reference::Decoded(c.to_string(), len)
        }
        None => Reference::Literal,
    }
}

/// Whether a link to `url` may stay a link: its scheme (what precedes a `:` that comes
/// before any `/`, `?` or `#`, ASCII case and the whitespace and control characters
/// browsers skip ignored) is `http`, `https` or `mailto`, or it has none (a relative link
/// or a `#fragment`).
///
/// ```
/// use planner_text::safe_link;
/// assert!(safe_link("https://example.org/a") && safe_link("charts/a.svg") && safe_link("#s1"));
/// assert!(!safe_link("javascript:alert(1)") && !safe_link(" JaVa\tScRiPt:x") && !safe_link("data:text/html,x"));
/// ```
pub fn safe_link(url: &str) -> bool {
    let cleaned: String = url
        .chars()
        .filter(|c| !c.is_whitespace() && !c.is_control())
        .collect();
    match cleaned.find([':', '/', '?', '#']) {
        Some(i) if cleaned[i..].starts_with(':') => {
            let scheme = cleaned[..i].to_ascii_lowercase();
            matches!(scheme.as_str(), "http" | "https" | "mailto")
        }
        _ => true,
    }
}

/// `text` escaped for XML and HTML text and quoted attribute values (`&`, `<`, `>`, `"`,
/// and `'` as `&#39;`, which both read).
///
/// ```
/// assert_eq!(planner_text::xml_escape("<b a='1'>&"), "&lt;b a=&#39;1&#39;&gt;&amp;");
/// ```
pub fn xml_escape(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    for c in text.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            '\'' => out.push_str("&#39;"),
            c => out.push(c),
        }
    }
    out
}

/// `text` for one line of a terminal: every control character written as an escape
/// (`\u{a}` for a line break, `\u{9}` for a tab), so that a path or name a user supplied
/// (a file named `new\nline.map`) can neither send a control sequence nor end the line of
/// the message it is in, which a script reading stderr line by line would take as two.
/// Apply it to the user's text before it goes into a message that may span lines on
/// purpose; [`terminal`] is then for the message.
///
/// ```
/// use planner_text::one_line;
/// assert_eq!(one_line("new\nline\t\r.map"), "new\\u{a}line\\u{9}\\u{d}.map");
/// assert_eq!(one_line("plain.map"), "plain.map");
/// ```
pub fn one_line(text: &str) -> Cow<'_, str> {
    if !text.chars().any(char::is_control) {
        return Cow::Borrowed(text);
    }
    let mut out = String::with_capacity(text.len() + 8);
    for c in text.chars() {
        if c.is_control() {
            out.extend(c.escape_unicode());
        } else {
            out.push(c);
        }
    }
    Cow::Owned(out)
}

/// `text` for a terminal: control characters other than line breaks and tabs written as
/// escapes (`\u{1b}`), so that a label, path or map name from a config someone else wrote
/// cannot recolour, retitle or move the cursor of the terminal the command's messages go to.
/// Line breaks and tabs are kept for messages that span lines on purpose: a user's path or
/// name in them is written with [`one_line`] first.
///
/// ```
/// use planner_text::terminal;
/// assert_eq!(terminal("a\u{1b}[31mb\u{7}\nc\td"), "a\\u{1b}[31mb\\u{7}\nc\td");
/// assert_eq!(terminal("plain"), "plain");
/// ```
pub fn terminal(text: &str) -> Cow<'_, str> {
    let escaped = |c: char| c.is_control() && !matches!(c, '\n' | '\t');
    if !text.chars().any(escaped) {
        return Cow::Borrowed(text);
    }
    let mut out = String::with_capacity(text.len() + 8);
    for c in text.chars() {
        if escaped(c) {
            out.extend(c.escape_unicode());
        } else {
            out.push(c);
        }
    }
    Cow::Owned(out)
}
