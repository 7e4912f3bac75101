//! Navigation in unknown terrain on Moving AI maps: D* Lite, LPA* restarted at the agent,
//! and A* from scratch (forward and backward) at every replan, every replan checked by
//! the exact oracle.
//!
//! ```text
//! cargo run --release -p planner-replan --example navigate -- [--scenarios 100] \
//!     [--maps den520d,random512-10-0] [--radius 1,5] [--out target/replan/navigate]
//! ```
//!
//! For each map, `--scenarios` scenarios spread evenly over its `.scen` file; for each
//! scenario and radius, every planner drives its own agent (the planner order rotates per
//! scenario, so machine load falls on all alike). Writes `runs.csv` (one line per run),
//! `replans.csv` (one line per replan, with A*'s expansions from scratch at that replan:
//! the oracle's search) and `dstar_lite_vs_astar.svg` (D* Lite's expansions per replan
//! against A* from scratch at the same replan), and prints per map and radius: runs,
//! replans, mismatches, and the medians over scenarios of D* Lite's (and LPA*'s) total
//! expansions and planning time as a share of repeated A*'s.

use std::fmt::Write as _;
use std::path::PathBuf;
use std::time::Duration;

use planner_api::Budget;
use planner_replan::args::{loadavg, movingai_map, spread, Args};
use planner_replan::navigate::{self, NavConfig, NavRun};
use planner_replan::report::{quantile, scatter_svg};
use planner_replan::{planners, Oracle};

