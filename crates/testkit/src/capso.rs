//! [`reference_capso_guide`]: CAPSO's guide, an A\* route over blocks of cells, written again.

use std::collections::BTreeSet;

use planner_api::{segment_is_free, Cell, Grid};

/// What [`reference_capso_guide`] found: planner-capso's `Guide::find` results
/// (`block`, `n_expanded`, `polyline`) and so its `guide_block` and `n_guide_expanded`.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct CapsoGuideSearch {
    /// The block size in cells of the level that found a route (0 when none did).
    pub block: u32,
    /// Blocks expanded over all levels tried.
    pub n_expanded: u64,
    /// The route shortened by line of sight, start first (empty when there is none).
    pub polyline: Vec<Cell>,
}

/// At most this many blocks along the grid's longer side at the first level.
const BLOCKS_PER_SIDE: u32 = 64;

/// planner-capso's guide (the module docs of its `guide`) written for clarity: block size
/// `b = ceil(max(W, H) / 64)`, halved (rounding down) while no route exists, down to 1.
/// At each level a block is free when every cell of it inside the grid is free, and the
/// blocks of the start and of the goal count as free. The route is A\* over blocks,
/// 8-connected with a diagonal step allowed only when both side blocks are free, steps
/// costing 5 and 7, the octile heuristic `7 min + 5 (max - min)` of the block offsets to
/// the goal's block, and OPEN an ordered set of `(f, block index)` (ties to the lower
/// row-major index) with decrease-key, so no stale entry; a block counts as expanded when
/// it leaves OPEN, the goal's block included (the heuristic is consistent, so none leaves
/// twice). The route is the start, the centre cells of the blocks strictly between the
/// start's and the goal's blocks (the centre of a block's part inside the grid, rounded
/// down), and the goal (the start alone when it is the goal); it is shortened from each
/// anchor by keeping the waypoint after it and then moving on to the next one while the
/// anchor sees that ([`segment_is_free`]), stopping at the first it does not see.
/// Unlimited budget.
pub fn reference_capso_guide(grid: &Grid, start: Cell, goal: Cell) -> CapsoGuideSearch {
    let longest = grid.width().max(grid.height());
    let mut b = longest.div_ceil(BLOCKS_PER_SIDE).max(1);
    let mut n_expanded = 0;
    loop {
        let (expanded, route) = search_level(grid, start, goal, b);
        n_expanded += expanded;
        if let Some(route) = route {
            return CapsoGuideSearch {
                block: b,
                n_expanded,
                polyline: shorten(grid, &route),
            };
        }
        if b == 1 {
            return CapsoGuideSearch {
                block: 0,
                n_expanded,
                polyline: Vec::new(),
            };
        }
        b /= 2;
    }
}

