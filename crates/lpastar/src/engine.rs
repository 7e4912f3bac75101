//! The incremental search both LPA* and D* Lite run: g- and rhs-values, the queue U of
//! locally inconsistent vertices, and ComputeShortestPath.
//!
//! LPA* (Koenig, Likhachev and Furcy 2004, <https://doi.org/10.1016/j.artint.2003.12.001>,
//! the pseudocode of its Fig. 3) searches from the start to the goal; D* Lite (Koenig and
//! Likhachev 2002, AAAI, <https://cdn.aaai.org/AAAI/2002/AAAI02-072.pdf>, the optimized
//! version, Fig. 4) is the same search run from the goal to the agent with a key modifier
//! `km`. One engine serves both: it grows a search from a *root* (the vertex whose
//! `rhs` is 0: LPA*'s start, D* Lite's goal) until the *target* (LPA*'s goal, D* Lite's
//! start) is locally consistent and no queued key is below the target's. The grid graph
//! is undirected (every move can be reversed at the same cost), so predecessors and
//! successors are the same neighbours and one neighbour loop serves both directions.
//!
//! - `key(s) = [min(g, rhs) + h(s, target) + km; min(g, rhs)]`, `h` Manhattan on 4
//!   moves and octile on 8, both consistent, in exact [`Cost`] units; `km = 0` for LPA*.
//! - ComputeShortestPath: while `U.TopKey() < key(target)` or `rhs(target) != g(target)`:
//!   pop the least `u`; if its key is out of date (`k_old < key(u)`, only after `km` grew)
//!   re-key it; else if overconsistent (`g > rhs`) set `g = rhs` and lower the `rhs` of its
//!   neighbours through it; else (underconsistent) set `g = inf` and recompute the `rhs`
//!   of every neighbour whose `rhs` came through `u`. Both cases count as one vertex
//!   expansion (the papers' measure).
//! - A changed cell changes the cost of every edge that touches it or, on 8 moves without
//!   corner cutting, passes diagonally beside it: all such edges join cells of its 3 x 3
//!   block (4 moves: itself and its four neighbours). Those vertices get their `rhs`
//!   recomputed over all neighbours and are re-queued (UpdateVertex). This is the basic
//!   version's rule (Fig. 3 of D* Lite) rather than Fig. 4's test per changed edge, since
//!   one cell changes up to 20 edges at once; the result is the same `rhs`.
//! - UpdateVertex runs only for a vertex whose `rhs` changed (or, in ComputeShortestPath,
//!   whose `g` did): the papers call it for every neighbour, but a vertex whose `g` and
//!   `rhs` are unchanged keeps its consistency, so it stays in or out of the queue as it
//!   was, and its queued key stays a lower bound of its current key (`km` only grows to
//!   keep it so), which is all the lazy re-keying on pop needs. This saves most key
//!   updates; the counters count the operations actually done.
//! - Ties: the queue orders by `(k1, k2, row-major index)`, a total order (module `heap`).
//!   The path is traced from the target by the neighbour minimising `c + g`, the first of
//!   equal ones in the move order right, left, down, up, then the diagonals.
//!
//! Per-cell state is `g`, `rhs` and a stamp (the session number in which they were last
//! written, so a reset is O(1): older stamps read as `g = rhs = inf`), plus the queue's
//! position table: 24 bytes a cell, allocated zeroed (committed by the system as touched).

use planner_api::{Budget, Cell, Cost, Counters, Grid, MemoryShortfall, Path};

use crate::heap::Heap;

const INF: u64 = u64::MAX;

/// Bytes of per-cell state the engine allocates for a grid (its memory budget check).
pub const BYTES_PER_CELL: u64 = 24;

/// The counters of one repair (or first search), as plain integers.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct RepairStats {
    /// Vertex expansions: pops that made a vertex consistent (g = rhs) or set g = inf.
    pub expanded: u64,
    /// Insertions into the queue.
    pub heap_pushes: u64,
    /// Removals of the least entry (an expansion's pop).
    pub heap_pops: u64,
    /// Key changes of a queued vertex (UpdateVertex on a queued vertex, and re-keying of
    /// out-of-date keys after `km` grew).
    pub heap_updates: u64,
    /// Removals of a queued vertex that became consistent, other than by a pop.
    pub heap_removes: u64,
    /// Times a vertex's rhs got a different value.
    pub rhs_changes: u64,
}

