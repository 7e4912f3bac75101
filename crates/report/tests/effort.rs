//! Search effort and memory: every planner that records its expanded cells lists exactly
//! `n_expanded` of them without changing its search, figures draw them, and every
//! planner that checks a memory budget refuses a tiny one with a clear outcome.

use std::path::{Path, PathBuf};

use planner_api::{Budget, Problem, Status};
use planner_report::figures;
use planner_runner::config;
use planner_runner::expanded::{self, ExpandedError};
use planner_runner::plan::{PlanArgs, PlanOptions};
use planner_runner::Built;
use planner_runner::{run_all, RunOptions, RunStatus};

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// The planners that record expanded cells, as (label, registry name, parameters).
const RECORDING: &[(&str, &str, &str)] = &[
    ("astar4", "astar", ""),
    ("octile", "astar", "moves = 8\nheuristic = \"octile\""),
    ("dijkstra", "astar", "moves = 8\nheuristic = \"zero\""),
    ("bfs", "bfs", "moves = 8"),
    ("dfs", "dfs", ""),
    ("jps", "jps", ""),
    ("jps_prime", "jps", "variant = \"jps_prime\""),
    ("jps_plus", "jps", "variant = \"jps_plus\""),
    ("lexastar", "lexastar", "moves = 8"),
    ("bidirectional", "bidirectional_astar", "moves = 8"),
];

fn built(name: &str, params: &str) -> Box<dyn planner_api::Planner> {
    let table: toml::Table = toml::from_str(params).unwrap();
    let spec = config::planner_from_table(name, name, table, Budget::unlimited()).unwrap();
    match spec.factory.build().unwrap() {
        Built::Path(p) => p,
        Built::Coverage(_) => panic!("{name} is a coverage planner"),
    }
}

/// Recording lists `n_expanded` cells, all free, and changes nothing else; the
/// planners' docs say what a repeat means (a state's cell for lexastar, a cell both
/// directions expand for bidirectional A*).
#[test]
fn recorded_expanded_cells_match_n_expanded_on_several_maps() {
    for map in ["arena.map", "den520d.map", "Berlin_0_256.map"] {
        let dir = root().join("maps/movingai");
        let grid = planner_maps::read_map(&dir.join(map)).unwrap().grid;
        let scenarios = planner_maps::read_scenarios(&dir.join(format!("{map}.scen"))).unwrap();
        for scenario in scenarios.iter().rev().step_by(151).take(3) {
            let problem = Problem::new(&grid, scenario.start, scenario.goal).unwrap();
            for &(label, name, params) in RECORDING {
                let what = format!("{label} on {map} line {}", scenario.line);
                let mut planner = built(name, params);
                let budget = Budget::expansions(200_000);
                let timed = planner.plan(&problem, &budget);
                assert!(timed.expanded.is_empty(), "{what}: recorded while off");
                let recorded = planner.plan(&problem, &budget.recording_expanded(true));
                let n_expanded = recorded.counters.get("n_expanded").unwrap();
                assert!(n_expanded > 0, "{what}");
                assert_eq!(recorded.expanded.len() as u64, n_expanded, "{what}");
                assert_eq!(recorded.counters, timed.counters, "{what}");
                assert_eq!(recorded.path, timed.path, "{what}");
                assert_eq!(recorded.status, timed.status, "{what}");
                assert!(recorded.expanded.iter().all(|&c| grid.is_free(c)), "{what}");
                if recorded.status == Status::Found {
                    assert!(recorded.expanded.contains(&scenario.goal), "{what}");
                }
            }
        }
    }
}

#[test]
fn a_tiny_memory_budget_gives_a_clear_outcome_for_every_checking_planner() {
    let grid = planner_maps::read_map(&root().join("maps/movingai/den520d.map"))
        .unwrap()
        .grid;
    let scenarios =
        planner_maps::read_scenarios(&root().join("maps/movingai/den520d.map.scen")).unwrap();
    let last = scenarios.last().unwrap();
    let problem = Problem::new(&grid, last.start, last.goal).unwrap();
    for &(label, name, params) in RECORDING {
        let mut planner = built(name, params);
        let outcome = planner.plan(&problem, &Budget::unlimited().with_memory_mb(0));
        assert_eq!(outcome.status, Status::BudgetExhausted, "{label}");
        assert_eq!(outcome.counters.get("n_expanded"), Some(0), "{label}");
        assert!(outcome.path.is_none(), "{label}");
        let message = outcome.memory.expect(label).to_string();
        assert!(
            message.starts_with("needs ")
                && message.ends_with("MB for a 256 x 257 grid, over the max_memory_mb = 0 budget"),
            "{label}: {message}"
        );
        // The default limit (half the machine's memory) lets the same planner run.
        let outcome = planner.plan(&problem, &Budget::unlimited());
        assert_eq!(outcome.status, Status::Found, "{label}");
    }
}

