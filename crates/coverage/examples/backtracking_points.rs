//! Seed 004 reports fewer backtracking points for zigzag (two) than for spiral (three) on its
//! 30 x 30 map. This counts them on many seeded 30 x 30 maps of random rectangles (start
//! (0, 0), unreachable pockets blocked, as in `maps/coverage/`):
//!
//! `cargo run --release -p planner-coverage --example backtracking_points [n_maps]`

use planner_api::{Budget, Cell, CoveragePlanner, CoverageProblem};
use planner_coverage::generate::{keep_component, random_blocks};
use planner_coverage::{Config, Coverage, Pattern, Rotation, Side};

fn main() {
    let n_maps: u64 = std::env::args()
        .nth(1)
        .and_then(|a| a.parse().ok())
        .unwrap_or(200);
    let configs = [
        (
            "spiral",
            Config {
                reference_side: Some(Side::Left),
                ..Config::default()
            },
        ),
        (
            "zigzag",
            Config {
                pattern: Pattern::Zigzag,
                rotation: Some(Rotation::CounterClockwise),
                ..Config::default()
            },
        ),
    ];
    let mut planners: Vec<Coverage> = configs
        .iter()
        .map(|(_, c)| Coverage::new(c.clone()).expect("valid config"))
        .collect();
    println!("{n_maps} maps of 30 x 30 per row, rectangles with sides 1..=max_side");
    println!("| rectangles | max side | mean spiral | mean zigzag | zigzag fewer | spiral fewer | equal |");
    println!("|---:|---:|---:|---:|---:|---:|---:|");
    for (n_blocks, max_side) in [(4, 6), (8, 6), (12, 5), (20, 5)] {
        let mut sums = [0u64; 2];
        let mut wins = [0u64; 3];
        for seed in 1..=n_maps {
            let start = Cell::new(0, 0);
            let mut grid =
                random_blocks(30, 30, n_blocks, max_side, start, seed).expect("valid parameters");
            keep_component(&mut grid, start);
            let problem = CoverageProblem::new(&grid, start).expect("the start is kept free");
            let counts: Vec<u64> = planners
                .iter_mut()
                .map(|p| p.cover(&problem, &Budget::unlimited()).returns.len() as u64)
                .collect();
            sums[0] += counts[0];
            sums[1] += counts[1];
            let k = match counts[0].cmp(&counts[1]) {
                std::cmp::Ordering::Greater => 0,
                std::cmp::Ordering::Less => 1,
                std::cmp::Ordering::Equal => 2,
            };
            wins[k] += 1;
        }
        println!(
            "| {n_blocks} | {max_side} | {:.2} | {:.2} | {} | {} | {} |",
            sums[0] as f64 / n_maps as f64,
            sums[1] as f64 / n_maps as f64,
            wins[0],
            wins[1],
            wins[2]
        );
    }
}
