//! The `navigate` and `dynamic` experiment kinds end to end: every config under
//! `configs/replan/` run with their `[test]` limits and snapshotted (no times), results
//! independent of the thread count, and config errors with file, line and column.

use std::path::{Path, PathBuf};

use planner_api::{
    Budget, Cell, CellChange, ChangeError, Connectivity, Cost, Counters, Grid, IncrementalPlanner,
    MoveSet, Outcome, PathSpec, PlannerSpecs, Problem, Status,
};
use planner_replan::experiment::{self, ExperimentError, RunOptions};

use crate::wrap::{Change, Wrapped};
use planner_testkit::{reference_astar, Tie, REFERENCE_COUNTERS};

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

fn scratch(name: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join(format!("replan-experiment-{name}"));
    let _ = std::fs::remove_dir_all(&dir);
    dir
}

fn test_options(threads: usize) -> RunOptions {
    RunOptions {
        test: true,
        timing: false,
        threads,
        stop: None,
    }
}

fn read(dir: &Path, file: &str) -> String {
    std::fs::read_to_string(dir.join(file)).unwrap_or_default()
}

/// Every output but the chart and the per-replan lines, for the snapshot.
fn outputs(dir: &Path) -> String {
    let mut text = String::new();
    for file in ["summary.md", "runs.csv", "gppc.csv"] {
        let body = read(dir, file);
        if !body.is_empty() {
            text.push_str(&format!("==> {file}\n{body}\n"));
        }
    }
    text
}

fn snapshot(config: &str) {
    let out = scratch(config);
    let path = root().join(format!("configs/replan/{config}.toml"));
    let done = experiment::run(&path, &out, &test_options(2)).unwrap();
    assert_eq!(done.mismatches, 0, "{}", read(&out, "summary.md"));
    assert!(done.replans > 0);
    // One JSON line per replan, each with the oracle's expansions.
    let replans = read(&out, "replans.jsonl");
    let lines: Vec<serde_json::Value> = replans
        .lines()
        .map(|l| serde_json::from_str(l).unwrap())
        .collect();
    let per_run: u64 = read(&out, "runs.csv")
        .lines()
        .skip(1)
        .map(|l| l.split(',').nth(6).unwrap().parse::<u64>().unwrap())
        .sum();
    assert_eq!(lines.len() as u64, per_run);
    assert!(lines.iter().all(|l| l["astar_expansions"].is_u64()));
    assert!(read(&out, "expansions.svg").starts_with("<svg"));
    insta::with_settings!({
        snapshot_path => "../../../snapshots",
        prepend_module_to_snapshot => false,
        description => format!("configs/replan/{config}.toml with its [test] limits"),
        omit_expression => true,
    }, {
        insta::assert_snapshot!(format!("replan-{config}"), outputs(&out));
    });
}

#[test]
fn navigate_costmap_config_is_snapshotted() {
    snapshot("navigate-costmap");
}

#[test]
fn dynamic_costmap_config_is_snapshotted() {
    snapshot("dynamic-costmap");
}

#[test]
fn navigate_config_is_snapshotted() {
    snapshot("navigate");
}

#[test]
fn dynamic_config_is_snapshotted() {
    snapshot("dynamic");
}

/// Paths, counters and summaries do not depend on the number of threads.
#[test]
fn results_do_not_depend_on_threads() {
    let path = root().join("configs/replan/navigate.toml");
    let (one, three) = (scratch("threads-1"), scratch("threads-3"));
    experiment::run(&path, &one, &test_options(1)).unwrap();
    experiment::run(&path, &three, &test_options(3)).unwrap();
    for file in ["summary.md", "runs.csv", "runs.jsonl", "replans.jsonl"] {
        assert_eq!(read(&one, file), read(&three, file), "{file}");
    }
}

/// The values of the column `name` of a CSV `table` whose fields hold no comma.
fn column(table: &str, name: &str) -> Vec<String> {
    let mut lines = table.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let at = header.iter().position(|h| *h == name).unwrap();
    lines
        .map(|l| l.split(',').nth(at).unwrap().to_owned())
        .collect()
}

fn parse_error(text: &str) -> ExperimentError {
    experiment::parse(Path::new("bad.toml"), text).unwrap_err()
}

#[test]
fn config_errors_name_file_line_column_and_key() {
    let base = "kind = \"navigate\"\nname = \"x\"\nradii = [1]\n[[maps]]\nmap = \"a.map\"\nscen = \"a.scen\"\n";
    assert!(experiment::parse(Path::new("ok.toml"), base).is_ok());
    // An unknown key: toml's span, the key named.
    let e = parse_error(&format!("{base}colour = 3\n"));
    assert!(
        matches!(&e, ExperimentError::Parse { line: 7, column: 1, message, .. } if message.contains("colour")),
        "{e}"
    );
    // A value of the wrong type.
    let e = parse_error("kind = \"navigate\"\nname = 5\n");
    assert!(matches!(&e, ExperimentError::Parse { line: 2, .. }), "{e}");
    assert!(e.to_string().starts_with("bad.toml:2:"), "{e}");
    // An unknown kind.
    let e = parse_error("kind = \"walk\"\nname = \"x\"\n");
    assert!(matches!(&e, ExperimentError::Parse { line: 1, .. }), "{e}");
    // An unknown planner: the line and column of its name.
    let e = parse_error(&format!("compare = [\"astar\", \"dstar\"]\n{base}"));
    assert!(
        matches!(&e, ExperimentError::Invalid { line: 1, column: 21, key, .. } if key == "compare"),
        "{e}"
    );
    assert!(
        e.to_string().contains("unknown replanning planner `dstar`"),
        "{e}"
    );
    // A cost rule without a weight file: its line and column.
    let e = parse_error(&format!("{base}cost_rule = \"entered\"\n"));
    assert!(
        matches!(&e, ExperimentError::Invalid { line: 7, column: 13, key, .. } if key == "cost_rule"),
        "{e}"
    );
    // Bad moves, a bad name, a key of the other kind.
    let e = parse_error(&format!("moves = 6\n{base}"));
    assert!(
        matches!(&e, ExperimentError::Invalid { line: 1, column: 9, key, .. } if key == "moves"),
        "{e}"
    );
    let e = parse_error("kind = \"navigate\"\nname = \"a b\"\nradii = [1]\n");
    assert!(
        matches!(&e, ExperimentError::Invalid { line: 2, key, .. } if key == "name"),
        "{e}"
    );
    let e = parse_error("kind = \"dynamic\"\nname = \"x\"\nradii = [1]\n");
    assert!(
        matches!(&e, ExperimentError::Invalid { line: 3, key, .. } if key == "radii"),
        "{e}"
    );
    let e = parse_error("kind = \"navigate\"\nname = \"x\"\nradii = [1]\n");
    assert!(
        matches!(&e, ExperimentError::Invalid { key, .. } if key == "maps"),
        "{e}"
    );
    // A missing key is said at 1:1, as toml says a missing `name` (it was the file
    // alone); an empty list, an array of tables in the wrong kind, their value's.
    assert_eq!(
        e.to_string(),
        "bad.toml:1:1: `maps`: a navigate experiment needs [[maps]]"
    );
    let no_radii = base.replace("radii = [1]\n", "");
    assert_eq!(
        parse_error(&no_radii).to_string(),
        "bad.toml:1:1: `radii`: a navigate experiment needs radii"
    );
    assert_eq!(
        parse_error("kind = \"dynamic\"\nname = \"x\"\n").to_string(),
        "bad.toml:1:1: `toggles`: a dynamic experiment needs [toggles] (with [[maps]]) or [[gppc]]"
    );
    let e = parse_error(&format!("compare = []\n{base}"));
    assert_eq!(
        e.to_string(),
        "bad.toml:1:11: `compare`: name at least one planner"
    );
    let e = parse_error(&base.replace("radii = [1]", "radii = []"));
    assert_eq!(
        e.to_string(),
        "bad.toml:3:9: `radii`: a navigate experiment needs radii"
    );
    let e = parse_error(&format!("{base}[[gppc]]\nscen = \"g.scen\"\n"));
    assert!(
        matches!(&e, ExperimentError::Invalid { line: 7, column: 1, key, .. } if key == "gppc"),
        "{e}"
    );
}

/// A value of the wrong type named no key (`n.toml:3:10: invalid value: integer `-1`,
/// expected u32`): read through serde_path_to_error, as the runner's configs are, each
/// names its key.
#[test]
fn type_errors_name_their_key() {
    let base = "kind = \"navigate\"\nname = \"x\"\nradii = [1]\n[[maps]]\nmap = \"a.map\"\nscen = \"a.scen\"\n";
    let dynamic = "kind = \"dynamic\"\nname = \"x\"\n[[maps]]\nmap = \"a.map\"\nscen = \"a.scen\"\n[toggles]\nevents = 2\nk = 1\nradius = 3\nseeds = [1]\n";
    let cases = [
        (
            base.replace("radii = [1]", "radii = [-1]"),
            "bad.toml:3:10: key `radii[0]`: invalid value: integer `-1`, expected u32",
        ),
        (
            format!("max_steps = -1\n{base}"),
            "bad.toml:1:13: key `max_steps`: invalid value: integer `-1`, expected u64",
        ),
        (
            format!("{base}scenarios = \"1\"\n"),
            "bad.toml:7:13: key `maps[0].scenarios`: invalid type: string \"1\", expected usize",
        ),
        (
            dynamic.replace("seeds = [1]", "seeds = [-1]"),
            "bad.toml:10:10: key `toggles.seeds[0]`: invalid value: integer `-1`, expected u64",
        ),
        (
            dynamic.replace("seeds = [1]", "seeds = [\"a\"]"),
            "bad.toml:10:10: key `toggles.seeds[0]`: invalid type: string \"a\", expected u64",
        ),
    ];
    for (text, expected) in cases {
        assert_eq!(parse_error(&text).to_string(), expected, "{text}");
    }
}