#[test]
fn plan_reports_the_memory_budget_and_draws_the_expanded_cells() {
    let map = root().join("maps/movingai/arena.map");
    let args = PlanArgs {
        map: map.clone(),
        planner: "astar".into(),
        problem: Some(100),
        ..Default::default()
    };
    let refused = planner_runner::plan::run_with(
        &args,
        &PlanOptions {
            max_memory_mb: Some(0),
            record_expanded: false,
            ..Default::default()
        },
    )
    .unwrap();
    assert_eq!(refused.record.status, RunStatus::BudgetExhausted);
    let error = refused.record.error.clone().unwrap();
    assert_eq!(
        error,
        "needs 1 MB for a 49 x 49 grid, over the max_memory_mb = 0 budget"
    );
    assert!(refused.to_text().contains(&error), "{}", refused.to_text());

    let result = planner_runner::plan::run_with(
        &args,
        &PlanOptions {
            max_memory_mb: None,
            record_expanded: true,
            ..Default::default()
        },
    )
    .unwrap();
    let n_expanded = result.record.counters.get("n_expanded").unwrap();
    assert_eq!(result.expanded.len() as u64, n_expanded);
    let svg = figures::draw_run(&result.grid, &result.record, &result.expanded);
    assert!(svg.contains(r#"class="expanded""#), "no expanded group");
    assert!(svg.contains(&format!("expanded: {n_expanded} cells")));
}

/// An experiment on arena's scenarios with `figures_expanded` and the given planners.
fn experiment(planners: &str) -> planner_runner::Experiment {
    let dir = root().join("maps/movingai");
    let text = format!(
        "name = \"effort\"\nfigures = \"all\"\nfigures_per_map = 2\nfigures_pick = \"hardest\"\n\
         figures_expanded = true\n[[maps]]\nfiles = [{:?}]\nscen = {:?}\nevery = 40\n{planners}",
        dir.join("arena.map").display().to_string(),
        dir.join("arena.map.scen").display().to_string(),
    );
    config::parse(&root().join("configs/effort-test.toml"), &text).unwrap()
}

#[test]
fn figures_draw_the_expanded_cells_of_a_rerun_that_repeats_the_timed_run() {
    let experiment = experiment(
        "[planners.astar]\nplanner = \"astar\"\nmoves = 8\nheuristic = \"octile\"\n\
         [planners.dijkstra]\nplanner = \"astar\"\nmoves = 8\nheuristic = \"zero\"\n\
         [planners.bfs]\nplanner = \"bfs\"\nmoves = 8\n[planners.jps]\nplanner = \"jps\"\n\
         [planners.theta]\nplanner = \"theta_star\"\n[planners.rrt]\nplanner = \"rrt\"\n",
    );
    let records = run_all(&experiment, &RunOptions::default()).unwrap();
    let cells = expanded::record_all(&experiment, &records).unwrap();
    let files = figures::render(&experiment, &records, &cells);
    let effort: Vec<_> = files
        .iter()
        .filter(|f| f.path.to_string_lossy().ends_with("-expanded.svg"))
        .collect();
    assert_eq!(effort.len(), 2, "one per drawn problem");
    for file in effort {
        let svg = String::from_utf8(file.contents.clone()).unwrap();
        let name = file.path.to_string_lossy().to_string();
        // figures/arena-<k>-expanded.svg
        let k: usize = name.split('-').nth(1).unwrap().parse().unwrap();
        assert_eq!(svg.matches(r#"class="expanded""#).count(), 5, "{name}");
        for label in ["astar", "dijkstra", "bfs", "jps", "theta"] {
            let run = records
                .iter()
                .find(|r| r.problem == k && r.planner == label)
                .unwrap();
            let n = run.counters.get("n_expanded").unwrap();
            assert!(
                svg.contains(&format!("expanded: {n} cells")),
                "{name} {label} {n}"
            );
        }
        assert!(svg.contains("expanded cells: not recorded"), "rrt");
        // Dijkstra expands more than A* on the hardest problems.
        let count = |label: &str| {
            records
                .iter()
                .find(|r| r.problem == k && r.planner == label)
                .and_then(|r| r.counters.get("n_expanded"))
                .unwrap()
        };
        assert!(count("dijkstra") > count("astar"), "{name}");
    }
    // The per-run figures of `figures = "all"` draw them too.
    let per_run = files
        .iter()
        .find(|f| f.path.to_string_lossy().ends_with("-dijkstra.svg"))
        .unwrap();
    assert!(String::from_utf8_lossy(&per_run.contents).contains(r#"class="expanded""#));

    // A timed record whose counters the rerun does not repeat is an error, not a figure.
    let mut tampered = records.clone();
    let drawn = files
        .iter()
        .find_map(|f| {
            let name = f.path.to_string_lossy().to_string();
            name.strip_suffix("-expanded.svg")
                .and_then(|s| s.rsplit('-').next()?.parse::<usize>().ok())
        })
        .unwrap();
    let record = tampered
        .iter_mut()
        .find(|r| r.problem == drawn && r.planner == "bfs")
        .unwrap();
    let n = record.counters.get("n_expanded").unwrap();
    record.counters = record.counters.clone().with("n_expanded", n + 1);
    match expanded::record_all(&experiment, &tampered) {
        Err(ExpandedError::Mismatch { label, problem, .. }) => {
            assert_eq!((label.as_str(), problem), ("bfs", drawn));
        }
        other => panic!("expected a mismatch, got {other:?}"),
    }
    // Without `figures_expanded` nothing is rerun and no such figure is written.
    let mut plain = experiment.clone();
    plain.figures_expanded = false;
    let cells = expanded::record_all(&plain, &tampered).unwrap();
    assert!(cells.is_empty());
    let files = figures::render(&plain, &tampered, &cells);
    assert!(files
        .iter()
        .all(|f| !f.path.to_string_lossy().ends_with("-expanded.svg")));
}
