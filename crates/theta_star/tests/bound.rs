//! Theta\*'s length bound (never longer than the 8-connected optimum) on every Moving AI
//! scenario file and on seeded random maps against planner-astar, path validity, budgets,
//! unreachable goals, reproducibility and parameter errors, for both variants of the search.
//!
//! In a debug build the scenario test runs every [`DEBUG_EVERY`]th scenario of each file
//! (the first included) to stay within CI time; a release build (`cargo test --release`)
//! or `GRIDPLAN_ALL_SCENARIOS=1` runs all of them.

use planner_api::{
    Budget, Cell, Connectivity, Grid, Outcome, Path, PathRule, PathSpec, Planner, Problem, Status,
};
use planner_astar::{AStar, Heuristic, TieBreak};
use planner_theta_star::{AnyAngle, Config, ConfigError, ThetaStar, Variant};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// The stride through each `.scen` file in debug builds.
const DEBUG_EVERY: usize = 40;

/// Relative slack of length comparisons with stated optima (8 decimals in the files) and
/// with A*'s costs (see the crate docs on the epsilon).
const SLACK: f64 = 1e-4;

fn scenario_stride() -> usize {
    if cfg!(debug_assertions) && std::env::var_os("GRIDPLAN_ALL_SCENARIOS").is_none() {
        DEBUG_EVERY
    } else {
        1
    }
}

/// Checks a found any-angle path: from start to goal, valid by `PathRule::AnyAngle`, its
/// length equal to the search's g(goal), and returns the length.
fn check_found(what: &str, grid: &Grid, start: Cell, goal: Cell, outcome: &Outcome) -> f64 {
    assert_eq!(
        outcome.status,
        Status::Found,
        "{what}: {}",
        outcome.counters
    );
    let path = outcome.path.as_ref().expect("a found outcome has a path");
    assert_eq!(
        (path.start(), path.goal()),
        (Some(start), Some(goal)),
        "{what}"
    );
    if let Err(e) = path.validate(grid, PathRule::AnyAngle) {
        panic!("{what}: invalid any-angle path: {e}: {:?}", path.cells());
    }
    path.metrics().length
}

#[test]
fn never_longer_than_the_movingai_optimum() {
    let stride = scenario_stride();
    let mut theta = ThetaStar::new(Config::default()).unwrap();
    let mut n_checked = 0;
    for map in planner_testkit::movingai_maps() {
        let grid = planner_testkit::movingai(&format!("movingai/{map}"));
        let scenarios = planner_testkit::scenarios(&format!("movingai/{map}.scen"));
        for scenario in scenarios.iter().step_by(stride) {
            let what = format!("{map} line {}", scenario.line);
            let problem = Problem::new(&grid, scenario.start, scenario.goal).unwrap();
            let search = theta.search(&problem, &Budget::unlimited());
            let outcome = Outcome::new(search.status, search.path, Default::default());
            let length = check_found(&what, &grid, scenario.start, scenario.goal, &outcome);
            let cost = search.cost.unwrap();
            assert!((cost - length).abs() <= 1e-9 * length.max(1.0), "{what}");
            let optimum = scenario.optimal_length;
            assert!(
                length <= optimum * (1.0 + SLACK),
                "{what}: Theta* {length} > optimum {optimum}"
            );
            // Never shorter than the straight line.
            let line = scenario.start.euclidean(scenario.goal);
            assert!(length >= line * (1.0 - 1e-12), "{what}");
            n_checked += 1;
        }
    }
    assert!(n_checked >= 5665 / DEBUG_EVERY, "{n_checked} scenarios");
}

fn random_grid(rng: &mut ChaCha8Rng, width: u32, height: u32, density: f64) -> Grid {
    let free = (0..width * height)
        .map(|_| !rng.gen_bool(density))
        .collect();
    Grid::from_free_cells(width, height, free).unwrap()
}

fn octile_astar() -> AStar {
    AStar::new(planner_astar::Config {
        moves: Connectivity::Eight,
        heuristic: Heuristic::Octile,
        tie_break: TieBreak::HighG,
        ..Default::default()
    })
    .unwrap()
}

