//! What A* pays when its grid changes: [`Planner::prepare`] after one cell flipped (a new
//! grid revision), which rebuilds A*'s per-grid tables (the bit grid for 4 and 8
//! directions, the adjacency's masks for more), on square grids whose cells are 10 %
//! blocked in a fixed scattered pattern.
//!
//! `cargo bench -p planner-astar --bench prepare [-- SIDE ...]` (default 2048) prints a
//! line per side and neighbourhood, `side=<n> moves=<n> prepare_ms=<t>`, the best of five.

use std::time::Instant;

use planner_api::{Cell, Connectivity, Grid, Planner};
use planner_astar::{AStar, Config};

fn main() {
    let sides: Vec<u32> = std::env::args()
        .skip(1)
        .filter(|a| !a.starts_with('-'))
        .map(|a| a.parse().expect("a grid side in cells"))
        .collect();
    let sides = if sides.is_empty() { vec![2048] } else { sides };
    for side in sides {
        // A multiplicative hash of the cell's index: about one cell in ten blocked.
        let free = (0..u64::from(side) * u64::from(side))
            .map(|i| i.wrapping_mul(0x9e37_79b9_7f4a_7c15) >> 32 & 1023 >= 102)
            .collect();
        let mut grid = Grid::from_free_cells(side, side, free).expect("a valid grid");
        for moves in [
            Connectivity::Four,
            Connectivity::Eight,
            Connectivity::Sixteen,
            Connectivity::FortyEight,
        ] {
            let mut astar = AStar::new(Config {
                moves,
                ..Config::default()
            })
            .expect("a valid configuration");
            astar.prepare(&grid);
            let best = (0..5)
                .map(|k| {
                    let cell = Cell::new(k, 0);
                    grid.set_free(cell, !grid.is_free(cell));
                    let started = Instant::now();
                    astar.prepare(&grid);
                    started.elapsed().as_secs_f64() * 1e3
                })
                .fold(f64::INFINITY, f64::min);
            println!(
                "side={side} moves={} prepare_ms={best:.2}",
                astar.move_set().moves().len()
            );
        }
    }
}
