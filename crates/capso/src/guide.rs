//! The guide: a coarse path from start to goal through free blocks that seeds part of the
//! swarm with control points on a nearly free route (issue 34; Lian et al.'s own
//! initialisation is not in the stored copies of their paper, see the crate docs).
//!
//! 1. The grid is covered by square blocks of `b` cells, `b = ceil(max(W, H) / 64)` (at
//!    most 64 x 64 blocks: 3 on seed 002's 140 x 120 maps, 4 on 200 x 200, 8 on 500 x 500).
//!    Cell `(x, y)` is in block `(x / b, y / b)`, whose index is `(y / b) ceil(W / b) +
//!    x / b` (row-major); the last column and row of blocks may stick out of the grid,
//!    and only their cells inside it count. A block is free when all its cells are; the
//!    blocks of the start and the goal count as free (at every level, blocked cells and
//!    all; only the goal's changes a result: the start's block is where the search
//!    starts, and a diagonal step beside it never gives a block a lower `g` than the
//!    straight step from it).
//! 2. A* over the blocks, 8-connected without corner cutting (a diagonal step needs both
//!    side blocks free), step costs 5 and 7 (1 and 1.4, near the Euclidean 1 and sqrt 2)
//!    and the matching octile heuristic `7 min(dx, dy) + 5 (max(dx, dy) - min(dx, dy))`
//!    in blocks, which is consistent; OPEN gives the least `(f, index)`, so ties go to the
//!    lower block index and the route is a pure function of the grid. A block's `g` and
//!    parent change only when a step gives it a strictly lower `g`. A block is *expanded*
//!    when it leaves OPEN for the first time (the start's first, the goal's last: the
//!    search stops there); older OPEN entries of an improved block are skipped uncounted,
//!    and no block is expanded twice (the heuristic is consistent). [`Guide::n_expanded`]
//!    sums the expansions of every level tried, those that found no route included.
//! 3. When no route exists at block size `b`, `b` is halved, rounding down (5, 2, 1), down
//!    to 1 (the cells themselves). At `b = 1` no route means the goal is unreachable by
//!    any any-angle path either (a valid any-angle path's cells form an 8-connected chain
//!    of free cells in which every diagonal step has a free side cell, because the segment
//!    walk visits a side cell at every change of row and column), so the planner stops
//!    with `no_path`.
//! 4. The route is the start, the centre cells of the inner blocks (those on the parent
//!    chain strictly between the start's block and the goal's), and the goal; the start
//!    alone when it is the goal. A block's centre cell is that of its part inside the
//!    grid, rounded down: `x0 + (min(b, W - x0) - 1) / 2` for the block's first column
//!    `x0`, and the same in y. The route is shortened greedily by line of sight on the
//!    cells ([`BitGrid::segment_is_free`], the cells of `planner_api::segment_is_free`):
//!    from an anchor (first the start), the waypoint after it is kept without a check,
//!    then replaced by the next one as long as the anchor sees that one, stopping at the
//!    first it does not see (not the farthest waypoint it sees overall); the kept
//!    waypoint is the next anchor. This leaves the route's corners. The route's pieces
//!    between inner block centres are free, but at `b > 1` its first piece (from the
//!    start) and its last (to the goal), which the shortening may keep unchecked, can
//!    cross blocked cells of the start's or the goal's block (they count as free), so the
//!    polyline is not always collision-free.
//! 5. [`control_points`] puts `n` control points on that polyline: its corners when there
//!    are at most `n` of them, the others splitting the longest pieces in half; with more
//!    than `n` corners, `n` points at equal arc-length steps.
//!
//! `planner_testkit::reference_capso_guide` is these rules written again (an ordered set
//! with decrease-key as OPEN, the blocks' cells tested one by one); the tests hold
//! [`Guide::find`] and CAPSO's `n_guide_expanded` and `guide_block` to it.

use std::cmp::Reverse;
use std::collections::BinaryHeap;

use planner_api::{BudgetClock, Cell};

use crate::collision::BitGrid;

/// At most this many blocks along the grid's longer side at the first attempt.
pub const MAX_BLOCKS_PER_SIDE: u32 = 64;

/// Bytes per block of the search's state (g, parent, closed flag) at the finest level,
/// for the budget's memory check.
pub const BYTES_PER_BLOCK: u64 = 9;

