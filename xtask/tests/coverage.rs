//! Coverage planners in the runner: `configs/coverage.toml` covers every map completely
//! with valid paths, and `problems = "start"` configs are checked.

use crate::common;

use common::root;
use planner_api::reachable_cells;
use planner_runner::config;

#[test]
fn coverage_config_covers_every_map() {
    let experiment = config::load(&root().join("configs/coverage.toml")).unwrap();
    let records = common::run(&experiment, 2);
    assert_eq!(
        records.len(),
        experiment.maps.len() * experiment.planners.len()
    );
    for r in &records {
        let what = format!("{} on {}", r.planner, r.map);
        let map = experiment.maps.iter().find(|m| m.name == r.map).unwrap();
        let reachable = reachable_cells(&map.grid, r.start)
            .iter()
            .filter(|&&x| x)
            .count() as u64;
        assert_eq!(r.status.as_str(), "found", "{what}");
        assert_eq!(r.valid, Some(true), "{what}");
        assert_eq!(r.counters.get("n_reachable"), Some(reachable), "{what}");
        assert_eq!(r.counters.get("n_covered"), Some(reachable), "{what}");
        let path = r.path.as_ref().unwrap();
        assert_eq!(r.steps, Some(path.len() as u64 - 1), "{what}");
        // Each return ends where the next filling starts; the legs are in order.
        let legs = r.returns.as_ref().unwrap();
        assert_eq!(
            r.counters.get("n_backtracking_points"),
            Some(legs.len() as u64)
        );
        assert!(legs.windows(2).all(|w| w[0].end < w[1].start), "{what}");
        let return_moves: usize = legs.iter().map(|l| l.end - l.start).sum();
        assert_eq!(
            r.counters.get("n_return_moves"),
            Some(return_moves as u64),
            "{what}"
        );
    }
    // The crop of 16room_000 keeps rooms whose doors lead out of it: free but unreachable.
    let crop = experiment
        .maps
        .iter()
        .find(|m| m.name == "16room_000-crop64.map")
        .unwrap();
    assert_eq!(crop.grid.n_free(), 3624);
    assert_eq!(
        records
            .iter()
            .find(|r| r.map == crop.name)
            .unwrap()
            .counters
            .get("n_reachable"),
        Some(3399)
    );
}

fn error(text: &str) -> String {
    let path = root().join("configs/bad.toml");
    config::parse(&path, text)
        .map(|_| ())
        .unwrap_err()
        .to_string()
        .replace(&path.display().to_string(), "bad.toml")
}

#[test]
fn start_problems_are_checked() {
    let maps = "[[maps]]\nfiles = [\"../maps/coverage/rooms30-1.map\"]\n";
    assert_eq!(
        error(&format!(
            "name = \"x\"\n{maps}problems = \"start\"\n[planners.a]\nplanner = \"coverage\"\n"
        )),
        "bad.toml:2:1: maps[0]: `problems = \"start\"` needs `start = [x, y]`"
    );
    assert_eq!(
        error(&format!(
            "name = \"x\"\n{maps}problems = \"corners\"\nstart = [0, 1]\n[planners.a]\nplanner = \"coverage\"\n"
        )),
        "bad.toml:5:9: maps[0]: key `start` goes with `problems = \"start\"`"
    );
    assert_eq!(
        error(&format!(
            "name = \"x\"\n{maps}problems = \"start\"\nstart = [0, 1]\n[planners.a]\nplanner = \"coverage\"\n[planners.b]\nplanner = \"astar\"\n"
        )),
        "bad.toml:4:12: `problems = \"start\"` has no goal, but planner `b` (astar) is not a coverage planner (coverage planners: coverage)"
    );
    assert_eq!(
        error(&format!(
            "name = \"x\"\n{maps}problems = \"start\"\nstart = [0, 1]\n[planners.a]\nplanner = \"coverage\"\nrotation = \"cw\"\n"
        )),
        "bad.toml:8:1: planner `a` (coverage): parameter `rotation` applies only to pattern = \"zigzag\""
    );
    // A blocked start is recorded as an invalid problem, not a config error.
    let experiment = config::parse(
        &root().join("configs/bad.toml"),
        &format!("name = \"x\"\n{maps}problems = \"start\"\nstart = [0, 0]\n[planners.a]\nplanner = \"coverage\"\n"),
    )
    .unwrap();
    let records = common::run(&experiment, 1);
    assert_eq!(records[0].status.as_str(), "invalid_problem");
    assert_eq!(records[0].error.as_deref(), Some("start (0, 0) is blocked"));
}

