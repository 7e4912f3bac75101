//! Test and bench support: a tiny reader for maps/wpi, a linear-scan nearest-neighbour
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

/// Reads `maps/wpi/<name>.txt`: `#` header lines (those with `Start: (x,y) | Goal: (x,y)`
/// give the pairs, x = column, y = row), then rows of `.` free / `X` obstacle; blank
/// lines are skipped. Test-only: panics on a malformed file.
pub fn wpi(name: &'static str) -> WpiMap {
    let path = format!("{}/../../maps/wpi/{name}.txt", env!("CARGO_MANIFEST_DIR"));
    let text = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{path}: {e}"));
    let mut pairs = Vec::new();
    let mut rows: Vec<&str> = Vec::new();
    for line in text.lines().map(str::trim) {
        if let Some(header) = line.strip_prefix('#') {
            if let (Some(s), Some(g)) = (header.find("Start:"), header.find("Goal:")) {
                let start = parse_cell(&header[s + 6..]);
                let goal = parse_cell(&header[g + 5..]);
                pairs.push((pairs.len() + 1, start, goal));
            }
        } else if !line.is_empty() {
            rows.push(line);
        }
    }
    let width = rows[0].len();
    assert!(rows.iter().all(|r| r.len() == width), "{path}: ragged rows");
    let free = rows
        .iter()
        .flat_map(|r| r.chars())
        .map(|c| match c {
            '.' => true,
            'X' => false,
            other => panic!("{path}: unexpected {other:?}"),
        })
        .collect();
    let grid = Grid::from_free_cells(width as u32, rows.len() as u32, free).unwrap();
    WpiMap { name, grid, pairs }
}

/// `(x,y)` at the start of `text` (after optional spaces).
fn parse_cell(text: &str) -> Cell {
    let text = text.trim_start();
    let inner = &text[1..text.find(')').unwrap()];
    let (x, y) = inner.split_once(',').unwrap();
    Cell::new(x.trim().parse().unwrap(), y.trim().parse().unwrap())
}

/// Reads `maps/movingai/<name>`: the four header lines, then rows where `.`, `G` and
/// `S` are free and anything else (`@`, `O`, `T`, `W`) is blocked. Test-only.
pub fn movingai(name: &str) -> Grid {
    let path = format!("{}/../../maps/movingai/{name}", env!("CARGO_MANIFEST_DIR"));
    let text = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{path}: {e}"));
    let rows: Vec<&str> = text
        .lines()
        .skip(4)
        .map(str::trim_end)
        .filter(|r| !r.is_empty())
        .collect();
    let free = rows
        .iter()
        .flat_map(|r| r.chars())
        .map(|c| matches!(c, '.' | 'G' | 'S'))
        .collect();
    Grid::from_free_cells(rows[0].len() as u32, rows.len() as u32, free).unwrap()
}

/// The linear scan that seed 003's RRT does: every node, least squared distance, ties to
/// the smallest id.
#[derive(Debug, Default, Clone)]
pub struct LinearScan {
    cells: Vec<Cell>,
}

impl NearestIndex for LinearScan {
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
