//! [`ReferenceIncremental`]: LPA\* and D\* Lite written again from the papers and
//! planner-lpastar's engine docs, through map changes and moves of the start; and
//! [`reference_lpa`], its first search.

use std::collections::BTreeSet;

use planner_api::{
    Budget, Cell, CellChange, ChangeError, Connectivity, Cost, Counters, Grid, IncrementalPlanner,
    MoveSet, Outcome, Path, PathSpec, PlannerSpecs, Problem, Status,
};

/// The counters of [`reference_lpa`] and of every [`ReferenceIncremental`] replan, in their
/// order (`path_cost_units` only when found).
pub const LPA_COUNTERS: [&str; 7] = [
    "n_expanded",
    "n_heap_pushes",
    "n_heap_pops",
    "n_heap_updates",
    "n_heap_removes",
    "n_rhs_changes",
    "path_cost_units",
];

/// What [`reference_lpa`] found: status, the path from start to goal, and the counters
/// named in [`LPA_COUNTERS`] (the last only when found).
pub type LpaSearch = (Status, Option<Vec<Cell>>, Vec<u64>);

/// The moves in planner-lpastar's order: right, left, down, up, then the diagonals
/// (1, 1), (1, -1), (-1, 1), (-1, -1).
const MOVES: [(i64, i64); 8] = [
    (1, 0),
    (-1, 0),
    (0, 1),
    (0, -1),
    (1, 1),
    (1, -1),
    (-1, 1),
    (-1, -1),
];

const INF: u64 = u64::MAX;

// Places in [`ReferenceIncremental`]'s counts, in [`LPA_COUNTERS`]' order.
const EXPANDED: usize = 0;
const PUSHES: usize = 1;
const POPS: usize = 2;
const UPDATES: usize = 3;
const REMOVES: usize = 4;
const RHS_CHANGES: usize = 5;

/// The first search of LPA\* (from `start`) or D\* Lite (`dstar`, from `goal`) on `grid`:
/// [`ReferenceIncremental`] reset on the problem and replanned once, without limits.
/// `eight`: 8 moves without corner cutting, else 4. Panics on a start or goal outside the
/// grid or blocked (test input).
pub fn reference_lpa(grid: &Grid, eight: bool, start: Cell, goal: Cell, dstar: bool) -> LpaSearch {
    let problem = Problem::new(grid, start, goal)
        .unwrap_or_else(|e| panic!("reference_lpa: a bad problem: {e}"));
    let mut planner = ReferenceIncremental::new(dstar, eight);
    planner.reset(&problem);
    let outcome = planner.replan(&Budget::unlimited());
    let counters = LPA_COUNTERS
        .iter()
        .filter_map(|name| outcome.counters.get(name))
        .collect();
    let path = outcome.path.map(|path| path.cells().to_vec());
    (outcome.status, path, counters)
}

/// LPA\* (Koenig, Likhachev and Furcy 2004, Fig. 3: the root is the start, the target the
/// goal) or D\* Lite (Koenig and Likhachev 2002, Fig. 4: the root is the goal, the target
/// the agent's cell, `km` grows by `h` between the agent's old and new cell), as
/// planner-lpastar's engine documents them, written for clarity and not speed: `g` and
/// `rhs` in exact [`Cost`] units per cell, the queue U a `BTreeSet` of
/// `(k1, k2, row-major cell index)` with each queued vertex's key beside it.
///
/// - `key(s) = [min(g, rhs) + h(s, target) + km; min(g, rhs)]`, `h` Manhattan (4 moves) or
///   octile (8), times the grid's smallest weight when the session began.
/// - A move between cells `far` (away from the root) and `near` costs
///   [`Grid::move_cost`] travelled the way paths run: from `near` to `far` for LPA\*
///   (paths leave the root), from `far` to `near` for D\* Lite (paths reach it).
/// - ComputeShortestPath: while the least queued key is below `key(target)` or the target
///   is inconsistent: an out-of-date least key (below the vertex's key, after `km` grew)
///   is re-keyed (an update); else the vertex is expanded: overconsistent, `g = rhs` and it
///   leaves the queue (a pop), lowering its neighbours' `rhs` through it; underconsistent,
///   `g = inf`, every neighbour whose `rhs` came through it gets its `rhs` computed again,
///   and the vertex itself is re-keyed (an update) or, with `rhs = inf`, leaves the queue
///   (a pop).
/// - UpdateVertex runs for a vertex whose `rhs` changed (and the expanded one): inserted
///   (a push) or re-keyed (an update) when inconsistent, removed (a remove) when
///   consistent and queued. `rhs` changes count only when the value differs.
/// - A change that alters a cell (freed, blocked or reweighted) recomputes the `rhs` of
///   every cell of its 3 x 3 block (4 moves: itself and its four neighbours), once per
///   batch, after the whole batch is on the map (in any order: `rhs` depends on `g` alone,
///   which no change alters). A weight below the
///   session's heuristic weight ends the session: the next replan searches from scratch.
///   LPA\* moving its start starts a new session too.
/// - The path is traced from the target through the neighbour of least cost plus `g`, the
///   first in move order (right, left, down, up, then the diagonals).
///
/// Its counters are those of [`LPA_COUNTERS`], per replan; the budget's expansion limit is
/// honoured (checked before each expansion), its memory limit is not.
#[derive(Debug, Clone)]
pub struct ReferenceIncremental {
    dstar: bool,
    eight: bool,
    grid: Option<Grid>,
    root: Cell,
    target: Cell,
    km: u64,
    /// Whether a session's search state exists (its root was queued).
    searching: bool,
    h_weight: u64,
    g: Vec<u64>,
    rhs: Vec<u64>,
    queued: Vec<Option<(u64, u64)>>,
    queue: BTreeSet<(u64, u64, usize)>,
    /// `n_expanded` .. `n_rhs_changes` of the current replan.
    counts: [u64; 6],
}

