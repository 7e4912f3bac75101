//! The heuristic is consistent (checked for every state, move and goal of a window) and
//! admissible (checked against exact costs-to-go from an uninformed Dijkstra over states,
//! written here), and lexastar's optimum equals Dijkstra's for every objective, with and
//! without dominance pruning.

use std::cmp::Reverse;
use std::collections::BinaryHeap;

use planner_api::{Budget, Cell, Connectivity, Grid, MoveSet, Problem, Status};
use planner_lexastar::{heuristic, Config, Cost, LexAStar, Objective};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

const CONNECTIVITIES: [Connectivity; 2] = [Connectivity::Four, Connectivity::Eight];

fn unit_moves(connectivity: Connectivity) -> Vec<(i32, i32)> {
    MoveSet::standard(connectivity)
        .moves()
        .iter()
        .map(|m| (m.dx, m.dy))
        .collect()
}

/// The turn a move `d` makes after heading `h` (none for the start): the paper's c_i - 1.
fn turn(h: Option<(i32, i32)>, d: (i32, i32)) -> u64 {
    u64::from(h.is_some_and(|h| h != d))
}

#[test]
fn consistent_for_every_state_move_and_goal_of_a_window() {
    // The heuristic ignores obstacles, so checking an open 9x9 window covers every relative
    // position within 8 cells, every heading (and none) and every move.
    let side = 9;
    for connectivity in CONNECTIVITIES {
        let moves = unit_moves(connectivity);
        let mut headings: Vec<Option<(i32, i32)>> = vec![None];
        headings.extend(moves.iter().map(|&m| Some(m)));
        let mut n_checked = 0u64;
        let mut max_turns = 0;
        for goal in (0..side * side).map(|i| Cell::new(i % side, i / side)) {
            for cell in (0..side * side).map(|i| Cell::new(i % side, i / side)) {
                for &h in &headings {
                    let here = heuristic(connectivity, cell, h, goal);
                    max_turns = max_turns.max(here.turns);
                    if cell == goal {
                        assert_eq!(here, Cost::new(0, 0), "goal state {cell} {h:?}");
                    }
                    for &d in &moves {
                        let Some(next) = cell.checked_offset(d.0, d.1) else {
                            continue;
                        };
                        if next.x >= side || next.y >= side {
                            continue;
                        }
                        let there = heuristic(connectivity, next, Some(d), goal);
                        let cost = Cost::new(1, turn(h, d));
                        let what = format!("{connectivity} {cell} {h:?} -> {d:?}, goal {goal}");
                        // Lexicographic consistency, and each component on its own (which
                        // makes steps + lambda * turns consistent for every lambda >= 0).
                        assert!(here <= cost.plus(there), "{what}");
                        assert!(here.steps <= 1 + there.steps, "{what}");
                        assert!(here.turns <= cost.turns + there.turns, "{what}");
                        n_checked += 1;
                    }
                }
            }
        }
        // 81 goals x 81 cells x (1 + k) headings x k moves, minus moves leaving the window.
        assert!(n_checked > 81 * 81 * 5 * 3, "{n_checked}");
        let expected_max = if connectivity == Connectivity::Four {
            2
        } else {
            1
        };
        assert_eq!(max_turns, expected_max, "{connectivity}");
    }
}

/// How a cost is turned into a scalar for one objective: `scale_steps * D + scale_turns * T`
/// for weighted objectives with rational lambda, or `D << 64 | T` for the lexicographic one.
/// Both are additive, so Dijkstra on the scalar is Dijkstra on the objective.
#[derive(Debug, Clone, Copy)]
enum Weight {
    Lexicographic,
    /// lambda = turns / steps as a fraction: (steps scale, turns scale).
    Ratio(u128, u128),
}

impl Weight {
    fn of(self, cost: Cost) -> u128 {
        match self {
            Weight::Lexicographic => (u128::from(cost.steps) << 64) | u128::from(cost.turns),
            Weight::Ratio(q, p) => q * u128::from(cost.steps) + p * u128::from(cost.turns),
        }
    }

    fn config(self, connectivity: Connectivity) -> Config {
        let base = Config {
            moves: connectivity,
            ..Config::default()
        };
        match self {
            Weight::Lexicographic => base,
            Weight::Ratio(q, p) => Config {
                objective: Objective::Weighted,
                lambda: p as f64 / q as f64,
                ..base
            },
        }
    }
}

const WEIGHTS: [Weight; 5] = [
    Weight::Lexicographic,
    Weight::Ratio(1, 0), // lambda 0: plain shortest paths
    Weight::Ratio(2, 1), // lambda 0.5
    Weight::Ratio(1, 1), // lambda 1: Score
    Weight::Ratio(1, 4), // lambda 4
];

