//! Bidirectional A*'s lengths against planner-astar on every Moving AI scenario file (4-
//! and 8-connected) and on seeded random maps, hand-checked counters, budgets, unreachable
//! goals, reproducibility and parameter errors.
//!
//! In a debug build the scenario test runs every [`DEBUG_EVERY`]th scenario of each file
//! (the first included) to stay within CI time; a release build (`cargo test --release`)
//! or `GRIDPLAN_ALL_SCENARIOS=1` runs all of them.

use planner_api::{
    Budget, Cell, Connectivity, Grid, MoveSet, NeighborOrder, PathRule, PathSpec, Planner, Problem,
    Status,
};
use planner_astar::{AStar, Heuristic, TieBreak};
use planner_bidirectional_astar::{BidirectionalAStar, Config, Search};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// The stride through each `.scen` file in debug builds.
const DEBUG_EVERY: usize = 80;

fn scenario_stride() -> usize {
    if cfg!(debug_assertions) && std::env::var_os("GRIDPLAN_ALL_SCENARIOS").is_none() {
        DEBUG_EVERY
    } else {
        1
    }
}

fn config(moves: Connectivity) -> Config {
    Config {
        moves,
        ..Config::default()
    }
}

/// planner-astar with the same moves and a consistent heuristic: the reference lengths.
fn astar(moves: Connectivity) -> AStar {
    AStar::new(planner_astar::Config {
        moves,
        heuristic: match moves {
            Connectivity::Four => Heuristic::Manhattan,
            _ => Heuristic::Octile,
        },
        tie_break: TieBreak::HighG,
        ..Default::default()
    })
    .unwrap()
}

/// Runs both planners on `problem` and checks: the same status; when found, a valid path
/// from start to goal whose length equals A*'s cost and the search's `mu`. Returns the
/// search when a path was found.
fn check(
    what: &str,
    problem: &Problem<'_>,
    moves: Connectivity,
    bidirectional: &mut BidirectionalAStar,
    reference: &mut AStar,
) -> Option<Search> {
    let expect = reference.search(problem, &Budget::unlimited());
    let found = bidirectional.search(problem, &Budget::unlimited());
    let counters = found.counters();
    assert_eq!(found.status, expect.status, "{what}: {counters}");
    let Some(optimum) = expect.cost else {
        assert_eq!(found.path, None, "{what}");
        return None;
    };
    let path = found.path.as_ref().expect("found has a path");
    assert_eq!(
        (path.start(), path.goal()),
        (Some(problem.start()), Some(problem.goal())),
        "{what}"
    );
    let set = MoveSet::new(moves, false, &NeighborOrder::default()).unwrap();
    if let Err(e) = path.validate(problem.grid(), PathRule::Moves(&set)) {
        panic!("{what}: {e}");
    }
    let length = path.metrics().length;
    let cost = found.cost.unwrap();
    let close = |a: f64, b: f64| (a - b).abs() <= 1e-9 * a.max(1.0);
    assert!(
        close(length, optimum),
        "{what}: bidirectional {length}, A* {optimum}"
    );
    assert!(close(cost, length), "{what}: mu {cost}, path {length}");
    if moves == Connectivity::Four {
        assert_eq!(path.metrics().steps as f64, optimum, "{what}");
    }
    Some(found)
}

#[test]
fn lengths_equal_astar_on_every_scen_file() {
    let stride = scenario_stride();
    for moves in [Connectivity::Four, Connectivity::Eight] {
        let mut bidirectional = BidirectionalAStar::new(config(moves)).unwrap();
        let mut reference = astar(moves);
        let (mut n_checked, mut n_both_sides) = (0, 0);
        for map in planner_testkit::movingai_maps() {
            let grid = planner_testkit::movingai(&format!("movingai/{map}"));
            let scenarios = planner_testkit::scenarios(&format!("movingai/{map}.scen"));
            for scenario in scenarios.iter().step_by(stride) {
                let what = format!("{map} line {} {moves}", scenario.line);
                let problem = Problem::new(&grid, scenario.start, scenario.goal).unwrap();
                let found = check(&what, &problem, moves, &mut bidirectional, &mut reference)
                    .unwrap_or_else(|| panic!("{what}: solvable"));
                if moves == Connectivity::Eight {
                    let (length, optimum) = (found.cost.unwrap(), scenario.optimal_length);
                    assert!(
                        (length - optimum).abs() <= 1e-4 * optimum.max(1.0),
                        "{what}: {length} vs stated {optimum}"
                    );
                }
                n_both_sides += usize::from(found.stats.iter().all(|s| s.n_expanded > 0));
                n_checked += 1;
            }
        }
        assert!(n_checked >= 5665 / DEBUG_EVERY, "{n_checked}");
        // Both searches do work on most scenarios: this is not A* in disguise.
        assert!(
            n_both_sides * 10 >= n_checked * 9,
            "{moves}: {n_both_sides} of {n_checked}"
        );
    }
}

