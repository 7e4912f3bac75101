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
//!   expansion (the papers' measure). The overconsistent vertex leaves the queue (a pop);
//!   the underconsistent one is re-keyed where it is (an update), or leaves the queue (a
//!   pop) when its `rhs` is infinite too.
//! - Weighted maps: a move costs `half * (k_from * w(from) + k_to * w(to))` units
//!   ([`planner_api::weights`]), `from` the cell a path leaves: LPA*'s paths run from the
//!   root, D* Lite's toward it ([`Engine::with_paths_to_root`]), which matters only for
//!   the entered cell's rule. The heuristic is multiplied by the smallest weight when the
//!   session began; a change to a lower weight ends the session ([`Engine::apply`]).
//! - A changed cell (blocked, freed or reweighted) changes the cost of every edge that
//!   touches it or, on 8 moves without corner cutting, passes diagonally beside it: all
//!   such edges join cells of its 3 x 3 block (4 moves: itself and its four neighbours).
//!   Those vertices get their `rhs` recomputed over all neighbours and are re-queued
//!   (UpdateVertex), each once per batch of changes, after the whole batch is on the map
//!   (in any order: `rhs` depends on `g`, which a batch does not change). This is the
//!   basic version's rule (Fig. 3 of D* Lite) rather than Fig. 4's test per changed edge,
//!   since one cell changes up to 20 edges at once; the result is the same `rhs`. A moved
//!   start re-roots LPA*'s search, which begins a new session at its next replan.
//! - UpdateVertex runs only for a vertex whose `rhs` changed (or, in ComputeShortestPath,
//!   whose `g` did): the papers call it for every neighbour, but a vertex whose `g` and
//!   `rhs` are unchanged keeps its consistency, so it stays in or out of the queue as it
//!   was, and its queued key stays a lower bound of its current key (`km` only grows to
//!   keep it so), which is all the lazy re-keying on pop needs. This saves most key
//!   updates; the counters count the operations on the papers' queue U (insert, update,
//!   remove, pop), one each, however the queue ([`KeyedQueue`]) carries them out. A first
//!   search's counters, path and cost equal those of `planner_testkit::reference_lpa`,
//!   the papers' ComputeShortestPath written again with a `BTreeSet` for the queue, for
//!   LPA\* and D\* Lite, 4- and 8-connected, on 3,080 random grids (`tests/reference.rs`)
//!   and on every run of `configs/incremental.toml` (xtask's
//!   `every_lpastar_and_dstar_lite_run_matches_the_reference_search`). So do the repairs:
//!   `planner_testkit::ReferenceIncremental` (the same written again through changes,
//!   moves and budgets) gives the same status, path and counters at every replan of
//!   random sessions on 280 grids, weighted or not (`tests/reference.rs`), and of every
//!   run of the configs under `configs/replan/` (planner-replan's
//!   `every_replan_matches_the_reference_planners`); and every repair's path and cost are
//!   A\* from scratch's (planner-replan's oracle).
//! - Ties: the queue orders by `(k1, k2, row-major index)`, a total order ([`KeyedQueue`]).
//!   The path is traced from the target by the neighbour minimising `c + g`, the first of
//!   equal ones in the move order right, left, down, up, then the diagonals. That least
//!   is `rhs` (kept equal to it for every vertex but the root), so the scan of a vertex's
//!   neighbours stops at the first that reaches it.
//!
//! Data layout (the search is the papers'; this is how it is stored). Vertices are
//! indices into a copy of the map padded with one blocked cell on every side, so a
//! neighbour is a fixed offset and needs no bounds test; the padded row-major order is the
//! grid's, so ties come out as they would by the grid's own index. Per vertex one 16-byte
//! record holds `g` and `rhs`, complemented so that zero reads as `inf` (a four-to-a-line
//! record read with no test; with a third word for a session stamp instead, D* Lite's
//! navigations were slower, PERFORMANCE.md's D* Lite section, seventh round). A session lists
//! the vertices whose records it wrote, in at most one entry per vertex of space (4
//! bytes; a longer list gives way to clearing the whole array), and the next session
//! clears those, so a reset costs the last session's work, not the map's size. The queue keeps a 4-byte ticket ([`KeyedQueue`]: buckets of `k1` with lazy
//! deletion), and the padded map one bit: 24 bytes and a bit a padded cell at most,
//! allocated zeroed (committed by the system as touched).
//! A cell's moves come from its 3 x 3 block of map bits (three two-byte loads) looked up
//! in a table. After a map's first searches, a search allocates nothing.

