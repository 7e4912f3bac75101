//! The installed `gridplan` outside the repository: the built binary is copied into a
//! temporary install root (`<root>/bin/gridplan`, as `cargo install --root` lays it out)
//! and run from a temporary directory that holds only a map and a config written there.
//! (.ci/run does the real `cargo install --path crates/cli` once.)

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// A fresh directory under the system's temporary directory.
fn scratch(name: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join(format!("gridplan-install-{name}"));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("create the scratch directory");
    dir
}

/// Installs the built binary into `root` the way `cargo install --root` does.
fn install(root: &Path) -> PathBuf {
    let bin = root.join("bin");
    std::fs::create_dir_all(&bin).expect("create bin/");
    let installed = bin.join("gridplan");
    std::fs::copy(env!("CARGO_BIN_EXE_gridplan"), &installed).expect("copy the binary");
    installed
}

/// Runs the installed binary in `dir` with `args`; the output, after checking it succeeded.
fn run(binary: &Path, dir: &Path, args: &[&str]) -> String {
    let output: Output = Command::new(binary)
        .args(args)
        .current_dir(dir)
        .env_remove("RUST_LOG")
        .output()
        .expect("run gridplan");
    let stdout = String::from_utf8_lossy(&output.stdout).into_owned();
    assert!(
        output.status.success(),
        "gridplan {args:?} failed: {}\n{stdout}",
        String::from_utf8_lossy(&output.stderr)
    );
    stdout
}

/// A 6x3 Moving AI map with a wall that leaves one gap at the bottom.
const MAP: &str = "type octile\nheight 3\nwidth 6\nmap\n..@...\n..@...\n......\n";

const CONFIG: &str = r#"
name = "mine"
[[maps]]
files = ["wall.map"]
pairs = [{ start = [0, 0], goal = [5, 0] }]
[planners.astar]
planner = "astar"
moves = [4, 8]
heuristic = "octile"
"#;

#[test]
fn the_installed_binary_runs_outside_the_repository() {
    let root = scratch("root");
    let work = scratch("work");
    let gridplan = install(&root);
    std::fs::write(work.join("wall.map"), MAP).expect("write the map");
    std::fs::write(work.join("mine.toml"), CONFIG).expect("write the config");

    let version = run(&gridplan, &work, &["--version"]);
    assert!(
        version.starts_with(&format!("gridplan {} (commit ", env!("CARGO_PKG_VERSION"))),
        "{version}"
    );

    // The sweep's two labels, 4- and 8-connected, into results/mine in this directory.
    let experiment = run(&gridplan, &work, &["experiment", "mine.toml", "--quiet"]);
    assert!(experiment.starts_with("2 runs in "), "{experiment}");
    let csv = std::fs::read_to_string(work.join("results/mine/runs.csv")).expect("runs.csv");
    assert!(
        csv.contains("astar[moves=4]") && csv.contains("astar[moves=8]"),
        "{csv}"
    );
    // Outside any git tree, the provenance still names the commit the binary was built
    // from (where its build knew one).
    let commit = version
        .split("(commit ")
        .nth(1)
        .and_then(|rest| rest.split(')').next())
        .expect("the version names a commit");
    if commit != "unknown" {
        let summary =
            std::fs::read_to_string(work.join("results/mine/summary.md")).expect("summary.md");
        assert!(
            summary.contains(&format!("gridplan built from commit: {commit}")),
            "{summary}"
        );
    }

    // Around the wall: 4-connected 9 steps (down 2, right 5, up 2).
    let json = run(
        &gridplan,
        &work,
        &[
            "plan",
            "wall.map",
            "--planner",
            "astar",
            "--start",
            "0,0",
            "--goal",
            "5,0",
            "--json",
            "--svg",
            "wall.svg",
        ],
    );
    let json: serde_json::Value = serde_json::from_str(&json).expect("one JSON object");
    assert_eq!(json["status"], "found");
    assert_eq!(json["metrics"]["steps"], 9);
    let svg = std::fs::read_to_string(work.join("wall.svg")).expect("the figure");
    assert!(
        svg.starts_with("<svg") || svg.starts_with("<?xml"),
        "{svg:.80}"
    );

    // The label of the config's sweep, as `plan --config` names it.
    let text = run(
        &gridplan,
        &work,
        &[
            "plan",
            "wall.map",
            "--config",
            "mine.toml",
            "--planner",
            "astar[moves=8]",
            "--problem",
            "1",
        ],
    );
    assert!(text.contains("found"), "{text}");

    let planners = run(&gridplan, &work, &["planners", "astar"]);
    assert!(planners.contains("  moves: integer"), "{planners}");
    assert!(planners.contains("one of: 4, 8, 16, 32, 48"), "{planners}");
    assert!(
        planners.contains("with its defaults: paths: 4-connected; least-cost by design"),
        "{planners}"
    );

    let schema: serde_json::Value =
        serde_json::from_str(&run(&gridplan, &work, &["schema"])).expect("the schema is JSON");
    assert_eq!(schema["title"], "gridplan config");
    assert!(
        schema.to_string().contains("gridplan experiment config"),
        "the experiment schema is one branch of the composed schema"
    );

    let completions = run(&gridplan, &work, &["completions", "bash"]);
    assert!(completions.contains("_gridplan()"), "{completions:.200}");

    let _ = std::fs::remove_dir_all(&root);
    let _ = std::fs::remove_dir_all(&work);
}

