//! Security and data loss through the real `gridplan` binary (issue 26): config and option
//! values never run as commands in the Slurm scripts (run by bash here, and submitted to a
//! real Slurm when one answers, as in CI's `== slurm` block), report.html holds no live
//! script, lock files planted as links are refused with their target untouched, a foreign
//! stream directory survives, records of another config or gridplan version are refused
//! by merge and --resume, and distinct maps and labels never share an output file, every
//! SVG is well-formed XML and summary.md's tables keep their columns, and no control
//! sequence in config text reaches the terminal.

use std::fs;
use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::{Duration, Instant};

use crate::common::{self, gridplan, refused, run_slurm_scripts, shard, succeeded, SMALL};

fn scratch(name: &str) -> PathBuf {
    common::scratch("security", name)
}

/// The documented exit status of a failure that is none of the classes below.
const FAILURE: i32 = 1;
/// The documented exit status of arguments that do not fit (a refused `--resume`, a
/// value that cannot be written into a Slurm script).
const USAGE: i32 = 2;
/// The documented exit status of an output directory gridplan may not write.
const OUTPUT: i32 = 5;

/// A scratch directory with `small.map` and `cfg.toml` (`extra` added to its top level,
/// `output = "res"` unless `extra` sets it).
fn setup(name: &str, extra: &str) -> PathBuf {
    let dir = scratch(name);
    fs::write(dir.join("small.map"), SMALL).unwrap();
    let output = if extra.contains("output =") {
        ""
    } else {
        "output = \"res\"\n"
    };
    fs::write(
        dir.join("cfg.toml"),
        format!(
            "name = \"c\"\n{output}{extra}\n[[maps]]\nfiles = [\"small.map\"]\nproblems = \"corners\"\n\
             [planners.a]\nplanner = \"astar\"\n[planners.b]\nplanner = \"bfs\"\n"
        ),
    )
    .unwrap();
    dir
}

/// The marker files an injected `touch` would create, anywhere under `dir`.
fn injected(dir: &Path) -> Vec<PathBuf> {
    let mut found = Vec::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(at) = stack.pop() {
        for entry in fs::read_dir(&at).into_iter().flatten().flatten() {
            let name = entry.file_name().to_string_lossy().into_owned();
            if name.starts_with("INJECTED") {
                found.push(entry.path());
            }
            if entry.file_type().is_ok_and(|t| t.is_dir()) {
                stack.push(entry.path());
            }
        }
    }
    found
}

/// An output directory name holding every character that means something to bash or to
/// sbatch's `#SBATCH` parser, and commands that would run if it were not quoted.
const HOSTILE_DIR: &str = "o q'u\"o $(touch INJECTED1) `touch INJECTED2` ;touch INJECTED3 #%j";

#[test]
fn slurm_values_with_line_breaks_are_refused_naming_the_key() {
    let dir = setup("slurm-refused", "");
    for (option, key) in [
        ("--partition", "--partition"),
        ("--account", "--account"),
        ("--qos", "--qos"),
        ("--time", "--time"),
        ("--mem", "--mem"),
        ("--output", "--output"),
    ] {
        for value in ["p\ntouch INJECTED #", "p\rtouch INJECTED #"] {
            let out = gridplan(&dir, &["slurm", "cfg.toml", "--shards", "2", option, value]);
            refused(&out, USAGE, key);
            assert!(injected(&dir).is_empty());
        }
    }
    // A backslash reads differently to sbatch and bash: refused in a directive.
    let out = gridplan(
        &dir,
        &["slurm", "cfg.toml", "--shards", "2", "--partition", "a\\b"],
    );
    refused(&out, USAGE, "--partition");
    // The config's own `output` key.
    let bad = setup("slurm-refused-config", "output = \"r\\ntouch INJECTED #\"");
    let out = gridplan(&bad, &["slurm", "cfg.toml", "--shards", "2"]);
    refused(&out, USAGE, "key `output`");
    // No script was written anywhere.
    for d in [&dir, &bad] {
        assert!(
            fs::read_dir(d)
                .unwrap()
                .flatten()
                .all(|e| !e.file_name().to_string_lossy().ends_with("-slurm")),
            "a -slurm directory was written in {}",
            d.display()
        );
    }
}