/// Exact cost-to-go of every state `(cell, heading)` to `goal` under `weight`, by an
/// uninformed Dijkstra run backwards from the goal states. Heading slot 0 is "none",
/// slot k + 1 is move k. `None` where the goal is unreachable.
fn cost_to_go(grid: &Grid, set: &MoveSet, goal: Cell, weight: Weight) -> Vec<Option<u128>> {
    let moves = set.moves();
    let slots = moves.len() + 1;
    let mut best: Vec<Option<u128>> = vec![None; grid.len() * slots];
    let mut heap = BinaryHeap::new();
    for slot in 0..slots {
        let state = grid.index(goal) * slots + slot;
        best[state] = Some(0);
        heap.push(Reverse((0u128, state)));
    }
    while let Some(Reverse((value, state))) = heap.pop() {
        if best[state] != Some(value) {
            continue;
        }
        let (index, slot) = (state / slots, state % slots);
        if slot == 0 {
            continue; // No move leads into a state without heading.
        }
        // The state (cell, heading d) is entered by move d from cell - d.
        let cell = grid.cell(index);
        let d = &moves[slot - 1];
        let Some(from) = cell.checked_offset(-d.dx, -d.dy) else {
            continue;
        };
        if !grid.is_free(from) || set.apply(grid, from, d) != Some(cell) {
            continue;
        }
        for from_slot in 0..slots {
            let h = (from_slot > 0).then(|| (moves[from_slot - 1].dx, moves[from_slot - 1].dy));
            let step = weight.of(Cost::new(1, turn(h, (d.dx, d.dy))));
            let candidate = value + step;
            let from_state = grid.index(from) * slots + from_slot;
            if best[from_state].is_none_or(|b| candidate < b) {
                best[from_state] = Some(candidate);
                heap.push(Reverse((candidate, from_state)));
            }
        }
    }
    best
}

/// Checks admissibility at every state and lexastar's optimum from every free start, for
/// every objective, on `grid` towards `goal`. Returns the number of searches run.
fn check_grid(grid: &Grid, goal: Cell, connectivity: Connectivity) -> u64 {
    let set = MoveSet::standard(connectivity);
    let moves = set.moves();
    let slots = moves.len() + 1;
    let mut n_searches = 0;
    for weight in WEIGHTS {
        let exact = cost_to_go(grid, &set, goal, weight);
        for cell in grid.cells().filter(|&c| grid.is_free(c)) {
            for slot in 0..slots {
                let h = (slot > 0).then(|| (moves[slot - 1].dx, moves[slot - 1].dy));
                if let Some(exact) = exact[grid.index(cell) * slots + slot] {
                    let estimate = weight.of(heuristic(connectivity, cell, h, goal));
                    assert!(
                        estimate <= exact,
                        "{weight:?} {connectivity} {cell} {h:?} goal {goal}\n{grid:?}"
                    );
                }
            }
            let problem = Problem::new(grid, cell, goal).unwrap();
            for dominance in [true, false] {
                let config = Config {
                    dominance,
                    ..weight.config(connectivity)
                };
                let search = LexAStar::new(config)
                    .unwrap()
                    .search(&problem, &Budget::unlimited());
                n_searches += 1;
                let what = format!("{weight:?} dominance {dominance} {cell}->{goal}\n{grid:?}");
                match exact[grid.index(cell) * slots] {
                    Some(optimum) => {
                        assert_eq!(search.status, Status::Found, "{what}");
                        let cost = search.cost.unwrap();
                        assert_eq!(weight.of(cost), optimum, "{what}");
                        // The returned cells have the reported cost, counted independently.
                        let m = search.path.unwrap().metrics();
                        assert_eq!((m.steps, m.turns), (cost.steps, cost.turns), "{what}");
                    }
                    None => assert_eq!(search.status, Status::NoPath, "{what}"),
                }
            }
        }
    }
    n_searches
}

#[test]
fn admissible_and_optimal_on_every_3x3_grid() {
    // Every obstacle pattern of a 3x3 grid, every free goal and start.
    let mut n_searches = 0;
    for mask in 0u32..512 {
        let free = (0..9).map(|i| mask & (1 << i) == 0).collect();
        let grid = Grid::from_free_cells(3, 3, free).unwrap();
        for goal in grid.cells().filter(|&c| grid.is_free(c)) {
            for connectivity in CONNECTIVITIES {
                n_searches += check_grid(&grid, goal, connectivity);
            }
        }
    }
    // (goal, start) pairs: the sum over patterns of f^2, f = free cells, is
    // sum f + sum f (f - 1) = 9 * 2^8 + 9 * 8 * 2^7 = 11520; x 2 neighbourhoods
    // x 5 objectives x dominance on and off.
    assert_eq!(n_searches, 11520 * 2 * 5 * 2);
}

#[test]
fn admissible_and_optimal_on_random_grids() {
    let mut rng = ChaCha8Rng::seed_from_u64(7);
    for _ in 0..60 {
        let (width, height) = (rng.gen_range(4..=6), rng.gen_range(4..=6));
        let density = rng.gen_range(0.1..0.4);
        let free = (0..width * height)
            .map(|_| !rng.gen_bool(density))
            .collect();
        let grid = Grid::from_free_cells(width, height, free).unwrap();
        let free_cells: Vec<Cell> = grid.cells().filter(|&c| grid.is_free(c)).collect();
        if free_cells.is_empty() {
            continue;
        }
        let goal = free_cells[rng.gen_range(0..free_cells.len())];
        for connectivity in CONNECTIVITIES {
            check_grid(&grid, goal, connectivity);
        }
    }
}
