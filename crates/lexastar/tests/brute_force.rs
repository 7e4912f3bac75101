//! Property test: on seeded random grids lexastar's (D, T, Score) equals the best by
//! `PathRank` among all simple paths, found by an independent brute-force DFS written here
//! (seed 000's Backtracking, section 2.3: every simple path, no cell twice).
//!
//! The literal enumeration is exponential, and the test crate is compiled without
//! optimisation, so it runs with a call cap ([`CALL_CAP`]). Where it completes, it is
//! compared with lexastar in every mode: lexicographic (D, T, Score) with and without
//! dominance pruning, and the weighted optima `D + lambda T` for lambda = 0, 0.5, 1 and 4. Where it hits the cap, a second
//! exhaustive DFS enumerates every simple path that can still reach the goal within the
//! shortest distance D* (breadth-first distances prune the rest). The best path by
//! `PathRank` has D = D*, so this DFS sees every candidate; it checks the lexicographic
//! mode only. Every grid is checked one way or the other, and no-path answers must agree
//! with breadth-first search (and the literal DFS finding no solution where it completes).

use std::collections::VecDeque;

use planner_api::{Budget, Cell, Connectivity, Grid, MoveSet, PathRank, PathRule, Problem, Status};
use planner_lexastar::{Config, LexAStar, Objective};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// Calls after which the literal enumeration gives up on a grid.
const CALL_CAP: u64 = 20_000;

/// Weighted objectives checked against the literal enumeration, as lambda = p / q:
/// `(q, p)`, compared as the integer `q D + p T`.
const LAMBDAS: [(u64, u64); 4] = [(1, 0), (2, 1), (1, 1), (1, 4)];

/// The best solutions found by a brute-force DFS.
#[derive(Debug, Default)]
struct Best {
    rank: Option<PathRank>,
    /// Least `q D + p T` per entry of [`LAMBDAS`].
    weighted: [Option<u64>; LAMBDAS.len()],
    n_solutions: u64,
}

/// Brute-force enumeration of simple paths with seed 000's Visited matrix, counting D and
/// T move by move (the paper's equations 22 and 24).
struct Dfs<'a> {
    /// Per cell, the allowed moves: (target cell, move index).
    neighbours: &'a [Vec<(usize, usize)>],
    goal: usize,
    visited: Vec<bool>,
    calls: u64,
    cap: u64,
    /// Breadth-first distance to the goal and D*: prune paths that cannot reach the goal
    /// in D* steps. `None`: literal enumeration.
    prune: Option<(&'a [u64], u64)>,
    best: Best,
}

impl Dfs<'_> {
    /// Enumerates from `cell`, reached after `steps` moves and `turns` turns, the last
    /// move being `heading` (`None` at the start); false when the call cap was hit.
    fn run(&mut self, cell: usize, steps: u64, turns: u64, heading: Option<usize>) -> bool {
        self.calls += 1;
        if self.calls > self.cap {
            return false;
        }
        if cell == self.goal {
            let rank = PathRank {
                steps,
                turns,
                score: steps + turns,
            };
            if self.best.rank.is_none_or(|best| rank.is_better_than(&best)) {
                self.best.rank = Some(rank);
            }
            for (slot, &(q, p)) in self.best.weighted.iter_mut().zip(&LAMBDAS) {
                let value = q * steps + p * turns;
                *slot = Some(slot.map_or(value, |best| best.min(value)));
            }
            self.best.n_solutions += 1;
            return true;
        }
        let neighbours = self.neighbours;
        for &(next, direction) in &neighbours[cell] {
            if self.visited[next] {
                continue;
            }
            if let Some((distance, shortest)) = self.prune {
                if steps + 1 + distance[next] > shortest {
                    continue;
                }
            }
            let turn = u64::from(heading.is_some_and(|h| h != direction));
            self.visited[next] = true;
            let complete = self.run(next, steps + 1, turns + turn, Some(direction));
            self.visited[next] = false;
            if !complete {
                return false;
            }
        }
        true
    }
}

