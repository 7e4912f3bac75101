//! [`reference_bidirectional_astar`]: bidirectional A\* written again for clarity.

use std::cmp::Reverse;
use std::collections::BinaryHeap;

use planner_api::{Cell, Connectivity, Cost, Grid, MoveSet, NeighborOrder, Status};

/// What [`reference_bidirectional_astar`] found: status, path, and the counters by name in
/// planner-bidirectional_astar's order (the totals, `forward_*`, `backward_*`,
/// `n_meeting_updates`).
pub type BidirectionalSearch = (Status, Option<Vec<Cell>>, Vec<(String, u64)>);

/// A path cost as the planner keeps it: `f64` on a grid without weights, exact [`Cost`]
/// units on a weighted one.
trait Scalar: Copy + PartialOrd {
    const ZERO: Self;
    const INFINITY: Self;
    fn add(self, other: Self) -> Self;
    /// A key that orders as the value does (non-negative values).
    fn key(self) -> u64;
}

impl Scalar for f64 {
    const ZERO: f64 = 0.0;
    const INFINITY: f64 = f64::INFINITY;
    fn add(self, other: f64) -> f64 {
        self + other
    }
    fn key(self) -> u64 {
        self.to_bits()
    }
}

impl Scalar for u64 {
    const ZERO: u64 = 0;
    const INFINITY: u64 = u64::MAX;
    fn add(self, other: u64) -> u64 {
        self.saturating_add(other)
    }
    fn key(self) -> u64 {
        self
    }
}

/// planner-bidirectional_astar's search as its crate docs define it, written for clarity
/// and not speed: two A\* searches over planner-api's [`MoveSet::apply`] (the planner
/// reads move masks), each OPEN a std `BinaryHeap` keyed by least `f`, then larger `g`,
/// then push order, stale entries dropped when they reach the top; Pohl's stopping rule
/// checked before every expansion against the least live `f` of both OPENs; the side with
/// fewer nodes in OPEN expands (forward on ties); `mu` improved whenever a node's `g`
/// improves in one direction and the node was reached in the other. Costs as the planner
/// keeps them: on a grid without weights `f64` sums of the moves' costs with `h` from
/// [`Cell::octile`] or the Manhattan distance; on a weighted grid exact [`Cost`] units,
/// each move charged [`Grid::move_cost`] in its forward direction (the backward search
/// follows moves in reverse) and `h` times the smallest weight. `moves` is 4 or 8, without
/// corner cutting, in the default order. Unlimited budget.
pub fn reference_bidirectional_astar(
    grid: &Grid,
    moves: Connectivity,
    start: Cell,
    goal: Cell,
) -> BidirectionalSearch {
    let move_set = MoveSet::new(moves, false, &NeighborOrder::default())
        .unwrap_or_else(|e| panic!("the {moves:?} moves: {e}"));
    let eight = moves == Connectivity::Eight;
    match grid.weights() {
        None => search::<f64>(
            grid,
            &move_set,
            start,
            goal,
            |_, _, cost| cost,
            |c, t| match eight {
                true => c.octile(t),
                false => c.manhattan(t) as f64,
            },
        ),
        Some(weights) => {
            let min = u64::from(weights.min());
            search::<u64>(
                grid,
                &move_set,
                start,
                goal,
                |from, to, _| grid.move_cost(from, to).units(),
                move |c, t| {
                    let estimate = match eight {
                        true => Cost::octile_distance(c.x.abs_diff(t.x), c.y.abs_diff(t.y)),
                        false => Cost::steps(c.manhattan(t)),
                    };
                    estimate.times(min).units()
                },
            )
        }
    }
}

/// An OPEN list: entries `(f key, complement of g's key, push sequence, cell index)`, least
/// first.
type Heap = BinaryHeap<Reverse<(u64, u64, u64, usize)>>;