/// Theta* against 8-connected A* (octile, no corner cutting) on `rounds` seeded random
/// maps: the same status, and Theta*'s length at most A*'s; Lazy Theta*'s paths valid.
fn check_random_maps(seed: u64, rounds: usize, side: u32, density: f64) -> (usize, usize) {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut astar = octile_astar();
    let mut search = AnyAngle::new(&Config::default()).unwrap();
    let (mut n_found, mut n_shorter) = (0, 0);
    for round in 0..rounds {
        let mut grid = random_grid(&mut rng, side, side, density);
        let start = Cell::new(rng.gen_range(0..side), rng.gen_range(0..side));
        let goal = Cell::new(rng.gen_range(0..side), rng.gen_range(0..side));
        grid.set_free(start, true);
        grid.set_free(goal, true);
        let problem = Problem::new(&grid, start, goal).unwrap();
        let what = format!("seed {seed} round {round}");
        let reference = astar.search(&problem, &Budget::unlimited());
        for variant in [Variant::Theta, Variant::Lazy] {
            let found = search.search(&problem, &Budget::unlimited(), variant);
            let outcome = Outcome::new(found.status, found.path, Default::default());
            let what = format!("{what} {variant:?}");
            match reference.cost {
                None => {
                    assert_eq!(outcome.status, Status::NoPath, "{what}");
                    assert!(outcome.path.is_none(), "{what}");
                }
                Some(optimum) => {
                    let length = check_found(&what, &grid, start, goal, &outcome);
                    if variant == Variant::Theta {
                        assert!(
                            length <= optimum * (1.0 + SLACK),
                            "{what}: Theta* {length} > A* {optimum}\n{}",
                            grid.to_ascii()
                        );
                        n_found += 1;
                        n_shorter += usize::from(length < optimum * (1.0 - 1e-9));
                    }
                }
            }
        }
    }
    (n_found, n_shorter)
}

#[test]
fn never_longer_than_astar_on_random_maps() {
    for (seed, side, density) in [(1, 12, 0.3), (2, 24, 0.2), (3, 40, 0.35), (4, 8, 0.45)] {
        let (n_found, n_shorter) = check_random_maps(seed, 150, side, density);
        // The comparison means something: many problems are solvable and on a third or more
        // of them the any-angle path is strictly shorter.
        assert!(n_found >= 30, "seed {seed}: {n_found} found");
        assert!(
            n_shorter * 3 >= n_found,
            "seed {seed}: {n_shorter} of {n_found} shorter"
        );
    }
}

#[test]
fn straight_line_on_an_open_grid() {
    let grid = Grid::new(30, 20).unwrap();
    let mut rng = ChaCha8Rng::seed_from_u64(7);
    let mut search = AnyAngle::new(&Config::default()).unwrap();
    for _ in 0..50 {
        let start = Cell::new(rng.gen_range(0..30), rng.gen_range(0..20));
        let goal = Cell::new(rng.gen_range(0..30), rng.gen_range(0..20));
        let problem = Problem::new(&grid, start, goal).unwrap();
        for variant in [Variant::Theta, Variant::Lazy] {
            let found = search.search(&problem, &Budget::unlimited(), variant);
            let expect = if start == goal {
                vec![start]
            } else {
                vec![start, goal]
            };
            assert_eq!(found.path, Some(Path::new(expect)), "{variant:?}");
            assert_eq!(found.cost, Some(start.euclidean(goal)), "{variant:?}");
        }
    }
}

#[test]
fn counters_by_hand() {
    // S = (0,1), G = (2,1), the centre blocked; moves R L D U DR DL UR UL; h = |c G|.
    // Every cell has 2 safe moves here (all diagonals touch the centre), so each of the 6
    // non-goal expansions counts 8 checks, 6 blocked.
    // 1. S (f 2): D (0,2) and U (0,0) inserted, g 1, f 1 + sqrt 5. Parent(S) = S: no
    //    line of sight checked.
    // 2. (0,2) (equal key, pushed first): U S closed (skip 1). R (1,2): S sees it? The
    //    segment passes the vertex (1,2) and meets the side cell (1,1): blocked after 2
    //    cells (check 1, cells 2). Path 1: g 2, f 2 + sqrt 2, parent (0,2).
    // 3. (0,0): D S closed (skip 2). R (1,0): blocked from S the same way (check 2, cells
    //    4). Path 1: g 2, f 2 + sqrt 2.
    // 4. (1,2) (pushed before (1,0)): L closed (skip 3). R (2,2): (0,2) sees it through
    //    (1,2) (check 3, cells 7). Path 2: g 3, f 4, parent (0,2).
    // 5. (1,0): L closed (skip 4). R (2,0): (0,0) sees it (check 4, cells 10): g 3, f 4.
    // 6. (2,2) (f 4, g 3, pushed before (2,0)): L closed (skip 5). U G: (0,2) to (2,1)
    //    crosses x = 1 at y 2.25, then y = 2 at x = 1.5, entering the centre: blocked
    //    after (0,2), (1,2), (1,1) (check 5, cells 13). Path 1: g 4, f 4, parent (2,2).
    // 7. G (f 4 as (2,0), larger g first): found, length 4 (the 8-connected optimum;
    //    no shortcut exists around a single block). Insertions 8, relaxations 7, OPEN
    //    never holds more than 2.
    check(
        "
        ...
        .#.
        ...
        ",
        (0, 1),
        (2, 1),
        "
status found
path (0,1) (0,2) (2,2) (2,1)
n_expanded=7 n_neighbor_checks=48 n_blocked=36 n_skipped=5 n_open_insertions=8 n_relaxations=7 peak_open=2 n_los_checks=5 n_los_cells=13
        ",
    );
}

