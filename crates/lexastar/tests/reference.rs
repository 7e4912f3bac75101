//! lexastar against `planner_testkit::reference_lexastar`, its lexicographic search written
//! again with flat arrays and std's binary heap: the same status, path and every counter,
//! 4- and 8-connected, with and without dominance pruning.

use planner_api::{Budget, Cell, Connectivity, Grid, MoveSet, NeighborOrder, Planner, Problem};
use planner_lexastar::{Config, LexAStar};
use planner_testkit::{
    assert_reference_outcome, random_problems, reference_lexastar, small_random_problems,
    LEXASTAR_COUNTERS,
};

/// Plans every problem with both move sets, with and without dominance, and compares with
/// the reference; returns the expansions and the states dominated.
fn check(label: &str, problems: &[(Grid, Cell, Cell)]) -> (u64, u64) {
    let (mut expanded, mut dominated) = (0, 0);
    for moves in [Connectivity::Four, Connectivity::Eight] {
        for dominance in [true, false] {
            let config = Config {
                moves,
                dominance,
                ..Config::default()
            };
            let move_set = MoveSet::new(moves, false, &NeighborOrder::default()).unwrap();
            let mut planner = LexAStar::new(config).unwrap();
            for (k, (grid, start, goal)) in problems.iter().enumerate() {
                let what = format!(
                    "{label} {moves:?} dominance {dominance} problem {k}: {start:?} -> {goal:?}"
                );
                let problem = Problem::new(grid, *start, *goal).unwrap();
                let outcome = planner.plan(&problem, &Budget::unlimited());
                let (status, path, counters) =
                    reference_lexastar(grid, &move_set, *start, *goal, dominance);
                let reference = (status, path);
                assert_reference_outcome(&outcome, reference, LEXASTAR_COUNTERS, counters, &what);
                expanded += counters[0];
                dominated += counters[7];
            }
        }
    }
    (expanded, dominated)
}

#[test]
fn every_counter_equals_the_reference_on_small_random_grids() {
    let (expanded, dominated) = check("small", &small_random_problems(61, 2000));
    // 85,777 expansions and 49,323 states dominated (2026-12-06).
    assert!(
        expanded > 80_000 && dominated > 40_000,
        "{expanded} {dominated}"
    );
}

/// Grids of 20 to 60 cells a side with 5 to 30 % of their cells blocked.
#[test]
fn every_counter_equals_the_reference_on_larger_grids() {
    let problems = random_problems(0x00de_ad1e_5eed, 60, (20, 60), (500, 3000));
    let (expanded, dominated) = check("larger", &problems);
    // 68,034 expansions and 66,691 states dominated (2026-12-06).
    assert!(
        expanded > 50_000 && dominated > 50_000,
        "{expanded} {dominated}"
    );
}