fn micros(d: Duration) -> u128 {
    d.as_micros()
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args = Args::from_env();
    let n_scenarios: usize = args.parsed("--scenarios", "100")?;
    let maps = args.list("--maps", "den520d,random512-10-0");
    let radii: Vec<u32> = args.parsed_list("--radius", "1,5")?;
    let names = args.list("--planners", &planners::names().join(","));
    let out = PathBuf::from(args.value("--out", "target/replan/navigate"));
    for name in &names {
        planners::by_name(name, true)?;
    }
    // Every map is read (and its name checked) before anything is written.
    let loaded = maps
        .iter()
        .map(|map| movingai_map(map))
        .collect::<Result<Vec<_>, _>>()?;
    std::fs::create_dir_all(&out)?;
    let mut runs_csv = String::from("map,scenario_line,radius,planner,reached,steps,replans,total_expansions,time_to_first_move_us,planning_time_us,replan_time_us,mismatches\n");
    let mut replans_csv = String::from("map,scenario_line,radius,planner,replan,step,expansions,astar_expansions,update_us,replan_us,counters\n");
    let mut chart = Vec::new();
    let (mut all_replans, mut all_mismatches) = (0u64, 0u64);
    println!("load average at start: {}", loadavg());
    for (map, (grid, scenarios)) in maps.iter().zip(&loaded) {
        let picked = spread(scenarios, n_scenarios);
        for &radius in &radii {
            let config = NavConfig {
                radius,
                ..NavConfig::default()
            };
            // Per scenario: planner name -> run.
            let mut table: Vec<Vec<(String, NavRun)>> = Vec::new();
            let mut oracle = Oracle::new(true);
            for (k, scenario) in picked.iter().enumerate() {
                let mut row = Vec::new();
                for j in 0..names.len() {
                    let name = &names[(k + j) % names.len()];
                    let mut planner = planners::by_name(name, true)?;
                    let run = navigate::run(
                        planner.as_mut(),
                        Some(&mut oracle),
                        grid,
                        scenario.start,
                        scenario.goal,
                        &config,
                        &Budget::unlimited(),
                    )?;
                    for m in &run.mismatches {
                        eprintln!(
                            "MISMATCH {map} line {} r={radius} {name}: {m}",
                            scenario.line
                        );
                    }
                    let _ = writeln!(
                        runs_csv,
                        "{map},{},{radius},{name},{},{},{},{},{},{},{},{}",
                        scenario.line,
                        run.reached,
                        run.steps,
                        run.replans.len(),
                        run.total_expansions(),
                        micros(run.time_to_first_move()),
                        micros(run.planning_time()),
                        micros(run.replans.iter().map(|r| r.replan_time).sum()),
                        run.mismatches.len()
                    );
                    for (i, r) in run.replans.iter().enumerate() {
                        let _ = writeln!(
                            replans_csv,
                            "{map},{},{radius},{name},{i},{},{},{},{},{},{}",
                            scenario.line,
                            r.step,
                            r.expansions,
                            r.oracle_expansions.unwrap_or(0),
                            micros(r.update_time),
                            micros(r.replan_time),
                            r.counters
                                .iter()
                                .map(|(k, v)| format!("{k}={v}"))
                                .collect::<Vec<_>>()
                                .join(";")
                        );
                        if name == "dstar_lite" {
                            chart.push((r.oracle_expansions.unwrap_or(0), r.expansions));
                        }
                    }
                    all_replans += run.replans.len() as u64;
                    all_mismatches += run.mismatches.len() as u64;
                    row.push((name.clone(), run));
                }
                table.push(row);
            }
            let get = |row: &Vec<(String, NavRun)>, name: &str| {
                row.iter().find(|(n, _)| n == name).map(|(_, r)| r.clone())
            };
            let replans: usize = table.iter().flatten().map(|(_, r)| r.replans.len()).sum();
            let mismatches: usize = table
                .iter()
                .flatten()
                .map(|(_, r)| r.mismatches.len())
                .sum();
            println!(
                "{map} radius {radius}: {} scenarios, {} runs, {replans} replans, {mismatches} mismatches",
                table.len(),
                table.len() * names.len()
            );
            for name in ["dstar_lite", "lpastar", "astar_backward"] {
                for base in ["astar", "astar_backward"] {
                    if name == base
                        || !names.iter().any(|n| n == name)
                        || !names.iter().any(|n| n == base)
                    {
                        continue;
                    }
                    let (mut exp, mut time, mut replan_time) = (Vec::new(), Vec::new(), Vec::new());
                    for row in &table {
                        let (Some(a), Some(b)) = (get(row, name), get(row, base)) else {
                            continue;
                        };
                        if b.total_expansions() > 0 {
                            exp.push(a.total_expansions() as f64 / b.total_expansions() as f64);
                        }
                        if !b.planning_time().is_zero() {
                            time.push(
                                a.planning_time().as_secs_f64() / b.planning_time().as_secs_f64(),
                            );
                        }
                        let rt = |r: &NavRun| {
                            r.replans
                                .iter()
                                .map(|x| x.replan_time)
                                .sum::<Duration>()
                                .as_secs_f64()
                        };
                        if rt(&b) > 0.0 {
                            replan_time.push(rt(&a) / rt(&b));
                        }
                    }
                    let pct =
                        |v: Option<f64>| v.map_or("-".into(), |x| format!("{:.1} %", 100.0 * x));
                    println!(
                        "  {name} / {base}: median total expansions {}, median planning time {} (replan only {}) [p10-p90 expansions {} - {}]",
                        pct(quantile(&exp, 0.5)),
                        pct(quantile(&time, 0.5)),
                        pct(quantile(&replan_time, 0.5)),
                        pct(quantile(&exp, 0.1)),
                        pct(quantile(&exp, 0.9)),
                    );
                }
            }
            for name in &names {
                let per: Vec<f64> = table
                    .iter()
                    .flatten()
                    .filter(|(n, _)| n == name)
                    .flat_map(|(_, r)| r.replans.iter().skip(1).map(|x| x.expansions as f64))
                    .collect();
                let first: Vec<f64> = table
                    .iter()
                    .flatten()
                    .filter(|(n, _)| n == name)
                    .filter_map(|(_, r)| r.replans.first().map(|x| x.expansions as f64))
                    .collect();
                let f = |q| quantile(&per, q).map_or("-".into(), |v| format!("{v:.0}"));
                println!(
                    "  {name}: expansions per replan after the first: p50 {} p90 {} p99 {} max {}; first plan median {}",
                    f(0.5),
                    f(0.9),
                    f(0.99),
                    f(1.0),
                    quantile(&first, 0.5).map_or("-".into(), |v| format!("{v:.0}"))
                );
            }
        }
    }
    std::fs::write(out.join("runs.csv"), runs_csv)?;
    std::fs::write(out.join("replans.csv"), replans_csv)?;
    std::fs::write(
        out.join("dstar_lite_vs_astar.svg"),
        scatter_svg(
            &chart,
            "A* from scratch: expansions at the replan",
            "D* Lite: expansions at the replan",
            "Expansions per replan, navigation in unknown terrain (dashed: equal; red: 20 %)",
        ),
    )?;
    println!("total: {all_replans} replans, {all_mismatches} mismatches");
    println!("load average at end: {}", loadavg());
    println!("wrote {}", out.display());
    if all_mismatches > 0 {
        std::process::exit(1);
    }
    Ok(())
}