/// What [`Guide::find`] found.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Route {
    /// A route: [`Guide::polyline`] holds it.
    Found,
    /// No route even over single cells: the goal is unreachable.
    Unreachable,
    /// The budget's deadline passed or its cancel flag was raised first.
    Stopped,
}

/// Scratch of the guide's search, reused between plans.
#[derive(Debug, Clone, Default)]
pub struct Guide {
    free: Vec<bool>,
    g: Vec<u32>,
    parent: Vec<u32>,
    closed: Vec<bool>,
    heap: BinaryHeap<Reverse<(u32, u32)>>,
    route: Vec<Cell>,
    /// The shortened polyline of the last successful [`Guide::find`].
    pub polyline: Vec<Cell>,
    /// Blocks expanded by the searches of the last [`Guide::find`] (all levels).
    pub n_expanded: u64,
    /// The block size of the level that found the route (0 when none did).
    pub block: u32,
}

impl Guide {
    /// Finds the guide polyline from `start` to `goal` into [`Guide::polyline`] (module
    /// docs). [`Route::Unreachable`] when there is none, which means the goal is
    /// unreachable; [`Route::Stopped`] when `clock` (the plan's budget: its deadline and
    /// cancel flag, not its expansions, which count fitness evaluations) ran out first.
    pub fn find(
        &mut self,
        grid: &BitGrid,
        start: Cell,
        goal: Cell,
        clock: &mut BudgetClock,
    ) -> Route {
        self.n_expanded = 0;
        self.block = 0;
        self.polyline.clear();
        let longest = grid.width().max(grid.height());
        let mut block = longest.div_ceil(MAX_BLOCKS_PER_SIDE).max(1);
        loop {
            match self.search(grid, start, goal, block, clock) {
                Route::Found => {
                    self.block = block;
                    self.shorten(grid);
                    return Route::Found;
                }
                Route::Stopped => return Route::Stopped,
                Route::Unreachable if block == 1 => return Route::Unreachable,
                Route::Unreachable => block /= 2,
            }
        }
    }

    /// A* over blocks of `b` cells; when found, the route's cells are in `self.route`.
    fn search(
        &mut self,
        grid: &BitGrid,
        start: Cell,
        goal: Cell,
        b: u32,
        clock: &mut BudgetClock,
    ) -> Route {
        let (bw, bh) = (grid.width().div_ceil(b), grid.height().div_ceil(b));
        let n = bw as usize * bh as usize;
        // A block is free when the summed-area table counts no blocked cell in it (one
        // query a block rather than a test a cell).
        self.free.clear();
        for by in 0..bh {
            let (y0, y1) = (by * b, ((by + 1) * b).min(grid.height()) - 1);
            for bx in 0..bw {
                let (x0, x1) = (bx * b, ((bx + 1) * b).min(grid.width()) - 1);
                self.free.push(grid.blocked_in(x0, x1, y0, y1) == 0);
            }
        }
        let block_of = |c: Cell| (c.y / b) * bw + c.x / b;
        let (s, t) = (block_of(start), block_of(goal));
        self.free[s as usize] = true;
        self.free[t as usize] = true;
        self.g.clear();
        self.g.resize(n, u32::MAX);
        self.parent.clear();
        self.parent.resize(n, u32::MAX);
        self.closed.clear();
        self.closed.resize(n, false);
        self.heap.clear();
        let (tx, ty) = (t % bw, t / bw);
        let h = |i: u32| {
            let (dx, dy) = ((i % bw).abs_diff(tx), (i / bw).abs_diff(ty));
            7 * dx.min(dy) + 5 * dx.abs_diff(dy)
        };
        self.g[s as usize] = 0;
        self.heap.push(Reverse((h(s), s)));
        let mut found = false;
        while let Some(Reverse((_, i))) = self.heap.pop() {
            if self.closed[i as usize] {
                continue;
            }
            if !clock.allows_uncounted() {
                return Route::Stopped;
            }
            self.closed[i as usize] = true;
            self.n_expanded += 1;
            if i == t {
                found = true;
                break;
            }
            let (x, y) = (i % bw, i / bw);
            let free = |x: i64, y: i64| {
                x >= 0
                    && y >= 0
                    && x < i64::from(bw)
                    && y < i64::from(bh)
                    && self.free[y as usize * bw as usize + x as usize]
            };
            for (dx, dy) in [
                (1i64, 0i64),
                (-1, 0),
                (0, 1),
                (0, -1),
                (1, 1),
                (1, -1),
                (-1, 1),
                (-1, -1),
            ] {
                let (nx, ny) = (i64::from(x) + dx, i64::from(y) + dy);
                if !free(nx, ny) {
                    continue;
                }
                let diagonal = dx != 0 && dy != 0;
                if diagonal
                    && !(free(i64::from(x) + dx, i64::from(y))
                        && free(i64::from(x), i64::from(y) + dy))
                {
                    continue;
                }
                // Inside the block grid, so the casts are exact.
                let j = ny as u32 * bw + nx as u32;
                let g = self.g[i as usize] + if diagonal { 7 } else { 5 };
                if g < self.g[j as usize] {
                    self.g[j as usize] = g;
                    self.parent[j as usize] = i;
                    self.heap.push(Reverse((g + h(j), j)));
                }
            }
        }
        if !found {
            return Route::Unreachable;
        }
        // The route backwards: goal, inner block centres, start.
        self.route.clear();
        self.route.push(goal);
        let mut i = self.parent[t as usize];
        while i != u32::MAX && i != s {
            let (x0, y0) = ((i % bw) * b, (i / bw) * b);
            // The centre of the block's part inside the grid (a free block's cells are all free).
            let cx = x0 + (b.min(grid.width() - x0) - 1) / 2;
            let cy = y0 + (b.min(grid.height() - y0) - 1) / 2;
            self.route.push(Cell::new(cx, cy));
            i = self.parent[i as usize];
        }
        if start != goal {
            self.route.push(start);
        }
        self.route.reverse();
        Route::Found
    }

