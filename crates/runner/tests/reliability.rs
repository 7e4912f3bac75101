//! Bad and extreme input to the runner: each case is refused with a positioned error, or
//! handled within bounded time and memory, never accepted silently.

use std::path::{Path, PathBuf};

use planner_runner::config;
use planner_runner::plan::{PlanArgs, DEFAULT_PLAN_EXPANSIONS};
use planner_runner::run::RunList;
use planner_runner::{run_all, RunOptions, RunStatus};

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

fn scratch(name: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join(format!("gridplan-reliability-{name}"));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

fn paper_map() -> String {
    root().join("maps/paper/map01.map").display().to_string()
}

/// The error of a config with `published` pointing at a file holding `published`.
fn published_error(published: &str) -> String {
    // One directory per call: the tests that call it run at once.
    static CALLS: std::sync::atomic::AtomicUsize = std::sync::atomic::AtomicUsize::new(0);
    let call = CALLS.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
    let dir = scratch(&format!("published-{call}"));
    std::fs::write(dir.join("p.toml"), published).unwrap();
    let text = format!(
        "name = \"p\"\npublished = \"p.toml\"\n[[maps]]\nfiles = [{:?}]\nproblems = \"corners\"\n[planners.a]\nplanner = \"astar\"\n",
        paper_map()
    );
    let result = config::parse(&dir.join("c.toml"), &text);
    std::fs::remove_dir_all(&dir).unwrap();
    result
        .err()
        .map(|e| e.to_string().replace(&dir.display().to_string(), "DIR"))
        .unwrap_or_default()
}

#[test]
fn published_values_are_read_strictly() {
    assert_eq!(
        published_error("[map01.astar]\nsteps = \"5\"\n"),
        "DIR/p.toml:2:9: `map01.astar.steps` must be a number, not string"
    );
    assert!(
        published_error("[map01.astar]\nturnz = 1\n")
            .starts_with("DIR/p.toml:2:1: `map01.astar`: unknown metric `turnz`, expected one of steps, turns, score, length, n_expanded"),
        "{}",
        published_error("[map01.astar]\nturnz = 1\n")
    );
    assert!(published_error("[map01]\nastar = 3\n")
        .starts_with("DIR/p.toml:2:1: `map01.astar` must be a table"));
    assert_eq!(
        published_error(&format!(
            "[map01]\nfile = {:?}\n[map01.astar]\nsteps = 10\n",
            paper_map()
        )),
        ""
    );
}

/// A published table or key that names no planner or map is refused where it is: before,
/// `[map01.astr]`, `[mapp01.astar]` and `file = "nothere.map"` were read and their numbers
/// never compared, and summary.md counted them nowhere.
#[test]
fn published_values_naming_nothing_are_refused() {
    assert!(
        published_error("[map01.astr]\nsteps = 10\n")
            .starts_with("DIR/p.toml:1:8: `[map01.astr]`: unknown planner `astr`, expected a registry name (astar, "),
        "{}",
        published_error("[map01.astr]\nsteps = 10\n")
    );
    assert_eq!(
        published_error("[mapp01.astar]\nsteps = 10\n"),
        "DIR/p.toml:1:2: `[mapp01]`: no map of the config and no file in DIR has the stem `mapp01`"
    );
    assert_eq!(
        published_error("[\"mapp01#2\".astar]\nsteps = 10\n"),
        "DIR/p.toml:1:2: `[mapp01#2]`: no map of the config and no file in DIR has the stem `mapp01`"
    );
    // A table of a map beside the published file (not in this config) is allowed, so one
    // file serves configs that run some of its maps. A problem the config's map does not
    // have is refused (51d587c: `#9` of a map with one problem vanished from the count).
    assert_eq!(published_error("[p.astar]\nsteps = 10\n"), "");
    assert_eq!(
        published_error("[\"map01#2\".astar]\nsteps = 10\n"),
        "DIR/p.toml:1:2: `[map01#2]`: map `map01.map` has 1 problem (`#1` to `#1`); the table names no problem of it"
    );
    assert_eq!(
        published_error("[map01]\nfile = \"nothere.map\"\n"),
        "DIR/p.toml:2:8: `map01.file`: DIR/nothere.map is not a file (`file` is the map the values are for, beside the published file)"
    );
    assert_eq!(
        published_error("[map01]\nfile = \"p.toml\"\n"),
        "DIR/p.toml:2:8: `map01.file`: `p.toml` is map `p`, not `map01`"
    );
}

/// `published` is compared by the `seed000` section only: a config whose `sections` leave
/// it out checked nothing and said nothing; now it is refused at the key.
#[test]
fn published_values_need_the_seed000_section() {
    let dir = scratch("published-sections");
    std::fs::write(dir.join("p.toml"), "[map01.astar]\nsteps = 10\n").unwrap();
    let text = |sections: &str| {
        format!(
            "name = \"p\"\n{sections}published = \"p.toml\"\n[[maps]]\nfiles = [{:?}]\nproblems = \"corners\"\n[planners.a]\nplanner = \"astar\"\n",
            paper_map()
        )
    };
    let parse = |sections: &str| {
        config::parse(&dir.join("c.toml"), &text(sections))
            .err()
            .map(|e| e.to_string().replace(&dir.display().to_string(), "DIR"))
            .unwrap_or_default()
    };
    assert_eq!(
        parse("sections = [\"aggregate\"]\n"),
        "DIR/c.toml:3:13: key `published`: the published values are compared by the `seed000` section, which `sections` leaves out; add \"seed000\" to `sections` (or leave `sections` out: `published` then shows it)"
    );
    assert_eq!(parse("sections = [\"seed000\", \"aggregate\"]\n"), "");
    assert_eq!(parse(""), "");
    std::fs::remove_dir_all(&dir).unwrap();
}

fn config_error(text: &str) -> String {
    config::parse(Path::new("c.toml"), text)
        .err()
        .map(|e| e.to_string())
        .unwrap_or_default()
}

#[test]
fn misspelt_compare_metrics_are_refused() {
    let text = format!(
        "name = \"c\"\n[[maps]]\nfiles = [{:?}]\nproblems = \"corners\"\n[planners.l]\nplanner = \"lexastar\"\ncompare = {{ with = \"backtracking\", metrics = [\"steps\", \"turnz\"] }}\n",
        paper_map()
    );
    let error = config_error(&text);
    assert!(
        error.starts_with("c.toml:7:11: planner `l`, key `compare`: unknown metric `turnz`"),
        "{error}"
    );
}

/// `compare.with` is the published key the values are read under: a misspelt one compared
/// nothing; now it is refused at the key.
#[test]
fn misspelt_compare_planners_are_refused() {
    let text = format!(
        "name = \"c\"\n[[maps]]\nfiles = [{:?}]\nproblems = \"corners\"\n[planners.l]\nplanner = \"lexastar\"\ncompare = {{ with = \"backtrackin\", metrics = [\"steps\"] }}\n",
        paper_map()
    );
    let error = config_error(&text);
    assert!(
        error.starts_with("c.toml:7:11: planner `l`, key `compare`: `with = \"backtrackin\"` is no planner; expected a registry name (astar, "),
        "{error}"
    );
}

#[test]
fn thread_counts_are_capped() {
    let text = format!(
        "name = \"t\"\nthreads = 100000\n[[maps]]\nfiles = [{:?}]\nproblems = \"corners\"\n[planners.a]\nplanner = \"astar\"\n",
        paper_map()
    );
    assert_eq!(
        config_error(&text),
        "c.toml:2:11: key `threads`: 100000 is more than 256; use 0 for one per core"
    );
    let experiment = config::parse(Path::new("c.toml"), &text.replace("100000", "1")).unwrap();
    let options = RunOptions {
        threads: 100_000,
        ..Default::default()
    };
    let error = run_all(&experiment, &options).err().unwrap().to_string();
    assert!(
        error.starts_with("100000 worker threads asked for"),
        "{error}"
    );
}

#[test]
fn maps_with_one_stem_are_refused() {
    let dir = scratch("stem");
    std::fs::write(
        dir.join("ok.map"),
        "type octile\nheight 2\nwidth 2\nmap\n..\n..\n",
    )
    .unwrap();
    std::fs::write(dir.join("ok.txt"), "..\n..\n").unwrap();
    let text = "name = \"s\"\n[[maps]]\nfiles = [\"ok.map\", \"ok.txt\"]\nproblems = \"corners\"\n[planners.a]\nplanner = \"astar\"\n";
    let error = config::parse(&dir.join("c.toml"), text)
        .err()
        .unwrap()
        .to_string();
    std::fs::remove_dir_all(&dir).unwrap();
    assert!(
        error.contains("`ok.map` and `ok.txt` have the same stem `ok`"),
        "{error}"
    );
}

/// Four billion repeats: the run list is computed, not stored.
#[test]
fn huge_repeat_counts_are_not_materialised() {
    let text = format!(
        "name = \"r\"\nrepeats = 4_000_000_000\n[[maps]]\nfiles = [{:?}]\nproblems = \"corners\"\n[planners.a]\nplanner = \"astar\"\n[planners.b]\nplanner = \"bfs\"\n",
        paper_map()
    );
    let experiment = config::parse(Path::new("c.toml"), &text).unwrap();
    assert_eq!(experiment.n_runs(), 8_000_000_000);
    let list = RunList::new(&experiment);
    assert_eq!(list.len(), 8_000_000_000);
    let last = list.get(7_999_999_999).unwrap();
    assert_eq!((last.planner, last.repeat), (1, 3_999_999_999));
    assert!(list.get(8_000_000_000).is_none());
}

/// Seeds are u64 end to end: the largest TOML integer as the base seed, plus a repeat.
#[test]
fn seeds_past_the_largest_toml_integer_run() {
    let map = root().join("maps/wpi/map1.txt").display().to_string();
    let text = format!(
        "name = \"s\"\nseed = 9223372036854775807\nrepeats = 2\n[[maps]]\nfiles = [{map:?}]\nproblems = \"file\"\n[planners.r]\nplanner = \"rrt\"\n"
    );
    let experiment = config::parse(Path::new("c.toml"), &text).unwrap();
    let records = run_all(&experiment, &RunOptions::default()).unwrap();
    let seeds: Vec<Option<u64>> = records.iter().take(2).map(|r| r.seed).collect();
    assert_eq!(
        seeds,
        [
            Some(9_223_372_036_854_775_807),
            Some(9_223_372_036_854_775_808)
        ]
    );
    assert!(records.iter().all(|r| r.status == RunStatus::Found));
}

/// `plan` always ends: Backtracking on an open 30x30 map stops at the default budget and
/// says so.
#[test]
fn plan_has_a_default_budget() {
    let dir = scratch("budget");
    let rows = ".".repeat(30);
    let map = format!(
        "type octile\nheight 30\nwidth 30\nmap\n{}",
        format!("{rows}\n").repeat(30)
    );
    std::fs::write(dir.join("open.map"), map).unwrap();
    let args = PlanArgs {
        map: dir.join("open.map"),
        planner: "backtracking".into(),
        ..Default::default()
    };
    let result = planner_runner::plan::run(&args).unwrap();
    std::fs::remove_dir_all(&dir).unwrap();
    assert_eq!(result.record.status, RunStatus::BudgetExhausted);
    assert_eq!(
        result.record.counters.get("n_expanded"),
        Some(DEFAULT_PLAN_EXPANSIONS)
    );
    assert!(result.hit_default_budget());
    assert!(result
        .to_text()
        .contains("default budget of 10000000 expansions"));
}

/// A `.scen` beside a map but written for another map size is refused by `plan`, as by
/// `experiment`.
#[test]
fn plan_refuses_scenarios_for_another_map_size() {
    let dir = scratch("scen");
    std::fs::write(
        dir.join("small.map"),
        "type octile\nheight 2\nwidth 2\nmap\n..\n..\n",
    )
    .unwrap();
    std::fs::write(
        dir.join("small.map.scen"),
        "version 1\n0\tsmall.map\t3\t3\t0\t0\t1\t1\t1.41421356\n",
    )
    .unwrap();
    let args = PlanArgs {
        map: dir.join("small.map"),
        planner: "astar".into(),
        problem: Some(1),
        ..Default::default()
    };
    let error = planner_runner::plan::run(&args).err().unwrap().to_string();
    // Line 2, column 13: the width, after "0\tsmall.map\t".
    assert!(
        error.contains("small.map.scen:2:13: the scenario is for a 3x3 map, but"),
        "{error}"
    );
    // A start and goal given need no scenario: the file is not read, bad or not.
    let cells = PlanArgs {
        problem: None,
        start: Some(planner_api::Cell::new(0, 0)),
        goal: Some(planner_api::Cell::new(1, 1)),
        ..args.clone()
    };
    for scen in [
        "version 1\n0\tsmall.map\t3\t3\t0\t0\t1\t1\t1.41421356\n",
        "garbage\n",
    ] {
        std::fs::write(dir.join("small.map.scen"), scen).unwrap();
        let planned = planner_runner::plan::run(&cells);
        assert!(planned.is_ok(), "{scen:?}: {:?}", planned.err());
        // Without cells, the problems are the scenario's, and a bad one is an error.
        let first = PlanArgs {
            problem: None,
            ..args.clone()
        };
        assert!(planner_runner::plan::run(&first).is_err(), "{scen:?}");
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Seed 002's TA-star (Manhattan with 8 moves) is recorded as inadmissible (planner-report's
/// tests/summary.rs checks that the summary says so).
#[test]
fn inadmissible_heuristics_are_recorded() {
    let experiment = config::load(&root().join("configs/pastar.toml"))
        .unwrap()
        .trimmed_for_test();
    let records = run_all(&experiment, &RunOptions::default()).unwrap();
    let flag = |label: &str| {
        records
            .iter()
            .find(|r| r.planner == label)
            .unwrap()
            .admissible
    };
    assert_eq!(flag("TA-star"), Some(false));
    assert_eq!(flag("RA-star1"), None);
}

/// A config for one `.csv` map `m.csv` holding `matrix`, with `extra` keys on the map set.
fn csv_config(name: &str, matrix: &str, extra: &str) -> Result<config::Experiment, String> {
    let dir = scratch(name);
    std::fs::write(dir.join("m.csv"), matrix).unwrap();
    let text = format!(
        "name = \"m\"\n[[maps]]\nfiles = [\"m.csv\"]\nproblems = \"corners\"\n{extra}\n[planners.a]\nplanner = \"astar\"\n"
    );
    let result = config::parse(&dir.join("c.toml"), &text).map_err(|e| e.to_string());
    std::fs::remove_dir_all(&dir).unwrap();
    result
}

/// `obstacle = 1` reads a `.csv` matrix with 1 = obstacle; the default (0) finds the
/// corners blocked and says the map looks inverted; other values and other formats are
/// refused, naming the key.
#[test]
fn csv_obstacle_convention() {
    let matrix = "0,1,1\n1,1,0\n";
    let one = csv_config("csv1", matrix, "obstacle = 1").unwrap();
    let grid = &one.maps[0].grid;
    assert_eq!(grid.to_ascii(), ".##\n##.\n");
    assert_eq!(one.maps[0].problems[0].invalid, None);
    let records = run_all(&one, &RunOptions::default()).unwrap();
    assert_eq!(records[0].status, RunStatus::NoPath);

    let zero = csv_config("csv0", matrix, "").unwrap();
    assert_eq!(
        zero.maps[0].problems[0].invalid.as_deref(),
        Some(
            "start (0, 0) is blocked; start (0, 0) and goal (2, 1) are blocked with obstacle = 0 \
             but free with obstacle = 1: the map looks written with 1 = obstacle"
        )
    );
    let explicit = csv_config("csv0e", matrix, "obstacle = 0").unwrap();
    assert_eq!(explicit.maps[0].grid, zero.maps[0].grid);

    let error = csv_config("csv2", matrix, "obstacle = 2").unwrap_err();
    assert!(
        error.ends_with("c.toml:5:12: maps[0]: key `obstacle`: 2 is neither 0 nor 1 (the value of a `.csv` cell that is an obstacle)"),
        "{error}"
    );
    let error = csv_config("csvs", matrix, "obstacle = \"1\"").unwrap_err();
    assert!(error.contains("c.toml:5:12"), "{error}");

    let text = format!(
        "name = \"m\"\n[[maps]]\nfiles = [{:?}]\nproblems = \"corners\"\nobstacle = 1\n[planners.a]\nplanner = \"astar\"\n",
        paper_map()
    );
    let error = config_error(&text);
    assert!(
        error.starts_with("c.toml:5:12: maps[0]: key `obstacle` applies to `.csv` maps, not"),
        "{error}"
    );
}

/// `plan --obstacle 1` reads the matrix the other way; without it the error says the
/// start and goal would be free with `--obstacle 1`.
#[test]
fn plan_obstacle_option() {
    let dir = scratch("plan-csv");
    std::fs::write(dir.join("m.csv"), "0,0,1\n1,0,0\n").unwrap();
    let args = PlanArgs {
        map: dir.join("m.csv"),
        planner: "astar".into(),
        ..Default::default()
    };
    let error = planner_runner::plan::run(&args).err().unwrap().to_string();
    let one = planner_runner::plan::run(&PlanArgs {
        obstacle: planner_maps::CsvConvention::from_obstacle_value(1),
        ..args.clone()
    })
    .unwrap();
    let not_csv = planner_runner::plan::run(&PlanArgs {
        map: root().join("maps/paper/map01.map"),
        obstacle: planner_maps::CsvConvention::from_obstacle_value(1),
        ..args.clone()
    })
    .err()
    .unwrap()
    .to_string();
    std::fs::remove_dir_all(&dir).unwrap();
    assert!(
        error.ends_with(
            "m.csv: start (0, 0) is blocked; start (0, 0) and goal (2, 1) are blocked with \
             obstacle = 0 but free with obstacle = 1: the map looks written with 1 = obstacle \
             (--obstacle 1)"
        ),
        "{error}"
    );
    assert_eq!(one.record.status, RunStatus::Found);
    assert_eq!(one.record.path.unwrap().metrics().steps, 3);
    assert!(
        not_csv.starts_with("--obstacle 1 applies to .csv maps, not"),
        "{not_csv}"
    );
}

/// Configs and published-values files are read like maps: a device, a FIFO or a
/// directory is refused before it is read (`/dev/zero` used to be read until memory ran
/// out).
#[test]
fn configs_and_published_files_must_be_regular_files() {
    let error = config::load(Path::new("/dev/zero"))
        .err()
        .unwrap()
        .to_string();
    assert_eq!(
        error,
        "/dev/zero: cannot read the config: not a regular file (a character device): gridplan reads its inputs (maps, images, scenarios, configs, weights) from regular files only"
    );
    let text = format!(
        "name = \"p\"\npublished = \"/dev/zero\"\n[[maps]]\nfiles = [{:?}]\nproblems = \"corners\"\n[planners.a]\nplanner = \"astar\"\n",
        paper_map()
    );
    assert_eq!(
        config_error(&text),
        "c.toml:2:13: key `published`: cannot read /dev/zero: not a regular file (a character device): gridplan reads its inputs (maps, images, scenarios, configs, weights) from regular files only"
    );
}

/// `limit` without `scen` used to be accepted and ignored.
#[test]
fn scenario_selection_needs_a_scen() {
    let text = format!(
        "name = \"l\"\n[[maps]]\nfiles = [{:?}]\nproblems = \"corners\"\nlimit = 3\n[planners.a]\nplanner = \"astar\"\n",
        paper_map()
    );
    assert_eq!(
        config_error(&text),
        "c.toml:2:1: maps[0]: `buckets`, `lines`, `every` and `limit` select scenarios and need `scen`"
    );
}

/// A `**` pattern over a map directory holding links back to its parents lists the maps
/// once each and ends: the `glob` crate followed the links, and `config::load` never
/// returned (`maps/sub/loop -> ..`, `maps/sub/up -> ../..`).
#[test]
#[cfg(unix)]
fn a_double_star_over_links_back_up_the_tree_ends() {
    let dir = scratch("globloop");
    let maps = dir.join("maps");
    std::fs::create_dir_all(maps.join("sub")).unwrap();
    std::fs::copy(root().join("maps/paper/map01.map"), maps.join("a.map")).unwrap();
    std::fs::copy(root().join("maps/paper/map02.map"), maps.join("sub/b.map")).unwrap();
    std::os::unix::fs::symlink("..", maps.join("sub/loop")).unwrap();
    std::os::unix::fs::symlink("../..", maps.join("sub/up")).unwrap();
    let config = dir.join("c.toml");
    std::fs::write(
        &config,
        "name = \"g\"\n[[maps]]\nfiles = [\"maps/**/*.map\"]\nproblems = \"corners\"\n[planners.a]\nplanner = \"astar\"\n",
    )
    .unwrap();
    let experiment = config::load(&config);
    std::fs::remove_dir_all(&dir).unwrap();
    let experiment = experiment.unwrap();
    let names: Vec<&str> = experiment.maps.iter().map(|m| m.name.as_str()).collect();
    assert_eq!(names, ["a.map", "b.map"]);
}

/// A report step that writes nothing, or, with `stop`, raises the sweep's stop flag (as
/// Ctrl-C does once the runs are done) and then reads the records, as a section does.
struct StopWhileRendering<'a> {
    stop: Option<&'a std::sync::atomic::AtomicBool>,
}

impl planner_runner::sweep::Render for StopWhileRendering<'_> {
    fn check(&self, _: &config::Experiment) -> Result<(), config::ConfigError> {
        Ok(())
    }

    fn render(
        &self,
        results: &planner_runner::sweep::Results<'_>,
    ) -> Result<
        (
            Vec<planner_runner::output::OutputFile>,
            planner_runner::record::Reproduction,
        ),
        planner_runner::RunnerError,
    > {
        if let Some(stop) = self.stop {
            stop.store(true, std::sync::atomic::Ordering::Relaxed);
        }
        let mut seen = 0;
        results.passes.pass(&mut |_| seen += 1)?;
        Ok((Vec::new(), Default::default()))
    }
}

/// The stop flag raised while a sweep's results are rendered (its report ran for
/// minutes, then wrote everything and exited 0): the sweep ends as interrupted, the old
/// results stay as they were, and the stream keeps every run for `--resume`, which then
/// writes the results.
#[test]
fn a_stop_while_rendering_writes_nothing_and_resumes() {
    use planner_runner::sweep::{experiment, SweepArgs};
    use std::sync::atomic::AtomicBool;

    let dir = scratch("stop-rendering");
    let _ = std::fs::remove_dir_all(dir.join("res"));
    let _ = std::fs::remove_dir_all(dir.join(".res.stream"));
    let config = dir.join("c.toml");
    std::fs::write(
        &config,
        format!(
            "name = \"c\"\nrepeats = 3\n[[maps]]\nfiles = [{:?}]\nproblems = \"corners\"\n\
             [planners.a]\nplanner = \"astar\"\n",
            paper_map()
        ),
    )
    .unwrap();
    let output = dir.join("res");
    let plain = StopWhileRendering { stop: None };
    let first = experiment(&SweepArgs {
        output: Some(&output),
        ..SweepArgs::new(&config, &plain)
    })
    .unwrap();
    assert_eq!(first.interrupted, None);
    let old = std::fs::read(output.join("runs.csv")).unwrap();

    let stop = AtomicBool::new(false);
    let stopping = StopWhileRendering { stop: Some(&stop) };
    let report = experiment(&SweepArgs {
        output: Some(&output),
        stop: Some(&stop),
        ..SweepArgs::new(&config, &stopping)
    })
    .unwrap();
    assert_eq!(report.interrupted, Some(3), "every run recorded");
    assert_eq!(std::fs::read(output.join("runs.csv")).unwrap(), old);
    assert!(dir.join(".res.stream/records.stream").is_file());

    let resumed = experiment(&SweepArgs {
        output: Some(&output),
        resume: true,
        ..SweepArgs::new(&config, &plain)
    })
    .unwrap();
    assert_eq!(resumed.interrupted, None);
    assert!(!dir.join(".res.stream").exists());
    std::fs::remove_dir_all(&dir).unwrap();
}
