//! [`reference_weighted_jps`]: weighted JPS written again for clarity.

use planner_api::{Cell, Grid};

use crate::path_from_parents;

/// The counters of [`reference_weighted_jps`], in its order.
pub const WEIGHTED_JPS_COUNTERS: [&str; 6] = [
    "n_expanded",
    "n_jumps",
    "n_open_insertions",
    "n_relaxations",
    "peak_open",
    "n_reopened",
];

/// What [`reference_weighted_jps`] found: status, the jump points of the path from start to
/// goal (both included), and the counters named in [`WEIGHTED_JPS_COUNTERS`].
pub type WeightedJpsSearch = (planner_api::Status, Option<Vec<Cell>>, [u64; 6]);

/// planner-weighted_jps's search as its crate docs define it, written for clarity and not
/// speed: every jump walked cell by cell from the definitions (a uniform cell, a forced
/// neighbour, a diagonal jump's stop where a straight component jump stops or reaches
/// the goal), the uniform test and the forced test on the grid itself, each move's cost
/// from [`Grid::move_cost`] summed along the jump, and std's `BinaryHeap` with lazy
/// deletion and the full key `(f, g, push sequence)` (lower `g` first). It shares no code
/// with the planner, whose jumps are reads of precomputed tables and whose OPEN is
/// planner-search's bucket list; what it takes from the planner are the choices the crate
/// docs name and the order of the eight directions (east, west, south, north, then
/// south-east, south-west, north-east, north-west: the order of the pushes, so of ties).
/// 8-connected without corner cutting, unlimited budget.
pub fn reference_weighted_jps(grid: &Grid, start: Cell, goal: Cell) -> WeightedJpsSearch {
    use planner_api::Cost;
    use std::cmp::Reverse;
    use std::collections::BinaryHeap;
    // planner-api's default move order: the four straight moves, then the diagonals.
    let directions: [(i64, i64); 8] = planner_api::Direction::DEFAULT_ORDER.map(|d| {
        let (dx, dy) = d.offset();
        (i64::from(dx), i64::from(dy))
    });
    let index_of = |dx: i64, dy: i64| {
        directions
            .iter()
            .position(|&d| d == (dx, dy))
            .unwrap_or_else(|| panic!("no direction ({dx}, {dy})"))
    };
    let (width, height) = (i64::from(grid.width()), i64::from(grid.height()));
    let cell_at = |x: i64, y: i64| {
        ((0..width).contains(&x) && (0..height).contains(&y)).then(|| Cell::new(x as u32, y as u32))
    };
    let free = |x: i64, y: i64| cell_at(x, y).is_some_and(|c| grid.is_free(c));
    let weight = |x: i64, y: i64| {
        grid.weights()
            .map_or(1, |w| w.cells()[grid.index(Cell::new(x as u32, y as u32))])
    };
    // Free, and every free cell of its 3 x 3 neighbourhood has its weight.
    let uniform = |x: i64, y: i64| {
        free(x, y)
            && directions
                .iter()
                .all(|&(dx, dy)| !free(x + dx, y + dy) || weight(x + dx, y + dy) == weight(x, y))
    };
    let sides = |k: usize| if k < 2 { [2, 3] } else { [0, 1] };
    // A straight move in direction k onto (x, y) forces side s: its cell is free and the
    // cell beside it one step back is blocked.
    let forced = |x: i64, y: i64, k: usize, s: usize| {
        let ((dx, dy), (sx, sy)) = (directions[k], directions[s]);
        free(x + sx, y + sy) && !free(x + sx - dx, y + sy - dy)
    };
    let straight_stop =
        |x: i64, y: i64, k: usize| !uniform(x, y) || sides(k).iter().any(|&s| forced(x, y, k, s));
    let (gx, gy) = (i64::from(goal.x), i64::from(goal.y));
    // Walks straight from (x, y) in direction k: `Some((cell, reached the goal))` for the
    // first cell that is the goal or a straight jump point, `None` at a blocked cell.
    let walk_straight = |x: i64, y: i64, k: usize| {
        let (dx, dy) = directions[k];
        let (mut cx, mut cy) = (x + dx, y + dy);
        loop {
            if !free(cx, cy) {
                return None;
            }
            if (cx, cy) == (gx, gy) {
                return Some(((cx, cy), true));
            }
            if straight_stop(cx, cy, k) {
                return Some(((cx, cy), false));
            }
            cx += dx;
            cy += dy;
        }
    };
    // A jump from (x, y) in direction k: the jump point and the cost of the way there.
    let jump = |x: i64, y: i64, k: usize| -> Option<((i64, i64), u64)> {
        let (dx, dy) = directions[k];
        let (mut px, mut py, mut cost) = (x, y, 0u64);
        loop {
            let (cx, cy) = (px + dx, py + dy);
            let allowed = free(cx, cy) && (k < 4 || (free(px + dx, py) && free(px, py + dy)));
            if !allowed {
                return None;
            }
            let step = grid.move_cost(
                Cell::new(px as u32, py as u32),
                Cell::new(cx as u32, cy as u32),
            );
            cost += step.units();
            let stop = if (cx, cy) == (gx, gy) {
                true
            } else if k < 4 {
                straight_stop(cx, cy, k)
            } else {
                let (kx, ky) = (index_of(dx, 0), index_of(0, dy));
                // A straight component jump from here that ends at a jump point, or that
                // reaches the goal (a target jump point).
                !uniform(cx, cy) || [kx, ky].iter().any(|&s| walk_straight(cx, cy, s).is_some())
            };
            if stop {
                return Some(((cx, cy), cost));
            }
            (px, py) = (cx, cy);
        }
    };
    let min_weight = grid.weights().map_or(1, |w| w.min());
    let h = |x: i64, y: i64| {
        let (dx, dy) = (x.abs_diff(gx), y.abs_diff(gy));
        let diagonals = dx.min(dy);
        Cost::octile(dx.max(dy) - diagonals, diagonals)
            .times(u64::from(min_weight))
            .units()
    };
    let successors = |x: i64, y: i64, arrived: u8| -> u8 {
        if arrived == 0 || !uniform(x, y) {
            return 0xff;
        }
        let mut keep = 0u8;
        for k in (0..8).filter(|k| arrived >> k & 1 == 1) {
            let (dx, dy) = directions[k];
            keep |= 1 << k;
            if k < 4 {
                for s in sides(k) {
                    if forced(x, y, k, s) {
                        let (sx, sy) = directions[s];
                        keep |= 1 << s | 1 << index_of(dx + sx, dy + sy);
                    }
                }
            } else {
                keep |= 1 << index_of(dx, 0) | 1 << index_of(0, dy);
            }
        }
        keep
    };
    #[derive(Clone, Copy, PartialEq)]
    enum State {
        Unseen,
        Open,
        Closed,
    }
    let n = grid.len();
    let at = |x: i64, y: i64| (y * width + x) as usize;
    let mut state = vec![State::Unseen; n];
    let mut g = vec![0u64; n];
    let mut parent = vec![usize::MAX; n];
    let mut directions = vec![0u8; n];
    let mut reopen = vec![0u8; n];
    let mut heap = BinaryHeap::new();
    let mut seq = 0u64;
    let (sx, sy) = (i64::from(start.x), i64::from(start.y));
    let s = at(sx, sy);
    state[s] = State::Open;
    heap.push(Reverse((h(sx, sy), 0u64, seq, s)));
    seq += 1;
    let [mut n_expanded, mut n_jumps, mut n_open_insertions, mut n_relaxations] = [0u64, 0, 1, 0];
    let (mut peak_open, mut n_reopened) = (1u64, 0u64);
    let status = loop {
        let Some(Reverse((_, _, _, p))) = heap.pop() else {
            break planner_api::Status::NoPath;
        };
        let (x, y) = ((p as i64) % width, (p as i64) / width);
        let reopened = state[p] == State::Closed;
        let arrived = match state[p] {
            State::Closed if reopen[p] == 0 => continue,
            State::Closed => {
                n_reopened += 1;
                std::mem::take(&mut reopen[p])
            }
            _ => directions[p],
        };
        state[p] = State::Closed;
        n_expanded += 1;
        if (x, y) == (gx, gy) {
            break planner_api::Status::Found;
        }
        let expand = match (reopened, uniform(x, y)) {
            (true, false) => 0,
            _ => successors(x, y, arrived),
        };
        for k in (0..8).filter(|k| expand >> k & 1 == 1) {
            n_jumps += 1;
            let Some(((qx, qy), cost)) = jump(x, y, k) else {
                continue;
            };
            let q = at(qx, qy);
            let bit = 1u8 << k;
            let g_q = g[p] + cost;
            match state[q] {
                State::Unseen => {
                    state[q] = State::Open;
                    n_open_insertions += 1;
                }
                State::Open if g_q > g[q] => continue,
                State::Open if g_q == g[q] => {
                    directions[q] |= bit;
                    continue;
                }
                State::Open => {}
                State::Closed if g_q == g[q] => {
                    if directions[q] & bit == 0 {
                        directions[q] |= bit;
                        reopen[q] |= bit;
                        heap.push(Reverse((g_q + h(qx, qy), g_q, seq, q)));
                        seq += 1;
                    }
                    continue;
                }
                State::Closed if g_q > g[q] => continue,
                State::Closed => {
                    state[q] = State::Open;
                    reopen[q] = 0;
                }
            }
            n_relaxations += 1;
            g[q] = g_q;
            parent[q] = p;
            directions[q] = bit;
            heap.push(Reverse((g_q + h(qx, qy), g_q, seq, q)));
            seq += 1;
        }
        peak_open = peak_open.max(n_open_insertions.saturating_sub(n_expanded));
    };
    let counters = [
        n_expanded,
        n_jumps,
        n_open_insertions,
        n_relaxations,
        peak_open,
        n_reopened,
    ];
    let chain = (status == planner_api::Status::Found)
        .then(|| path_from_parents(grid, &parent, start, goal));
    (status, chain, counters)
}
