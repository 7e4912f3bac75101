//! Theta\* (with and without `skip_hopeless`) and Lazy Theta\* against
//! `planner_testkit::reference_theta_star`, the search written again with planner-api's
//! line-of-sight walk and std's binary heap: the same status, waypoints and every counter.

use planner_api::{Budget, Cell, Grid, Problem};
use planner_testkit::{
    random_problems, reference_theta_star, small_random_problems, THETA_COUNTERS,
};
use planner_theta_star::{AnyAngle, Config, Variant};

/// Plans every problem with Theta\* (both settings) and Lazy Theta\* and compares with the
/// reference; returns the expansions and line-of-sight checks of each.
fn check(label: &str, problems: &[(Grid, Cell, Cell)]) -> [(u64, u64); 3] {
    let mut totals = [(0, 0); 3];
    let settings = [
        (Variant::Theta, true),
        (Variant::Theta, false),
        (Variant::Lazy, true),
    ];
    for (k, (variant, skip_hopeless)) in settings.into_iter().enumerate() {
        let mut search = AnyAngle::new(&Config::default()).unwrap();
        search.skip_hopeless = skip_hopeless;
        for (i, (grid, start, goal)) in problems.iter().enumerate() {
            let what = format!(
                "{label} {variant:?} skip {skip_hopeless} problem {i}: {start:?} -> {goal:?}"
            );
            let problem = Problem::new(grid, *start, *goal).unwrap();
            let outcome = search
                .search(&problem, &Budget::unlimited(), variant)
                .outcome(variant);
            let lazy = variant == Variant::Lazy;
            let (status, path, counters) =
                reference_theta_star(grid, *start, *goal, lazy, skip_hopeless);
            assert_eq!(outcome.status, status, "{what}");
            let names = &THETA_COUNTERS[..9 + usize::from(lazy)];
            let actual: Vec<(&str, u64)> = outcome.counters.iter().collect();
            let expected: Vec<(&str, u64)> = names.iter().copied().zip(counters).collect();
            assert_eq!(actual, expected, "{what}");
            assert_eq!(outcome.path.map(|p| p.cells().to_vec()), path, "{what}");
            totals[k].0 += counters[0];
            totals[k].1 += counters[7];
        }
    }
    totals
}

#[test]
fn theta_and_lazy_theta_equal_the_reference_on_small_random_grids() {
    let totals = check("small", &small_random_problems(31, 3000));
    // 19,613 expansions for Theta* (20,373 line-of-sight checks, 31,668 checking every
    // relaxation), 19,859 for Lazy Theta* (2026-12-06).
    assert!(
        totals.iter().all(|&(expanded, _)| expanded > 15_000),
        "{totals:?}"
    );
    assert!(totals[0].1 < totals[1].1, "{totals:?}");
}

/// Grids of 40 to 120 cells a side with 5 to 30 % of their cells blocked.
#[test]
fn theta_and_lazy_theta_equal_the_reference_on_larger_grids() {
    let problems = random_problems(0x7e7a_5eed, 60, (40, 120), (500, 3000));
    let totals = check("larger", &problems);
    // 27,160 expansions for Theta* (45,917 line-of-sight checks, 75,533 checking every
    // relaxation), 27,996 for Lazy Theta* (2026-12-06).
    assert!(
        totals.iter().all(|&(expanded, _)| expanded > 20_000),
        "{totals:?}"
    );
    assert!(totals[0].1 < totals[1].1, "{totals:?}");
}
