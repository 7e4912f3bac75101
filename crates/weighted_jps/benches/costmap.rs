//! weighted_jps against A* on weighted maps, in the same run: a real robot costmap (nav2's
//! warehouse map read as graded costs, `maps/ros-graded/SOURCE.md`) and Moving AI's arena
//! with its 7 x 7 terrain patches (`maps/weighted/arena-weights.csv`).
//!
//! `cargo bench -p planner-weighted_jps --bench costmap [-- --repeats=N --clock=cpu]
//! [map ...]` prints one line per map: `map=<name> problems=<n> unreachable=<n>
//! mismatches=<n> astar_expansions=<total> jps_expansions=<total> jps_jumps=<total>
//! astar_ms=<t> jps_ms=<t> speedup=<astar/jps>`. A mismatch is a problem whose two exact
//! path costs differ. A* is planner-astar with the octile heuristic times the smallest
//! weight, 8 directions without corner cutting (weighted_jps's moves), larger g first
//! among equal f (its bench's rule) and all counters on. The warehouse's problems are 200
//! seeded pairs of free cells (xorshift, seed 33), arena's every scenario of its `.scen`
//! file. Each side runs the whole set `--repeats=N` times (default 3), alternating; its
//! best time counts, and every pass must give the same results.

use std::path::PathBuf;

use planner_api::{Budget, Cell, Connectivity, CostRule, Grid, Planner, Problem};
use planner_astar::{AStar, Config as AStarConfig, Heuristic, TieBreak};
use planner_bench::{best_of_alternating, Repeats};
use planner_maps::{read_map_with, ReadOptions};
use planner_weighted_jps::{Config, WeightedJps};

fn maps_dir() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../maps")
}

/// A map and its start-goal pairs.
type Problems = (Grid, Vec<(Cell, Cell)>);

/// The warehouse costmap and 200 seeded pairs of free cells.
fn warehouse() -> Problems {
    let mut options = ReadOptions::default();
    options.costs.graded = true;
    let path = maps_dir().join("ros-graded/warehouse-scale.yaml");
    let grid = read_map_with(&path, &options)
        .unwrap_or_else(|e| panic!("{e}"))
        .file
        .grid;
    let free: Vec<Cell> = grid.cells().filter(|&c| grid.is_free(c)).collect();
    let mut next = planner_testkit::xorshift(33u64);
    let pairs = (0..200)
        .map(|_| {
            let a = free[(next() % free.len() as u64) as usize];
            let b = free[(next() % free.len() as u64) as usize];
            (a, b)
        })
        .collect();
    (grid, pairs)
}

/// Arena with its terrain weights and every scenario.
fn arena() -> Problems {
    let grid = read_map_with(
        &maps_dir().join("movingai/arena.map"),
        &ReadOptions::default(),
    )
    .unwrap_or_else(|e| panic!("{e}"))
    .file
    .grid;
    let grid = planner_maps::read_weights(
        &maps_dir().join("weighted/arena-weights.csv"),
        grid,
        CostRule::Mean,
        &ReadOptions::default(),
    )
    .unwrap_or_else(|e| panic!("{e}"));
    let scenarios = planner_maps::read_scenarios(&maps_dir().join("movingai/arena.map.scen"))
        .unwrap_or_else(|e| panic!("{e}"));
    let pairs = scenarios.iter().map(|s| (s.start, s.goal)).collect();
    (grid, pairs)
}

/// The exact costs of one side's paths and its total expansions (and jumps tried).
type Pass = (Vec<Option<u64>>, u64, u64);

fn run(planner: &mut dyn Planner, grid: &Grid, problems: &[Problem<'_>]) -> Pass {
    let (mut expanded, mut jumps) = (0, 0);
    let costs = problems
        .iter()
        .map(|problem| {
            let outcome = planner.plan(problem, &Budget::unlimited());
            expanded += outcome.counters.get("n_expanded").unwrap_or(0);
            jumps += outcome.counters.get("n_jumps").unwrap_or(0);
            outcome.path.map(|p| grid.path_cost(p.cells()).units())
        })
        .collect();
    (costs, expanded, jumps)
}

fn main() {
    let (repeats, filter) = Repeats::parse(std::env::args().skip(1)).unwrap_or_else(|e| {
        eprintln!("{e}");
        std::process::exit(2);
    });
    for name in ["warehouse-scale", "arena-weights"] {
        if !filter.is_empty() && !filter.iter().any(|f| f == name) {
            continue;
        }
        let (grid, pairs) = match name {
            "warehouse-scale" => warehouse(),
            _ => arena(),
        };
        let problems: Vec<Problem<'_>> = pairs
            .iter()
            .filter_map(|&(a, b)| Problem::new(&grid, a, b).ok())
            .collect();
        let mut astar = AStar::new(AStarConfig {
            moves: Connectivity::Eight,
            heuristic: Heuristic::Octile,
            tie_break: TieBreak::HighG,
            ..AStarConfig::default()
        })
        .unwrap_or_else(|e| panic!("{e}"));
        let mut jps = WeightedJps::new(Config::default()).unwrap_or_else(|e| panic!("{e}"));
        astar.prepare(&grid);
        jps.prepare(&grid);
        let (a, j) = best_of_alternating(
            repeats,
            || run(&mut astar, &grid, &problems),
            || run(&mut jps, &grid, &problems),
        )
        .unwrap_or_else(|e| panic!("{e}"));
        let mismatches = a
            .result
            .0
            .iter()
            .zip(&j.result.0)
            .filter(|(x, y)| x != y)
            .count();
        let unreachable = a.result.0.iter().filter(|c| c.is_none()).count();
        let (astar_ms, jps_ms) = (a.best.as_secs_f64() * 1e3, j.best.as_secs_f64() * 1e3);
        println!(
            "map={name} problems={} unreachable={unreachable} mismatches={mismatches} astar_expansions={} jps_expansions={} jps_jumps={} astar_ms={astar_ms:.1} jps_ms={jps_ms:.1} speedup={:.2}",
            problems.len(),
            a.result.1,
            j.result.1,
            j.result.2,
            astar_ms / jps_ms,
        );
    }
}