/// One level: A\* over the blocks of `b` cells. Returns the blocks expanded and, when the
/// goal's block was reached, the unshortened route of cells.
fn search_level(grid: &Grid, start: Cell, goal: Cell, b: u32) -> (u64, Option<Vec<Cell>>) {
    let (w, h) = (grid.width(), grid.height());
    let (bw, bh) = (w.div_ceil(b), h.div_ceil(b));
    let index = |bx: u32, by: u32| by as usize * bw as usize + bx as usize;
    // The block's cells inside the grid: columns x0 .. x1 and rows y0 .. y1 (exclusive).
    let cells_of = |bx: u32, by: u32| {
        let (x0, y0) = (bx * b, by * b);
        (x0, (x0 + b).min(w), y0, (y0 + b).min(h))
    };
    let n = bw as usize * bh as usize;
    let mut free = vec![false; n];
    for by in 0..bh {
        for bx in 0..bw {
            let (x0, x1, y0, y1) = cells_of(bx, by);
            let all_free = (y0..y1).all(|y| (x0..x1).all(|x| grid.is_free(Cell::new(x, y))));
            free[index(bx, by)] = all_free;
        }
    }
    let (sx, sy) = (start.x / b, start.y / b);
    let (tx, ty) = (goal.x / b, goal.y / b);
    free[index(sx, sy)] = true;
    free[index(tx, ty)] = true;
    let is_free = |x: i64, y: i64| {
        x >= 0
            && y >= 0
            && x < i64::from(bw)
            && y < i64::from(bh)
            && free[index(x as u32, y as u32)]
    };
    let heuristic = |bx: u32, by: u32| {
        let (dx, dy) = (bx.abs_diff(tx), by.abs_diff(ty));
        7 * dx.min(dy) + 5 * (dx.max(dy) - dx.min(dy))
    };

    let mut g: Vec<Option<u32>> = vec![None; n];
    let mut parent: Vec<Option<(u32, u32)>> = vec![None; n];
    let mut closed = vec![false; n];
    let mut open: BTreeSet<(u32, usize)> = BTreeSet::new();
    g[index(sx, sy)] = Some(0);
    open.insert((heuristic(sx, sy), index(sx, sy)));
    let mut expanded = 0;
    let mut reached = false;
    while let Some((_, i)) = open.pop_first() {
        closed[i] = true;
        expanded += 1;
        // Below the block count, so the quotient and remainder fit.
        let (bx, by) = ((i % bw as usize) as u32, (i / bw as usize) as u32);
        if (bx, by) == (tx, ty) {
            reached = true;
            break;
        }
        // A block in OPEN has a g.
        let g_here = g[i].unwrap_or(u32::MAX);
        for dy in -1i64..=1 {
            for dx in -1i64..=1 {
                let (nx, ny) = (i64::from(bx) + dx, i64::from(by) + dy);
                if (dx, dy) == (0, 0) || !is_free(nx, ny) {
                    continue;
                }
                let diagonal = dx != 0 && dy != 0;
                if diagonal
                    && !(is_free(i64::from(bx) + dx, i64::from(by))
                        && is_free(i64::from(bx), i64::from(by) + dy))
                {
                    continue;
                }
                // Inside the block grid (checked by `is_free`).
                let (nx, ny) = (nx as u32, ny as u32);
                let j = index(nx, ny);
                if closed[j] {
                    continue;
                }
                let through = g_here + if diagonal { 7 } else { 5 };
                if g[j].is_some_and(|old| old <= through) {
                    continue;
                }
                if let Some(old) = g[j] {
                    open.remove(&(old + heuristic(nx, ny), j));
                }
                g[j] = Some(through);
                parent[j] = Some((bx, by));
                open.insert((through + heuristic(nx, ny), j));
            }
        }
    }
    if !reached {
        return (expanded, None);
    }
    // The blocks strictly between the start's and the goal's, goal side first.
    let mut inner = Vec::new();
    let mut at = parent[index(tx, ty)];
    while let Some((bx, by)) = at {
        if (bx, by) == (sx, sy) {
            break;
        }
        let (x0, x1, y0, y1) = cells_of(bx, by);
        inner.push(Cell::new(x0 + (x1 - x0 - 1) / 2, y0 + (y1 - y0 - 1) / 2));
        at = parent[index(bx, by)];
    }
    let mut route = vec![start];
    route.extend(inner.iter().rev());
    if goal != start {
        route.push(goal);
    }
    (expanded, Some(route))
}

/// The route shortened greedily by line of sight: from each anchor the next waypoint is
/// kept, or the last of the waypoints after it that the anchor sees one after another.
fn shorten(grid: &Grid, route: &[Cell]) -> Vec<Cell> {
    let mut line = Vec::new();
    let Some(&first) = route.first() else {
        return line;
    };
    line.push(first);
    let mut anchor = 0;
    while anchor + 1 < route.len() {
        let mut kept = anchor + 1;
        while kept + 1 < route.len() && segment_is_free(grid, route[anchor], route[kept + 1]) {
            kept += 1;
        }
        line.push(route[kept]);
        anchor = kept;
    }
    line
}
