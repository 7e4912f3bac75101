//! A* on weighted maps (issue 32), beside the `pathfinding` crate's A* with the same integer
//! costs, and beside A* on the same maps without weights, in the same run.
//!
//! `cargo bench -p planner-astar --bench weighted [-- --repeats=N --clock=cpu --every=K]
//! [map ...]` gives every Moving AI map of the benchmark (den520d, random512-10-0) seeded
//! random weights, uniform in 1..=255 for every cell (xorshift64, seed 32; the mean rule,
//! 8-connected, no corner cutting), runs every K-th scenario of its `.scen` file (default
//! 16) and prints two lines per map:
//! - `map=<name> weighted ... peer_expansions=... gridplan_ms ... pathfinding_ms ...
//!   ratio=<pathfinding/gridplan>` with `mismatches` the scenarios whose exact integer
//!   costs differ (the peer computes gridplan's own integers: `planner_bench::WeightedPeer`);
//! - `map=<name> per_expansion weighted_ns=<t> unweighted_ns=<t> ratio=<weighted/unweighted>
//!   weighted_expansions=<n> unweighted_expansions=<n>`: A*'s time per expansion on the
//!   weighted map against A* (the same configuration) on the map without weights, both timed
//!   alternately in this run;
//! - `map=<name> uniform_weights ...`: the same with every weight 1 instead of random, so
//!   that both sides expand exactly the same cells (the cost of the weighted loop alone,
//!   without the larger OPEN lists of the random weights' weaker heuristic).
//!
//! gridplan runs with all its counters on, the octile heuristic times the smallest weight,
//! and the peer's tie rule (larger g first). Each side runs the whole selection
//! `--repeats=N` times (default 3), alternating, its best time counts, and every pass must
//! give the same results.

use planner_api::{Budget, Connectivity, CostRule, Grid, Problem};
use planner_astar::{AStar, Config, Heuristic, TieBreak};
use planner_bench::{best_of_alternating, load_movingai, seeded_weights, Repeats, WeightedPeer};

const MAPS: [&str; 2] = ["den520d", "random512-10-0"];
const SEED: u64 = 32;
const MAX_WEIGHT: u16 = 255;

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let every = args
        .iter()
        .find_map(|a| a.strip_prefix("--every="))
        .map_or(Ok(16), str::parse::<usize>)
        .ok()
        .filter(|&k| k >= 1)
        .unwrap_or_else(|| {
            eprintln!("--every: expected an integer >= 1");
            std::process::exit(2);
        });
    let (repeats, filter) = Repeats::parse(args).unwrap_or_else(|e| {
        eprintln!("{e}");
        std::process::exit(2);
    });
    for name in MAPS
        .iter()
        .filter(|m| filter.is_empty() || filter.iter().any(|f| f == *m))
    {
        let (grid, scenarios) = load_movingai(name).unwrap_or_else(|e| panic!("{e}"));
        let weighted = seeded_weights(&grid, SEED, MAX_WEIGHT, CostRule::Mean);
        let pairs: Vec<_> = scenarios
            .iter()
            .step_by(every)
            .map(|s| (s.start, s.goal))
            .collect();
        run(name, &grid, &weighted, &pairs, repeats);
        let uniform = seeded_weights(&grid, SEED, 1, CostRule::Mean);
        per_expansion(name, "uniform_weights", &grid, &uniform, &pairs, repeats);
    }
}

/// Costs (exact units) and total expansions of one pass.
type Pass = (Vec<Option<u64>>, u64);

fn astar() -> AStar {
    let config = Config {
        moves: Connectivity::Eight,
        heuristic: Heuristic::Octile,
        tie_break: TieBreak::HighG,
        ..Config::default()
    };
    AStar::new(config).unwrap_or_else(|e| panic!("{e}"))
}

fn searches(astar: &mut AStar, problems: &[Problem<'_>]) -> Pass {
    let mut n_expanded = 0;
    let costs = problems
        .iter()
        .map(|problem| {
            let search = astar.search(problem, &Budget::unlimited());
            n_expanded += search.stats.n_expanded;
            search.exact_cost.map(|c| c.units())
        })
        .collect();
    (costs, n_expanded)
}

fn run(
    name: &str,
    grid: &Grid,
    weighted: &Grid,
    pairs: &[(planner_api::Cell, planner_api::Cell)],
    repeats: Repeats,
) {
    let on_weighted: Vec<Problem<'_>> = pairs
        .iter()
        .map(|&(s, t)| Problem::new(weighted, s, t).unwrap_or_else(|e| panic!("{e}")))
        .collect();
    let mut ours = astar();
    let peer = WeightedPeer::new(weighted);
    let theirs = || -> Pass {
        let mut n_expanded = 0;
        let costs = pairs
            .iter()
            .map(|&(s, t)| {
                peer.octile(s, t).map(|(cost, n)| {
                    n_expanded += n;
                    cost
                })
            })
            .collect();
        (costs, n_expanded)
    };
    let (a, b) = best_of_alternating(repeats, || searches(&mut ours, &on_weighted), theirs)
        .unwrap_or_else(|e| panic!("{e}"));
    let mismatches = a
        .result
        .0
        .iter()
        .zip(&b.result.0)
        .filter(|(x, y)| x != y)
        .count();
    let ms = |d: std::time::Duration| d.as_secs_f64() * 1e3;
    println!(
        "map={name} weighted scenarios={} mismatches={mismatches} expansions={} peer_expansions={} \
         gridplan_ms={:.1} pathfinding_ms={:.1} ratio={:.2}",
        pairs.len(),
        a.result.1,
        b.result.1,
        ms(a.best),
        ms(b.best),
        b.best.as_secs_f64() / a.best.as_secs_f64().max(1e-12)
    );
    per_expansion(name, "per_expansion", grid, weighted, pairs, repeats);
}

/// A* per expansion on `weighted` against the unweighted `grid`, alternating, one line.
fn per_expansion(
    name: &str,
    what: &str,
    grid: &Grid,
    weighted: &Grid,
    pairs: &[(planner_api::Cell, planner_api::Cell)],
    repeats: Repeats,
) {
    let problems = |g| -> Vec<Problem<'_>> {
        pairs
            .iter()
            .map(|&(s, t)| Problem::new(g, s, t).unwrap_or_else(|e| panic!("{e}")))
            .collect()
    };
    let (on_weighted, on_plain) = (problems(weighted), problems(grid));
    let (mut ours, mut plain) = (astar(), astar());
    let (w, u) = best_of_alternating(
        repeats,
        || searches(&mut ours, &on_weighted),
        || searches(&mut plain, &on_plain),
    )
    .unwrap_or_else(|e| panic!("{e}"));
    let per = |t: std::time::Duration, n: u64| t.as_secs_f64() * 1e9 / n.max(1) as f64;
    let (w_ns, u_ns) = (per(w.best, w.result.1), per(u.best, u.result.1));
    println!(
        "map={name} {what} weighted_ns={w_ns:.1} unweighted_ns={u_ns:.1} ratio={:.2} \
         weighted_expansions={} unweighted_expansions={}",
        w_ns / u_ns,
        w.result.1,
        u.result.1
    );
}
