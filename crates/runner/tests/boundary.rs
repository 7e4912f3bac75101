//! The typed planner boundary end to end: `plan` and `experiment` agree (seeds included),
//! the runner validates paths by the rule a planner declares, parameter errors point at
//! their key for every registered planner, and run records keep the planner's counter order.

use std::path::{Path, PathBuf};

use planner_api::{
    Budget, Cell, Connectivity, Counters, MoveSet, Outcome, ParamKey, PathSpec, Planner,
    PlannerSpecs, Problem,
};
use planner_registry::Factory;
use planner_registry::PLANNERS;
use planner_runner::plan::PlanArgs;
use planner_runner::{config, output, run_all, RunOptions};

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

fn scratch(name: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join(format!("gridplan-boundary-{name}"));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// A config's top-level `seed` reaches RRT the same way through `plan --config` as through
/// `experiment` (it did not: `plan` ran seed 0 while `experiment` ran seed 5).
#[test]
fn plan_and_experiment_run_the_same_run() {
    let dir = scratch("seed");
    let map = root().join("maps/wpi/map3.txt");
    let config = dir.join("c.toml");
    std::fs::write(
        &config,
        format!(
            "name = \"s\"\nseed = 5\n[[maps]]\nfiles = [{:?}]\nproblems = \"file\"\n[planners.r]\nplanner = \"rrt\"\n[planners.a]\nplanner = \"astar\"\nmoves = 8\nheuristic = \"octile\"\n",
            map.display().to_string()
        ),
    )
    .unwrap();
    let experiment = config::load(&config).unwrap();
    let records = run_all(&experiment, &RunOptions::default()).unwrap();
    for label in ["r", "a"] {
        for problem in 1..=3 {
            let swept = records
                .iter()
                .find(|r| r.planner == label && r.problem == problem && r.repeat == 0)
                .unwrap();
            let args = PlanArgs {
                map: map.clone(),
                planner: label.into(),
                config: Some(config.clone()),
                problem: Some(problem),
                ..Default::default()
            };
            let planned = planner_runner::plan::run(&args).unwrap().record;
            let what = format!("{label} problem {problem}");
            assert_eq!(planned.seed, swept.seed, "{what}");
            assert_eq!(planned.counters, swept.counters, "{what}");
            assert_eq!(planned.path, swept.path, "{what}");
            assert_eq!(planned.status, swept.status, "{what}");
        }
    }
    let rrt = records.iter().find(|r| r.planner == "r").unwrap();
    assert_eq!(rrt.seed, Some(5));
    std::fs::remove_dir_all(&dir).unwrap();
}

/// A planner that declares 4-connected moves and returns a diagonal step.
struct Liar;

#[derive(Debug, Clone, Default, serde::Deserialize, serde::Serialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
struct LiarConfig {}

#[derive(Debug, thiserror::Error)]
#[error("never")]
struct Never;

impl ParamKey for Never {
    fn param_key(&self) -> &str {
        ""
    }
}

impl Liar {
    fn new(_: LiarConfig) -> Result<Liar, Never> {
        Ok(Liar)
    }
}

impl Planner for Liar {
    fn name(&self) -> &str {
        "liar"
    }

    fn specs(&self) -> PlannerSpecs {
        PlannerSpecs::deterministic(PathSpec::Moves(MoveSet::standard(Connectivity::Four)))
    }

    fn plan(&mut self, problem: &Problem<'_>, _budget: &Budget) -> Outcome {
        let (s, g) = (problem.start(), problem.goal());
        // A straight diagonal from start to goal: fine under the any-angle rule on an
        // open map, not a 4-connected path.
        let cells = (0..=g.x - s.x)
            .map(|i| Cell::new(s.x + i, s.y + i))
            .collect();
        Outcome::found(planner_api::Path::new(cells), Counters::new())
    }
}

#[test]
fn a_path_breaking_the_declared_rule_is_recorded_invalid() {
    let dir = scratch("liar");
    std::fs::write(
        dir.join("open.map"),
        "type octile\nheight 4\nwidth 4\nmap\n....\n....\n....\n....\n",
    )
    .unwrap();
    let text = "name = \"l\"\n[[maps]]\nfiles = [\"open.map\"]\nproblems = \"corners\"\n[planners.x]\nplanner = \"astar\"\n";
    let mut experiment = config::parse(&dir.join("c.toml"), text).unwrap();
    let honest = run_all(&experiment, &RunOptions::default()).unwrap();
    assert_eq!(honest[0].valid, Some(true));
    experiment.planners[0].factory = Factory::path("liar", &toml::Table::new(), Liar::new).unwrap();
    let records = run_all(&experiment, &RunOptions::default()).unwrap();
    assert_eq!(records[0].steps, Some(3));
    assert_eq!(
        records[0].valid,
        Some(false),
        "a diagonal path from a 4-connected planner"
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

/// A planner that says found without a path.
struct Pathless;

impl Pathless {
    fn new(_: LiarConfig) -> Result<Pathless, Never> {
        Ok(Pathless)
    }
}

impl Planner for Pathless {
    fn name(&self) -> &str {
        "pathless"
    }

    fn specs(&self) -> PlannerSpecs {
        PlannerSpecs::deterministic(PathSpec::Moves(MoveSet::standard(Connectivity::Four)))
    }

    fn plan(&mut self, _problem: &Problem<'_>, _budget: &Budget) -> Outcome {
        Outcome::new(planner_api::Status::Found, None, Counters::new())
    }
}

/// `found` without a path was recorded as found (empty steps and validity, no warning,
/// summary.md counting it found); it is an invalid run that says why.
#[test]
fn found_without_a_path_is_recorded_invalid() {
    let dir = scratch("pathless");
    std::fs::write(
        dir.join("open.map"),
        "type octile\nheight 4\nwidth 4\nmap\n....\n....\n....\n....\n",
    )
    .unwrap();
    let text = "name = \"l\"\n[[maps]]\nfiles = [\"open.map\"]\nproblems = \"corners\"\n[planners.x]\nplanner = \"astar\"\n";
    let mut experiment = config::parse(&dir.join("c.toml"), text).unwrap();
    experiment.planners[0].factory =
        Factory::path("pathless", &toml::Table::new(), Pathless::new).unwrap();
    let records = run_all(&experiment, &RunOptions::default()).unwrap();
    assert_eq!(records[0].valid, Some(false));
    assert_eq!(
        records[0].error.as_deref(),
        Some("the planner said found but returned no path")
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

/// A bad parameter, for every planner: an unknown key, and for the planners listed a value
/// its constructor rejects. The error points at the key's line and column.
#[test]
fn parameter_errors_point_at_their_key_for_every_planner() {
    let bad_values = [
        ("astar", "weight = -2.0"),
        ("astar", "order = \"R\""),
        ("backtracking", "order = \"R\""),
        ("backtracking", "corner_cutting = true"),
        ("bfs", "order = \"R L\""),
        ("dfs", "order = \"R L D\""),
        ("lexastar", "moves = 16"),
        ("rrt", "goal_bias = 2.0"),
        ("rrt", "seed = -1"),
        ("pastar", "beta = -1.0"),
        ("coverage", "pattern = \"diagonal\""),
    ];
    let map = root().join("maps/paper/map01.map").display().to_string();
    let check = |name: &str, line: &str| {
        let text = format!(
            "name = \"k\"\n[[maps]]\nfiles = [{map:?}]\nproblems = \"corners\"\n[planners.x]\nplanner = \"{name}\"\n{line}\n"
        );
        let error = config::parse(Path::new("k.toml"), &text)
            .err()
            .unwrap_or_else(|| panic!("{name}: `{line}` was accepted"));
        assert_eq!(
            (error.line, error.column),
            (7, 1),
            "{name}: `{line}` reported at {}:{} ({error})",
            error.line,
            error.column
        );
        assert!(error.message.starts_with("planner `x`"), "{error}");
    };
    for entry in PLANNERS {
        check(entry.name, "no_such_parameter = 1");
    }
    for (name, line) in bad_values {
        check(name, line);
    }
}

/// runs.json lists A*'s counters in seed 000 Table 2's order (then `peak_open`), not
/// alphabetically.
#[test]
fn run_records_keep_the_planners_counter_order() {
    let experiment = config::load(&root().join("configs/paper.toml")).unwrap();
    let records = run_all(&experiment, &RunOptions::default()).unwrap();
    let json = output::runs_json(&experiment, &records).unwrap();
    let value: serde_json::Value = serde_json::from_slice(&json).unwrap();
    let table = &value["runs"];
    let columns: Vec<&str> = table["columns"]
        .as_array()
        .unwrap()
        .iter()
        .map(|c| c.as_str().unwrap())
        .collect();
    let algorithm = columns.iter().position(|&c| c == "algorithm").unwrap();
    let astar = table["data"]
        .as_array()
        .unwrap()
        .iter()
        .find(|row| row[algorithm] == "astar")
        .unwrap();
    // The counter columns (after the fixed ones) that A*'s row fills, in column order.
    let first_counter = columns.iter().position(|&c| c == "n_expanded").unwrap();
    let names: Vec<&str> = (first_counter..columns.len())
        .filter(|&i| !astar[i].is_null())
        .map(|i| columns[i])
        .collect();
    assert_eq!(
        names,
        [
            "n_expanded",
            "n_neighbor_checks",
            "n_blocked",
            "n_skipped",
            "n_open_insertions",
            "n_relaxations",
            "peak_open"
        ]
    );
    let csv = String::from_utf8(output::runs_csv(&records)).unwrap();
    let header = csv.lines().next().unwrap();
    assert!(
        header.contains(",peak_heap_bytes,bucket,n_expanded,n_neighbor_checks,n_blocked,n_skipped,n_open_insertions,n_relaxations,peak_open,"),
        "{header}"
    );
}

/// A coverage label on a `pairs` problem whose goal is blocked was recorded
/// `invalid_problem` ("goal (2, 2) is blocked"), though a coverage planner ignores the goal
/// (configs/README.md). It now covers from the start, every repeat, while a start-goal
/// label beside it is still refused for the goal; a blocked start refuses both.
#[test]
fn a_coverage_label_is_not_refused_for_its_goal() {
    let dir = scratch("coverage-goal");
    std::fs::write(
        dir.join("g.map"),
        "type octile\nheight 3\nwidth 3\nmap\n...\n...\n..@\n",
    )
    .unwrap();
    let text = "name = \"g\"\nrepeats = 2\n[[maps]]\nfiles = [\"g.map\"]\n\
                pairs = [{ start = [0, 0], goal = [2, 2] }, { start = [2, 2], goal = [0, 0] }]\n\
                [planners.cov]\nplanner = \"coverage\"\n[planners.a]\nplanner = \"astar\"\n";
    let experiment = config::parse(&dir.join("g.toml"), text).unwrap();
    let records = run_all(&experiment, &RunOptions::default()).unwrap();
    let runs = |problem: usize, label: &str| -> Vec<(String, Option<String>)> {
        records
            .iter()
            .filter(|r| r.problem == problem && r.planner == label)
            .map(|r| (r.status.as_str().to_string(), r.error.clone()))
            .collect()
    };
    let covered = runs(1, "cov");
    assert_eq!(covered.len(), 2, "{covered:?}");
    assert!(
        covered.iter().all(|(s, e)| s == "found" && e.is_none()),
        "{covered:?}"
    );
    let refused = runs(1, "a");
    assert_eq!(refused.len(), 2, "{refused:?}");
    assert!(
        refused.iter().all(|(s, e)| s == "invalid_problem"
            && e.as_deref()
                .is_some_and(|e| e.contains("goal (2, 2) is blocked"))),
        "{refused:?}"
    );
    for label in ["cov", "a"] {
        let blocked = runs(2, label);
        assert_eq!(blocked.len(), 1, "{label}: {blocked:?}");
        assert_eq!(blocked[0].0, "invalid_problem", "{label}");
        assert!(
            blocked[0]
                .1
                .as_deref()
                .is_some_and(|e| e.contains("start (2, 2) is blocked")),
            "{label}: {blocked:?}"
        );
    }
    assert_eq!(records.len() as u64, experiment.n_runs());
}

/// Config value errors named no key (`cfg.toml:7:9: number too large to fit in target
/// type`; `invalid value: integer -1, expected u64`), and `output = ""` had no position
/// at all (the sweep's "output directory `` has no name"). Each now names its key, at
/// its line and column; the special messages stay. A `kind` that no replanning
/// experiment has was "unknown field `kind`": it is now said to be an unknown kind.
#[test]
fn config_value_errors_name_their_key() {
    let dir = scratch("config-keys");
    std::fs::write(
        dir.join("s.map"),
        "type octile\nheight 3\nwidth 3\nmap\n...\n...\n...\n",
    )
    .unwrap();
    let config = |top: &str, maps: &str, planner: &str| {
        format!(
            "name = \"c\"\n{top}\n[[maps]]\nfiles = [\"s.map\"]\nproblems = \"corners\"\n{maps}\n\
             [planners.a]\nplanner = \"astar\"\n{planner}\n"
        )
    };
    let cases = [
        (
            config("", "", "moves = 99999999999999999999"),
            "9:9: key `planners.a.moves`: a number too large: integers are from -2^63 to 2^63 - 1",
        ),
        (
            config("", "", "inflation = 18446744073709551615"),
            "9:13: key `planners.a.inflation`: a number too large",
        ),
        (
            config("", "seeds = [18446744073709551615]", ""),
            "6:10: key `maps[0].seeds`: a number too large",
        ),
        (
            config("seed = -1", "", ""),
            "2:8: key `seed`: expected a non-negative integer, got -1",
        ),
        (
            config("[budget]\nmax_expansions = -1", "", ""),
            "3:18: key `budget.max_expansions`: expected a non-negative integer, got -1",
        ),
        (
            config("[budget]\nmax_memory_mb = 99999999999999999999", "", ""),
            "3:17: key `budget.max_memory_mb`: a number too large",
        ),
        (
            config("", "costs = { lethal = 300 }", ""),
            "key `maps[0].costs.lethal`: expected an integer from 0 to 255, got 300",
        ),
        (
            config("", "costs = { unknown = -1 }", ""),
            "key `maps[0].costs.unknown`: expected an integer from 0 to 255, got -1",
        ),
        (
            config("", "costs = { lethal = 2.5 }", ""),
            "key `maps[0].costs.lethal`: expected an integer from 0 to 255, got 2.5",
        ),
        (
            config("", "costs = { swamp = 70000 }", ""),
            "key `maps[0].costs.swamp`: expected an integer from 0 to 65535, got 70000",
        ),
        (
            config("", "", "weight = \"a\""),
            "parameter `weight`: expected a number, got the string \"a\"",
        ),
        (
            config("", "", "tie_break = true"),
            "parameter `tie_break`: expected one of: ",
        ),
        (
            config("output = \"\"", "", ""),
            "2:10: key `output`: output directory `` has no name",
        ),
        (
            config("kind = \"nosuch\"", "", ""),
            "2:8: key `kind`: unknown kind \"nosuch\": a replanning experiment has kind = \
             \"navigate\" or \"dynamic\" (configs/replan/README.md); an experiment runner \
             config has no kind",
        ),
        // Unchanged: an unknown top-level key, an unknown key of a map set (now with the
        // set), a replanning experiment's kind.
        (config("colour = 1", "", ""), "2:1: unknown field `colour`"),
        (
            config("", "nosuch = 1", ""),
            "6:1: key `maps[0]`: unknown field `nosuch`",
        ),
        (
            config("kind = \"navigate\"", "", ""),
            "key `kind`: a replanning experiment (kind = \"navigate\"",
        ),
    ];
    for (text, expected) in cases {
        let error = config::parse(&dir.join("cfg.toml"), &text)
            .unwrap_err()
            .to_string();
        let expected = match expected.starts_with(char::is_numeric) {
            true => format!("cfg.toml:{expected}"),
            false => expected.to_string(),
        };
        assert!(error.contains(&expected), "{text}\n{error}");
        for rust in [
            "expected u",
            "expected f64",
            "string only",
            "unit variant",
            "target type",
        ] {
            assert!(!error.contains(rust), "{text}\n{error}");
        }
    }
}

/// Planner parameters given with `--set` (`plan`, `serve`: [`config::planner_from_table`])
/// said serde's words: "invalid value: integer `-1`, expected u64", "expected u32",
/// "invalid type: unit variant, expected string only" for a choice given a number. They
/// say what a value takes in words, and a choice lists its values as a wrong string does.
#[test]
fn parameter_values_are_said_in_words() {
    let cases: [(&str, &str, toml::Value, &str); 5] = [
        (
            "rrt",
            "seed",
            toml::Value::Integer(-1),
            "parameter `seed`: expected a non-negative integer, got -1",
        ),
        (
            "astar",
            "moves",
            toml::Value::Float(1.5),
            "parameter `moves`: expected ",
        ),
        (
            "astar",
            "weight",
            toml::Value::String("a".into()),
            "parameter `weight`: expected a number, got the string \"a\"",
        ),
        (
            "astar",
            "heuristic",
            toml::Value::Integer(5),
            "parameter `heuristic`: expected one of: ",
        ),
        (
            "astar",
            "tie_break",
            toml::Value::Boolean(true),
            "parameter `tie_break`: expected one of: ",
        ),
    ];
    for (planner, key, value, expected) in cases {
        let table = toml::Table::from_iter([(key.to_string(), value)]);
        let error = config::planner_from_table("p", planner, table, Budget::default())
            .err()
            .unwrap()
            .to_string();
        assert!(error.contains(expected), "{planner} {key}: {error}");
        for rust in ["u32", "u64", "f64", "string only", "unit variant"] {
            assert!(!error.contains(rust), "{planner} {key}: {error}");
        }
        // A choice lists its values, as a wrong string does.
        if expected.ends_with("one of: ") {
            let wrong =
                toml::Table::from_iter([(key.to_string(), toml::Value::String("nosuch".into()))]);
            let said = config::planner_from_table("p", planner, wrong, Budget::default())
                .err()
                .unwrap()
                .to_string();
            let first = error
                .split("one of: ")
                .nth(1)
                .unwrap()
                .split(',')
                .next()
                .unwrap()
                .trim();
            assert!(said.contains(first), "{said} / {error}");
        }
    }
}

/// A planner's own `budget = { max_time_ms = 100000 }` replaced the whole experiment
/// `[budget]` (its `max_expansions = 1` was lost for that planner), while the docs say
/// `[budget]` is for every planner. Now a planner's table sets its keys one by one: the
/// keys it leaves out keep the experiment's.
#[test]
fn a_planners_budget_overrides_the_experiments_key_by_key() {
    let dir = scratch("budget-keys");
    std::fs::write(
        dir.join("s.map"),
        "type octile\nheight 3\nwidth 3\nmap\n...\n...\n...\n",
    )
    .unwrap();
    let text = "name = \"c\"\n[budget]\nmax_expansions = 1\nmax_memory_mb = 64\n\
                [[maps]]\nfiles = [\"s.map\"]\nproblems = \"corners\"\n\
                [planners.timed]\nplanner = \"astar\"\nbudget = { max_time_ms = 100000 }\n\
                [planners.more]\nplanner = \"astar\"\nbudget = { max_expansions = 5 }\n\
                [planners.plain]\nplanner = \"astar\"\n";
    let experiment = config::parse(&dir.join("cfg.toml"), text).unwrap();
    let budget = |label: &str| {
        experiment
            .planners
            .iter()
            .find(|p| p.label == label)
            .map(|p| p.budget)
            .unwrap()
    };
    let timed = budget("timed");
    assert_eq!(timed.max_expansions, Some(1));
    assert_eq!(
        timed.max_time,
        Some(std::time::Duration::from_millis(100_000))
    );
    assert_eq!(timed.max_memory_mb, Some(64));
    let more = budget("more");
    assert_eq!(more.max_expansions, Some(5));
    assert_eq!(more.max_time, None);
    assert_eq!(more.max_memory_mb, Some(64));
    assert_eq!(
        budget("plain"),
        Budget {
            max_expansions: Some(1),
            max_memory_mb: Some(64),
            ..Budget::default()
        }
    );
}