#[test]
fn lengths_equal_astar_on_random_maps() {
    for moves in [Connectivity::Four, Connectivity::Eight] {
        let mut bidirectional = BidirectionalAStar::new(config(moves)).unwrap();
        let mut reference = astar(moves);
        // Small maps, many without a path.
        let mut n_found = 0;
        for (round, (grid, start, goal)) in planner_testkit::small_random_problems(11, 400)
            .iter()
            .enumerate()
        {
            let problem = Problem::new(grid, *start, *goal).unwrap();
            let what = format!("small {round} {moves}");
            let found = check(&what, &problem, moves, &mut bidirectional, &mut reference);
            n_found += usize::from(found.is_some());
        }
        assert!((100..350).contains(&n_found), "{n_found} of 400 found");
        // Larger maps.
        let mut rng = ChaCha8Rng::seed_from_u64(20);
        for round in 0..120 {
            let side = rng.gen_range(10..50);
            let free = (0..side * side).map(|_| !rng.gen_bool(0.3)).collect();
            let mut grid = Grid::from_free_cells(side, side, free).unwrap();
            let start = Cell::new(rng.gen_range(0..side), rng.gen_range(0..side));
            let goal = Cell::new(rng.gen_range(0..side), rng.gen_range(0..side));
            grid.set_free(start, true);
            grid.set_free(goal, true);
            let problem = Problem::new(&grid, start, goal).unwrap();
            check(
                &format!("random {round} {moves}"),
                &problem,
                moves,
                &mut bidirectional,
                &mut reference,
            );
        }
    }
}

#[test]
fn counters_by_hand() {
    // A corridor, 4-connected, S = (0,0), G = (3,0); h_F = 3 - x, h_B = x. Both OPENs hold
    // one node at every step, so the forward side expands (ties go forward):
    // (0,0): R (1,0) g 1 inserted; L, D, U blocked.
    // (1,0): R (2,0) g 2 inserted; L closed.
    // (2,0): R (3,0) g 3 inserted; it is the backward start (g_B 0): mu = 3, meeting
    //        update 1; L closed.
    // Then fmin_F = f(3,0) = 3 >= mu: stop. 3 expansions checking 4 moves each, 5 safe,
    // 2 skipped; insertions 4 forward + 1 backward; OPEN never holds more than 2 nodes.
    let grid = Grid::from_ascii("....").unwrap();
    let problem = Problem::new(&grid, Cell::new(0, 0), Cell::new(3, 0)).unwrap();
    let outcome = BidirectionalAStar::new(config(Connectivity::Four))
        .unwrap()
        .plan(&problem, &Budget::unlimited());
    let text = planner_testkit::outcome_text(&outcome);
    assert_eq!(
        text,
        "status found\npath (0,0) (1,0) (2,0) (3,0)\n\
         n_expanded=3 n_neighbor_checks=12 n_blocked=7 n_skipped=2 n_open_insertions=5 n_relaxations=3 peak_open=2 \
         forward_n_expanded=3 forward_n_neighbor_checks=12 forward_n_blocked=7 forward_n_skipped=2 forward_n_open_insertions=4 forward_n_relaxations=3 forward_peak_open=1 \
         backward_n_expanded=0 backward_n_neighbor_checks=0 backward_n_blocked=0 backward_n_skipped=0 backward_n_open_insertions=1 backward_n_relaxations=0 backward_peak_open=1 \
         n_meeting_updates=1"
    );
    // Start = goal: met before any expansion, a one-cell path.
    let same = Problem::new(&grid, Cell::new(2, 0), Cell::new(2, 0)).unwrap();
    let outcome = BidirectionalAStar::new(Config::default())
        .unwrap()
        .plan(&same, &Budget::unlimited());
    assert_eq!(outcome.status, Status::Found);
    assert_eq!(outcome.path.unwrap().cells(), &[Cell::new(2, 0)]);
    assert_eq!(outcome.counters.get("n_expanded"), Some(0));
}

