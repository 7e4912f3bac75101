//! Seeded scripted changes on Moving AI maps: between replans the agent drives a few
//! cells and `k` cells are toggled on its path or near it; D* Lite, LPA* and A* from
//! scratch replan, each replan checked by the exact oracle.
//!
//! ```text
//! cargo run --release -p planner-replan --example toggles -- [--scenarios 50] \
//!     [--maps den520d,random512-10-0] [--events 40] [--k 5] [--radius 5] [--drive 2]
//! ```

use planner_api::{Budget, Problem};
use planner_replan::args::{movingai_map, spread, Args};
use planner_replan::report::quantile;
use planner_replan::toggles::{self, ToggleConfig};
use planner_replan::{planners, Oracle};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args = Args::from_env();
    let n: usize = args.parsed("--scenarios", "50")?;
    let events: u32 = args.parsed("--events", "40")?;
    let k: u32 = args.parsed("--k", "5")?;
    let radius: u32 = args.parsed("--radius", "5")?;
    let drive: u32 = args.parsed("--drive", "2")?;
    let names = ["dstar_lite", "lpastar", "astar"];
    let mut total_mismatches = 0;
    for map in args.list("--maps", "den520d,random512-10-0") {
        let (grid, scenarios) = movingai_map(&map)?;
        let picked = spread(&scenarios, n);
        let mut oracle = Oracle::new(true);
        // Per planner: repair expansions (after the first plan) / A*'s from scratch, per run.
        let mut ratios: Vec<Vec<f64>> = vec![Vec::new(); names.len()];
        let (mut replans, mut mismatches) = (0usize, 0usize);
        for (i, s) in picked.iter().enumerate() {
            let problem = Problem::new(&grid, s.start, s.goal)?;
            let config = ToggleConfig {
                events,
                k,
                radius,
                drive,
                seed: i as u64,
            };
            for (j, name) in names.iter().enumerate() {
                let mut planner = planners::by_name(name, true)?;
                let run = toggles::run(
                    planner.as_mut(),
                    &mut oracle,
                    &problem,
                    &config,
                    &Budget::unlimited(),
                );
                for m in &run.mismatches {
                    eprintln!("MISMATCH {map} line {} {name}: {m}", s.line);
                }
                replans += run.replans.len();
                mismatches += run.mismatches.len();
                let own: u64 = run.replans.iter().skip(1).map(|r| r.expansions).sum();
                let scratch: u64 = run
                    .replans
                    .iter()
                    .skip(1)
                    .filter_map(|r| r.oracle_expansions)
                    .sum();
                if scratch > 0 {
                    ratios[j].push(own as f64 / scratch as f64);
                }
            }
        }
        println!("{map}: {} scenarios x {events} events of {k} toggles (radius {radius}, drive {drive}): {replans} replans, {mismatches} mismatches", picked.len());
        for (j, name) in names.iter().enumerate() {
            let f =
                |q| quantile(&ratios[j], q).map_or("-".into(), |v| format!("{:.1} %", 100.0 * v));
            println!("  {name}: repair expansions / A* from scratch at the same replans, per run: median {} (p10 {}, p90 {})", f(0.5), f(0.1), f(0.9));
        }
        total_mismatches += mismatches;
    }
    if total_mismatches > 0 {
        std::process::exit(1);
    }
    Ok(())
}