/// A malformed map or scenario file is reported with its file, line and column, before
/// anything is written.
#[test]
fn malformed_inputs_are_reported_before_writing() {
    let dir = scratch("malformed");
    std::fs::create_dir_all(&dir).unwrap();
    let maps = root().join("maps/movingai");
    std::fs::write(
        dir.join("bad.scen"),
        "version 1\n0\tarena.map\t49\t49\t1\t1\t2\tx\t1\n",
    )
    .unwrap();
    let config = format!(
        "kind = \"navigate\"\nname = \"bad\"\nradii = [1]\n[[maps]]\nmap = {:?}\nscen = \"bad.scen\"\n",
        maps.join("arena.map").display().to_string()
    );
    std::fs::write(dir.join("bad.toml"), config).unwrap();
    let out = dir.join("out");
    let e = experiment::run(&dir.join("bad.toml"), &out, &test_options(1)).unwrap_err();
    match &e {
        ExperimentError::Map(m) => {
            assert!(m.file.ends_with("bad.scen") && m.line == 2, "{e}");
        }
        other => panic!("expected a map error, got {other}"),
    }
    assert!(!out.exists());
}

/// A GPPC scenario or patch file that is not a regular file (a FIFO, `/dev/zero`) is refused
/// before it is opened, and a scenario's map that no grid can hold is an error at its
/// width: neither hangs, and neither gives an empty replay that reports 0 mismatches.
#[test]
fn gppc_inputs_that_cannot_be_replayed_are_refused() {
    let dir = scratch("gppc-inputs");
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(
        dir.join("d.toml"),
        "kind = \"dynamic\"\nname = \"d\"\n[[gppc]]\nscen = \"s.scen\"\n",
    )
    .unwrap();
    std::fs::write(
        dir.join("p.patch"),
        "type patch\npatches 1\npatch 0\nheight 1\nwidth 1\nmap\n.\n",
    )
    .unwrap();
    let scen = |height: &str, patch: &str| {
        let text = format!(
            "version 2\nheight {height}\nwidth 3\ncost 1 octile\npatch {patch}\ncommands\nP 0 0 0 0\nQ 0 0 0 1 1 1.4142135624\n"
        );
        std::fs::write(dir.join("s.scen"), text).unwrap();
    };
    let out = dir.join("out");
    let run = || experiment::run(&dir.join("d.toml"), &out, &test_options(1));
    scen("3", "p.patch");
    assert_eq!(run().unwrap().runs, 4);
    std::fs::remove_dir_all(&out).unwrap();
    let status = std::process::Command::new("mkfifo")
        .arg(dir.join("fifo"))
        .status()
        .unwrap();
    assert!(status.success());
    for patch in ["/dev/zero", "fifo"] {
        scen("3", patch);
        let e = run().unwrap_err();
        match &e {
            ExperimentError::Map(m) => assert!(
                m.to_string().contains("not a regular file")
                    && m.to_string().contains(&format!("patch file '{patch}'"))
                    && m.file.ends_with("s.scen")
                    && (m.line, m.column) == (5, 7),
                "{e}"
            ),
            other => panic!("{patch}: expected a map error, got {other}"),
        }
    }
    std::fs::rename(dir.join("s.scen"), dir.join("real.scen")).unwrap();
    std::os::unix::fs::symlink("fifo", dir.join("s.scen")).unwrap();
    let e = run().unwrap_err();
    assert!(e.to_string().contains("not a regular file"), "{e}");
    std::fs::remove_file(dir.join("s.scen")).unwrap();
    scen("3000000000", "p.patch");
    let e = run().unwrap_err();
    match &e {
        ExperimentError::Map(m) => assert!(
            m.file.ends_with("s.scen") && (m.line, m.column) == (3, 1),
            "{e}"
        ),
        other => panic!("expected a map error, got {other}"),
    }
    assert!(
        e.to_string()
            .contains("more than the limit of 2147483648 cells"),
        "{e}"
    );
    assert!(!out.exists());
}

/// A raised stop flag (the command line's Ctrl-C) ends the experiment with
/// `Interrupted`: no run starts after it, the earlier results stay as they were, and the
/// working area beside the output, where the tables were being written, is gone.
#[test]
fn a_stopped_experiment_leaves_the_output_as_it_was() {
    use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
    static STOP: AtomicBool = AtomicBool::new(false);
    static BUILT: AtomicUsize = AtomicUsize::new(0);
    let path = root().join("configs/replan/navigate.toml");
    let config = experiment::load(&path).unwrap();
    let out = scratch("stopped");
    let options = RunOptions {
        stop: Some(&STOP),
        ..test_options(1)
    };
    experiment::run_config(&config, &path, &out, &options).unwrap();
    let before = read(&out, "runs.csv");
    assert!(!before.is_empty());
    // The third run's planner raises the flag: the runs after it in its chunk (the
    // test limits' runs are one chunk) do not start.
    let make = |name: &str, eight: bool| {
        if BUILT.fetch_add(1, Ordering::SeqCst) == 2 {
            STOP.store(true, Ordering::SeqCst);
        }
        planner_replan::planners::by_name(name, eight).unwrap()
    };
    let e = experiment::run_config_with(&config, &path, &out, &options, &make).unwrap_err();
    assert!(matches!(e, ExperimentError::Interrupted), "{e}");
    assert_eq!(
        BUILT.load(Ordering::SeqCst),
        3,
        "runs started after the stop"
    );
    assert_eq!(read(&out, "runs.csv"), before);
    let parent = out.parent().unwrap();
    let name = out.file_name().unwrap().to_string_lossy();
    for leftover in ["stream", "stream.lock"] {
        let path = parent.join(format!(".{name}.{leftover}"));
        assert!(!path.exists(), "{} stayed", path.display());
    }
}

/// The output directory is replaced only when it is empty or an earlier run's.
#[test]
fn foreign_output_directories_are_left_alone() {
    let out = scratch("foreign");
    std::fs::create_dir_all(&out).unwrap();
    std::fs::write(out.join("notes.txt"), "mine").unwrap();
    let path = root().join("configs/replan/navigate.toml");
    let e = experiment::run(&path, &out, &test_options(1)).unwrap_err();
    assert!(matches!(e, ExperimentError::Output(_)), "{e}");
    assert_eq!(read(&out, "notes.txt"), "mine");
}

/// A second run into the same directory: a file of the user's among the results refuses it
/// with everything left as it was (the experiment runner's rule); once the file is moved
/// out, the first run's outputs that it does not write (`dynamic`'s GPPC table after
/// `navigate`) go, and the marker lists exactly the files written, in the runner's format.
#[test]
fn a_rerun_leaves_no_output_of_the_earlier_config() {
    let out = scratch("rerun");
    let run = |config: &str| {
        let path = root().join(format!("configs/replan/{config}.toml"));
        experiment::run(&path, &out, &test_options(1)).unwrap()
    };
    let first = run("dynamic");
    assert!(out.join("gppc.csv").is_file());
    assert!(first.files.iter().any(|f| f.ends_with("gppc.csv")));
    std::fs::write(out.join("notes.txt"), "mine").unwrap();
    let path = root().join("configs/replan/navigate.toml");
    let refused = experiment::run(&path, &out, &test_options(1)).unwrap_err();
    assert!(refused.to_string().contains("notes.txt"), "{refused}");
    assert_eq!(read(&out, "notes.txt"), "mine");
    assert!(
        out.join("gppc.csv").is_file(),
        "the refused run changed the results"
    );
    std::fs::remove_file(out.join("notes.txt")).unwrap();
    let second = run("navigate");
    assert!(!out.join("gppc.csv").exists(), "a stale gppc.csv stayed");
    let marker: toml::Table = toml::from_str(&read(&out, experiment::MARKER)).unwrap();
    let mut listed: Vec<String> = marker["files"]
        .as_array()
        .unwrap()
        .iter()
        .map(|f| f.as_str().unwrap().to_string())
        .collect();
    listed.sort();
    let mut written: Vec<String> = second
        .files
        .iter()
        .map(|f| f.file_name().unwrap().to_string_lossy().into_owned())
        .collect();
    written.sort();
    assert_eq!(listed, written);
    assert_eq!(marker["format"].as_integer(), Some(1));
    assert_eq!(marker["experiment"].as_str(), Some("navigate"));
    // Nothing half-written is left in the directory or beside it (the runner writes the
    // new directory as `.<name>.partial` beside it and keeps no lock once done).
    let beside = format!(".{}.", out.file_name().unwrap().to_string_lossy());
    let mut names: Vec<String> = std::fs::read_dir(&out)
        .unwrap()
        .chain(std::fs::read_dir(out.parent().unwrap()).unwrap())
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n.ends_with(".partial") || n.starts_with(&beside))
        .collect();
    names.sort();
    assert!(names.is_empty(), "{names:?}");
}

