//! [`reference_jps`]: planner-jps's three variants written again for clarity.

use std::cmp::Reverse;
use std::collections::BinaryHeap;

use planner_api::{Cell, Cost, Grid, Status};

/// The variants of planner-jps, as its `Variant` names them.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum JpsVariant {
    /// Online JPS: a diagonal walk stops where a component jump finds a jump point.
    Jps,
    /// JPS': the component jumps' jump points are successors and the diagonal walk goes on.
    JpsPrime,
    /// JPS+ with pruned intermediate points: jumps read from per-cell jump distances.
    JpsPlus,
}

/// The counters of [`reference_jps`], in its order; the second is `n_lookups` for
/// [`JpsVariant::JpsPlus`].
pub const JPS_COUNTERS: [&str; 5] = [
    "n_expanded",
    "n_scanned",
    "n_open_insertions",
    "n_relaxations",
    "peak_open",
];

/// What [`reference_jps`] found: status, the jump points of the path from start to goal
/// (both included), and the counters named in [`JPS_COUNTERS`].
pub type JpsSearch = (Status, Option<Vec<Cell>>, [u64; 5]);

/// The eight directions in planner-jps's order: east, west, south, north, then the
/// diagonals `4 + (dx < 0) + 2 (dy < 0)`.
const DX: [i64; 8] = [1, -1, 0, 0, 1, -1, 1, -1];
const DY: [i64; 8] = [0, 0, 1, -1, 1, 1, -1, -1];

fn diagonal(dx: i64, dy: i64) -> usize {
    4 + usize::from(dx < 0) + 2 * usize::from(dy < 0)
}

/// JPS+'s jump table encoding (planner-jps's `plus` module docs): an entry of 127 cells or
/// more is *far* and moves this many cells before the next read.
const FAR: i64 = 127;
const SPAN: i64 = 63;

/// planner-jps's search as its crate docs define it, written for clarity and not speed:
/// jumps walked cell by cell from the rules (no bit rows, no 64-cell blocks), JPS+'s jump
/// distances computed by a memoized walk instead of its table sweeps, exact costs as
/// planner-api's [`Cost`] (the planner counts straight and diagonal moves), and OPEN as
/// std's `BinaryHeap` behind a stack, with the documented order: least `f`; among equal `f`
/// the entries pushed with the `f` of the last entry taken from the heap first, last in
/// first out; then larger `g` to 1/1024, then the cell's row-major position. `f` is the
/// `f64` value `straight + diagonal * sqrt 2` of the exact cost, as the planner keys it. It
/// shares no code with the planner; what it takes from it are the choices its docs name,
/// the order of the directions (east, west, south, north, south-east, south-west,
/// north-east, north-west: the order of the pushes) and, for JPS+, how far entries split
/// a lookup (every 63 cells of a jump of 127 or more). 8-connected without corner cutting,
/// no goal bounding, unlimited budget.
pub fn reference_jps(grid: &Grid, start: Cell, goal: Cell, variant: JpsVariant) -> JpsSearch {
    Reference::new(grid, goal, variant).run(start)
}

struct Reference<'a> {
    grid: &'a Grid,
    width: i64,
    height: i64,
    goal: (i64, i64),
    variant: JpsVariant,
    /// JPS+'s exact jump distances, memoized per cell and direction (`None`: not yet).
    exact: Vec<[Option<i64>; 8]>,
    /// Per cell: 0 unseen, 1 open, 2 closed.
    state: Vec<u8>,
    /// Per cell: the exact cost as straight and diagonal moves.
    g: Vec<(u32, u32)>,
    parent: Vec<usize>,
    incoming: Vec<u8>,
    heap: BinaryHeap<Reverse<(u64, u64)>>,
    front: Vec<(u64, u64)>,
    front_key: u64,
    counters: [u64; 5],
}