impl RepairStats {
    /// The counters in this order: `n_expanded`, `n_heap_pushes`, `n_heap_pops`,
    /// `n_heap_updates`, `n_heap_removes`, `n_rhs_changes`.
    pub fn report(&self) -> Counters {
        Counters::new()
            .with("n_expanded", self.expanded)
            .with("n_heap_pushes", self.heap_pushes)
            .with("n_heap_pops", self.heap_pops)
            .with("n_heap_updates", self.heap_updates)
            .with("n_heap_removes", self.heap_removes)
            .with("n_rhs_changes", self.rhs_changes)
    }
}

/// How a [`Engine::compute`] call ended.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Computed {
    /// The target is consistent: its g is its distance to the root (inf: unreachable).
    Done,
    /// The budget ran out; the state is valid and the next call continues.
    Exhausted,
    /// The per-cell state does not fit the memory budget.
    OverMemory(MemoryShortfall),
}

/// One offset of the neighbourhood, with the cells a diagonal must find free.
#[derive(Debug, Clone, Copy)]
struct Step {
    dx: i32,
    dy: i32,
    cost: u64,
}

const STEPS_4: [Step; 4] = [
    Step {
        dx: 1,
        dy: 0,
        cost: Cost::ONE.units(),
    },
    Step {
        dx: -1,
        dy: 0,
        cost: Cost::ONE.units(),
    },
    Step {
        dx: 0,
        dy: 1,
        cost: Cost::ONE.units(),
    },
    Step {
        dx: 0,
        dy: -1,
        cost: Cost::ONE.units(),
    },
];

const STEPS_8: [Step; 8] = [
    Step {
        dx: 1,
        dy: 0,
        cost: Cost::ONE.units(),
    },
    Step {
        dx: -1,
        dy: 0,
        cost: Cost::ONE.units(),
    },
    Step {
        dx: 0,
        dy: 1,
        cost: Cost::ONE.units(),
    },
    Step {
        dx: 0,
        dy: -1,
        cost: Cost::ONE.units(),
    },
    Step {
        dx: 1,
        dy: 1,
        cost: Cost::SQRT_2.units(),
    },
    Step {
        dx: 1,
        dy: -1,
        cost: Cost::SQRT_2.units(),
    },
    Step {
        dx: -1,
        dy: 1,
        cost: Cost::SQRT_2.units(),
    },
    Step {
        dx: -1,
        dy: -1,
        cost: Cost::SQRT_2.units(),
    },
];

/// The incremental search (see the [module docs](self)).
#[derive(Debug, Clone)]
pub struct Engine {
    eight: bool,
    grid: Option<Grid>,
    width: i64,
    height: i64,
    g: Vec<u64>,
    rhs: Vec<u64>,
    stamp: Vec<u32>,
    session: u32,
    heap: Heap,
    root: u32,
    target: u32,
    km: u64,
    /// Whether the per-cell state is sized and the root queued for this session.
    initialized: bool,
    stats: RepairStats,
    /// Scratch list of the vertices a batch of changes touches.
    affected: Vec<u32>,
}

impl Engine {
    /// An engine for 8 moves without corner cutting (`eight`) or 4 moves.
    pub fn new(eight: bool) -> Engine {
        Engine {
            eight,
            grid: None,
            width: 0,
            height: 0,
            g: Vec::new(),
            rhs: Vec::new(),
            stamp: Vec::new(),
            session: 0,
            heap: Heap::default(),
            root: 0,
            target: 0,
            km: 0,
            initialized: false,
            stats: RepairStats::default(),
            affected: Vec::new(),
        }
    }

    /// Begins a session on a copy of `grid`, rooted at `root`, towards `target`. Both are
    /// cells of `grid` (the caller validated them). Searches nothing.
    pub fn reset(&mut self, grid: &Grid, root: Cell, target: Cell) {
        self.width = i64::from(grid.width());
        self.height = i64::from(grid.height());
        self.grid = Some(grid.clone());
        self.root = grid.index(root) as u32;
        self.target = grid.index(target) as u32;
        self.km = 0;
        self.initialized = false;
        self.stats = RepairStats::default();
    }

