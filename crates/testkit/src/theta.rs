//! [`reference_theta_star`]: Theta\* and Lazy Theta\* written again for clarity.

use std::cmp::Reverse;
use std::collections::BinaryHeap;

use planner_api::{walk_segment, Cell, Connectivity, Grid, MoveSet, NeighborOrder, Status};

/// The counters of [`reference_theta_star`], in its order (`n_parent_repairs` for Lazy
/// Theta\* only).
pub const THETA_COUNTERS: [&str; 10] = [
    "n_expanded",
    "n_neighbor_checks",
    "n_blocked",
    "n_skipped",
    "n_open_insertions",
    "n_relaxations",
    "peak_open",
    "n_los_checks",
    "n_los_cells",
    "n_parent_repairs",
];

/// What [`reference_theta_star`] found: status, the path's waypoints, and the counters
/// named in [`THETA_COUNTERS`] (the last 0 for Theta\*).
pub type ThetaSearch = (Status, Option<Vec<Cell>>, [u64; 10]);

/// planner-theta_star's search (`AnyAngle`) as its crate docs define it, for Theta\*
/// (`lazy` false, with its `skip_hopeless` setting) and Lazy Theta\*, written for clarity
/// and not speed: line of sight by planner-api's [`walk_segment`] (the planner walks a
/// bit-packed copy with a summed-area table), moves through [`MoveSet::apply`] in the
/// default order (the planner reads move masks from bit codes), CLOSED as a `Vec<bool>`,
/// and OPEN as std's `BinaryHeap` with the documented key: `f` rounded to a multiple of
/// `2^-24`, then larger `g`, then the push sequence. Costs are `f64` as the planner's: a
/// move's [`planner_api::Move`] cost for path 1, [`Cell::euclidean`] for path 2 and Lazy
/// Theta\*'s repair, `h = sqrt(dx^2 + dy^2)`, and a node's `g` replaced only by one smaller
/// by more than `2^-24`. What it takes from the planner are those documented choices and
/// where line of sight is skipped because it cannot change the search (a neighbour in OPEN
/// that already has the expanded node's parent; for Theta\* with `skip_hopeless`, one whose
/// `g` neither path could replace). Unlimited budget.
pub fn reference_theta_star(
    grid: &Grid,
    start: Cell,
    goal: Cell,
    lazy: bool,
    skip_hopeless: bool,
) -> ThetaSearch {
    const EPSILON: f64 = 1.0 / 16_777_216.0;
    let moves = MoveSet::new(Connectivity::Eight, false, &NeighborOrder::default())
        .unwrap_or_else(|e| panic!("the 8-connected moves: {e}"));
    let n = grid.len();
    let h = |c: Cell| {
        let (dx, dy) = (
            f64::from(c.x.abs_diff(goal.x)),
            f64::from(c.y.abs_diff(goal.y)),
        );
        (dx * dx + dy * dy).sqrt()
    };
    let key = |f: f64| (f / EPSILON).round() as u64;
    let mut g = vec![0.0f64; n];
    let mut parent = vec![usize::MAX; n];
    let mut open = vec![false; n];
    let mut closed = vec![false; n];
    let mut heap = BinaryHeap::new();
    let mut seq = 0u64;
    let mut counters = [0u64; 10];
    let [mut safe, mut checked] = [0u64; 2];
    let line_of_sight = |counters: &mut [u64; 10], a: Cell, b: Cell| {
        let walk = walk_segment(grid, a, b);
        counters[7] += 1;
        counters[8] += walk.n_cells;
        walk.free
    };
    let s = grid.index(start);
    parent[s] = s;
    open[s] = true;
    // Larger g first: the complement of g's bits (non-negative floats order as their bits).
    heap.push(Reverse((key(h(start)), !0f64.to_bits(), seq, s)));
    seq += 1;
    counters[4] = 1;
    counters[6] = 1;
    let t = grid.index(goal);
    let status = loop {
        let Some(Reverse((_, _, _, p))) = heap.pop() else {
            break Status::NoPath;
        };
        if closed[p] {
            continue;
        }
        let cell = grid.cell(p);
        if lazy && parent[p] != p && !line_of_sight(&mut counters, grid.cell(parent[p]), cell) {
            // SetVertex: the CLOSED neighbour with the least g(n) + c(n, s), the first in
            // move order on ties.
            counters[9] += 1;
            let mut best: Option<(f64, usize)> = None;
            for mv in moves.moves() {
                if let Some(to) = moves.apply(grid, cell, mv) {
                    let q = grid.index(to);
                    if closed[q] && best.is_none_or(|(b, _)| g[q] + mv.cost < b) {
                        best = Some((g[q] + mv.cost, q));
                    }
                }
            }
            if let Some((cost, q)) = best {
                g[p] = cost;
                parent[p] = q;
            }
        }
        closed[p] = true;
        open[p] = false;
        counters[0] += 1;
        if p == t {
            break Status::Found;
        }
        checked += 1;
        let (g_node, up) = (g[p], parent[p]);
        let up_cell = grid.cell(up);
        for mv in moves.moves() {
            let Some(q_cell) = moves.apply(grid, cell, mv) else {
                continue;
            };
            safe += 1;
            let q = grid.index(q_cell);
            if closed[q] {
                counters[3] += 1;
                continue;
            }
            let known = open[q];
            let path_1 = g_node + mv.cost;
            let path_2 = || g[up] + up_cell.euclidean(q_cell);
            let holds_path_2 = known && parent[q] == up;
            let (g_new, new_parent) = if up == p {
                (path_1, p)
            } else if lazy {
                if holds_path_2 {
                    continue;
                }
                (path_2(), up)
            } else {
                // Line of sight only where its answer could change g(q).
                let hopeless =
                    || path_1 >= g[q] - EPSILON && (holds_path_2 || path_2() >= g[q] - EPSILON);
                if skip_hopeless && known && hopeless() {
                    continue;
                }
                match line_of_sight(&mut counters, up_cell, q_cell) {
                    true => (path_2(), up),
                    false => (path_1, p),
                }
            };
            if !known || g_new < g[q] - EPSILON {
                counters[5] += 1;
                if !known {
                    counters[4] += 1;
                }
                open[q] = true;
                g[q] = g_new;
                parent[q] = new_parent;
                heap.push(Reverse((key(g_new + h(q_cell)), !g_new.to_bits(), seq, q)));
                seq += 1;
            }
        }
        counters[6] = counters[6].max(counters[4] - counters[0]);
    };
    counters[1] = 8 * checked;
    counters[2] = counters[1] - safe;
    let path =
        (status == Status::Found).then(|| crate::path_from_parents(grid, &parent, start, goal));
    (status, path, counters)
}
