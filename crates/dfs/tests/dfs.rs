//! DFS on seed 003's maps and tables, hand-counted maps, identities on every map, a
//! reference search written here, budgets and configs.

mod common;

use planner_api::{
    Budget, Cell, Connectivity, Grid, MoveSet, NeighborOrder, Outcome, PathRule, Planner, Problem,
    Status,
};
use planner_dfs::{Config, ConfigError, Dfs};

fn plan(grid: &Grid, start: Cell, goal: Cell, config: Config) -> Outcome {
    let problem = Problem::new(grid, start, goal).unwrap();
    Dfs::new(config)
        .unwrap()
        .plan(&problem, &Budget::unlimited())
}

fn steps(outcome: &Outcome) -> Option<u64> {
    outcome.path.as_ref().map(|p| p.metrics().steps)
}

fn seed_order() -> Config {
    Config {
        order: "L R U D".parse().unwrap(),
        ..Config::default()
    }
}

#[test]
fn seed_003_dfs_lengths_with_the_seeds_order() {
    // Table I (map1.txt pairs 1-3): DFS 38, 26, 20.
    let (grid, pairs) = common::wpi("wpi/map1.txt");
    let lengths: Vec<_> = pairs
        .iter()
        .map(|&(s, g)| steps(&plan(&grid, s, g, seed_order())))
        .collect();
    assert_eq!(lengths, [Some(38), Some(26), Some(20)]);
    // Table II (map3.txt): "Map 1" 196 is pair 1, "Map 2" 73 is pair 3.
    let (grid, pairs) = common::wpi("wpi/map3.txt");
    assert_eq!(
        steps(&plan(&grid, pairs[0].0, pairs[0].1, seed_order())),
        Some(196)
    );
    assert_eq!(
        steps(&plan(&grid, pairs[2].0, pairs[2].1, seed_order())),
        Some(73)
    );
}

#[test]
fn map2_pair_2_goal_on_an_obstacle_is_an_error_naming_the_cell() {
    let (grid, pairs) = common::wpi("wpi/map2.txt");
    let (start, goal) = pairs[1];
    let err = Problem::new(&grid, start, goal).unwrap_err();
    assert_eq!(err.to_string(), "goal (12, 3) is blocked");
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
    // A ring around a pillar, (0,0) to (2,2), order R L D U (b blocked, s skipped, + pushed):
    // (0,0): R (1,0)+, L b, D (0,1)+, U b          stack (1,0) (0,1)
    // (0,1): R (1,1)b, L b, D (0,2)+, U (0,0)s     stack (1,0) (0,2)
    // (0,2): R (1,2)+, L b, D b, U (0,1)s          stack (1,0) (1,2)
    // (1,2): R (2,2)+, L (0,2)s, D b, U (1,1)b     stack (1,0) (2,2)
    // (2,2): the goal. 5 popped, 4 x 4 checks, 8 blocked, 3 skipped, stack never over 2,
    // 6 cells pushed (the start included).
    check(
        "...\n.#.\n...",
        (0, 0),
        (2, 2),
        Status::Found,
        [5, 16, 8, 3, 2, 6],
    );
    // A wall: (0,0): R b, L b, D (0,1)+, U b; (0,1): R (1,1)b, L b, D b, U (0,0)s; empty.
    check(
        ".#.\n.#.",
        (0, 0),
        (2, 0),
        Status::NoPath,
        [2, 8, 6, 1, 1, 2],
    );
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
    for file in ["wpi/map1.txt", "wpi/map2.txt", "wpi/map3.txt"] {
        let (grid, pairs) = common::wpi(file);
        for &(s, g) in pairs
            .iter()
            .filter(|&&(s, g)| Problem::new(&grid, s, g).is_ok())
        {
            let outcome = plan(&grid, s, g, seed_order());
            common::check_frontier_identities(&format!("{file} {s}->{g}"), &outcome, 4);
        }
    }
    for map in common::movingai_maps() {
        let grid = common::movingai(&format!("movingai/{map}"));
        let (s, g) = common::first_scenario(&format!("movingai/{map}.scen"));
        let problem = Problem::new(&grid, s, g).unwrap();
        let mut dfs = Dfs::new(Config::default()).unwrap();
        // The first scenarios are short, but depth-first may wander over the whole map.
        let outcome = common::check_budget_cut(&mut dfs, &problem, &map, 4);
        let moves = MoveSet::standard(Connectivity::Four);
        outcome
            .path
            .as_ref()
            .unwrap()
            .validate(&grid, PathRule::Moves(&moves))
            .unwrap();
    }
}

