//! RRT-Connect end to end: hand-checked runs, validity and tree invariants on seeded
//! random maps, reproducibility, the budget, and success wherever RRT succeeds.

use std::collections::HashSet;

use planner_api::{
    Budget, Cell, Connectivity, Grid, MoveSet, Outcome, PathRule, Planner, Problem, Status,
};
use planner_rrt::Steer;
use planner_rrt_connect::{Config, RrtConnect};
use planner_testkit::{fewest_moves, small_random_problems};

fn counter(outcome: &Outcome, name: &str) -> u64 {
    outcome
        .counters
        .get(name)
        .unwrap_or_else(|| panic!("no counter {name} in {}", outcome.counters))
}

/// The counter identity of the crate docs, and the path's ends and distinct cells.
fn check_outcome(what: &str, outcome: &Outcome, start: Cell, goal: Cell) {
    let c = |name| counter(outcome, name);
    assert_eq!(c("n_expanded"), c("n_extensions"), "{what}");
    let met = u64::from(outcome.status == Status::Found && start != goal);
    assert_eq!(
        c("n_extensions"),
        c("n_collisions") + c("n_duplicates") + c("start_tree_size") - 1 + c("goal_tree_size") - 1
            + met,
        "{what}: {}",
        outcome.counters
    );
    assert!(
        c("n_connect_steps") <= c("n_extensions") - c("n_duplicates"),
        "{what}"
    );
    if let Some(path) = &outcome.path {
        assert_eq!(
            (path.start(), path.goal()),
            (Some(start), Some(goal)),
            "{what}"
        );
        let distinct: HashSet<Cell> = path.cells().iter().copied().collect();
        assert_eq!(distinct.len(), path.len(), "{what}: a repeated cell");
    }
}

fn run(grid: &Grid, start: Cell, goal: Cell, config: &Config, budget: &Budget) -> Outcome {
    let problem = Problem::new(grid, start, goal).unwrap();
    let outcome = RrtConnect::new(config.clone())
        .unwrap()
        .plan(&problem, budget);
    check_outcome(
        &format!("{start} -> {goal}, {config:?}"),
        &outcome,
        start,
        goal,
    );
    outcome
}

/// Two cells: the first sample is the start (a duplicate in the start tree, then the goal
/// tree connects to it in one step) or the goal (the start tree's first step meets the goal
/// tree). Both happen over 20 seeds, and both give the one path.
#[test]
fn two_cells_by_hand() {
    let grid = Grid::from_ascii("..").unwrap();
    let (start, goal) = (Cell::new(0, 0), Cell::new(1, 0));
    let mut seen = HashSet::new();
    for seed in 0..20 {
        let outcome = run(
            &grid,
            start,
            goal,
            &Config {
                seed,
                ..Config::default()
            },
            &Budget::unlimited(),
        );
        assert_eq!(outcome.status, Status::Found);
        assert_eq!(outcome.path.as_ref().unwrap().cells(), [start, goal]);
        let counts = (
            counter(&outcome, "n_iterations"),
            counter(&outcome, "n_extensions"),
            counter(&outcome, "n_duplicates"),
            counter(&outcome, "n_connect_steps"),
        );
        assert!(
            counts == (1, 2, 1, 1) || counts == (1, 1, 0, 0),
            "{counts:?}"
        );
        seen.insert(counts);
    }
    assert_eq!(seen.len(), 2);
    // Start = goal: found before any iteration.
    let outcome = run(
        &grid,
        start,
        start,
        &Config::default(),
        &Budget::unlimited(),
    );
    assert_eq!(outcome.path.as_ref().unwrap().cells(), [start]);
    assert_eq!(counter(&outcome, "n_iterations"), 0);
}

/// A wall between the two cells: every sample is the start or the goal. Sampling the root
/// of the active tree is a duplicate followed by a trapped connect; sampling the other root
/// is a trapped extend. The iterations run out; nothing is ever added.
#[test]
fn unreachable_goal_exhausts_the_iterations() {
    let grid = Grid::from_ascii(".#.").unwrap();
    let (start, goal) = (Cell::new(0, 0), Cell::new(2, 0));
    for seed in 0..10 {
        let config = Config {
            seed,
            max_iterations: 25,
            ..Config::default()
        };
        let outcome = run(&grid, start, goal, &config, &Budget::unlimited());
        assert_eq!(
            (outcome.status, outcome.path.as_ref()),
            (Status::BudgetExhausted, None)
        );
        let c = |name| counter(&outcome, name);
        assert_eq!(c("n_iterations"), 25);
        assert_eq!((c("start_tree_size"), c("goal_tree_size")), (1, 1));
        // One collision per iteration, and one extra extension per duplicate.
        assert_eq!(c("n_collisions"), 25);
        assert_eq!(c("n_extensions"), 25 + c("n_duplicates"));
    }
}

