//! The live backtracking points, indexed for the nearest-point scan of a return (crate
//! docs, "Nearest" and "Run time").
//!
//! A point is live from its marking until its 4-neighbourhood is covered; it is dropped
//! then, by the cover that closes it ([`Points::drop_closed_around`]), which is when the
//! seed's list would drop it at the next return (a covered neighbourhood never reopens).
//! Each live point keeps its marking order (the `k`-th marking has order `k`, from 1),
//! which breaks ties towards the point marked last.
//!
//! The index is a count pyramid over the grid: level 0 counts the live points of blocks
//! of 8 x 8 cells, level `k` those of blocks of `8 * 2^k` cells a side, up to one block
//! covering the grid. [`Points::next`] takes the points in increasing order of
//! [`Distance::bound`] from the robot's cell, ties by the point marked last, exactly the
//! order of the seed's sorted candidate list, by a best-first walk down the pyramid: a
//! block's key is the bound to its nearest cell (the octile distance grows with each of
//! `dx` and `dy`, so no point inside is nearer), a block comes before a point with an
//! equal key, and empty blocks are never entered. A scan that stops at distance `D`
//! touches the blocks reaching within `D` of the robot, `O(D)` of them on the boundary
//! plus `O(log)` per point taken, where sorting every point cost `O(P log P)` a return.
//!
//! Memory: a `u32` order per cell (0: no live point there), a `u8` count per 8 x 8 block
//! and a `u32` count per block above: at most 5 bytes a cell (4.04 on a 1000 x 1000
//! grid, 4.63 on a long one-cell-wide strip), the heap of a scan apart.

use std::cmp::Reverse;
use std::collections::BinaryHeap;

use planner_api::{Cell, Grid};

use crate::fill::Field;
use crate::Distance;

/// log2 of a level-0 block's side in cells.
const LEAF_SHIFT: u32 = 3;

/// A block of the pyramid or a point, keyed for the best-first scan: by bound, blocks
/// before points, then the point marked last first (`later`), then the rest for a total
/// order.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
struct Entry {
    bound: Distance,
    point: bool,
    later: Reverse<u32>,
    level: u32,
    index: usize,
}

/// The live points and their index.
#[derive(Debug, Clone, Default)]
pub(crate) struct Points {
    width: usize,
    height: usize,
    /// Per cell: the marking order of the live point there, 0 for none.
    order: Vec<u32>,
    /// Per level-0 block (row-major, [`Points::cols`] of them a row): live points.
    leaves: Vec<u8>,
    /// Levels 1.. : per block, row-major, live points.
    counts: Vec<Vec<u32>>,
    /// Live points in all.
    live: usize,
    /// The scan's frontier ([`Points::begin`], [`Points::next`]).
    heap: BinaryHeap<Reverse<Entry>>,
}

impl Points {
    /// Blocks a row at `level`.
    fn cols(&self, level: u32) -> usize {
        self.width.div_ceil(1 << (LEAF_SHIFT + level))
    }

    /// Block rows at `level`.
    fn rows(&self, level: u32) -> usize {
        self.height.div_ceil(1 << (LEAF_SHIFT + level))
    }

    /// The top level: one block covers the grid.
    fn top(&self) -> u32 {
        self.counts.len() as u32
    }

    /// No live point, for a `width` x `height` grid; reuses the allocations.
    pub fn reset(&mut self, width: usize, height: usize) {
        self.width = width;
        self.height = height;
        self.order.clear();
        self.order.resize(width * height, 0);
        self.leaves.clear();
        self.leaves.resize(self.cols(0) * self.rows(0), 0);
        let mut level = 1;
        let mut used = 0;
        while self.cols(level - 1) > 1 || self.rows(level - 1) > 1 {
            let len = self.cols(level) * self.rows(level);
            match self.counts.get_mut(used) {
                Some(counts) => {
                    counts.clear();
                    counts.resize(len, 0);
                }
                None => self.counts.push(vec![0; len]),
            }
            used += 1;
            level += 1;
        }
        self.counts.truncate(used);
        self.live = 0;
        self.heap.clear();
    }

    /// Whether no point is live.
    pub fn is_empty(&self) -> bool {
        self.live == 0
    }

    /// Whether a live point is at `cell`.
    pub fn contains(&self, cell: usize) -> bool {
        self.order[cell] != 0
    }

    /// The index of the block holding cell `(x, y)` at `level`.
    fn block(&self, level: u32, x: usize, y: usize) -> usize {
        let shift = LEAF_SHIFT + level;
        (y >> shift) * self.cols(level) + (x >> shift)
    }