impl ReferenceIncremental {
    /// D\* Lite (`dstar`) or LPA\*, 8 moves without corner cutting (`eight`) or 4.
    pub fn new(dstar: bool, eight: bool) -> ReferenceIncremental {
        ReferenceIncremental {
            dstar,
            eight,
            grid: None,
            root: Cell::new(0, 0),
            target: Cell::new(0, 0),
            km: 0,
            searching: false,
            h_weight: 1,
            g: Vec::new(),
            rhs: Vec::new(),
            queued: Vec::new(),
            queue: BTreeSet::new(),
            counts: [0; 6],
        }
    }

    fn map(&self) -> &Grid {
        self.grid
            .as_ref()
            .unwrap_or_else(|| panic!("ReferenceIncremental used before reset"))
    }

    fn index(&self, cell: Cell) -> usize {
        cell.y as usize * self.map().width() as usize + cell.x as usize
    }

    /// The cells a move from `cell` reaches, in move order: free, and on a diagonal both
    /// side cells free. None from a blocked cell.
    fn neighbours(&self, cell: Cell) -> Vec<Cell> {
        let grid = self.map();
        let free = |x: i64, y: i64| {
            x >= 0
                && y >= 0
                && x < i64::from(grid.width())
                && y < i64::from(grid.height())
                && grid.is_free(Cell::new(x as u32, y as u32))
        };
        let (x, y) = (i64::from(cell.x), i64::from(cell.y));
        if !free(x, y) {
            return Vec::new();
        }
        let n_moves = if self.eight { 8 } else { 4 };
        MOVES[..n_moves]
            .iter()
            .filter(|&&(dx, dy)| {
                free(x + dx, y + dy) && (dx == 0 || dy == 0 || (free(x + dx, y) && free(x, y + dy)))
            })
            .map(|&(dx, dy)| Cell::new((x + dx) as u32, (y + dy) as u32))
            .collect()
    }

    /// The cost of the edge between `far` and its neighbour `near`, the way paths run.
    fn edge(&self, far: Cell, near: Cell) -> u64 {
        let (from, to) = match self.dstar {
            true => (far, near),
            false => (near, far),
        };
        self.map().move_cost(from, to).units()
    }

    fn h(&self, a: Cell, b: Cell) -> u64 {
        let (dx, dy) = (a.x.abs_diff(b.x), a.y.abs_diff(b.y));
        let length = match self.eight {
            true => Cost::octile_distance(dx, dy).units(),
            false => Cost::steps(u64::from(dx) + u64::from(dy)).units(),
        };
        length.saturating_mul(self.h_weight)
    }

    fn key(&self, cell: Cell) -> (u64, u64) {
        let i = self.index(cell);
        let least = self.g[i].min(self.rhs[i]);
        (
            least
                .saturating_add(self.h(cell, self.target))
                .saturating_add(self.km),
            least,
        )
    }

    /// `rhs` from its definition: infinite at a blocked cell, 0 at the root, else the
    /// least edge cost plus `g` over the neighbours.
    fn fresh_rhs(&self, cell: Cell) -> u64 {
        if !self.map().is_free(cell) {
            return INF;
        }
        if cell == self.root {
            return 0;
        }
        self.neighbours(cell)
            .into_iter()
            .map(|s| self.edge(cell, s).saturating_add(self.g[self.index(s)]))
            .min()
            .unwrap_or(INF)
    }