/// More toggles per event than the map has cells is refused before anything runs or is
/// written: the change list of `k = 4000000000` took 10 GB in 16 s, before the first replan.
#[test]
fn more_toggles_than_cells_is_refused() {
    let dir = scratch("toggles-k");
    std::fs::create_dir_all(&dir).unwrap();
    let arena = root().join("maps/movingai/arena.map");
    let config = format!(
        "kind = \"dynamic\"\nname = \"k\"\ncompare = [\"dstar_lite\"]\n[[maps]]\nmap = {:?}\nscen = {:?}\nscenarios = 1\n[toggles]\nevents = 2\nk = K\nradius = 3\nseeds = [1]\n",
        arena.display().to_string(),
        format!("{}.scen", arena.display())
    );
    let run = |k: &str| {
        let path = dir.join(format!("k{k}.toml"));
        std::fs::write(&path, config.replace("K", k)).unwrap();
        experiment::run(&path, &dir.join(format!("out{k}")), &test_options(1))
    };
    // arena is 49 x 49: 2401 cells.
    let error = run("4000000000").unwrap_err();
    assert!(
        matches!(error, ExperimentError::TooManyToggles { cells: 2401, .. }),
        "{error}"
    );
    // At the value's line and column, as every other key's error (it had neither).
    let place = "k4000000000.toml:10:5: `[toggles] k`: 4000000000 toggles per event";
    assert!(error.to_string().contains(place), "{error}");
    assert!(!dir.join("out4000000000").exists());
    assert!(run("2401").is_ok());
}

/// What users write is data in every output: a description's raw HTML and `javascript:`
/// link show as text in summary.md (its prose rule had lacked the link check the runner's
/// reports have), and a map named with a comma, `<`, `|` and a carriage return keeps its
/// runs.csv rows whole and its summary.md row to its columns.
#[test]
fn names_and_descriptions_are_data() {
    let dir = scratch("names");
    std::fs::create_dir_all(&dir).unwrap();
    let stem = "m,<b>|x\ry";
    let arena = root().join("maps/movingai/arena.map");
    std::fs::copy(&arena, dir.join(format!("{stem}.map"))).unwrap();
    std::fs::copy(
        root().join("maps/movingai/arena.map.scen"),
        dir.join("s.scen"),
    )
    .unwrap();
    let config = format!(
        "kind = \"dynamic\"\nname = \"n\"\ndescription = \"<script>x</script> [j](javascript:alert(1)) [ok](https://o.org)\"\ncompare = [\"dstar_lite\", \"astar\"]\n[[maps]]\nmap = {:?}\nscen = \"s.scen\"\nscenarios = 2\n[toggles]\nevents = 1\nk = 2\nradius = 3\nseeds = [1]\n",
        format!("{stem}.map")
    );
    let path = dir.join("n.toml");
    std::fs::write(&path, config).unwrap();
    let out = dir.join("out");
    experiment::run(&path, &out, &test_options(1)).unwrap();
    let summary = read(&out, "summary.md");
    assert!(summary.contains("&lt;script>x&lt;/script>"), "{summary}");
    assert!(summary.contains("[j]\\(javascript:alert(1))"), "{summary}");
    assert!(summary.contains("[ok](https://o.org)"), "{summary}");
    assert!(summary.contains("m,&lt;b&gt;\\|x y"), "{summary}");
    // 2 scenarios x 2 planners, each one record: a `\r` outside quotes would end one.
    let csv = read(&out, "runs.csv");
    let (mut records, mut quoted) = (0, false);
    for c in csv.chars() {
        match c {
            '"' => quoted = !quoted,
            '\n' | '\r' if !quoted => records += 1,
            _ => {}
        }
    }
    assert_eq!(records, 1 + 4, "{csv:?}");
}

/// A* from scratch behind the incremental interface as planner-replan's `Restart`
/// documents it (forward, or backward with the path reversed; octile or Manhattan times
/// the map's smallest weight, exact costs, FIFO ties; no search when the start or goal is
/// blocked), each replan `planner_testkit::reference_astar`.
struct ReferenceRestart {
    eight: bool,
    backward: bool,
    grid: Option<Grid>,
    start: Cell,
    goal: Cell,
}

impl IncrementalPlanner for ReferenceRestart {
    fn name(&self) -> &str {
        "reference_restart"
    }

    fn specs(&self) -> PlannerSpecs {
        let moves = MoveSet::standard(match self.eight {
            true => Connectivity::Eight,
            false => Connectivity::Four,
        });
        PlannerSpecs::deterministic(PathSpec::Moves(moves)).with_admissible(true)
    }

    fn reset(&mut self, problem: &Problem<'_>) {
        self.grid = Some(problem.grid().clone());
        (self.start, self.goal) = (problem.start(), problem.goal());
    }

    fn grid(&self) -> Option<&Grid> {
        self.grid.as_ref()
    }

    fn start(&self) -> Option<Cell> {
        Some(self.start)
    }

    fn move_start(&mut self, cell: Cell) -> Result<(), ChangeError> {
        self.start = cell;
        Ok(())
    }

    fn apply(&mut self, changes: &[CellChange]) -> Result<(), ChangeError> {
        let grid = self.grid.as_mut().unwrap();
        for change in changes {
            if let Some(weight) = change.weight {
                grid.set_weight(change.cell, weight);
            }
            grid.set_free(change.cell, change.free);
        }
        Ok(())
    }

    fn replan(&mut self, _: &Budget) -> Outcome {
        let grid = self.grid.as_ref().unwrap();
        let (from, to) = match self.backward {
            true => (self.goal, self.start),
            false => (self.start, self.goal),
        };
        if !grid.is_free(from) || !grid.is_free(to) {
            return Outcome::no_path(Counters::new().with("n_expanded", 0));
        }
        let moves = self.specs().path_rule;
        let PathSpec::Moves(moves) = moves else {
            unreachable!("grid moves")
        };
        let weight = grid.weights().map_or(1, |w| u64::from(w.min()));
        let h = |c: Cell| {
            let (dx, dy) = (c.x.abs_diff(to.x), c.y.abs_diff(to.y));
            let length = match self.eight {
                true => Cost::octile_distance(dx, dy),
                false => Cost::steps(u64::from(dx + dy)),
            };
            length.times(weight)
        };
        let (status, path, counts) = reference_astar(grid, &moves, h, Tie::Fifo, from, to);
        let mut counters = Counters::new();
        for (&name, value) in REFERENCE_COUNTERS.iter().zip(counts) {
            counters = counters.with(name, value);
        }
        match path {
            Some(mut cells) if status == Status::Found => {
                if self.backward {
                    cells.reverse();
                }
                Outcome::found(planner_api::Path::new(cells), counters)
            }
            _ => Outcome::no_path(counters),
        }
    }
}

/// Every planner of every config under `configs/replan/` (their `[test]` limits) run again
/// with a reference in its place: LPA\* and D\* Lite by `planner_testkit::
/// ReferenceIncremental` (the papers' searches written again plainly, a `BTreeSet` for the
/// queue), A* from scratch (`astar`, `astar_backward`) by [`ReferenceRestart`]. Every
/// output file is the same, so the snapshots' expansions, counters, paths and the oracle's
/// expansions (the forward A*'s) are the references'.
#[test]
fn every_replan_matches_the_reference_planners() {
    use planner_testkit::ReferenceIncremental;
    let reference = |name: &str, eight: bool| -> Box<dyn IncrementalPlanner> {
        match name {
            "lpastar" => Box::new(ReferenceIncremental::new(false, eight)),
            "dstar_lite" => Box::new(ReferenceIncremental::new(true, eight)),
            "astar" | "astar_backward" => Box::new(ReferenceRestart {
                eight,
                backward: name == "astar_backward",
                grid: None,
                start: Cell::new(0, 0),
                goal: Cell::new(0, 0),
            }),
            _ => panic!("no reference for {name}"),
        }
    };
    for config in ["navigate", "dynamic", "navigate-costmap", "dynamic-costmap"] {
        let path = root().join(format!("configs/replan/{config}.toml"));
        let loaded = experiment::load(&path).unwrap();
        assert!(
            loaded
                .planners
                .iter()
                .any(|p| ["lpastar", "dstar_lite"].contains(&p.get_ref().as_str())),
            "{config} compares no incremental planner"
        );
        let (ours, theirs) = (
            scratch(&format!("{config}-ours")),
            scratch(&format!("{config}-reference")),
        );
        experiment::run_config(&loaded, &path, &ours, &test_options(2)).unwrap();
        experiment::run_config_with(&loaded, &path, &theirs, &test_options(2), &reference).unwrap();
        let names = |dir: &Path| {
            let mut files: Vec<_> = std::fs::read_dir(dir)
                .unwrap()
                .map(|entry| entry.unwrap().file_name())
                .collect();
            files.sort();
            files
        };
        let files = names(&ours);
        assert_eq!(files, names(&theirs), "{config}");
        assert!(files.len() >= 4, "{config}: {files:?}");
        for file in files {
            let file = file.to_string_lossy();
            let (a, b) = (read(&ours, &file), read(&theirs, &file));
            // The first line that differs, rather than two whole files.
            let differ = a.lines().zip(b.lines()).find(|(x, y)| x != y);
            assert_eq!(differ, None, "{config}: {file}");
            assert_eq!(a.lines().count(), b.lines().count(), "{config}: {file}");
        }
    }
}

/// Calls `on_replan` with each replan's number (1 for the first plan) after it; for tests
/// that act from inside a run.
struct Watched {
    replans: usize,
    on_replan: fn(usize),
}

impl Change for Watched {
    fn replan(&mut self, inner: &mut dyn IncrementalPlanner, budget: &Budget) -> Outcome {
        let outcome = inner.replan(budget);
        self.replans += 1;
        (self.on_replan)(self.replans);
        outcome
    }
}