#[test]
fn slurm_checks_the_output_directory_like_experiment() {
    let dir = setup("slurm-outdir", "");
    fs::create_dir(dir.join("res")).unwrap();
    fs::write(dir.join("res/thesis.tex"), "mine").unwrap();
    let out = gridplan(&dir, &["slurm", "cfg.toml", "--shards", "2"]);
    refused(&out, OUTPUT, "not a gridplan results directory");
    assert!(!dir.join("res-slurm").exists());
    assert_eq!(
        fs::read_to_string(dir.join("res/thesis.tex")).unwrap(),
        "mine"
    );
}

/// `slurm cfg.toml --shards 2 --output HOSTILE_DIR` (with `extra`) in a fresh [`setup`]
/// named `name`, which must succeed: the directory, the output path and the stdout.
fn hostile_slurm(name: &str, extra: &[&str]) -> (PathBuf, PathBuf, String) {
    let dir = setup(name, "");
    let output = dir.join(HOSTILE_DIR);
    let output_arg = output.display().to_string();
    let mut args = vec![
        "slurm",
        "cfg.toml",
        "--shards",
        "2",
        "--output",
        &output_arg,
    ];
    args.extend_from_slice(extra);
    let out = gridplan(&dir, &args);
    succeeded(&out);
    (dir, output, out.stdout)
}

/// The Slurm work directory of results directory `output`: `OUTPUT-slurm`.
fn slurm_work(output: &Path) -> PathBuf {
    let mut work = output.as_os_str().to_os_string();
    work.push("-slurm");
    PathBuf::from(work)
}

#[test]
fn slurm_scripts_run_by_bash_run_no_injected_command() {
    let (dir, output, _) = hostile_slurm(
        "slurm-bash",
        &[
            "--partition",
            "p q'\"$(touch INJECTED4)",
            "--account",
            "lab #; touch INJECTED6 `touch INJECTED5`",
            "--qos",
            "q'$(touch INJECTED7)\"`touch INJECTED8`",
            // `--time` and `--mem` take only sbatch's forms (refused otherwise: careless.rs).
            "--time",
            "1:00",
            "--mem",
            "1G",
        ],
    );
    succeeded(&run_slurm_scripts(&slurm_work(&output), &dir, 2));
    assert!(injected(&dir).is_empty(), "{:?}", injected(&dir));
    // The results went to the directory of that very name.
    assert!(output.join("runs.json").is_file());
}

/// Why the Slurm test cannot run here (no sbatch, or no controller answering), if so.
fn slurm_missing() -> Option<String> {
    let ping = match Command::new("scontrol").arg("ping").output() {
        Err(e) => return Some(format!("no Slurm here (scontrol: {e})")),
        Ok(out) => String::from_utf8_lossy(&out.stdout).into_owned(),
    };
    if Command::new("sbatch").arg("--version").output().is_err() {
        return Some("no sbatch on PATH".into());
    }
    if !ping.contains("UP") {
        return Some(format!("no Slurm controller answers: {}", ping.trim()));
    }
    None
}

