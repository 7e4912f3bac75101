//! Bidirectional A\* against `planner_testkit::reference_bidirectional_astar`, the search
//! written again with std's binary heaps and planner-api's moves and move costs: the same
//! status, path and every counter, 4- and 8-connected, with and without cell weights.

use planner_api::{Budget, Cell, Connectivity, Grid, Planner, Problem};
use planner_bidirectional_astar::{BidirectionalAStar, Config};
use planner_testkit::{
    random_weighted_problems, reference_bidirectional_astar, small_random_problems,
};

/// Plans every problem with both move sets and compares with the reference; returns the
/// expansions and meeting updates.
fn check(label: &str, problems: &[(Grid, Cell, Cell)]) -> (u64, u64) {
    let (mut expanded, mut meetings) = (0, 0);
    for moves in [Connectivity::Four, Connectivity::Eight] {
        let mut planner = BidirectionalAStar::new(Config {
            moves,
            ..Config::default()
        })
        .unwrap();
        for (k, (grid, start, goal)) in problems.iter().enumerate() {
            let what = format!("{label} {moves:?} problem {k}: {start:?} -> {goal:?}");
            let problem = Problem::new(grid, *start, *goal).unwrap();
            let outcome = planner.plan(&problem, &Budget::unlimited());
            let (status, path, counters) =
                reference_bidirectional_astar(grid, moves, *start, *goal);
            assert_eq!(outcome.status, status, "{what}");
            let actual: Vec<(String, u64)> = outcome
                .counters
                .iter()
                .map(|(name, value)| (name.to_string(), value))
                .collect();
            assert_eq!(actual, counters, "{what}");
            assert_eq!(outcome.path.map(|p| p.cells().to_vec()), path, "{what}");
            expanded += counters[0].1;
            meetings += counters[counters.len() - 1].1;
        }
    }
    (expanded, meetings)
}

#[test]
fn every_counter_equals_the_reference_without_weights() {
    let (expanded, meetings) = check("unweighted", &small_random_problems(41, 3000));
    // 29,777 expansions and 5,043 meeting updates over both move sets (2026-12-06).
    assert!(
        expanded > 25_000 && meetings > 4_000,
        "{expanded} {meetings}"
    );
}

#[test]
fn every_counter_equals_the_reference_with_weights() {
    let problems: Vec<(Grid, Cell, Cell)> = random_weighted_problems(43, 1500)
        .into_iter()
        .map(|p| (p.grid, p.start, p.goal))
        .collect();
    let (expanded, meetings) = check("weighted", &problems);
    // 211,618 expansions and 3,685 meeting updates over both move sets (2026-12-06).
    assert!(
        expanded > 200_000 && meetings > 3_000,
        "{expanded} {meetings}"
    );
}