/// The search for one representation of costs: `cost(from, to, f64 cost of the move)` is a
/// move's cost forward, `h(cell, target)` the estimate.
fn search<S: Scalar>(
    grid: &Grid,
    moves: &MoveSet,
    start: Cell,
    goal: Cell,
    cost: impl Fn(Cell, Cell, f64) -> S,
    h: impl Fn(Cell, Cell) -> S,
) -> BidirectionalSearch {
    const FORWARD: usize = 0;
    const BACKWARD: usize = 1;
    let n = grid.len();
    let targets = [goal, start];
    // Per direction: 0 unseen, 1 open, 2 closed.
    let mut state = [vec![0u8; n], vec![0u8; n]];
    let mut g = [vec![S::ZERO; n], vec![S::ZERO; n]];
    let mut parent = [vec![usize::MAX; n], vec![usize::MAX; n]];
    let mut open: [Heap; 2] = [BinaryHeap::new(), BinaryHeap::new()];
    // Per direction: expanded, safe moves, skipped, insertions, relaxations, peak OPEN.
    let mut tally = [[0u64; 6]; 2];
    let mut seq = 0u64;
    for (d, cell) in [(FORWARD, start), (BACKWARD, goal)] {
        let p = grid.index(cell);
        state[d][p] = 1;
        parent[d][p] = p;
        open[d].push(Reverse((h(cell, targets[d]).key(), !0, seq, p)));
        seq += 1;
        tally[d][3] = 1;
        tally[d][5] = 1;
    }
    let (mut mu, mut meet, mut n_meeting_updates) = (S::INFINITY, usize::MAX, 0u64);
    if start == goal {
        (mu, meet, n_meeting_updates) = (S::ZERO, grid.index(start), 1);
    }
    let mut peak_open = 2u64;
    let in_open = |tally: &[[u64; 6]; 2], d: usize| tally[d][3] - tally[d][0];
    let status = loop {
        let mut fmin = [u64::MAX; 2];
        for d in [FORWARD, BACKWARD] {
            while let Some(&Reverse((f, g_rev, _, q))) = open[d].peek() {
                if state[d][q] == 2 || g[d][q].key() != !g_rev {
                    open[d].pop();
                } else {
                    fmin[d] = f;
                    break;
                }
            }
        }
        let stop = open.iter().any(BinaryHeap::is_empty)
            || (mu != S::INFINITY && mu.key() <= fmin[0].max(fmin[1]));
        if stop {
            break match mu != S::INFINITY {
                true => Status::Found,
                false => Status::NoPath,
            };
        }
        let d = match in_open(&tally, BACKWARD) < in_open(&tally, FORWARD) {
            true => BACKWARD,
            false => FORWARD,
        };
        let other = 1 - d;
        let Some(Reverse((_, _, _, p))) = open[d].pop() else {
            break Status::NoPath;
        };
        state[d][p] = 2;
        tally[d][0] += 1;
        let cell = grid.cell(p);
        for mv in moves.moves() {
            let Some(to) = moves.apply(grid, cell, mv) else {
                continue;
            };
            tally[d][1] += 1;
            let q = grid.index(to);
            if state[d][q] == 2 {
                tally[d][2] += 1;
                continue;
            }
            let step = match d {
                FORWARD => cost(cell, to, mv.cost),
                _ => cost(to, cell, mv.cost),
            };
            let g_new = g[d][p].add(step);
            let known = state[d][q] == 1;
            if known && g_new >= g[d][q] {
                continue;
            }
            tally[d][4] += 1;
            tally[d][3] += u64::from(!known);
            state[d][q] = 1;
            g[d][q] = g_new;
            parent[d][q] = p;
            if state[other][q] != 0 && g_new.add(g[other][q]) < mu {
                mu = g_new.add(g[other][q]);
                meet = q;
                n_meeting_updates += 1;
            }
            let f = g_new.add(h(to, targets[d]));
            open[d].push(Reverse((f.key(), !g_new.key(), seq, q)));
            seq += 1;
        }
        tally[d][5] = tally[d][5].max(in_open(&tally, d));
        peak_open = peak_open.max(in_open(&tally, FORWARD) + in_open(&tally, BACKWARD));
    };
    let n_moves = moves.moves().len() as u64;
    let counters_of = |t: &[u64; 6], peak: u64| {
        let checks = n_moves * t[0];
        [t[0], checks, checks - t[1], t[2], t[3], t[4], peak]
    };
    let total: [u64; 6] = std::array::from_fn(|i| tally[0][i] + tally[1][i]);
    let names = crate::REFERENCE_COUNTERS;
    let mut counters: Vec<(String, u64)> = names
        .iter()
        .map(|n| n.to_string())
        .zip(counters_of(&total, peak_open))
        .collect();
    for (prefix, t) in [
        ("forward_", &tally[FORWARD]),
        ("backward_", &tally[BACKWARD]),
    ] {
        let values = counters_of(t, t[5]);
        counters.extend(names.iter().map(|n| format!("{prefix}{n}")).zip(values));
    }
    counters.push(("n_meeting_updates".to_string(), n_meeting_updates));
    let path = (mu != S::INFINITY).then(|| {
        let mut cells = vec![grid.cell(meet)];
        let mut node = meet;
        while parent[FORWARD][node] != node {
            node = parent[FORWARD][node];
            cells.push(grid.cell(node));
        }
        cells.reverse();
        node = meet;
        while parent[BACKWARD][node] != node {
            node = parent[BACKWARD][node];
            cells.push(grid.cell(node));
        }
        cells
    });
    (status, path, counters)
}