#[test]
fn unreachable_goal_is_no_path() {
    let grid = Grid::from_ascii(
        "
        ..#....
        ..#....
        .##....
        ",
    )
    .unwrap();
    let problem = Problem::new(&grid, Cell::new(0, 0), Cell::new(6, 2)).unwrap();
    for moves in [Connectivity::Four, Connectivity::Eight] {
        let found = BidirectionalAStar::new(config(moves))
            .unwrap()
            .search(&problem, &Budget::unlimited());
        assert_eq!(found.status, Status::NoPath, "{moves}");
        assert_eq!((found.path, found.cost), (None, None));
        // The smaller OPEN empties first: the start's component of 5 cells, all expanded
        // forward, while the backward search works its larger side.
        assert_eq!(found.stats[0].n_expanded, 5, "{moves}");
        assert_eq!(found.stats[0].n_open_insertions, 5, "{moves}");
        assert_eq!(found.n_meeting_updates, 0);
    }
}

#[test]
fn budget_is_honoured() {
    let grid = planner_testkit::movingai("movingai/arena.map");
    let scenario = planner_testkit::scenarios("movingai/arena.map.scen")
        .into_iter()
        .last()
        .unwrap();
    let problem = Problem::new(&grid, scenario.start, scenario.goal).unwrap();
    for moves in [Connectivity::Four, Connectivity::Eight] {
        let mut planner = BidirectionalAStar::new(config(moves)).unwrap();
        let full = planner.plan(&problem, &Budget::unlimited());
        assert_eq!(full.status, Status::Found);
        let n = full.counters.get("n_expanded").unwrap();
        for cut in [0, 1, n / 2, n - 1] {
            let part = planner.plan(&problem, &Budget::expansions(cut));
            assert_eq!(part.status, Status::BudgetExhausted, "{moves} {cut}");
            assert_eq!(part.counters.get("n_expanded"), Some(cut), "{moves}");
            // A path met before the budget ran out is returned, and it is valid.
            if let Some(path) = &part.path {
                let set = MoveSet::new(moves, false, &NeighborOrder::default()).unwrap();
                assert!(path.validate(&grid, PathRule::Moves(&set)).is_ok());
            }
        }
        assert_eq!(
            planner.plan(&problem, &Budget::expansions(n)),
            full,
            "{moves}"
        );
    }
}

#[test]
fn reproducible_and_independent_of_earlier_queries() {
    let grid = planner_testkit::movingai("movingai/den520d.map");
    let scenarios = planner_testkit::scenarios("movingai/den520d.map.scen");
    let mut reused = BidirectionalAStar::new(Config::default()).unwrap();
    for scenario in scenarios.iter().step_by(101) {
        let problem = Problem::new(&grid, scenario.start, scenario.goal).unwrap();
        let a = BidirectionalAStar::new(Config::default())
            .unwrap()
            .search(&problem, &Budget::unlimited());
        let b = reused.search(&problem, &Budget::unlimited());
        let c = reused.search(&problem, &Budget::unlimited());
        assert_eq!(a, b, "line {}", scenario.line);
        assert_eq!(b, c, "line {}", scenario.line);
    }
}

#[test]
fn bad_parameters_are_errors_naming_the_key() {
    let check = |toml: &str, key: &str| {
        let config: Config = toml::from_str(toml).unwrap();
        let err = BidirectionalAStar::new(config).unwrap_err();
        assert!(
            err.to_string().contains(&format!("parameter `{key}`")),
            "{err}"
        );
    };
    check("moves = 16", "moves");
    check("moves = 8\ncorner_cutting = true", "corner_cutting");
    check("moves = 4\norder = \"R L D U DR DL UR UL\"", "order");
    let unknown: Result<Config, _> = toml::from_str("heuristic = \"octile\"");
    assert!(unknown.unwrap_err().to_string().contains("heuristic"));
    let err = BidirectionalAStar::new(Config {
        corner_cutting: true,
        ..Config::default()
    })
    .unwrap_err();
    assert_eq!(
        err.to_string(),
        "parameter `corner_cutting`: corner cutting is not supported"
    );
    for moves in [Connectivity::Four, Connectivity::Eight] {
        let planner = BidirectionalAStar::new(config(moves)).unwrap();
        let set = MoveSet::new(moves, false, &NeighborOrder::default()).unwrap();
        assert_eq!(planner.specs().path_rule, PathSpec::Moves(set));
    }
}
