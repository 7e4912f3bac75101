//! Planning time of navigation in unknown terrain: D* Lite (and LPA*) against A* from
//! scratch at every replan, forward and backward, on Moving AI maps, without the oracle
//! (the `navigate` example checks every replan of the same runs; counters are
//! deterministic, so the expansions here are the checked ones).
//!
//! ```text
//! cargo bench -p planner-replan --bench navigate -- [--scenarios 100] \
//!     [--maps den520d,random512-10-0] [--radius 1,5] [--planners dstar_lite,astar,astar_backward] \
//!     [--repeat 3] [--per-scenario]
//! ```
//!
//! For each map, radius and scenario (spread evenly over the `.scen` file), every planner
//! drives its own agent, one after the other in an order that rotates per scenario, in
//! one process, so machine load falls on all alike. Each planner object is kept across
//! the scenarios of a map and radius (as a robot keeps its planner), so no side allocates
//! its per-cell arrays per run. Each run is repeated `--repeat` times (the planners
//! alternating) and every replan keeps its least time over the repeats, so preemption by
//! other processes, which only adds time, mostly drops out; the counters must agree. Printed per map and radius: the
//! medians over scenarios of each planner's total expansions and planning time as a share
//! of A*'s. A planner's planning time is the time of telling it the moves and changes
//! plus its replans (its reset, the first update, included); for A* from scratch three
//! figures are given: its searches alone (no map build at all: the strict baseline), its
//! searches and its reset (the first build of its bit-packed map), and its searches with
//! its map brought up to date after every change (a rebuild of the bit-packed map until
//! 2026-12-06; since then planner-astar sets the changed cells' bits in place,
//! `planner_api::Grid::changed_since`, so this is close to the second figure). The
//! first two compare like with like only in the second: the planner's time includes its
//! reset (setting up its copy of the map), A*'s bare searches include no setup at all, so
//! a fourth figure takes the setup out of both (the planner without its reset against A*'s
//! searches). `--per-scenario` also prints a line per scenario and planner (its first
//! plan, reset, later updates and totals), to see which part of a run the time goes to.

use std::time::Duration;

use planner_api::Budget;
use planner_replan::args::{loadavg, movingai_map, spread, Args};
use planner_replan::navigate::{self, NavConfig, NavRun};
use planner_replan::planners;
use planner_replan::report::quantile;

/// Replan time alone (the search, without telling the planner the changes).
fn search_time(run: &NavRun) -> Duration {
    run.replans.iter().map(|r| r.replan_time).sum()
}

