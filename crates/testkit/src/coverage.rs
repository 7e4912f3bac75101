//! [`reference_coverage`]: seed 004's coverage by backtracking written again.

use planner_api::{Cell, Cost, CoverageMetrics, Grid, MoveSet, Path, Status};

use crate::{reference_astar, Tie};

/// The filling pattern of [`reference_coverage`], with headings as indices into right,
/// down, left, up (clockwise on screen).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Fill {
    /// Section 2.1: the reference lateral side on the left (`left`) or the right, and the
    /// first heading scanned.
    Spiral {
        /// Whether the RLS is the robot's left.
        left: bool,
        /// The first heading a phase scans.
        heading: usize,
    },
    /// Section 2.2: the headings in the order tried.
    Zigzag {
        /// The order.
        order: [usize; 4],
    },
}

/// The counters of [`reference_coverage`], in planner-coverage's order.
pub const COVERAGE_COUNTERS: [&str; 11] = [
    "n_reachable",
    "n_covered",
    "n_revisits",
    "n_moves",
    "n_turns",
    "n_backtracking_points",
    "n_marked_points",
    "n_fill_moves",
    "n_return_moves",
    "n_return_searches",
    "n_return_expansions",
];

/// Right, down, left, up.
const STEPS: [(i64, i64); 4] = [(1, 0), (0, 1), (-1, 0), (0, -1)];