/// The names beside `out` in its parent that start with `.<out's name>.`: the working
/// directory, its lock and the temporary siblings.
fn beside(out: &Path) -> Vec<String> {
    let prefix = format!(".{}.", out.file_name().unwrap().to_string_lossy());
    let mut names: Vec<String> = std::fs::read_dir(out.parent().unwrap())
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n.starts_with(&prefix))
        .collect();
    names.sort();
    names
}

/// A raised stop flag ends a run in progress before its next event or step, not at its end:
/// a toggle script of a million events, or a navigation, stopped at its 3rd replan makes no
/// other, and the experiment ends `Interrupted`, the output absent as it was and nothing
/// left beside it. Before, the flag was looked at only between runs, so a run of
/// 4,294,967,295 events could not be stopped, and its replans filled the memory.
#[test]
fn a_stop_ends_a_run_in_progress() {
    use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
    static STOP: AtomicBool = AtomicBool::new(false);
    static REPLANS: AtomicUsize = AtomicUsize::new(0);
    let dir = scratch("stop-in-run");
    std::fs::create_dir_all(&dir).unwrap();
    // Arena's last scenario, the longest: its navigation replans more than 3 times.
    let arena = root().join("maps/movingai/arena.map");
    let scen = std::fs::read_to_string(root().join("maps/movingai/arena.map.scen")).unwrap();
    let last = scen.lines().rev().find(|l| !l.trim().is_empty()).unwrap();
    std::fs::write(dir.join("s.scen"), format!("version 1\n{last}\n")).unwrap();
    let maps = format!(
        "compare = [\"dstar_lite\"]\n[[maps]]\nmap = {:?}\nscen = \"s.scen\"\nscenarios = 1\n",
        arena.display().to_string(),
    );
    let dynamic = (
        "kind = \"dynamic\"\nname = \"s\"\n",
        "[toggles]\nevents = 1000000\nk = 5\nradius = 5\nseeds = [1]\n",
    );
    let navigate = ("kind = \"navigate\"\nname = \"s\"\nradii = [1]\n", "");
    let make = |name: &str, eight: bool| -> Box<dyn IncrementalPlanner> {
        Box::new(Wrapped {
            inner: planner_replan::planners::by_name(name, eight).unwrap(),
            change: Watched {
                replans: 0,
                on_replan: |n| {
                    REPLANS.store(n, Ordering::SeqCst);
                    if n == 3 {
                        STOP.store(true, Ordering::SeqCst);
                    }
                },
            },
        })
    };
    for (kind, (head, tail)) in [("dynamic", dynamic), ("navigate", navigate)] {
        let path = dir.join(format!("{kind}.toml"));
        std::fs::write(&path, format!("{head}{maps}{tail}")).unwrap();
        let config = experiment::load(&path).unwrap();
        let out = dir.join(format!("out-{kind}"));
        if kind == "navigate" {
            // Unstopped, the run replans more than 3 times.
            let whole = experiment::run_config(&config, &path, &out, &test_options(1)).unwrap();
            assert!(whole.replans > 3, "{} replans", whole.replans);
            std::fs::remove_dir_all(&out).unwrap();
        }
        STOP.store(false, Ordering::SeqCst);
        let options = RunOptions {
            stop: Some(&STOP),
            ..test_options(1)
        };
        let e = experiment::run_config_with(&config, &path, &out, &options, &make).unwrap_err();
        assert!(matches!(e, ExperimentError::Interrupted), "{kind}: {e}");
        assert_eq!(
            REPLANS.load(Ordering::SeqCst),
            3,
            "{kind}: replans after the stop"
        );
        assert!(!out.exists(), "{kind}: the output was written");
        assert_eq!(
            beside(&out),
            Vec::<String>::new(),
            "{kind}: left beside the output"
        );
    }
}

/// What a killed run leaves beside its output (the working directory, with gridplan's
/// marker and its tables, and its lock) holds nothing to resume: the next run on that
/// output, whatever its config, takes them over and removes them. A GPPC replay alone,
/// which writes no table there, left them before.
#[test]
fn a_killed_runs_working_files_go_with_the_next_run() {
    let dir = scratch("leftovers");
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(
        dir.join("p.patch"),
        "type patch\npatches 1\npatch 0\nheight 1\nwidth 1\nmap\n.\n",
    )
    .unwrap();
    std::fs::write(
        dir.join("s.scen"),
        "version 2\nheight 3\nwidth 3\ncost 1 octile\npatch p.patch\ncommands\nP 0 0 0 0\nQ 0 0 0 1 1 1.4142135624\n",
    )
    .unwrap();
    std::fs::write(
        dir.join("g.toml"),
        "kind = \"dynamic\"\nname = \"g\"\ncompare = [\"astar\"]\n[[gppc]]\nscen = \"s.scen\"\n",
    )
    .unwrap();
    let out = dir.join("out");
    let area = dir.join(".out.stream");
    std::fs::create_dir_all(&area).unwrap();
    std::fs::write(
        area.join(planner_runner::outdir::STREAM_MARKER),
        "# Written by gridplan\n",
    )
    .unwrap();
    for table in ["runs.csv", "runs.jsonl", "replans.jsonl", "run-0.later"] {
        std::fs::write(area.join(table), "").unwrap();
    }
    std::fs::write(dir.join(".out.stream.lock"), "12345\n").unwrap();
    let done = experiment::run(&dir.join("g.toml"), &out, &test_options(1)).unwrap();
    assert_eq!(done.runs, 1);
    assert_eq!(beside(&out), Vec::<String>::new());
}

/// Writes into `dir` a 4 x 4 GPPC scenario `s.scen` (patches `p.patch`) of two batches of
/// three queries, the second after walls at (1, 1) and (2, 1), and `g.toml`, a dynamic
/// config replaying it with D* Lite and A*, every query checked and carried.
fn small_gppc(dir: &Path) {
    std::fs::create_dir_all(dir).unwrap();
    std::fs::write(
        dir.join("p.patch"),
        "type patch\npatches 2\npatch 0\nheight 4\nwidth 4\nmap\n....\n....\n....\n....\npatch 1\nheight 1\nwidth 2\nmap\n@@\n",
    )
    .unwrap();
    std::fs::write(
        dir.join("s.scen"),
        "version 2\nheight 4\nwidth 4\ncost 1 octile\npatch p.patch\ncommands\nP 0 0 0 0\n\
         Q 0 0 0 3 3 4.2426406871\nQ 0 0 1 3 1 3\nQ 0 0 3 3 0 4.2426406871\n\
         P 1 1 1 1\nQ 1 0 0 3 3 5.4142135624\nQ 1 0 1 3 1 5\nQ 1 0 3 3 0 5.4142135624\n",
    )
    .unwrap();
    std::fs::write(
        dir.join("g.toml"),
        "kind = \"dynamic\"\nname = \"g\"\ncompare = [\"dstar_lite\", \"astar\"]\n[[gppc]]\nscen = \"s.scen\"\nquery_every = 1\ncarry_every = 1\n",
    )
    .unwrap();
}

/// A GPPC replay's counts agree everywhere: the command line's (the returned summary),
/// summary.md's head and its table. A replay (a scenario file and a planner) is a run, its
/// carried queries its replans, its checked queries counted apart. summary.md's head read
/// "0 runs, 0 replans" before while the command line said 4 runs.
#[test]
fn gppc_counts_agree_in_every_output() {
    let dir = scratch("gppc-counts");
    small_gppc(&dir);
    let out = dir.join("out");
    let done = experiment::run(&dir.join("g.toml"), &out, &test_options(1)).unwrap();
    // Two replays; each checks 6 queries and carries the first batch's 3.
    assert_eq!((done.runs, done.replans, done.mismatches), (2, 6, 0));
    assert_eq!(done.queries, 12);
    let summary = read(&out, "summary.md");
    assert!(
        summary.contains(
            "Kind `dynamic` (test limits): 2 runs (2 of them GPPC replays), 6 replans (6 of them GPPC queries carried across the next batch's patches), each checked against A* from scratch on the same map, and 12 GPPC queries checked against their recorded optimum: **0 mismatches**."
        ),
        "{summary}"
    );
    let rows: Vec<&str> = summary.lines().filter(|l| l.starts_with("| s |")).collect();
    assert_eq!(rows.len(), done.runs, "{summary}");
    for row in rows {
        let cells: Vec<&str> = row.split('|').map(str::trim).collect();
        // | scenario | planner | patches | queries | agree | carried | mismatches | ...
        assert_eq!(
            (cells[4], cells[5], cells[6], cells[7]),
            ("6", "6", "3", "0"),
            "{row}"
        );
    }
}