/// Runs Theta* from `start` to `goal` on `map` and compares the outcome, written as
/// planner-testkit's `outcome_text`, with `expect`.
fn check(map: &str, start: (u32, u32), goal: (u32, u32), expect: &str) {
    let grid = Grid::from_ascii(map).unwrap();
    let problem = Problem::new(&grid, start.into(), goal.into()).unwrap();
    let outcome = ThetaStar::new(Config::default())
        .unwrap()
        .plan(&problem, &Budget::unlimited());
    let actual = planner_testkit::outcome_text(&outcome);
    assert_eq!(actual.trim(), expect.trim(), "\n{actual}");
}

#[test]
fn unreachable_goal_is_no_path() {
    let grid = Grid::from_ascii(
        "
        ..#..
        ..#..
        .##..
        ",
    )
    .unwrap();
    let problem = Problem::new(&grid, Cell::new(0, 0), Cell::new(4, 2)).unwrap();
    let mut search = AnyAngle::new(&Config::default()).unwrap();
    for variant in [Variant::Theta, Variant::Lazy] {
        let found = search.search(&problem, &Budget::unlimited(), variant);
        assert_eq!(found.status, Status::NoPath, "{variant:?}");
        assert_eq!(found.path, None);
        let s = found.stats.search;
        // The start's component, (0,0), (1,0), (0,1), (1,1), (0,2), expanded entirely.
        assert_eq!((s.n_expanded, s.n_open_insertions), (5, 5), "{variant:?}");
        assert_eq!(s.n_neighbor_checks, 8 * 5);
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
    let mut search = AnyAngle::new(&Config::default()).unwrap();
    for variant in [Variant::Theta, Variant::Lazy] {
        let full = search.search(&problem, &Budget::unlimited(), variant);
        assert_eq!(full.status, Status::Found);
        let n = full.stats.search.n_expanded;
        for cut in [0, 1, n / 2, n - 1] {
            let part = search.search(&problem, &Budget::expansions(cut), variant);
            assert_eq!(part.status, Status::BudgetExhausted, "{variant:?} {cut}");
            assert_eq!(part.stats.search.n_expanded, cut, "{variant:?}");
            assert_eq!(part.stats.search.n_neighbor_checks, 8 * cut);
        }
        let exact = search.search(&problem, &Budget::expansions(n), variant);
        assert_eq!(
            exact, full,
            "{variant:?}: a budget of exactly n expansions suffices"
        );
    }
}

#[test]
fn reproducible_and_independent_of_earlier_queries() {
    let grid = planner_testkit::movingai("movingai/den520d.map");
    let scenarios = planner_testkit::scenarios("movingai/den520d.map.scen");
    let mut reused = AnyAngle::new(&Config::default()).unwrap();
    for scenario in scenarios.iter().step_by(97) {
        let problem = Problem::new(&grid, scenario.start, scenario.goal).unwrap();
        for variant in [Variant::Theta, Variant::Lazy] {
            let mut fresh = AnyAngle::new(&Config::default()).unwrap();
            let a = fresh.search(&problem, &Budget::unlimited(), variant);
            let b = reused.search(&problem, &Budget::unlimited(), variant);
            let c = reused.search(&problem, &Budget::unlimited(), variant);
            assert_eq!(a, b, "line {}", scenario.line);
            assert_eq!(b, c, "line {}", scenario.line);
        }
    }
}

#[test]
fn bad_parameters_are_errors_naming_the_key() {
    let check = |config: Config, key: &str| {
        let err = ThetaStar::new(config).unwrap_err();
        assert!(
            err.to_string().contains(&format!("parameter `{key}`")),
            "{err}"
        );
    };
    check(
        Config {
            moves: Connectivity::Four,
            ..Config::default()
        },
        "moves",
    );
    check(
        Config {
            moves: Connectivity::Sixteen,
            ..Config::default()
        },
        "moves",
    );
    check(
        Config {
            corner_cutting: true,
            ..Config::default()
        },
        "corner_cutting",
    );
    assert_eq!(
        AnyAngle::new(&Config {
            corner_cutting: true,
            ..Config::default()
        })
        .unwrap_err(),
        ConfigError::CornerCutting
    );
    let unknown: Result<Config, _> = toml::from_str("heuristic = \"octile\"");
    assert!(unknown.unwrap_err().to_string().contains("heuristic"));
    let eight: Config = toml::from_str("moves = 8\ncorner_cutting = false").unwrap();
    assert_eq!(eight, Config::default());
    let theta = ThetaStar::new(eight).unwrap();
    let specs = theta.specs();
    assert!(!specs.seeded);
    assert_eq!(specs.path_rule, PathSpec::AnyAngle);
}
