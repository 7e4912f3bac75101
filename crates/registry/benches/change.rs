//! What a grid change costs each planner: the time of a trivial plan (start and goal side
//! by side) right after one cell of the grid flipped, which is the planner rebuilding its
//! per-grid tables for the new grid revision (masks, bit grids, summed-area tables), or
//! bringing them up to date from the grid's log of changed cells
//! ([`planner_api::Grid::changed_since`]), and almost nothing else. A robot whose map
//! changes as it drives pays this before every replan on a changed map. Beside it, the same
//! plan on a copy of the grid without that log and with another cell flipped (a new grid to
//! the planner): the full build.
//!
//! `cargo bench -p planner-registry --bench change [-- SIDE] [--weighted]` (default 2048: a
//! square grid whose cells are 10 % blocked in a fixed scattered pattern) prints a line per
//! planner label, `planner=<label> change_ms=<t> rebuild_ms=<t> status=<status>`, each the
//! best of five plans, for every registered start-goal planner with its defaults and A*
//! with 8 and 16 directions. With `--weighted` the grid carries weights 1 to 9 (the mean
//! rule; a hash of the cell's index) and a change is also a new weight for the flipped
//! cell, for the planners that honour weights only.
//! Each plan has a budget of one second: a planner that does not find the neighbouring
//! goal within it (backtracking enumerates paths) is reported with its status, and its
//! time is the budget's, not a change's cost.

use std::time::{Duration, Instant};

use planner_api::{Budget, Cell, Grid, Problem};
use planner_registry::{Built, PLANNERS};

fn main() {
    let side: u32 = std::env::args()
        .skip(1)
        .find(|a| !a.starts_with('-'))
        .map_or(2048, |a| a.parse().expect("a grid side in cells"));
    // A multiplicative hash of the cell's index: about one cell in ten blocked.
    let free = (0..u64::from(side) * u64::from(side))
        .map(|i| i.wrapping_mul(0x9e37_79b9_7f4a_7c15) >> 32 & 1023 >= 102)
        .collect();
    let mut grid = Grid::from_free_cells(side, side, free).expect("a valid grid");
    let weighted = std::env::args().any(|a| a == "--weighted");
    let weights: Vec<u16> = (0..u64::from(side) * u64::from(side))
        .map(|i| 1 + (i.wrapping_mul(0xd6e8_feb8_6659_fd93) >> 40) as u16 % 9)
        .collect();
    // A copy of `grid`'s cells with the bench's weights when weighted: a new grid.
    let anew = |grid: &Grid| match weighted {
        true => grid
            .without_weights()
            .with_weights(weights.clone(), planner_api::CostRule::Mean)
            .expect("one weight per cell, none 0"),
        false => grid.without_weights(),
    };
    grid = anew(&grid);
    // Two free cells side by side, away from the cells that flip (row 0).
    let start = grid
        .cells()
        .find(|c| {
            c.y > 0 && c.x + 1 < side && grid.is_free(*c) && grid.is_free(Cell::new(c.x + 1, c.y))
        })
        .expect("two free cells side by side");
    let goal = Cell::new(start.x + 1, start.y);
    let mut labels: Vec<(String, &str, toml::Table)> = PLANNERS
        .iter()
        .map(|e| (e.name.to_owned(), e.name, toml::Table::new()))
        .collect();
    for moves in [8, 16] {
        let mut params = toml::Table::new();
        params.insert("moves".into(), toml::Value::Integer(moves));
        labels.push((format!("astar[moves={moves}]"), "astar", params));
    }
    let budget = Budget {
        max_time: Some(Duration::from_secs(1)),
        ..Budget::unlimited()
    };
    for (label, name, params) in labels {
        let Some(entry) = planner_registry::find(name) else {
            continue;
        };
        let Ok(factory) = (entry.factory)(&params) else {
            continue;
        };
        if weighted && !factory.specs().cell_costs {
            continue;
        }
        let Ok(Built::Path(mut planner)) = factory.build() else {
            continue;
        };
        let problem = Problem::new(&grid, start, goal).expect("free cells in the grid");
        planner.plan(&problem, &budget);
        let mut status = None;
        let best = (0..5)
            .map(|k| {
                let cell = Cell::new(k, 0);
                grid.set_free(cell, !grid.is_free(cell));
                grid.set_weight(cell, 1 + (grid.weight(cell) + k as u16) % 9);
                let problem = Problem::new(&grid, start, goal).expect("free cells in the grid");
                let started = Instant::now();
                status = Some(planner.plan(&problem, &budget).status);
                started.elapsed().as_secs_f64() * 1e3
            })
            .fold(f64::INFINITY, f64::min);
        let rebuild = (0..5)
            .map(|k| {
                // A new revision without a log of the changes since the planner's tables
                // were built, and one cell different (caches that compare the cells to
                // tell a new grid equal to their own do not take it).
                let mut fresh = anew(&grid);
                let cell = Cell::new(side - 1 - k.min(side - 1), side - 1);
                if cell != start && cell != goal {
                    fresh.set_free(cell, !fresh.is_free(cell));
                }
                let problem = Problem::new(&fresh, start, goal).expect("free cells in the grid");
                let started = Instant::now();
                planner.plan(&problem, &budget);
                started.elapsed().as_secs_f64() * 1e3
            })
            .fold(f64::INFINITY, f64::min);
        let status = status.map(|s| format!("{s:?}")).unwrap_or_default();
        println!("planner={label} change_ms={best:.2} rebuild_ms={rebuild:.2} status={status}");
    }
}