/// The allowed moves out of every cell.
fn neighbours(grid: &Grid, set: &MoveSet) -> Vec<Vec<(usize, usize)>> {
    grid.cells()
        .map(|cell| {
            set.moves()
                .iter()
                .enumerate()
                .filter_map(|(k, mv)| set.apply(grid, cell, mv).map(|next| (grid.index(next), k)))
                .collect()
        })
        .collect()
}

fn enumerate(
    grid: &Grid,
    neighbours: &[Vec<(usize, usize)>],
    start: Cell,
    goal: Cell,
    cap: u64,
    prune: Option<(&[u64], u64)>,
) -> Option<Best> {
    let mut dfs = Dfs {
        neighbours,
        goal: grid.index(goal),
        visited: vec![false; grid.len()],
        calls: 0,
        cap,
        prune,
        best: Best::default(),
    };
    dfs.visited[grid.index(start)] = true;
    dfs.run(grid.index(start), 0, 0, None).then_some(dfs.best)
}

/// Breadth-first steps from every cell to `goal` (moves are symmetric), `u64::MAX` where
/// unreachable.
fn distances_to(grid: &Grid, set: &MoveSet, goal: Cell) -> Vec<u64> {
    let mut distance = vec![u64::MAX; grid.len()];
    distance[grid.index(goal)] = 0;
    let mut queue = VecDeque::from([goal]);
    while let Some(cell) = queue.pop_front() {
        for mv in set.moves() {
            if let Some(next) = set.apply(grid, cell, mv) {
                if distance[grid.index(next)] == u64::MAX {
                    distance[grid.index(next)] = distance[grid.index(cell)] + 1;
                    queue.push_back(next);
                }
            }
        }
    }
    distance
}

fn random_grid(rng: &mut ChaCha8Rng, sides: std::ops::RangeInclusive<u32>) -> Grid {
    let (width, height) = (rng.gen_range(sides.clone()), rng.gen_range(sides));
    let density = rng.gen_range(0.20..=0.45);
    let free = (0..width * height)
        .map(|_| !rng.gen_bool(density))
        .collect();
    Grid::from_free_cells(width, height, free).unwrap()
}

/// Tallies of one property run.
#[derive(Debug, Default)]
struct Tally {
    grids: u64,
    literal: u64,
    pruned: u64,
    no_path: u64,
    weighted_longer: u64,
    fewer_turns_than_astar: u64,
}

