//! CAPSO with seed 002's settings (6 control points, 30 particles, 100 iterations) on the
//! scenarios of `configs/pastar.toml`: per scenario the median time of a search over
//! `--repeats=N` seeds (default 10), the time per fitness evaluation, and how many seeds
//! found a path.
//!
//! `cargo bench -p planner-capso --bench seed002 [-- --repeats=N]`

use std::time::Instant;

use planner_api::{Budget, Cell, Planner, Problem, Status};
use planner_capso::{Capso, Config};

fn main() {
    let repeats: u64 = std::env::args()
        .find_map(|a| a.strip_prefix("--repeats=").map(str::to_owned))
        .map_or(10, |n| {
            n.parse().expect("--repeats=N takes a positive integer")
        });
    let scenarios = [
        ("pastar/open-140x120.map", (20, 10), (70, 110)),
        ("pastar/two-140x120.map", (20, 10), (70, 110)),
        ("pastar/several-140x120.map", (20, 10), (70, 110)),
        ("pastar/random200-1.map", (25, 35), (140, 190)),
        ("pastar/random200-2.map", (25, 35), (140, 190)),
        ("pastar/scenario500.map", (50, 250), (400, 200)),
        ("pastar/scenario500.map", (50, 425), (400, 225)),
    ];
    println!("scenario | found | median ms | us per evaluation | evaluations");
    for (map, (sx, sy), (gx, gy)) in scenarios {
        let grid = planner_testkit::map_file(map).grid;
        let problem = Problem::new(&grid, Cell::new(sx, sy), Cell::new(gx, gy))
            .expect("the configs' problems are valid");
        let mut capso = Capso::new(Config::default()).expect("the defaults are valid");
        let (mut times, mut n_found, mut n_evaluations) = (Vec::new(), 0, 0);
        for seed in 0..repeats {
            capso.reseed(seed);
            let started = Instant::now();
            let outcome = capso.plan(&problem, &Budget::unlimited());
            times.push(started.elapsed().as_secs_f64() * 1e3);
            n_found += u64::from(outcome.status == Status::Found);
            n_evaluations = outcome.counters.get("n_fitness_evaluations").unwrap_or(0);
        }
        times.sort_by(f64::total_cmp);
        let median = times[times.len() / 2];
        println!(
            "{map} ({sx},{sy})->({gx},{gy}) | {n_found}/{repeats} | {median:.1} | {:.2} | {n_evaluations}",
            median * 1e3 / n_evaluations.max(1) as f64
        );
    }
}