    /// Sets `rhs(cell)` and counts the change; whether the value differed.
    fn set_rhs(&mut self, cell: Cell, value: u64) -> bool {
        let i = self.index(cell);
        if self.rhs[i] == value {
            return false;
        }
        self.rhs[i] = value;
        self.counts[RHS_CHANGES] += 1;
        true
    }

    fn enqueue(&mut self, cell: Cell) {
        let i = self.index(cell);
        if let Some((k1, k2)) = self.queued[i].take() {
            self.queue.remove(&(k1, k2, i));
        }
        let (k1, k2) = self.key(cell);
        self.queue.insert((k1, k2, i));
        self.queued[i] = Some((k1, k2));
    }

    fn dequeue(&mut self, cell: Cell) {
        let i = self.index(cell);
        if let Some((k1, k2)) = self.queued[i].take() {
            self.queue.remove(&(k1, k2, i));
        }
    }

    /// UpdateVertex.
    fn update_vertex(&mut self, cell: Cell) {
        let i = self.index(cell);
        let queued = self.queued[i].is_some();
        if self.g[i] != self.rhs[i] {
            self.counts[if queued { UPDATES } else { PUSHES }] += 1;
            self.enqueue(cell);
        } else if queued {
            self.counts[REMOVES] += 1;
            self.dequeue(cell);
        }
    }

    /// A new session: every `g` and `rhs` infinite, the queue empty, `km = 0`, the
    /// heuristic's weight the map's smallest, and the root's `rhs` set and queued.
    fn begin_session(&mut self) {
        let n = self.map().len();
        self.h_weight = self.map().weights().map_or(1, |w| u64::from(w.min()));
        self.g = vec![INF; n];
        self.rhs = vec![INF; n];
        self.queued = vec![None; n];
        self.queue.clear();
        self.km = 0;
        self.searching = true;
        let root = self.root;
        let value = self.fresh_rhs(root);
        if self.set_rhs(root, value) {
            self.update_vertex(root);
        }
    }

    /// ComputeShortestPath; false when the budget stopped it.
    fn compute(&mut self, budget: &Budget) -> bool {
        let mut clock = budget.start();
        let mut expanded = 0;
        let t = self.index(self.target);
        let width = self.map().width() as usize;
        while let Some(&(k1, k2, i)) = self.queue.first() {
            let target_least = self.g[t].min(self.rhs[t]);
            let target_key = (target_least.saturating_add(self.km), target_least);
            if (k1, k2) >= target_key && self.g[t] == self.rhs[t] {
                break;
            }
            let u = Cell::new((i % width) as u32, (i / width) as u32);
            if (k1, k2) < self.key(u) {
                self.counts[UPDATES] += 1;
                self.enqueue(u);
                continue;
            }
            if !clock.allows(expanded) {
                return false;
            }
            expanded += 1;
            self.counts[EXPANDED] += 1;
            if self.g[i] > self.rhs[i] {
                self.counts[POPS] += 1;
                self.dequeue(u);
                self.g[i] = self.rhs[i];
                for s in self.neighbours(u) {
                    if s == self.root {
                        continue;
                    }
                    let through = self.edge(s, u).saturating_add(self.g[i]);
                    if through < self.rhs[self.index(s)] {
                        self.set_rhs(s, through);
                        self.update_vertex(s);
                    }
                }
            } else {
                let g_old = self.g[i];
                self.g[i] = INF;
                for s in self.neighbours(u) {
                    let came_through =
                        self.rhs[self.index(s)] == self.edge(s, u).saturating_add(g_old);
                    if s != self.root && came_through {
                        let value = self.fresh_rhs(s);
                        if self.set_rhs(s, value) {
                            self.update_vertex(s);
                        }
                    }
                }
                if self.rhs[i] != INF {
                    self.counts[UPDATES] += 1;
                    self.enqueue(u);
                } else {
                    self.counts[POPS] += 1;
                    self.dequeue(u);
                }
            }
        }
        true
    }

