//! BFS on seed 003's maps and tables, hand-counted maps, identities on every map, a
//! reference search written here, budgets and configs.

mod common;

use planner_api::{
    Budget, Cell, Connectivity, Grid, MoveSet, NeighborOrder, Outcome, PathRule, Planner, Problem,
    Status,
};
use planner_bfs::{Bfs, Config, ConfigError};

fn plan(grid: &Grid, start: Cell, goal: Cell, config: Config) -> Outcome {
    let problem = Problem::new(grid, start, goal).unwrap();
    Bfs::new(config)
        .unwrap()
        .plan(&problem, &Budget::unlimited())
}

fn steps(outcome: &Outcome) -> Option<u64> {
    outcome.path.as_ref().map(|p| p.metrics().steps)
}

#[test]
fn seed_003_table_1_and_2_lengths() {
    // Table I (map1.txt, "Map 1".."Map 3" = pairs 1-3): BFS 18, 14, 16.
    let (grid, pairs) = common::wpi("wpi/map1.txt");
    let lengths: Vec<_> = pairs
        .iter()
        .map(|&(s, g)| steps(&plan(&grid, s, g, Config::default())))
        .collect();
    assert_eq!(lengths, [Some(18), Some(14), Some(16)]);
    // Table II (map3.txt): "Map 1" 70 is pair 1, "Map 2" 41 is pair 3.
    let (grid, pairs) = common::wpi("wpi/map3.txt");
    let (s, g) = pairs[0];
    assert_eq!(steps(&plan(&grid, s, g, Config::default())), Some(70));
    let (s, g) = pairs[2];
    assert_eq!((s, g), (Cell::new(3, 2), Cell::new(14, 12)));
    assert_eq!(steps(&plan(&grid, s, g, Config::default())), Some(41));
    // Seed 003's own order (left, right, up, down) gives the same lengths.
    let seed_order = Config {
        order: "L R U D".parse().unwrap(),
        ..Config::default()
    };
    assert_eq!(steps(&plan(&grid, s, g, seed_order)), Some(41));
}

#[test]
fn map2_pair_2_goal_on_an_obstacle_is_an_error_naming_the_cell() {
    let (grid, pairs) = common::wpi("wpi/map2.txt");
    let (start, goal) = pairs[1];
    assert_eq!(goal, Cell::new(12, 3));
    let err = Problem::new(&grid, start, goal).unwrap_err();
    assert_eq!(err.to_string(), "goal (12, 3) is blocked");
}

#[test]
fn every_wpi_pair_matches_the_reference_search() {
    for file in ["wpi/map1.txt", "wpi/map2.txt", "wpi/map3.txt"] {
        let (grid, pairs) = common::wpi(file);
        for (connectivity, k) in [(Connectivity::Four, 4), (Connectivity::Eight, 8)] {
            let config = Config {
                moves: connectivity,
                ..Config::default()
            };
            let moves = MoveSet::standard(connectivity);
            for &(s, g) in &pairs {
                if Problem::new(&grid, s, g).is_err() {
                    continue;
                }
                let outcome = plan(&grid, s, g, config.clone());
                let what = format!("{file} {s}->{g} {connectivity}");
                assert_eq!(
                    steps(&outcome),
                    common::fewest_moves(&grid, &moves, s, g),
                    "{what}"
                );
                outcome
                    .path
                    .as_ref()
                    .unwrap()
                    .validate(&grid, PathRule::Moves(&moves))
                    .unwrap();
                common::check_frontier_identities(&what, &outcome, k);
            }
        }
    }
}

/// Hand-counted maps. `check(map, start, goal, expect)` with expect =
/// [n_expanded, n_neighbor_checks, n_blocked, n_skipped, peak_open, n_open_insertions].
fn check(map: &str, start: (u32, u32), goal: (u32, u32), status: Status, expect: [u64; 6]) {
    let grid = Grid::from_ascii(map).unwrap();
    let outcome = plan(&grid, start.into(), goal.into(), Config::default());
    assert_eq!(outcome.status, status, "{map}");
    assert_eq!(common::frontier_counters(&outcome), expect, "{map}");
    common::check_frontier_identities(map, &outcome, 4);
}