/// The budget counts extensions: a run cut at half its extensions stops after exactly
/// that many, without a path; the uncut run is reproduced by the same seed.
#[test]
fn budget_counts_extensions() {
    let (grid, pairs) = planner_testkit::wpi("wpi/map3.txt");
    for (seed, &(start, goal)) in pairs.iter().enumerate() {
        let config = Config {
            seed: seed as u64,
            ..Config::default()
        };
        let full = run(&grid, start, goal, &config, &Budget::unlimited());
        assert_eq!(full.status, Status::Found);
        assert_eq!(run(&grid, start, goal, &config, &Budget::unlimited()), full);
        let cut = counter(&full, "n_extensions") / 2;
        let outcome = run(&grid, start, goal, &config, &Budget::expansions(cut));
        assert_eq!(
            (outcome.status, outcome.path.as_ref()),
            (Status::BudgetExhausted, None)
        );
        assert_eq!(counter(&outcome, "n_extensions"), cut);
    }
}

/// Same seed, same outcome: fresh planners, a planner reused after another map, and
/// different outcomes for different seeds.
#[test]
fn same_seed_same_outcome() {
    let (grid, pairs) = planner_testkit::wpi("wpi/map3.txt");
    let (start, goal) = pairs[0];
    let problem = Problem::new(&grid, start, goal).unwrap();
    let first = run(&grid, start, goal, &Config::default(), &Budget::unlimited());
    let mut reused = RrtConnect::new(Config::default()).unwrap();
    let (other, other_pairs) = planner_testkit::wpi("wpi/map1.txt");
    reused.plan(
        &Problem::new(&other, other_pairs[0].0, other_pairs[0].1).unwrap(),
        &Budget::unlimited(),
    );
    assert_eq!(reused.plan(&problem, &Budget::unlimited()), first);
    let extensions: HashSet<u64> = (1..8)
        .map(|seed| {
            let outcome = run(
                &grid,
                start,
                goal,
                &Config {
                    seed,
                    ..Config::default()
                },
                &Budget::unlimited(),
            );
            counter(&outcome, "n_extensions")
        })
        .collect();
    assert!(extensions.len() > 3, "{extensions:?}");
}

/// Trees after a run: disjoint cells, each tree rooted at its end, every edge a free
/// segment from an earlier node.
fn check_trees(what: &str, planner: &RrtConnect, grid: &Grid, roots: [Cell; 2]) {
    let mut all = HashSet::new();
    for (k, (tree, root)) in planner.trees().into_iter().zip(roots).enumerate() {
        let nodes: Vec<(Cell, Option<Cell>)> = tree.collect();
        assert_eq!(nodes[0], (root, None), "{what}");
        for (i, &(cell, parent)) in nodes.iter().enumerate() {
            // Start = goal is the one cell both trees hold (as their roots).
            let shared_root = k == 1 && i == 0 && roots[0] == roots[1];
            if !shared_root {
                assert!(all.insert(cell), "{what}: {cell} in both trees or twice");
            }
            if let Some(parent) = parent {
                assert!(nodes[..i].iter().any(|&(c, _)| c == parent), "{what}");
                assert!(planner_api::segment_is_free(grid, parent, cell), "{what}");
            }
        }
    }
}

/// 300 seeded random maps (planner-testkit's, many unsolvable), random configs: a found
/// path is valid (any-angle, and the 4- or 8-connected moves with `step = 1`, never fewer
/// moves than the optimum) and joins start to goal; a reachable goal is found within
/// 20,000 iterations, an unreachable one exhausts them; the trees are disjoint and free.
/// RRT with the same seed, steering and iterations finds a path only where RRT-Connect
/// does.
#[test]
fn valid_on_random_maps_and_found_where_rrt_finds() {
    let (mut found, mut exhausted) = (0, 0);
    for (case, (grid, start, goal)) in small_random_problems(5, 300).into_iter().enumerate() {
        let steer = if case % 2 == 0 {
            Steer::Four
        } else {
            Steer::Eight
        };
        let config = Config {
            seed: case as u64,
            max_iterations: 20_000,
            steer,
            step: 1 + (case / 2 % 4) as u32,
        };
        let what = format!("case {case}: {start} -> {goal}, {config:?}\n{grid:?}");
        let problem = Problem::new(&grid, start, goal).unwrap();
        let mut planner = RrtConnect::new(config.clone()).unwrap();
        let outcome = planner.plan(&problem, &Budget::unlimited());
        check_outcome(&what, &outcome, start, goal);
        check_trees(&what, &planner, &grid, [start, goal]);
        let reachable = fewest_moves(&grid, &MoveSet::standard(Connectivity::Four), start, goal);
        let rrt = planner_rrt::Rrt::new(planner_rrt::Config {
            seed: config.seed,
            max_iterations: 20_000,
            steer,
            step: config.step,
            ..planner_rrt::Config::default()
        })
        .unwrap()
        .plan(&problem, &Budget::unlimited());
        if rrt.status == Status::Found {
            assert_eq!(outcome.status, Status::Found, "{what}: RRT found a path");
        }
        match outcome.status {
            Status::Found => {
                found += 1;
                assert!(reachable.is_some(), "{what}");
                let path = outcome.path.as_ref().unwrap();
                assert_eq!(path.validate(&grid, PathRule::AnyAngle), Ok(()), "{what}");
                if let Some(connectivity) = config.path_moves() {
                    let moves = MoveSet::standard(connectivity);
                    assert_eq!(
                        path.validate(&grid, PathRule::Moves(&moves)),
                        Ok(()),
                        "{what}"
                    );
                    let optimum = fewest_moves(&grid, &moves, start, goal).expect("reachable");
                    assert!(path.metrics().steps >= optimum, "{what}");
                }
            }
            Status::BudgetExhausted => {
                exhausted += 1;
                assert!(reachable.is_none(), "{what}");
                assert_eq!(counter(&outcome, "n_iterations"), 20_000, "{what}");
            }
            Status::NoPath => panic!("RRT-Connect cannot prove there is no path: {what}"),
        }
    }
    assert!(
        found > 100 && exhausted > 30,
        "found {found}, exhausted {exhausted}"
    );
}