#[test]
fn random_grids_find_a_valid_path_exactly_when_one_exists() {
    for (round, (grid, start, goal)) in common::small_random_problems(0x2545_f491_4f6c_dd1d, 200)
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
            let shortest = common::fewest_moves(&grid, &moves, start, goal);
            assert_eq!(steps(&outcome).is_some(), shortest.is_some(), "{what}");
            if let Some(path) = &outcome.path {
                path.validate(&grid, PathRule::Moves(&moves)).unwrap();
                assert_eq!((path.start(), path.goal()), (Some(start), Some(goal)));
                assert!(steps(&outcome) >= shortest, "{what}");
                // Parent links never revisit a cell.
                let mut cells = path.cells().to_vec();
                cells.sort();
                cells.dedup();
                assert_eq!(cells.len(), path.len(), "{what}");
            }
            common::check_frontier_identities(&what, &outcome, k);
        }
    }
}

#[test]
fn budget_ends_the_search_with_the_counters_so_far() {
    let grid = Grid::new(12, 12).unwrap();
    let problem = Problem::new(&grid, Cell::new(0, 0), Cell::new(11, 11)).unwrap();
    let mut dfs = Dfs::new(Config::default()).unwrap();
    let outcome = dfs.plan(&problem, &Budget::expansions(10));
    assert_eq!(outcome.status, Status::BudgetExhausted);
    assert_eq!(outcome.path, None);
    assert_eq!(outcome.counters.get("n_expanded"), Some(10));
    common::check_frontier_identities("open 12x12, 10 expansions", &outcome, 4);
    let a = dfs.plan(&problem, &Budget::unlimited());
    let b = dfs.plan(&problem, &Budget::unlimited());
    assert_eq!(a, b);
    assert_eq!(a.status, Status::Found);
}

#[test]
fn config_keys_and_errors() {
    let config: Config = toml::from_str("moves = 8\norder = \"L R U D\"").unwrap();
    assert_eq!(config.moves, Connectivity::Eight);
    assert!(Dfs::new(config.clone()).is_ok());
    let json = serde_json::to_string(&config).unwrap();
    assert_eq!(serde_json::from_str::<Config>(&json).unwrap(), config);
    assert_eq!(toml::from_str::<Config>("").unwrap(), Config::default());
    assert!(toml::from_str::<Config>("prune = \"bound\"").is_err());
    let err = Dfs::new(Config {
        order: "R L D U DR DL UR UL".parse().unwrap(),
        ..Config::default()
    })
    .unwrap_err();
    assert!(matches!(err, ConfigError::Order(_)));
    let err = Dfs::new(Config {
        corner_cutting: true,
        ..Config::default()
    })
    .unwrap_err();
    assert!(
        err.to_string().starts_with("parameter `corner_cutting`: "),
        "{err}"
    );
    assert_eq!(Dfs::new(Config::default()).unwrap().name(), "dfs");
}

/// Every counter and path equals planner-testkit's `reference_frontier` (a `VecDeque`
/// used as a LIFO stack, moves through `MoveSet::apply`), on random grids with three move
/// sets in two orders (the default and seed 003's `L R U D`) and on every pair of seed
/// 003's maps.
#[test]
fn counters_and_paths_equal_the_reference_frontier_search() {
    let problems = planner_testkit::small_and_wpi_problems(0x0ddf_5eed_1234_5678, 2000);
    let mut expanded = 0;
    for order in ["R L D U", "L R U D"] {
        let order: NeighborOrder = order.parse().unwrap();
        for (connectivity, cutting) in [
            (Connectivity::Four, false),
            (Connectivity::Eight, false),
            (Connectivity::Eight, true),
        ] {
            let config = Config {
                moves: connectivity,
                corner_cutting: cutting,
                order: order.clone(),
            };
            let moves = MoveSet::new(connectivity, cutting, &order).unwrap();
            for (k, (grid, start, goal)) in problems.iter().enumerate() {
                let outcome = plan(grid, *start, *goal, config.clone());
                let (status, path, counters) =
                    planner_testkit::reference_frontier(grid, &moves, *start, *goal, true);
                let what = format!("{order:?} {connectivity} cutting {cutting} problem {k}");
                assert_eq!(outcome.status, status, "{what}");
                assert_eq!(common::frontier_counters(&outcome), counters, "{what}");
                assert_eq!(outcome.path.map(|p| p.cells().to_vec()), path, "{what}");
                expanded += counters[0];
            }
        }
    }
    // 160,439 expansions (2026-12-06).
    assert!(expanded > 150_000, "{expanded}");
}