#[test]
fn hand_counted() {
    // A ring around a pillar, (0,0) to (2,2), order R L D U. Dequeued in order, with the
    // outcome of each check (b blocked, s skipped, + enqueued):
    // (0,0): R (1,0)+, L b, D (0,1)+, U b          queue (1,0) (0,1)
    // (1,0): R (2,0)+, L (0,0)s, D (1,1)b, U b     queue (0,1) (2,0)
    // (0,1): R (1,1)b, L b, D (0,2)+, U (0,0)s     queue (2,0) (0,2)
    // (2,0): R b, L (1,0)s, D (2,1)+, U b          queue (0,2) (2,1)
    // (0,2): R (1,2)+, L b, D b, U (0,1)s          queue (2,1) (1,2)
    // (2,1): R b, L (1,1)b, D (2,2)+, U (2,0)s     queue (1,2) (2,2)
    // (1,2): R (2,2)s, L (0,2)s, D b, U (1,1)b     queue (2,2)
    // (2,2): the goal. 8 dequeued, 7 x 4 checks, 14 blocked, 7 skipped, queue never over 2,
    // 8 cells enqueued.
    check(
        "...\n.#.\n...",
        (0, 0),
        (2, 2),
        Status::Found,
        [8, 28, 14, 7, 2, 8],
    );
    // A wall: (0,0): R b, L b, D (0,1)+, U b; (0,1): R (1,1)b, L b, D b, U (0,0)s; empty.
    check(
        ".#.\n.#.",
        (0, 0),
        (2, 0),
        Status::NoPath,
        [2, 8, 6, 1, 1, 2],
    );
    // Start = goal: dequeued once, nothing checked.
    check("..", (1, 0), (1, 0), Status::Found, [1, 0, 0, 0, 1, 1]);
}

#[test]
fn identities_on_every_map() {
    for (name, grid) in common::paper_maps() {
        let n = grid.width() - 1;
        for (connectivity, k) in [(Connectivity::Four, 4), (Connectivity::Eight, 8)] {
            let config = Config {
                moves: connectivity,
                ..Config::default()
            };
            let outcome = plan(&grid, Cell::new(0, 0), Cell::new(n, n), config);
            common::check_frontier_identities(&format!("{name} {connectivity}"), &outcome, k);
        }
    }
    for map in common::movingai_maps() {
        let grid = common::movingai(&format!("movingai/{map}"));
        let (s, g) = common::first_scenario(&format!("movingai/{map}.scen"));
        // In full, and within a budget: the counters so far.
        let problem = Problem::new(&grid, s, g).unwrap();
        let mut bfs = Bfs::new(Config::default()).unwrap();
        let outcome = common::check_budget_cut(&mut bfs, &problem, &map, 4);
        let moves = MoveSet::standard(Connectivity::Four);
        assert_eq!(
            steps(&outcome),
            common::fewest_moves(&grid, &moves, s, g),
            "{map}"
        );
    }
}

#[test]
fn random_grids_match_the_reference_search() {
    for (round, (grid, start, goal)) in common::small_random_problems(0x9e37_79b9_7f4a_7c15, 200)
        .into_iter()
        .enumerate()
    {
        for (connectivity, cutting, k) in [
            (Connectivity::Four, false, 4),
            (Connectivity::Eight, false, 8),
            (Connectivity::Eight, true, 8),
        ] {
            let config = Config {
                moves: connectivity,
                corner_cutting: cutting,
                ..Config::default()
            };
            let moves = MoveSet::new(connectivity, cutting, &NeighborOrder::default()).unwrap();
            let outcome = plan(&grid, start, goal, config);
            let what = format!("round {round} {connectivity} cutting {cutting}\n{grid:?}");
            assert_eq!(
                steps(&outcome),
                common::fewest_moves(&grid, &moves, start, goal),
                "{what}"
            );
            if let Some(path) = &outcome.path {
                path.validate(&grid, PathRule::Moves(&moves)).unwrap();
                assert_eq!((path.start(), path.goal()), (Some(start), Some(goal)));
            }
            common::check_frontier_identities(&what, &outcome, k);
        }
    }
}