use planner_api::{Budget, Cell, CellChange, Cost, Counters, Grid, MemoryShortfall, Path};

use planner_search::keyed::KeyedQueue;

const INF: u64 = u64::MAX;

/// The largest finite `g` or `rhs`: sums stop here, one below infinity (`u64::MAX`), so that a vertex
/// reached through saturated weighted costs is still reached (planner-api's weights docs,
/// "The range"); a target at this distance ends the search with
/// [`planner_api::Outcome::cost_overflow`].
pub const SATURATED: u64 = INF - 1;

/// `c + g` for a move of cost `edge` to a vertex of distance `g`: [`INF`] when `g` is, else
/// at most [`SATURATED`].
#[inline]
fn via(edge: u64, g: u64) -> u64 {
    match g {
        INF => INF,
        _ => edge.saturating_add(g).min(SATURATED),
    }
}

/// Bytes of per-cell state the engine allocates for each cell of the padded grid (its
/// memory budget check).
pub const BYTES_PER_CELL: u64 = 25;

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

/// Bytes of the bit map of `padded` cells: a bit a cell and two bytes of slack (for the
/// two-byte loads of [`Engine::legal`]).
fn bits_len(padded: u64) -> usize {
    (padded / 8) as usize + 3
}

/// Sets padded cell `p`'s bit to `free`.
#[inline]
fn set_bit(bits: &mut [u8], p: usize, free: bool) {
    if let Some(byte) = bits.get_mut(p / 8) {
        if free {
            *byte |= 1 << (p % 8);
        } else {
            *byte &= !(1 << (p % 8));
        }
    }
}

/// The moves in the order the engine tries them (the trace's tie order): right, left,
/// down, up, then the diagonals; `(dx, dy, cost in Cost units)`.
const MOVES: [(i32, i32, u64); 8] = [
    (1, 0, Cost::ONE.units()),
    (-1, 0, Cost::ONE.units()),
    (0, 1, Cost::ONE.units()),
    (0, -1, Cost::ONE.units()),
    (1, 1, Cost::SQRT_2.units()),
    (1, -1, Cost::SQRT_2.units()),
    (-1, 1, Cost::SQRT_2.units()),
    (-1, -1, Cost::SQRT_2.units()),
];

/// One move on the padded grid: the offset to the neighbour, the coordinate steps and the
/// cost.
#[derive(Debug, Clone, Copy, Default)]
struct Step {
    offset: isize,
    dx: i32,
    dy: i32,
    cost: u64,
}

/// The move table of [`Engine::legal`]: for each 3 x 3 block of free flags, the moves
/// from its centre, 4 or 8 without corner cutting (none when the centre is blocked).
fn move_table(eight: bool) -> Vec<u8> {
    let n_moves = if eight { 8 } else { 4 };
    (0..512usize)
        .map(|code| {
            let free = |dx: i32, dy: i32| code >> (3 * (dy + 1) + dx + 1) & 1 == 1;
            if !free(0, 0) {
                return 0;
            }
            let mut mask = 0u8;
            for (k, &(dx, dy, _)) in MOVES.iter().enumerate().take(n_moves) {
                if free(dx, dy) && (dx == 0 || dy == 0 || (free(dx, 0) && free(0, dy))) {
                    mask |= 1 << k;
                }
            }
            mask
        })
        .collect()
}

/// A vertex's record: `g` and `rhs`, each stored complemented (`!value`), so that a zeroed
/// record (and a zeroed allocation) reads `g = rhs = inf`.
type Record = [u64; 2];

