//! A* on full Moving AI scenario files, beside the `pathfinding` crate's A* in the same run.
//!
//! `cargo bench -p planner-astar --bench movingai [-- --repeats=N --clock=cpu] [map ...]` prints one
//! line per map and move set:
//! `map=<name> moves=<8|4> scenarios=<n> mismatches=<n> expansions=<gridplan total>
//! peer_expansions=<pathfinding total> gridplan_ms=<t> pathfinding_ms=<t>
//! ratio=<pathfinding/gridplan>`.
//!
//! The peer is planner-bench's [`Peer`]: the pathfinding crate with integer costs, its
//! fastest documented use. 8-connected runs (octile heuristic, no corner cutting, the
//! benchmark's own rules) count a mismatch when either side's length is off the
//! scenario's optimum (relative tolerance 1e-4); 4-connected runs (Manhattan) when the
//! two sides' step counts differ. gridplan runs with all its counters on and with the
//! peer's tie rule (larger g first among equal f). Each side runs the whole scenario file
//! `--repeats=N` times (default 3), alternating, and its best time counts; every pass
//! must give the same lengths and counts. Times are wall time, or with `--clock=cpu` the
//! thread's time on a CPU (Linux; a loaded machine's waits for a core do not count). Map
//! names as arguments run a subset.

use planner_api::{Budget, Connectivity, Grid, Problem};
use planner_astar::{AStar, Config, Heuristic, TieBreak};
use planner_bench::{best_of_alternating, close, load_movingai, Line, Peer, Repeats, STRAIGHT};
use planner_maps::Scenario;

const MAPS: [&str; 2] = ["den520d", "random512-10-0"];

fn main() {
    let (repeats, filter) = Repeats::parse(std::env::args().skip(1)).unwrap_or_else(|e| {
        eprintln!("{e}");
        std::process::exit(2);
    });
    for name in MAPS
        .iter()
        .filter(|m| filter.is_empty() || filter.iter().any(|f| f == *m))
    {
        let (grid, scenarios) = load_movingai(name).unwrap_or_else(|e| panic!("{e}"));
        for moves in [Connectivity::Eight, Connectivity::Four] {
            println!("{}", run(name, &grid, &scenarios, moves, repeats));
        }
    }
}

/// Lengths (in the map's units) and the total expansions of one side's pass.
type Pass = (Vec<Option<f64>>, u64);

fn run(
    name: &str,
    grid: &Grid,
    scenarios: &[Scenario],
    moves: Connectivity,
    repeats: Repeats,
) -> Line {
    let config = Config {
        moves,
        heuristic: match moves {
            Connectivity::Four => Heuristic::Manhattan,
            _ => Heuristic::Octile,
        },
        // The pathfinding crate pops the larger g among equal f; use the same rule so both
        // expand comparable sets (the paper's FIFO expands whole f-bands on open grids).
        tie_break: TieBreak::HighG,
        ..Config::default()
    };
    let mut astar = AStar::new(config).unwrap_or_else(|e| panic!("{e}"));
    let problems: Vec<Problem<'_>> = scenarios
        .iter()
        .map(|s| Problem::new(grid, s.start, s.goal).unwrap_or_else(|e| panic!("{e}")))
        .collect();
    let ours = || -> Pass {
        let mut n_expanded = 0;
        let lengths = problems
            .iter()
            .map(|problem| {
                let search = astar.search(problem, &Budget::unlimited());
                n_expanded += search.stats.n_expanded;
                search.cost
            })
            .collect();
        (lengths, n_expanded)
    };
    let peer = Peer::new(grid);
    let theirs = || -> Pass {
        let mut n_expanded = 0;
        let lengths = scenarios
            .iter()
            .map(|s| {
                let found = match moves {
                    Connectivity::Four => peer.manhattan(s.start, s.goal),
                    _ => peer.octile(s.start, s.goal),
                };
                found.map(|(cost, n)| {
                    n_expanded += n;
                    cost as f64 / STRAIGHT as f64
                })
            })
            .collect();
        (lengths, n_expanded)
    };
    let (ours, theirs) =
        best_of_alternating(repeats, ours, theirs).unwrap_or_else(|e| panic!("{e}"));

    let mut mismatches = 0;
    for ((s, a), b) in scenarios.iter().zip(&ours.result.0).zip(&theirs.result.0) {
        let reference = match moves {
            Connectivity::Four => *b,
            _ => Some(s.optimal_length),
        };
        let agree = match (a, reference, b) {
            (Some(a), Some(r), Some(b)) => close(*a, r) && close(*b, r),
            _ => false,
        };
        if !agree {
            mismatches += 1;
            eprintln!(
                "mismatch {name} line {}: ours {a:?} theirs {b:?} reference {reference:?}",
                s.line
            );
        }
    }
    Line {
        map: name.to_string(),
        moves: moves.n_directions(),
        scenarios: scenarios.len(),
        mismatches,
        expansions: ours.result.1,
        peer_expansions: theirs.result.1,
        gridplan: ours.best,
        pathfinding: theirs.best,
    }
}