#[test]
fn budget_ends_the_search_with_the_counters_so_far() {
    let grid = Grid::new(12, 12).unwrap();
    let problem = Problem::new(&grid, Cell::new(0, 0), Cell::new(11, 11)).unwrap();
    let mut bfs = Bfs::new(Config::default()).unwrap();
    let outcome = bfs.plan(&problem, &Budget::expansions(10));
    assert_eq!(outcome.status, Status::BudgetExhausted);
    assert_eq!(outcome.path, None);
    assert_eq!(outcome.counters.get("n_expanded"), Some(10));
    common::check_frontier_identities("open 12x12, 10 expansions", &outcome, 4);
    let outcome = bfs.plan(&problem, &Budget::expansions(0));
    assert_eq!(outcome.status, Status::BudgetExhausted);
    assert_eq!(outcome.counters.get("n_expanded"), Some(0));
    // The planner is reusable: the same problem again gives the same outcome.
    let a = bfs.plan(&problem, &Budget::unlimited());
    let b = bfs.plan(&problem, &Budget::unlimited());
    assert_eq!(a, b);
    assert_eq!(a.counters.get("n_expanded"), Some(144));
}

#[test]
fn config_keys_and_errors() {
    let config: Config =
        toml::from_str("moves = 8\ncorner_cutting = true\norder = \"U D L R\"").unwrap();
    assert_eq!(config.moves, Connectivity::Eight);
    assert!(Bfs::new(config.clone()).is_ok());
    let json = serde_json::to_string(&config).unwrap();
    assert_eq!(serde_json::from_str::<Config>(&json).unwrap(), config);
    assert_eq!(toml::from_str::<Config>("").unwrap(), Config::default());
    assert!(toml::from_str::<Config>("mvoes = 4").is_err());
    assert!(toml::from_str::<Config>("moves = 5").is_err());
    let err = Bfs::new(Config {
        order: "R L D".parse().unwrap(),
        ..Config::default()
    })
    .unwrap_err();
    assert!(matches!(err, ConfigError::Order(_)));
    assert!(err.to_string().starts_with("parameter `order`: "), "{err}");
    let err = Bfs::new(Config {
        corner_cutting: true,
        ..Config::default()
    })
    .unwrap_err();
    assert!(
        err.to_string().starts_with("parameter `corner_cutting`: "),
        "{err}"
    );
    assert_eq!(Bfs::new(Config::default()).unwrap().name(), "bfs");
}

/// Every counter and path equals planner-testkit's `reference_frontier` (a `VecDeque`
/// used as a FIFO queue, moves through `MoveSet::apply`), on random grids with three move
/// sets and on every pair of seed 003's maps.
#[test]
fn counters_and_paths_equal_the_reference_frontier_search() {
    let problems = planner_testkit::small_and_wpi_problems(0x51ed_2701_aa44_0b13, 2000);
    let mut expanded = 0;
    for (connectivity, cutting) in [
        (Connectivity::Four, false),
        (Connectivity::Eight, false),
        (Connectivity::Eight, true),
    ] {
        let config = Config {
            moves: connectivity,
            corner_cutting: cutting,
            ..Config::default()
        };
        let moves = MoveSet::new(connectivity, cutting, &NeighborOrder::default()).unwrap();
        for (k, (grid, start, goal)) in problems.iter().enumerate() {
            let outcome = plan(grid, *start, *goal, config.clone());
            let (status, path, counters) =
                planner_testkit::reference_frontier(grid, &moves, *start, *goal, false);
            let what = format!("{connectivity} cutting {cutting} problem {k}");
            assert_eq!(outcome.status, status, "{what}");
            assert_eq!(common::frontier_counters(&outcome), counters, "{what}");
            assert_eq!(outcome.path.map(|p| p.cells().to_vec()), path, "{what}");
            expanded += counters[0];
        }
    }
    // 84,118 expansions (2026-12-06).
    assert!(expanded > 80_000, "{expanded}");
}
