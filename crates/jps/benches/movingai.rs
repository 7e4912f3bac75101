//! Jump Point Search on full Moving AI scenario files, beside the `pathfinding` crate's A*
//! (planner-bench's integer-cost peer, the A* bench's) in the same run.
//!
//! `cargo bench -p planner-jps --bench movingai` runs every scenario of den520d (888) and
//! random512-10-0 (1670) with each variant and prints one line per map and variant:
//! `map=<name> variant=<jps|jps_prime|jps_plus> scenarios=<n> mismatches=<n> expansions=<n>
//! inner=<k> jps_ms=<t> pathfinding_ms=<t> ratio=<pathfinding/jps>`: `jps_ms` is the time of
//! one pass over the scenarios, from timed runs of `k` passes each (at least 0.2 s: the
//! `--clock=cpu` thread time advances in scheduler ticks of 4 ms). A scenario is a mismatch unless
//! both JPS's path length and the peer's cost equal the scenario's optimum (relative
//! 1e-4). A timed pass plans every scenario and keeps the paths, as the peer's search
//! returns its path and cost; JPS's path lengths are measured after the timing.
//! `expansions` is JPS's total `n_expanded` (jump points); the peer's expansions (cells)
//! are printed once per map as `map=<name> peer_expansions=<n>`. For `jps_plus`, a
//! line `map=<name> variant=jps_plus precompute_ms=<t> jump_table_bytes=<n>
//! bit_grid_bytes=<n>` gives the one-off precomputation (on a fresh planner), which the
//! timed queries then reuse. Marks are off (`marks = false`), so JPS builds the path
//! cell by cell but no labels.
//!
//! Each side runs the whole file `--repeats=N` times (default 3), alternating, and its best
//! time counts (planner-bench's `best_of_alternating`). Pass map names, variant names or both
//! to run a subset (`-- den520d jps_plus`). With `JPS_DUMP_COUNTERS=FILE` set, every
//! scenario's counters and path cells are appended to FILE first (one line each), so that two
//! builds can be checked to search identically (`cmp`).
//!
//! `--goal-bounding` runs every variant with goal bounding (`goal_bounding = true`) and
//! prints, per variant, `map=<name> variant=<v> goal_bounding precompute_ms=<t>
//! jump_points=<n> goal_bounds_bytes=<n>` first: the one-off build of the boxes (one
//! Dijkstra search per jump point over the pool's threads), which the timed queries reuse.
//! With `--goal-bounding` the maps are den520d alone unless named: on random512-10-0 the
//! build is long (a search of 236,000 cells for each of its many jump points).

use std::time::Instant;

use planner_api::{Budget, Grid, Path, Planner, Problem};
use planner_bench::{best_of_alternating, close, load_movingai, Peer, Repeats, STRAIGHT};
use planner_jps::{Config, Jps, Variant};
use planner_maps::Scenario;

const MAPS: [&str; 2] = ["den520d", "random512-10-0"];
/// The least time of one timed run of our side, in seconds (see `run`).
const MIN_TIMED: f64 = 0.2;
const VARIANTS: [Variant; 3] = [Variant::Jps, Variant::JpsPrime, Variant::JpsPlus];

fn main() {
    let (repeats, filters) = Repeats::parse(std::env::args().skip(1)).unwrap_or_else(|e| {
        eprintln!("{e}");
        std::process::exit(2)
    });
    let goal_bounding = std::env::args().any(|a| a == "--goal-bounding");
    let map_chosen = |m: &str| match filters.iter().any(|f| MAPS.contains(&f.as_str())) {
        true => filters.iter().any(|f| f == m),
        false => !goal_bounding || m == "den520d",
    };
    for name in MAPS.iter().filter(|m| map_chosen(m)) {
        let (grid, scenarios) = load_movingai(name).unwrap_or_else(|e| panic!("{e}"));
        let mut peer_expansions = None;
        for variant in VARIANTS.into_iter().filter(|v| {
            let chosen = |f: &String| VARIANTS.iter().any(|w| w.as_str() == f);
            !filters.iter().any(chosen) || filters.iter().any(|f| f == v.as_str())
        }) {
            let n = run(name, &grid, &scenarios, variant, goal_bounding, repeats);
            peer_expansions.get_or_insert(n);
        }
        println!(
            "map={name} peer_expansions={}",
            peer_expansions.unwrap_or(0)
        );
    }
}

