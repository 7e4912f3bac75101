//! Every variant against the scenario optima of every `.scen` file in `maps/movingai/`,
//! and, with and without goal bounding, against planner-astar (octile, no corner cutting)
//! on seeded random grids.

use planner_api::{Budget, Cell, Connectivity, Grid, Planner, Problem, Status};
use planner_astar::{AStar, Heuristic};
use planner_jps::{Config, Jps, Variant};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

const VARIANTS: [Variant; 3] = [Variant::Jps, Variant::JpsPrime, Variant::JpsPlus];

fn jps(variant: Variant) -> Jps {
    Jps::new(Config {
        variant,
        ..Config::default()
    })
    .unwrap()
}

fn close(a: f64, b: f64) -> bool {
    (a - b).abs() <= 1e-4 * b.abs().max(1.0)
}

/// The path is valid (8-connected, no corner cutting, free cells, start to goal) and its
/// length; `None` when there is no path.
fn checked_length(
    grid: &Grid,
    start: Cell,
    goal: Cell,
    outcome: &planner_api::Outcome,
) -> Option<f64> {
    let path = outcome.path.as_ref()?;
    let cells = path.cells();
    assert_eq!(cells.first(), Some(&start));
    assert_eq!(cells.last(), Some(&goal));
    for pair in cells.windows(2) {
        let (a, b) = (pair[0], pair[1]);
        assert!(grid.is_free(b), "{b} blocked");
        let (dx, dy) = (b.x as i64 - a.x as i64, b.y as i64 - a.y as i64);
        assert!(
            dx.abs() <= 1 && dy.abs() <= 1 && (dx, dy) != (0, 0),
            "{a} -> {b}"
        );
        if dx != 0 && dy != 0 {
            assert!(
                grid.is_free(Cell::new(b.x, a.y)) && grid.is_free(Cell::new(a.x, b.y)),
                "{a} -> {b} cuts a corner"
            );
        }
    }
    Some(path.metrics().length)
}

/// Every `every`-th scenario of every `.scen` file with `variant`.
fn check_scenarios(variant: Variant, every: usize) {
    let mut planner = jps(variant);
    for map in planner_testkit::movingai_maps() {
        let grid = planner_testkit::movingai(&format!("movingai/{map}"));
        let scenarios = planner_testkit::scenarios(&format!("movingai/{map}.scen"));
        for s in scenarios.iter().step_by(every) {
            let problem = Problem::new(&grid, s.start, s.goal).unwrap();
            let outcome = planner.plan(&problem, &Budget::unlimited());
            assert_eq!(outcome.status, Status::Found, "{map} line {}", s.line);
            let length = checked_length(&grid, s.start, s.goal, &outcome).unwrap();
            assert!(
                close(length, s.optimal_length),
                "{map} line {} {variant:?}: {length} vs optimum {}",
                s.line,
                s.optimal_length
            );
        }
    }
}

/// The online variants scan cell rows; unoptimised (debug) builds run every 8th
/// scenario of them to stay fast, release builds (`cargo test --release`) all.
const ONLINE_EVERY: usize = if cfg!(debug_assertions) { 8 } else { 1 };

/// The random grids' rounds that also run goal bounding: every 4th with debug assertions
/// (unoptimised builds and CI's), else all.
const GOAL_BOUNDING_EVERY: usize = if cfg!(debug_assertions) { 4 } else { 1 };

#[test]
fn every_scenario_length_is_the_optimum_jps_plus() {
    check_scenarios(Variant::JpsPlus, 1);
}

#[test]
fn scenario_lengths_are_the_optima_jps() {
    check_scenarios(Variant::Jps, ONLINE_EVERY);
}

#[test]
fn scenario_lengths_are_the_optima_jps_prime() {
    check_scenarios(Variant::JpsPrime, ONLINE_EVERY);
}

#[test]
fn random_grids_agree_with_astar() {
    let mut rng = ChaCha8Rng::seed_from_u64(15);
    let mut astar = AStar::new(planner_astar::Config {
        moves: Connectivity::Eight,
        heuristic: Heuristic::Octile,
        ..planner_astar::Config::default()
    })
    .unwrap();
    // Each variant without goal bounding, then with it.
    let mut planners: Vec<Jps> = [false, true]
        .into_iter()
        .flat_map(|goal_bounding| {
            VARIANTS.iter().map(move |&variant| {
                Jps::new(Config {
                    variant,
                    goal_bounding,
                    ..Config::default()
                })
                .unwrap()
            })
        })
        .collect();
    let mut expanded = [0u64; 6];
    for round in 0..600 {
        let (w, h) = (rng.gen_range(1..=40), rng.gen_range(1..=40));
        let density = rng.gen_range(0..45);
        let free: Vec<bool> = (0..w * h)
            .map(|_| rng.gen_range(0..100) >= density)
            .collect();
        let grid = Grid::from_free_cells(w, h, free).unwrap();
        let free_cells: Vec<Cell> = grid.cells().filter(|&c| grid.is_free(c)).collect();
        if free_cells.is_empty() {
            continue;
        }
        for _ in 0..8 {
            let start = free_cells[rng.gen_range(0..free_cells.len())];
            let goal = free_cells[rng.gen_range(0..free_cells.len())];
            let problem = Problem::new(&grid, start, goal).unwrap();
            let expected = astar.plan(&problem, &Budget::unlimited());
            let expected_length = checked_length(&grid, start, goal, &expected);
            // Goal bounding's build (a Dijkstra search per jump point) is slow unoptimised:
            // those planners, and the expansions compared, on every GOAL_BOUNDING_EVERY-th
            // round only.
            #[allow(
                clippy::modulo_one,
                reason = "GOAL_BOUNDING_EVERY is 1 without assertions"
            )]
            let bounded_round = round % GOAL_BOUNDING_EVERY == 0;
            for (k, planner) in planners.iter_mut().enumerate() {
                if k >= 3 && !bounded_round {
                    continue;
                }
                let outcome = planner.plan(&problem, &Budget::unlimited());
                if bounded_round {
                    expanded[k] += outcome.counters.get("n_expanded").unwrap_or(0);
                }
                let what = format!(
                    "round {round} {:?} goal bounding {} {start} -> {goal}\n{}",
                    planner.config().variant,
                    planner.config().goal_bounding,
                    grid.to_ascii()
                );
                assert_eq!(outcome.status, expected.status, "{what}");
                let length = checked_length(&grid, start, goal, &outcome);
                match (length, expected_length) {
                    (Some(a), Some(b)) => assert!((a - b).abs() < 1e-9, "{what}: {a} vs {b}"),
                    (None, None) => {}
                    _ => panic!("{what}"),
                }
            }
        }
    }
    // The boxes prune: each variant expands fewer nodes with them.
    for k in 0..3 {
        assert!(
            expanded[k + 3] * 10 < expanded[k] * 9,
            "{:?}: {} with goal bounding, {} without",
            VARIANTS[k],
            expanded[k + 3],
            expanded[k]
        );
    }
}
