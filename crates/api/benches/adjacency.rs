//! The time to build an [`Adjacency`] (every cell's safe-move mask), which a search pays
//! once per grid revision: for every neighbourhood on square grids whose cells are 10 %
//! blocked in a fixed scattered pattern.
//!
//! `cargo bench -p planner-api --bench adjacency [-- SIDE ...]` (default sides 512 and
//! 2048) prints a line per side and neighbourhood, `side=<n> moves=<n> build_ms=<t>
//! rebuild_ms=<t> update_ms=<t>`: the best of five builds from nothing; the best of five
//! rebuilds through [`Adjacency::cached`] for a grid one cell different from the cached
//! one (a copy, so with no log of edits: rebuilt in the masks' memory); and the best of
//! five lookups after one cell of the cached grid was edited in place
//! ([`Grid::changed_since`]: the masks around it brought up to date).

use std::time::Instant;

use planner_api::{Adjacency, Cell, Connectivity, Grid, MoveSet};

fn main() {
    let sides: Vec<u32> = std::env::args()
        .skip(1)
        .filter(|a| !a.starts_with('-'))
        .map(|a| a.parse().expect("a grid side in cells"))
        .collect();
    let sides = if sides.is_empty() {
        vec![512, 2048]
    } else {
        sides
    };
    for side in sides {
        // A multiplicative hash of the cell's index: about one cell in ten blocked.
        let free = (0..u64::from(side) * u64::from(side))
            .map(|i| i.wrapping_mul(0x9e37_79b9_7f4a_7c15) >> 32 & 1023 >= 102)
            .collect();
        let grid = Grid::from_free_cells(side, side, free).expect("a valid grid");
        for connectivity in Connectivity::ALL {
            let moves = MoveSet::standard(connectivity);
            let best = (0..5)
                .map(|_| {
                    let started = Instant::now();
                    let adjacency = Adjacency::build(&grid, &moves);
                    let elapsed = started.elapsed().as_secs_f64() * 1e3;
                    assert_eq!(adjacency.n_moves(), moves.moves().len());
                    elapsed
                })
                .fold(f64::INFINITY, f64::min);
            let mut cache = Some(Adjacency::build(&grid, &moves));
            // A lookup of `grid` in the cache, timed.
            let mut timed = |grid: &Grid| {
                let started = Instant::now();
                let adjacency = Adjacency::cached(&mut cache, grid, &moves);
                let elapsed = started.elapsed().as_secs_f64() * 1e3;
                assert!(adjacency.is_for(grid));
                elapsed
            };
            let rebuild = (0..5)
                .map(|k| {
                    let mut other = grid.without_weights();
                    let cell = Cell::new(k, 0);
                    other.set_free(cell, !other.is_free(cell));
                    timed(&other)
                })
                .fold(f64::INFINITY, f64::min);
            timed(&grid);
            let mut edited = grid.clone();
            let update = (0..5)
                .map(|k| {
                    let cell = Cell::new(k, 0);
                    edited.set_free(cell, !edited.is_free(cell));
                    timed(&edited)
                })
                .fold(f64::INFINITY, f64::min);
            println!(
                "side={side} moves={} build_ms={best:.2} rebuild_ms={rebuild:.2} \
                 update_ms={update:.3}",
                moves.moves().len()
            );
        }
    }
}
