//! CAPSO against PA-star on the scenarios of `configs/pastar.toml`, with seed 002's
//! settings (CAPSO: 6 control points, 30 particles, 100 iterations; PA-star: Table 5's
//! parameters, the crate defaults), or on the several-obstacle map per control-point count
//! with `--control-points`.
//!
//! Per scenario, PA-star runs its repeats and then CAPSO its own (repeat `r` with seed
//! `r`, as the runner's repeats), each planner's in a row as the runner runs them
//! (`configs/pastar.toml`, one thread): alternating single runs, as this bench did until
//! 2026-12-05, let each CAPSO search (2 ms, its tables and swarm) push PA-star's data out
//! of the caches, and PA-star then took 0.075-0.14 ms on the two-obstacle and 200 x 200
//! maps against 0.055-0.069 ms in a row, CAPSO the same either way. It prints how
//! many CAPSO runs found a collision-free path, their mean, best and worst length beside
//! seed 002's CAPSO length, the median search time of each planner and their ratio, both
//! as wall time and as the thread's CPU time (on a shared, oversubscribed machine a long
//! search is preempted many times and a short one rarely, which wall time charges to the
//! long one), both sides' work (PA-star's expansions, CAPSO's fitness evaluations), and
//! the share of CAPSO's path segments that its segment cache answered.
//!
//! `cargo bench -p planner-capso --bench seed002 -- [--repeats=N] [--control-points]
//! [--only=TEXT] [--set=KEY=VALUE ...]` (default 50 repeats, seed 002's count; `--only`
//! keeps the scenarios whose map file name contains TEXT; `--set` changes a CAPSO
//! parameter, in TOML: `--set=samples_per_segment=3`).

use std::time::Instant;

use cpu_time::ThreadTime;

use planner_api::{Budget, Cell, Planner, Problem, Status};
use planner_capso::{Capso, Config};
use planner_pastar::PaStar;

/// A scenario: map file, start, goal, and seed 002's CAPSO length on it.
type Scenario = (&'static str, (u32, u32), (u32, u32), f64);

/// The median of `times` (sorted here); the upper middle for an even count.
fn median(times: &mut [f64]) -> f64 {
    times.sort_by(f64::total_cmp);
    times[times.len() / 2]
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let repeats: u64 = args
        .iter()
        .find_map(|a| a.strip_prefix("--repeats=").map(str::to_owned))
        .map_or(50, |n| {
            n.parse().expect("--repeats=N takes a positive integer")
        });
    assert!(repeats > 0, "--repeats=N takes a positive integer");
    // Only the scenarios whose map file name contains this text.
    let only = args
        .iter()
        .find_map(|a| a.strip_prefix("--only=").map(str::to_owned))
        .unwrap_or_default();
    let several: Scenario = ("pastar/several-140x120.map", (20, 10), (70, 110), 114.46);
    let scenarios = [
        ("pastar/open-140x120.map", (20, 10), (70, 110), 111.84),
        ("pastar/two-140x120.map", (20, 10), (70, 110), 112.85),
        several,
        ("pastar/scenario500.map", (50, 250), (400, 200), 382.34),
        ("pastar/scenario500.map", (50, 425), (400, 225), 427.30),
        ("pastar/random200-1.map", (25, 35), (140, 190), 210.89),
        ("pastar/random200-2.map", (25, 35), (140, 190), 215.09),
    ];
    // CAPSO parameters other than the defaults, as TOML lines `key=value`.
    let set: String = args
        .iter()
        .filter_map(|a| a.strip_prefix("--set="))
        .map(|kv| format!("{kv}\n"))
        .collect();
    let base: Config = toml::from_str(&set).expect("--set=KEY=VALUE takes CAPSO parameters");
    let runs: Vec<(String, Scenario, Config)> = if args.iter().any(|a| a == "--control-points") {
        (3..=6)
            .map(|n| {
                let config = Config {
                    control_points: n,
                    ..base.clone()
                };
                (format!(", {n} control points"), several, config)
            })
            .collect()
    } else {
        scenarios
            .iter()
            .map(|&s| (String::new(), s, base.clone()))
            .collect()
    };
    println!(
        "scenario | CAPSO found | mean length (seed 002) | best | worst | PA-star ms | CAPSO ms | ratio | PA-star CPU ms | CAPSO CPU ms | CPU ratio | PA-star expansions | CAPSO evaluations | segments cached"
    );
    for (label, (map, (sx, sy), (gx, gy), seed_length), config) in runs {
        if !map.contains(&only) {
            continue;
        }
        let grid = planner_testkit::map_file(map).grid;
        let problem = Problem::new(&grid, Cell::new(sx, sy), Cell::new(gx, gy))
            .expect("the configs' problems are valid");
        let mut capso = Capso::new(config).expect("the config is valid");
        let mut pastar =
            PaStar::new(planner_pastar::Config::default()).expect("the defaults are valid");
        let (mut capso_ms, mut pastar_ms, mut lengths) = (Vec::new(), Vec::new(), Vec::new());
        let (mut capso_cpu, mut pastar_cpu) = (Vec::new(), Vec::new());
        let (mut expansions, mut evaluations) = (0, 0);
        let (mut segments, mut cached) = (0, 0);
        for _ in 0..repeats {
            let (started, cpu) = (Instant::now(), ThreadTime::now());
            let outcome = pastar.plan(&problem, &Budget::unlimited());
            pastar_cpu.push(cpu.elapsed().as_secs_f64() * 1e3);
            pastar_ms.push(started.elapsed().as_secs_f64() * 1e3);
            expansions = outcome.counters.get("n_expanded").unwrap_or(0);
        }
        for seed in 0..repeats {
            capso.reseed(seed);
            let (started, cpu) = (Instant::now(), ThreadTime::now());
            let outcome = capso.plan(&problem, &Budget::unlimited());
            capso_cpu.push(cpu.elapsed().as_secs_f64() * 1e3);
            capso_ms.push(started.elapsed().as_secs_f64() * 1e3);
            evaluations = outcome.counters.get("n_fitness_evaluations").unwrap_or(0);
            segments += outcome.counters.get("n_segments").unwrap_or(0);
            cached += outcome.counters.get("n_segment_cache_hits").unwrap_or(0);
            if let (Status::Found, Some(path)) = (outcome.status, &outcome.path) {
                lengths.push(path.metrics().length);
            }
        }
        let n_found = lengths.len();
        let mean = lengths.iter().sum::<f64>() / n_found.max(1) as f64;
        let best = lengths.iter().copied().fold(f64::INFINITY, f64::min);
        let worst = lengths.iter().copied().fold(0.0, f64::max);
        let (p, c) = (median(&mut pastar_ms), median(&mut capso_ms));
        let (pc, cc) = (median(&mut pastar_cpu), median(&mut capso_cpu));
        println!(
            "{map} ({sx},{sy})->({gx},{gy}){label} | {n_found}/{repeats} | {mean:.2} ({seed_length:.2}, {:+.1}%) | {best:.2} | {worst:.2} | {p:.3} | {c:.2} | {:.1} | {pc:.3} | {cc:.2} | {:.1} | {expansions} | {evaluations} | {:.1}%",
            100.0 * (mean / seed_length - 1.0),
            c / p,
            cc / pc,
            100.0 * cached as f64 / segments.max(1) as f64
        );
    }
}
