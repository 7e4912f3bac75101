//! [`reference_lexastar`]: lexicographic A\* over (cell, heading) written again.

use std::cmp::Reverse;
use std::collections::BinaryHeap;

use planner_api::{Cell, Grid, MoveSet, Status};

/// The counters of [`reference_lexastar`], in planner-lexastar's order.
pub const LEXASTAR_COUNTERS: [&str; 9] = [
    "n_expanded",
    "n_neighbor_checks",
    "n_blocked",
    "n_skipped",
    "n_open_insertions",
    "n_relaxations",
    "peak_open",
    "n_dominated",
    "n_cells_expanded",
];

/// What [`reference_lexastar`] found: status, path, and the counters named in
/// [`LEXASTAR_COUNTERS`].
pub type LexSearch = (Status, Option<Vec<Cell>>, [u64; 9]);

/// planner-lexastar's lexicographic search (its default objective, a grid without weights)
/// as its crate docs define it, written for clarity and not speed: states `(cell, heading)`
/// in flat arrays, a move costing `(1, 1)` when it changes the heading and
/// `(1, 0)` otherwise (the start's moves never turn), `f = g + (M, H)` with `M` the
/// Manhattan (4 moves) or Chebyshev (8) distance and `H` the documented turn bound, OPEN a
/// std `BinaryHeap` of `(f, push sequence)` (ties first in, first out), and dominance
/// pruning (`dominance`) against the best `g` of any state of the target cell plus one
/// turn. Moves are those of `moves` in their order, through [`MoveSet::apply`]. Unlimited
/// budget.
pub fn reference_lexastar(
    grid: &Grid,
    moves: &MoveSet,
    start: Cell,
    goal: Cell,
    dominance: bool,
) -> LexSearch {
    let four = moves.moves().len() == 4;
    let headings = moves.moves().len();
    // The turn bound H for a state at `c` with heading `(hx, hy)` ((0, 0): none).
    let estimate = |c: Cell, hx: i64, hy: i64| -> (u64, u64) {
        let (dx, dy) = (
            i64::from(goal.x) - i64::from(c.x),
            i64::from(goal.y) - i64::from(c.y),
        );
        let (sx, sy) = (dx.signum(), dy.signum());
        let (ax, ay) = (dx.unsigned_abs(), dy.unsigned_abs());
        let none = (hx, hy) == (0, 0);
        if four {
            // Axis directions towards the goal, less the heading's when it is one of them.
            let toward = u64::from(sx != 0) + u64::from(sy != 0);
            let turns = match none {
                true => toward.saturating_sub(1),
                false => toward - u64::from((hx != 0 && hx == sx) || (hy != 0 && hy == sy)),
            };
            (ax + ay, turns)
        } else {
            let in_line = ax == 0 || ay == 0 || ax == ay;
            let turns = match (ax, ay) {
                (0, 0) => 0,
                _ if in_line => u64::from(!none && (hx, hy) != (sx, sy)),
                _ => 1,
            };
            (ax.max(ay), turns)
        }
    };
    let n = grid.len();
    // Per state (cell * headings + heading): reached, closed, g, the parent's heading
    // (`usize::MAX`: the start).
    let mut reached = vec![false; n * headings];
    let mut closed = vec![false; n * headings];
    let mut g = vec![(0u64, 0u64); n * headings];
    let mut parent = vec![usize::MAX; n * headings];
    // Per cell: the best g of its states (`None`: none reached), and whether expanded.
    let mut best: Vec<Option<(u64, u64)>> = vec![None; n];
    let mut cell_expanded = vec![false; n];
    let start_state = usize::MAX;
    best[grid.index(start)] = Some((0, 0));
    let mut heap = BinaryHeap::new();
    heap.push(Reverse((estimate(start, 0, 0), 0u64, start_state)));
    let mut seq = 1u64;
    let mut counters = [0u64; 9];
    counters[4] = 1;
    counters[6] = 1;
    let mut in_open = 1u64;
    let t = grid.index(goal);
    while let Some(Reverse((_, _, state))) = heap.pop() {
        let (node, heading, g_state) = match state == start_state {
            true => (grid.index(start), None, (0, 0)),
            false => {
                if closed[state] {
                    continue;
                }
                closed[state] = true;
                (state / headings, Some(state % headings), g[state])
            }
        };
        in_open -= 1;
        counters[0] += 1;
        if !cell_expanded[node] {
            cell_expanded[node] = true;
            counters[8] += 1;
        }
        if node == t {
            // Back along the parents' headings.
            let mut cells = vec![goal];
            let (mut at, mut h) = (node, heading);
            while let Some(k) = h {
                let mv = &moves.moves()[k];
                let c = grid.cell(at);
                let back = Cell::new(
                    (i64::from(c.x) - i64::from(mv.dx)) as u32,
                    (i64::from(c.y) - i64::from(mv.dy)) as u32,
                );
                let previous = parent[at * headings + k];
                at = grid.index(back);
                cells.push(back);
                h = (previous != usize::MAX).then_some(previous);
            }
            cells.reverse();
            return (Status::Found, Some(cells), counters);
        }
        let cell = grid.cell(node);
        for (k, mv) in moves.moves().iter().enumerate() {
            counters[1] += 1;
            let Some(to) = moves.apply(grid, cell, mv) else {
                counters[2] += 1;
                continue;
            };
            let next = grid.index(to);
            let next_state = next * headings + k;
            if reached[next_state] && closed[next_state] {
                counters[3] += 1;
                continue;
            }
            let turn = u64::from(heading.is_some_and(|h| h != k));
            let g_next = (g_state.0 + 1, g_state.1 + turn);
            if let (true, Some((steps, turns))) = (dominance, best[next]) {
                if g_next >= (steps, turns + 1) {
                    counters[7] += 1;
                    continue;
                }
            }
            if !reached[next_state] || g_next < g[next_state] {
                counters[5] += 1;
                if !reached[next_state] {
                    reached[next_state] = true;
                    counters[4] += 1;
                    in_open += 1;
                    counters[6] = counters[6].max(in_open);
                }
                g[next_state] = g_next;
                parent[next_state] = heading.unwrap_or(usize::MAX);
                if best[next].is_none_or(|b| g_next < b) {
                    best[next] = Some(g_next);
                }
                let (m, h) = estimate(to, i64::from(mv.dx), i64::from(mv.dy));
                heap.push(Reverse(((g_next.0 + m, g_next.1 + h), seq, next_state)));
                seq += 1;
            }
        }
    }
    (Status::NoPath, None, counters)
}
