//! Time and memory of one A* query on a large grid, with reading and setup timed apart
//! from the search. Run it under `/usr/bin/time -v` for the peak memory:
//!
//! `cargo run --release -p planner-astar --example astar_memory -- (--png FILE | --open N)
//! [--moves 4|8] [--expansions K]`
//!
//! `--open N` searches an obstacle-free N x N grid built in memory, `--png FILE` a map
//! read through planner-maps; the query runs from the top-left to the bottom-right cell.
//! With `--moves 8` (the default) A* uses the octile heuristic and the larger g first
//! among equal f (the benchmark's setting); with `--moves 4` the crate's defaults
//! (Manhattan, FIFO), which on an open grid expand the whole rectangle. Prints one line:
//! `read_ms=.. cells=.. prepare_ms=.. search_ms=.. status=.. n_expanded=..`.

use std::time::Instant;

use planner_api::{Budget, Cell, Connectivity, Grid, Planner, Problem};
use planner_astar::{AStar, Config, Heuristic, TieBreak};

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let value = |flag: &str| {
        args.iter()
            .position(|a| a == flag)
            .and_then(|i| args.get(i + 1))
            .cloned()
    };
    let started = Instant::now();
    let grid = match (value("--png"), value("--open")) {
        (Some(file), _) => match planner_maps::read_map(std::path::Path::new(&file)) {
            Ok(map) => map.grid,
            Err(e) => exit(&e.to_string()),
        },
        (None, Some(n)) => {
            let n: u32 = n
                .parse()
                .unwrap_or_else(|_| exit("--open takes a side length"));
            Grid::new(n, n).unwrap_or_else(|e| exit(&e.to_string()))
        }
        (None, None) => exit("give --png FILE or --open N"),
    };
    let read_ms = started.elapsed().as_secs_f64() * 1e3;
    let eight = value("--moves").as_deref() != Some("4");
    let config = if eight {
        Config {
            moves: Connectivity::Eight,
            heuristic: Heuristic::Octile,
            tie_break: TieBreak::HighG,
            ..Config::default()
        }
    } else {
        Config::default()
    };
    let budget = match value("--expansions") {
        Some(k) => Budget::expansions(k.parse().unwrap_or_else(|_| exit("--expansions K"))),
        None => Budget::unlimited(),
    };
    let mut astar = AStar::new(config).unwrap_or_else(|e| exit(&e.to_string()));
    let corner = Cell::new(grid.width() - 1, grid.height() - 1);
    let problem =
        Problem::new(&grid, Cell::new(0, 0), corner).unwrap_or_else(|e| exit(&e.to_string()));
    let setup = Instant::now();
    astar.prepare(&grid);
    let prepare_ms = setup.elapsed().as_secs_f64() * 1e3;
    let searched = Instant::now();
    let outcome = astar.plan(&problem, &budget);
    let search_ms = searched.elapsed().as_secs_f64() * 1e3;
    println!(
        "read_ms={read_ms:.0} cells={} prepare_ms={prepare_ms:.0} search_ms={search_ms:.0} status={} n_expanded={}",
        grid.len(),
        outcome.status.as_str(),
        outcome.counters.get("n_expanded").unwrap_or(0)
    );
}

fn exit(message: &str) -> ! {
    eprintln!("{message}");
    std::process::exit(2)
}