/// The incremental search (see the [module docs](self)).
#[derive(Debug, Clone)]
pub struct Engine {
    eight: bool,
    grid: Option<Grid>,
    width: u32,
    height: u32,
    /// Padded width: `width + 2`.
    stride: u32,
    /// The padded map, a bit per cell (bit `p % 8` of byte `p / 8` set when padded cell
    /// `p` is free), with a blocked border and two bytes of slack; empty when the grid is
    /// too large for 32-bit vertex indices.
    bits: Vec<u8>,
    steps: [Step; 8],
    /// The legal moves (bits in [`MOVES`] order) of each 3 x 3 block of free flags
    /// (bit `3 * (dy + 1) + dx + 1` for the cell at offset `(dx, dy)`).
    table: Vec<u8>,
    records: Vec<Record>,
    /// The vertices whose records this session wrote, each listed when its record first
    /// left `g = rhs = inf` (a vertex can be listed again after returning there). The list
    /// holds at most as many entries as there are vertices; past that, `touched_all` says
    /// the whole array is cleared at the next session instead.
    touched: Vec<u32>,
    touched_all: bool,
    queue: KeyedQueue,
    root: u32,
    target: u32,
    /// The target's padded coordinates.
    target_xy: (u32, u32),
    /// On a weighted map: each padded cell's weight (0 on the border), else empty.
    weights: Vec<u16>,
    /// The weighted move cost's factors ([`planner_api::CostRule::factors`]) for the cell a
    /// path leaves and the cell it enters.
    factors: (u64, u64),
    /// Whether a path runs from the target to the root (D* Lite: the agent drives toward
    /// the goal) rather than from the root to the target (LPA*): which end of an edge is
    /// left and which entered, for a rule that is not symmetric.
    toward_root: bool,
    /// What the heuristic is multiplied by: the smallest weight of the map when the
    /// session began (1 unweighted), a lower bound of every weight during the session.
    h_weight: u64,
    km: u64,
    /// Whether the per-cell state is sized and the root queued for this session.
    initialized: bool,
    stats: RepairStats,
    /// Scratch list of the vertices a batch of changes touches.
    affected: Vec<u32>,
    /// The revision of the grid the map was last made a copy of by [`Engine::reset`] (none
    /// once [`Engine::apply`] changed the map): a later revision of that grid edited in
    /// place lists its changed cells ([`Grid::changed_since`]).
    synced: Option<u64>,
}

impl Engine {
    /// An engine for 8 moves without corner cutting (`eight`) or 4 moves.
    pub fn new(eight: bool) -> Engine {
        Engine {
            eight,
            grid: None,
            width: 0,
            height: 0,
            stride: 2,
            bits: Vec::new(),
            steps: [Step::default(); 8],
            table: move_table(eight),
            records: Vec::new(),
            touched: Vec::new(),
            touched_all: false,
            queue: KeyedQueue::default(),
            root: 0,
            target: 0,
            target_xy: (0, 0),
            weights: Vec::new(),
            factors: (0, 0),
            toward_root: false,
            h_weight: 1,
            km: 0,
            initialized: false,
            stats: RepairStats::default(),
            affected: Vec::new(),
            synced: None,
        }
    }

    /// This engine for paths that run from the target to the root (`true`: D* Lite, whose
    /// agent drives toward the goal at the root) or from the root to the target (`false`,
    /// the default: LPA*). Only a move cost rule that is not symmetric
    /// ([`planner_api::CostRule::Entered`]) tells them apart.
    pub fn with_paths_to_root(mut self, toward_root: bool) -> Engine {
        self.toward_root = toward_root;
        self
    }

    /// The padded index of `cell`.
    fn vertex(&self, cell: Cell) -> u32 {
        (cell.y + 1) * self.stride + cell.x + 1
    }

    /// The padded coordinates of vertex `v`.
    fn xy(&self, v: u32) -> (u32, u32) {
        let y = v / self.stride;
        (v - y * self.stride, y)
    }

    /// The grid cell of vertex `v` (not on the border).
    fn cell_of(&self, v: u32) -> Cell {
        let (x, y) = self.xy(v);
        Cell::new(x - 1, y - 1)
    }

