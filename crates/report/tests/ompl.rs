//! OMPL benchmark logs: the header's limits from the labels' budgets, each label's limits
//! among its common properties, and no time or memory for a problem that never ran.

use planner_report::aggregate::Measured;
use planner_report::ompl;
use planner_runner::provenance::{Machine, Provenance};
use planner_runner::{config, run_all, RunOptions};

/// The log of a sweep on an open 4 x 4 map with a blocked corner: two problems, the
/// second starting on the wall (so it never runs), and the labels of `planners`, in a
/// scratch directory of its own (`name`: tests run in parallel).
fn log(name: &str, planners: &str) -> String {
    log_of(name, "open.map", "", planners)
}

/// [`log`] on map `file` (`open.map`, or `swamp.map`: the same map with its first three
/// rows and columns swamp), its set's keys `costs`.
fn log_of(name: &str, file: &str, costs: &str, planners: &str) -> String {
    let dir =
        std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join(format!("gridplan-ompl-{name}"));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(
        dir.join("open.map"),
        "type octile\nheight 4\nwidth 4\nmap\n....\n....\n....\n...@\n",
    )
    .unwrap();
    std::fs::write(
        dir.join("swamp.map"),
        "type octile\nheight 4\nwidth 4\nmap\nSSS.\nSSS.\nSSS.\n...@\n",
    )
    .unwrap();
    let text = format!(
        "name = \"o\"\nompl = true\n[[maps]]\nfiles = [{file:?}]\n{costs}\n\
         pairs = [{{ start = [0, 0], goal = [2, 2] }}, {{ start = [3, 3], goal = [0, 0] }}]\n\
         {planners}"
    );
    let experiment = config::parse(&dir.join("o.toml"), &text).unwrap();
    let records = run_all(&experiment, &RunOptions::default()).unwrap();
    let machine = Machine {
        commit: None,
        host: None,
    };
    let provenance = Provenance::collect(&experiment.source, 1, &machine);
    let logs = ompl::logs(&experiment, &records, &provenance, 1.0);
    assert_eq!(logs.len(), 1);
    String::from_utf8(logs[0].contents.clone()).unwrap()
}

/// The header said `0 MB per run` whatever the budgets, and took the time limit from the
/// first label alone.
#[test]
fn the_header_gives_the_largest_limit_the_labels_set() {
    let text = log(
        "limits",
        "[planners.a]\nplanner = \"astar\"\nbudget = { max_time_ms = 1500, max_memory_mb = 64 }\n\
         [planners.b]\nplanner = \"bfs\"\nbudget = { max_time_ms = 2500, max_memory_mb = 32, max_expansions = 99 }\n",
    );
    assert!(text.contains("\n2.5 seconds per run\n"), "{text}");
    assert!(text.contains("\n64 MB per run\n"), "{text}");
    for property in [
        "budget.max_time_s = 1.5",
        "budget.max_memory_mb = 64",
        "budget.max_time_s = 2.5",
        "budget.max_memory_mb = 32",
        "budget.max_expansions = 99",
    ] {
        assert!(
            text.contains(&format!("\n{property}\n")),
            "{property}: {text}"
        );
    }
    // A label without a time limit: the experiment has none. A label without a memory
    // limit ran with the runner's default, half the machine's memory (the log said 0 MB,
    // no limit), which is the limit written for it.
    let text = log(
        "no-limit",
        "[planners.a]\nplanner = \"astar\"\nbudget = { max_time_ms = 1500, max_memory_mb = 64 }\n\
         [planners.b]\nplanner = \"bfs\"\n",
    );
    let default = planner_runner::run::default_max_memory_mb();
    let memory = default.map_or(0, |mb| mb.max(64));
    assert!(
        text.contains(&format!("\n0 seconds per run\n{memory} MB per run\n")),
        "{text}"
    );
    if let Some(mb) = default {
        assert!(
            text.contains(&format!("\nbudget.max_memory_mb = {mb}\n")),
            "{text}"
        );
    }
}

