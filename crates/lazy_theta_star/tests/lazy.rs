//! Lazy Theta\* on every Moving AI scenario file (valid any-angle paths, its length
//! against the optimum and Theta\*'s, its line-of-sight savings), a hand-checked parent
//! repair, the planner's counters, budgets and unreachable goals.
//!
//! In a debug build the scenario test runs every [`DEBUG_EVERY`]th scenario of each file
//! (the first included); a release build (`cargo test --release`) or
//! `GRIDPLAN_ALL_SCENARIOS=1` runs all of them. The measured excess over the optimum is
//! printed (`cargo test -p planner-lazy_theta_star -- --nocapture`); the full figures
//! come from `cargo bench -p planner-theta_star --bench movingai`.

use planner_api::{Budget, Cell, Grid, PathRule, Planner, Problem, Status};
use planner_lazy_theta_star::{Config, LazyThetaStar, NAME};
use planner_theta_star::{AnyAngle, ThetaStar, Variant};

/// The stride through each `.scen` file in debug builds.
const DEBUG_EVERY: usize = 40;

fn scenario_stride() -> usize {
    if cfg!(debug_assertions) && std::env::var_os("GRIDPLAN_ALL_SCENARIOS").is_none() {
        DEBUG_EVERY
    } else {
        1
    }
}

#[test]
fn valid_paths_and_measured_lengths_on_every_scen_file() {
    let stride = scenario_stride();
    let mut lazy = LazyThetaStar::new(Config::default()).unwrap();
    // Theta* as the paper states it: line of sight checked on every relaxation (the
    // crate's default leaves out the checks that cannot change the search).
    let mut theta = AnyAngle::new(&Config::default()).unwrap();
    theta.skip_hopeless = false;
    let (mut n, mut n_over_optimum, mut n_over_theta) = (0usize, 0usize, 0usize);
    let mut max_over_optimum = 0.0f64;
    let (mut lazy_checks, mut theta_checks) = (0u64, 0u64);
    for map in planner_testkit::movingai_maps() {
        let grid = planner_testkit::movingai(&format!("movingai/{map}"));
        for scenario in planner_testkit::scenarios(&format!("movingai/{map}.scen"))
            .iter()
            .step_by(stride)
        {
            let what = format!("{map} line {}", scenario.line);
            let problem = Problem::new(&grid, scenario.start, scenario.goal).unwrap();
            let found = lazy.search(&problem, &Budget::unlimited());
            assert_eq!(found.status, Status::Found, "{what}");
            let path = found.path.as_ref().unwrap();
            assert_eq!(path.start(), Some(scenario.start), "{what}");
            assert_eq!(path.goal(), Some(scenario.goal), "{what}");
            if let Err(e) = path.validate(&grid, PathRule::AnyAngle) {
                panic!("{what}: {e}");
            }
            let length = path.metrics().length;
            assert!((found.cost.unwrap() - length).abs() <= 1e-9 * length.max(1.0));
            let reference = theta.search(&problem, &Budget::unlimited(), Variant::Theta);
            let optimum = scenario.optimal_length;
            let excess = length / optimum.max(1.0) - 1.0;
            if excess > 1e-4 {
                n_over_optimum += 1;
                max_over_optimum = max_over_optimum.max(excess);
            }
            n_over_theta += usize::from(length > reference.cost.unwrap() * (1.0 + 1e-9));
            lazy_checks += found.stats.n_los_checks;
            theta_checks += reference.stats.n_los_checks;
            n += 1;
        }
    }
    println!(
        "lazy theta*: {n} scenarios, {n_over_optimum} longer than the 8-connected optimum \
         (at most {:.4}%), {n_over_theta} longer than Theta*; line-of-sight checks {lazy_checks} \
         against Theta*'s {theta_checks}",
        max_over_optimum * 100.0
    );
    // Lazy Theta*'s point: far fewer line-of-sight checks than Theta*.
    assert!(
        lazy_checks * 3 < theta_checks,
        "{lazy_checks} vs {theta_checks}"
    );
    // No guarantee, but on these maps it stays within 1% of the 8-connected optimum.
    assert!(max_over_optimum < 0.01, "{max_over_optimum}");
}

