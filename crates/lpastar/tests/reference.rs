//! LPA* and D* Lite against planner-testkit's reference (the papers' searches written
//! again with a `BTreeSet` for the queue): first searches (`reference_lpa`) and sessions of
//! changes, moves and replans (`ReferenceIncremental`), the same status, path and every
//! counter, 4- and 8-connected, with and without weights.

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

/// Drives LPA* and D* Lite (4 and 8 moves) and `planner_testkit::ReferenceIncremental`
/// through the same sessions on every problem: a first plan, then `rounds` rounds of an
/// optional move of the start along the last path, a batch of 1 to 6 changed cells
/// (toggled, and on a weighted grid reweighted, sometimes below the session's smallest
/// weight) and a replan, every fourth one under a small expansion budget. Every replan's
/// status, path and counters must be equal. Returns the expansions of the replans after
/// the first, per planner and move set.
fn check_replans(
    label: &str,
    problems: &[(Grid, Cell, Cell)],
    rounds: usize,
    seed: u64,
) -> [u64; 4] {
    use planner_api::{CellChange, IncrementalPlanner};
    use planner_testkit::ReferenceIncremental;
    let mut next = planner_testkit::xorshift(seed | 1);
    let mut repaired = [0; 4];
    for (k, (moves, dstar)) in [(4, false), (8, false), (4, true), (8, true)]
        .into_iter()
        .enumerate()
    {
        let config = Config { moves };
        let mut planner: Box<dyn IncrementalPlanner> = match dstar {
            true => Box::new(DStarLite::new(planner_dstar_lite::Config { moves }).unwrap()),
            false => Box::new(LpaStar::new(config).unwrap()),
        };
        let mut reference = ReferenceIncremental::new(dstar, moves == 8);
        for (i, (grid, start, goal)) in problems.iter().enumerate() {
            let problem = Problem::new(grid, *start, *goal).unwrap();
            planner.reset(&problem);
            reference.reset(&problem);
            let mut path: Option<Vec<Cell>> = None;
            for round in 0..=rounds {
                let what = format!(
                    "{label} moves {moves} D* Lite {dstar} problem {i} round {round}: {start:?} -> {goal:?}"
                );
                if round > 0 {
                    if let Some(cells) = path.as_ref().filter(|_| next() % 2 == 0) {
                        let to = cells[(next() as usize % 3).min(cells.len() - 1)];
                        assert_eq!(planner.move_start(to), reference.move_start(to), "{what}");
                    }
                    let map = reference.grid().unwrap().clone();
                    let changes: Vec<CellChange> = (0..1 + next() % 6)
                        .map(|_| {
                            let cell = map.cell((next() % map.len() as u64) as usize);
                            let weight = map.is_weighted().then(|| match next() % 4 {
                                0 => 1 + (next() % 3) as u16,
                                _ => map.weight(cell),
                            });
                            let free = match next() % 3 {
                                0 => !map.is_free(cell),
                                _ => map.is_free(cell),
                            };
                            CellChange { cell, free, weight }
                        })
                        .collect();
                    assert_eq!(planner.apply(&changes), reference.apply(&changes), "{what}");
                }
                let budget = match round % 4 == 3 {
                    true => Budget::expansions(next() % 40),
                    false => Budget::unlimited(),
                };
                let (ours, theirs) = (planner.replan(&budget), reference.replan(&budget));
                assert_eq!(ours.status, theirs.status, "{what}");
                let counters = |o: &planner_api::Outcome| {
                    o.counters
                        .iter()
                        .map(|(name, value)| (name.to_string(), value))
                        .collect::<Vec<_>>()
                };
                assert_eq!(counters(&ours), counters(&theirs), "{what}");
                path = ours.path.map(|p| p.cells().to_vec());
                assert_eq!(path, theirs.path.map(|p| p.cells().to_vec()), "{what}");
                if round > 0 {
                    repaired[k] += ours.counters.get("n_expanded").unwrap_or(0);
                }
            }
        }
    }
    repaired
}

#[test]
fn replans_equal_the_reference_through_changes_and_moves() {
    let problems = random_problems(0x5eed_2e91, 120, (8, 40), (0, 3000));
    let repaired = check_replans("unweighted", &problems, 12, 7);
    // Repair expansions (LPA* 4 and 8 moves, D* Lite 4 and 8): 18,973, 15,651, 3,346 and
    // 3,173 (2026-12-06).
    assert!(repaired.iter().all(|&n| n > 2_500), "{repaired:?}");
}

#[test]
fn replans_equal_the_reference_on_weighted_grids() {
    let problems: Vec<(Grid, Cell, Cell)> = planner_testkit::random_weighted_problems(0xc057, 160)
        .into_iter()
        .map(|p| (p.grid, p.start, p.goal))
        .collect();
    let repaired = check_replans("weighted", &problems, 12, 11);
    // 33,831, 36,670, 18,596 and 18,112 (2026-12-06).
    assert!(repaired.iter().all(|&n| n > 15_000), "{repaired:?}");
}
