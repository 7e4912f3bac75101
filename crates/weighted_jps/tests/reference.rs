//! weighted_jps against `planner_testkit::reference_weighted_jps`, the crate docs' search
//! written again with jumps walked cell by cell and std's binary heap: the same status,
//! jump points, path and every counter on random weighted grids and on grids without
//! weights.

use planner_api::{Budget, Cell, Grid, Planner, Problem};
use planner_testkit::{
    cells_through, random_weighted_problems, reference_weighted_jps, small_random_problems,
    WEIGHTED_JPS_COUNTERS,
};
use planner_weighted_jps::{Config, WeightedJps};

/// Plans `problems` and compares each outcome with the reference's; returns the total
/// expansions and reopened expansions.
fn check(label: &str, problems: &[(Grid, Cell, Cell)]) -> (u64, u64) {
    let mut planner = WeightedJps::new(Config::default()).unwrap();
    let (mut expanded, mut reopened) = (0, 0);
    for (k, (grid, start, goal)) in problems.iter().enumerate() {
        let what = format!("{label} problem {k}: {start:?} -> {goal:?}");
        let outcome = planner.plan(
            &Problem::new(grid, *start, *goal).unwrap(),
            &Budget::unlimited(),
        );
        let (status, chain, counters) = reference_weighted_jps(grid, *start, *goal);
        assert_eq!(outcome.status, status, "{what}");
        for (name, want) in WEIGHTED_JPS_COUNTERS.iter().zip(counters) {
            assert_eq!(outcome.counters.get(name), Some(want), "{what}: {name}");
        }
        expanded += counters[0];
        reopened += counters[5];
        match (&outcome.path, chain) {
            (Some(path), Some(chain)) => {
                assert_eq!(path.cells(), cells_through(&chain), "{what}");
                let marks: Vec<Cell> = outcome.marks.iter().map(|m| m.cell).collect();
                let inner = &chain[1..chain.len().saturating_sub(1).max(1)];
                assert_eq!(marks, inner, "{what}");
            }
            (None, None) => {}
            (path, chain) => panic!("{what}: path {:?}, reference {chain:?}", path.is_some()),
        }
    }
    (expanded, reopened)
}

#[test]
fn every_counter_equals_the_reference_on_random_weighted_grids() {
    let problems: Vec<(Grid, Cell, Cell)> = random_weighted_problems(11, 3000)
        .into_iter()
        .map(|p| (p.grid, p.start, p.goal))
        .collect();
    let (expanded, _) = check("weighted", &problems);
    // Enough search to mean something: 173,872 expansions (2026-12-06).
    assert!(expanded > 100_000, "{expanded}");
}

#[test]
fn every_counter_equals_the_reference_without_weights() {
    let problems = small_random_problems(12, 4000);
    let (expanded, reopened) = check("unweighted", &problems);
    // 15,106 expansions (2026-12-06).
    assert!(expanded > 10_000, "{expanded}");
    assert_eq!(reopened, 0);
}
