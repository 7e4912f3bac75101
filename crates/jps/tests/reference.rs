//! Every variant of planner-jps against `planner_testkit::reference_jps`, its search written
//! again with jumps walked cell by cell and std's binary heap: the same status, jump points,
//! path and every counter.

use planner_api::{Budget, Cell, Grid, Planner, Problem};
use planner_jps::{Config, Jps, Variant};
use planner_testkit::{
    cells_through, random_problems, reference_jps, small_random_problems, JpsVariant, JPS_COUNTERS,
};

const VARIANTS: [(Variant, JpsVariant); 3] = [
    (Variant::Jps, JpsVariant::Jps),
    (Variant::JpsPrime, JpsVariant::JpsPrime),
    (Variant::JpsPlus, JpsVariant::JpsPlus),
];

/// Plans every problem with every variant and compares with the reference; returns the
/// expansions per variant.
fn check(label: &str, problems: &[(Grid, Cell, Cell)]) -> [u64; 3] {
    let mut expanded = [0; 3];
    for (v, (variant, reference)) in VARIANTS.into_iter().enumerate() {
        let mut planner = Jps::new(Config {
            variant,
            ..Config::default()
        })
        .unwrap();
        for (k, (grid, start, goal)) in problems.iter().enumerate() {
            let what = format!("{label} {variant:?} problem {k}: {start:?} -> {goal:?}");
            let problem = Problem::new(grid, *start, *goal).unwrap();
            let outcome = planner.plan(&problem, &Budget::unlimited());
            let (status, chain, counters) = reference_jps(grid, *start, *goal, reference);
            assert_eq!(outcome.status, status, "{what}");
            let actual: Vec<u64> = outcome.counters.iter().map(|(_, value)| value).collect();
            assert_eq!(actual, counters, "{what}: {JPS_COUNTERS:?}");
            expanded[v] += counters[0];
            match (&outcome.path, chain) {
                (Some(path), Some(chain)) => {
                    assert_eq!(path.cells(), cells_through(&chain), "{what}");
                    let marks: Vec<Cell> = outcome.marks.iter().map(|m| m.cell).collect();
                    assert_eq!(
                        marks,
                        chain[1..chain.len().saturating_sub(1).max(1)],
                        "{what}"
                    );
                }
                (None, None) => {}
                (path, chain) => panic!("{what}: path {:?}, reference {chain:?}", path.is_some()),
            }
        }
    }
    expanded
}

#[test]
fn every_variant_equals_the_reference_on_small_random_grids() {
    let expanded = check("small", &small_random_problems(21, 3000));
    // 11,151, 9,880 and 9,880 expansions (2026-12-06).
    assert!(expanded.iter().all(|&n| n > 9_000), "{expanded:?}");
}

/// Grids of 150 to 300 cells a side, half with 2 to 20 % of their cells blocked, half with
/// 0.05 to 0.2 %: long jumps, and JPS+'s far table entries (jumps of 127 cells or more,
/// read again every 63 cells) on the sparse ones.
#[test]
fn every_variant_equals_the_reference_on_large_open_grids() {
    let mut problems = random_problems(0x005e_ed0f_1a7e, 16, (150, 300), (200, 2000));
    problems.extend(random_problems(0x005e_ed0f_1a7f, 16, (150, 300), (5, 20)));
    let expanded = check("large", &problems);
    // 13,823, 7,740 and 7,740 expansions (2026-12-06).
    assert!(expanded.iter().all(|&n| n > 1_500), "{expanded:?}");
}