    /// The current map.
    pub fn grid(&self) -> Option<&Grid> {
        self.grid.as_ref()
    }

    /// The root cell.
    pub fn root(&self) -> Option<Cell> {
        self.grid.as_ref().map(|g| g.cell(self.root as usize))
    }

    /// The target cell.
    pub fn target(&self) -> Option<Cell> {
        self.grid.as_ref().map(|g| g.cell(self.target as usize))
    }

    /// The key modifier `km` in [`Cost`] units.
    pub fn km(&self) -> Cost {
        Cost::from_units(self.km)
    }

    /// Moves the root to `cell` by starting the search over (LPA*'s answer to a moved
    /// start: its g-values are distances from the old start).
    pub fn move_root(&mut self, cell: Cell) {
        if let Some(grid) = &self.grid {
            let v = grid.index(cell) as u32;
            if v != self.root {
                self.root = v;
                self.initialized = false;
            }
        }
    }

    /// Moves the target to `cell`, D* Lite's way: `km += h(old target, new target)`, so
    /// that the keys already queued stay lower bounds without re-keying them all.
    pub fn move_target(&mut self, cell: Cell) {
        if let Some(grid) = &self.grid {
            let v = grid.index(cell) as u32;
            if v != self.target {
                if self.initialized {
                    self.km = self.km.saturating_add(self.h_between(self.target, v));
                }
                self.target = v;
            }
        }
    }

    /// Applies changed cells (each in the map, checked by the caller) and re-queues the
    /// vertices whose edges changed. Before the first search only the map changes.
    pub fn apply(&mut self, changes: &[(Cell, bool)]) {
        let Some(grid) = self.grid.as_mut() else {
            return;
        };
        self.affected.clear();
        for &(cell, free) in changes {
            if grid.is_free(cell) == free {
                continue;
            }
            grid.set_free(cell, free);
            let (x, y) = (i64::from(cell.x), i64::from(cell.y));
            for dy in -1..=1i64 {
                for dx in -1..=1i64 {
                    if !self.eight && dx != 0 && dy != 0 {
                        continue;
                    }
                    let (nx, ny) = (x + dx, y + dy);
                    if nx >= 0 && ny >= 0 && nx < self.width && ny < self.height {
                        self.affected.push((ny * self.width + nx) as u32);
                    }
                }
            }
        }
        if !self.initialized {
            return;
        }
        self.affected.sort_unstable();
        self.affected.dedup();
        let affected = std::mem::take(&mut self.affected);
        for &u in &affected {
            let value = self.fresh_rhs(u);
            if self.set_rhs(u, value) {
                self.update_vertex(u);
            }
        }
        self.affected = affected;
    }

    /// The counters since the last call, which zeroes them.
    pub fn take_stats(&mut self) -> RepairStats {
        std::mem::take(&mut self.stats)
    }

