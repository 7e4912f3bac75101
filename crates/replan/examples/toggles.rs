//! Seeded scripted changes on Moving AI maps: between replans the agent drives a few
//! cells and `k` cells are toggled on its path or near it; D* Lite, LPA* and A* from
//! scratch replan, each replan checked by the exact oracle.
//!
//! ```text
//! cargo run --release -p planner-replan --example toggles -- [--scenarios 50] \
//!     [--maps den520d,random512-10-0] [--events 40] [--k 5] [--radius 5] [--drive 2]
//! ```

use std::path::PathBuf;

use planner_api::{Budget, Problem};
use planner_replan::report::quantile;
use planner_replan::toggles::{self, ToggleConfig};
use planner_replan::{planners, Oracle};

fn arg(args: &[String], key: &str, default: &str) -> String {
    args.iter()
        .position(|a| a == key)
        .and_then(|i| args.get(i + 1))
        .map_or(default, String::as_str)
        .to_owned()
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let n: usize = arg(&args, "--scenarios", "50").parse()?;
    let events: u32 = arg(&args, "--events", "40").parse()?;
    let k: u32 = arg(&args, "--k", "5").parse()?;
    let radius: u32 = arg(&args, "--radius", "5").parse()?;
    let drive: u32 = arg(&args, "--drive", "2").parse()?;
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../maps/movingai");
    let names = ["dstar_lite", "lpastar", "astar"];
    let mut total_mismatches = 0;
    for map in arg(&args, "--maps", "den520d,random512-10-0").split(',') {
        if !map
            .chars()
            .all(|c| c.is_ascii_alphanumeric() || "-_.".contains(c))
        {
            return Err(format!("map name {map:?}: letters, digits, '-', '_' and '.' only").into());
        }
        let grid = planner_maps::read_map(&root.join(format!("{map}.map")))?.grid;
        let scenarios = planner_maps::read_scenarios(&root.join(format!("{map}.map.scen")))?;
        let count = n.min(scenarios.len());
        let mut oracle = Oracle::new(true);
        // Per planner: repair expansions (after the first plan) / A*'s from scratch, per run.
        let mut ratios: Vec<Vec<f64>> = vec![Vec::new(); names.len()];
        let (mut replans, mut mismatches) = (0usize, 0usize);
        for i in 0..count {
            let s = &scenarios[i * scenarios.len() / count];
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
        println!("{map}: {count} scenarios x {events} events of {k} toggles (radius {radius}, drive {drive}): {replans} replans, {mismatches} mismatches");
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