/// A GPPC replay that carries no query (`carry_every = 0`) measured no repair: gppc.csv's
/// expansion columns are empty and summary.md shows `-` there (they said 0, which a mean
/// would count).
#[test]
fn gppc_expansions_are_empty_when_no_query_is_carried() {
    let dir = scratch("gppc-uncarried");
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(
        dir.join("p.patch"),
        "type patch\npatches 1\npatch 0\nheight 1\nwidth 1\nmap\n@\n",
    )
    .unwrap();
    std::fs::write(
        dir.join("s.scen"),
        "version 2\nheight 3\nwidth 3\ncost 1 octile\npatch p.patch\ncommands\n\
         Q 0 0 0 2 2 2.8284271247\nP 1 0 1 1\nQ 1 0 0 2 2 4\n",
    )
    .unwrap();
    std::fs::write(
        dir.join("g.toml"),
        "kind = \"dynamic\"\nname = \"g\"\ncompare = [\"dstar_lite\"]\n[[gppc]]\nscen = \"s.scen\"\ncarry_every = 0\n",
    )
    .unwrap();
    let out = dir.join("out");
    let done = experiment::run(&dir.join("g.toml"), &out, &test_options(1)).unwrap();
    assert_eq!(
        (done.runs, done.replans, done.queries, done.mismatches),
        (1, 0, 2, 0)
    );
    let table = read(&out, "gppc.csv");
    assert_eq!(column(&table, "carried"), vec!["0"], "{table}");
    for name in ["repair_expansions", "astar_expansions", "first_expansions"] {
        assert_eq!(column(&table, name), vec![""], "{name}: {table}");
    }
    let summary = read(&out, "summary.md");
    assert!(
        summary.contains("| s | dstar_lite | 1 | 2 | 2 | 0 | 0 | - | - | - |"),
        "{summary}"
    );
}

/// A GPPC scenario's command that names a patch the patch file lacks, places a patch
/// outside the map, or asks a query from outside it, is an error at the line and column
/// of the field: the patch number, the `x` or `y`, the coordinate. They named the line
/// alone before.
#[test]
fn gppc_command_errors_name_their_column() {
    let dir = scratch("gppc-columns");
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(
        dir.join("p.patch"),
        "type patch\npatches 2\npatch 0\nheight 4\nwidth 4\nmap\n....\n....\n....\n....\npatch 1\nheight 2\nwidth 2\nmap\n@@\n@@\n",
    )
    .unwrap();
    std::fs::write(
        dir.join("g.toml"),
        "kind = \"dynamic\"\nname = \"g\"\ncompare = [\"astar\"]\n[[gppc]]\nscen = \"s.scen\"\n",
    )
    .unwrap();
    let out = dir.join("out");
    for (command, column, message) in [
        ("P 1  7 0 0", 6, "patch 7 does not exist"),
        ("P 1 1 3 0", 7, "patch 1 (2x2) placed at (3, 0)"),
        ("P 1 1 0 3", 9, "patch 1 (2x2) placed at (0, 3)"),
        ("P 1 1 9 3", 7, "patch 1 (2x2) placed at (9, 3)"),
        ("Q 1 5 0 3 3 1", 5, "start (5, 0)"),
        ("\u{3000}Q 1 0 9 3 3 1", 8, "start (0, 9)"),
        ("Q 1 0 0 3 12 1", 11, "goal (3, 12)"),
        ("Q 1 0 0 30 1 1\r", 9, "goal (30, 1)"),
    ] {
        std::fs::write(
            dir.join("s.scen"),
            format!("version 2\nheight 4\nwidth 4\ncost 1 octile\npatch p.patch\ncommands\nP 0 0 0 0\n{command}\n"),
        )
        .unwrap();
        let e = experiment::run(&dir.join("g.toml"), &out, &test_options(1)).unwrap_err();
        match &e {
            ExperimentError::Map(m) => {
                assert_eq!((m.line, m.column), (8, column), "{command:?}: {e}");
                assert!(m.file.ends_with("s.scen"), "{e}");
            }
            other => panic!("{command:?}: expected a map error, got {other}"),
        }
        assert!(e.to_string().contains(message), "{e}");
    }
    assert!(!out.exists());
}

/// `[toggles] events` beyond `MAX_EVENTS` is refused at its line and column before anything
/// runs: 4,294,967,295 events was accepted, a run that would write over a terabyte.
#[test]
fn too_many_events_are_refused() {
    let base = "kind = \"dynamic\"\nname = \"e\"\n[[maps]]\nmap = \"a.map\"\nscen = \"a.scen\"\n[toggles]\nk = 5\nradius = 5\nseeds = [1]\nevents = ";
    assert!(experiment::parse(Path::new("e.toml"), &format!("{base}1000000\n")).is_ok());
    let e = parse_error(&format!("{base}1000001\n"));
    match &e {
        ExperimentError::Invalid {
            line, column, key, ..
        } => assert_eq!((*line, *column, key.as_str()), (10, 10, "events"), "{e}"),
        other => panic!("expected an invalid value, got {other}"),
    }
    assert!(
        e.to_string().contains("more than the limit of 1000000"),
        "{e}"
    );
    let e = parse_error(&format!("{base}4294967295\n"));
    assert!(e.to_string().starts_with("bad.toml:10:10: `events`"), "{e}");
}

/// A planner that finds no path: every replan where there is one fails its check.
fn lost(name: &str, eight: bool) -> Box<dyn IncrementalPlanner> {
    struct Lost;
    impl Change for Lost {
        fn replan(&mut self, _: &mut dyn IncrementalPlanner, _: &Budget) -> Outcome {
            Outcome::no_path(Counters::new().with("n_expanded", 0))
        }
    }
    Box::new(Wrapped {
        inner: planner_replan::planners::by_name(name, eight).unwrap(),
        change: Lost,
    })
}

/// A run whose every replan fails its check keeps the messages of its first
/// `MISMATCHES_LISTED` (runs.jsonl, summary.md), counts them all (runs.csv, the summary's
/// head) and marks every failed replan's line in replans.jsonl with its `mismatch`: a
/// broken planner's messages do not fill the memory. They were all kept before.
#[test]
fn a_runs_mismatches_are_counted_and_the_first_listed() {
    let dir = scratch("mismatches");
    std::fs::create_dir_all(&dir).unwrap();
    let arena = root().join("maps/movingai/arena.map");
    let path = dir.join("m.toml");
    std::fs::write(
        &path,
        format!(
            "kind = \"dynamic\"\nname = \"m\"\ncompare = [\"astar\"]\n[[maps]]\nmap = {:?}\nscen = {:?}\nscenarios = 1\n[toggles]\nevents = 149\nk = 1\nradius = 0\nseeds = [1]\n",
            arena.display().to_string(),
            format!("{}.scen", arena.display())
        ),
    )
    .unwrap();
    let config = experiment::load(&path).unwrap();
    let out = dir.join("out");
    let done = experiment::run_config_with(&config, &path, &out, &test_options(1), &lost).unwrap();
    let failed = done.mismatches;
    assert!(
        failed > experiment::MISMATCHES_LISTED as u64,
        "{failed} mismatches"
    );
    let csv = read(&out, "runs.csv");
    assert_eq!(
        column(&csv, "mismatches"),
        vec![failed.to_string()],
        "{csv}"
    );
    let run: serde_json::Value = serde_json::from_str(read(&out, "runs.jsonl").trim()).unwrap();
    assert_eq!(
        run["mismatch_messages"].as_array().unwrap().len(),
        experiment::MISMATCHES_LISTED
    );
    assert_eq!(run["mismatches"], failed);
    let marked = read(&out, "replans.jsonl")
        .lines()
        .filter(|l| {
            let line: serde_json::Value = serde_json::from_str(l).unwrap();
            line["mismatch"].is_string()
        })
        .count();
    assert_eq!(marked as u64, failed);
    let summary = read(&out, "summary.md");
    assert_eq!(
        summary.matches("- MISMATCH ").count(),
        experiment::MISMATCHES_LISTED,
        "{summary}"
    );
    let more = format!(
        "- and {} more mismatches",
        failed - experiment::MISMATCHES_LISTED as u64
    );
    assert!(summary.contains(&more), "{summary}");
    assert!(
        summary.contains(&format!("**{failed} mismatches**")),
        "{summary}"
    );
}

/// A stop raised once the runs are done, while the results are being written, still ends
/// the experiment `Interrupted` with the output as it was: the tables' copy into the new
/// directory looks at the flag between blocks. The experiment is held at the output's
/// lock (taken here by another write, blocked in its writer) until the flag is raised. It
/// wrote the results and returned them before, a Ctrl-C during a large table's copy unheard.
#[test]
fn a_stop_while_the_results_are_written_leaves_the_output_as_it_was() {
    use std::sync::atomic::{AtomicBool, Ordering};
    use std::sync::mpsc;
    static STOP: AtomicBool = AtomicBool::new(false);
    let dir = scratch("stop-in-write");
    std::fs::create_dir_all(&dir).unwrap();
    let arena = root().join("maps/movingai/arena.map");
    let path = dir.join("w.toml");
    std::fs::write(
        &path,
        format!(
            "kind = \"dynamic\"\nname = \"w\"\ncompare = [\"astar\"]\n[[maps]]\nmap = {:?}\nscen = {:?}\nscenarios = 2\n[toggles]\nevents = 5\nk = 2\nradius = 3\nseeds = [1]\n",
            arena.display().to_string(),
            format!("{}.scen", arena.display())
        ),
    )
    .unwrap();
    let config = experiment::load(&path).unwrap();
    let out = dir.join("out");
    let (held, release) = (mpsc::channel::<()>(), mpsc::channel::<()>());
    let holder = {
        let out = out.clone();
        let (held, release) = (held.0, release.1);
        std::thread::spawn(move || {
            let blocked = planner_runner::output::StreamedFile {
                path: PathBuf::from("t.csv"),
                write: Box::new(move |_| {
                    held.send(()).unwrap();
                    release.recv().unwrap();
                    Err(planner_runner::RunnerError::io(
                        Path::new("t.csv"),
                        std::io::Error::other("the holder gives up"),
                    ))
                }),
            };
            planner_runner::outdir::write_results_streamed(
                &out,
                "holder",
                &[],
                &[blocked],
                std::time::Duration::from_secs(60),
            )
        })
    };
    held.1.recv().unwrap();
    let experiment = {
        let (config, path, out) = (config.clone(), path.clone(), out.clone());
        std::thread::spawn(move || {
            let options = RunOptions {
                stop: Some(&STOP),
                ..test_options(1)
            };
            experiment::run_config(&config, &path, &out, &options)
        })
    };
    // The tables are complete (flushed into the working area) once runs.csv holds them.
    let runs = dir.join(".out.stream").join("runs.csv");
    let started = std::time::Instant::now();
    while std::fs::read_to_string(&runs).map_or(0, |t| t.lines().count()) < 3 {
        assert!(started.elapsed().as_secs() < 60, "the runs did not end");
        std::thread::sleep(std::time::Duration::from_millis(5));
    }
    STOP.store(true, Ordering::SeqCst);
    release.0.send(()).unwrap();
    assert!(holder.join().unwrap().is_err());
    let e = experiment.join().unwrap().unwrap_err();
    assert!(matches!(e, ExperimentError::Interrupted), "{e}");
    assert!(!out.exists(), "the output was written");
    assert_eq!(beside(&out), Vec::<String>::new(), "left beside the output");
}