    /// Begins a session on a copy of `grid`, rooted at `root`, towards `target`. Both are
    /// cells of `grid` (the caller validated them). Searches nothing.
    ///
    /// When the engine's map has `grid`'s size and weights (a planner kept across runs on
    /// one map, as a robot keeps its planner), the copy is brought up to date in place:
    /// the free flags are compared a block at a time and only the cells that differ are
    /// written, so a reset costs a comparison of the maps rather than a new copy of both
    /// (the per-cell search state is cleared where the last session wrote it, when the
    /// next search begins). When `grid` is the grid of the last reset edited in place
    /// since ([`Grid::changed_since`]; and no [`Engine::apply`] between), only the edited
    /// cells are written, weights included.
    pub fn reset(&mut self, grid: &Grid, root: Cell, target: Cell) {
        // The cells edited since the map was a copy of `grid`, if it was.
        let logged: Option<Vec<Cell>> = match (&self.grid, self.synced) {
            (Some(old), Some(revision))
                if (old.width(), old.height()) == (grid.width(), grid.height()) =>
            {
                grid.changed_since(revision).map(Iterator::collect)
            }
            _ => None,
        };
        let same_shape = logged.is_some()
            || self.grid.as_ref().is_some_and(|old| {
                old.width() == grid.width()
                    && old.height() == grid.height()
                    && old.weights() == grid.weights()
            });
        self.width = grid.width();
        self.height = grid.height();
        self.stride = self.width.saturating_add(2);
        let stride = self.stride as isize;
        for (step, &(dx, dy, cost)) in self.steps.iter_mut().zip(&MOVES) {
            let (sx, sy) = (dx as isize, dy as isize * stride);
            *step = Step {
                offset: sx + sy,
                dx,
                dy,
                cost,
            };
        }
        // The padded map (its memory reused when the size is unchanged); left empty for a
        // grid whose padded cells overflow the 32-bit vertex indices, which compute
        // refuses.
        let padded = u64::from(self.stride) * (u64::from(self.height) + 2);
        let fits = padded <= u64::from(u32::MAX);
        match self.grid.as_mut() {
            Some(old) if same_shape && fits && self.bits.len() == bits_len(padded) => {
                let (w, stride) = (self.width as usize, self.stride as usize);
                if let Some(cells) = logged {
                    for cell in cells {
                        let v = (cell.y as usize + 1) * stride + cell.x as usize + 1;
                        if old.is_free(cell) != grid.is_free(cell) {
                            old.set_free(cell, grid.is_free(cell));
                            set_bit(&mut self.bits, v, grid.is_free(cell));
                        }
                        if old.weight(cell) != grid.weight(cell) {
                            old.set_weight(cell, grid.weight(cell));
                            if let Some(slot) = self.weights.get_mut(v) {
                                *slot = grid.weight(cell);
                            }
                        }
                    }
                    debug_assert!(old == grid);
                } else {
                    const BLOCK: usize = 256;
                    for (b, block) in grid.free_cells().chunks(BLOCK).enumerate() {
                        let base = b * BLOCK;
                        if old.free_cells()[base..base + block.len()] == *block {
                            continue;
                        }
                        for (j, &free) in block.iter().enumerate() {
                            let i = base + j;
                            if old.free_cells()[i] != free {
                                let cell = old.cell(i);
                                old.set_free(cell, free);
                                set_bit(&mut self.bits, (i / w + 1) * stride + i % w + 1, free);
                            }
                        }
                    }
                }
            }
            _ => {
                self.grid = Some(grid.clone());
                if fits {
                    // Blocked everywhere, then the free cells set.
                    self.bits.clear();
                    self.bits.resize(bits_len(padded), 0);
                    let (w, stride) = (self.width as usize, self.stride as usize);
                    for (y, row) in grid.free_cells().chunks(w.max(1)).enumerate() {
                        let at = (y + 1) * stride + 1;
                        for (x, &free) in row.iter().enumerate() {
                            if free {
                                set_bit(&mut self.bits, at + x, true);
                            }
                        }
                    }
                } else {
                    self.bits = Vec::new();
                }
                self.load_weights();
            }
        }
        self.synced = Some(grid.revision());
        self.root = self.vertex(root);
        self.target = self.vertex(target);
        self.target_xy = self.xy(self.target);
        self.km = 0;
        self.initialized = false;
        self.stats = RepairStats::default();
    }

    /// Copies the map's weights into the padded layout (none on an unweighted map or one
    /// too large for it).
    fn load_weights(&mut self) {
        self.weights.clear();
        self.factors = (0, 0);
        let Some(weights) = self.grid.as_ref().and_then(Grid::weights) else {
            return;
        };
        if self.bits.is_empty() {
            return;
        }
        self.factors = weights.rule().factors();
        let (w, stride) = (self.width as usize, self.stride as usize);
        self.weights.resize(stride * (self.height as usize + 2), 0);
        for (y, row) in weights.cells().chunks(w.max(1)).enumerate() {
            let at = (y + 1) * stride + 1;
            self.weights[at..at + row.len()].copy_from_slice(row);
        }
    }