/// The logs carried no status (budget_exhausted, no_path and invalid_problem were all
/// `solved = 0`) and no cost on a weighted map: `status` is now an ENUM of gridplan's
/// statuses, declared in the header, and `cost` a REAL on weighted maps (empty without a
/// path); lengths and costs are the doubles of runs.json, not 6 decimals.
#[test]
fn runs_have_a_status_enum_and_a_cost_on_weighted_maps() {
    let planners = "[planners.a]\nplanner = \"astar\"\n\
                    [planners.b]\nplanner = \"astar\"\nbudget = { max_expansions = 1 }\n";
    let text = log_of("status", "swamp.map", "costs = { swamp = 5 }", planners);
    assert!(
        text.contains(
            "seconds spent to collect the data\n1 enum type\n\
             status|found|no_path|budget_exhausted|invalid_problem\n2 planners\n"
        ),
        "{text}"
    );
    assert!(text.contains("\nsolved BOOLEAN\nstatus ENUM\n"), "{text}");
    assert!(text.contains("\nvalid BOOLEAN\ncost REAL\n"), "{text}");
    let runs: Vec<Vec<&str>> = text
        .lines()
        .filter(|line| line.ends_with("; "))
        .map(|line| line.split("; ").collect())
        .collect();
    // problem, repeat, seed, time, solved, status, memory, solution length, optimal
    // length, steps, turns, valid, cost: a's two runs, then b's.
    assert_eq!(runs.len(), 4, "{text}");
    let status: Vec<&str> = runs.iter().map(|r| r[5]).collect();
    assert_eq!(status, ["0", "3", "2", "3"], "{text}");
    // A found path's cost, exactly; none without a path.
    let cost: f64 = runs[0][12].parse().unwrap();
    let length: f64 = runs[0][7].parse().unwrap();
    assert!(cost > length, "{text}");
    assert_eq!(format!("{length:?}"), runs[0][7]);
    assert_eq!(runs[2][12], "", "{text}");
    // An unweighted map has no cost property.
    let plain = log("no-cost", planners);
    assert!(plain.contains("\nstatus ENUM\n") && !plain.contains("cost REAL"));
}

/// A problem that never ran (its start on a wall) was a run of time 0 and memory 0,
/// pulling Planner Arena's distributions down; its time and memory are now empty (NULL).
#[test]
fn a_problem_that_never_ran_has_no_time_or_memory() {
    let text = log("never-ran", "[planners.a]\nplanner = \"astar\"\n");
    let runs: Vec<Vec<&str>> = text
        .lines()
        .filter(|line| line.ends_with("; "))
        .map(|line| line.split("; ").collect())
        .collect();
    assert_eq!(runs.len(), 2, "{text}");
    // problem, repeat, seed, time, solved, status, memory, ...
    let (ran, never) = (&runs[0], &runs[1]);
    assert_eq!((ran[0], never[0]), ("1", "2"), "{text}");
    assert!(
        ran[3].parse::<f64>().is_ok() && ran[6].parse::<f64>().is_ok(),
        "{text}"
    );
    assert_eq!(
        (never[3], never[4], never[5], never[6]),
        ("", "0", "3", ""),
        "{text}"
    );
}