#[test]
fn slurm_submitted_jobs_run_no_injected_command() {
    if let Some(reason) = slurm_missing() {
        assert!(
            std::env::var("GRIDPLAN_SLURM_TEST").as_deref() != Ok("1"),
            "GRIDPLAN_SLURM_TEST=1 but {reason}; start one with scripts/slurm-start.sh"
        );
        eprintln!("skipped: {reason} (scripts/slurm-start.sh starts a one-node cluster)");
        return;
    }
    // An account and memory that sbatch must read as written (no accounting here, so any
    // account name is taken).
    let account = "o'k #1 \"$(touch INJECTED9)\"";
    let (dir, output, printed) = hostile_slurm(
        "slurm-submit",
        &[
            "--time",
            "10:00",
            "--account",
            account,
            "--mem",
            "300M",
            "--submit",
        ],
    );
    let id = |what: &str| {
        printed
            .lines()
            .find_map(|l| l.strip_prefix(what))
            .unwrap_or_else(|| panic!("no {what:?} in {printed}"))
            .trim()
            .to_string()
    };
    let jobs = format!("{},{}", id("array job "), id("merge job "));
    let shown = Command::new("scontrol")
        .args(["show", "job", &id("merge job ")])
        .output()
        .unwrap();
    let shown = String::from_utf8_lossy(&shown.stdout);
    // Slurm lowercases account names.
    let expected = format!("Account={} ", account.to_lowercase());
    assert!(shown.contains(&expected), "{shown}");
    assert!(shown.contains("MinMemoryNode=300M"), "{shown}");
    let started = Instant::now();
    loop {
        let queue = Command::new("squeue")
            .args(["-h", "-j", &jobs, "-o", "%i %T"])
            .output()
            .unwrap();
        if String::from_utf8_lossy(&queue.stdout).trim().is_empty() {
            break;
        }
        if started.elapsed() > Duration::from_secs(180) {
            let _ = Command::new("scancel").args(jobs.split(',')).status();
            panic!("jobs {jobs} still queued after 180 s");
        }
        std::thread::sleep(Duration::from_millis(250));
    }
    assert!(injected(&dir).is_empty(), "{:?}", injected(&dir));
    assert!(
        output.join("runs.json").is_file(),
        "the merge wrote no results into {}",
        output.display()
    );
    // `%j` of the directory reached Slurm as `%%j`: the logs are in the directory as named.
    assert!(slurm_work(&output).join("merge.log").is_file());
}

/// Every element of `html` with a `<script>`, an `on*` attribute or a `javascript:` link.
fn live_script(html: &str) -> Vec<String> {
    let page = scraper::Html::parse_document(html);
    let mut found = Vec::new();
    for node in page.tree.nodes() {
        let Some(element) = node.value().as_element() else {
            continue;
        };
        if element.name().eq_ignore_ascii_case("script") {
            found.push(format!("<{}>", element.name()));
        }
        for (name, value) in element.attrs() {
            let compact: String = value
                .chars()
                .filter(|c| !c.is_whitespace() && !c.is_control())
                .collect::<String>()
                .to_ascii_lowercase();
            if name.to_ascii_lowercase().starts_with("on")
                || compact.starts_with("javascript:")
                || compact.starts_with("data:")
            {
                found.push(format!("<{} {name}={value:?}>", element.name()));
            }
        }
    }
    found
}

/// `markdown` without its inline code spans (a run of backticks to the next run as long, on
/// one line), where text is never HTML.
fn without_code_spans(markdown: &str) -> String {
    let mut out = String::new();
    for line in markdown.lines() {
        let mut rest = line;
        while let Some(open) = rest.find('`') {
            out.push_str(&rest[..open]);
            let run = rest[open..].len() - rest[open..].trim_start_matches('`').len();
            let after = &rest[open + run..];
            let fence = "`".repeat(run);
            // The closing run: as long as the opening one, not part of a longer run.
            let close = after.match_indices(&fence).find(|&(at, _)| {
                !after[at + run..].starts_with('`') && (at == 0 || !after[..at].ends_with('`'))
            });
            match close {
                Some((at, _)) => rest = &after[at + run..],
                None => {
                    out.push_str(&rest[open..open + run]);
                    rest = after;
                }
            }
        }
        out.push_str(rest);
        out.push('\n');
    }
    out
}