    /// Adds one to (`add`) or takes one from the counts of every block holding `cell`.
    fn count(&mut self, cell: usize, add: bool) {
        let (x, y) = (cell % self.width, cell / self.width);
        let leaf = self.block(0, x, y);
        let step = |n: &mut u32| *n = if add { *n + 1 } else { *n - 1 };
        let mut n = u32::from(self.leaves[leaf]);
        step(&mut n);
        self.leaves[leaf] = n as u8;
        for level in 1..=self.top() {
            let block = self.block(level, x, y);
            step(&mut self.counts[level as usize - 1][block]);
        }
    }

    /// Makes `cell` a live point with marking order `order` (at least 1).
    pub fn insert(&mut self, cell: usize, order: u32) {
        debug_assert!(order != 0 && self.order[cell] == 0);
        self.order[cell] = order;
        self.count(cell, true);
        self.live += 1;
    }

    /// Drops the live points beside `cell` (just covered) whose 4-neighbourhood is now
    /// covered: at most four checks per covered cell.
    pub fn drop_closed_around(&mut self, field: &Field<'_>, cell: usize) {
        for h in 0..4 {
            if let Some(q) = field.step(cell, h) {
                if self.order[q] != 0 && !field.any_open(q) {
                    self.order[q] = 0;
                    self.count(q, false);
                    self.live -= 1;
                }
            }
        }
    }

    /// Live points in the block `index` of `level` (level 0 included).
    fn live_in(&self, level: u32, index: usize) -> u32 {
        match level {
            0 => u32::from(self.leaves[index]),
            _ => self.counts[level as usize - 1][index],
        }
    }

    /// The cells of block `index` at `level`, clipped to the grid: `(x0, y0, x1, y1)`,
    /// bounds included.
    fn extent(&self, level: u32, index: usize) -> (usize, usize, usize, usize) {
        let shift = LEAF_SHIFT + level;
        let cols = self.cols(level);
        let (x0, y0) = ((index % cols) << shift, (index / cols) << shift);
        let side = 1 << shift;
        (
            x0,
            y0,
            (x0 + side).min(self.width) - 1,
            (y0 + side).min(self.height) - 1,
        )
    }

    /// Queues block `index` of `level` when it holds a live point, keyed by the bound
    /// from `from` to its nearest cell.
    fn push_block(&mut self, grid: &Grid, from: Cell, level: u32, index: usize) {
        if self.live_in(level, index) == 0 {
            return;
        }
        let (x0, y0, x1, y1) = self.extent(level, index);
        let near = Cell::new(
            (from.x as usize).clamp(x0, x1) as u32,
            (from.y as usize).clamp(y0, y1) as u32,
        );
        self.heap.push(Reverse(Entry {
            bound: Distance::bound(grid, from, near),
            point: false,
            later: Reverse(0),
            level,
            index,
        }));
    }

    /// Starts a scan from `from`: [`Points::next`] then gives the live points nearest
    /// first. The points must not change during the scan.
    pub fn begin(&mut self, grid: &Grid, from: Cell) {
        self.heap.clear();
        self.push_block(grid, from, self.top(), 0);
    }

    /// The next live point of the scan from `from` ([`Points::begin`]): its bound
    /// ([`Distance::bound`]), marking order and cell; `None` when every point was given.
    /// Points come by increasing bound, ties by decreasing marking order.
    pub fn next(&mut self, grid: &Grid, from: Cell) -> Option<(Distance, u32, usize)> {
        while let Some(Reverse(entry)) = self.heap.pop() {
            if entry.point {
                return Some((entry.bound, entry.later.0, entry.index));
            }
            if entry.level == 0 {
                let (x0, y0, x1, y1) = self.extent(0, entry.index);
                for y in y0..=y1 {
                    for x in x0..=x1 {
                        let cell = y * self.width + x;
                        let order = self.order[cell];
                        if order != 0 {
                            let at = Cell::new(x as u32, y as u32);
                            self.heap.push(Reverse(Entry {
                                bound: Distance::bound(grid, from, at),
                                point: true,
                                later: Reverse(order),
                                level: 0,
                                index: cell,
                            }));
                        }
                    }
                }
                continue;
            }
            // The four blocks of the level below, those inside the grid.
            let level = entry.level - 1;
            let (cols, rows) = (self.cols(level), self.rows(level));
            let (cx, cy) = (
                (entry.index % self.cols(entry.level)) * 2,
                (entry.index / self.cols(entry.level)) * 2,
            );
            for (x, y) in [(cx, cy), (cx + 1, cy), (cx, cy + 1), (cx + 1, cy + 1)] {
                if x < cols && y < rows {
                    self.push_block(grid, from, level, y * cols + x);
                }
            }
        }
        None
    }
}
