//! `cargo bench -p planner-rrt`: RRT on seed 003's map3 pair 1 ((0,0) -> (49,19)) for
//! seeds 0..100 with the default config, timed with the bucketed index and with a
//! linear-scan nearest neighbour (seed 003's method) in the same run; then every
//! solvable maps/wpi pair with the bucketed index.
//!
//! Each run is timed `REPEATS` times and the fastest kept, to damp noise from other
//! processes; the runs themselves are deterministic.

#[path = "../tests/support/mod.rs"]
mod support;

use std::time::{Duration, Instant};

use planner_api::{Budget, Cell, Outcome, Planner, Problem, Status};
use planner_rrt::{BucketGrid, Config, NearestIndex, Rrt};
use support::{movingai, wpi, LinearScan};

const SEEDS: u64 = 100;
const REPEATS: usize = 5;

/// Plans `problem` `REPEATS` times; the outcome and the fastest time.
fn timed<I: NearestIndex>(rrt: &mut Rrt<I>, problem: &Problem<'_>) -> (Outcome, Duration) {
    let mut best = Duration::MAX;
    let mut outcome = None;
    for _ in 0..REPEATS {
        let t = Instant::now();
        let o = rrt.plan(problem, &Budget::unlimited());
        best = best.min(t.elapsed());
        outcome = Some(o);
    }
    (outcome.expect("REPEATS > 0"), best)
}

fn median<T: Copy + Ord>(values: &[T]) -> T {
    let mut v = values.to_vec();
    v.sort();
    v[v.len() / 2]
}

/// Lower quartile, median, upper quartile (nearest rank).
fn quartiles<T: Copy + Ord>(values: &[T]) -> (T, T, T) {
    let mut v = values.to_vec();
    v.sort();
    (v[v.len() / 4], v[v.len() / 2], v[(3 * v.len()) / 4])
}

struct Runs {
    found: usize,
    iterations: Vec<u64>,
    steps: Vec<u64>,
    times: Vec<Duration>,
    outcomes: Vec<Outcome>,
}

fn runs<I: NearestIndex + Clone>(problem: &Problem<'_>, index: I, seeds: u64) -> Runs {
    let mut r = Runs {
        found: 0,
        iterations: Vec::new(),
        steps: Vec::new(),
        times: Vec::new(),
        outcomes: Vec::new(),
    };
    for seed in 0..seeds {
        let config = Config {
            seed,
            ..Config::default()
        };
        let mut rrt = Rrt::with_index(config, index.clone()).expect("valid config");
        let (outcome, time) = timed(&mut rrt, problem);
        if outcome.status == Status::Found {
            r.found += 1;
            if let Some(path) = &outcome.path {
                r.steps.push(path.metrics().steps);
            }
        }
        r.iterations
            .push(outcome.counters.get("n_iterations").unwrap_or(0));
        r.times.push(time);
        r.outcomes.push(outcome);
    }
    r
}

fn us(d: Duration) -> String {
    format!("{:.1} us", d.as_secs_f64() * 1e6)
}

/// A larger map: den520d (256 x 257), its longest scenario, a few seeds, one timing each.
fn larger_map() {
    let grid = movingai("den520d.map");
    let (start, goal) = (Cell::new(15, 214), Cell::new(239, 11));
    let problem = Problem::new(&grid, start, goal).expect("scenario cells are free");
    let seeds = 5;
    for (what, config) in [
        ("four, step 1", Config::default()),
        (
            "four, step 4",
            Config {
                step: 4,
                ..Config::default()
            },
        ),
    ] {
        println!("den520d {start} -> {goal}, {what}, seeds 0..{seeds}, one run each:");
        let mut line = Vec::new();
        let mut reference: Option<Vec<Outcome>> = None;
        let mut time_with = |name: String, make: &dyn Fn(Config) -> Box<dyn Planner>| {
            let mut times = Vec::new();
            let mut outcomes = Vec::new();
            for seed in 0..seeds {
                let mut rrt = make(Config {
                    seed,
                    ..config.clone()
                });
                let t = Instant::now();
                outcomes.push(rrt.plan(&problem, &Budget::unlimited()));
                times.push(t.elapsed());
            }
            match &reference {
                None => {
                    let found = outcomes
                        .iter()
                        .filter(|o| o.status == Status::Found)
                        .count();
                    let iterations: Vec<u64> = outcomes
                        .iter()
                        .map(|o| o.counters.get("n_iterations").unwrap_or(0))
                        .collect();
                    let tree: Vec<u64> = outcomes
                        .iter()
                        .map(|o| o.counters.get("tree_size").unwrap_or(0))
                        .collect();
                    println!(
                        "  found {found}/{seeds}, median iterations {}, median tree size {}",
                        median(&iterations),
                        median(&tree)
                    );
                    reference = Some(outcomes);
                }
                Some(r) => assert!(*r == outcomes, "{name} changed a result"),
            }
            line.push(format!("{name} {}", us(median(&times))));
        };
        for side in [1, 2, 4, 8] {
            time_with(format!("bucket {side}"), &|c| {
                Box::new(Rrt::with_index(c, BucketGrid::with_block_side(side)).expect("valid"))
            });
        }
        time_with("linear".to_string(), &|c| {
            Box::new(Rrt::with_index(c, LinearScan::default()).expect("valid"))
        });
        println!("  median time: {}", line.join(", "));
    }
}