#[test]
fn report_html_has_no_live_script() {
    let dir = scratch("report");
    fs::write(dir.join("small.map"), SMALL).unwrap();
    fs::write(
        dir.join("cfg.toml"),
        "name = \"c\"\noutput = \"res\"\n\
         description = \"<script>alert(1)</script> <img src=x onerror=alert(2)> [x](javascript:alert(3)) <javascript:alert(4)>\\n\\nA [link](javascript:alert(8)) and [ok](https://example.org).\"\n\
         [[maps]]\nfiles = [\"small.map\"]\nproblems = \"corners\"\n\
         [planners.\"<script>alert(5)</script>\"]\nplanner = \"astar\"\n\
         [planners.\"[l](javascript:alert(6))\"]\nplanner = \"bfs\"\n\
         [planners.\"<b onmouseover=alert(7)>b</b>\"]\nplanner = \"dfs\"\n",
    )
    .unwrap();
    succeeded(&gridplan(&dir, &["experiment", "cfg.toml", "--quiet"]));
    let html = fs::read_to_string(dir.join("res/report.html")).unwrap();
    assert_eq!(live_script(&html), Vec::<String>::new());
    // The text is there, as text; the safe link stays a link.
    assert!(html.contains("&lt;script&gt;alert(5)&lt;/script&gt;"));
    assert!(html.contains("<a href=\"https://example.org\">ok</a>"));
    // summary.md holds no raw HTML either, for the markdown viewers that would render it:
    // the description's and the labels' tags are character references.
    // (Labels and paths in code spans are written as they are: nothing in a code span is
    // HTML.)
    let summary = fs::read_to_string(dir.join("res/summary.md")).unwrap();
    let outside_code = without_code_spans(&summary);
    for raw in ["<script", "<img", "<b ", "</script", "<javascript"] {
        assert!(!outside_code.contains(raw), "summary.md holds {raw}");
    }
    assert!(summary.contains("&lt;script>alert(1)&lt;/script>"));
    assert!(summary.contains("&lt;script&gt;alert(5)&lt;/script&gt;"));
    assert!(!summary.contains("](javascript"), "a label became a link");
    // A config's file name in a code span, with a backtick, a tag and a line break in it:
    // one line, shown as written.
    let name = "c`<img src=x onerror=alert(9)>\n# Injected.toml";
    fs::copy(dir.join("cfg.toml"), dir.join(name)).unwrap();
    succeeded(&gridplan(
        &dir,
        &["experiment", name, "--quiet", "--output", "res2"],
    ));
    let summary = fs::read_to_string(dir.join("res2/summary.md")).unwrap();
    assert!(
        !summary.lines().any(|l| l.starts_with("# Injected")),
        "{summary}"
    );
    assert!(!without_code_spans(&summary).contains("<img"), "{summary}");
    let html = fs::read_to_string(dir.join("res2/report.html")).unwrap();
    assert_eq!(live_script(&html), Vec::<String>::new());
    assert!(
        html.contains("<code>c`&lt;img src=x onerror=alert(9)&gt; # Injected.toml</code>"),
        "{html}"
    );
    // The check itself finds what it looks for.
    assert_eq!(
        live_script("<p><script>x</script><a href=\" JavaScript:x\">a</a><b onclick=x>b</b></p>")
            .len(),
        3
    );
}

#[cfg(unix)]
#[test]
fn lock_files_planted_as_links_are_refused_and_their_targets_untouched() {
    for lock in [".res.lock", ".res.stream.lock"] {
        let dir = setup(&format!("lock{lock}"), "");
        fs::write(dir.join("victim.txt"), "precious\n").unwrap();
        std::os::unix::fs::symlink(dir.join("victim.txt"), dir.join(lock)).unwrap();
        let out = gridplan(&dir, &["experiment", "cfg.toml", "--quiet"]);
        refused(&out, OUTPUT, lock);
        refused(&out, OUTPUT, "symbolic link");
        assert_eq!(
            fs::read_to_string(dir.join("victim.txt")).unwrap(),
            "precious\n"
        );
        assert!(!dir.join("res").exists());
    }
}