/// `w.map` (7 x 3, its middle cell (3, 1) blocked) and `w.map.scen` with `lines` (after
/// the version line) in `dir`.
fn wall_map(dir: &Path, lines: &[&str]) {
    std::fs::create_dir_all(dir).unwrap();
    std::fs::write(
        dir.join("w.map"),
        "type octile\nheight 3\nwidth 7\nmap\n.......\n...@...\n.......\n",
    )
    .unwrap();
    let scen: String = lines.iter().map(|l| format!("{l}\n")).collect();
    std::fs::write(dir.join("w.map.scen"), format!("version 1\n{scen}")).unwrap();
}

/// A sensor radius of 0 is refused at its line and column: the robot of the D* Lite
/// paper's experiments senses its neighbours. A radius of 0 was run, and drove through
/// walls.
#[test]
fn a_radius_of_zero_is_refused_at_its_line_and_column() {
    let base = "kind = \"navigate\"\nname = \"x\"\n[[maps]]\nmap = \"a.map\"\nscen = \"a.scen\"\n";
    assert!(experiment::parse(Path::new("r.toml"), &format!("radii = [1, 5]\n{base}")).is_ok());
    let e = parse_error(&format!("radii = [1, 0]\n{base}"));
    match &e {
        ExperimentError::Invalid {
            line, column, key, ..
        } => assert_eq!((*line, *column, key.as_str()), (1, 13, "radii"), "{e}"),
        other => panic!("expected an invalid value, got {other}"),
    }
    assert!(e.to_string().contains("at least 1"), "{e}");
}

/// A toggle script's runs.csv and runs.jsonl give the cells the agent drove (`steps`: it
/// wrote 0), and leave `reached` empty (absent in JSON): a script ends after its events,
/// not at the goal, so a 0 or `false` there would not be a measurement.
#[test]
fn a_toggle_scripts_steps_are_the_cells_driven() {
    let dir = scratch("toggle-steps");
    wall_map(&dir, &["0\tw.map\t7\t3\t0\t0\t6\t2\t6.82842712"]);
    let path = dir.join("t.toml");
    std::fs::write(
        &path,
        "kind = \"dynamic\"\nname = \"t\"\ncompare = [\"dstar_lite\"]\n[toggles]\nevents = 2\nk = 0\nradius = 0\ndrive = 2\nseeds = [1]\n[[maps]]\nmap = \"w.map\"\nscen = \"w.map.scen\"\nscenarios = 1\n",
    )
    .unwrap();
    let out = dir.join("out");
    experiment::run(&path, &out, &test_options(1)).unwrap();
    // Two events, two cells each, on a path of 6 moves with nothing toggled.
    let csv = read(&out, "runs.csv");
    assert_eq!(column(&csv, "steps"), vec!["4"], "{csv}");
    assert_eq!(column(&csv, "reached"), vec![""], "{csv}");
    assert_eq!(column(&csv, "status"), vec!["ran"], "{csv}");
    let run: serde_json::Value = serde_json::from_str(read(&out, "runs.jsonl").trim()).unwrap();
    assert_eq!(run["steps"], 4);
    assert!(run.get("reached").is_none(), "{run}");
}

/// A scenario whose goal is blocked is a run with status `invalid_problem` per setting
/// and planner, its `error` naming the `.scen` file, line and column of the goal, and
/// the other scenarios run: the whole experiment stopped at it before, its error without
/// a column. Nothing is measured for it, so its measurement fields are empty (null in
/// JSON), and summary.md counts and lists it once. Both kinds.
#[test]
fn a_blocked_goal_is_an_invalid_problem_and_the_other_runs_go_on() {
    let dir = scratch("invalid-problem");
    wall_map(
        &dir,
        &[
            "0\tw.map\t7\t3\t0\t1\t6\t1\t6",
            "0\tw.map\t7\t3\t0\t0\t3\t1\t3",
            "0\tw.map\t7\t3\t0\t2\t6\t2\t6",
        ],
    );
    let maps = "[[maps]]\nmap = \"w.map\"\nscen = \"w.map.scen\"\nscenarios = 3\n";
    for (kind, setting) in [
        ("navigate", "radii = [1, 2]\n"),
        (
            "dynamic",
            "[toggles]\nevents = 2\nk = 1\nradius = 1\nseeds = [1, 2]\n",
        ),
    ] {
        let path = dir.join(format!("{kind}.toml"));
        std::fs::write(
            &path,
            format!("kind = \"{kind}\"\nname = \"i\"\ncompare = [\"dstar_lite\", \"astar\"]\n{setting}{maps}"),
        )
        .unwrap();
        let out = dir.join(format!("out-{kind}"));
        let options = RunOptions {
            timing: true,
            ..test_options(2)
        };
        let done = experiment::run(&path, &out, &options).unwrap();
        assert_eq!((done.runs, done.mismatches), (12, 0), "{kind}");
        let csv = read(&out, "runs.csv");
        let status = column(&csv, "status");
        let invalid: Vec<usize> = (0..12)
            .filter(|&i| status[i] == "invalid_problem")
            .collect();
        assert_eq!(invalid, vec![4, 5, 6, 7], "{kind}: {csv}");
        assert!(
            status.iter().filter(|s| *s == "ran").count() == 8,
            "{kind}: {csv}"
        );
        let lines: Vec<&str> = csv.lines().skip(1).collect();
        // The goal's x is on column 17 of the scenario's line 3.
        let error = format!(
            "{}:3:17: goal (3, 1) is blocked",
            dir.join("w.map.scen").display()
        );
        for &i in &invalid {
            // Scenario line 3; reached, steps, replans, expansions, A*'s and mismatches
            // empty; the error quoted (it has a comma); both times empty.
            let (head, tail) = lines[i].split_once(",invalid_problem,").unwrap();
            assert!(
                head.starts_with("w,3,") && head.ends_with(",,,,,,"),
                "{kind}: {}",
                lines[i]
            );
            assert_eq!(tail, format!("\"{error}\",,"), "{kind}");
        }
        for i in (0..12).filter(|i| !invalid.contains(i)) {
            let fields: Vec<&str> = lines[i].split(',').collect();
            assert_eq!(fields.len(), 14, "{kind}: {}", lines[i]);
            assert!(
                fields[5..10].iter().all(|f| !f.is_empty()),
                "{kind}: {}",
                lines[i]
            );
            assert!(fields[11].is_empty(), "{kind}: {}", lines[i]);
        }
        let runs: Vec<serde_json::Value> = read(&out, "runs.jsonl")
            .lines()
            .map(|l| serde_json::from_str(l).unwrap())
            .collect();
        assert_eq!(runs.len(), 12);
        for run in &runs[4..8] {
            assert_eq!(run["status"], "invalid_problem", "{run}");
            assert_eq!(run["error"], error.as_str(), "{run}");
            assert!(
                run["replans"].is_null() && run["total_expansions"].is_null(),
                "{run}"
            );
            assert!(run.get("steps").is_none() && run.get("planning_time_us").is_none());
        }
        let summary = read(&out, "summary.md");
        assert!(
            summary.contains("12 runs (4 of them on 1 invalid problem, which did not run: listed below, in no table row)"),
            "{summary}"
        );
        assert_eq!(
            summary.matches("- INVALID PROBLEM w: ").count(),
            1,
            "{summary}"
        );
        assert!(summary.contains(&error), "{summary}");
        // The groups count the runs that ran: two scenarios each.
        assert!(summary.contains("| w | 1 | dstar_lite | 2 |"), "{summary}");
    }
}

/// A GPPC scenario naming a patch file that is not there is an error at the scenario's
/// line and column where it names it (it named the missing file alone), before anything
/// is written.
#[test]
fn a_missing_patch_file_is_an_error_where_the_scenario_names_it() {
    let dir = scratch("gppc-missing-patch");
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(
        dir.join("g.toml"),
        "kind = \"dynamic\"\nname = \"g\"\n[[gppc]]\nscen = \"s.scen\"\n",
    )
    .unwrap();
    std::fs::write(
        dir.join("s.scen"),
        "version 2\nheight 3\nwidth 3\ncost 1 octile\npatch   nope.patch\r\ncommands\nQ 0 0 0 1 1 1.4142135624\n",
    )
    .unwrap();
    let out = dir.join("out");
    let e = experiment::run(&dir.join("g.toml"), &out, &test_options(1)).unwrap_err();
    match &e {
        ExperimentError::Map(m) => {
            assert!(m.file.ends_with("s.scen"), "{e}");
            assert_eq!((m.line, m.column), (5, 9), "{e}");
        }
        other => panic!("expected a map error, got {other}"),
    }
    let message = e.to_string();
    let resolved = dir.join("nope.patch").display().to_string();
    assert!(
        message.contains(&format!("patch file 'nope.patch' ({resolved}): ")),
        "{e}"
    );
    assert!(!out.exists());
}

