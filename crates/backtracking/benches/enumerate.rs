//! `cargo bench -p planner-backtracking`: exhaustive enumeration of the open 6x6 grid from
//! (0, 0) to (5, 5), which has 1,262,816 simple corner-to-corner paths. Prints expansions
//! per second on one core (goal: at least 100 million), by wall clock and by the thread's own
//! CPU time (`clock_gettime(CLOCK_THREAD_CPUTIME_ID)` through the `cpu-time` crate, as
//! planner-bench's `--clock=cpu`), which other processes sharing the machine do not inflate.
//!
//! Then the same with `parallel = true` (the root's subtrees on the rayon pool; two on
//! this corner start), whose outcome must equal the serial one.
//!
//! Last, the open 12x12 grid (about 10^25 paths) under `Budget::expansions(10_000_000)`:
//! the runner's case, which must come back well under a second with a budget-exhausted
//! status.
//!
//! Optional argument: the number of repetitions (default 7).

use std::hint::black_box;
use std::time::{Duration, Instant};

use planner_api::{Budget, Cell, Grid, Outcome, Planner, Problem, Status};
use planner_backtracking::{Backtracking, Config};

/// Nanoseconds this thread has run on a CPU, if the platform says. Not
/// `/proc/thread-self/schedstat`, which the kernel brings up to date only at scheduler ticks
/// while the thread computes.
fn thread_cpu_ns() -> Option<u64> {
    let now = cpu_time::ThreadTime::try_now().ok()?.as_duration();
    u64::try_from(now.as_nanos()).ok()
}

fn main() {
    let reps: usize = std::env::args()
        .skip(1)
        .find_map(|a| a.parse().ok())
        .unwrap_or(7)
        .max(1);
    let grid = Grid::new(6, 6).expect("6x6 grid");
    let problem = Problem::new(&grid, Cell::new(0, 0), Cell::new(5, 5)).expect("corners are free");
    let serial = measure(&problem, Config::default(), reps);
    // `serial` as an argument: only the serial runs (for profilers).
    if std::env::args().any(|a| a == "serial") {
        let cpu = serial.2.iter().min().copied().unwrap_or_default();
        let expanded = serial.0.counters.get("n_expanded").unwrap_or(0);
        println!(
            "serial only: {:.1} M expansions/s of thread CPU time",
            expanded as f64 / cpu.as_secs_f64() / 1e6
        );
        return;
    }
    let parallel = measure(
        &problem,
        Config {
            parallel: true,
            ..Config::default()
        },
        reps,
    );
    assert_eq!(parallel.0, serial.0, "parallel and serial outcomes differ");
    let expanded = serial.0.counters.get("n_expanded").unwrap_or(0);
    let rate = |d: Duration| expanded as f64 / d.as_secs_f64() / 1e6;
    let summary = |name: &str, mut times: Vec<Duration>| {
        times.sort();
        format!(
            "{name}: best {:.3} s = {:.1} M expansions/s, median {:.3} s = {:.1} M/s",
            times[0].as_secs_f64(),
            rate(times[0]),
            times[times.len() / 2].as_secs_f64(),
            rate(times[times.len() / 2]),
        )
    };
    println!(
        "open 6x6, (0,0) to (5,5): 1262816 solutions, {expanded} expansions, {reps} runs each"
    );
    println!("  serial, {}", summary("wall", serial.1));
    if serial.2.len() == reps {
        println!("  serial, {}", summary("thread cpu", serial.2));
    }
    println!(
        "  parallel ({} rayon threads), {}",
        rayon_threads(),
        summary("wall", parallel.1)
    );

    let grid = Grid::new(12, 12).expect("12x12 grid");
    let problem =
        Problem::new(&grid, Cell::new(0, 0), Cell::new(11, 11)).expect("corners are free");
    let mut planner = Backtracking::new(Config::default()).expect("default config");
    let t = Instant::now();
    let outcome = planner.plan(&problem, &Budget::expansions(10_000_000));
    let elapsed = t.elapsed();
    assert_eq!(outcome.status, Status::BudgetExhausted);
    assert_eq!(outcome.counters.get("n_expanded"), Some(10_000_000));
    println!(
        "open 12x12, Budget::expansions(10_000_000): {} in {:.3} s wall, best so far {:?}",
        outcome.status.as_str(),
        elapsed.as_secs_f64(),
        outcome.path.map(|p| p.rank())
    );
}

fn rayon_threads() -> usize {
    rayon::current_num_threads()
}

/// Runs the 6x6 enumeration `reps` times: the outcome, wall times, thread CPU times.
fn measure(
    problem: &Problem<'_>,
    config: Config,
    reps: usize,
) -> (Outcome, Vec<Duration>, Vec<Duration>) {
    let mut planner = Backtracking::new(config).expect("valid config");
    let mut wall = Vec::new();
    let mut cpu = Vec::new();
    let mut last = None;
    for _ in 0..reps {
        let c0 = thread_cpu_ns();
        let t = Instant::now();
        let outcome = black_box(planner.plan(black_box(problem), &Budget::unlimited()));
        wall.push(t.elapsed());
        if let (Some(a), Some(b)) = (c0, thread_cpu_ns()) {
            cpu.push(Duration::from_nanos(b - a));
        }
        assert_eq!(outcome.status, Status::Found);
        assert_eq!(
            outcome.counters.get("n_solutions"),
            Some(1_262_816),
            "6x6 solutions"
        );
        last = Some(outcome);
    }
    (last.expect("at least one run"), wall, cpu)
}
