//! weighted_jps against the test kit's oracle (a plain Dijkstra over the weighted graph) on
//! random weighted grids, and against planner-jps's lengths on grids without weights.

use planner_api::{
    Budget, Cell, Connectivity, CostRule, Grid, MoveSet, NeighborOrder, PathRule, Planner, Problem,
    Status,
};
use planner_testkit::{random_weighted_problems, weighted_dijkstra};
use planner_weighted_jps::{Config, WeightedJps};

fn moves() -> MoveSet {
    MoveSet::new(Connectivity::Eight, false, &NeighborOrder::default()).unwrap()
}

/// Plans every problem and compares its path's cost with the oracle's; returns the total
/// of `n_reopened` and of the expansions.
fn check_all(label: &str, problems: &[(Grid, Cell, Cell)]) -> (u64, u64) {
    let moves = moves();
    let mut planner = WeightedJps::new(Config::default()).unwrap();
    let (mut mismatches, mut reopened, mut expanded) = (0, 0, 0);
    for (k, (grid, start, goal)) in problems.iter().enumerate() {
        let oracle = weighted_dijkstra(grid, &moves, *start, *goal);
        let problem = Problem::new(grid, *start, *goal).unwrap();
        let outcome = planner.plan(&problem, &Budget::unlimited());
        reopened += outcome.counters.get("n_reopened").unwrap();
        expanded += outcome.counters.get("n_expanded").unwrap();
        match (oracle, &outcome.path) {
            (None, None) => assert_eq!(outcome.status, Status::NoPath, "{label} {k}"),
            (Some(cost), Some(path)) => {
                path.validate(grid, PathRule::Moves(&moves)).unwrap();
                assert_eq!(path.cells().first(), Some(start), "{label} {k}");
                assert_eq!(path.cells().last(), Some(goal), "{label} {k}");
                if grid.path_cost(path.cells()) != cost {
                    mismatches += 1;
                    eprintln!(
                        "{label} problem {k}: {:?} against the oracle's {cost:?}",
                        grid.path_cost(path.cells())
                    );
                }
            }
            (oracle, path) => panic!("{label} problem {k}: oracle {oracle:?}, path {path:?}"),
        }
    }
    assert_eq!(mismatches, 0, "{label}");
    (reopened, expanded)
}

#[test]
fn ten_thousand_random_weighted_grids_match_the_oracle() {
    // The test kit's grids: weights 1-255 per cell or in patches of 2 to 5 cells, blocked
    // densities 0-0.4, both cost rules.
    let problems: Vec<_> = random_weighted_problems(0x5eed_0032, 10_000)
        .into_iter()
        .map(|p| (p.grid, p.start, p.goal))
        .collect();
    let (reopened, _) = check_all("test kit", &problems);
    assert_eq!(reopened, 0);
}

/// Grids of 8 to 56 cells a side in patches of 3 to 14 cells of one of a few weights, few
/// blocked cells: long jumps through uniform patches that stop at their edges.
fn patchy_problems(seed: u64, rounds: usize) -> Vec<(Grid, Cell, Cell)> {
    let mut next = planner_testkit::xorshift(seed | 1);
    (0..rounds)
        .map(|round| {
            let (w, h) = (8 + (next() % 49) as u32, 8 + (next() % 49) as u32);
            let density = next() % 16;
            let free: Vec<bool> = (0..w * h).map(|_| next() % 100 >= density).collect();
            let patch = 3 + (next() % 12) as u32;
            let palette = [1u16, 1, 2, 3, 7, 40];
            let cols = w.div_ceil(patch);
            let patches: Vec<u16> = (0..cols * h.div_ceil(patch))
                .map(|_| palette[(next() % 6) as usize])
                .collect();
            let weights: Vec<u16> = (0..w * h)
                .map(|i| patches[((i / w / patch) * cols + (i % w) / patch) as usize])
                .collect();
            let rule = if round % 2 == 0 {
                CostRule::Mean
            } else {
                CostRule::Entered
            };
            let mut grid = Grid::from_free_cells(w, h, free)
                .and_then(|g| g.with_weights(weights, rule))
                .unwrap();
            let mut cell = || {
                Cell::new(
                    (next() % u64::from(w)) as u32,
                    (next() % u64::from(h)) as u32,
                )
            };
            let (start, goal) = (cell(), cell());
            grid.set_free(start, true);
            grid.set_free(goal, true);
            (grid, start, goal)
        })
        .collect()
}

/// A costmap's updates between plans: cells blocked and freed and 3 x 3 patches given new
/// weights, eight rounds of edits per grid, one planner throughout, which brings its tables
/// up to date after each round ([`Grid::changed_since`]) instead of rebuilding them.
#[test]
fn grids_edited_between_plans_match_the_oracle() {
    let mut next = planner_testkit::xorshift(0xed17_u64);
    let mut problems = Vec::new();
    for (mut grid, start, goal) in patchy_problems(0x0ed1_7ed1, 300) {
        let (w, h) = (grid.width(), grid.height());
        for _ in 0..8 {
            for _ in 0..1 + next() % 6 {
                let cell = Cell::new(
                    (next() % u64::from(w)) as u32,
                    (next() % u64::from(h)) as u32,
                );
                if next() % 2 == 0 {
                    if cell != start && cell != goal {
                        grid.set_free(cell, next() % 3 == 0);
                    }
                } else {
                    let weight = [1u16, 2, 7, 40][(next() % 4) as usize];
                    for (dx, dy) in (0..9).map(|i| (i % 3 - 1, i / 3 - 1)) {
                        if let Some(near) = grid.offset(cell, dx, dy) {
                            grid.set_weight(near, weight);
                        }
                    }
                }
            }
            problems.push((grid.clone(), start, goal));
        }
    }
    check_all("edited", &problems);
}