/// An invalid problem's `error` places the coordinate at fault: the start's or goal's x,
/// or its y when only the y is outside the map (past a field's leading spaces, as
/// planner-maps counts columns).
#[test]
fn an_invalid_problems_error_names_the_column_of_its_coordinate() {
    let dir = scratch("invalid-columns");
    wall_map(
        &dir,
        &[
            "0\tw.map\t7\t3\t0\t9\t6\t1\t6",
            "0\tw.map\t7\t3\t3\t1\t6\t1\t6",
            "0\tw.map\t7\t3\t0\t0\t 12\t1\t6",
        ],
    );
    let path = dir.join("c.toml");
    std::fs::write(
        &path,
        "kind = \"navigate\"\nname = \"c\"\ncompare = [\"astar\"]\nradii = [1]\n[[maps]]\nmap = \"w.map\"\nscen = \"w.map.scen\"\nscenarios = 3\n",
    )
    .unwrap();
    let out = dir.join("out");
    experiment::run(&path, &out, &test_options(1)).unwrap();
    let errors: Vec<String> = read(&out, "runs.jsonl")
        .lines()
        .map(|l| serde_json::from_str::<serde_json::Value>(l).unwrap()["error"].to_string())
        .collect();
    let scen = dir.join("w.map.scen").display().to_string();
    assert_eq!(
        errors,
        [
            format!("\"{scen}:2:15: start (0, 9) is outside the 7x3 grid\""),
            format!("\"{scen}:3:13: start (3, 1) is blocked\""),
            format!("\"{scen}:4:18: goal (12, 1) is outside the 7x3 grid\""),
        ]
    );
}

/// A radius or a seed listed twice is refused at the repeat's line and column, naming
/// it, as a planner listed twice in `compare` is: both were run twice, and runs.csv held
/// every (map, line, radius or seed, planner) key twice.
#[test]
fn a_radius_or_seed_listed_twice_is_refused_at_its_line_and_column() {
    let base = "kind = \"navigate\"\nname = \"x\"\n[[maps]]\nmap = \"a.map\"\nscen = \"a.scen\"\n";
    let e = parse_error(&format!("radii = [1, 3, 1]\n{base}"));
    assert_eq!(
        e.to_string(),
        "bad.toml:1:16: `radii`: radius 1 is listed twice: its runs would have the same identity"
    );
    let dynamic = "kind = \"dynamic\"\nname = \"x\"\n[[maps]]\nmap = \"a.map\"\nscen = \"a.scen\"\n[toggles]\nevents = 1\nk = 1\nradius = 1\n";
    assert!(experiment::parse(Path::new("ok.toml"), &format!("{dynamic}seeds = [1, 2]\n")).is_ok());
    let e = parse_error(&format!("{dynamic}seeds = [7,\n  2, 7]\n"));
    assert_eq!(
        e.to_string(),
        "bad.toml:11:6: `seeds`: seed 7 is listed twice: its runs would have the same identity"
    );
}

/// An empty `seeds` of `[toggles]` is refused at the key's value, not at the table's
/// header (it said `bad.toml:6:1`), and `[[maps]]` without `[toggles]` at the maps (it
/// named no line).
#[test]
fn an_empty_list_in_a_table_is_refused_at_its_value() {
    let dynamic = "kind = \"dynamic\"\nname = \"x\"\n[[maps]]\nmap = \"a.map\"\nscen = \"a.scen\"\n[toggles]\nevents = 1\nk = 1\nradius = 1\n";
    let e = parse_error(&format!("{dynamic}seeds = []\n"));
    assert_eq!(
        e.to_string(),
        "bad.toml:10:9: `seeds`: name at least one seed"
    );
    let e = parse_error("kind = \"dynamic\"\nname = \"x\"\n[[maps]]\nmap = \"a.map\"\nscen = \"a.scen\"\n[[gppc]]\nscen = \"g.scen\"\n");
    assert!(
        matches!(&e, ExperimentError::Invalid { line: 3, key, .. } if key == "maps"),
        "{e}"
    );
}

/// A GPPC replay is a run and its carried queries are replans in the tables too: a line
/// of runs.csv and runs.jsonl per replay and a line of replans.jsonl per carried query,
/// so that the tables' lines are the counts the command line and summary.md give. A
/// GPPC-only config wrote summary.md and gppc.csv alone, and with `[toggles]` the tables
/// left the replays out (52 runs said, 48 lines).
#[test]
fn gppc_replays_are_runs_in_every_table() {
    let dir = scratch("gppc-tables");
    small_gppc(&dir);
    let out = dir.join("out");
    let done = experiment::run(&dir.join("g.toml"), &out, &test_options(1)).unwrap();
    assert_eq!((done.runs, done.replans, done.mismatches), (2, 6, 0));
    let runs = read(&out, "runs.csv");
    assert_eq!(runs.lines().count(), 1 + done.runs, "{runs}");
    assert_eq!(column(&runs, "map"), vec!["s", "s"], "{runs}");
    assert_eq!(
        column(&runs, "planner"),
        vec!["dstar_lite", "astar"],
        "{runs}"
    );
    assert_eq!(column(&runs, "scenario_line"), vec!["", ""], "{runs}");
    assert_eq!(column(&runs, "replans"), vec!["3", "3"], "{runs}");
    assert_eq!(column(&runs, "status"), vec!["ran", "ran"], "{runs}");
    assert_eq!(column(&runs, "mismatches"), vec!["0", "0"], "{runs}");
    // The expansions are gppc.csv's sums over the carried queries.
    let gppc = read(&out, "gppc.csv");
    assert_eq!(
        column(&runs, "total_expansions"),
        column(&gppc, "repair_expansions"),
        "{runs}{gppc}"
    );
    assert_eq!(
        column(&runs, "astar_expansions"),
        column(&gppc, "astar_expansions"),
        "{runs}{gppc}"
    );
    let jsonl = read(&out, "runs.jsonl");
    assert_eq!(jsonl.lines().count(), done.runs, "{jsonl}");
    let replans: Vec<serde_json::Value> = read(&out, "replans.jsonl")
        .lines()
        .map(|l| serde_json::from_str(l).unwrap())
        .collect();
    assert_eq!(replans.len() as u64, done.replans);
    // The first batch's three queries, carried by each planner.
    let lines: Vec<u64> = replans
        .iter()
        .map(|r| r["query_line"].as_u64().unwrap())
        .collect();
    assert_eq!(lines, vec![8, 9, 10, 8, 9, 10]);
    assert!(
        replans
            .iter()
            .all(|r| r["status"] == "found" && r["astar_expansions"].is_u64()),
        "{replans:?}"
    );
}

/// A scratch directory `name` with a GPPC patch file and one scenario `NAME.scen` per
/// `(NAME, side)`, each declaring a `side` x `side` map and the same two batches of 4 x 4
/// patches and queries.
fn gppc_scenarios(name: &str, scenarios: &[(&str, u32)]) -> PathBuf {
    let dir = scratch(name);
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(
        dir.join("p.patch"),
        "type patch\npatches 2\npatch 0\nheight 4\nwidth 4\nmap\n....\n....\n....\n....\npatch 1\nheight 1\nwidth 2\nmap\n@@\n",
    )
    .unwrap();
    let commands = "cost 1 octile\npatch p.patch\ncommands\nP 0 0 0 0\n\
         Q 0 0 0 3 3 4.2426406871\nP 1 1 1 1\nQ 1 0 0 3 3 5.4142135624\n";
    for (stem, side) in scenarios {
        std::fs::write(
            dir.join(format!("{stem}.scen")),
            format!("version 2\nheight {side}\nwidth {side}\n{commands}"),
        )
        .unwrap();
    }
    dir
}

/// Without `max_memory_mb`, a GPPC scenario declaring a map whose per-cell state is over
/// half the machine's memory (46,000 cells a side, within the reader's 2^31 cells: about
/// 58 GB) is recorded `over_memory` against the runner's default budget, and the other
/// replay runs; it aborted the process on the failed allocation.
#[test]
fn a_gppc_map_over_half_the_machines_memory_is_refused_without_a_budget() {
    let side = 46_000;
    let needed = planner_replan::gppc::memory_bytes(side, side, true);
    match planner_runner::run::default_max_memory_mb() {
        Some(mb) if needed > mb.saturating_mul(1 << 20) => {}
        _ => {
            eprintln!("skipped: this machine's memory is unknown or would hold the map");
            return;
        }
    }
    let dir = gppc_scenarios("gppc-default-memory", &[("s", 4), ("huge", side)]);
    let config = "kind = \"dynamic\"\nname = \"g\"\ncompare = [\"dstar_lite\"]\n[[gppc]]\nscen = \"s.scen\"\ncarry_every = 1\n[[gppc]]\nscen = \"huge.scen\"\ncarry_every = 1\n";
    std::fs::write(dir.join("g.toml"), config).unwrap();
    let out = dir.join("out");
    let done = experiment::run(&dir.join("g.toml"), &out, &test_options(1)).unwrap();
    assert_eq!((done.runs, done.replans), (2, 1));
    let runs = read(&out, "runs.csv");
    assert_eq!(
        column(&runs, "status"),
        vec!["ran", "over_memory"],
        "{runs}"
    );
    assert!(
        runs.contains("46000 x 46000 grid, over the max_memory_mb = "),
        "{runs}"
    );
}