    /// The cost of the edge between `far` and its neighbour `near` (nearer the root) by move
    /// `step` from `near` to `far` or back: the move's length unweighted, else the weighted
    /// cost of travelling it the way paths run ([`Engine::with_paths_to_root`]).
    #[inline(always)]
    fn edge(&self, step: &Step, far: usize, near: usize) -> u64 {
        if self.weights.is_empty() {
            return step.cost;
        }
        let (from, to) = if self.toward_root {
            (far, near)
        } else {
            (near, far)
        };
        let (k_from, k_to) = self.factors;
        let factor = k_from * u64::from(self.weights[from]) + k_to * u64::from(self.weights[to]);
        (step.cost / 2).saturating_mul(factor)
    }

    /// The current map.
    pub fn grid(&self) -> Option<&Grid> {
        self.grid.as_ref()
    }

    /// The root cell.
    pub fn root(&self) -> Option<Cell> {
        self.grid.as_ref().map(|_| self.cell_of(self.root))
    }

    /// The target cell.
    pub fn target(&self) -> Option<Cell> {
        self.grid.as_ref().map(|_| self.cell_of(self.target))
    }

    /// The key modifier `km` in [`Cost`] units.
    pub fn km(&self) -> Cost {
        Cost::from_units(self.km)
    }

    /// Moves the root to `cell` by starting the search over (LPA*'s answer to a moved
    /// start: its g-values are distances from the old start).
    pub fn move_root(&mut self, cell: Cell) {
        if self.grid.is_some() {
            let v = self.vertex(cell);
            if v != self.root {
                self.root = v;
                self.initialized = false;
            }
        }
    }

    /// Moves the target to `cell`, D* Lite's way: `km += h(old target, new target)`, so
    /// that the keys already queued stay lower bounds without re-keying them all.
    pub fn move_target(&mut self, cell: Cell) {
        if self.grid.is_some() {
            let v = self.vertex(cell);
            if v != self.target {
                let xy = self.xy(v);
                if self.initialized {
                    self.km = self.km.saturating_add(self.h(xy, self.target_xy));
                }
                self.target = v;
                self.target_xy = xy;
            }
        }
    }