impl<'a> Reference<'a> {
    fn new(grid: &'a Grid, goal: Cell, variant: JpsVariant) -> Reference<'a> {
        let n = grid.len();
        Reference {
            grid,
            width: i64::from(grid.width()),
            height: i64::from(grid.height()),
            goal: (i64::from(goal.x), i64::from(goal.y)),
            variant,
            exact: if variant == JpsVariant::JpsPlus {
                vec![[None; 8]; n]
            } else {
                Vec::new()
            },
            state: vec![0; n],
            g: vec![(0, 0); n],
            parent: vec![usize::MAX; n],
            incoming: vec![0; n],
            heap: BinaryHeap::new(),
            front: Vec::new(),
            front_key: u64::MAX,
            counters: [0; 5],
        }
    }

    fn at(&self, x: i64, y: i64) -> usize {
        (y * self.width + x) as usize
    }

    fn free(&self, x: i64, y: i64) -> bool {
        (0..self.width).contains(&x)
            && (0..self.height).contains(&y)
            && self.grid.is_free(Cell::new(x as u32, y as u32))
    }

    /// Whether the move from `(x, y)` in direction `d` is allowed (no corner cutting).
    fn allowed(&self, x: i64, y: i64, d: usize) -> bool {
        let (dx, dy) = (DX[d], DY[d]);
        self.free(x + dx, y + dy) && (d < 4 || (self.free(x + dx, y) && self.free(x, y + dy)))
    }

    /// Whether a straight move in direction `d` onto `(x, y)` has a forced neighbour: a
    /// cell beside it free while the cell beside it one step back is blocked.
    fn forced(&self, x: i64, y: i64, d: usize) -> bool {
        let (dx, dy) = (DX[d], DY[d]);
        let (sx, sy) = (dy.abs(), dx.abs());
        [1, -1].iter().any(|&s| {
            self.free(x + s * sx, y + s * sy) && !self.free(x + s * sx - dx, y + s * sy - dy)
        })
    }

    /// The directions a node keeps for its incoming directions (the crate docs' rules).
    fn directions(&self, x: i64, y: i64, incoming: u8) -> u8 {
        if incoming == 0 {
            return 0xff;
        }
        let mut keep = 0u8;
        for d in (0..8).filter(|d| incoming >> d & 1 == 1) {
            let (dx, dy) = (DX[d], DY[d]);
            keep |= 1 << d;
            if d < 2 {
                for (s, side) in [(1, 2), (-1, 3)] {
                    if self.free(x, y + s) && !self.free(x - dx, y + s) {
                        keep |= 1 << side | 1 << diagonal(dx, s);
                    }
                }
            } else if d < 4 {
                for (s, side) in [(1, 0), (-1, 1)] {
                    if self.free(x + s, y) && !self.free(x + s, y - dy) {
                        keep |= 1 << side | 1 << diagonal(s, dy);
                    }
                }
            } else {
                keep |= 1 << usize::from(dx < 0) | 1 << (2 + usize::from(dy < 0));
            }
        }
        keep
    }

    /// The online straight jump from `(x, y)` in direction `d`: `(true, k)` for the goal or
    /// a forced cell `k` cells on, `(false, k)` at a wall after `k` free cells.
    fn straight_jump(&self, x: i64, y: i64, d: usize) -> (bool, i64) {
        let mut k = 0;
        loop {
            let (cx, cy) = (x + (k + 1) * DX[d], y + (k + 1) * DY[d]);
            if !self.free(cx, cy) {
                return (false, k);
            }
            k += 1;
            if (cx, cy) == self.goal || self.forced(cx, cy, d) {
                return (true, k);
            }
        }
    }

    /// JPS+'s exact distance from `(x, y)` in direction `d`, the goal ignored: `k > 0` for
    /// a jump point `k` cells on, `-k` at a wall after `k` free cells.
    fn exact(&mut self, x: i64, y: i64, d: usize) -> i64 {
        let i = self.at(x, y);
        if let Some(e) = self.exact[i][d] {
            return e;
        }
        // Walk to the end, then fill the cells walked, last first.
        let mut walked = vec![(x, y)];
        let end = loop {
            let &(cx, cy) = walked.last().unwrap_or(&(x, y));
            if let Some(e) = self.exact[self.at(cx, cy)][d] {
                walked.pop();
                break e;
            }
            if !self.allowed(cx, cy, d) {
                walked.pop();
                let j = self.at(cx, cy);
                self.exact[j][d] = Some(0);
                break 0;
            }
            let (nx, ny) = (cx + DX[d], cy + DY[d]);
            let stops = match d < 4 {
                true => self.forced(nx, ny, d),
                false => {
                    let (h, v) = (usize::from(DX[d] < 0), 2 + usize::from(DY[d] < 0));
                    self.exact(nx, ny, h) > 0 || self.exact(nx, ny, v) > 0
                }
            };
            if stops {
                walked.pop();
                let j = self.at(cx, cy);
                self.exact[j][d] = Some(1);
                break 1;
            }
            walked.push((nx, ny));
        };
        let mut e = end;
        while let Some((cx, cy)) = walked.pop() {
            e = if e > 0 { e + 1 } else { e - 1 };
            let j = self.at(cx, cy);
            self.exact[j][d] = Some(e);
        }
        self.exact[i][d].unwrap_or(end)
    }

    /// What a table entry holding `e` says: the cells it reaches, and whether it is far.
    fn entry_reach(e: i64) -> (i64, bool) {
        match e.abs() >= FAR {
            true => (SPAN, true),
            false => (e.abs(), false),
        }
    }

    /// JPS+'s straight jump from `(x, y)` in direction `d`: the goal when it lies on the
    /// way, else the jump point; each entry read counted.
    fn plus_straight(&mut self, x: i64, y: i64, d: usize) -> Option<(i64, i64)> {
        let (gx, gy) = self.goal;
        let to_goal = match d {
            0 if gy == y && gx > x => gx - x,
            1 if gy == y && gx < x => x - gx,
            2 if gx == x && gy > y => gy - y,
            3 if gx == x && gy < y => y - gy,
            _ => i64::MAX,
        };
        let mut base = 0;
        loop {
            self.counters[1] += 1;
            let (cx, cy) = (x + base * DX[d], y + base * DY[d]);
            let e = self.exact(cx, cy, d);
            let (reach, far) = Self::entry_reach(e);
            if far {
                if to_goal <= base + SPAN {
                    return Some(self.goal);
                }
                base += SPAN;
                continue;
            }
            let reach = base + reach;
            return if to_goal <= reach {
                Some(self.goal)
            } else if e > 0 {
                Some((x + reach * DX[d], y + reach * DY[d]))
            } else {
                None
            };
        }
    }

    /// JPS+'s diagonal walk from node `p` at `(x, y)` in direction `d`: at each diagonal
    /// jump point or target jump point (on the goal's row or column) the component jumps'
    /// results become successors, and the walk goes on.
    fn plus_diagonal(&mut self, p: usize, x: i64, y: i64, d: usize) {
        let (dx, dy) = (DX[d], DY[d]);
        let (h, v) = (usize::from(dx < 0), 2 + usize::from(dy < 0));
        let (gx, gy) = self.goal;
        let (mut cx, mut cy) = (x, y);
        loop {
            self.counters[1] += 1;
            let e = self.exact(cx, cy, d);
            let (reach, far) = Self::entry_reach(e);
            let target = ((gx - cx) * dx).min((gy - cy) * dy);
            let (k, stops) = if target > 0 && target <= reach {
                (target, true)
            } else if far {
                (reach, false)
            } else if e > 0 {
                (reach, true)
            } else {
                return;
            };
            (cx, cy) = (cx + k * dx, cy + k * dy);
            if !stops {
                continue;
            }
            if (cx, cy) == self.goal {
                self.relax(p, x, y, cx, cy);
                return;
            }
            for component in [h, v] {
                if let Some((tx, ty)) = self.plus_straight(cx, cy, component) {
                    self.relax(p, x, y, tx, ty);
                }
            }
        }
    }

    /// The online diagonal walk (JPS and JPS') from node `p` at `(x, y)` in direction `d`.
    fn online_diagonal(&mut self, p: usize, x: i64, y: i64, d: usize) {
        let (h, v) = (usize::from(DX[d] < 0), 2 + usize::from(DY[d] < 0));
        let (mut cx, mut cy) = (x, y);
        loop {
            if !self.allowed(cx, cy, d) {
                return;
            }
            (cx, cy) = (cx + DX[d], cy + DY[d]);
            self.counters[1] += 1;
            if (cx, cy) == self.goal {
                self.relax(p, x, y, cx, cy);
                return;
            }
            for component in [h, v] {
                let (found, k) = self.straight_jump(cx, cy, component);
                self.counters[1] += k as u64;
                if found {
                    if self.variant == JpsVariant::Jps {
                        self.relax(p, x, y, cx, cy);
                        return;
                    }
                    self.relax(p, x, y, cx + k * DX[component], cy + k * DY[component]);
                }
            }
        }
    }

    fn units((straight, diagonal): (u32, u32)) -> u64 {
        Cost::octile(u64::from(straight), u64::from(diagonal)).units()
    }

    fn value((straight, diagonal): (u32, u32)) -> f64 {
        f64::from(straight) + f64::from(diagonal) * std::f64::consts::SQRT_2
    }

    fn octile(dx: i64, dy: i64) -> (u32, u32) {
        let (low, high) = (dx.abs().min(dy.abs()), dx.abs().max(dy.abs()));
        ((high - low) as u32, low as u32)
    }

    fn push(&mut self, i: usize, g: (u32, u32), x: i64, y: i64) {
        let h = Self::octile(x - self.goal.0, y - self.goal.1);
        let f = Self::value((g.0 + h.0, g.1 + h.1)).to_bits();
        let tie = u32::MAX - (Self::value(g) * 1024.0) as u32;
        let entry = (f, u64::from(tie) << 32 | i as u64);
        if f == self.front_key {
            self.front.push(entry);
        } else {
            self.heap.push(Reverse(entry));
        }
    }

    fn pop(&mut self) -> Option<usize> {
        if let Some((_, tie)) = self.front.pop() {
            return Some((tie & u64::from(u32::MAX)) as usize);
        }
        let Reverse((f, tie)) = self.heap.pop()?;
        self.front_key = f;
        Some((tie & u64::from(u32::MAX)) as usize)
    }

    /// Offers `(tx, ty)` as a successor of node `p` at `(x, y)`.
    fn relax(&mut self, p: usize, x: i64, y: i64, tx: i64, ty: i64) {
        let i = self.at(tx, ty);
        if self.state[i] == 2 {
            return;
        }
        let step = Self::octile(tx - x, ty - y);
        let g_new = (self.g[p].0 + step.0, self.g[p].1 + step.1);
        let (dx, dy) = (tx - x, ty - y);
        // The last move of the leg, diagonal first.
        let last = if dx.abs() == dy.abs() {
            diagonal(dx.signum(), dy.signum())
        } else if dx.abs() > dy.abs() {
            usize::from(dx < 0)
        } else {
            2 + usize::from(dy < 0)
        };
        if self.state[i] == 0 {
            self.state[i] = 1;
            self.counters[3] += 1;
            self.counters[2] += 1;
        } else {
            let (new, old) = (Self::units(g_new), Self::units(self.g[i]));
            if new == old {
                self.incoming[i] |= 1 << last;
                return;
            }
            if new > old {
                return;
            }
            self.counters[3] += 1;
        }
        self.g[i] = g_new;
        self.parent[i] = p;
        self.incoming[i] = 1 << last;
        self.push(i, g_new, tx, ty);
    }

    fn run(mut self, start: Cell) -> JpsSearch {
        let (sx, sy) = (i64::from(start.x), i64::from(start.y));
        let s = self.at(sx, sy);
        self.state[s] = 1;
        self.parent[s] = s;
        self.push(s, (0, 0), sx, sy);
        self.counters[2] = 1;
        self.counters[4] = 1;
        let goal = self.at(self.goal.0, self.goal.1);
        let status = loop {
            let Some(p) = self.pop() else {
                break Status::NoPath;
            };
            if self.state[p] == 2 {
                continue;
            }
            self.state[p] = 2;
            self.counters[0] += 1;
            if p == goal {
                break Status::Found;
            }
            let (x, y) = (p as i64 % self.width, p as i64 / self.width);
            let directions = self.directions(x, y, self.incoming[p]);
            for d in (0..8).filter(|d| directions >> d & 1 == 1) {
                match (self.variant, d < 4) {
                    (JpsVariant::JpsPlus, true) => {
                        if let Some((tx, ty)) = self.plus_straight(x, y, d) {
                            self.relax(p, x, y, tx, ty);
                        }
                    }
                    (JpsVariant::JpsPlus, false) => self.plus_diagonal(p, x, y, d),
                    (_, true) => {
                        let (found, k) = self.straight_jump(x, y, d);
                        self.counters[1] += k as u64;
                        if found {
                            self.relax(p, x, y, x + k * DX[d], y + k * DY[d]);
                        }
                    }
                    (_, false) => self.online_diagonal(p, x, y, d),
                }
            }
            self.counters[4] = self.counters[4].max(self.counters[2] - self.counters[0]);
        };
        let goal_cell = Cell::new(self.goal.0 as u32, self.goal.1 as u32);
        let chain = (status == Status::Found)
            .then(|| crate::path_from_parents(self.grid, &self.parent, start, goal_cell));
        (status, chain, self.counters)
    }
}