/// scripts/check-ompl.sh compared the database's planners with the raw labels, so it failed
/// on any label the writer reshapes into one word (`bfs ig\nnl` is `bfs_ig_nl-ec12bcf8`);
/// it now computes each label's OMPL name, and its `--ompl-names` gives the same names as
/// the logs (line breaks, tabs, U+2028, NEL, no-break and ideographic spaces; `x y` and
/// `x_y` stay two planners). Skipped without `python3`.
#[test]
fn check_ompl_names_the_planners_as_the_logs_do() {
    if std::process::Command::new("python3")
        .arg("--version")
        .output()
        .is_err()
    {
        eprintln!("skipped: no python3");
        return;
    }
    let labels = [
        "astar",
        "bfs ig\nnl",
        "x y",
        "x_y",
        "tab\there ",
        "a\u{2028}b",
        "\u{85}nel",
        "é\u{a0}ü",
        "wide\u{3000}space",
        "r\r\nn",
    ];
    let planners: String = labels
        .iter()
        .map(|l| format!("[planners.{l:?}]\nplanner = \"astar\"\n"))
        .collect();
    let planners = toml_escape(&planners);
    let text = log("names", &planners);
    // A planner's name is the line before its "N common properties".
    let lines: Vec<&str> = text.lines().collect();
    let mut in_log: Vec<String> = lines
        .windows(2)
        .filter(|w| w[1].ends_with(" common properties"))
        .map(|w| w[0].to_string())
        .collect();
    assert_eq!(in_log.len(), labels.len(), "{text}");
    assert_eq!(in_log[1], "bfs_ig_nl-ec12bcf8");
    let script =
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scripts/check-ompl.sh");
    let mut child = std::process::Command::new("bash")
        .arg(&script)
        .arg("--ompl-names")
        .stdin(std::process::Stdio::piped())
        .stdout(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    let input = serde_json::to_string(&labels).unwrap();
    std::io::Write::write_all(&mut child.stdin.take().unwrap(), input.as_bytes()).unwrap();
    let out = child.wait_with_output().unwrap();
    assert!(out.status.success());
    let mut named: Vec<String> = serde_json::from_slice(&out.stdout).unwrap();
    in_log.sort();
    named.sort();
    assert_eq!(named, in_log);
}

/// `text` with each `\u{X}` escape (Rust's `{:?}`) as TOML's `\uXXXX`.
fn toml_escape(text: &str) -> String {
    let mut out = String::new();
    let mut rest = text;
    while let Some(at) = rest.find("\\u{") {
        out.push_str(&rest[..at]);
        let end = rest[at..].find('}').unwrap() + at;
        let hex = &rest[at + 3..end];
        out.push_str(&format!("\\u{:0>4}", hex));
        rest = &rest[end + 1..];
    }
    out.push_str(rest);
    out
}

/// The resolved parameters (runs.json's `planners`, summary.md's table, the OMPL logs'
/// common properties) said `seed = 0` for a seeded planner whose table sets no `seed`,
/// while its runs used the config's `seed` plus the repeat. They now give the base seed
/// the runs use: the config's for a label without its own, the label's own otherwise.
#[test]
fn the_resolved_seed_is_the_seed_the_runs_use() {
    use planner_runner::output;
    let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join("gridplan-ompl-seeds");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(
        dir.join("open.map"),
        "type octile\nheight 4\nwidth 4\nmap\n....\n....\n....\n....\n",
    )
    .unwrap();
    for (base, unset) in [
        (5u64, [5u64, 6]),
        (
            9223372036854775807,
            [9223372036854775807, 9223372036854775808],
        ),
    ] {
        let text = format!(
            "name = \"s\"\nompl = true\nseed = {base}\nrepeats = 2\n[[maps]]\nfiles = [\"open.map\"]\n\
             pairs = [{{ start = [0, 0], goal = [2, 2] }}]\n\
             [planners.unset]\nplanner = \"rrt\"\n[planners.zero]\nplanner = \"rrt\"\nseed = 0\n"
        );
        let experiment = config::parse(&dir.join("s.toml"), &text).unwrap();
        let records = run_all(&experiment, &RunOptions::default()).unwrap();
        let seeds = |label: &str| -> Vec<Option<u64>> {
            records
                .iter()
                .filter(|r| r.planner == label)
                .map(|r| r.seed)
                .collect()
        };
        assert_eq!(seeds("unset"), unset.map(Some));
        assert_eq!(seeds("zero"), [Some(0), Some(1)]);
        let machine = Machine {
            commit: None,
            host: None,
        };
        let provenance = Provenance::collect(&experiment.source, 1, &machine);
        let json = output::runs_json_with(&experiment, &records, Some(&provenance)).unwrap();
        let json: serde_json::Value = serde_json::from_slice(&json).unwrap();
        let planners = &json["planners"];
        assert_eq!(planners["unset"]["parameters"]["seed"], base, "{planners}");
        assert_eq!(planners["zero"]["parameters"]["seed"], 0, "{planners}");
        let table = planner_report::aggregate::parameters(&experiment, Measured::Shown);
        let row = |label: &str| {
            table
                .lines()
                .find(|l| l.starts_with(&format!("| {label} |")))
                .unwrap_or_default()
                .to_string()
        };
        assert!(row("unset").contains(&format!("seed = {base}")), "{table}");
        assert!(row("zero").contains("seed = 0"), "{table}");
        assert!(table.contains("repeat r runs with seed + r"), "{table}");
        let logs = ompl::logs(&experiment, &records, &provenance, 1.0);
        let log = String::from_utf8(logs[0].contents.clone()).unwrap();
        let zero = log.find("\nzero\n").unwrap();
        let (unset_block, zero_block) = log.split_at(zero);
        assert!(unset_block.contains(&format!("\nseed = {base}\n")), "{log}");
        assert!(zero_block.contains("\nseed = 0\n"), "{log}");
    }
}