    /// Applies changed cells (each in the map, and a weight only on a weighted map and not
    /// 0: checked by the caller, [`crate::checked_changes`]) and re-queues the vertices
    /// whose edges changed. Before the first search only the map changes.
    ///
    /// A weight below the one the session's heuristic is multiplied by (the map's smallest
    /// when the session began) would make the heuristic overestimate: the session then
    /// ends, and the next [`Engine::compute`] searches from scratch with the new smallest
    /// weight.
    pub fn apply(&mut self, changes: &[CellChange]) {
        let Some(grid) = self.grid.as_mut() else {
            return;
        };
        // The map is no longer a copy of the grid of the last reset.
        self.synced = None;
        self.affected.clear();
        let (width, height, stride) = (self.width, self.height, self.stride);
        let padded = !self.bits.is_empty();
        for change in changes {
            let cell = change.cell;
            let v = (cell.y + 1) * stride + cell.x + 1;
            let mut changed = false;
            if let Some(weight) = change.weight.filter(|&w| w > 0) {
                if grid.is_weighted() && grid.weight(cell) != weight {
                    grid.set_weight(cell, weight);
                    if let Some(slot) = self.weights.get_mut(v as usize) {
                        *slot = weight;
                    }
                    if u64::from(weight) < self.h_weight {
                        self.initialized = false;
                    }
                    changed = true;
                }
            }
            if grid.is_free(cell) != change.free {
                grid.set_free(cell, change.free);
                if padded {
                    set_bit(&mut self.bits, v as usize, change.free);
                }
                changed = true;
            }
            if !changed {
                continue;
            }
            for dy in -1..=1i64 {
                for dx in -1..=1i64 {
                    if !self.eight && dx != 0 && dy != 0 {
                        continue;
                    }
                    let (nx, ny) = (i64::from(cell.x) + dx, i64::from(cell.y) + dy);
                    if nx >= 0 && ny >= 0 && nx < i64::from(width) && ny < i64::from(height) {
                        self.affected
                            .push(((ny + 1) * i64::from(stride) + nx + 1) as u32);
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
                self.update_vertex(u, self.xy(u));
            }
        }
        self.affected = affected;
    }

    /// The counters since the last call, which zeroes them.
    pub fn take_stats(&mut self) -> RepairStats {
        std::mem::take(&mut self.stats)
    }

    /// Sizes the per-cell state for a new session; the shortfall when
    /// they do not fit the budget (or the engine's 32-bit vertex indices).
    fn begin_session(&mut self, budget: &Budget) -> Result<(), MemoryShortfall> {
        let Some(grid) = self.grid.as_ref() else {
            return Ok(());
        };
        let padded = u64::from(self.stride) * (u64::from(self.height) + 2);
        // A weighted map's padded weights: two bytes a cell more.
        let per_cell = BYTES_PER_CELL + if grid.is_weighted() { 2 } else { 0 };
        let needed = per_cell.saturating_mul(padded);
        budget.check_memory(needed, grid)?;
        self.h_weight = grid.weights().map_or(1, |w| u64::from(w.min()));
        if padded > u64::from(u32::MAX) {
            // Vertices and queue positions are 32-bit: at most 2^32 - 1 padded cells.
            return Err(MemoryShortfall {
                needed_bytes: needed,
                max_memory_mb: (BYTES_PER_CELL * u64::from(u32::MAX)) >> 20,
                width: self.width,
                height: self.height,
            });
        }
        let n = padded as usize;
        if self.records.len() != n {
            self.records = vec![[0; 2]; n];
        } else if self.touched_all {
            self.records.fill([0; 2]);
        } else {
            // Only the records the last session wrote differ from `inf`: a reset costs
            // that session's work, not the map's size.
            for &v in &self.touched {
                self.records[v as usize] = [0; 2];
            }
        }
        self.touched.clear();
        self.touched_all = false;
        // The queue forgets the old session's vertices.
        self.queue.reset(n);
        Ok(())
    }

    /// ComputeShortestPath within `budget` (its expansion and time limits; the memory
    /// limit when the per-cell state is first sized).
    pub fn compute(&mut self, budget: &Budget) -> Computed {
        if self.grid.is_none() {
            return Computed::Done;
        }
        if !self.initialized {
            if let Err(shortfall) = self.begin_session(budget) {
                return Computed::OverMemory(shortfall);
            }
            self.km = 0;
            self.initialized = true;
            let root = self.root;
            let value = self.fresh_rhs(root);
            self.set_rhs(root, value);
            self.update_vertex(root, self.xy(root));
        }
        let mut clock = budget.start();
        let mut expanded = 0u64;
        let t = self.target as usize;
        let steps = self.steps;
        while let Some((k1, k2, u)) = self.queue.top() {
            let ui = u as usize;
            let record = self.records[ui].map(|stored| !stored);
            // key(target): h(target, target) = 0.
            let (g_t, rhs_t) = (self.g_of(t), self.rhs_of(t));
            let m_t = g_t.min(rhs_t);
            if (k1, k2) >= (m_t.saturating_add(self.km), m_t) && rhs_t == g_t {
                break;
            }
            let (g_u, rhs_u) = (record[0], record[1]);
            let xy = self.xy(u);
            let new_key = self.key_with(g_u.min(rhs_u), xy);
            if (k1, k2) < new_key {
                self.queue.rekey_top(new_key.0, new_key.1);
                self.stats.heap_updates += 1;
                continue;
            }
            if !clock.allows(expanded) {
                return Computed::Exhausted;
            }
            expanded += 1;
            self.stats.expanded += 1;
            if g_u > rhs_u {
                self.queue.pop_top();
                self.stats.heap_pops += 1;
                self.records[ui][0] = !rhs_u;
                let mut legal = self.legal(ui);
                while legal != 0 {
                    let step = steps[legal.trailing_zeros() as usize];
                    legal &= legal - 1;
                    let s = ui.wrapping_add_signed(step.offset);
                    if s == self.root as usize {
                        continue;
                    }
                    let through = via(self.edge(&step, s, ui), rhs_u);
                    if through < self.rhs_of(s) {
                        self.set_rhs(s as u32, through);
                        let sxy = (
                            xy.0.wrapping_add_signed(step.dx),
                            xy.1.wrapping_add_signed(step.dy),
                        );
                        self.update_vertex(s as u32, sxy);
                    }
                }
            } else {
                self.records[ui][0] = !INF;
                let mut legal = self.legal(ui);
                while legal != 0 {
                    let step = steps[legal.trailing_zeros() as usize];
                    legal &= legal - 1;
                    let s = ui.wrapping_add_signed(step.offset);
                    if s != self.root as usize
                        && self.rhs_of(s) == via(self.edge(&step, s, ui), g_u)
                    {
                        let value = self.fresh_rhs(s as u32);
                        if self.set_rhs(s as u32, value) {
                            let sxy = (
                                xy.0.wrapping_add_signed(step.dx),
                                xy.1.wrapping_add_signed(step.dy),
                            );
                            self.update_vertex(s as u32, sxy);
                        }
                    }
                }
                // u's own rhs does not depend on its g; it stays queued with its new key
                // (it may no longer be on top) or leaves the queue, counted as the pop
                // of the least.
                if rhs_u != INF {
                    let (k1, k2) = self.key_with(rhs_u, xy);
                    self.queue.update(k1, k2, u);
                    self.stats.heap_updates += 1;
                } else {
                    self.queue.remove(u);
                    self.stats.heap_pops += 1;
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
        let distance = self.target_distance()?;
        let mut at = self.cell_of(self.target);
        // Every move costs at least one, so the path has at most `distance + 1` cells.
        let most = (distance.units() / Cost::ONE.units()).saturating_add(1);
        let mut cells = Vec::with_capacity((most as usize).min(grid.len()));
        cells.push(at);
        let mut u = self.target as usize;
        while u != self.root as usize {
            if cells.len() > grid.len() {
                return None;
            }
            // The least c + g, the first of equal ones in move order (strict <). That
            // least is rhs(u) (rhs is kept equal to it for every vertex but the root), so
            // the first neighbour that reaches it is the one: the scan stops there.
            let least = self.rhs_of(u);
            let (mut best, mut best_k) = (INF, 8usize);
            let mut legal = self.legal(u);
            while legal != 0 {
                let k = legal.trailing_zeros() as usize;
                legal &= legal - 1;
                let step = &self.steps[k];
                let s = u.wrapping_add_signed(step.offset);
                let through = via(self.edge(step, u, s), self.g_of(s));
                if through < best {
                    (best, best_k) = (through, k);
                    if through == least {
                        break;
                    }
                }
            }
            let step = self.steps.get(best_k)?;
            u = u.wrapping_add_signed(step.offset);
            at = Cell::new(
                at.x.wrapping_add_signed(step.dx),
                at.y.wrapping_add_signed(step.dy),
            );
            cells.push(at);
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

    #[inline]
    fn g_of(&self, i: usize) -> u64 {
        !self.records[i][0]
    }

    #[inline]
    fn rhs_of(&self, i: usize) -> u64 {
        !self.records[i][1]
    }

    /// Sets `rhs(u)`; whether it changed. A record leaving `g = rhs = inf` is listed for
    /// the next session's reset.
    #[inline]
    fn set_rhs(&mut self, u: u32, value: u64) -> bool {
        let i = u as usize;
        let record = self.records[i];
        if !record[1] == value {
            return false;
        }
        if record == [0; 2] {
            if self.touched.len() < self.records.len() {
                self.touched.push(u);
            } else {
                self.touched_all = true;
            }
        }
        self.records[i][1] = !value;
        self.stats.rhs_changes += 1;
        true
    }

    /// `rhs(u)` from scratch: 0 at a free root, else the least `c(u, s) + g(s)`.
    fn fresh_rhs(&self, u: u32) -> u64 {
        let ui = u as usize;
        if self
            .bits
            .get(ui / 8)
            .is_none_or(|&byte| byte >> (ui % 8) & 1 == 0)
        {
            return INF;
        }
        if u == self.root {
            return 0;
        }
        let mut best = INF;
        let mut legal = self.legal(ui);
        while legal != 0 {
            let step = &self.steps[legal.trailing_zeros() as usize];
            legal &= legal - 1;
            let s = ui.wrapping_add_signed(step.offset);
            best = best.min(via(self.edge(step, ui, s), self.g_of(s)));
        }
        best
    }

    /// The moves from interior vertex `u`, a bit per move of [`MOVES`] (in their order):
    /// its 3 x 3 block of the padded map looked up in the move table.
    #[inline]
    fn legal(&self, u: usize) -> u8 {
        let (bits, w) = (&self.bits[..], self.stride as usize);
        // Three bits from bit `at` on: one range check and one two-byte load (out of
        // range cannot happen for an interior vertex, two bytes of slack; it reads as
        // blocked).
        let three = |at: usize| match bits.get(at / 8..at / 8 + 2) {
            Some(&[low, high]) => usize::from(u16::from_le_bytes([low, high])) >> (at % 8) & 7,
            _ => 0,
        };
        let code = three(u - w - 1) | three(u - 1) << 3 | three(u + w - 1) << 6;
        self.table.get(code).copied().unwrap_or(0)
    }

    /// `key = [m + h(xy, target) + km; m]` for `m = min(g, rhs)` of the vertex at `xy`.
    #[inline]
    fn key_with(&self, m: u64, xy: (u32, u32)) -> (u64, u64) {
        (
            m.saturating_add(self.h(xy, self.target_xy))
                .saturating_add(self.km),
            m,
        )
    }

    /// UpdateVertex: queues `u` (at padded coordinates `xy`) with its current key when it
    /// is inconsistent, else takes it out of the queue.
    fn update_vertex(&mut self, u: u32, xy: (u32, u32)) {
        let i = u as usize;
        let [g, rhs] = self.records[i].map(|stored| !stored);
        let queued = self.queue.contains(u);
        if g != rhs {
            let (k1, k2) = self.key_with(g.min(rhs), xy);
            if queued {
                self.queue.update(k1, k2, u);
                self.stats.heap_updates += 1;
            } else {
                self.queue.push(k1, k2, u);
                self.stats.heap_pushes += 1;
            }
        } else if queued {
            self.queue.remove(u);
            self.stats.heap_removes += 1;
        }
    }

    /// The heuristic between two padded coordinates: Manhattan (4 moves) or octile (8),
    /// exact, times the session's smallest weight on a weighted map (every move costs at
    /// least its length times it, so the heuristic stays consistent).
    #[inline]
    fn h(&self, a: (u32, u32), b: (u32, u32)) -> u64 {
        let (dx, dy) = (a.0.abs_diff(b.0), a.1.abs_diff(b.1));
        let length = if self.eight {
            Cost::octile_distance(dx, dy).units()
        } else {
            Cost::steps(u64::from(dx) + u64::from(dy)).units()
        };
        if self.weights.is_empty() {
            length
        } else {
            length.saturating_mul(self.h_weight)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn grid(text: &str) -> Grid {
        Grid::from_ascii(text).unwrap()
    }

    /// A search from `root` to `target` on `grid` by `engine`: g(target) and the counters.
    fn search(
        engine: &mut Engine,
        grid: &Grid,
        root: Cell,
        target: Cell,
    ) -> (Option<Cost>, RepairStats) {
        engine.reset(grid, root, target);
        assert_eq!(engine.compute(&Budget::unlimited()), Computed::Done);
        (engine.target_distance(), engine.take_stats())
    }

    /// A kept engine's sessions give what a fresh engine gives, whether the reset clears
    /// the listed records or, after the list filled, the whole array.
    #[test]
    fn a_kept_engine_searches_as_a_fresh_one() {
        let map = grid(
            "
            ......
            .##...
            ...#..
            ......",
        );
        let cells: Vec<Cell> = (0..map.len())
            .map(|i| map.cell(i))
            .filter(|&c| map.is_free(c))
            .collect();
        let mut kept = Engine::new(true);
        let mut filled = false;
        for (k, &root) in cells.iter().enumerate() {
            let target = cells[(k * 7 + 3) % cells.len()];
            // Toggling a cell beside the root many times in one session lists its record
            // again each time it returns from infinite: the list fills.
            kept.reset(&map, root, target);
            assert_eq!(kept.compute(&Budget::unlimited()), Computed::Done);
            if k % 5 == 0 {
                let toggled = cells[(k + 1) % cells.len()];
                for round in 0..2 * kept.records.len() {
                    kept.apply(&[CellChange {
                        cell: toggled,
                        free: round % 2 == 1,
                        weight: None,
                    }]);
                    assert_eq!(kept.compute(&Budget::unlimited()), Computed::Done);
                }
                filled |= kept.touched_all;
            }
            let again = search(&mut kept, &map, target, root);
            let fresh = search(&mut Engine::new(true), &map, target, root);
            assert_eq!(again, fresh, "root {root:?}, target {target:?}");
        }
        assert!(filled, "the whole-array clear was exercised");
    }
}