/// An output name of 243 to 255 bytes is a valid directory name, but `.<name>.lock` and
/// `.<name>.stream` beside it are not ("File name too long"): gridplan's side files get a
/// cut name with a hash, the same for every run on that output.
#[test]
fn an_output_name_of_255_bytes_takes_side_files_that_fit() {
    let dir = setup("long-output", "");
    for long in [250, 255] {
        let output = format!("od/{}", "L".repeat(long));
        for args in [&[][..], &["--resume"][..]] {
            let mut all = vec!["experiment", "cfg.toml", "--quiet", "--output", &output];
            all.extend(args);
            succeeded(&gridplan(&dir, &all));
            assert!(dir.join(&output).join("runs.json").is_file());
        }
        // Nothing is left beside it: the lock and stream area were found and removed.
        let beside: Vec<String> = fs::read_dir(dir.join("od"))
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        assert_eq!(beside, ["L".repeat(long)]);
        fs::remove_dir_all(dir.join("od")).unwrap();
    }
}

#[test]
fn a_foreign_stream_directory_survives() {
    let dir = setup("stream", "");
    fs::create_dir(dir.join(".res.stream")).unwrap();
    fs::write(dir.join(".res.stream/notes.txt"), "mine\n").unwrap();
    let out = gridplan(&dir, &["experiment", "cfg.toml", "--quiet"]);
    refused(&out, OUTPUT, ".res.stream");
    assert_eq!(
        fs::read_to_string(dir.join(".res.stream/notes.txt")).unwrap(),
        "mine\n"
    );
    // gridplan's own stream area is removed after a sweep.
    fs::remove_dir_all(dir.join(".res.stream")).unwrap();
    succeeded(&gridplan(&dir, &["experiment", "cfg.toml", "--quiet"]));
    assert!(!dir.join(".res.stream").exists());
    assert!(dir.join("res/runs.json").is_file());
}

/// Writes the framed stream `framed` (a shard's shard.stream) to `out` as a JSON Lines
/// stream, the format of earlier versions' shard.jsonl and resume stream.
fn json_lines(framed: &Path, out: &Path) {
    let reader = std::io::BufReader::new(fs::File::open(framed).unwrap());
    let mut file = fs::File::create(out).unwrap();
    planner_runner::frames::write_json_lines(reader, "shard.stream", (&mut file, out), None)
        .unwrap();
}

/// Replaces the first `"planner":"a"` after line 1 of `file` with another label; returns
/// the line it changed (1-based).
fn forge_label(file: &Path) -> usize {
    let text = fs::read_to_string(file).unwrap();
    let mut lines: Vec<String> = text.lines().map(String::from).collect();
    let k = (1..lines.len())
        .find(|&k| lines[k].contains("\"planner\":\"a\""))
        .expect("a record of label a");
    lines[k] = lines[k].replace("\"planner\":\"a\"", "\"planner\":\"other\"");
    fs::write(file, lines.join("\n") + "\n").unwrap();
    k + 1
}

#[test]
fn merge_refuses_foreign_records_and_mixed_versions() {
    let dir = setup("merge", "repeats = 2");
    for k in 1..=2 {
        shard(&dir, "cfg.toml", &format!("{k}/2"), &format!("s{k}"));
    }
    // Untouched, they merge.
    succeeded(&gridplan(&dir, &["merge", "s1", "s2", "--output", "m"]));
    // A record of another label at a valid run index is refused, naming file and line
    // (in an earlier version's JSON Lines shard.jsonl, which merge still reads: the
    // framed shard.stream's checksums refuse a changed byte before any record is read).
    let original = fs::read(dir.join("s2/shard.stream")).unwrap();
    json_lines(&dir.join("s2/shard.stream"), &dir.join("s2/shard.jsonl"));
    fs::remove_file(dir.join("s2/shard.stream")).unwrap();
    let line = forge_label(&dir.join("s2/shard.jsonl"));
    let out = gridplan(&dir, &["merge", "s1", "s2", "--output", "m2"]);
    refused(&out, FAILURE, &format!("shard.jsonl line {line}"));
    refused(&out, FAILURE, "\"other\"");
    assert!(!dir.join("m2").exists());
    fs::remove_file(dir.join("s2/shard.jsonl")).unwrap();
    fs::write(dir.join("s2/shard.stream"), original).unwrap();
    // Shards of two gridplan versions are refused, naming both.
    let marker = dir.join("s2/.gridplan-results");
    let text = fs::read_to_string(&marker).unwrap();
    let version = env!("CARGO_PKG_VERSION");
    fs::write(
        &marker,
        text.replace(
            &format!("gridplan = \"{version}\""),
            "gridplan = \"0.0.0-other\"",
        ),
    )
    .unwrap();
    let out = gridplan(&dir, &["merge", "s1", "s2", "--output", "m3"]);
    refused(&out, FAILURE, "0.0.0-other");
    refused(&out, FAILURE, version);
    assert!(!dir.join("m3").exists());
}

