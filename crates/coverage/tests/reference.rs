//! Coverage against `planner_testkit::reference_coverage`, seed 004's run written again
//! (filling rules on cell coordinates, the documented branch and bound with the test kit's
//! reference A*): the same path and every counter, both patterns, with and without cell
//! weights.

use planner_api::{Budget, Cell, CoveragePlanner, CoverageProblem, Grid};
use planner_coverage::generate::random_cells;
use planner_coverage::{Config, Coverage, Heading, Pattern, Rotation, Side};
use planner_testkit::{
    random_problems, random_weighted_problems, reference_coverage, small_random_problems, Fill,
    COVERAGE_COUNTERS,
};

/// The heading's index in right, down, left, up.
fn index(h: Heading) -> usize {
    match h {
        Heading::Right => 0,
        Heading::Down => 1,
        Heading::Left => 2,
        Heading::Up => 3,
    }
}

/// `config`'s pattern as the reference takes it (the crate docs' defaults).
fn fill(config: &Config) -> Fill {
    match config.pattern {
        Pattern::Spiral => Fill::Spiral {
            left: config.reference_side.unwrap_or_default() == Side::Left,
            heading: index(config.heading.unwrap_or(Heading::Right)),
        },
        Pattern::Zigzag => {
            let rotation = config.rotation.unwrap_or_default();
            let (turn, first) = match rotation {
                Rotation::CounterClockwise => (3, Heading::Right),
                Rotation::Clockwise => (1, Heading::Down),
            };
            let first = index(config.first.unwrap_or(first));
            Fill::Zigzag {
                order: [0, 1, 2, 3].map(|k| (first + k * turn) % 4),
            }
        }
    }
}

fn configs() -> Vec<Config> {
    let base = Config {
        pattern: Pattern::Spiral,
        reference_side: None,
        heading: None,
        rotation: None,
        first: None,
    };
    vec![
        base.clone(),
        Config {
            reference_side: Some(Side::Right),
            heading: Some(Heading::Up),
            ..base.clone()
        },
        Config {
            pattern: Pattern::Zigzag,
            ..base.clone()
        },
        Config {
            pattern: Pattern::Zigzag,
            rotation: Some(Rotation::Clockwise),
            first: Some(Heading::Left),
            ..base
        },
    ]
}

/// Covers from every problem's start with every config and compares with the reference;
/// returns the returns (backtracking points) and return searches.
fn check(label: &str, problems: &[(Grid, Cell)]) -> (u64, u64) {
    let (mut returns, mut searches) = (0, 0);
    for config in configs() {
        let mut planner = Coverage::new(config.clone()).unwrap();
        for (k, (grid, start)) in problems.iter().enumerate() {
            let what = format!("{label} {config:?} problem {k}: from {start:?}");
            let problem = CoverageProblem::new(grid, *start).unwrap();
            let outcome = planner.cover(&problem, &Budget::unlimited());
            let (path, counters) = reference_coverage(grid, *start, fill(&config));
            assert_eq!(outcome.path.cells(), path, "{what}");
            let actual = COVERAGE_COUNTERS.map(|name| outcome.counters.get(name).unwrap());
            assert_eq!(actual, counters, "{what}");
            returns += counters[5];
            searches += counters[9];
        }
    }
    (returns, searches)
}

#[test]
fn every_counter_equals_the_reference_on_random_grids() {
    let problems: Vec<(Grid, Cell)> = small_random_problems(71, 1000)
        .into_iter()
        .map(|(grid, start, _)| (grid, start))
        .collect();
    let (returns, searches) = check("unweighted", &problems);
    // 12,903 returns and 16,767 return searches (2026-12-06).
    assert!(
        returns > 10_000 && searches > 12_000,
        "{returns} {searches}"
    );
}

#[test]
fn every_counter_equals_the_reference_on_random_weighted_grids() {
    let problems: Vec<(Grid, Cell)> = random_weighted_problems(73, 100)
        .into_iter()
        .map(|p| (p.grid, p.start))
        .collect();
    let (returns, searches) = check("weighted", &problems);
    // 5,473 returns and 85,133 return searches (2026-12-06).
    assert!(returns > 4_000 && searches > 60_000, "{returns} {searches}");
}

/// Grids of up to 64 cells a side and long strips, with and without weights: the points'
/// index (`src/points.rs`, blocks of 8 x 8 cells and up to five levels above here) gives
/// the points in the order of the reference's sorted list, where the grids above fit a
/// block or four. Debug builds take every third grid unless `GRIDPLAN_ALL_SCENARIOS` is
/// set (a minute for all of them).
#[test]
fn every_counter_equals_the_reference_on_larger_grids() {
    let mut problems: Vec<(Grid, Cell)> = random_problems(79, 24, (1, 64), (0, 3500))
        .into_iter()
        .map(|(grid, start, _)| (grid, start))
        .collect();
    for (k, (w, h)) in [(1, 300), (300, 1), (2, 150), (150, 3), (17, 70), (69, 9)]
        .into_iter()
        .enumerate()
    {
        let grid = random_cells(w, h, 0.15, Cell::new(0, 0), k as u64).unwrap();
        problems.push((grid, Cell::new(0, 0)));
    }
    let all = !cfg!(debug_assertions) || std::env::var_os("GRIDPLAN_ALL_SCENARIOS").is_some();
    let problems: Vec<(Grid, Cell)> = problems
        .into_iter()
        .step_by(if all { 1 } else { 3 })
        .collect();
    // The same grids weighted: each cell 1 to 9, the rules alternating.
    let weighted: Vec<(Grid, Cell)> = problems
        .iter()
        .enumerate()
        .map(|(k, (grid, start))| {
            let weights = (0..grid.len())
                .map(|i| 1 + ((i * 7 + k * 13 + i / 5) % 9) as u16)
                .collect();
            let rule = match k % 2 {
                0 => planner_api::CostRule::Mean,
                _ => planner_api::CostRule::Entered,
            };
            (grid.clone().with_weights(weights, rule).unwrap(), *start)
        })
        .collect();
    let (returns, searches) = check("larger", &problems);
    let (weighted_returns, weighted_searches) = check("larger weighted", &weighted);
    // All grids: 7,592 and 7,657 returns, 13,051 and 95,321 searches (2026-12-07).
    println!("{returns} {searches} {weighted_returns} {weighted_searches}");
    let least = if all { 7_000 } else { 2_000 };
    assert!(
        returns > least && weighted_returns > least,
        "{returns} {weighted_returns}"
    );
    assert!(
        weighted_searches > searches,
        "{searches} {weighted_searches}"
    );
}