#[test]
fn parent_repair_by_hand() {
    // S = (0,1), G = (2,1), the centre blocked; moves R L D U DR DL UR UL.
    // 1. S: D (0,2), U (0,0) get parent S, g 1 (no check: parent(S) = S).
    // 2. (0,2) (f 1 + sqrt 5, pushed first): S sees it (check 1). R (1,2) gets parent S
    //    unchecked, g sqrt 2, f 2 sqrt 2.
    // 3. (1,2) (f 2.83 < 3.24): S to (1,2) crosses the centre's corner: no line of sight
    //    (check 2). Repair: its CLOSED neighbours are (0,2) (L, g 1 + 1) and S, but S is
    //    not a safe move from (1,2) (the UL diagonal cuts the centre); parent (0,2), g 2,
    //    f 2 + sqrt 2 (repair 1). R (2,2) gets parent (0,2) unchecked: g 3, f 4.
    // 4. (0,0) (f 1 + sqrt 5): S sees it (check 3). R (1,0) parent S, g sqrt 2.
    // 5. (1,0) (f 2 sqrt 2): no line of sight from S (check 4); repaired to (0,0), g 2
    //    (repair 2). R (2,0) parent (0,0), g 3, f 4.
    // 6. (2,2) (f 4, g 3, pushed before (2,0)): (0,2) sees it (check 5). U G gets parent
    //    (0,2) unchecked: g 1 + sqrt 5, f 1 + sqrt 5 = 3.24.
    // 7. G: (0,2) to G crosses the centre (check 6): repaired to its best CLOSED
    //    neighbour, (2,2) with g 3 + 1 (repair 3) -- (1,2) and (1,0) are not safe moves.
    //    Found, length 4 as Theta*'s.
    let grid = Grid::from_ascii(
        "
        ...
        .#.
        ...
        ",
    )
    .unwrap();
    let problem = Problem::new(&grid, Cell::new(0, 1), Cell::new(2, 1)).unwrap();
    let mut lazy = LazyThetaStar::new(Config::default()).unwrap();
    assert_eq!(lazy.name(), NAME);
    let outcome = lazy.plan(&problem, &Budget::unlimited());
    let text = planner_testkit::outcome_text(&outcome);
    let expect = "status found\npath (0,1) (0,2) (2,2) (2,1)\n";
    assert!(text.starts_with(expect), "{text}");
    let c = &outcome.counters;
    assert_eq!(c.get("n_expanded"), Some(7), "{c}");
    assert_eq!(c.get("n_los_checks"), Some(6), "{c}");
    assert_eq!(c.get("n_parent_repairs"), Some(3), "{c}");
    let theta = ThetaStar::new(Config::default())
        .unwrap()
        .plan(&problem, &Budget::unlimited());
    assert_eq!(theta.path, outcome.path);
}

#[test]
fn budget_and_unreachable_goal() {
    let grid = Grid::from_ascii(
        "
        ...#....
        ...#....
        ...#....
        ",
    )
    .unwrap();
    let mut lazy = LazyThetaStar::new(Config::default()).unwrap();
    let problem = Problem::new(&grid, Cell::new(0, 0), Cell::new(7, 2)).unwrap();
    let outcome = lazy.plan(&problem, &Budget::unlimited());
    assert_eq!(outcome.status, Status::NoPath);
    assert_eq!(outcome.path, None);
    assert_eq!(outcome.counters.get("n_expanded"), Some(9));
    let problem = Problem::new(&grid, Cell::new(0, 0), Cell::new(2, 2)).unwrap();
    let cut = lazy.plan(&problem, &Budget::expansions(1));
    assert_eq!(cut.status, Status::BudgetExhausted);
    assert_eq!(cut.counters.get("n_expanded"), Some(1));
    let err = LazyThetaStar::new(Config {
        corner_cutting: true,
        ..Config::default()
    })
    .unwrap_err();
    assert!(err.to_string().contains("parameter `corner_cutting`"));
}