#[test]
fn resume_refuses_foreign_records() {
    let dir = setup("resume", "repeats = 2");
    // A whole sweep's stream, as a killed sweep leaves it in the stream area.
    shard(&dir, "cfg.toml", "1/1", "whole");
    fs::create_dir(dir.join(".res.stream")).unwrap();
    fs::write(dir.join(".res.stream/.gridplan-stream"), "").unwrap();
    let stream = dir.join(".res.stream/records.jsonl");
    json_lines(&dir.join("whole/shard.stream"), &stream);
    let line = forge_label(&stream);
    let out = gridplan(&dir, &["experiment", "cfg.toml", "--quiet", "--resume"]);
    refused(&out, USAGE, &format!("records.jsonl line {line}"));
    assert!(!dir.join("res").exists());
    // The same stream unforged resumes (nothing left to run) and writes the results.
    json_lines(&dir.join("whole/shard.stream"), &stream);
    succeeded(&gridplan(
        &dir,
        &["experiment", "cfg.toml", "--quiet", "--resume"],
    ));
    assert!(dir.join("res/runs.json").is_file());
}

/// Every file under `dir` whose name ends in `ext`.
fn files_with(dir: &Path, ext: &str) -> Vec<PathBuf> {
    let mut found = Vec::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(at) = stack.pop() {
        for entry in fs::read_dir(&at).into_iter().flatten().flatten() {
            if entry.file_type().is_ok_and(|t| t.is_dir()) {
                stack.push(entry.path());
            } else if entry.file_name().to_string_lossy().ends_with(ext) {
                found.push(entry.path());
            }
        }
    }
    found.sort();
    found
}

/// `|` not escaped by a backslash in `line`.
fn columns(line: &str) -> usize {
    let mut n = 0;
    let mut escaped = false;
    for c in line.chars() {
        match c {
            '\\' if !escaped => escaped = true,
            '|' if !escaped => n += 1,
            _ => escaped = false,
        }
        if c != '\\' {
            escaped = false;
        }
    }
    n
}

/// The records of CSV `text` as RFC 4180 readers count them: a `\n`, `\r` or `\r\n`
/// outside quotes ends one.
fn csv_records(text: &str) -> usize {
    let (mut records, mut quoted, mut after_cr) = (0, false, false);
    for c in text.chars() {
        match c {
            '"' => quoted = !quoted,
            '\n' if !quoted && after_cr => {}
            '\n' | '\r' if !quoted => records += 1,
            _ => {}
        }
        after_cr = c == '\r' && !quoted;
    }
    records
}