    /// ComputeShortestPath within `budget` (its expansion and time limits; the memory
    /// limit when the per-cell state is first sized).
    pub fn compute(&mut self, budget: &Budget) -> Computed {
        let Some(grid) = self.grid.as_ref() else {
            return Computed::Done;
        };
        if !self.initialized {
            let n = grid.len();
            if let Err(shortfall) = budget.check_memory(BYTES_PER_CELL * n as u64, grid) {
                return Computed::OverMemory(shortfall);
            }
            if self.g.len() != n {
                self.g = vec![0; n];
                self.rhs = vec![0; n];
                self.stamp = vec![0; n];
                self.session = 0;
            }
            self.heap.fit(n);
            self.session = self.session.wrapping_add(1);
            if self.session == 0 {
                // After 2^32 sessions the stamps could collide: clear them once.
                self.stamp.iter_mut().for_each(|s| *s = 0);
                self.session = 1;
            }
            self.km = 0;
            self.initialized = true;
            let root = self.root;
            let value = self.fresh_rhs(root);
            self.set_rhs(root, value);
            self.update_vertex(root);
        }
        let mut clock = budget.start();
        let mut expanded = 0u64;
        while let Some((k1, k2, u)) = self.heap.top() {
            let target_key = self.key(self.target);
            let t = self.target as usize;
            if (k1, k2) >= target_key && self.rhs_of(t) == self.g_of(t) {
                break;
            }
            let new_key = self.key(u);
            if (k1, k2) < new_key {
                self.heap.update(u, new_key.0, new_key.1);
                self.stats.heap_updates += 1;
                continue;
            }
            if !clock.allows(expanded) {
                return Computed::Exhausted;
            }
            expanded += 1;
            self.stats.expanded += 1;
            let ui = u as usize;
            let (g_u, rhs_u) = (self.g_of(ui), self.rhs_of(ui));
            if g_u > rhs_u {
                self.set_g(u, rhs_u);
                self.heap.remove(u);
                self.stats.heap_pops += 1;
                self.for_each_neighbour(u, |engine, s, cost| {
                    if s != engine.root {
                        let through = cost.saturating_add(rhs_u);
                        if through < engine.rhs_of(s as usize) {
                            engine.set_rhs(s, through);
                            engine.update_vertex(s);
                        }
                    }
                });
            } else {
                self.set_g(u, INF);
                self.for_each_neighbour(u, |engine, s, cost| {
                    if s != engine.root
                        && g_u != INF
                        && engine.rhs_of(s as usize) == cost.saturating_add(g_u)
                    {
                        let value = engine.fresh_rhs(s);
                        if engine.set_rhs(s, value) {
                            engine.update_vertex(s);
                        }
                    }
                });
                // u's own rhs does not depend on its g; it is re-queued or dropped.
                if self.heap.contains(u) {
                    let key = self.key(u);
                    if self.g_of(ui) != self.rhs_of(ui) {
                        self.heap.update(u, key.0, key.1);
                        self.stats.heap_updates += 1;
                    } else {
                        self.heap.remove(u);
                        self.stats.heap_pops += 1;
                    }
                }
            }
        }
        Computed::Done
    }

    /// `g(target)`, the target's distance to the root once [`Engine::compute`] is done
    /// (`None`: unreachable or not searched).
    pub fn target_distance(&self) -> Option<Cost> {
        if !self.initialized {
            return None;
        }
        let g = self.g_of(self.target as usize);
        (g != INF).then(|| Cost::from_units(g))
    }

    /// The path from the target to the root, each step to the neighbour minimising
    /// `c + g` (ties: move order), once [`Engine::compute`] is done; `None` when the target
    /// is unreachable, or when the trace meets no finite neighbour or runs longer than the
    /// map has cells (which a correct search never does; the oracle tests say so).
    pub fn trace(&self) -> Option<Vec<Cell>> {
        let grid = self.grid.as_ref()?;
        self.target_distance()?;
        let mut cells = vec![grid.cell(self.target as usize)];
        let mut u = self.target;
        while u != self.root {
            if cells.len() > grid.len() {
                return None;
            }
            let mut best: Option<(u64, u32)> = None;
            self.for_each_neighbour_ro(u, |s, cost| {
                let through = cost.saturating_add(self.g_of(s as usize));
                if through != INF && best.is_none_or(|(b, _)| through < b) {
                    best = Some((through, s));
                }
            });
            let (_, next) = best?;
            u = next;
            cells.push(grid.cell(u as usize));
        }
        Some(cells)
    }

    /// A path that the trace returned, as a [`Path`] from root to target or reversed.
    pub fn path(&self, root_first: bool) -> Option<Path> {
        let mut cells = self.trace()?;
        if root_first {
            cells.reverse();
        }
        Some(Path::new(cells))
    }

    fn g_of(&self, i: usize) -> u64 {
        if self.stamp[i] == self.session {
            self.g[i]
        } else {
            INF
        }
    }

    fn rhs_of(&self, i: usize) -> u64 {
        if self.stamp[i] == self.session {
            self.rhs[i]
        } else {
            INF
        }
    }

    fn touch(&mut self, i: usize) {
        if self.stamp[i] != self.session {
            self.stamp[i] = self.session;
            self.g[i] = INF;
            self.rhs[i] = INF;
        }
    }