/// One line per planner of a scenario (`--per-scenario`): replans, the first plan's
/// expansions and time, its reset (the first update), the totals, and the later updates'
/// time (telling the planner the moves and changes).
fn print_scenario(line: usize, row: &[(String, NavRun)]) {
    for (name, run) in row {
        let first = run.replans.first();
        println!(
            "  scenario {line} {name}: replans {} first {} exp {:.1} us (reset {:.1} us) total {} exp {:.1} us (searches {:.1} us, later updates {:.1} us)",
            run.replans.len(),
            first.map_or(0, |r| r.expansions),
            first.map_or(0.0, |r| r.replan_time.as_secs_f64() * 1e6),
            first.map_or(0.0, |r| r.update_time.as_secs_f64() * 1e6),
            run.total_expansions(),
            run.planning_time().as_secs_f64() * 1e6,
            search_time(run).as_secs_f64() * 1e6,
            run.replans
                .iter()
                .skip(1)
                .map(|r| r.update_time)
                .sum::<Duration>()
                .as_secs_f64()
                * 1e6,
        );
    }
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args = Args::from_env();
    let n_scenarios: usize = args.parsed("--scenarios", "100")?;
    let maps = args.list("--maps", "den520d,random512-10-0");
    let radii: Vec<u32> = args.parsed_list("--radius", "1,5")?;
    let names = args.list("--planners", "dstar_lite,astar,astar_backward");
    let repeats = args.parsed::<usize>("--repeat", "3")?.max(1);
    let per_scenario = args.flag("--per-scenario");
    for name in &names {
        planners::by_name(name, true)?;
    }
    println!("load average at start: {}", loadavg());
    for map in &maps {
        let (grid, scenarios) = movingai_map(map)?;
        let picked = spread(&scenarios, n_scenarios);
        for &radius in &radii {
            let config = NavConfig {
                radius,
                ..NavConfig::default()
            };
            let mut table: Vec<Vec<(String, NavRun)>> = Vec::new();
            // One planner of each kind per map and radius, kept across the scenarios as
            // a robot keeps its planner: neither side allocates its per-cell arrays per run.
            let mut kept = names
                .iter()
                .map(|name| planners::by_name(name, true))
                .collect::<Result<Vec<_>, _>>()?;
            for (k, scenario) in picked.iter().enumerate() {
                let mut row: Vec<(String, NavRun)> = Vec::new();
                for repeat in 0..repeats {
                    for j in 0..names.len() {
                        let p = (k + j + repeat) % names.len();
                        let run = navigate::run(
                            kept[p].as_mut(),
                            None,
                            &grid,
                            scenario.start,
                            scenario.goal,
                            &config,
                            &Budget::unlimited(),
                        )?;
                        match row.iter_mut().find(|(n, _)| *n == names[p]) {
                            None => row.push((names[p].clone(), run)),
                            Some((_, best)) => {
                                // Counters are deterministic; each replan keeps its least time
                                // over the repeats (preemption only ever adds time).
                                assert_eq!(best.total_expansions(), run.total_expansions());
                                assert_eq!(best.replans.len(), run.replans.len());
                                for (b, r) in best.replans.iter_mut().zip(&run.replans) {
                                    b.update_time = b.update_time.min(r.update_time);
                                    b.replan_time = b.replan_time.min(r.replan_time);
                                }
                            }
                        }
                    }
                }
                if per_scenario {
                    print_scenario(scenario.line, &row);
                }
                table.push(row);
            }
            let replans: usize = table.iter().flatten().map(|(_, r)| r.replans.len()).sum();
            println!(
                "{map} radius {radius}: {} scenarios, {replans} replans",
                table.len()
            );
            let pct = |v: Option<f64>| v.map_or("-".into(), |x| format!("{:.1} %", 100.0 * x));
            for name in &names {
                // Shares need the baseline, A* from scratch, in the same run.
                if name == "astar" || !names.iter().any(|n| n == "astar") {
                    continue;
                }
                let (mut exp, mut strict, mut fair, mut with_rebuild) =
                    (Vec::new(), Vec::new(), Vec::new(), Vec::new());
                let mut unset = Vec::new();
                let (mut total_a, mut total_b, mut exp_a, mut exp_b) =
                    (Duration::ZERO, Duration::ZERO, 0u64, 0u64);
                for row in &table {
                    let find = |n: &str| row.iter().find(|(m, _)| m == n).map(|(_, r)| r);
                    let (Some(a), Some(b)) = (find(name), find("astar")) else {
                        continue;
                    };
                    total_a += a.planning_time();
                    total_b += search_time(b);
                    exp_a += a.total_expansions();
                    exp_b += b.total_expansions();
                    if b.total_expansions() > 0 {
                        exp.push(a.total_expansions() as f64 / b.total_expansions() as f64);
                    }
                    let time_a = a.planning_time().as_secs_f64();
                    if !search_time(b).is_zero() {
                        strict.push(time_a / search_time(b).as_secs_f64());
                    }
                    let built = search_time(b)
                        + b.replans.first().map_or(Duration::ZERO, |r| r.update_time);
                    // Neither side's map setup: the planner without its reset (its first
                    // update), against A*'s searches alone.
                    let reset = a.replans.first().map_or(Duration::ZERO, |r| r.update_time);
                    if !search_time(b).is_zero() {
                        unset.push(
                            (a.planning_time() - reset).as_secs_f64()
                                / search_time(b).as_secs_f64(),
                        );
                    }
                    if !built.is_zero() {
                        fair.push(time_a / built.as_secs_f64());
                    }
                    if !b.planning_time().is_zero() {
                        with_rebuild.push(time_a / b.planning_time().as_secs_f64());
                    }
                }
                println!(
                    "  {name} / astar: median total expansions {} [p10 {}, p90 {}]; median planning time {} of A*'s searches [p10 {}, p90 {}], {} of A*'s searches and first map build, {} without its reset against A*'s searches, {} of A*'s searches with its map update per replan; sums: {exp_a} vs {exp_b} expansions, {:.1} ms vs {:.1} ms (searches)",
                    pct(quantile(&exp, 0.5)),
                    pct(quantile(&exp, 0.1)),
                    pct(quantile(&exp, 0.9)),
                    pct(quantile(&strict, 0.5)),
                    pct(quantile(&strict, 0.1)),
                    pct(quantile(&strict, 0.9)),
                    pct(quantile(&fair, 0.5)),
                    pct(quantile(&unset, 0.5)),
                    pct(quantile(&with_rebuild, 0.5)),
                    total_a.as_secs_f64() * 1e3,
                    total_b.as_secs_f64() * 1e3,
                );
            }
        }
    }
    println!("load average at end: {}", loadavg());
    Ok(())
}
