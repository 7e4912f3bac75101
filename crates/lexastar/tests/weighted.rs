//! Lexicographic A* on weighted grids (crate docs, "Weighted grids"): with 4-connected
//! moves its first criterion is the path's cost under the grid's rule, held to the test
//! kit's oracle (a plain Dijkstra over the weighted graph) on 4,000 seeded random weighted
//! grids (weights 1-255, densities 0-0.4, both cost rules); its second, the turns, and the
//! weighted objective `D + lambda T` are held to an uninformed Dijkstra over
//! `(cell, heading)` states written here. With 8-connected moves it declares no cell costs
//! and plans as on the unweighted grid.

use std::cmp::Reverse;
use std::collections::BinaryHeap;

use planner_api::{Budget, Cell, Connectivity, Grid, MoveSet, PathRule, Planner, Problem, Status};
use planner_lexastar::{Config, LexAStar, Objective};
use planner_testkit::{random_weighted_problems, weighted_dijkstra};

/// Weighted objectives as lambda = p / q: `(q, p)`.
const LAMBDAS: [(u64, u64); 4] = [(1, 0), (2, 1), (1, 1), (1, 4)];

/// The least `(q * D2 + 2 p * T, D2, T)`-first... precisely: the least key over all paths
/// from `start` to `goal`, where a path's key is `key(D2, T)` for its doubled weighted cost
/// `D2` (per move `k_from * a + k_to * b`) and turns `T`, by Dijkstra over `(cell,
/// heading)` states. Keys must be monotone in both components. `None` when unreachable.
fn state_dijkstra(
    grid: &Grid,
    start: Cell,
    goal: Cell,
    key: impl Fn(u64, u64) -> (u64, u64),
) -> Option<(u64, u64)> {
    let moves = MoveSet::standard(Connectivity::Four);
    let n = moves.moves().len();
    let (k_from, k_to) = grid.weights().map_or((1, 1), |w| w.rule().factors());
    // State n * cell + heading; heading n is "none" (the start).
    let mut best = vec![None::<(u64, u64)>; grid.len() * (n + 1)];
    let mut heap = BinaryHeap::new();
    let s = grid.index(start) * (n + 1) + n;
    best[s] = Some((0, 0));
    heap.push(Reverse((key(0, 0), 0u64, 0u64, s)));
    while let Some(Reverse((k, d2, t, state))) = heap.pop() {
        if best[state].is_some_and(|(bd, bt)| key(bd, bt) < k) {
            continue;
        }
        let (cell, heading) = (grid.cell(state / (n + 1)), state % (n + 1));
        if cell == goal {
            return Some(k);
        }
        for (h, mv) in moves.moves().iter().enumerate() {
            let Some(to) = moves.apply(grid, cell, mv) else {
                continue;
            };
            let step = k_from * u64::from(grid.weight(cell)) + k_to * u64::from(grid.weight(to));
            let turn = u64::from(heading != n && heading != h);
            let (nd, nt) = (d2 + step, t + turn);
            let next = grid.index(to) * (n + 1) + h;
            if best[next].is_none_or(|(bd, bt)| key(nd, nt) < key(bd, bt)) {
                best[next] = Some((nd, nt));
                heap.push(Reverse((key(nd, nt), nd, nt, next)));
            }
        }
    }
    None
}

fn planner(objective: Objective, lambda: f64, dominance: bool) -> LexAStar {
    LexAStar::new(Config {
        objective,
        lambda,
        dominance,
        ..Config::default()
    })
    .unwrap()
}

