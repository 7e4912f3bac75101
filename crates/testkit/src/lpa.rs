//! [`reference_lpa`]: a first search of LPA\* or D\* Lite written again from the papers.

use std::collections::BTreeSet;

use planner_api::{Cell, Cost, Grid, Status};

/// The counters of [`reference_lpa`], in its order (`path_cost_units` only when found).
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

/// The first search of planner-lpastar's engine on a grid without weights, as LPA\*
/// (Koenig, Likhachev and Furcy 2004, Fig. 3: the root is the start, the target the goal)
/// or D\* Lite (Koenig and Likhachev 2002, Fig. 4, `km = 0`: the root is the goal, the
/// target the start) runs it, written for clarity and not speed: `g` and `rhs` in exact
/// [`Cost`] units per cell, the queue U a `BTreeSet` of `(k1, k2, cell index)` with each
/// queued vertex's key beside it, ComputeShortestPath and UpdateVertex as the papers give
/// them (a vertex is updated when its `rhs` changed, as the engine's docs say it does, which
/// the papers' calls for unchanged vertices leave the same), and the path traced from the
/// target through the neighbour of least `c + g`, the first in move order. `moves` is 4 or 8
/// (no corner cutting); `h` is Manhattan or octile. The counters count the papers' queue
/// operations: inserts, pops (one per expansion), key updates of queued vertices, removals
/// of queued vertices that became consistent otherwise, and `rhs` changes (the root's 0
/// included). Unlimited budget; no weights.
pub fn reference_lpa(grid: &Grid, eight: bool, start: Cell, goal: Cell, dstar: bool) -> LpaSearch {
    let (root, target) = match dstar {
        true => (goal, start),
        false => (start, goal),
    };
    let n_moves = if eight { 8 } else { 4 };
    let (width, height) = (i64::from(grid.width()), i64::from(grid.height()));
    let free = |x: i64, y: i64| {
        (0..width).contains(&x)
            && (0..height).contains(&y)
            && grid.is_free(Cell::new(x as u32, y as u32))
    };
    let at = |x: i64, y: i64| (y * width + x) as usize;
    // The neighbours of (x, y) in move order, with the move's cost in units.
    let neighbours = |x: i64, y: i64| -> Vec<(i64, i64, u64)> {
        MOVES[..n_moves]
            .iter()
            .filter(|&&(dx, dy)| {
                free(x + dx, y + dy) && (dx == 0 || dy == 0 || (free(x + dx, y) && free(x, y + dy)))
            })
            .map(|&(dx, dy)| {
                let cost = match dx != 0 && dy != 0 {
                    true => Cost::SQRT_2.units(),
                    false => Cost::ONE.units(),
                };
                (x + dx, y + dy, cost)
            })
            .collect()
    };
    let (tx, ty) = (i64::from(target.x), i64::from(target.y));
    let h = |x: i64, y: i64| {
        let (dx, dy) = (x.abs_diff(tx), y.abs_diff(ty));
        match eight {
            true => Cost::octile_distance(dx as u32, dy as u32).units(),
            false => Cost::steps(dx + dy).units(),
        }
    };
    let n = grid.len();
    let mut g = vec![INF; n];
    let mut rhs = vec![INF; n];
    let mut queued: Vec<Option<(u64, u64)>> = vec![None; n];
    let mut queue: BTreeSet<(u64, u64, usize)> = BTreeSet::new();
    let [mut expanded, mut pushes, mut pops, mut updates, mut removes, mut rhs_changes] = [0u64; 6];
    let key = |g: u64, rhs: u64, x: i64, y: i64| {
        let least = g.min(rhs);
        (least.saturating_add(h(x, y)), least)
    };
    // UpdateVertex.
    let mut update = |i: usize,
                      x: i64,
                      y: i64,
                      g: &[u64],
                      rhs: &[u64],
                      queue: &mut BTreeSet<(u64, u64, usize)>,
                      queued: &mut [Option<(u64, u64)>]| {
        let consistent = g[i] == rhs[i];
        match (queued[i], consistent) {
            (Some((k1, k2)), false) => {
                queue.remove(&(k1, k2, i));
                let (k1, k2) = key(g[i], rhs[i], x, y);
                queue.insert((k1, k2, i));
                queued[i] = Some((k1, k2));
                updates += 1;
            }
            (None, false) => {
                let (k1, k2) = key(g[i], rhs[i], x, y);
                queue.insert((k1, k2, i));
                queued[i] = Some((k1, k2));
                pushes += 1;
            }
            (Some((k1, k2)), true) => {
                queue.remove(&(k1, k2, i));
                queued[i] = None;
                removes += 1;
            }
            (None, true) => {}
        }
    };
    let (rx, ry) = (i64::from(root.x), i64::from(root.y));
    let r = at(rx, ry);
    rhs[r] = 0;
    rhs_changes += 1;
    update(r, rx, ry, &g, &rhs, &mut queue, &mut queued);
    let t = at(tx, ty);
    loop {
        let top = queue.first().copied();
        let target_key = key(g[t], rhs[t], tx, ty);
        let below = top.is_some_and(|(k1, k2, _)| (k1, k2) < target_key);
        if !below && rhs[t] == g[t] {
            break;
        }
        let Some((k1, k2, u)) = top else {
            break;
        };
        let (ux, uy) = (u as i64 % width, u as i64 / width);
        if (k1, k2) < key(g[u], rhs[u], ux, uy) {
            // Out of date (only after km grew: not in a first search).
            update(u, ux, uy, &g, &rhs, &mut queue, &mut queued);
            continue;
        }
        queue.remove(&(k1, k2, u));
        queued[u] = None;
        pops += 1;
        expanded += 1;
        if g[u] > rhs[u] {
            g[u] = rhs[u];
            for (sx, sy, cost) in neighbours(ux, uy) {
                let s = at(sx, sy);
                let through = g[u].saturating_add(cost);
                if s != r && through < rhs[s] {
                    rhs[s] = through;
                    rhs_changes += 1;
                    update(s, sx, sy, &g, &rhs, &mut queue, &mut queued);
                }
            }
        } else {
            // Underconsistent vertices come only from changes after a search.
            panic!("a first search met an underconsistent vertex at ({ux}, {uy})");
        }
    }
    let mut counters = vec![expanded, pushes, pops, updates, removes, rhs_changes];
    if g[t] == INF {
        return (Status::NoPath, None, counters);
    }
    counters.push(g[t]);
    // From the target through the neighbour of least c + g, the first in move order.
    let mut cells = vec![target];
    let (mut x, mut y) = (tx, ty);
    while at(x, y) != r {
        let mut best: Option<(u64, i64, i64)> = None;
        for (sx, sy, cost) in neighbours(x, y) {
            let through = cost.saturating_add(g[at(sx, sy)]);
            if best.is_none_or(|(b, _, _)| through < b) {
                best = Some((through, sx, sy));
            }
        }
        let Some((_, sx, sy)) = best else {
            return (Status::NoPath, None, counters);
        };
        (x, y) = (sx, sy);
        cells.push(Cell::new(x as u32, y as u32));
    }
    if !dstar {
        cells.reverse();
    }
    (Status::Found, Some(cells), counters)
}