#[test]
fn bad_input_is_an_error_message_not_a_panic() {
    let work = scratch("errors");
    let gridplan = env!("CARGO_BIN_EXE_gridplan");
    // The documented exit codes (README.md): 2 usage, 4 map, 3 config.
    for (args, code) in [
        (&["planners", "no_such_planner"][..], 2),
        (&["plan", "missing.map", "--planner", "astar"], 4),
        (&["experiment", "missing.toml"], 3),
    ] {
        let output = Command::new(gridplan)
            .args(args)
            .current_dir(&work)
            .output()
            .expect("run gridplan");
        let stderr = String::from_utf8_lossy(&output.stderr);
        assert_eq!(output.status.code(), Some(code), "{args:?}: {stderr}");
        assert!(stderr.starts_with("error: "), "{args:?}: {stderr}");
        assert!(!stderr.contains("panicked"), "{args:?}: {stderr}");
    }
    let _ = std::fs::remove_dir_all(&work);
}

#[test]
fn plan_marks_a_coverage_paths_end_and_refuses_maps_wider_than_200_columns() {
    let work = scratch("text");
    let gridplan = Path::new(env!("CARGO_BIN_EXE_gridplan"));
    std::fs::write(
        work.join("open.map"),
        "type octile\nheight 2\nwidth 3\nmap\n...\n...\n",
    )
    .expect("write");
    let text = run(
        gridplan,
        &work,
        &[
            "plan",
            "open.map",
            "--planner",
            "coverage",
            "--start",
            "0,0",
        ],
    );
    let drawing: Vec<&str> = text
        .lines()
        .filter(|l| l.len() == 3 && !l.contains(' '))
        .collect();
    assert_eq!(drawing.len(), 2, "{text}");
    assert_eq!(drawing.concat().matches('E').count(), 1, "{text}");
    assert!(drawing[0].starts_with('S'), "{text}");

    // Off a terminal the limit is 200 columns: 200 cells are drawn, 201 are not.
    for (width, drawn) in [(200, true), (201, false)] {
        let row = ".".repeat(width);
        std::fs::write(
            work.join("wide.map"),
            format!("type octile\nheight 1\nwidth {width}\nmap\n{row}\n"),
        )
        .expect("write");
        let text = run(
            gridplan,
            &work,
            &[
                "plan",
                "wide.map",
                "--planner",
                "bfs",
                "--start",
                "0,0",
                "--goal",
                "9,0",
            ],
        );
        assert_eq!(
            text.contains(&format!("S{}", ">".repeat(8))),
            drawn,
            "{text}"
        );
        assert_eq!(
            text.contains("more than the 200 columns here: not drawn; --svg FILE draws it"),
            !drawn,
            "{text}"
        );
    }
    let _ = std::fs::remove_dir_all(&work);
}

/// `plan --max-memory-mb` refuses a planner whose arrays need more, saying how much and
/// which flag raises it (not the expansion budget's note), and with `--json` in the field
/// `not_run`; `--svg` draws the expanded cells, as many as the run's `n_expanded`.
#[test]
fn plan_takes_a_memory_limit_and_draws_expanded_cells() {
    let work = scratch("memory");
    let gridplan = Path::new(env!("CARGO_BIN_EXE_gridplan"));
    std::fs::write(work.join("wall.map"), MAP).expect("write");
    let args = [
        "plan",
        "wall.map",
        "--planner",
        "astar",
        "--start",
        "0,0",
        "--goal",
        "5,0",
    ];
    let mut limited = args.to_vec();
    limited.extend(["--max-memory-mb", "0"]);
    let text = run(gridplan, &work, &limited);
    assert!(text.contains("budget_exhausted"), "{text}");
    assert!(
        text.contains("over the max_memory_mb = 0 budget; raise it with --max-memory-mb"),
        "{text}"
    );
    assert!(!text.contains("default budget"), "{text}");
    // With --json, the reason is a field (absent when the planner ran).
    limited.push("--json");
    let refused: serde_json::Value =
        serde_json::from_str(run(gridplan, &work, &limited).trim()).expect("one JSON object");
    assert_eq!(refused["status"], "budget_exhausted");
    let reason = refused["not_run"].as_str().expect("not_run");
    assert!(
        reason.contains("over the max_memory_mb = 0 budget"),
        "{reason}"
    );

    let mut drawn = args.to_vec();
    drawn.extend(["--json", "--svg", "run.svg"]);
    let json: serde_json::Value =
        serde_json::from_str(run(gridplan, &work, &drawn).trim()).expect("one JSON object");
    assert!(json.get("not_run").is_none(), "{json}");
    let n_expanded = json["counters"]["n_expanded"].as_u64().expect("n_expanded");
    let svg = std::fs::read_to_string(work.join("run.svg")).expect("the figure");
    assert!(
        svg.contains(&format!("expanded: {n_expanded} cells")),
        "no legend line for {n_expanded} expanded cells in {svg}"
    );
}