/// A GPPC scenario declaring a map whose per-cell state is over `max_memory_mb` is
/// recorded as refused (`over_memory`, with the shortfall) and its map never made; the
/// other replays run. A 20000 x 20000 declaration with one small patch made the A* oracle
/// allocate 3.2 GB for the whole map and aborted the process.
#[test]
fn a_gppc_map_over_the_memory_budget_is_refused() {
    let dir = gppc_scenarios("gppc-memory", &[("s", 4), ("big", 20_000)]);
    let config = "kind = \"dynamic\"\nname = \"g\"\ncompare = [\"dstar_lite\"]\nmax_memory_mb = 100\n[[gppc]]\nscen = \"s.scen\"\ncarry_every = 1\n[[gppc]]\nscen = \"big.scen\"\ncarry_every = 1\n";
    std::fs::write(dir.join("g.toml"), config).unwrap();
    let out = dir.join("out");
    let done = experiment::run(&dir.join("g.toml"), &out, &test_options(1)).unwrap();
    assert_eq!((done.runs, done.replans, done.queries), (2, 1, 2));
    let runs = read(&out, "runs.csv");
    assert_eq!(
        column(&runs, "status"),
        vec!["ran", "over_memory"],
        "{runs}"
    );
    assert!(
        runs.contains(",over_memory,\"big: needs ")
            && runs.contains("20000 x 20000 grid, over the max_memory_mb = 100 budget\""),
        "{runs}"
    );
    assert_eq!(column(&runs, "replans")[1], "", "{runs}");
    let summary = read(&out, "summary.md");
    assert!(summary.contains("- OVER MEMORY big: needs "), "{summary}");
    assert!(
        summary.contains("| big | dstar_lite | - | - | - | - | - | - | - | - |"),
        "{summary}"
    );
    let e = parse_error(&config.replace("max_memory_mb = 100", "max_memory_mb = 0"));
    assert_eq!(
        e.to_string(),
        "bad.toml:4:17: `max_memory_mb`: must be at least 1"
    );
}

/// The lines of a CSV `table`, each split into its fields (RFC 4180: a quoted field may
/// hold commas, doubled quotes and line breaks).
fn csv_rows(table: &str) -> Vec<Vec<String>> {
    let (mut rows, mut row, mut field) = (Vec::new(), Vec::new(), String::new());
    let (mut quoted, mut chars) = (false, table.chars().peekable());
    while let Some(c) = chars.next() {
        match (quoted, c) {
            (true, '"') if chars.peek() == Some(&'"') => {
                chars.next();
                field.push('"');
            }
            (true, '"') => quoted = false,
            (true, c) => field.push(c),
            (false, '"') => quoted = true,
            (false, ',') => row.push(std::mem::take(&mut field)),
            (false, '\n') => {
                row.push(std::mem::take(&mut field));
                rows.push(std::mem::take(&mut row));
            }
            (false, c) => field.push(c),
        }
    }
    assert!(
        field.is_empty() && row.is_empty(),
        "{table:?} ends mid-line"
    );
    rows
}

/// Checks that every line of `out`'s runs.jsonl holds every column of the same line of
/// runs.csv under the column's name, with the same value: an empty field is `null` or no
/// key, a string the field's text, a number or boolean its decimal or `true`/`false`.
fn assert_runs_jsonl_has_runs_csv(out: &Path) {
    let rows = csv_rows(&read(out, "runs.csv"));
    let (header, rows) = rows.split_first().unwrap();
    let lines: Vec<serde_json::Value> = read(out, "runs.jsonl")
        .lines()
        .map(|l| serde_json::from_str(l).unwrap())
        .collect();
    assert_eq!(lines.len(), rows.len(), "{}", out.display());
    for (row, line) in rows.iter().zip(&lines) {
        assert_eq!(row.len(), header.len(), "{row:?}");
        for (column, field) in header.iter().zip(row) {
            let value = line.get(column).unwrap_or(&serde_json::Value::Null);
            let text = match value {
                serde_json::Value::Null => String::new(),
                serde_json::Value::String(s) => s.clone(),
                serde_json::Value::Number(_) | serde_json::Value::Bool(_) => value.to_string(),
                other => panic!("`{column}` is {other} in runs.jsonl, a value in runs.csv"),
            };
            assert_eq!(
                &text, field,
                "`{column}`: runs.jsonl's {value} against runs.csv's {field:?} in {line}"
            );
        }
    }
}

/// Every column of runs.csv is in runs.jsonl under its name with the same value, for
/// every kind of line (navigations, toggle scripts, runs of an invalid problem, GPPC
/// replays, one over the memory budget, runs with failed checks) with and without times:
/// runs.jsonl had no `time_to_first_move_us`, and its `mismatches` were the first 100
/// messages instead of the count (now `mismatch_messages`).
#[test]
fn runs_jsonl_has_every_runs_csv_column_with_its_value() {
    let dir = gppc_scenarios("jsonl-columns", &[("s", 4), ("big", 20_000)]);
    wall_map(
        &dir,
        &[
            "0\tw.map\t7\t3\t0\t1\t6\t1\t6",
            "0\tw.map\t7\t3\t0\t0\t3\t1\t3",
            "0\tw.map\t7\t3\t0\t2\t6\t2\t6",
        ],
    );
    let head = "name = \"c\"\ncompare = [\"dstar_lite\", \"astar\"]\n";
    let maps = "[[maps]]\nmap = \"w.map\"\nscen = \"w.map.scen\"\nscenarios = 3\n";
    let configs = [
        ("navigate", format!("kind = \"navigate\"\n{head}radii = [1, 2]\n{maps}")),
        (
            "dynamic",
            format!(
                "kind = \"dynamic\"\n{head}max_memory_mb = 100\n[toggles]\nevents = 2\nk = 1\nradius = 1\nseeds = [1]\n{maps}\
                 [[gppc]]\nscen = \"s.scen\"\ncarry_every = 1\n[[gppc]]\nscen = \"big.scen\"\ncarry_every = 1\n"
            ),
        ),
    ];
    for (kind, text) in &configs {
        let path = dir.join(format!("{kind}.toml"));
        std::fs::write(&path, text).unwrap();
        for timing in [false, true] {
            let out = dir.join(format!("out-{kind}-{timing}"));
            let options = RunOptions {
                timing,
                ..test_options(2)
            };
            experiment::run(&path, &out, &options).unwrap();
            let csv = read(&out, "runs.csv");
            assert!(csv.contains(",invalid_problem,"), "{csv}");
            assert_eq!(csv.contains(",time_to_first_move_us,"), timing, "{csv}");
            assert_runs_jsonl_has_runs_csv(&out);
        }
    }
    // Runs whose every replan fails its check.
    let path = dir.join("dynamic.toml");
    let config = experiment::load(&path).unwrap();
    let out = dir.join("out-lost");
    let done = experiment::run_config_with(&config, &path, &out, &test_options(1), &lost).unwrap();
    assert!(done.mismatches > 0);
    assert_runs_jsonl_has_runs_csv(&out);
}

/// A map that is not a Moving AI `.map` (a ROS map, say) is refused at its key, line and
/// column: it was read, its graded costs dropped without a word, and its `.scen` never
/// checked against it.
#[test]
fn a_map_that_is_not_moving_ai_is_refused_at_its_key() {
    let text = |map: &str| {
        format!("kind = \"navigate\"\nname = \"x\"\nradii = [1]\n[[maps]]\nmap = \"{map}\"\nscen = \"a.scen\"\n")
    };
    assert!(experiment::parse(Path::new("m.toml"), &text("maps/a.MAP")).is_ok());
    for map in ["TenByTen-scale.yaml", "m.png", "m.csv", "m.txt", "m"] {
        let e = parse_error(&text(map));
        match &e {
            ExperimentError::Invalid {
                line, column, key, ..
            } => assert_eq!((*line, *column, key.as_str()), (5, 7, "map"), "{e}"),
            other => panic!("expected an invalid value, got {other}"),
        }
        assert!(
            e.to_string()
                .contains(&format!("\"{map}\" is not a Moving AI map (.map)")),
            "{e}"
        );
    }
}

/// A `.scen` file made for a map of another size (another map's) is an error naming the
/// `.scen` file, the line and the column of its width, before anything is written: every
/// problem was recorded as outside the grid, or run on the wrong map.
#[test]
fn a_scenario_for_a_map_of_another_size_is_an_error_at_its_line() {
    let dir = scratch("scen-size");
    wall_map(
        &dir,
        &[
            "0\tw.map\t7\t3\t0\t0\t6\t2\t6.82842712",
            "0\tw.map\t10\t10\t0\t0\t6\t2\t6.82842712",
        ],
    );
    let path = dir.join("n.toml");
    std::fs::write(
        &path,
        "kind = \"navigate\"\nname = \"n\"\ncompare = [\"astar\"]\nradii = [1]\n[[maps]]\nmap = \"w.map\"\nscen = \"w.map.scen\"\nscenarios = 2\n",
    )
    .unwrap();
    let out = dir.join("out");
    let e = experiment::run(&path, &out, &test_options(1)).unwrap_err();
    assert_eq!(
        e.to_string(),
        format!(
            "{}:3:9: the scenario is for a 10x10 map, but the grid is 7x3",
            dir.join("w.map.scen").display()
        )
    );
    assert!(!out.exists());
}