#[test]
fn names_never_collide_and_every_svg_is_xml() {
    let dir = scratch("names");
    // The longest name a file may have (255 bytes), and a label as long: a figure's name
    // joins the two (its write failed with "File name too long" after every run).
    let long_map = format!("{}.map", "l".repeat(251));
    let long_label = "k".repeat(251);
    for map in ["p q.map", "p_q.map", "p\n|>>>.map", &long_map] {
        fs::write(dir.join(map), SMALL).unwrap();
    }
    fs::write(
        dir.join("cfg.toml"),
        format!(
            "name = \"c\"\noutput = \"res\"\nfigures = \"all\"\nompl = true\n\
             [[maps]]\nfiles = [\"p q.map\", \"p_q.map\", \"p\\n|>>>.map\", \"{long_map}\"]\n\
             problems = \"corners\"\n\
             [planners.\"x y\"]\nplanner = \"astar\"\n[planners.\"x_y\"]\nplanner = \"astar\"\n\
             [planners.\"c\\u0001d\"]\nplanner = \"bfs\"\n[planners.\"e|f\"]\nplanner = \"dfs\"\n\
             [planners.\"g\\rh\"]\nplanner = \"astar\"\n[planners.\"{long_label}\"]\nplanner = \"astar\"\n"
        ),
    )
    .unwrap();
    succeeded(&gridplan(&dir, &["experiment", "cfg.toml", "--quiet"]));
    let res = dir.join("res");
    let runs: serde_json::Value =
        serde_json::from_str(&fs::read_to_string(res.join("runs.json")).unwrap()).unwrap();
    let n_runs = runs["runs"]["data"].as_array().map_or(0, Vec::len);
    assert_eq!(n_runs, 4 * 6, "4 maps x 6 labels x 1 problem");
    // runs.csv has a record per run: a line break in a name (a map's `\n`, a label's
    // bare `\r`, which pandas and Python's csv module end a record at) is inside quotes.
    let csv = fs::read_to_string(res.join("runs.csv")).unwrap();
    assert_eq!(csv_records(&csv), 1 + n_runs, "{csv:?}");
    // One OMPL log per map, each with every run of its map, its lines unbroken.
    let logs = files_with(&res.join("ompl"), ".log");
    assert_eq!(logs.len(), 4, "{logs:?}");
    for log in &logs {
        let text = fs::read_to_string(log).unwrap();
        let counted: usize = text
            .lines()
            .filter_map(|l| l.strip_suffix(" runs")?.parse::<usize>().ok())
            .sum();
        assert_eq!(counted, 6, "{}: {text}", log.display());
        // A `|>>>` only closes a block that `<<<|` opened.
        let mut open = false;
        for line in text.lines() {
            if line.starts_with("<<<|") {
                open = true;
            } else if line.starts_with("|>>>") {
                assert!(open, "{}: stray |>>>", log.display());
                open = false;
            }
        }
        assert_eq!(text.matches("planner = ").count(), 6, "{}", log.display());
    }
    // A comparison figure per map and a figure per run, no two sharing a file.
    let svgs = files_with(&res, ".svg");
    let figures = files_with(&res.join("figures"), ".svg");
    assert_eq!(figures.len(), 4 + 4 * 6, "{figures:?}");
    for svg in &svgs {
        let text = fs::read_to_string(svg).unwrap();
        if let Err(e) = roxmltree::Document::parse(&text) {
            panic!("{} is not XML: {e}", svg.display());
        }
    }
    assert!(files_with(&res.join("charts"), ".svg").len() >= 3);
    // summary.md's table rows have their header's columns.
    let summary = fs::read_to_string(res.join("summary.md")).unwrap();
    let mut header: Option<usize> = None;
    for line in summary.lines() {
        if line.starts_with('|') {
            let n = columns(line);
            match header {
                None => header = Some(n),
                Some(h) => assert_eq!(n, h, "row {line:?} of summary.md"),
            }
        } else {
            header = None;
        }
    }
    assert!(summary.contains("e\\|f"));
}

/// Maps and labels that differ only in letter case get output files that differ in more:
/// on a case-insensitive file system (macOS's, Windows' defaults) `figures/Case-1.svg`
/// and `figures/case-1.svg` are one file, and one output would replace the other.
#[test]
fn names_differing_in_case_never_share_a_file() {
    let dir = scratch("case");
    for map in ["Case.map", "case.map"] {
        fs::write(dir.join(map), SMALL).unwrap();
    }
    fs::write(
        dir.join("cfg.toml"),
        "name = \"c\"\noutput = \"res\"\nfigures = \"all\"\nompl = true\n\
         [[maps]]\nfiles = [\"Case.map\", \"case.map\"]\nproblems = \"corners\"\n\
         [planners.Case]\nplanner = \"astar\"\n[planners.case]\nplanner = \"bfs\"\n",
    )
    .unwrap();
    succeeded(&gridplan(&dir, &["experiment", "cfg.toml", "--quiet"]));
    let res = dir.join("res");
    let figures = files_with(&res.join("figures"), ".svg");
    let logs = files_with(&res.join("ompl"), ".log");
    // A comparison per map and a figure per run; a log per map.
    assert_eq!(
        (figures.len(), logs.len()),
        (2 + 2 * 2, 2),
        "{figures:?} {logs:?}"
    );
    let mut lowered: Vec<String> = figures
        .iter()
        .chain(&logs)
        .map(|p| p.to_string_lossy().to_lowercase())
        .collect();
    lowered.sort();
    lowered.dedup();
    assert_eq!(
        lowered.len(),
        figures.len() + logs.len(),
        "{figures:?} {logs:?}"
    );
    // The first of each pair keeps its plain name.
    assert!(res.join("figures/Case-1.svg").is_file(), "{figures:?}");
    assert!(res.join("ompl/Case.log").is_file(), "{logs:?}");
    let _ = fs::remove_dir_all(&dir);
}