fn main() {
    let map3 = wpi("map3");
    let (_, start, goal) = map3.pairs[0];
    let problem = Problem::new(&map3.grid, start, goal).expect("map3 pair 1 is valid");
    println!(
        "RRT, map3 pair 1 {start} -> {goal} ({}x{}), default config (four, step 1, goal_bias 0.05), seeds 0..{SEEDS}, best of {REPEATS}",
        map3.grid.width(),
        map3.grid.height()
    );
    let bucket = runs(&problem, BucketGrid::default(), SEEDS);
    let linear = runs(&problem, LinearScan::default(), SEEDS);
    let same = bucket.outcomes == linear.outcomes;
    let (i25, i50, i75) = quartiles(&bucket.iterations);
    let (s25, s50, s75) = quartiles(&bucket.steps);
    let tree = median(
        &bucket
            .outcomes
            .iter()
            .map(|o| o.counters.get("tree_size").unwrap_or(0))
            .collect::<Vec<_>>(),
    );
    println!("  success rate        {}/{SEEDS}", bucket.found);
    println!("  iterations          median {i50} (IQR {i25}..{i75})");
    println!("  tree size           median {tree}");
    println!("  path steps          median {s50} (IQR {s25}..{s75}); BFS shortest is 70");
    for (name, r) in [("bucket grid", &bucket), ("linear scan", &linear)] {
        let (t25, t50, t75) = quartiles(&r.times);
        let total: Duration = r.times.iter().sum();
        println!(
            "  time, {name}    median {} (IQR {}..{}), max {}, total {}",
            us(t50),
            us(t25),
            us(t75),
            us(*r.times.iter().max().unwrap_or(&Duration::ZERO)),
            us(total)
        );
    }
    let ratio = median(&linear.times).as_secs_f64() / median(&bucket.times).as_secs_f64();
    let total_ratio = linear.times.iter().sum::<Duration>().as_secs_f64()
        / bucket.times.iter().sum::<Duration>().as_secs_f64();
    println!("  linear / bucket     {ratio:.2}x on the median, {total_ratio:.2}x on the total");
    println!("  identical outcomes  {same} (same paths and counters with both indexes)");
    println!("  (seed 003 Table II: RRT took 10.35 s on this map and found no path)");
    let sides: Vec<String> = [1, 2, 4, 8, 16]
        .into_iter()
        .map(|side| {
            let r = runs(&problem, BucketGrid::with_block_side(side), SEEDS);
            assert!(
                r.outcomes == bucket.outcomes,
                "block side {side} changed a result"
            );
            format!("{side}: {}", us(median(&r.times)))
        })
        .collect();
    println!("  median time by block side  {}", sides.join(", "));

    println!();
    println!("Every solvable maps/wpi pair, bucket grid, seeds 0..{SEEDS}:");
    println!("  map  pair  success  median iterations  median steps (IQR)  median time");
    for name in ["map1", "map2", "map3"] {
        let map = wpi(name);
        for &(number, start, goal) in &map.pairs {
            let Ok(problem) = Problem::new(&map.grid, start, goal) else {
                println!("  {name}  {number}     skipped: {goal} is an obstacle");
                continue;
            };
            let r = runs(&problem, BucketGrid::default(), SEEDS);
            let (s25, s50, s75) = quartiles(&r.steps);
            println!(
                "  {name}  {number}     {:>3}/{SEEDS}  {:>17}  {s50:>5} ({s25}..{s75})  {:>12}",
                r.found,
                median(&r.iterations),
                us(median(&r.times))
            );
        }
    }
    println!();
    larger_map();
}
