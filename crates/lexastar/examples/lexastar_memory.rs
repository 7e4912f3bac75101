//! Memory of lexastar after a bounded search on a large open grid. Run it under
//! `/usr/bin/time -v` for the peak memory:
//!
//! `cargo run --release -p planner-lexastar --example lexastar_memory -- [--open N] [--expansions K]`
//!
//! Searches an obstacle-free N x N grid (default 4000) from the top-left to the
//! bottom-right cell, 4-connected, for at most K state expansions (default 1000), and
//! prints `cells=.. search_ms=.. status=.. n_expanded=..`.

use std::time::Instant;

use planner_api::{Budget, Cell, Grid, Planner, Problem};
use planner_lexastar::{Config, LexAStar};

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let number = |flag: &str, default: u64| {
        args.iter()
            .position(|a| a == flag)
            .and_then(|i| args.get(i + 1))
            .map_or(Some(default), |v| v.parse().ok())
            .unwrap_or_else(|| exit(&format!("{flag} takes a number")))
    };
    let n = number("--open", 4000) as u32;
    let grid = Grid::new(n, n).unwrap_or_else(|e| exit(&e.to_string()));
    let mut planner = LexAStar::new(Config::default()).unwrap_or_else(|e| exit(&e.to_string()));
    let problem = Problem::new(&grid, Cell::new(0, 0), Cell::new(n - 1, n - 1))
        .unwrap_or_else(|e| exit(&e.to_string()));
    let started = Instant::now();
    let outcome = planner.plan(&problem, &Budget::expansions(number("--expansions", 1000)));
    let search_ms = started.elapsed().as_secs_f64() * 1e3;
    println!(
        "cells={} search_ms={search_ms:.0} status={} n_expanded={}",
        grid.len(),
        outcome.status.as_str(),
        outcome.counters.get("n_expanded").unwrap_or(0)
    );
}

fn exit(message: &str) -> ! {
    eprintln!("{message}");
    std::process::exit(2)
}