/// Runs the property on random grids until `n_with_path` of them have a path (grids
/// without one are checked and counted too).
fn property(
    connectivity: Connectivity,
    n_with_path: u64,
    sides: std::ops::RangeInclusive<u32>,
    seed: u64,
) -> Tally {
    let set = MoveSet::standard(connectivity);
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let lexicographic = Config {
        moves: connectivity,
        ..Config::default()
    };
    let mut lex = LexAStar::new(lexicographic.clone()).unwrap();
    let mut undominated = LexAStar::new(Config {
        dominance: false,
        ..lexicographic.clone()
    })
    .unwrap();
    let mut weighted: Vec<LexAStar> = LAMBDAS
        .iter()
        .map(|&(q, p)| {
            LexAStar::new(Config {
                objective: Objective::Weighted,
                lambda: p as f64 / q as f64,
                ..lexicographic.clone()
            })
            .unwrap()
        })
        .collect();
    let mut astar = planner_astar::AStar::new(planner_astar::Config {
        moves: connectivity,
        ..planner_astar::Config::default()
    })
    .unwrap();
    let mut tally = Tally::default();
    while tally.literal + tally.pruned < n_with_path {
        let grid = random_grid(&mut rng, sides.clone());
        let free: Vec<Cell> = grid.cells().filter(|&c| grid.is_free(c)).collect();
        if free.is_empty() {
            continue;
        }
        let start = free[rng.gen_range(0..free.len())];
        let goal = free[rng.gen_range(0..free.len())];
        tally.grids += 1;
        let problem = Problem::new(&grid, start, goal).unwrap();
        let what = format!("{connectivity} {start} -> {goal}\n{grid:?}");
        let search = lex.search(&problem, &Budget::unlimited());
        let distance = distances_to(&grid, &set, goal);
        let adjacency = neighbours(&grid, &set);
        let shortest = distance[grid.index(start)];

        if shortest == u64::MAX {
            tally.no_path += 1;
            assert_eq!(search.status, Status::NoPath, "{what}");
            let plain = undominated.search(&problem, &Budget::unlimited());
            assert_eq!(plain.status, Status::NoPath, "no dominance: {what}");
            if let Some(best) = enumerate(&grid, &adjacency, start, goal, CALL_CAP, None) {
                assert_eq!(best.n_solutions, 0, "{what}");
            }
            continue;
        }
        assert_eq!(search.status, Status::Found, "{what}");
        let path = search.path.unwrap();
        assert_eq!(
            path.validate(&grid, PathRule::Moves(&set)),
            Ok(()),
            "{what}"
        );
        assert_eq!((path.start(), path.goal()), (Some(start), Some(goal)));
        let rank = path.rank();
        let plain = undominated.search(&problem, &Budget::unlimited());
        assert_eq!(
            plain.path.map(|p| p.rank()),
            Some(rank),
            "no dominance: {what}"
        );

        match enumerate(&grid, &adjacency, start, goal, CALL_CAP, None) {
            Some(best) => {
                tally.literal += 1;
                assert_eq!(Some(rank), best.rank, "{what}");
                for (k, planner) in weighted.iter_mut().enumerate() {
                    let (q, p) = LAMBDAS[k];
                    let found = planner.search(&problem, &Budget::unlimited());
                    let m = found.path.unwrap().metrics();
                    assert_eq!(
                        Some(q * m.steps + p * m.turns),
                        best.weighted[k],
                        "lambda {p}/{q} {what}"
                    );
                    if m.steps > rank.steps {
                        tally.weighted_longer += 1;
                    }
                }
            }
            None => {
                tally.pruned += 1;
                let best = enumerate(
                    &grid,
                    &adjacency,
                    start,
                    goal,
                    u64::MAX,
                    Some((&distance, shortest)),
                );
                assert_eq!(Some(rank), best.and_then(|b| b.rank), "{what}");
            }
        }
        let astar_rank = astar
            .search(&problem, &Budget::unlimited())
            .path
            .unwrap()
            .rank();
        // 8-connected A* minimises Euclidean length, not the number of moves.
        if connectivity == Connectivity::Four {
            assert_eq!(astar_rank.steps, rank.steps, "{what}");
        }
        if rank.steps == astar_rank.steps && rank.turns < astar_rank.turns {
            tally.fewer_turns_than_astar += 1;
        }
    }
    tally
}

#[test]
fn four_connected_matches_exhaustive_enumeration_on_10000_grids_with_a_path() {
    let tally = property(Connectivity::Four, 10_000, 5..=8, 2026);
    println!("4-connected: {tally:?}");
    assert_eq!(tally.literal + tally.pruned, 10_000);
    assert_eq!(tally.grids, tally.literal + tally.pruned + tally.no_path);
    // The literal enumeration completes on most grids, and the weighted objective with a
    // large lambda does trade steps for turns somewhere.
    assert!(tally.literal > tally.pruned, "{tally:?}");
    assert!(tally.weighted_longer > 0, "{tally:?}");
    assert!(tally.fewer_turns_than_astar > 0, "{tally:?}");
}

#[test]
fn eight_connected_matches_exhaustive_enumeration() {
    let tally = property(Connectivity::Eight, 1_000, 5..=7, 8);
    println!("8-connected: {tally:?}");
    assert_eq!(tally.literal + tally.pruned, 1_000);
    assert_eq!(tally.grids, tally.literal + tally.pruned + tally.no_path);
}