#[test]
fn grids_with_large_uniform_patches_match_the_oracle() {
    let (reopened, expanded) = check_all("patches", &patchy_problems(0x5eed_0033, 3_000));
    assert_eq!(reopened, 0);
    assert!(expanded > 0);
}

#[test]
fn grids_without_weights_match_the_oracle_and_jps() {
    // The same grids without their weights: the uniform test then only sees blocked cells,
    // and the search is JPS's, so the costs are planner-jps's too.
    let problems: Vec<_> = patchy_problems(0x5eed_0034, 2_000)
        .into_iter()
        .map(|(grid, start, goal)| {
            let free = grid.free_cells().to_vec();
            let plain = Grid::from_free_cells(grid.width(), grid.height(), free).unwrap();
            (plain, start, goal)
        })
        .collect();
    check_all("unweighted", &problems);
    let mut jps = planner_jps::Jps::new(planner_jps::Config::default()).unwrap();
    let mut ours = WeightedJps::new(Config::default()).unwrap();
    for (grid, start, goal) in &problems {
        let problem = Problem::new(grid, *start, *goal).unwrap();
        let a = ours.plan(&problem, &Budget::unlimited());
        let b = jps.plan(&problem, &Budget::unlimited());
        let length = |o: &planner_api::Outcome| o.path.as_ref().map(|p| grid.path_cost(p.cells()));
        assert_eq!(length(&a), length(&b));
    }
}

#[test]
fn jumps_cross_uniform_terrain_in_one_expansion() {
    // An open 40 x 40 grid of one weight: the diagonal from corner to corner is one jump,
    // so the search expands the start and the goal only.
    let grid = Grid::from_free_cells(40, 40, vec![true; 1600])
        .unwrap()
        .with_weights(vec![3; 1600], CostRule::Mean)
        .unwrap();
    let problem = Problem::new(&grid, Cell::new(0, 0), Cell::new(39, 39)).unwrap();
    let outcome = WeightedJps::new(Config::default())
        .unwrap()
        .plan(&problem, &Budget::unlimited());
    // By hand: the start's eight jumps (the five leaving the grid at once included), of
    // which the diagonal one reaches the goal; the goal is expanded without jumping.
    assert_eq!(outcome.counters.get("n_expanded"), Some(2));
    assert_eq!(outcome.counters.get("n_jumps"), Some(8));
    assert_eq!(outcome.counters.get("n_open_insertions"), Some(2));
    assert_eq!(outcome.counters.get("n_relaxations"), Some(1));
    let path = outcome.path.unwrap();
    assert_eq!(path.cells().len(), 40);
    assert!(outcome.marks.is_empty());
    // A band of weight 5 across it: the jump stops on each side of the band's edges.
    let weights: Vec<u16> = (0..1600u32)
        .map(|i| if (18..22).contains(&(i / 40)) { 5 } else { 1 })
        .collect();
    let banded = grid.with_weights(weights, CostRule::Mean).unwrap();
    let problem = Problem::new(&banded, Cell::new(0, 0), Cell::new(39, 39)).unwrap();
    let outcome = WeightedJps::new(Config::default())
        .unwrap()
        .plan(&problem, &Budget::unlimited());
    let oracle = weighted_dijkstra(&banded, &moves(), Cell::new(0, 0), Cell::new(39, 39));
    assert_eq!(
        banded.path_cost(outcome.path.unwrap().cells()),
        oracle.unwrap()
    );
    let expanded = outcome.counters.get("n_expanded").unwrap();
    assert!(expanded > 2 && expanded < 400, "{expanded}");
}

#[test]
fn budgets_and_bad_parameters() {
    let (grid, start, goal) = patchy_problems(7, 40)
        .into_iter()
        .max_by_key(|(g, _, _)| g.len())
        .unwrap();
    let problem = Problem::new(&grid, start, goal).unwrap();
    let mut planner = WeightedJps::new(Config::default()).unwrap();
    let full = planner.plan(&problem, &Budget::unlimited());
    let n = full.counters.get("n_expanded").unwrap();
    assert!(n > 2, "{n}");
    let cut = planner.plan(&problem, &Budget::expansions(n / 2));
    assert_eq!(cut.status, Status::BudgetExhausted);
    assert_eq!(cut.counters.get("n_expanded"), Some(n / 2));
    assert!(cut.path.is_none());
    // The same planner again: the same outcome as the first run; recording lists each
    // expanded jump point once.
    assert_eq!(planner.plan(&problem, &Budget::unlimited()), full);
    let recording = Budget {
        record_expanded: true,
        ..Budget::unlimited()
    };
    let recorded = planner.plan(&problem, &recording);
    assert_eq!(recorded.counters, full.counters);
    assert_eq!(recorded.expanded.len() as u64, n);
    assert_eq!(recorded.expanded.first(), Some(&start));
    if full.status == Status::Found {
        assert_eq!(recorded.expanded.last(), Some(&goal));
    }
    use planner_api::ParamKey;
    let four = Config {
        moves: Connectivity::Four,
        ..Config::default()
    };
    assert_eq!(WeightedJps::new(four).unwrap_err().param_key(), "moves");
    let cutting = Config {
        corner_cutting: true,
        ..Config::default()
    };
    assert_eq!(
        WeightedJps::new(cutting).unwrap_err().param_key(),
        "corner_cutting"
    );
}
