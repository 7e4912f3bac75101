//! LPA* and D* Lite's first searches against `planner_testkit::reference_lpa`, the papers'
//! ComputeShortestPath written again with a `BTreeSet` for the queue: the same status,
//! path and every counter, 4- and 8-connected.

use planner_api::{Budget, Cell, Grid, Planner, Problem};
use planner_dstar_lite::DStarLite;
use planner_lpastar::{Config, LpaStar};
use planner_testkit::{random_problems, reference_lpa, small_random_problems, LPA_COUNTERS};

/// Plans every problem with both planners and both move sets and compares with the
/// reference; returns the expansions of each of the four.
fn check(label: &str, problems: &[(Grid, Cell, Cell)]) -> [u64; 4] {
    let mut expanded = [0; 4];
    for (k, (moves, dstar)) in [(4, false), (8, false), (4, true), (8, true)]
        .into_iter()
        .enumerate()
    {
        let config = Config { moves };
        let mut planner: Box<dyn Planner> = match dstar {
            true => Box::new(DStarLite::new(planner_dstar_lite::Config { moves }).unwrap()),
            false => Box::new(LpaStar::new(config).unwrap()),
        };
        for (i, (grid, start, goal)) in problems.iter().enumerate() {
            let what =
                format!("{label} moves {moves} D* Lite {dstar} problem {i}: {start:?} -> {goal:?}");
            let outcome = planner.plan(
                &Problem::new(grid, *start, *goal).unwrap(),
                &Budget::unlimited(),
            );
            let (status, path, counters) = reference_lpa(grid, moves == 8, *start, *goal, dstar);
            assert_eq!(outcome.status, status, "{what}");
            let actual: Vec<(&str, u64)> = outcome.counters.iter().collect();
            let expected: Vec<(&str, u64)> = LPA_COUNTERS
                .iter()
                .copied()
                .zip(counters.iter().copied())
                .collect();
            assert_eq!(actual, expected, "{what}");
            assert_eq!(outcome.path.map(|p| p.cells().to_vec()), path, "{what}");
            expanded[k] += counters[0];
        }
    }
    expanded
}

#[test]
fn first_searches_equal_the_reference_on_small_random_grids() {
    let expanded = check("small", &small_random_problems(51, 3000));
    // 24,058, 21,541, 24,054 and 21,459 expansions (2026-12-06).
    assert!(expanded.iter().all(|&n| n > 15_000), "{expanded:?}");
}

/// Grids of 30 to 80 cells a side with 5 to 35 % of their cells blocked.
#[test]
fn first_searches_equal_the_reference_on_larger_grids() {
    let problems = random_problems(0x019a_5eed, 80, (30, 80), (500, 3500));
    let expanded = check("larger", &problems);
    // 26,863, 18,731, 28,116 and 20,100 expansions (2026-12-06).
    assert!(expanded.iter().all(|&n| n > 15_000), "{expanded:?}");
}