/// `cargo xtask plan` runs a coverage planner from --start: the same path, counters and
/// returns as the config's run of that planner, and 100% coverage; --goal is refused.
#[test]
fn plan_runs_coverage_planners_like_the_config() {
    let config_path = root().join("configs/coverage.toml");
    let experiment = config::load(&config_path).unwrap();
    let records = common::run(&experiment, 1);
    let record = records
        .iter()
        .find(|r| r.map == "rooms30-1.map" && r.planner == "zigzag")
        .unwrap();
    let args = planner_runner::plan::PlanArgs {
        map: root().join("maps/coverage/rooms30-1.map"),
        planner: "zigzag".into(),
        config: Some(config_path),
        start: Some(planner_api::Cell::new(0, 1)),
        ..Default::default()
    };
    let result = planner_runner::plan::run(&args).unwrap();
    assert!(result.coverage);
    assert_eq!(result.record.path, record.path);
    assert_eq!(result.record.counters, record.counters);
    let json: serde_json::Value = serde_json::from_str(&result.to_json().unwrap()).unwrap();
    assert_eq!(json["status"], "found");
    assert_eq!(json["coverage"]["percent"], 100.0);
    let returns = json["coverage"]["returns"].as_array().unwrap().len();
    assert_eq!(Some(returns), record.returns.as_ref().map(Vec::len));
    let text = result.to_text();
    assert!(
        text.contains("zigzag on a 30x30 grid, covering from (0, 1): found"),
        "{text}"
    );
    assert!(text.contains("reachable cells (100.00%)"), "{text}");

    let with_goal = planner_runner::plan::PlanArgs {
        goal: Some(planner_api::Cell::new(5, 5)),
        ..args
    };
    let error = planner_runner::plan::run(&with_goal).err().unwrap();
    assert_eq!(
        error.to_string(),
        "`coverage` is a coverage planner: it covers from --start and takes no --goal"
    );
}

/// Every return leg of every coverage run of every config (as snapshotted) is the path
/// `planner_testkit::reference_astar` finds between the leg's ends with coverage's A*
/// settings (8-connected, octile, FIFO, exact costs): the snapshot's paths, turns and
/// scores are checked against an independent search, not only pinned.
#[test]
fn every_return_leg_is_the_reference_search_path() {
    let moves = planner_api::MoveSet::standard(planner_api::Connectivity::Eight);
    let mut n_legs = 0;
    let n_runs = common::for_each_snapshotted_run("coverage", |path, map, _, r| {
        let what = format!("{} {} {}", path.display(), r.map, r.planner);
        let cells = r.path.as_ref().unwrap().cells();
        for leg in r.returns.as_ref().unwrap() {
            let (start, goal) = (cells[leg.start], cells[leg.end]);
            let h = |c: planner_api::Cell| {
                planner_api::Cost::octile_distance(c.x.abs_diff(goal.x), c.y.abs_diff(goal.y))
            };
            let tie = planner_testkit::Tie::Fifo;
            let (_, found, _) =
                planner_testkit::reference_astar(&map.grid, &moves, h, tie, start, goal);
            let leg_cells = cells[leg.start..=leg.end].to_vec();
            assert_eq!(found, Some(leg_cells), "{what}: leg {leg:?}");
            n_legs += 1;
        }
    });
    assert!(
        n_runs >= 10 && n_legs >= n_runs,
        "{n_runs} runs, {n_legs} legs"
    );
}

/// Every coverage run of every config (as snapshotted) has exactly the path and counters of
/// `planner_testkit::reference_coverage`, seed 004's run written again (filling rules,
/// backtracking points, the documented branch and bound over the test kit's reference A*):
/// the snapshot's coverage counters are checked against an independent run, not only
/// pinned.
#[test]
fn every_coverage_run_matches_the_reference_run() {
    use planner_coverage::{Heading, Pattern, Rotation, Side};
    let index = |h: Heading| match h {
        Heading::Right => 0,
        Heading::Down => 1,
        Heading::Left => 2,
        Heading::Up => 3,
    };
    let n_runs = common::for_each_snapshotted_run("coverage", |path, map, params, r| {
        let config: planner_coverage::Config = params.clone().try_into().unwrap();
        let fill = match config.pattern {
            Pattern::Spiral => planner_testkit::Fill::Spiral {
                left: config.reference_side.unwrap_or_default() == Side::Left,
                heading: index(config.heading.unwrap_or(Heading::Right)),
            },
            Pattern::Zigzag => {
                let (turn, first) = match config.rotation.unwrap_or_default() {
                    Rotation::CounterClockwise => (3, Heading::Right),
                    Rotation::Clockwise => (1, Heading::Down),
                };
                let first = index(config.first.unwrap_or(first));
                planner_testkit::Fill::Zigzag {
                    order: [0, 1, 2, 3].map(|k| (first + k * turn) % 4),
                }
            }
        };
        let (cells, counters) = planner_testkit::reference_coverage(&map.grid, r.start, fill);
        let what = format!("{} {} {}", path.display(), r.map, r.planner);
        assert_eq!(
            r.path.as_ref().map(|p| p.cells().to_vec()),
            Some(cells),
            "{what}"
        );
        let actual = planner_testkit::COVERAGE_COUNTERS.map(|n| r.counters.get(n).unwrap());
        assert_eq!(actual, counters, "{what}");
    });
    // coverage.toml: 40 runs (its maps, starts and pattern settings).
    assert_eq!(n_runs, 40);
}