#[test]
fn four_connected_weighted_runs_match_the_oracle_and_the_state_dijkstra() {
    let problems = random_weighted_problems(0x1e_0032, 4_000);
    let mut lex = [
        planner(Objective::Lexicographic, 1.0, true),
        planner(Objective::Lexicographic, 1.0, false),
    ];
    let mut weighted: Vec<LexAStar> = LAMBDAS
        .iter()
        .map(|&(q, p)| planner(Objective::Weighted, p as f64 / q as f64, true))
        .collect();
    let four = MoveSet::standard(Connectivity::Four);
    let (mut compared, mut found) = (0u64, 0u64);
    for (k, p) in problems.iter().enumerate() {
        let problem = Problem::new(&p.grid, p.start, p.goal).unwrap();
        let oracle = weighted_dijkstra(&p.grid, &four, p.start, p.goal);
        let best = state_dijkstra(&p.grid, p.start, p.goal, |d, t| (d, t));
        for planner in &mut lex {
            let search = planner.search(&problem, &Budget::unlimited());
            compared += 1;
            match (oracle, &search.path) {
                (None, None) => {
                    assert_eq!(search.status, Status::NoPath, "problem {k}");
                    assert_eq!(best, None, "problem {k}");
                }
                (Some(cost), Some(path)) => {
                    found += 1;
                    path.validate(&p.grid, PathRule::Moves(&four)).unwrap();
                    assert_eq!(path.cells().first(), Some(&p.start));
                    assert_eq!(path.cells().last(), Some(&p.goal));
                    assert_eq!(search.weighted_cost, Some(cost), "problem {k}");
                    assert_eq!(p.grid.path_cost(path.cells()), cost, "problem {k}");
                    let m = path.metrics();
                    let (steps, turns) = (m.steps, m.turns);
                    assert_eq!(
                        search.cost.map(|c| (c.steps, c.turns)),
                        Some((steps, turns))
                    );
                    // Least cost first (doubled: cost in half units), then fewest turns.
                    let half = planner_api::Cost::ONE.units() / 2;
                    assert_eq!(best, Some((cost.units() / half, turns)), "problem {k}");
                }
                (oracle, path) => panic!("problem {k}: oracle {oracle:?}, lexastar {path:?}"),
            }
        }
        // The weighted objectives on every fourth grid: the least q D2 + 2 p T.
        if k % 4 == 0 {
            for (planner, &(q, p_)) in weighted.iter_mut().zip(&LAMBDAS) {
                let search = planner.search(&problem, &Budget::unlimited());
                let want = state_dijkstra(&p.grid, p.start, p.goal, |d, t| (q * d + 2 * p_ * t, 0));
                let got = search.path.as_ref().map(|path| {
                    let d2 = p.grid.path_cost(path.cells()).units()
                        / (planner_api::Cost::ONE.units() / 2);
                    (q * d2 + 2 * p_ * path.metrics().turns, 0)
                });
                assert_eq!(got, want, "problem {k}, lambda {p_}/{q}");
            }
        }
    }
    assert!(
        compared >= 8_000 && found >= 5_000,
        "{compared} runs, {found} found"
    );
}

#[test]
fn weight_one_everywhere_is_the_unweighted_search() {
    for p in random_weighted_problems(7, 300) {
        let plain = p.grid.without_weights();
        let ones = plain
            .clone()
            .with_weights(vec![1; plain.len()], planner_api::CostRule::Mean)
            .unwrap();
        let mut a = planner(Objective::Lexicographic, 1.0, true);
        let mut b = planner(Objective::Lexicographic, 1.0, true);
        let x = a.search(
            &Problem::new(&plain, p.start, p.goal).unwrap(),
            &Budget::unlimited(),
        );
        let y = b.search(
            &Problem::new(&ones, p.start, p.goal).unwrap(),
            &Budget::unlimited(),
        );
        assert_eq!((x.path, x.cost), (y.path, y.cost));
        assert_eq!(x.stats, y.stats);
    }
}

#[test]
fn eight_connected_declares_no_cell_costs_and_ignores_weights() {
    let four = planner(Objective::Lexicographic, 1.0, true);
    assert!(four.specs().cell_costs);
    let config = Config {
        moves: Connectivity::Eight,
        ..Config::default()
    };
    let mut eight = LexAStar::new(config.clone()).unwrap();
    assert!(!eight.specs().cell_costs);
    // The specs say with which `moves` it does, so a refusal can name the setting.
    let condition = eight.specs().cell_costs_only_with.expect("a condition");
    assert_eq!((condition.param, condition.values), ("moves", "4"));
    assert!(four.specs().cell_costs_only_with.is_none());
    let mut plain = LexAStar::new(config).unwrap();
    for p in random_weighted_problems(11, 200) {
        let unweighted = p.grid.without_weights();
        let x = eight.search(
            &Problem::new(&p.grid, p.start, p.goal).unwrap(),
            &Budget::unlimited(),
        );
        let y = plain.search(
            &Problem::new(&unweighted, p.start, p.goal).unwrap(),
            &Budget::unlimited(),
        );
        assert_eq!((x.path, x.cost, x.weighted_cost), (y.path, y.cost, None));
    }
}

#[test]
fn a_heavy_cell_is_avoided_at_the_price_of_turns() {
    // Straight along row 0 through the weight-9 cell costs (1+9)/2 + (9+1)/2 = 10 with no
    // turn; around it through row 1 costs 4 with two turns. Lexastar pays the turns.
    let grid = Grid::from_ascii("...\n...").unwrap();
    let grid = grid
        .with_weights(vec![1, 9, 1, 1, 1, 1], planner_api::CostRule::Mean)
        .unwrap();
    let problem = Problem::new(&grid, Cell::new(0, 0), Cell::new(2, 0)).unwrap();
    let search =
        planner(Objective::Lexicographic, 1.0, true).search(&problem, &Budget::unlimited());
    let path = search.path.unwrap();
    assert_eq!(
        path.cells(),
        [
            Cell::new(0, 0),
            Cell::new(0, 1),
            Cell::new(1, 1),
            Cell::new(2, 1),
            Cell::new(2, 0)
        ]
    );
    assert_eq!(search.weighted_cost, Some(planner_api::Cost::steps(4)));
    assert_eq!(search.cost.map(|c| (c.steps, c.turns)), Some((4, 2)));
}
