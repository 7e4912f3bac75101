//! Coverage against `planner_testkit::reference_coverage`, seed 004's run written again
//! (filling rules on cell coordinates, the documented branch and bound with the test kit's
//! reference A*): the same path and every counter, both patterns, with and without cell
//! weights.

use planner_api::{Budget, Cell, CoveragePlanner, CoverageProblem, Grid};
use planner_coverage::{Config, Coverage, Heading, Pattern, Rotation, Side};
use planner_testkit::{
    random_weighted_problems, reference_coverage, small_random_problems, Fill, COVERAGE_COUNTERS,
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