    /// The path traced from the target to the root (module docs), in that order.
    fn trace(&self) -> Option<Vec<Cell>> {
        let mut cells = vec![self.target];
        let mut at = self.target;
        while at != self.root {
            if cells.len() > self.map().len() {
                return None;
            }
            let mut best: Option<(u64, Cell)> = None;
            for s in self.neighbours(at) {
                let through = self.edge(at, s).saturating_add(self.g[self.index(s)]);
                if through != INF && best.is_none_or(|(b, _)| through < b) {
                    best = Some((through, s));
                }
            }
            at = best?.1;
            cells.push(at);
        }
        Some(cells)
    }
}

impl IncrementalPlanner for ReferenceIncremental {
    fn name(&self) -> &str {
        match self.dstar {
            true => "reference_dstar_lite",
            false => "reference_lpastar",
        }
    }

    fn specs(&self) -> PlannerSpecs {
        let moves = MoveSet::standard(match self.eight {
            true => Connectivity::Eight,
            false => Connectivity::Four,
        });
        PlannerSpecs::deterministic(PathSpec::Moves(moves))
            .with_admissible(true)
            .with_incremental()
            .with_cell_costs()
    }

    fn reset(&mut self, problem: &Problem<'_>) {
        (self.root, self.target) = match self.dstar {
            true => (problem.goal(), problem.start()),
            false => (problem.start(), problem.goal()),
        };
        self.grid = Some(problem.grid().clone());
        self.km = 0;
        self.searching = false;
        self.counts = [0; 6];
    }

    fn grid(&self) -> Option<&Grid> {
        self.grid.as_ref()
    }

    fn start(&self) -> Option<Cell> {
        self.grid.as_ref()?;
        Some(if self.dstar { self.target } else { self.root })
    }

    fn move_start(&mut self, cell: Cell) -> Result<(), ChangeError> {
        let grid = self.grid.as_ref().ok_or(ChangeError::NotStarted)?;
        if !grid.contains(cell) || !grid.is_free(cell) {
            return Err(ChangeError::BadStart { cell });
        }
        if self.dstar {
            if cell != self.target && self.searching {
                self.km = self.km.saturating_add(self.h(cell, self.target));
            }
            self.target = cell;
        } else if cell != self.root {
            self.root = cell;
            self.searching = false;
        }
        Ok(())
    }

    /// Precondition: valid changes (cells in the map, weights only on a weighted map and
    /// never 0), as the drivers send them; the planners' checks of bad ones are theirs.
    fn apply(&mut self, changes: &[CellChange]) -> Result<(), ChangeError> {
        let grid = self.grid.as_mut().ok_or(ChangeError::NotStarted)?;
        let mut affected = BTreeSet::new();
        for c in changes {
            let mut changed = false;
            if let Some(weight) = c.weight {
                if grid.weight(c.cell) != weight {
                    grid.set_weight(c.cell, weight);
                    if u64::from(weight) < self.h_weight {
                        self.searching = false;
                    }
                    changed = true;
                }
            }
            if grid.is_free(c.cell) != c.free {
                grid.set_free(c.cell, c.free);
                changed = true;
            }
            if changed {
                for (dx, dy) in [(0, 0)].into_iter().chain(MOVES) {
                    let (x, y) = (i64::from(c.cell.x) + dx, i64::from(c.cell.y) + dy);
                    let diagonal = dx != 0 && dy != 0;
                    let inside = x >= 0
                        && y >= 0
                        && x < i64::from(grid.width())
                        && y < i64::from(grid.height());
                    if inside && (self.eight || !diagonal) {
                        // Row-major order: (y, x).
                        affected.insert((y as u32, x as u32));
                    }
                }
            }
        }
        if self.searching {
            for (y, x) in affected {
                let cell = Cell::new(x, y);
                let value = self.fresh_rhs(cell);
                if self.set_rhs(cell, value) {
                    self.update_vertex(cell);
                }
            }
        }
        Ok(())
    }

    fn replan(&mut self, budget: &Budget) -> Outcome {
        if self.grid.is_none() {
            return Outcome::no_path(Counters::new());
        }
        if !self.searching {
            self.begin_session();
        }
        let finished = self.compute(budget);
        let counts = std::mem::take(&mut self.counts);
        let mut counters = Counters::new();
        for (&name, value) in LPA_COUNTERS.iter().zip(counts) {
            counters = counters.with(name, value);
        }
        if !finished {
            return Outcome::budget_exhausted(None, counters);
        }
        let distance = self.g[self.index(self.target)];
        match (distance != INF).then(|| self.trace()).flatten() {
            Some(mut cells) => {
                counters.push("path_cost_units", distance);
                if !self.dstar {
                    cells.reverse();
                }
                Outcome::found(Path::new(cells), counters)
            }
            None => Outcome::no_path(counters),
        }
    }
}
