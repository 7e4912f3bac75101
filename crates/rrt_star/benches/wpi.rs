//! `cargo bench -p planner-rrt_star`: RRT, RRT* and RRT-Connect on every valid pair of
//! seed 003's maps (maps/wpi), seeds 0..SEEDS, for RRT's default steering (four, step 1)
//! and for eight-way steering with step 4, in the same run.
//!
//! Per pair: the mean path length of RRT, of RRT* after 0, 1,000 and 5,000 iterations
//! past its first solution (read from one run's `best_cost` series), and of RRT-Connect;
//! BFS's 4-connected optimum and the straight line for reference; the median time per
//! search (each search timed `REPEATS` times, fastest kept, to damp noise from other
//! processes; the searches themselves are deterministic), with the mean work counters
//! (RRT iterations, RRT* iterations, RRT-Connect extensions).

use std::time::{Duration, Instant};

use planner_api::{Budget, Connectivity, MoveSet, Outcome, Planner, Problem};
use planner_rrt::Steer;

const SEEDS: u64 = 20;
const REPEATS: usize = 3;
const AFTER: [u64; 3] = [0, 1_000, 5_000];

fn timed(planner: &mut dyn Planner, problem: &Problem<'_>) -> (Outcome, Duration) {
    let mut best = Duration::MAX;
    let mut outcome = None;
    for _ in 0..REPEATS {
        let t = Instant::now();
        let o = planner.plan(problem, &Budget::unlimited());
        best = best.min(t.elapsed());
        outcome = Some(o);
    }
    (outcome.expect("REPEATS > 0"), best)
}

fn length(outcome: &Outcome) -> f64 {
    outcome
        .path
        .as_ref()
        .map_or(f64::NAN, |p| p.metrics().length)
}

fn counter(outcome: &Outcome, name: &str) -> f64 {
    outcome.counters.get(name).unwrap_or(0) as f64
}

/// RRT*'s best cost `after` iterations past its first solution, from its series.
fn cost_after(outcome: &Outcome, after: u64) -> f64 {
    let first = counter(outcome, "first_solution_iteration");
    outcome.series[0]
        .points
        .iter()
        .take_while(|p| p[0] <= first + after as f64)
        .last()
        .map_or(f64::NAN, |p| p[1])
}

fn median(values: &mut [Duration]) -> Duration {
    values.sort();
    values[values.len() / 2]
}

fn ms(d: Duration) -> String {
    format!("{:.3}", d.as_secs_f64() * 1e3)
}

fn main() {
    let four = MoveSet::standard(Connectivity::Four);
    for (steer, step) in [(Steer::Four, 1), (Steer::Eight, 4)] {
        println!(
            "steer {steer:?}, step {step}, goal_bias 0.05 (RRT, RRT*), seeds 0..{SEEDS}, mean lengths; median ms (best of {REPEATS}) and mean work"
        );
        println!(
            "| map | pair | BFS | straight | RRT | RRT* +0 | RRT* +1000 | RRT* +5000 | RRT-Connect | RRT ms (iter) | RRT* +5000 ms (iter) | RRT-Connect ms (ext) |"
        );
        println!("|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|");
        for name in ["map1", "map2", "map3"] {
            let (grid, pairs) = planner_testkit::wpi(&format!("wpi/{name}.txt"));
            for (number, &(start, goal)) in pairs.iter().enumerate() {
                let Ok(problem) = Problem::new(&grid, start, goal) else {
                    continue; // map2's second pair puts its goal on an obstacle
                };
                let bfs = planner_testkit::fewest_moves(&grid, &four, start, goal)
                    .expect("every valid wpi pair is solvable");
                let (mut rrt_len, mut star_len, mut connect_len) = (0.0, [0.0; 3], 0.0);
                let (mut rrt_work, mut star_work, mut connect_work) = (0.0, 0.0, 0.0);
                let (mut rrt_t, mut star_t, mut connect_t) = (Vec::new(), Vec::new(), Vec::new());
                for seed in 0..SEEDS {
                    let mut rrt = planner_rrt::Rrt::new(planner_rrt::Config {
                        seed,
                        steer,
                        step,
                        ..planner_rrt::Config::default()
                    })
                    .expect("valid config");
                    let mut star = planner_rrt_star::RrtStar::new(planner_rrt_star::Config {
                        seed,
                        steer,
                        step,
                        iterations_after_solution: AFTER[2],
                        ..planner_rrt_star::Config::default()
                    })
                    .expect("valid config");
                    let mut connect =
                        planner_rrt_connect::RrtConnect::new(planner_rrt_connect::Config {
                            seed,
                            steer,
                            step,
                            ..planner_rrt_connect::Config::default()
                        })
                        .expect("valid config");
                    let (o, t) = timed(&mut rrt, &problem);
                    rrt_len += length(&o);
                    rrt_work += counter(&o, "n_iterations");
                    rrt_t.push(t);
                    let (o, t) = timed(&mut star, &problem);
                    for (total, after) in star_len.iter_mut().zip(AFTER) {
                        *total += cost_after(&o, after);
                    }
                    star_work += counter(&o, "n_iterations");
                    star_t.push(t);
                    let (o, t) = timed(&mut connect, &problem);
                    connect_len += length(&o);
                    connect_work += counter(&o, "n_extensions");
                    connect_t.push(t);
                }
                let n = SEEDS as f64;
                println!(
                    "| {name} | {} | {bfs} | {:.2} | {:.2} | {:.2} | {:.2} | {:.2} | {:.2} | {} ({:.0}) | {} ({:.0}) | {} ({:.0}) |",
                    number + 1,
                    start.euclidean(goal),
                    rrt_len / n,
                    star_len[0] / n,
                    star_len[1] / n,
                    star_len[2] / n,
                    connect_len / n,
                    ms(median(&mut rrt_t)),
                    rrt_work / n,
                    ms(median(&mut star_t)),
                    star_work / n,
                    ms(median(&mut connect_t)),
                    connect_work / n,
                );
            }
        }
        println!();
    }
}
