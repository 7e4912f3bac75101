//! A* alone on the Moving AI bench's searches, for profilers and for timing two builds
//! against each other (the benches also run the peer, which a profile of A* would mix in).
//!
//! `cargo run --release -p planner-astar --example search_alone -- [MAP] [PASSES]
//! [--unweighted] [--four] [--every=K]` (defaults: den520d, 1 pass, weighted, 8-connected,
//! every 16th scenario) runs A* as `cargo bench -p planner-astar --bench weighted` does
//! (8-connected, octile heuristic, larger g first among equal f) on every K-th scenario of
//! the map's `.scen` file, `PASSES` times, on the map with the bench's weights (seeded,
//! 1-255, the mean rule) or, with `--unweighted`, without weights (with `--every=1` the
//! `movingai` bench's 8-connected line; `--four` its 4-connected one: Manhattan), and
//! prints `<expansions> expansions <total time> best pass <time of the fastest pass>`. PERFORMANCE.md's A*
//! sections time two builds of it run alternately (`for i in $(seq 15); do old; new; done`,
//! minimum and median of each) and count its instructions under callgrind
//! (`valgrind --tool=callgrind --toggle-collect='planner_astar::AStar::run*' <binary>`).

use planner_api::{Budget, Connectivity, CostRule, Problem};
use planner_astar::{AStar, Config, Heuristic, TieBreak};

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let fail = |what: &str| -> ! {
        eprintln!("{what}");
        std::process::exit(2);
    };
    let unweighted = args.iter().any(|a| a == "--unweighted");
    let four = args.iter().any(|a| a == "--four");
    let every = match args.iter().find_map(|a| a.strip_prefix("--every=")) {
        None => 16,
        Some(k) => k
            .parse::<usize>()
            .ok()
            .filter(|&k| k >= 1)
            .unwrap_or_else(|| fail("--every=K: expected a whole number >= 1")),
    };
    let positional: Vec<&String> = args.iter().filter(|a| !a.starts_with("--")).collect();
    let name = positional.first().map_or("den520d", |s| s.as_str());
    let passes: usize = match positional.get(1).map(|a| a.parse()) {
        None => 1,
        Some(Ok(n)) => n,
        Some(Err(_)) => fail("PASSES: expected a whole number"),
    };
    let (grid, scenarios) =
        planner_bench::load_movingai(name).unwrap_or_else(|e| fail(&e.to_string()));
    // The weighted bench's weights: seed 32, 1 ..= 255, the mean rule.
    let weighted = planner_bench::seeded_weights(&grid, 32, 255, CostRule::Mean);
    let map = if unweighted { &grid } else { &weighted };
    let config = Config {
        moves: if four {
            Connectivity::Four
        } else {
            Connectivity::Eight
        },
        heuristic: if four {
            Heuristic::Manhattan
        } else {
            Heuristic::Octile
        },
        tie_break: TieBreak::HighG,
        ..Config::default()
    };
    let Ok(mut astar) = AStar::new(config) else {
        unreachable!("the benches' configuration is valid");
    };
    let problems: Vec<Problem<'_>> = scenarios
        .iter()
        .step_by(every)
        .filter_map(|s| Problem::new(map, s.start, s.goal).ok())
        .collect();
    let started = std::time::Instant::now();
    let (mut expansions, mut best) = (0, None);
    for _ in 0..passes {
        let pass = std::time::Instant::now();
        for problem in &problems {
            expansions += astar.search(problem, &Budget::unlimited()).stats.n_expanded;
        }
        let took = pass.elapsed();
        best = Some(best.map_or(took, |b: std::time::Duration| b.min(took)));
    }
    let best = best.unwrap_or_default();
    println!(
        "{expansions} expansions {:?} best pass {best:?}",
        started.elapsed()
    );
}
