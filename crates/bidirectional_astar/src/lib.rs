//! The `bidirectional_astar` planner.
//!
//! Scaffolded by `cargo xtask new-planner bidirectional_astar` as a greedy best-first search (pop the
//! OPEN cell closest to the goal by Manhattan distance; FIFO among ties). Replace the body
//! of `plan` with your algorithm; keep the counters honest (see `planner_api::counters`
//! for what each name means) and document every choice the source paper leaves open.
#![deny(missing_docs)]
#![cfg_attr(not(test), warn(clippy::unwrap_used))]

use std::cmp::Reverse;
use std::collections::BinaryHeap;

use planner_api::{
    Budget, Cell, Connectivity, Counter, IndexedMoves, MoveOrderError, MoveSet, NeighborOrder,
    Outcome, Path, Planner, Problem, SearchStats,
};
use serde::{Deserialize, Serialize};
use thiserror::Error;

/// The registry name.
pub const NAME: &str = "bidirectional_astar";

/// Parameters; every field has a default.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct Config {
    /// Neighbourhood: 4, 8, 16, 32 or 48 directions. Default 4.
    pub moves: Connectivity,
    /// Neighbour order, e.g. `"R L D U"`. Default `"R L D U"`.
    pub order: NeighborOrder,
}

impl Default for Config {
    fn default() -> Config {
        Config {
            moves: Connectivity::Four,
            order: NeighborOrder::default(),
        }
    }
}

/// A parameter the planner cannot run with.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum ConfigError {
    /// `moves` and `order` do not fit together.
    #[error("parameter `order`: {0}")]
    Moves(#[from] MoveOrderError),
}

/// The planner.
#[derive(Debug, Clone)]
pub struct BidirectionalAstar {
    moves: MoveSet,
}

impl BidirectionalAstar {
    /// A planner with `config`, validated.
    pub fn new(config: Config) -> Result<BidirectionalAstar, ConfigError> {
        Ok(BidirectionalAstar {
            moves: MoveSet::new(config.moves, false, &config.order)?,
        })
    }
}

impl Planner for BidirectionalAstar {
    fn name(&self) -> &str {
        NAME
    }

    fn plan(&mut self, problem: &Problem<'_>, budget: &Budget) -> Outcome {
        let grid = problem.grid();
        let goal = problem.goal();
        let moves = IndexedMoves::new(&self.moves, grid);
        let mut parent: Vec<Option<usize>> = vec![None; grid.len()];
        let mut seen = vec![false; grid.len()];
        let mut open = BinaryHeap::new();
        let mut stats = SearchStats::default();
        let mut clock = budget.start();
        let start = grid.index(problem.start());
        seen[start] = true;
        open.push(Reverse((problem.start().manhattan(goal), 0u64, start)));
        stats.n_open_insertions = 1;
        let mut n_pushed = 1u64;
        while let Some(Reverse((_, _, node))) = open.pop() {
            if !clock.allows(stats.n_expanded) {
                return Outcome::budget_exhausted(None, stats.report(Counter::ASTAR));
            }
            stats.n_expanded += 1;
            if node == grid.index(goal) {
                let mut cells = vec![grid.cell(node)];
                let mut at = node;
                while let Some(previous) = parent[at] {
                    cells.push(grid.cell(previous));
                    at = previous;
                }
                cells.reverse();
                return Outcome::found(Path::new(cells), stats.report(Counter::ASTAR));
            }
            let Cell { x, y } = grid.cell(node);
            for k in 0..moves.len() {
                stats.n_neighbor_checks += 1;
                let Some(next) = moves.target(grid.free_cells(), x, y, node, k) else {
                    stats.n_blocked += 1;
                    continue;
                };
                if seen[next] {
                    stats.n_skipped += 1;
                    continue;
                }
                seen[next] = true;
                parent[next] = Some(node);
                stats.n_relaxations += 1;
                stats.n_open_insertions += 1;
                open.push(Reverse((grid.cell(next).manhattan(goal), n_pushed, next)));
                n_pushed += 1;
                stats.peak_open = stats.peak_open.max(open.len() as u64);
            }
        }
        Outcome::no_path(stats.report(Counter::ASTAR))
    }
}