/// planner-coverage's run as its crate docs define it (seed 004 after BSA), written for
/// clarity: the filling rules one move at a time on cell coordinates, backtracking points
/// marked when the robot leaves a cell with an open 4-neighbour and dropped when their
/// neighbourhood is covered, and each return to the nearest point, found by the documented
/// branch and bound (points by increasing octile lower bound, the point marked last
/// first among equals, a search to each until the bound passes the best cost) with
/// [`reference_astar`] under the return legs' settings (8 moves without corner cutting,
/// octile, FIFO), costs compared in exact [`Cost`] units (the grid's rule on a weighted
/// grid). The path's coverage counters are planner-api's [`CoverageMetrics::measure`].
/// Returns the path and the counters named in [`COVERAGE_COUNTERS`]. Unlimited budget.
pub fn reference_coverage(grid: &Grid, start: Cell, fill: Fill) -> (Vec<Cell>, [u64; 11]) {
    let eight = MoveSet::standard(planner_api::Connectivity::Eight);
    let min_weight = grid.weights().map_or(1, |w| u64::from(w.min()));
    let (width, height) = (i64::from(grid.width()), i64::from(grid.height()));
    let mut visited = vec![false; grid.len()];
    let step = |c: Cell, h: usize| {
        let (x, y) = (i64::from(c.x) + STEPS[h].0, i64::from(c.y) + STEPS[h].1);
        ((0..width).contains(&x) && (0..height).contains(&y)).then(|| Cell::new(x as u32, y as u32))
    };
    let open = |visited: &[bool], c: Cell, h: usize| {
        step(c, h).is_some_and(|n| grid.is_free(n) && !visited[grid.index(n)])
    };
    let any_open = |visited: &[bool], c: Cell| (0..4).any(|h| open(visited, c, h));
    // Counters: backtracking points, marked points, fill moves, return moves, searches,
    // expansions.
    let mut tally = [0u64; 6];
    let mut path = vec![start];
    visited[grid.index(start)] = true;
    let mut marked = vec![false; grid.len()];
    let mut points: Vec<Cell> = Vec::new();
    // Enters `next` from the path's last cell, marking that cell when it has an open
    // neighbour left.
    let enter = |next: Cell,
                 path: &mut Vec<Cell>,
                 visited: &mut Vec<bool>,
                 marked: &mut Vec<bool>,
                 points: &mut Vec<Cell>,
                 tally: &mut [u64; 6]| {
        let from = path[path.len() - 1];
        visited[grid.index(next)] = true;
        path.push(next);
        if !marked[grid.index(from)] && any_open(visited, from) {
            marked[grid.index(from)] = true;
            points.push(from);
            tally[1] += 1;
        }
    };
    loop {
        let mut here = path[path.len() - 1];
        // The spiral's first heading: scanning from the configured one towards the OLS,
        // the first with an open front and an obstacle on the RLS, else the first with an
        // open front.
        let mut heading = match fill {
            Fill::Spiral { left, heading } => {
                let (rls, ols) = if left { (3, 1) } else { (1, 3) };
                let scan: Vec<usize> = (0..4).map(|k| (heading + k * ols) % 4).collect();
                scan.iter()
                    .copied()
                    .find(|&h| open(&visited, here, h) && !open(&visited, here, (h + rls) % 4))
                    .or_else(|| scan.iter().copied().find(|&h| open(&visited, here, h)))
                    .unwrap_or(heading)
            }
            Fill::Zigzag { .. } => 0,
        };
        loop {
            if !any_open(&visited, here) {
                break; // Rule 1.
            }
            let next = match fill {
                Fill::Spiral { left, .. } => {
                    let (rls, ols) = if left { (3, 1) } else { (1, 3) };
                    loop {
                        if open(&visited, here, (heading + rls) % 4) {
                            heading = (heading + rls) % 4; // Rule 2.
                            break step(here, heading);
                        }
                        if !open(&visited, here, heading) {
                            heading = (heading + ols) % 4; // Rule 3.
                            continue;
                        }
                        break step(here, heading); // Rule 4.
                    }
                }
                Fill::Zigzag { order } => order
                    .iter()
                    .find(|&&h| open(&visited, here, h))
                    .and_then(|&h| step(here, h)),
            };
            let Some(next) = next else { break };
            tally[2] += 1;
            enter(
                next,
                &mut path,
                &mut visited,
                &mut marked,
                &mut points,
                &mut tally,
            );
            here = next;
        }
        points.retain(|&p| {
            let keep = any_open(&visited, p);
            if !keep {
                marked[grid.index(p)] = false;
            }
            keep
        });
        if points.is_empty() {
            break;
        }
        // The nearest point: candidates by increasing lower bound, the point marked last
        // first among equal bounds; stop once the bound passes the best cost.
        let bound = |p: Cell| {
            Cost::octile_distance(here.x.abs_diff(p.x), here.y.abs_diff(p.y)).times(min_weight)
        };
        let mut candidates: Vec<(Cost, usize)> = points
            .iter()
            .enumerate()
            .map(|(k, &p)| (bound(p), k))
            .collect();
        candidates.sort_by(|a, b| a.0.cmp(&b.0).then(b.1.cmp(&a.1)));
        let mut best: Option<(Cost, usize, Vec<Cell>)> = None;
        for (lower, k) in candidates {
            if best.as_ref().is_some_and(|(cost, _, _)| lower > *cost) {
                break;
            }
            let target = points[k];
            let h = |c: Cell| {
                Cost::octile_distance(c.x.abs_diff(target.x), c.y.abs_diff(target.y))
                    .times(min_weight)
            };
            let (status, cells, counters) =
                reference_astar(grid, &eight, h, Tie::Fifo, here, target);
            tally[4] += 1;
            tally[5] += counters[0];
            let Some(cells) = cells.filter(|_| status == Status::Found) else {
                continue;
            };
            let cost = grid.path_cost(&cells);
            let better = best
                .as_ref()
                .is_none_or(|(b, order, _)| cost < *b || (cost == *b && k > *order));
            if better {
                best = Some((cost, k, cells));
            }
        }
        let Some((_, _, route)) = best else {
            break;
        };
        for &cell in &route[1..] {
            enter(
                cell,
                &mut path,
                &mut visited,
                &mut marked,
                &mut points,
                &mut tally,
            );
            tally[3] += 1;
        }
        tally[0] += 1;
    }
    let metrics = CoverageMetrics::measure(grid, start, &Path::new(path.clone()));
    let counters = [
        metrics.n_reachable,
        metrics.n_covered,
        metrics.n_revisits,
        metrics.path.steps,
        metrics.path.turns,
        tally[0],
        tally[1],
        tally[2],
        tally[3],
        tally[4],
        tally[5],
    ];
    (path, counters)
}