/// One map and variant; returns the peer's expansions.
fn run(
    name: &str,
    grid: &Grid,
    scenarios: &[Scenario],
    variant: Variant,
    goal_bounding: bool,
    repeats: Repeats,
) -> u64 {
    let config = Config {
        variant,
        marks: false,
        goal_bounding,
        ..Config::default()
    };
    let new = || Jps::new(config.clone()).unwrap_or_else(|e| panic!("{e}"));
    if goal_bounding {
        let mut fresh = new();
        let t = Instant::now();
        let prepared = fresh.precompute(grid);
        println!(
            "map={name} variant={} goal_bounding precompute_ms={:.1} jump_points={} goal_bounds_bytes={}",
            variant.as_str(),
            t.elapsed().as_secs_f64() * 1e3,
            prepared.goal_bounded_points,
            prepared.goal_bounds_bytes
        );
    } else if variant == Variant::JpsPlus {
        let mut fresh = new();
        let t = Instant::now();
        let prepared = fresh.precompute(grid);
        let elapsed = t.elapsed();
        println!(
            "map={name} variant=jps_plus precompute_ms={:.2} jump_table_bytes={} bit_grid_bytes={}",
            elapsed.as_secs_f64() * 1e3,
            prepared.jump_table_bytes,
            prepared.bit_grid_bytes
        );
    }
    let mut jps = new();
    jps.prepare(grid);
    let problems: Vec<Problem<'_>> = scenarios
        .iter()
        .map(|s| Problem::new(grid, s.start, s.goal).unwrap_or_else(|e| panic!("{e}")))
        .collect();
    if let Some(dump) = std::env::var_os("JPS_DUMP_COUNTERS") {
        use std::io::Write;
        let mut text = String::new();
        for (s, problem) in scenarios.iter().zip(&problems) {
            let outcome = jps.plan(problem, &Budget::unlimited());
            let cells = outcome.path.map(|p| p.cells().to_vec());
            text += &format!(
                "{name} {} {} {} {cells:?}\n",
                variant.as_str(),
                s.line,
                outcome.counters
            );
        }
        std::fs::OpenOptions::new()
            .create(true)
            .append(true)
            .open(&dump)
            .and_then(|mut out| out.write_all(text.as_bytes()))
            .unwrap_or_else(|e| panic!("{}: {e}", dump.to_string_lossy()));
    }
    let peer = Peer::new(grid);
    // One pass over the scenarios, as timed: the paths, as the peer returns its paths and
    // costs (their lengths are measured after the timing, as the peer's costs need no work).
    let mut pass = || {
        let mut n_expanded = 0;
        let paths: Vec<Option<Path>> = problems
            .iter()
            .map(|problem| {
                let outcome = jps.plan(problem, &Budget::unlimited());
                n_expanded += outcome.counters.get("n_expanded").unwrap_or(0);
                outcome.path
            })
            .collect();
        (paths, n_expanded)
    };
    // Linux updates a thread's CPU time (`--clock=cpu`) at scheduler ticks, every 4 ms here,
    // so a pass of a few milliseconds is timed as `inner` back-to-back passes of at least
    // MIN_TIMED in all (from untimed passes over at least 50 ms on the same clock); the
    // time printed is per pass.
    let clock = || repeats.1.now().map_or(0.0, |t| t.as_secs_f64());
    let (start, mut n_passes) = (clock(), 0u32);
    while clock() - start < 0.05 && n_passes < 1000 {
        pass();
        n_passes += 1;
    }
    let one = ((clock() - start) / f64::from(n_passes)).max(1e-9);
    let inner = (MIN_TIMED / one).ceil().clamp(1.0, 1000.0) as u32;
    let (ours, theirs) = best_of_alternating(
        repeats,
        || {
            let mut result = pass();
            for _ in 1..inner {
                result = pass();
            }
            result
        },
        || {
            let mut n_expanded = 0;
            let costs: Vec<Option<u64>> = scenarios
                .iter()
                .map(|s| {
                    peer.octile(s.start, s.goal).map(|(cost, n)| {
                        n_expanded += n;
                        cost
                    })
                })
                .collect();
            (costs, n_expanded)
        },
    )
    .unwrap_or_else(|e| panic!("{e}"));
    let mut mismatches = 0;
    for ((s, path), cost) in scenarios.iter().zip(&ours.result.0).zip(&theirs.result.0) {
        let length = path.as_ref().map(|path| path.metrics().length);
        let agree = match (length, cost) {
            (Some(length), Some(cost)) => {
                close(length, s.optimal_length)
                    && close(*cost as f64 / STRAIGHT as f64, s.optimal_length)
            }
            _ => false,
        };
        if !agree {
            mismatches += 1;
            eprintln!(
                "mismatch {name} line {} {}: jps {length:?} peer {cost:?} optimum {}",
                s.line,
                variant.as_str(),
                s.optimal_length
            );
        }
    }
    println!(
        "map={name} variant={} scenarios={} mismatches={mismatches} expansions={} inner={inner} jps_ms={:.2} pathfinding_ms={:.1} ratio={:.2}",
        variant.as_str(),
        scenarios.len(),
        ours.result.1,
        ours.best.as_secs_f64() * 1e3 / f64::from(inner),
        theirs.best.as_secs_f64() * 1e3,
        theirs.best.as_secs_f64() * f64::from(inner) / ours.best.as_secs_f64().max(1e-12),
    );
    theirs.result.1
}
