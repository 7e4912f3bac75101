//! Test and bench support: maps/wpi through planner-testkit, a linear-scan nearest-neighbour
//! index, and an independent BFS. Shared by `tests/` and `benches/` (`#[path]`).
#![allow(dead_code)]

use std::collections::VecDeque;

use planner_api::{Cell, Grid};
use planner_rrt::{squared_distance, NearestIndex};

/// One map of maps/wpi with its start-goal pairs, numbered from 1 in file order.
pub struct WpiMap {
    pub name: &'static str,
    pub grid: Grid,
    pub pairs: Vec<(usize, Cell, Cell)>,
}

/// `maps/wpi/<name>.txt` with its pairs numbered from 1 in file order.
pub fn wpi(name: &'static str) -> WpiMap {
    let (grid, pairs) = planner_testkit::wpi(&format!("wpi/{name}.txt"));
    let pairs = pairs
        .into_iter()
        .enumerate()
        .map(|(i, (start, goal))| (i + 1, start, goal))
        .collect();
    WpiMap { name, grid, pairs }
}

/// `maps/movingai/<name>`.
pub fn movingai(name: &str) -> Grid {
    planner_testkit::movingai(&format!("movingai/{name}"))
}

/// The linear scan that seed 003's RRT does: every node, least squared distance, ties to
/// the smallest id.
#[derive(Debug, Default, Clone)]
pub struct LinearScan {
    cells: Vec<Cell>,
}

impl NearestIndex for LinearScan {
    fn bytes_for(&self, _width: u32, _height: u32, nodes: u64) -> u64 {
        8 * nodes
    }

    fn clear(&mut self, _width: u32, _height: u32) {
        self.cells.clear();
    }

    fn insert(&mut self, cell: Cell) {
        self.cells.push(cell);
    }

    fn nearest(&self, query: Cell) -> Option<u32> {
        let mut best: Option<(u64, u32)> = None;
        for (id, &cell) in self.cells.iter().enumerate() {
            let d2 = squared_distance(query, cell);
            if best.is_none_or(|(b, _)| d2 < b) {
                best = Some((d2, id as u32));
            }
        }
        best.map(|(_, id)| id)
    }

    fn within(&self, query: Cell, max_squared: u64, out: &mut Vec<u32>) {
        for (id, &cell) in self.cells.iter().enumerate() {
            if squared_distance(query, cell) <= max_squared {
                out.push(id as u32);
            }
        }
    }

    fn len(&self) -> usize {
        self.cells.len()
    }
}

/// 4-connected BFS: the number of moves of a shortest path, or `None` when unreachable.
pub fn bfs_steps(grid: &Grid, start: Cell, goal: Cell) -> Option<u64> {
    let mut dist = vec![u64::MAX; grid.len()];
    let mut queue = VecDeque::from([start]);
    dist[grid.index(start)] = 0;
    while let Some(cell) = queue.pop_front() {
        let d = dist[grid.index(cell)];
        if cell == goal {
            return Some(d);
        }
        for (dx, dy) in [(1, 0), (-1, 0), (0, 1), (0, -1)] {
            if let Some(next) = grid.offset(cell, dx, dy) {
                if grid.is_free(next) && dist[grid.index(next)] == u64::MAX {
                    dist[grid.index(next)] = d + 1;
                    queue.push_back(next);
                }
            }
        }
    }
    None
}