/// Labels, paths and map names from a config someone else wrote reach the terminal as text:
/// a control sequence in them (a colour, a window title, a screen clear) is escaped in every
/// message and summary line, on stdout and stderr alike.
#[test]
fn control_sequences_in_config_text_never_reach_the_terminal() {
    let dir = setup(
        "terminal",
        "output = \"o\\u001b]0;title\\u0007ut\"\n[planners.\"w\\u001b[31mRED\"]\nplanner = \"astar\"\n",
    );
    let label = "w\u{1b}[31mRED";
    let runs = [
        gridplan(&dir, &["experiment", "cfg.toml"]),
        gridplan(
            &dir,
            &[
                "plan",
                "small.map",
                "--config",
                "cfg.toml",
                "--planner",
                label,
                "--start",
                "0,0",
                "--goal",
                "2,2",
            ],
        ),
        gridplan(&dir, &["report", "x\u{1b}[2J"]),
    ];
    for (i, out) in runs.iter().enumerate() {
        for text in [&out.stdout, &out.stderr] {
            assert!(
                !text.contains(['\u{1b}', '\u{7}']),
                "run {i}: {}",
                out.describe()
            );
        }
    }
    succeeded(&runs[0]);
    assert!(
        runs[0].stdout.contains("o\\u{1b}]0;title\\u{7}ut"),
        "{}",
        runs[0].describe()
    );
    succeeded(&runs[1]);
    assert!(
        runs[1].stdout.starts_with("w\\u{1b}[31mRED on a 3x3 grid"),
        "{}",
        runs[1].describe()
    );
    assert!(
        runs[2].stderr.contains("x\\u{1b}[2J"),
        "{}",
        runs[2].describe()
    );
}

/// `serve --host 0.0.0.0` says that the page is open to whoever reaches the machine; on
/// the loopback address it says nothing more than where it serves.
#[test]
fn serving_beyond_this_machine_is_said() {
    use std::io::{BufRead as _, Read as _};
    let dir = scratch("serve-host");
    fs::write(dir.join("small.map"), SMALL).unwrap();
    for (host, noted) in [("0.0.0.0", true), ("127.0.0.1", false)] {
        let mut child = Command::new(env!("CARGO_BIN_EXE_gridplan"))
            .args(["serve", ".", "--port", "0", "--host", host])
            .current_dir(&dir)
            .stdin(std::process::Stdio::null())
            .stdout(std::process::Stdio::piped())
            .stderr(std::process::Stdio::piped())
            .spawn()
            .unwrap();
        let mut line = String::new();
        let mut stdout = std::io::BufReader::new(child.stdout.take().unwrap());
        stdout.read_line(&mut line).unwrap();
        assert!(line.starts_with("serving . at http://"), "{line}");
        // The note follows the line at once; then the server is stopped.
        std::thread::sleep(Duration::from_millis(300));
        child.kill().unwrap();
        child.wait().unwrap();
        let mut stderr = String::new();
        child
            .stderr
            .take()
            .unwrap()
            .read_to_string(&mut stderr)
            .unwrap();
        assert_eq!(
            stderr.contains("not only this machine"),
            noted,
            "{host}: {stderr}"
        );
    }
}