    fn set_g(&mut self, u: u32, value: u64) {
        let i = u as usize;
        self.touch(i);
        self.g[i] = value;
    }

    /// Sets `rhs(u)`; whether it changed.
    fn set_rhs(&mut self, u: u32, value: u64) -> bool {
        let i = u as usize;
        self.touch(i);
        let changed = self.rhs[i] != value;
        if changed {
            self.rhs[i] = value;
            self.stats.rhs_changes += 1;
        }
        changed
    }

    /// `rhs(u)` from scratch: 0 at a free root, else the least `c(u, s) + g(s)`.
    fn fresh_rhs(&self, u: u32) -> u64 {
        if u == self.root {
            let free = self
                .grid
                .as_ref()
                .is_some_and(|g| g.free_cells()[u as usize]);
            return if free { 0 } else { INF };
        }
        let mut best = INF;
        self.for_each_neighbour_ro(u, |s, cost| {
            best = best.min(cost.saturating_add(self.g_of(s as usize)));
        });
        best
    }

    fn key(&self, u: u32) -> (u64, u64) {
        let i = u as usize;
        let m = self.g_of(i).min(self.rhs_of(i));
        let h = self.h_between(u, self.target);
        (m.saturating_add(h).saturating_add(self.km), m)
    }

    fn update_vertex(&mut self, u: u32) {
        let i = u as usize;
        let inconsistent = self.g_of(i) != self.rhs_of(i);
        match (inconsistent, self.heap.contains(u)) {
            (true, true) => {
                let (k1, k2) = self.key(u);
                self.heap.update(u, k1, k2);
                self.stats.heap_updates += 1;
            }
            (true, false) => {
                let (k1, k2) = self.key(u);
                self.heap.push(u, k1, k2);
                self.stats.heap_pushes += 1;
            }
            (false, true) => {
                self.heap.remove(u);
                self.stats.heap_removes += 1;
            }
            (false, false) => {}
        }
    }

    /// The heuristic between two vertices: Manhattan (4 moves) or octile (8), exact.
    fn h_between(&self, a: u32, b: u32) -> u64 {
        let w = self.width.max(1) as u32;
        let (ax, ay) = (a % w, a / w);
        let (bx, by) = (b % w, b / w);
        let (dx, dy) = (ax.abs_diff(bx), ay.abs_diff(by));
        if self.eight {
            Cost::octile_distance(dx, dy).units()
        } else {
            Cost::steps(u64::from(dx) + u64::from(dy)).units()
        }
    }

    /// Calls `visit(s, cost)` for every neighbour `s` joined to `u` by a move (both free,
    /// and for a diagonal both cells beside it free), in the move order.
    fn for_each_neighbour_ro(&self, u: u32, mut visit: impl FnMut(u32, u64)) {
        let Some(grid) = self.grid.as_ref() else {
            return;
        };
        let free = grid.free_cells();
        if !free[u as usize] {
            return;
        }
        let w = self.width;
        let (x, y) = (i64::from(u) % w, i64::from(u) / w);
        let steps: &[Step] = if self.eight { &STEPS_8 } else { &STEPS_4 };
        for step in steps {
            let (nx, ny) = (x + i64::from(step.dx), y + i64::from(step.dy));
            if nx < 0 || ny < 0 || nx >= w || ny >= self.height {
                continue;
            }
            let s = (ny * w + nx) as usize;
            if !free[s] {
                continue;
            }
            if step.dx != 0
                && step.dy != 0
                && !(free[(y * w + nx) as usize] && free[(ny * w + x) as usize])
            {
                continue;
            }
            visit(s as u32, step.cost);
        }
    }

    /// [`Engine::for_each_neighbour_ro`] with mutable access to the engine.
    fn for_each_neighbour(&mut self, u: u32, mut visit: impl FnMut(&mut Engine, u32, u64)) {
        let mut found = [(0u32, 0u64); 8];
        let mut n = 0;
        self.for_each_neighbour_ro(u, |s, cost| {
            found[n] = (s, cost);
            n += 1;
        });
        for &(s, cost) in &found[..n] {
            visit(self, s, cost);
        }
    }
}
