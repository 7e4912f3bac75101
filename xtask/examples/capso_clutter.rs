//! How often CAPSO finds a path on random clutter, by obstacle density, beside Theta\*.
//!
//! `cargo run --release -p xtask --example capso_clutter -- [CONTROL_POINTS]` (default 6,
//! seed 002's) draws 300 maps of 20-79 x 15-59 cells whose cells are blocked independently
//! with probability 0.05, 0.15, 0.25 or 0.35 (in turn), and a start and goal among the
//! free cells (xorshift64, fixed seed); it keeps the problems Theta\* solves (so a path
//! exists) and runs CAPSO with the defaults but the control points, seed = the map's
//! number. It prints the problems per density, those CAPSO missed, and CAPSO's length over
//! Theta\*'s for the paths it found (Theta\*'s paths are any-angle but not always
//! shortest, so the ratio can fall below 1).

use planner_api::{Budget, Cell, Grid, Planner, Problem, Status};
use planner_capso::{Capso, Config};

const DENSITIES: [f64; 4] = [0.05, 0.15, 0.25, 0.35];

fn main() {
    let control_points: u32 = match std::env::args().nth(1).map(|a| a.parse()) {
        None => 6,
        Some(Ok(n)) => n,
        Some(Err(_)) => {
            eprintln!("CONTROL_POINTS: expected an integer in 1..=20");
            std::process::exit(2);
        }
    };
    let mut next = planner_testkit::xorshift(0x9e37_79b9_7f4a_7c15);
    let theta = planner_registry::find("theta_star").expect("registered");
    let (mut tried, mut missed) = ([0u32; 4], [0u32; 4]);
    let mut ratios = Vec::new();
    for round in 0..300 {
        let (w, h) = (20 + (next() % 60) as u32, 15 + (next() % 45) as u32);
        let density = DENSITIES[round % 4];
        let rows: Vec<String> = (0..h)
            .map(|_| {
                (0..w)
                    .map(|_| match (next() % 1000) as f64 / 1000.0 < density {
                        true => '#',
                        false => '.',
                    })
                    .collect()
            })
            .collect();
        let grid = Grid::from_ascii(&rows.join("\n")).expect("a rectangle of . and #");
        let free: Vec<Cell> = (0..h)
            .flat_map(|y| (0..w).map(move |x| Cell::new(x, y)))
            .filter(|&c| grid.is_free(c))
            .collect();
        if free.len() < 2 {
            continue;
        }
        let start = free[(next() % free.len() as u64) as usize];
        let goal = free[(next() % free.len() as u64) as usize];
        if start == goal {
            continue;
        }
        let problem = Problem::new(&grid, start, goal).expect("free cells in the grid");
        let built = (theta.factory)(&toml::Table::new()).and_then(|f| f.build());
        let Ok(planner_registry::Built::Path(mut theta_star)) = built else {
            unreachable!("Theta* builds with its defaults");
        };
        let reference = theta_star.plan(&problem, &Budget::unlimited());
        let Some(reference) = reference.path.filter(|_| reference.status == Status::Found) else {
            continue;
        };
        tried[round % 4] += 1;
        let config = Config {
            seed: round as u64,
            control_points,
            ..Config::default()
        };
        let mut capso = match Capso::new(config) {
            Ok(capso) => capso,
            Err(e) => {
                eprintln!("{e}");
                std::process::exit(2);
            }
        };
        let outcome = capso.plan(&problem, &Budget::unlimited());
        match (outcome.status, outcome.path) {
            (Status::Found, Some(path)) => {
                ratios.push(path.metrics().length / reference.metrics().length)
            }
            _ => missed[round % 4] += 1,
        }
    }
    println!("control points: {control_points}");
    for (k, density) in DENSITIES.iter().enumerate() {
        println!(
            "density {density}: {} problems, CAPSO missed {}",
            tried[k], missed[k]
        );
    }
    ratios.sort_by(f64::total_cmp);
    if let (Some(median), Some(worst)) = (ratios.get(ratios.len() / 2), ratios.last()) {
        let mean = ratios.iter().sum::<f64>() / ratios.len() as f64;
        println!("CAPSO / Theta* length: mean {mean:.4}, median {median:.4}, worst {worst:.4}");
    }
}