    /// Greedy line-of-sight shortening of `self.route` into `self.polyline`.
    fn shorten(&mut self, grid: &BitGrid) {
        let route = &self.route;
        self.polyline.clear();
        let Some(&first) = route.first() else {
            return;
        };
        self.polyline.push(first);
        let mut anchor = 0;
        let mut next = 1;
        while next < route.len() {
            // Advance while the anchor sees the waypoint after `next`.
            while next + 1 < route.len() && grid.segment_is_free(route[anchor], route[next + 1]) {
                next += 1;
            }
            self.polyline.push(route[next]);
            anchor = next;
            next += 1;
        }
    }
}

/// `n` control points (`x_0, y_0, x_1, y_1, ...`) on the polyline `line`, appended to
/// `out` (module docs, step 5). `line` has at least two points.
pub fn control_points(line: &[Cell], n: usize, out: &mut Vec<f64>) {
    let point = |c: Cell| (f64::from(c.x), f64::from(c.y));
    let corners = line.len().saturating_sub(2);
    if corners <= n {
        // Corners, then split the longest piece until there are n inner points.
        let mut points: Vec<(f64, f64)> = line.iter().map(|&c| point(c)).collect();
        while points.len() < n + 2 {
            let (mut longest, mut at) = (-1.0, 0);
            for (k, pair) in points.windows(2).enumerate() {
                let d = (pair[1].0 - pair[0].0).hypot(pair[1].1 - pair[0].1);
                if d > longest {
                    (longest, at) = (d, k);
                }
            }
            let (a, b) = (points[at], points[at + 1]);
            points.insert(at + 1, ((a.0 + b.0) / 2.0, (a.1 + b.1) / 2.0));
        }
        for &(x, y) in &points[1..=n] {
            out.push(x);
            out.push(y);
        }
        return;
    }
    let length: f64 = line.windows(2).map(|p| p[0].euclidean(p[1])).sum();
    let mut piece = 0;
    let mut before = 0.0;
    for k in 1..=n {
        let target = length * k as f64 / (n + 1) as f64;
        while piece + 2 < line.len() && before + line[piece].euclidean(line[piece + 1]) < target {
            before += line[piece].euclidean(line[piece + 1]);
            piece += 1;
        }
        let (a, b) = (point(line[piece]), point(line[piece + 1]));
        let d = line[piece].euclidean(line[piece + 1]);
        let f = if d > 0.0 {
            ((target - before) / d).clamp(0.0, 1.0)
        } else {
            0.0
        };
        out.push(a.0 + f * (b.0 - a.0));
        out.push(a.1 + f * (b.1 - a.1));
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use planner_api::Grid;

    fn bits(grid: &Grid) -> BitGrid {
        let mut b = BitGrid::new();
        b.load(grid);
        b
    }

    #[test]
    fn a_wall_with_a_gap_is_passed_through_the_gap() {
        // 20 x 10, a wall in column 10 except row 8.
        let mut grid = Grid::new(20, 10).unwrap();
        for y in 0..10 {
            if y != 8 {
                grid.set_free(Cell::new(10, y), false);
            }
        }
        let mut guide = Guide::default();
        let mut clock = planner_api::Budget::unlimited().start();
        let (from, to) = (Cell::new(1, 1), Cell::new(18, 1));
        assert_eq!(guide.find(&bits(&grid), from, to, &mut clock), Route::Found);
        let line = &guide.polyline;
        assert_eq!(line.first(), Some(&Cell::new(1, 1)));
        assert_eq!(line.last(), Some(&Cell::new(18, 1)));
        // Every piece of the shortened line is free, and it goes through the gap's row.
        let b = bits(&grid);
        assert!(line.windows(2).all(|p| b.segment_is_free(p[0], p[1])));
        assert!(line.iter().any(|c| c.y >= 7), "{line:?}");
        // Unreachable: close the gap.
        grid.set_free(Cell::new(10, 8), false);
        let unreachable = guide.find(&bits(&grid), from, to, &mut clock);
        assert_eq!(unreachable, Route::Unreachable);
        assert_eq!(guide.block, 0);
        // The expansion limit does not apply (fitness evaluations are the expansions); a
        // raised cancel flag stops the search at the clock's first look.
        let mut counted = planner_api::Budget::expansions(0).start();
        let unreachable = guide.find(&bits(&grid), from, to, &mut counted);
        assert_eq!(unreachable, Route::Unreachable);
        // 100 x 100 cut by a wall: thousands of cells searched before "unreachable".
        let mut walled = Grid::new(100, 100).unwrap();
        for y in 0..100 {
            walled.set_free(Cell::new(50, y), false);
        }
        let (from, to) = (Cell::new(1, 1), Cell::new(98, 98));
        let unreachable = guide.find(&bits(&walled), from, to, &mut clock);
        assert_eq!(unreachable, Route::Unreachable);
        assert!(guide.n_expanded > 4_000, "{}", guide.n_expanded);
        let flag = planner_api::CancelFlag::new();
        flag.cancel();
        let mut cancelled = planner_api::Budget::unlimited().with_cancel(flag).start();
        let stopped = guide.find(&bits(&walled), from, to, &mut cancelled);
        assert_eq!(stopped, Route::Stopped);
        let interval = u64::from(planner_api::BudgetClock::TIME_CHECK_INTERVAL);
        assert_eq!(guide.n_expanded, interval - 1);
    }

    #[test]
    fn control_points_by_hand() {
        let c = |x, y| Cell::new(x, y);
        let mut out = Vec::new();
        // One corner, three points: the corner and the midpoints of the two pieces
        // (the longer first: (0,0)-(0,8) is 8, (0,8)-(4,8) is 4; then (0,0)-(0,4) is 4 and
        // (0,4)-(0,8) is 4, tied, and (0,8)-(4,8) is 4: the first of the longest splits).
        control_points(&[c(0, 0), c(0, 8), c(4, 8)], 3, &mut out);
        assert_eq!(out, [0.0, 2.0, 0.0, 4.0, 0.0, 8.0]);
        // No corner and two points: thirds of the segment... by halving: the middle, then
        // the first half's middle.
        out.clear();
        control_points(&[c(0, 0), c(8, 0)], 2, &mut out);
        assert_eq!(out, [2.0, 0.0, 4.0, 0.0]);
        // Three corners, one point: equal arc length, the middle of the length 4+4+4+4.
        out.clear();
        control_points(&[c(0, 0), c(4, 0), c(4, 4), c(8, 4), c(8, 8)], 1, &mut out);
        assert_eq!(out, [4.0, 4.0]);
    }
}
