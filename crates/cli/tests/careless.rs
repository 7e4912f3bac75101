//! The careless user: many bad inputs through the real `gridplan` binary. Every one must
//! end (a timeout per command), never panic (no "panicked", no exit code 101), fail with
//! a documented exit code (1 to 5: tests/exit_codes.rs checks which; 2 for arguments clap
//! refuses) and a message naming the file and position,
//! the key or the cell, and write nothing (the working directory is unchanged).

use std::collections::BTreeSet;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

use crate::common::{
    self, gridplan, gridplan_with, refused, run_slurm_scripts, shard, succeeded, SMALL,
};

/// What a case must give.
enum Expect {
    /// A documented failure exit code (1 to 5), this text in stderr, nothing written.
    Error(&'static str),
    /// Exit code 2 (clap refused the arguments), this text in stderr, nothing written.
    Usage(&'static str),
    /// Success (exit 0), with this warning text in stderr.
    Warn(&'static str),
}

/// One case: the files to write (name, bytes), the arguments, what must happen.
type Case = (Vec<(String, Vec<u8>)>, Vec<String>, Expect);

/// A valid config on `small.map`; cases edit it.
const CONFIG: &str = "name = \"c\"\n[[maps]]\nfiles = [\"small.map\"]\nproblems = \"corners\"\n[planners.a]\nplanner = \"astar\"\n";

fn scratch(case: usize) -> PathBuf {
    common::scratch("careless", case)
}

/// Every path under `dir`, relative to it.
fn listing(dir: &Path) -> BTreeSet<PathBuf> {
    let mut out = BTreeSet::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(at) = stack.pop() {
        let Ok(entries) = std::fs::read_dir(&at) else {
            continue;
        };
        for entry in entries.flatten() {
            let path = entry.path();
            out.insert(path.strip_prefix(dir).unwrap().to_path_buf());
            if entry.file_type().is_ok_and(|t| t.is_dir()) {
                stack.push(path);
            }
        }
    }
    out
}

/// Writes `files` into a fresh directory, runs `gridplan args` there and checks `expect`;
/// returns a description of what is wrong, if anything.
fn check(case: usize, files: &[(&str, &[u8])], args: &[&str], expect: Expect) -> Option<String> {
    let dir = scratch(case);
    for (name, bytes) in files {
        let path = dir.join(name);
        if let Some(parent) = path.parent() {
            std::fs::create_dir_all(parent).unwrap();
        }
        std::fs::write(path, bytes).unwrap();
    }
    let before = listing(&dir);
    let out = gridplan(&dir, args);
    let after = listing(&dir);
    let _ = std::fs::remove_dir_all(&dir);
    let mut problems = Vec::new();
    if out.stderr.contains("panicked") || out.code == Some(101) {
        problems.push("panicked".to_owned());
    }
    let (code, text) = match expect {
        Expect::Error(text) => (1, text),
        Expect::Usage(text) => (2, text),
        Expect::Warn(text) => (0, text),
    };
    // Plain text for a pipe: no ANSI colour codes, no Rust debug formatting.
    if out.stderr.contains('\u{1b}') {
        problems.push("ANSI escape codes in stderr".to_owned());
    }
    if out.stderr.contains("Some(") || out.stderr.contains("None") {
        problems.push("Rust debug formatting in stderr".to_owned());
    }
    let documented = match expect {
        Expect::Error(_) => matches!(out.code, Some(1..=5)),
        _ => out.code == Some(code),
    };
    if !documented {
        problems.push(format!("exit code {:?}, expected {code}", out.code));
    }
    if !out.stderr.contains(text) {
        problems.push(format!("stderr lacks {text:?}"));
    }
    // A warning is said once, however many runs it concerns.
    if code == 0 && out.stderr.matches(text).count() > 1 {
        problems.push(format!("stderr repeats {text:?}"));
    }
    if code != 0 {
        if before != after {
            let new: Vec<_> = after.difference(&before).collect();
            problems.push(format!("wrote {new:?} on failure"));
        }
        if !out.stdout.is_empty() {
            problems.push(format!("printed {:?} on failure", out.stdout));
        }
    }
    (!problems.is_empty()).then(|| {
        format!(
            "case {case}: gridplan {args:?}: {}\n  stderr: {}",
            problems.join("; "),
            out.stderr.trim_end().replace('\n', "\n          ")
        )
    })
}

/// `experiment c.toml` on `config` with `small.map` beside it.
fn experiment(config: &str) -> Vec<(&'static str, Vec<u8>)> {
    vec![
        ("c.toml", config.as_bytes().to_vec()),
        ("small.map", SMALL.to_vec()),
    ]
}

/// [`CONFIG`] with `from` replaced by `to` (which must occur).
fn edit(from: &str, to: &str) -> String {
    assert!(CONFIG.contains(from), "{from}");
    CONFIG.replacen(from, to, 1)
}

#[test]
fn careless_inputs_fail_cleanly() {
    use Expect::{Error, Usage, Warn};
    let exp = ["experiment", "c.toml", "--quiet"];
    let long_name = "x".repeat(300);
    let experiments: Vec<(String, Expect)> = vec![
        // Malformed TOML.
        ("".into(), Error("c.toml:1:1: missing field `name`")),
        ("name = \"c\"\n[[maps]\n".into(), Error("c.toml:2:")),
        ("name = \"c\nfoo".into(), Error("c.toml:1:")),
        ("name = c\n".into(), Error("c.toml:1:8")),
        (CONFIG.replace("astar\"", "astar"), Error("c.toml:6:")),
        (format!("name = \"d\"\n{CONFIG}"), Error("c.toml:2:1: duplicate key")),
        (format!("{CONFIG}name = \"d\"\n"), Error("c.toml:7:1: planner `a` (astar): unknown field `name`")),
        ("\u{feff}\u{1F600} = 1\n".into(), Error("c.toml:1:")),
        // Wrong types and values.
        (edit("name = \"c\"", "name = 5"), Error("c.toml:1:8")),
        (edit("name = \"c\"", "name = \"\""), Error("key `name`")),
        (edit("name = \"c\"", "name = \"../x\""), Error("key `name`")),
        (edit("name = \"c\"", "name = \"caf\u{e9}\""), Error("key `name`")),
        (
            edit("name = \"c\"", &format!("name = \"{long_name}\"")),
            Error("key `name`"),
        ),
        (format!("repeats = 0\n{CONFIG}"), Error("key `repeats`")),
        (format!("repeats = -1\n{CONFIG}"), Error("c.toml:1:11")),
        (format!("repeats = 1.5\n{CONFIG}"), Error("c.toml:1:11")),
        (
            format!("repeats = 99999999999999999999\n{CONFIG}"),
            Error("c.toml:1:11"),
        ),
        (format!("threads = -3\n{CONFIG}"), Error("c.toml:1:11")),
        (format!("threads = 100000\n{CONFIG}"), Error("key `threads`")),
        (format!("seed = -1\n{CONFIG}"), Error("c.toml:1:8")),
        (format!("seed = \"7\"\n{CONFIG}"), Error("c.toml:1:8")),
        (format!("figures = \"some\"\n{CONFIG}"), Error("c.toml:1:11")),
        (format!("sections = [\"nope\"]\n{CONFIG}"), Error("c.toml:1:")),
        (format!("colour = 1\n{CONFIG}"), Error("c.toml:1:1: unknown field `colour`")),
        // The two tables in the other shape: the shape each takes (toml's own words were
        // "invalid type: sequence, expected a map").
        (
            edit("[planners.a]", "[[planners]]"),
            Error("c.toml:5:1: key `planners`: a table of labelled planners, one `[planners.LABEL]`"),
        ),
        (
            format!(
                "planners = [{{ planner = \"astar\" }}]\n{}",
                edit("[planners.a]\nplanner = \"astar\"\n", "")
            ),
            Error("c.toml:1:12: key `planners`: a table of labelled planners"),
        ),
        (
            edit("[[maps]]", "[maps]"),
            Error("c.toml:2:1: key `maps`: an array of tables, one `[[maps]]` per group"),
        ),

        (format!("{CONFIG}[budget]\nmax_expansions = -5\n"), Error("c.toml:8:")),
        (format!("{CONFIG}[budget]\nmax_expansions = \"lots\"\n"), Error("c.toml:8:")),
        (format!("{CONFIG}[budget]\nmax_hours = 1\n"), Error("c.toml:8:")),
        // Map sets.
        (
            edit("files = [\"small.map\"]", "files = []"),
            Error("c.toml:3:9: maps[0]: key `files`: at least one map is needed"),
        ),
        // An empty list of pairs ran nothing without a word.
        (
            edit("problems = \"corners\"", "pairs = []"),
            Error("c.toml:4:9: maps[0]: key `pairs`: at least one start-goal pair is needed"),
        ),
        // Coordinates of more than two items were read as their first two.
        (
            edit("problems = \"corners\"", "pairs = [{ start = [0, 0, \"junk\", [1, 2]], goal = [2, 2] }]"),
            Error("c.toml:4:20: key `maps[0].pairs[0].start`: invalid length 4, expected an array of length 2"),
        ),
        (
            edit("problems = \"corners\"", "pairs = [{ start = [0, 0], goal = [2, 2, -7] }]"),
            Error("c.toml:4:35: key `maps[0].pairs[0].goal`: invalid length 3, expected an array of length 2"),
        ),
        (
            edit("problems = \"corners\"", "pairs = [{ start = [0], goal = [2, 2] }]"),
            Error("c.toml:4:20: key `maps[0].pairs[0].start`: invalid length 1, expected an array of length 2"),
        ),
        (
            edit("problems = \"corners\"", "problems = \"start\"\nstart = [0, 0, 5]"),
            Error("c.toml:5:9: key `maps[0].start`: invalid length 3, expected an array of length 2"),
        ),
        (edit("files = [\"small.map\"]", "files = \"small.map\""), Error("c.toml:3:9")),
        (edit("small.map\"]", "missing.map\"]"), Error("nothing matches \"missing.map\"")),
        (edit("small.map\"]", "[\"]"), Error("key `files`: bad pattern")),
        (edit("small.map\"]", "c.toml\"]"), Error("unsupported file extension '.toml'")),
        (edit("small.map\"]", "small.map\", \"small.map\"]"), Error("c.toml:2:1: maps[0]: map name `small.map` appears twice")),
        (edit("problems = \"corners\"", "problems = \"all\""), Error("c.toml:4:12")),
        // The list of `problems` values lacked "start".
        (
            edit("problems = \"corners\"", ""),
            Error("give exactly one of `problems` (\"corners\", \"file\" or \"start\"), `pairs`, `points` or `scen`"),
        ),
        (
            edit("problems = \"corners\"", "problems = \"corners\"\npairs = []"),
            Error("exclude each other"),
        ),
        (
            edit("problems = \"corners\"", "problems = \"file\""),
            Error("lists no start-goal pairs"),
        ),
        (edit("problems = \"corners\"", "problems = \"start\""), Error("needs `start = [x, y]`")),
        (
            edit(
                "problems = \"corners\"",
                "pairs = [{ start = [0, 0], goal = [-1, 2] }]",
            ),
            Error("c.toml:4:"),
        ),
        (
            edit(
                "problems = \"corners\"",
                "pairs = [{ start = [0, 0], goal = [2, 2], via = [1, 1] }]",
            ),
            Error("c.toml:4:"),
        ),
        (
            edit(
                "problems = \"corners\"",
                "pairs = [{ start = [0, 0], goal = [4294967296, 0] }]",
            ),
            Error("c.toml:4:"),
        ),
        (edit("problems = \"corners\"", "scen = \"none.scen\""), Error("key `scen`")),
        (
            edit("problems = \"corners\"", "problems = \"corners\"\ninflation = 2"),
            Error("apply to ROS `.yaml` maps"),
        ),
        (
            edit("problems = \"corners\"", "problems = \"corners\"\nobstacle = 1"),
            Error("key `obstacle` applies to `.csv` maps"),
        ),
        (
            edit("problems = \"corners\"", "problems = \"corners\"\nlimit = 3"),
            Error("need `scen`"),
        ),
        (edit("[[maps]]", "[maps]"), Error("c.toml:2:")),
        // Planners.
        (edit("planner = \"astar\"", "planner = \"astra\""), Error("unknown planner \"astra\"")),
        // A planner name that is no string was "unknown planner \"3\"".
        (
            edit("planner = \"astar\"", "planner = 3"),
            Error("c.toml:6:11: planner `a`, key `planner`: expected a registry name (a string: one of"),
        ),
        // An empty label was accepted (an empty planner cell in runs.csv, a figure named
        // `small-1--e3b0c442.svg`).
        (
            edit("[planners.a]", "[planners.\"\"]"),
            Error("c.toml:5:11: key `planners`: label \"\" is empty"),
        ),
        // No label, no map: said without a line and column.
        (
            edit("[planners.a]\nplanner = \"astar\"\n", "[planners]\n"),
            Error("c.toml:5:2: key `planners`: at least one planner is needed"),
        ),
        (
            format!("name = \"c\"\nmaps = []\n{}", &CONFIG[CONFIG.find("[planners").unwrap()..]),
            Error("c.toml:2:1: key `maps`: at least one map is needed"),
        ),
        // Rust type names in messages ("untagged enum RawSection", "struct RawCosts",
        // "struct Budget"): what is expected, in words.
        (
            format!("sections = [1]\n{CONFIG}"),
            Error("c.toml:1:12: key `sections[0]`: expected a section name (a string) or a table { name = \"...\", ... }, got 1"),
        ),
        (
            edit("problems = \"corners\"", "problems = \"corners\"\ncosts = \"ignore\""),
            Error("c.toml:5:9: key `maps[0].costs`: expected a table of cell-cost options (`rule`, `lethal`, `unknown`, `weights`, `swamp`, `water`), got the string \"ignore\""),
        ),
        (
            format!("budget = 5\n{CONFIG}"),
            Error("c.toml:1:10: key `budget`: expected a table of limits (`max_expansions`, `max_time_ms`, `max_memory_mb`), got 5"),
        ),
        (
            edit("planner = \"astar\"", "planner = \"astar\"\nbudget = 5"),
            Error("c.toml:7:10: planner `a`, key `budget`: expected a table of limits (`max_expansions`, `max_time_ms`, `max_memory_mb`), got 5"),
        ),
        // `inflate_unknown` on a .map was said at the `[[maps]]` header.
        (
            edit("problems = \"corners\"", "problems = \"corners\"\ninflate_unknown = true"),
            Error("c.toml:5:19: maps[0]: `inflation` and `inflate_unknown` apply to ROS `.yaml` maps"),
        ),
        // A seed 002 section whose planner no label runs was left out without a word.
        (
            format!("sections = [{{ name = \"seed002\", proposed = \"nope\" }}]\n{CONFIG}"),
            Error("c.toml:1:12: key `sections`: section \"seed002\": `proposed = \"nope\"` names no planner of this config; expected the registry name of one of its planners (astar)"),
        ),
        (
            format!("sections = [{{ name = \"seed002\", proposed = \"pastar\" }}]\n{CONFIG}"),
            Error("`proposed = \"pastar\"` names no planner of this config"),
        ),
        (
            format!("sections = [{{ name = \"seed002_capso\", planner = \"capso\" }}]\n{CONFIG}"),
            Error("section \"seed002_capso\": `planner = \"capso\"` names no planner of this config"),
        ),
        (edit("planner = \"astar\"", ""), Error("key `planner` is missing")),
        (
            edit("planner = \"astar\"", "planner = \"astar\"\nmoves = 7"),
            Error("parameter `moves`"),
        ),
        (
            edit("planner = \"astar\"", "planner = \"astar\"\nheuristic = \"manhatan\""),
            Error("c.toml:7:"),
        ),
        (
            edit("planner = \"astar\"", "planner = \"astar\"\nweight = -2.0"),
            Error("`weight`"),
        ),
        (
            edit("planner = \"astar\"", "planner = \"astar\"\nweight = nan"),
            Error("`weight`"),
        ),
        (
            edit("planner = \"astar\"", "planner = \"astar\"\nspeed = 3"),
            Error("c.toml:7:"),
        ),
        (
            edit("planner = \"astar\"", "planner = \"rrt\"\nmax_iterations = -1"),
            Error("c.toml:7:"),
        ),
        (
            edit("planner = \"astar\"", "planner = \"astar\"\nbudget = { max_expansions = -1 }"),
            Error("key `budget`"),
        ),
        (
            edit(
                "planner = \"astar\"",
                "planner = \"lexastar\"\ncompare = { with = \"backtracking\", metrics = [\"stepz\"] }",
            ),
            Error("unknown metric `stepz`"),
        ),
        (edit("[planners.a]\nplanner = \"astar\"\n", ""), Error("c.toml:")),
        // Issue 27: an inadmissible heuristic ran without a word; now a warning at config
        // time (the runs are recorded `admissible = false`, summary.md says so).
        (
            edit("planner = \"astar\"\n", "planner = \"astar\"\nmoves = 16\nheuristic = \"manhattan\"\n"),
            Warn("c.toml:5:11: planner `a` (astar): its specs declare that its paths need not be least-cost (for A*: its heuristic can overestimate under its moves"),
        ),
        // Published values.
        (format!("published = \"none.toml\"\n{CONFIG}"), Error("key `published`")),
        (format!("published = \"small.map\"\n{CONFIG}"), Error("small.map:1:")),
        (format!("published = \"/dev/zero\"\n{CONFIG}"), Error("not a regular file")),
        (format!("published = \".\"\n{CONFIG}"), Error("not a regular file")),
    ];
    let mut cases: Vec<Case> = Vec::new();
    let owned = |files: Vec<(&str, Vec<u8>)>| -> Vec<(String, Vec<u8>)> {
        files.into_iter().map(|(n, b)| (n.to_owned(), b)).collect()
    };
    let args = |list: &[&str]| -> Vec<String> { list.iter().map(|s| s.to_string()).collect() };
    for (config, expect) in experiments {
        cases.push((owned(experiment(&config)), args(&exp), expect));
    }

    // Map files as the config's maps.
    let bad_maps: Vec<(&str, &[u8], Expect)> = vec![
        ("bad.map", b"", Error("bad.map:1:1")),
        ("bad.map", b"type octile\nheight 3\nwidth 3\nmap\n...\n", Error("bad.map:")),
        ("bad.map", b"type octile\nheight 2\nwidth 2\nmap\n.Q\n..\n", Error("bad.map:5:2")),
        (
            "bad.map",
            b"type octile\nheight 100000\nwidth 100000\nmap\n",
            Error("more than the limit"),
        ),
        (
            "bad.map",
            b"type octile\nheight 99999999999\nwidth 2\nmap\n",
            Error("bad.map:2:"),
        ),
        ("bad.map", b"type octile\nheight -2\nwidth 2\nmap\n", Error("bad.map:2:")),
        ("bad.map", b"\x00\xff\xfe\x01junk", Error("bad.map:1:")),
        ("bad.map", b"type octile\nheight 0\nwidth 0\nmap\n", Error("bad.map:")),
        ("bad.txt", b"..X\n.Q.\n", Error("bad.txt:2:2")),
        ("bad.txt", b"# only a comment\n", Error("bad.txt:")),
        ("bad.txt", "..\u{2588}\n...\n".as_bytes(), Error("bad.txt:1:3")),
        ("bad.csv", b"1,0\n1\n", Error("bad.csv:2:")),
        ("bad.csv", b"1,2\n", Error("bad.csv:1:3")),
        ("bad.csv", b"1,,0\n", Error("bad.csv:1:3")),
        ("bad.csv", b"", Error("bad.csv:")),
        ("bad.yaml", b"image: [\n", Error("bad.yaml:")),
        ("bad.yaml", b"resolution: 0.05\n", Error("c.toml:3:9: maps[0]: bad.yaml:1:1: missing key 'image'")),
        (
            "bad.yaml",
            b"image: none.pgm\nresolution: 0.05\norigin: [0, 0, 0]\nnegate: 0\noccupied_thresh: 0.65\nfree_thresh: 0.196\n",
            Error("none.pgm"),
        ),
        ("bad.pgm", b"P5 3 3 255 \x00", Error("bad.pgm")),
        ("bad.pgm", b"P2 100000 100000 255\n", Error("more than the limit")),
        ("bad.png", b"\x89PNG\r\n\x1a\nnot really", Error("bad.png")),
    ];
    for (name, bytes, expect) in bad_maps {
        let config = edit("small.map", name);
        let files = vec![("c.toml", config.into_bytes()), (name, bytes.to_vec())];
        cases.push((owned(files), args(&exp), expect));
    }
    // The same bad maps given to `plan` would repeat these; a few through plan.
    let plan = |map: &str, rest: &[&str]| {
        let mut a = vec!["plan", map];
        a.extend_from_slice(rest);
        args(&a)
    };
    let small = || owned(vec![("small.map", SMALL.to_vec())]);
    let scen_other = b"version 1\n0\tother.map\t5\t5\t0\t0\t1\t1\t1.4\n".to_vec();
    let scen_same = b"version 1\n0\tother.map\t3\t3\t0\t0\t2\t2\t3.4\n".to_vec();
    let plan_cases: Vec<Case> = vec![
        (small(), plan("missing.map", &["--planner", "astar"]), Error("missing.map: cannot read the file")),
        (small(), plan(".", &["--planner", "astar"]), Error("unsupported file extension")),
        (
            owned(vec![("dir.map/x", b"".to_vec())]),
            plan("dir.map", &["--planner", "astar"]),
            Error("dir.map: not a regular file (a directory)"),
        ),
        (small(), plan("/dev/zero", &["--planner", "astar"]), Error("unsupported file extension")),
        (small(), plan("small.map", &["--planner", "astra"]), Error("unknown planner `astra`")),
        (small(), plan("small.map", &["--planner", ""]), Error("unknown planner ``")),
        (small(), plan("small.map", &["--planner", "astar", "--start", "1,1", "--goal", "2,2"]), Error("small.map: start (1, 1) is blocked")),
        (small(), plan("small.map", &["--planner", "astar", "--start", "0,0", "--goal", "3,0"]), Error("(3, 0)")),
        (small(), plan("small.map", &["--planner", "astar", "--start", "4294967295,4294967295", "--goal", "0,0"]), Error("(4294967295, 4294967295)")),
        (small(), plan("small.map", &["--planner", "astar", "--start", "0;0", "--goal", "2,2"]), Usage("expected x,y")),
        // A bad cell names the coordinate at fault and why, whatever its form (a negative
        // one was clap's "tip: to pass '-1' as a value, use '-- -1'"; `0,0,0` blamed "0,0").
        (small(), plan("small.map", &["--planner", "astar", "--start", "-1,0", "--goal", "2,2"]), Usage("\"-1,0\": x coordinate -1 is negative; cells are numbered from 0")),
        (small(), plan("small.map", &["--planner", "astar", "--start=-1,0", "--goal", "2,2"]), Usage("\"-1,0\": x coordinate -1 is negative")),
        (small(), plan("small.map", &["--planner", "astar", "--start", "0,0", "--goal", "0,-3"]), Usage("\"0,-3\": y coordinate -3 is negative")),
        (small(), plan("small.map", &["--planner", "astar", "--start", "0,0,0", "--goal", "2,2"]), Usage("\"0,0,0\": expected x,y (two coordinates separated by one comma)")),
        (small(), plan("small.map", &["--planner", "astar", "--start", "4294967296,0", "--goal", "2,2"]), Usage("x coordinate 4294967296 is over the largest cell coordinate, 4294967295")),
        (small(), plan("small.map", &["--planner", "astar", "--start", "0,0", "--goal", "99999999999,0"]), Usage("\"99999999999,0\": x coordinate 99999999999 is over the largest cell coordinate, 4294967295")),
        (small(), plan("small.map", &["--planner", "astar", "--start", "0,1.5", "--goal", "2,2"]), Usage("\"0,1.5\": y coordinate \"1.5\" is not a whole number")),
        // A line break in a path or value the user gave cannot end the error's line (a
        // script reading stderr line by line read `error: new` and `line.map: goal ...`).
        (
            owned(vec![("new\nline.map", SMALL.to_vec())]),
            plan("new\nline.map", &["--planner", "astar", "--start", "0,0", "--goal", "99,9"]),
            Error("error: new\\u{a}line.map: goal (99, 9) is outside the 3x3 grid\n"),
        ),
        (small(), plan("small.map", &["--planner", "astar", "--start", "x\n,0", "--goal", "2,2"]), Usage("error: invalid value 'x\\u{a},0' for '--start <X,Y>'")),
        (small(), plan("small.map", &["--planner", "astar", "--start", "0,0"]), Error("--start and --goal go together")),
        (small(), plan("small.map", &["--planner", "astar", "--problem", "1", "--start", "0,0", "--goal", "2,2"]), Error("not both")),
        (small(), plan("small.map", &["--planner", "astar", "--problem", "0"]), Error("--problem 0: small.map has 0 problem(s)")),
        (small(), plan("small.map", &["--planner", "astar", "--problem", "-1"]), Usage("unexpected argument '-1'")),
        (small(), plan("small.map", &["--planner", "astar", "--problem", "99999999999999999999999"]), Usage("--problem")),
        (small(), plan("small.map", &["--planner", "astar", "--set", "moves"]), Error("--set \"moves\": expected key=value")),
        (small(), plan("small.map", &["--planner", "astar", "--set", "moves=7"]), Error("planner `astar`: parameter `moves`: unsupported connectivity 7")),
        (small(), plan("small.map", &["--planner", "astar", "--set", "nonsense=1"]), Error("nonsense")),
        (small(), plan("small.map", &["--planner", "astar", "--set", "heuristic=[1,"]), Error("planner `astar`: parameter `heuristic`")),
        (small(), plan("small.map", &["--planner", "astar", "--set", "=3"]), Error("--set \"=3\": expected key=value")),
        // A number TOML cannot hold is said as such, not read as the word "1e400".
        (small(), plan("small.map", &["--planner", "astar", "--set", "weight=1e400"]), Error("--set weight=1e400: not a number (numbers are written as")),
        (small(), plan("small.map", &["--planner", "astar", "--set", "heuristic=octile", "--set", "heuristic=zero"]), Error("--set heuristic: given twice, as octile and as zero")),
        (small(), plan("small.map", &["--planner", "astar", "--max-expansions", "-1"]), Usage("unexpected argument '-1'")),
        (small(), plan("small.map", &["--planner", "astar", "--obstacle", "2"]), Usage("--obstacle")),
        (small(), plan("small.map", &["--planner", "astar", "--obstacle", "1"]), Error("--obstacle 1 applies to .csv maps")),
        (small(), plan("small.map", &["--planner", "coverage", "--start", "0,0", "--goal", "2,2"]), Error("takes no --goal")),
        (small(), plan("small.map", &["--planner", "astar", "--config", "none.toml"]), Error("none.toml: cannot read the config")),
        (small(), plan("small.map", &["--planner", "astar", "--config", "/dev/zero"]), Error("/dev/zero: cannot read the config: not a regular file")),
        (owned(experiment(CONFIG)), plan("small.map", &["--planner", "b", "--config", "c.toml"]), Error("no planner labelled `b` (labels: a)")),
        // A .scen beside the map, for another map size: refused; for another map of the
        // same size: a warning naming both.
        (
            owned(vec![("small.map", SMALL.to_vec()), ("small.map.scen", scen_other)]),
            plan("small.map", &["--planner", "astar", "--problem", "1"]),
            Error("small.map.scen:2:13: the scenario is for a 5x5 map, but small.map is 3x3"),
        ),
        (
            owned(vec![("small.map", SMALL.to_vec()), ("small.map.scen", scen_same)]),
            plan("small.map", &["--planner", "astar", "--problem", "1"]),
            Warn("small.map.scen:2: the scenario names map other.map, not small.map"),
        ),
        // Blocked starts on a .csv map written the other way round: the hint says so.
        (
            owned(vec![("inv.csv", b"0,1,1\n1,1,0\n".to_vec())]),
            plan("inv.csv", &["--planner", "astar"]),
            Error("inv.csv: start (0, 0) is blocked; start (0, 0) and goal (2, 1) are blocked with obstacle = 0 but free with obstacle = 1: the map looks written with 1 = obstacle (--obstacle 1)"),
        ),
        (
            owned(vec![("map.yaml", b"image: map.pgm\nresolution: 0.1\norigin: [0, 0, 0]\nnegate: 0\noccupied_thresh: 0.65\nfree_thresh: 0.196\nmap_name: x\n".to_vec()), ("map.pgm", b"P2 2 2 255 255 255 255 255".to_vec())]),
            plan("map.yaml", &["--planner", "astar"]),
            Warn("map.yaml:7:1: key 'map_name' is not one map_server reads"),
        ),
        // Issue 27: `negate: yes` was read as true without a word; ROS 1's map_server
        // refuses it (an int only), ROS 2's nav2 reads it as true: read as nav2 does, with
        // a warning saying both.
        (
            owned(vec![("map.yaml", b"image: map.pgm\nresolution: 0.1\norigin: [0, 0, 0]\nnegate: yes\noccupied_thresh: 0.65\nfree_thresh: 0.196\n".to_vec()), ("map.pgm", b"P2 2 2 255 0 0 0 0".to_vec())]),
            plan("map.yaml", &["--planner", "astar"]),
            Warn("map.yaml:4:9: 'negate' yes is a boolean: ROS 2's nav2_map_server reads it as true (and so does gridplan), ROS 1's map_server refuses the file; write 1"),
        ),
        // Unknown commands and flags.
        (small(), args(&["plan"]), Usage("required")),
        (small(), args(&["frobnicate"]), Usage("unrecognized subcommand")),
        (small(), plan("small.map", &["--planner", "astar", "--colour"]), Usage("--colour")),
        (small(), args(&["experiment", "missing.toml"]), Error("missing.toml: cannot read the config")),
        (small(), args(&["experiment", "small.map"]), Error("small.map:1:")),
        (small(), args(&["experiment", "/dev/zero"]), Error("not a regular file")),
        (small(), args(&["experiment", "."]), Error("not a regular file (a directory)")),
        (owned(experiment(CONFIG)), args(&["experiment", "c.toml", "--shard", "3/2"]), Error("3/2")),
        (owned(experiment(CONFIG)), args(&["experiment", "c.toml", "--shard", "0/0"]), Error("0/0")),
        // Issue 27: these aborted (an 8 TB allocation) or panicked (capacity overflow).
        (owned(experiment(CONFIG)), args(&["experiment", "c.toml", "--shard", "1/1000000000000"]), Error("--shard: shard 1/1000000000000: at most 1048576 shards")),
        (owned(experiment(CONFIG)), args(&["experiment", "c.toml", "--shard", "1/18446744073709551615"]), Error("--shard: shard 1/18446744073709551615: at most 1048576 shards")),
        (owned(experiment(CONFIG)), args(&["slurm", "c.toml", "--shards", "1000000000000"]), Error("--shards 1000000000000: at most 1048576 shards")),
        // The config has 1 run (the corner problem of small.map x 1 planner): an array of
        // 100000 tasks would be 99999 empty ones, and its merge line 4.4 MB.
        (owned(experiment(CONFIG)), args(&["slurm", "c.toml", "--shards", "100000"]), Error("--shards 100000: the sweep has 1 run(s), so at most 1 shard(s)")),
        // What sbatch would refuse at submission, refused before the scripts are written.
        (owned(experiment(CONFIG)), args(&["slurm", "c.toml", "--shards", "1", "--time", "abc def"]), Error("--time \"abc def\": a time as sbatch takes it")),
        (owned(experiment(CONFIG)), args(&["slurm", "c.toml", "--shards", "1", "--mem", "4 GB"]), Error("--mem \"4 GB\": a whole number of megabytes")),
        (owned(experiment(CONFIG)), args(&["slurm", "c.toml", "--shards", "1", "--partition", ""]), Error("--partition \"\": a value (it is empty)")),
        (owned(experiment(CONFIG)), args(&["slurm", "c.toml", "--shards", "1", "--cpus-per-task", "0"]), Error("--cpus-per-task \"0\": at least 1")),
        (owned(experiment(CONFIG)), args(&["merge", "--shards-in", "nowhere"]), Error("--shards-in nowhere")),
        (owned(experiment(CONFIG)), args(&["merge", "--shards-in", "."]), Error("--shards-in .: no shard-K directories in it")),
        (owned(experiment(CONFIG)), args(&["experiment", "c.toml", "--threads", "100000"]), Error("100000 worker threads")),
        (owned(experiment(CONFIG)), args(&["experiment", "c.toml", "--output", "c.toml"]), Error("c.toml")),
        (owned(experiment(CONFIG)), args(&["merge", "nowhere"]), Error("nowhere")),
        // A chart's x or group that no label has drew an empty chart.
        (owned(experiment(&format!("{CONFIG}[[charts]]\nx = \"wieght\"\ny = \"length\"\n"))), args(&["experiment", "c.toml"]), Error("c.toml:7:1: charts[0]: key `x`: \"wieght\" is no planner parameter of this config's labels (corner_cutting, heuristic, moves, order, tie_break, weight) nor `bucket`")),
        (owned(experiment(&format!("{CONFIG}[[charts]]\nx = \"weight\"\ny = \"length\"\ngroup = \"mapp\"\n"))), args(&["experiment", "c.toml"]), Error("charts[0]: key `group`: \"mapp\" is no planner parameter")),
    ];
    cases.extend(plan_cases);

    // An experiment whose .csv map is written with 1 = obstacle: the run is recorded as
    // invalid with the hint, and the warning says it.
    let inverted = "name = \"inv\"\n[[maps]]\nfiles = [\"inv.csv\"]\nproblems = \"corners\"\n[planners.a]\nplanner = \"astar\"\n";
    cases.push((
        owned(vec![
            ("c.toml", inverted.as_bytes().to_vec()),
            ("inv.csv", b"0,1,1\n1,1,0\n".to_vec()),
        ]),
        args(&exp),
        Warn("the map looks written with 1 = obstacle"),
    ));
    // A ROS map with a key map_server ignores: the experiment warns, naming file and line.
    let ros = "name = \"ros\"\n[[maps]]\nfiles = [\"map.yaml\"]\npairs = [{ start = [0, 0], goal = [1, 1] }]\n[planners.a]\nplanner = \"astar\"\n";
    cases.push((
        owned(vec![
            ("c.toml", ros.as_bytes().to_vec()),
            ("map.yaml", b"image: map.pgm\nresolution: 0.1\norigin: [0, 0, 0]\nnegate: 0\noccupied_thresh: 0.65\nfree_thresh: 0.196\nmap_type: occupancy\n".to_vec()),
            ("map.pgm", b"P2 2 2 255 255 255 255 255".to_vec()),
        ]),
        args(&exp),
        Warn("map.yaml:7:1: key 'map_type' is not one map_server reads"),
    ));

    // A pair outside the grid: recorded as an invalid problem, with a warning naming map,
    // problem and cell (configs/README.md), once, though two labels and two repeats skip it.
    cases.push((
        owned(experiment(&format!(
            "repeats = 2\n{}[planners.b]\nplanner = \"bfs\"\n",
            edit(
                "problems = \"corners\"",
                "pairs = [{ start = [0, 0], goal = [5, 5] }]",
            )
        ))),
        args(&exp),
        Warn("small.map problem 1: goal (5, 5) is outside the 3x3 grid; not run"),
    ));
    // A .scen naming another map file of the same size: used, with a warning naming both.
    let scen = "name = \"sc\"\n[[maps]]\nfiles = [\"small.map\"]\nscen = \"s.scen\"\n[planners.a]\nplanner = \"astar\"\n";
    cases.push((
        owned(vec![
            ("c.toml", scen.as_bytes().to_vec()),
            ("small.map", SMALL.to_vec()),
            (
                "s.scen",
                b"version 1\n0\tother.map\t3\t3\t0\t0\t2\t2\t3.4\n".to_vec(),
            ),
        ]),
        args(&exp),
        Warn("maps[0]: the scenarios name map other.map, not small.map (same size, so used)"),
    ));
    // The same .scen for a 5x5 map: refused at the `scen` key, naming its file and line and both sizes.
    cases.push((
        owned(vec![
            ("c.toml", scen.as_bytes().to_vec()),
            ("small.map", SMALL.to_vec()),
            (
                "s.scen",
                b"version 1\n0\tsmall.map\t5\t5\t0\t0\t2\t2\t3.4\n".to_vec(),
            ),
        ]),
        args(&exp),
        Error("key `scen`: s.scen:2:13: the scenario is for a 5x5 map, but small.map is 3x3"),
    ));
    // A ROS map's points of more than two coordinates, or none.
    for (points, expected) in [
        (
            "points = [{ start = [0.05, 0.05, 9], goal = [0.15, 0.15] }]",
            "c.toml:4:21: key `maps[0].points[0].start`: invalid length 3, expected an array of length 2",
        ),
        (
            "points = []",
            "c.toml:4:10: maps[0]: key `points`: at least one start-goal pair is needed",
        ),
    ] {
        cases.push((
            owned(vec![
                (
                    "c.toml",
                    ros.replace("pairs = [{ start = [0, 0], goal = [1, 1] }]", points)
                        .into_bytes(),
                ),
                ("map.yaml", b"image: map.pgm\nresolution: 0.1\norigin: [0, 0, 0]\nnegate: 0\noccupied_thresh: 0.65\nfree_thresh: 0.196\n".to_vec()),
                ("map.pgm", b"P2 2 2 255 255 255 255 255".to_vec()),
            ]),
            args(&exp),
            Error(expected),
        ));
    }
    // Published numbers dropped without a word: a problem the map does not have (its
    // numbers were counted "0 of 0"), a value that is not a number.
    for (published, expected) in [
        (
            "[\"small#9\".astar]\nsteps = 8\n",
            "p.toml:1:2: `[small#9]`: map `small.map` has 1 problem (`#1` to `#1`)",
        ),
        (
            "[\"small#0\".astar]\nsteps = 8\n",
            "p.toml:1:2: `[small#0]`: map `small.map` has 1 problem",
        ),
        (
            "[\"small#01\".astar]\nsteps = 8\n",
            "p.toml:1:2: `[small#01]`: map `small.map` has 1 problem",
        ),
        (
            "[small.astar]\nsteps = nan\n",
            "p.toml:2:9: `small.astar.steps` must be a number, not NaN",
        ),
        (
            "[small.astar]\nsteps = -inf\n",
            "p.toml:2:9: `small.astar.steps` must be a number, not -inf",
        ),
    ] {
        cases.push((
            owned(vec![
                (
                    "c.toml",
                    format!("published = \"p.toml\"\n{CONFIG}").into_bytes(),
                ),
                ("small.map", SMALL.to_vec()),
                ("p.toml", published.as_bytes().to_vec()),
            ]),
            args(&exp),
            Error(expected),
        ));
    }
    // Scenario selections that select nothing, each named.
    for (selection, expected) in [
        // Said at the key, not at the `[[maps]]` header (2:1); line 0 is no line.
        (
            "lines = [5, 3]",
            "c.toml:5:9: maps[0]: key `lines`: [5, 3] starts after it ends",
        ),
        (
            "lines = [0, 2]",
            "c.toml:5:9: maps[0]: key `lines`: [0, 2]: lines are 1-based",
        ),
        (
            "lines = [2, 3, 4]",
            "c.toml:5:9: key `maps[0].lines`: invalid length 3, expected an array of length 2",
        ),
        (
            "every = 0",
            "c.toml:5:9: maps[0]: key `every` must be at least 1",
        ),
        (
            "buckets = [9]",
            "the scenario selection (`buckets`, `lines`, `every`, `limit`) is empty",
        ),
    ] {
        cases.push((
            owned(vec![
                (
                    "c.toml",
                    scen.replace(
                        "scen = \"s.scen\"\n",
                        &format!("scen = \"s.scen\"\n{selection}\n"),
                    )
                    .into_bytes(),
                ),
                ("small.map", SMALL.to_vec()),
                (
                    "s.scen",
                    b"version 1\n0\tsmall.map\t3\t3\t0\t0\t2\t2\t3.4\n".to_vec(),
                ),
            ]),
            args(&exp),
            Error(expected),
        ));
    }

    let n_cases = cases.len();
    // The cases are independent (each in its own directory), so they run on a few
    // threads: most of a case is the binary starting and reading a tiny file.
    let cases: Vec<(usize, Case)> = cases.into_iter().enumerate().collect();
    let next = std::sync::Mutex::new(cases.into_iter());
    let threads = std::thread::available_parallelism().map_or(2, |n| n.get().clamp(2, 8));
    let mut failures: Vec<(usize, String)> = std::thread::scope(|scope| {
        let workers: Vec<_> = (0..threads)
            .map(|_| {
                scope.spawn(|| {
                    let mut failed = Vec::new();
                    loop {
                        let Some((i, (files, args, expect))) = next.lock().unwrap().next() else {
                            break;
                        };
                        let files: Vec<(&str, &[u8])> = files
                            .iter()
                            .map(|(n, b)| (n.as_str(), b.as_slice()))
                            .collect();
                        let args: Vec<&str> = args.iter().map(String::as_str).collect();
                        if let Some(failure) = check(i, &files, &args, expect) {
                            failed.push((i, failure));
                        }
                    }
                    failed
                })
            })
            .collect();
        workers
            .into_iter()
            .flat_map(|w| w.join().unwrap())
            .collect()
    });
    failures.sort();
    let failures: Vec<String> = failures.into_iter().map(|(_, f)| f).collect();
    assert!(
        failures.is_empty(),
        "{} of {n_cases} cases failed:\n{}",
        failures.len(),
        failures.join("\n")
    );
}

/// A scratch directory holding [`CONFIG`] as `c.toml` and `small.map`.
fn with_config(case: usize) -> PathBuf {
    let dir = scratch(case);
    for (name, bytes) in experiment(CONFIG) {
        std::fs::write(dir.join(name), bytes).unwrap();
    }
    dir
}

/// Issue 27: the largest JOB_COMPLETION_INDEX wrapped to "shard 0/3", an error naming no
/// variable; one past the count is refused naming both variables.
#[test]
fn job_array_environments_are_checked_and_named() {
    let dir = with_config(20_000);
    let exp = ["experiment", "c.toml", "--quiet"];
    for (env, text) in [
        (
            [
                ("JOB_COMPLETION_INDEX", "18446744073709551615"),
                ("GRIDPLAN_SHARD_COUNT", "3"),
            ],
            "JOB_COMPLETION_INDEX=18446744073709551615 (0-based), GRIDPLAN_SHARD_COUNT=3",
        ),
        (
            [
                ("JOB_COMPLETION_INDEX", "0"),
                ("GRIDPLAN_SHARD_COUNT", "1000000000000"),
            ],
            "GRIDPLAN_SHARD_COUNT=1000000000000: shard 1/1000000000000: at most 1048576 shards",
        ),
        (
            [
                ("SLURM_ARRAY_TASK_ID", "18446744073709551615"),
                ("SLURM_ARRAY_TASK_COUNT", "3"),
            ],
            "SLURM_ARRAY_TASK_ID=18446744073709551615",
        ),
    ] {
        let out = gridplan_with(&dir, &exp, &env, Stdio::piped());
        // A job array's environment that names no shard is a usage error (exit 2).
        assert_eq!(out.code, Some(2), "{env:?}: {}", out.stderr);
        assert!(out.stderr.contains(text), "{env:?}: {}", out.stderr);
        assert!(!out.stderr.contains("panicked"), "{}", out.stderr);
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// `merge sh1 sh2 --output sh1` wrote the merged results over shard sh1 ("6 runs merged"),
/// so the shard set could never be merged again. An output that is an input shard (by
/// canonical path, also through a link) or holds one is refused with exit 5, as any output
/// gridplan may not write, before anything is written.
#[cfg(unix)]
#[test]
fn merge_refuses_an_output_that_is_one_of_its_shards() {
    let dir = with_config(20_010);
    shard(&dir, "c.toml", "1/2", "sh1");
    shard(&dir, "c.toml", "2/2", "sh2");
    std::os::unix::fs::symlink("sh1", dir.join("link")).unwrap();
    std::fs::create_dir_all(dir.join("parent")).unwrap();
    std::fs::rename(dir.join("sh2"), dir.join("parent/sh2")).unwrap();
    let before = listing(&dir);
    let stream = std::fs::read(dir.join("sh1/shard.stream")).unwrap();
    for (output, needle) in [
        (
            "sh1",
            "output `sh1` is the shard directory `sh1` given to merge",
        ),
        ("./sh1/", "is the shard directory `sh1`"),
        ("link", "output `link` is the shard directory `sh1`"),
        (
            "parent",
            "output `parent` holds the shard directory `parent/sh2`",
        ),
    ] {
        let out = gridplan(&dir, &["merge", "sh1", "parent/sh2", "--output", output]);
        refused(&out, 5, needle);
        assert_eq!(listing(&dir), before, "--output {output}");
        assert_eq!(std::fs::read(dir.join("sh1/shard.stream")).unwrap(), stream);
    }
    succeeded(&gridplan(
        &dir,
        &["merge", "sh1", "parent/sh2", "--output", "m"],
    ));
}

/// `plan X.map` without a start fell back to the corner problem when `X.map.scen` was
/// there but not a regular file (a FIFO, a directory, a link loop, a dangling link): only
/// a missing `.scen` may fall back; anything else there is an error naming it (exit 4, as
/// an experiment refuses the same file), and a FIFO is not opened (no hang).
#[cfg(unix)]
#[test]
fn plan_refuses_a_scen_that_is_not_a_file() {
    let dir = with_config(20_011);
    let scen = dir.join("small.map.scen");
    let plan = ["plan", "small.map", "--planner", "astar"];
    // No .scen: the corner problem, as before.
    succeeded(&gridplan(&dir, &plan));
    let fifo = |path: &Path| {
        let made = Command::new("mkfifo").arg(path).status().unwrap();
        assert!(made.success());
    };
    let directory = |path: &Path| std::fs::create_dir(path).unwrap();
    let dangling = |path: &Path| std::os::unix::fs::symlink("nowhere.scen", path).unwrap();
    let looped = |path: &Path| std::os::unix::fs::symlink("small.map.scen", path).unwrap();
    for make in [&fifo as &dyn Fn(&Path), &directory, &dangling, &looped] {
        make(&scen);
        let out = gridplan(&dir, &plan);
        refused(&out, 4, "small.map.scen");
        if std::fs::symlink_metadata(&scen).unwrap().is_dir() {
            std::fs::remove_dir(&scen).unwrap();
        } else {
            std::fs::remove_file(&scen).unwrap();
        }
    }
}

/// Issue 27: `merge` of a shard whose stream is a link to /dev/zero aborted (a 2 GB
/// allocation) and a FIFO hung; `--resume` on either did the same. Both are refused as
/// not regular files, at once.
#[cfg(unix)]
#[test]
fn stream_readers_refuse_special_files() {
    let dir = with_config(20_001);
    shard(&dir, "c.toml", "1/2", "s1");
    let shard = dir.join("s1/shard.stream");
    let fifo = |path: &Path| {
        let _ = std::fs::remove_file(path);
        let made = Command::new("mkfifo").arg(path).status().unwrap();
        assert!(made.success());
    };
    let zero = |path: &Path| {
        let _ = std::fs::remove_file(path);
        std::os::unix::fs::symlink("/dev/zero", path).unwrap();
    };
    for (make, what) in [
        (&zero as &dyn Fn(&Path), "a character device"),
        (&fifo as &dyn Fn(&Path), "a FIFO"),
    ] {
        make(&shard);
        let out = gridplan(&dir, &["merge", "s1", "--output", "m"]);
        refused(&out, 1, &format!("not a regular file ({what})"));
    }
    // The stream a sweep on output `r` appends to, and --resume reads: `.r.stream/records.jsonl`.
    // The area carries gridplan's marker, as a killed sweep leaves it (issue 26: an
    // unmarked one is refused before its records are read).
    std::fs::create_dir_all(dir.join(".r.stream")).unwrap();
    std::fs::write(
        dir.join(".r.stream/.gridplan-stream"),
        "# Written by gridplan\n",
    )
    .unwrap();
    // A link there (to /dev/zero) is refused as a link before anything reads it (exit 5,
    // as the lock files' links); a FIFO is not a regular file.
    let records = dir.join(".r.stream/records.jsonl");
    for (make, code, what) in [
        (
            &zero as &dyn Fn(&Path),
            5,
            "records.jsonl` is a symbolic link; gridplan does not follow links",
        ),
        (
            &fifo as &dyn Fn(&Path),
            1,
            "records.jsonl: not a regular file (a FIFO)",
        ),
    ] {
        make(&records);
        let resume = [
            "experiment",
            "c.toml",
            "--quiet",
            "--resume",
            "--output",
            "r",
        ];
        let out = gridplan(&dir, &resume);
        refused(&out, code, what);
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// A pipe whose reading end is already closed, as the writing end for a child's stdout.
#[cfg(unix)]
#[allow(unsafe_code)]
fn closed_pipe() -> Stdio {
    use std::os::fd::FromRawFd as _;
    let mut fds = [0; 2];
    // SAFETY: pipe(2) fills the two descriptors; the reading one is closed at once and the
    // writing one is owned by the returned value alone.
    unsafe {
        assert_eq!(libc::pipe(fds.as_mut_ptr()), 0);
        libc::close(fds[0]);
        Stdio::from(std::os::fd::OwnedFd::from_raw_fd(fds[1]))
    }
}

/// Issue 27: with stdout a pipe whose reader has gone, `planners`, `plan --json` and
/// `experiment` panicked ("failed printing to stdout: Broken pipe", exit 101). The rule
/// (README): a closed pipe ends the command quietly with status 0, as `head`-style
/// pipelines expect; any other stdout error (a full disk) is an error, status 1. The same
/// for `--help` and `--version` (`>/dev/full` gave status 0 and no message).
#[cfg(unix)]
#[test]
fn a_closed_stdout_ends_quietly() {
    let dir = with_config(20_002);
    let plan = [
        "plan",
        "small.map",
        "--planner",
        "astar",
        "--start",
        "0,0",
        "--goal",
        "2,2",
        "--json",
    ];
    let commands: [&[&str]; 7] = [
        &["planners"],
        &["planners", "astar"],
        &plan,
        &["experiment", "c.toml", "--quiet", "--output", "out"],
        // clap's answers too: they were printed with their write errors ignored (exit 0
        // on a full disk).
        &["--help"],
        &["plan", "--help"],
        &["--version"],
    ];
    for args in commands {
        let out = gridplan_with(&dir, args, &[], closed_pipe());
        assert_eq!(out.code, Some(0), "{args:?}: {}", out.stderr);
        assert_eq!(out.stderr, "", "{args:?}");
        let full = std::fs::OpenOptions::new()
            .write(true)
            .open("/dev/full")
            .unwrap();
        let out = gridplan_with(&dir, args, &[], Stdio::from(full));
        assert_eq!(out.code, Some(1), "{args:?}: {}", out.stderr);
        assert!(
            out.stderr.contains("error: cannot write to stdout"),
            "{args:?}: {}",
            out.stderr
        );
        assert!(!out.stderr.contains("panicked"), "{}", out.stderr);
    }
    // The sweep's results were written before the closed pipe was found.
    assert!(dir.join("out/runs.csv").is_file());
    let _ = std::fs::remove_dir_all(&dir);
}

/// Issue 27: `slurm --shards N` wrote a merge job with N shard paths on its command line
/// (4.4 MB for N = 100000, over the argument limit). The merge job now names the
/// directory (`merge --shards-in`): its script has the same size for any N. The scripts
/// run here with bash, as Slurm would, task by task.
#[cfg(unix)]
#[test]
fn slurm_scripts_merge_with_a_bounded_command_line() {
    let dir = scratch(20_003);
    let config = CONFIG.replace("name = \"c\"", "name = \"c\"\nrepeats = 1000");
    std::fs::write(dir.join("c.toml"), config).unwrap();
    std::fs::write(dir.join("small.map"), SMALL).unwrap();
    let slurm = |n: &str| {
        let out = gridplan(
            &dir,
            &["slurm", "c.toml", "--shards", n, "--output", "merged"],
        );
        succeeded(&out);
        std::fs::read_to_string(dir.join("merged-slurm/merge.sbatch")).unwrap()
    };
    // 1 problem x 1000 repeats: 1000 runs, so 1000 shards are allowed.
    let wide = slurm("1000");
    assert!(wide.len() < 1024, "{} bytes:\n{wide}", wide.len());
    assert!(wide.contains(" merge --shards-in "), "{wide}");
    let narrow = slurm("3");
    // N is written twice: in the comment and as `--shards N`.
    assert_eq!(wide.len(), narrow.len() + 2 * 3, "{wide}\n{narrow}");
    let merge = run_slurm_scripts(&dir.join("merged-slurm"), &dir, 3);
    succeeded(&merge);
    let stdout = merge.stdout;
    // After the line each start writes first.
    assert!(
        stdout.contains("\n1000 runs merged from 3 shards"),
        "{stdout}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// `slurm` again with fewer shards on the same output left the earlier array's `shard-3`
/// beside the new `shard-1` and `shard-2`, and the merge job, which took every `shard-K`
/// there, failed after every task ("shards of different sweeps"). It merges exactly the
/// N shards of its own array now, and leaves the stale directory alone. Since the tasks
/// always resume, `slurm` refuses the earlier array's `shard-1` and `shard-2` (shards of
/// 3), naming them, until they are moved away.
#[cfg(unix)]
#[test]
fn slurm_again_with_fewer_shards_merges_its_own() {
    let dir = scratch(20_004);
    let config = CONFIG.replace("name = \"c\"", "name = \"c\"\nrepeats = 6");
    std::fs::write(dir.join("c.toml"), config).unwrap();
    std::fs::write(dir.join("small.map"), SMALL).unwrap();
    let work = dir.join("sl-slurm");
    for n in [3, 2] {
        let args = [
            "slurm",
            "c.toml",
            "--shards",
            &n.to_string(),
            "--output",
            "sl",
        ];
        if n == 2 {
            let before = listing(&dir);
            refused(
                &gridplan(&dir, &args),
                2,
                "holds the records of shard 1 of 3 (an earlier `slurm` of this output with --shards 3), not of shard 1 of 2",
            );
            assert_eq!(listing(&dir), before, "nothing written or removed");
            std::fs::create_dir_all(dir.join("earlier")).unwrap();
            for k in [1, 2] {
                let name = format!("shard-{k}");
                std::fs::rename(work.join(&name), dir.join("earlier").join(&name)).unwrap();
            }
        }
        succeeded(&gridplan(&dir, &args));
        let merge = run_slurm_scripts(&work, &dir, n);
        succeeded(&merge);
        assert!(
            merge
                .stdout
                .contains(&format!("6 runs merged from {n} shards")),
            "{}",
            merge.stdout
        );
    }
    assert!(
        work.join("shard-3").is_dir(),
        "the earlier array's shard stays"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// A Slurm array task that failed, timed out or was cancelled could not be resumed:
/// the array script passed `--resume` only to a task Slurm requeued
/// (`SLURM_RESTART_COUNT`), so submitting the same `slurm` command again ran every shard
/// from scratch and discarded the runs already recorded (a probe lost 164,910: its
/// `.shard-1.stream` shrank from 1.4 MB to 243 KB), and finished shards ran again. The
/// script always passes `--resume` now: task 1, stopped by SIGTERM (`scancel`, a time
/// limit) and started again, keeps its recorded runs byte for byte and runs the others;
/// started once more after it finished, it runs nothing and leaves `shard-1` as it is
/// (provenance included); each start says its date, job, task and restart first; and the
/// merge equals a serial run. The scripts run here with bash, as Slurm would.
#[cfg(unix)]
#[test]
fn a_stopped_slurm_task_started_again_keeps_its_runs() {
    let dir = scratch(20_005);
    let maps = common::root().join("maps/movingai");
    let config = format!(
        "name = \"resumed\"\nrepeats = 12\nfigures = \"none\"\n[[maps]]\nfiles = [{:?}]\n\
         scen = {:?}\n[planners.dijkstra]\nplanner = \"astar\"\nmoves = 8\nheuristic = \"zero\"\n",
        maps.join("den520d.map").display().to_string(),
        maps.join("den520d.map.scen").display().to_string(),
    );
    std::fs::write(dir.join("c.toml"), config).unwrap();
    let args = [
        "slurm",
        "c.toml",
        "--shards",
        "2",
        "--output",
        "res",
        "--cpus-per-task",
        "1",
    ];
    succeeded(&gridplan(&dir, &args));
    let work = dir.join("res-slurm");
    let task = |k: u32, job: &str| {
        let mut command = Command::new("bash");
        command
            .arg(work.join("array.sbatch"))
            .current_dir(&dir)
            .env("SLURM_ARRAY_TASK_ID", k.to_string())
            .env("SLURM_JOB_ID", job)
            .env_remove("SLURM_RESTART_COUNT")
            .stdin(Stdio::null())
            .stdout(Stdio::piped())
            .stderr(Stdio::piped());
        command.spawn().unwrap()
    };
    // Task 1 is stopped once its stream holds some runs.
    let stream = work.join(".shard-1.stream/records.stream");
    let mut child = task(1, "71");
    let started = Instant::now();
    while std::fs::metadata(&stream).map_or(0, |m| m.len()) < 20_000 {
        assert!(
            child.try_wait().unwrap().is_none(),
            "task 1 ended before it could be stopped"
        );
        assert!(
            started.elapsed() < Duration::from_secs(60),
            "no runs recorded"
        );
        std::thread::sleep(Duration::from_millis(5));
    }
    assert!(signal_and_wait(&mut child, "TERM", Duration::from_secs(60)));
    let stopped = common::finish(child, "task 1");
    assert_eq!(stopped.code, Some(130), "{}", stopped.describe());
    assert!(
        stopped
            .stdout
            .contains(" start: job 71, array task 1, restart 0"),
        "{}",
        stopped.describe()
    );
    let recorded = std::fs::read(&stream).unwrap();
    // Started again (the same command submitted again): the runs are kept, not rerun.
    let again = common::finish(task(1, "72"), "task 1 again");
    succeeded(&again);
    assert!(
        again
            .stdout
            .contains(" start: job 72, array task 1, restart 0"),
        "{}",
        again.describe()
    );
    let resumed = again
        .stderr
        .lines()
        .find_map(|l| l.strip_prefix("resuming: "))
        .unwrap_or_else(|| panic!("task 1 did not resume: {}", again.describe()));
    assert!(
        resumed.ends_with(" of 5328 runs already recorded"),
        "{resumed}"
    );
    let kept: u64 = resumed.split(' ').next().unwrap().parse().unwrap();
    assert!(kept > 0 && kept < 5328, "{resumed}");
    let shard = std::fs::read(work.join("shard-1/shard.stream")).unwrap();
    assert!(
        shard.len() > recorded.len() && shard.starts_with(&recorded),
        "the recorded runs were not kept as they were"
    );
    succeeded(&common::finish(task(2, "73"), "task 2"));
    // Started once more after it finished: nothing runs, nothing is rewritten.
    let files = |k: u32| {
        let mut files = std::collections::BTreeMap::new();
        let mut todo = vec![work.join(format!("shard-{k}"))];
        while let Some(at) = todo.pop() {
            for entry in std::fs::read_dir(at).unwrap() {
                let path = entry.unwrap().path();
                match path.is_dir() {
                    true => todo.push(path),
                    false => drop(files.insert(path.clone(), std::fs::read(&path).unwrap())),
                }
            }
        }
        files
    };
    let finished = files(1);
    std::thread::sleep(Duration::from_millis(1100));
    let once_more = common::finish(task(1, "74"), "task 1 once more");
    succeeded(&once_more);
    assert!(
        once_more
            .stderr
            .contains("resuming: 5328 of 5328 runs already recorded"),
        "{}",
        once_more.describe()
    );
    assert!(files(1) == finished, "the finished shard was rewritten");
    assert!(!work.join(".shard-1.stream").exists());
    let merge = common::finish(
        Command::new("bash")
            .arg(work.join("merge.sbatch"))
            .current_dir(&dir)
            .env("SLURM_JOB_ID", "75")
            .stdin(Stdio::null())
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .unwrap(),
        "merge",
    );
    succeeded(&merge);
    assert!(
        merge.stdout.contains(" start: job 75, "),
        "{}",
        merge.describe()
    );
    let serial = ["experiment", "c.toml", "--quiet", "--output", "serial"];
    succeeded(&gridplan(&dir, &serial));
    let compared = gridplan(&dir, &["compare", "serial", "res"]);
    succeeded(&compared);
    assert!(
        compared
            .stdout
            .contains("the same in all 10656 runs in both"),
        "{}",
        compared.describe()
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// A running `plan` (Backtracking on an open 30x30 map, which would run for hours) in a
/// fresh directory numbered `case`, its SIGINT disposition set in the child before it
/// starts: `ignored` as a `nohup`-style launcher or `trap '' INT` leaves it, else the
/// default, whatever this test inherited.
#[cfg(unix)]
#[allow(unsafe_code)]
fn running_plan(case: usize, ignored: bool) -> (PathBuf, std::process::Child) {
    use std::os::unix::process::CommandExt as _;
    let dir = scratch(case);
    let rows = format!("{}\n", ".".repeat(30)).repeat(30);
    std::fs::write(
        dir.join("open.map"),
        format!("type octile\nheight 30\nwidth 30\nmap\n{rows}"),
    )
    .unwrap();
    let disposition = if ignored {
        libc::SIG_IGN
    } else {
        libc::SIG_DFL
    };
    let mut command = Command::new(env!("CARGO_BIN_EXE_gridplan"));
    command
        .args([
            "plan",
            "open.map",
            "--planner",
            "backtracking",
            "--max-expansions",
            "100000000000000",
        ])
        .current_dir(&dir)
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped());
    // SAFETY: signal(2) is async-signal-safe, as code between fork and exec must be.
    unsafe {
        command.pre_exec(move || {
            libc::signal(libc::SIGINT, disposition);
            Ok(())
        });
    }
    let child = command.spawn().unwrap();
    // Long enough for the map to be read and the search to run.
    std::thread::sleep(Duration::from_millis(1500));
    (dir, child)
}

/// Sends `signal` (`INT`, `TERM`) to `child` and waits at most `wait` for it to end.
fn signal_and_wait(child: &mut std::process::Child, signal: &str, wait: Duration) -> bool {
    let status = Command::new("kill")
        .args([&format!("-{signal}"), &child.id().to_string()])
        .status()
        .unwrap();
    assert!(status.success());
    let started = Instant::now();
    while child.try_wait().unwrap().is_none() {
        if started.elapsed() > wait {
            return false;
        }
        std::thread::sleep(Duration::from_millis(20));
    }
    true
}

/// Ctrl-C on a running `plan` prints "interrupted" and exits with 130, also when the test
/// itself runs with SIGINT ignored (`(trap '' INT; cargo test)`): the child's disposition
/// is set to the default before it starts.
#[cfg(unix)]
#[test]
fn plan_stops_on_ctrl_c() {
    let (dir, mut child) = running_plan(10_000, false);
    assert!(child.try_wait().unwrap().is_none(), "plan ended early");
    if !signal_and_wait(&mut child, "INT", Duration::from_secs(30)) {
        child.kill().unwrap();
        panic!("plan did not stop within 30 s of SIGINT");
    }
    let output = child.wait_with_output().unwrap();
    let _ = std::fs::remove_dir_all(&dir);
    assert_eq!(output.status.code(), Some(130));
    assert_eq!(String::from_utf8_lossy(&output.stderr), "interrupted\n");
    assert!(output.stdout.is_empty());
}

/// Ctrl-C on a running replanning experiment (`kind = "navigate"`) stops it after the runs
/// in progress: exit 130, "interrupted", no output written and no working files left
/// beside it (the tables it was writing there). Before, the signal killed it mid-write.
#[cfg(unix)]
#[test]
#[allow(unsafe_code)]
fn a_replanning_experiment_stops_on_ctrl_c() {
    use std::os::unix::process::CommandExt as _;
    let dir = scratch(10_002);
    common::write_navigate_config(&dir, "den520d", "1, 5", 800);
    let mut command = Command::new(env!("CARGO_BIN_EXE_gridplan"));
    command
        .args(["experiment", "nav.toml", "--output", "out"])
        .current_dir(&dir)
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped());
    // SAFETY: signal(2) is async-signal-safe, as code between fork and exec must be.
    unsafe {
        command.pre_exec(|| {
            libc::signal(libc::SIGINT, libc::SIG_DFL);
            Ok(())
        });
    }
    let mut child = command.spawn().unwrap();
    // Long enough for the maps to be read and the first runs' tables to be written.
    std::thread::sleep(Duration::from_millis(2500));
    assert!(
        child.try_wait().unwrap().is_none(),
        "the experiment ended early"
    );
    if !signal_and_wait(&mut child, "INT", Duration::from_secs(30)) {
        child.kill().unwrap();
        panic!("the experiment did not stop within 30 s of SIGINT");
    }
    let output = child.wait_with_output().unwrap();
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(130), "{stderr}");
    assert!(
        stderr.contains("interrupted: no results were written, out is as it was"),
        "{stderr}"
    );
    let left: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    assert_eq!(left, ["nav.toml"], "left beside the output");
    let _ = std::fs::remove_dir_all(&dir);
}

/// The rule for a SIGINT inherited ignored (README, `--help`): it stays ignored, the POSIX
/// convention; SIGTERM still stops the command.
#[cfg(unix)]
#[test]
fn an_inherited_ignored_sigint_stays_ignored() {
    let (dir, mut child) = running_plan(10_001, true);
    assert!(child.try_wait().unwrap().is_none(), "plan ended early");
    let ended = signal_and_wait(&mut child, "INT", Duration::from_secs(2));
    if ended {
        let output = child.wait_with_output().unwrap();
        panic!("plan ended on an ignored SIGINT: {output:?}");
    }
    if !signal_and_wait(&mut child, "TERM", Duration::from_secs(30)) {
        child.kill().unwrap();
        panic!("plan did not stop within 30 s of SIGTERM");
    }
    let output = child.wait_with_output().unwrap();
    let _ = std::fs::remove_dir_all(&dir);
    assert_eq!(output.status.code(), Some(130));
    assert_eq!(String::from_utf8_lossy(&output.stderr), "interrupted\n");
}

/// Issue 27: a valid 20000 x 20000 PNG (a 1 km square at 5 cm) was refused at a fixed
/// 2^28-cell limit. Within `--max-memory-mb 6000` (A* declares 13.125 bytes a cell for
/// its arrays at full size, 5.3 GB here, allocated zeroed and committed only where the
/// search goes), A* plans a 10-step query on it, and the process's peak resident memory
/// stays under 1 GB: the grid is one byte a cell (400 MB), the decoded pixels become the
/// occupancy values in place (400 MB more while the map is read), the search touches a
/// few pages. Unoptimised it takes minutes, so it runs on the release profile, as CI does
/// (`cargo test --release -p gridplan --test it -- --ignored careless::`).
#[cfg(target_os = "linux")]
#[allow(unsafe_code)]
#[test]
#[ignore = "minutes unoptimised; CI runs it on the release profile"]
// The child is reaped by wait4, which reports its own peak RSS, not by Child::wait.
#[allow(clippy::zombie_processes)]
fn a_20000_square_png_plans_within_the_memory_budget() {
    let dir = scratch(20_004);
    let side = 20_000u32;
    {
        let file = std::io::BufWriter::new(std::fs::File::create(dir.join("big.png")).unwrap());
        let mut encoder = png::Encoder::new(file, side, side);
        encoder.set_color(png::ColorType::Grayscale);
        encoder.set_depth(png::BitDepth::One);
        let mut writer = encoder
            .write_header()
            .unwrap()
            .into_stream_writer()
            .unwrap();
        // White (free) rows, with a wall across row 1 but for its last cell, so the
        // path from (0, 0) to (10, 0) is 10 steps along row 0 either way.
        let white = vec![0xffu8; side as usize / 8];
        let mut wall = vec![0u8; side as usize / 8];
        *wall.last_mut().unwrap() = 1;
        use std::io::Write as _;
        for y in 0..side {
            writer
                .write_all(if y == 1 { &wall } else { &white })
                .unwrap();
        }
        writer.finish().unwrap();
    }
    let child = Command::new(env!("CARGO_BIN_EXE_gridplan"))
        .args([
            "plan",
            "big.png",
            "--planner",
            "astar",
            "--start",
            "0,0",
            "--goal",
            "10,0",
            "--max-memory-mb",
            "6000",
            "--json",
        ])
        .current_dir(&dir)
        .env_remove("RUST_LOG")
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let pid = child.id() as libc::pid_t;
    let output = {
        use std::io::Read as _;
        let (mut stdout, mut stderr) = (child.stdout.unwrap(), child.stderr.unwrap());
        let err = std::thread::spawn(move || {
            let mut text = String::new();
            stderr.read_to_string(&mut text).unwrap();
            text
        });
        let mut out = String::new();
        stdout.read_to_string(&mut out).unwrap();
        (out, err.join().unwrap())
    };
    // The child's own resource use: wait4 reaps it and reports its peak RSS (KiB).
    let mut status = 0;
    // SAFETY: a zeroed rusage is a valid value for wait4 to fill; `pid` is our child,
    // reaped here once (std's Child was consumed above without waiting).
    let usage = unsafe {
        let mut usage: libc::rusage = std::mem::zeroed();
        assert_eq!(libc::wait4(pid, &mut status, 0, &mut usage), pid);
        usage
    };
    let _ = std::fs::remove_dir_all(&dir);
    assert!(
        libc::WIFEXITED(status) && libc::WEXITSTATUS(status) == 0,
        "{}",
        output.1
    );
    let json: serde_json::Value = serde_json::from_str(&output.0).unwrap();
    assert_eq!(json["status"], "found", "{json}");
    assert_eq!(json["metrics"]["steps"], 10, "{json}");
    let peak_mb = usage.ru_maxrss / 1024;
    eprintln!("plan on a 20000 x 20000 PNG: peak RSS {peak_mb} MiB");
    assert!(peak_mb < 1000, "peak RSS {peak_mb} MiB");
}

/// SIGTERM (and Ctrl-C) stop `serve` with "interrupted" and status 130, as `--help` says of
/// every command (it was killed by the signal: status 143).
#[cfg(unix)]
#[test]
fn serve_stops_on_sigterm_with_130() {
    use std::io::BufRead as _;
    use std::os::unix::process::ExitStatusExt as _;
    let dir = scratch(10_100);
    std::fs::copy(
        common::root().join("maps/paper/map01.map"),
        dir.join("map01.map"),
    )
    .unwrap();
    let mut child = Command::new(env!("CARGO_BIN_EXE_gridplan"))
        .args(["serve", ".", "--port", "0"])
        .current_dir(&dir)
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    // Serving once its address is printed.
    let mut line = String::new();
    let stdout = child.stdout.take().unwrap();
    std::io::BufReader::new(stdout)
        .read_line(&mut line)
        .unwrap();
    assert!(line.starts_with("serving "), "{line}");
    assert!(signal_and_wait(&mut child, "TERM", Duration::from_secs(20)));
    let status = child.wait().unwrap();
    assert_eq!((status.code(), status.signal()), (Some(130), None));
    let mut err = String::new();
    std::io::Read::read_to_string(&mut child.stderr.take().unwrap(), &mut err).unwrap();
    assert!(err.contains("interrupted"), "{err}");
}

/// `dir/c.toml`: arena.map's 160 scenarios times `repeats` of A* (configs/bench's
/// arena-repeats with more repeats), a sweep that runs for a while.
fn arena_sweep(dir: &Path, repeats: u32) {
    let maps = common::root().join("maps/movingai");
    std::fs::write(
        dir.join("c.toml"),
        format!(
            "name = \"arena\"\nrepeats = {repeats}\nfigures = \"none\"\n[[maps]]\nfiles = [{:?}]\n\
             scen = {:?}\n[planners.octile]\nplanner = \"astar\"\nmoves = 8\nheuristic = \"octile\"\n",
            maps.join("arena.map").display().to_string(),
            maps.join("arena.map.scen").display().to_string(),
        ),
    )
    .unwrap();
}

/// GNU `timeout -s INT` signals the child and then its process group, which may arrive as
/// two SIGINTs a moment apart: the second was taken as "interrupt again" and the sweep quit
/// at once ("interrupted", its runs in progress abandoned, no `--resume` line). A signal
/// within a second of the first is now the same stop.
#[cfg(unix)]
#[test]
#[allow(unsafe_code)]
fn a_signal_delivered_twice_stops_a_sweep_once() {
    use std::os::unix::process::CommandExt as _;
    let dir = scratch(20_020);
    // Runs of a few seconds each (Backtracking on an open map, stopped by its budget), so
    // that the second signal comes while the first one's stop is still under way.
    let rows = format!("{}\n", ".".repeat(30)).repeat(30);
    std::fs::write(
        dir.join("open.map"),
        format!("type octile\nheight 30\nwidth 30\nmap\n{rows}"),
    )
    .unwrap();
    std::fs::write(
        dir.join("c.toml"),
        "name = \"slow\"\nrepeats = 10\n[budget]\nmax_expansions = 600000000\n[[maps]]\n\
         files = [\"open.map\"]\nproblems = \"corners\"\n[planners.b]\nplanner = \"backtracking\"\n",
    )
    .unwrap();
    // The two deliveries a few milliseconds apart: the sweep has not ended by the second
    // (before, one gap or another quit at once).
    for gap in [0, 1, 2, 5, 10, 20] {
        let mut command = Command::new(env!("CARGO_BIN_EXE_gridplan"));
        command
            .args(["experiment", "c.toml", "--threads", "2", "--output", "out"])
            .current_dir(&dir)
            .env_remove("RUST_LOG")
            .stdin(Stdio::null())
            .stdout(Stdio::piped())
            .stderr(Stdio::piped());
        // SAFETY: signal(2) is async-signal-safe, as code between fork and exec must be.
        unsafe {
            command.pre_exec(|| {
                libc::signal(libc::SIGINT, libc::SIG_DFL);
                Ok(())
            });
        }
        let mut child = command.spawn().unwrap();
        std::thread::sleep(Duration::from_millis(1200));
        assert!(child.try_wait().unwrap().is_none(), "the sweep ended early");
        let pid = libc::pid_t::try_from(child.id()).unwrap();
        // SAFETY: kill(2) only sends a signal; the child is not waited for yet, so its pid
        // is still its own (a zombie at worst).
        unsafe {
            assert_eq!(libc::kill(pid, libc::SIGINT), 0);
            std::thread::sleep(Duration::from_millis(gap));
            libc::kill(pid, libc::SIGINT);
        }
        let out = common::finish(child, "the twice-signalled sweep");
        assert_eq!(out.code, Some(130), "gap {gap} ms: {}", out.describe());
        assert!(
            out.stderr.contains(
                "stopping: cancelling the runs in progress; finished runs are kept \
                 (interrupt again to quit at once)"
            ) && out.stderr.contains("rerun with --resume"),
            "gap {gap} ms: {}",
            out.describe()
        );
        assert!(
            !out.stderr.lines().any(|line| line == "interrupted"),
            "gap {gap} ms: the second delivery quit at once: {}",
            out.describe()
        );
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// With stderr not a terminal (a Slurm log, `nohup`, `2> file`) a sweep showed no progress
/// at all until its last line. It prints a plain line now and then (every 30 s; here every
/// millisecond, by the tests' `GRIDPLAN_PROGRESS_LINE_MS`), with no carriage return or
/// escape code; `--quiet` prints none.
#[test]
fn a_sweep_without_a_terminal_prints_progress_lines() {
    let dir = scratch(20_021);
    arena_sweep(&dir, 100);
    let every = [("GRIDPLAN_PROGRESS_LINE_MS", "1")];
    let args = ["experiment", "c.toml", "--threads", "2", "--output", "out"];
    let out = gridplan_with(&dir, &args, &every, Stdio::piped());
    succeeded(&out);
    let lines: Vec<&str> = out
        .stderr
        .lines()
        .filter(|line| line.starts_with("progress: "))
        .collect();
    assert!(!lines.is_empty(), "no progress line: {}", out.describe());
    let shape = |line: &str| {
        let rest = line.strip_prefix("progress: ")?;
        let (done, rest) = rest.split_once(" of 16000 runs (")?;
        let (percent, seconds) = rest.split_once(" %), ")?;
        let done: u64 = done.parse().ok()?;
        let percent: u64 = percent.parse().ok()?;
        (done < 16_000 && percent == done * 100 / 16_000 && seconds.ends_with(" s")).then_some(())
    };
    for line in &lines {
        assert!(shape(line).is_some(), "{line:?}");
    }
    assert!(!out.stderr.contains(['\r', '\u{1b}']), "{:?}", out.stderr);
    let quiet = [&args[..], &["--quiet"]].concat();
    let out = gridplan_with(&dir, &quiet, &every, Stdio::piped());
    succeeded(&out);
    assert!(!out.stderr.contains("progress"), "{}", out.describe());
    let _ = std::fs::remove_dir_all(&dir);
}

/// The shell completions completed `plan --planner`, `--cost-rule`, `--obstacle`,
/// `planners NAME` and `completions SHELL` with file names (bash, zsh) or nothing: they
/// offer the registry's planners and the fixed values.
#[test]
fn completions_offer_planners_and_fixed_values() {
    let dir = scratch(20_022);
    let script = |shell: &str| {
        let out = gridplan(&dir, &["completions", shell]);
        succeeded(&out);
        out.stdout
    };
    for shell in ["bash", "zsh", "fish"] {
        let text = script(shell);
        for name in ["astar", "dstar_lite", "weighted_jps", "entered"] {
            assert!(text.contains(name), "{shell} lacks {name}");
        }
    }
    // What bash offers, the script sourced and its function called as bash would.
    let bash_script = dir.join("gridplan.bash");
    std::fs::write(&bash_script, script("bash")).unwrap();
    let complete = |words: &str| {
        let program = format!(
            "source {:?}; COMP_WORDS=({words} ''); COMP_CWORD=$((${{#COMP_WORDS[@]}} - 1)); \
             _gridplan gridplan '' \"${{COMP_WORDS[COMP_CWORD-1]}}\"; echo \"${{COMPREPLY[*]}}\"",
            bash_script.display().to_string()
        );
        let out = Command::new("bash").args(["-c", &program]).output().ok()?;
        Some(String::from_utf8_lossy(&out.stdout).trim().to_string())
    };
    let names: Vec<&str> = planner_registry::PLANNERS.iter().map(|e| e.name).collect();
    for (words, wanted) in [
        ("gridplan plan --planner", names.clone()),
        ("gridplan planners", names.clone()),
        ("gridplan plan --cost-rule", vec!["mean", "entered"]),
        ("gridplan plan --obstacle", vec!["0", "1"]),
        ("gridplan completions", vec!["bash", "fish", "zsh"]),
    ] {
        let Some(offered) = complete(words) else {
            eprintln!("skipped: no bash to ask");
            break;
        };
        let offered: Vec<&str> = offered.split(' ').collect();
        for word in wanted {
            assert!(
                offered.contains(&word),
                "{words} <TAB> lacks {word}: {offered:?}"
            );
        }
    }
    // What fish offers, asked of fish itself when it is installed.
    let fish_script = dir.join("gridplan.fish");
    std::fs::write(&fish_script, script("fish")).unwrap();
    for (line, wanted) in [
        ("gridplan completions ", "zsh"),
        ("gridplan planners ", "dstar_lite"),
        ("gridplan plan --planner ", "weighted_jps"),
    ] {
        let program = format!(
            "source {:?}; complete -C {line:?}",
            fish_script.display().to_string()
        );
        let Ok(out) = Command::new("fish").args(["-c", &program]).output() else {
            eprintln!("skipped: no fish to ask");
            break;
        };
        let offered = String::from_utf8_lossy(&out.stdout);
        assert!(
            offered
                .lines()
                .any(|l| l.split('\t').next() == Some(wanted)),
            "fish {line:?} lacks {wanted}: {offered}"
        );
    }
    let _ = std::fs::remove_dir_all(&dir);
}