/// Every valid pair of seed 003's maps, 20 seeds, four steering variants: RRT-Connect finds
/// a valid path every time RRT does (RRT finds all of them), within the default budget.
#[test]
fn solves_every_wpi_problem_rrt_solves() {
    for name in ["map1", "map2", "map3"] {
        let (grid, pairs) = planner_testkit::wpi(&format!("wpi/{name}.txt"));
        for &(start, goal) in &pairs {
            let Ok(problem) = Problem::new(&grid, start, goal) else {
                continue; // map2's second pair puts its goal on an obstacle
            };
            for (steer, step) in [
                (Steer::Four, 1),
                (Steer::Eight, 1),
                (Steer::Four, 3),
                (Steer::Eight, 5),
            ] {
                for seed in 0..20 {
                    let config = Config {
                        seed,
                        steer,
                        step,
                        ..Config::default()
                    };
                    let what = format!("{name} {start} -> {goal}, {config:?}");
                    let rrt = planner_rrt::Rrt::new(planner_rrt::Config {
                        seed,
                        steer,
                        step,
                        ..planner_rrt::Config::default()
                    })
                    .unwrap()
                    .plan(&problem, &Budget::unlimited());
                    assert_eq!(rrt.status, Status::Found, "{what}");
                    let outcome = RrtConnect::new(config.clone())
                        .unwrap()
                        .plan(&problem, &Budget::unlimited());
                    check_outcome(&what, &outcome, start, goal);
                    assert_eq!(outcome.status, Status::Found, "{what}");
                    let path = outcome.path.as_ref().unwrap();
                    assert_eq!(path.validate(&grid, PathRule::AnyAngle), Ok(()), "{what}");
                }
            }
        }
    }
}

/// A wall-clock budget of zero stops the search at the clock's first reading, after
/// `TIME_CHECK_INTERVAL - 1` extensions (seed 0 on map3's first pair needs more).
#[test]
fn time_budget_is_honoured() {
    let (grid, pairs) = planner_testkit::wpi("wpi/map3.txt");
    let (start, goal) = pairs[0];
    let full = run(&grid, start, goal, &Config::default(), &Budget::unlimited());
    let interval = u64::from(planner_api::BudgetClock::TIME_CHECK_INTERVAL);
    assert!(counter(&full, "n_extensions") > interval);
    let budget = Budget::unlimited().with_time(std::time::Duration::ZERO);
    let outcome = run(&grid, start, goal, &Config::default(), &budget);
    assert_eq!(
        (outcome.status, outcome.path.as_ref()),
        (Status::BudgetExhausted, None)
    );
    assert_eq!(counter(&outcome, "n_expanded"), interval - 1);
}

/// Every status, path and counter equals planner-testkit's `reference_rrt_connect` (the
/// run written again: the documented draws, flat trees with a linear scan for the nearest
/// node, planner-api's segment traversal), on random grids, seeds, both steerings and steps
/// of 1 to 4.
#[test]
fn runs_equal_the_reference_rrt_connect() {
    let mut found = 0;
    for (k, (grid, start, goal)) in small_random_problems(0x00c0_ffee, 600).iter().enumerate() {
        let settings = planner_testkit::RrtSettings {
            seed: k as u64 * 104_729,
            goal_bias: 0.0,
            max_iterations: 300,
            eight: k % 3 == 0,
            step: 1 + (k % 4) as u32,
        };
        let config = Config {
            seed: settings.seed,
            max_iterations: settings.max_iterations,
            steer: if settings.eight {
                Steer::Eight
            } else {
                Steer::Four
            },
            step: settings.step,
        };
        let outcome = RrtConnect::new(config).unwrap().plan(
            &Problem::new(grid, *start, *goal).unwrap(),
            &Budget::unlimited(),
        );
        let (status, path, counters) =
            planner_testkit::reference_rrt_connect(grid, *start, *goal, settings);
        let what = format!("problem {k}: {settings:?}");
        let names = planner_testkit::RRT_CONNECT_COUNTERS;
        planner_testkit::assert_reference_outcome(&outcome, (status, path), names, counters, &what);
        found += usize::from(status == Status::Found);
    }
    // 503 of the 600 runs meet (2026-12-06): paths are compared too.
    assert!(found > 450, "{found}");
}
