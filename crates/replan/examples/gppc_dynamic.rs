//! The GPPC 2023 dynamic track's sample scenario (`maps/gppc-dynamic/`): every query's
//! cost checked against the recorded optimum and A* on the patched map, and an
//! incremental planner carried across the next batch's patches.
//!
//! ```text
//! cargo run --release -p planner-replan --example gppc_dynamic -- [--planner dstar_lite] \
//!     [--query-every 1] [--carry-every 1]
//! ```

use std::path::PathBuf;
use std::time::Duration;

use planner_maps::gppc::{parse_gppc_patches, parse_gppc_scenario};
use planner_replan::args::Args;
use planner_replan::gppc::replay;
use planner_replan::planners;
use planner_replan::report::quantile;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args = Args::from_env();
    let name = args.value("--planner", "dstar_lite").to_owned();
    let query_every: usize = args.parsed("--query-every", "1")?;
    let carry_every: usize = args.parsed("--carry-every", "1")?;
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../maps/gppc-dynamic");
    let scen_path = dir.join("switch_sc1_Aurora_TheFrozenSea.scen");
    let scen_name = scen_path.display().to_string();
    let scenario = parse_gppc_scenario(&std::fs::read_to_string(&scen_path)?, &scen_name)?;
    let patch_path = dir.join(&scenario.patch_file);
    let patch_name = patch_path.display().to_string();
    let patches = parse_gppc_patches(&std::fs::read_to_string(&patch_path)?, &patch_name)?;
    scenario.validate(&patches, &scen_name)?;
    let mut planner = planners::by_name(&name, true)?;
    let replay = replay(
        &scenario,
        &patches,
        planner.as_mut(),
        query_every,
        carry_every,
    )?;
    let agree = replay.queries.iter().filter(|q| q.agrees).count();
    let no_path = replay
        .queries
        .iter()
        .filter(|q| q.recorded.is_none())
        .count();
    println!(
        "{} patch commands applied, {} queries checked ({no_path} recorded as no path): {agree} agree with the recorded optimum and A* on the patched map, {} disagree",
        replay.patches_applied,
        replay.queries.len(),
        replay.queries.len() - agree
    );
    for q in replay.queries.iter().filter(|q| !q.agrees).take(10) {
        println!(
            "  line {}: recorded {:?}, A* {:?}",
            q.line,
            q.recorded,
            q.astar.map(|c| c.to_f64())
        );
    }
    let carried = &replay.carried;
    let sum =
        |f: &dyn Fn(&planner_replan::gppc::CarryRecord) -> u64| carried.iter().map(f).sum::<u64>();
    let ratios: Vec<f64> = carried
        .iter()
        .filter(|c| c.astar_expansions > 0)
        .map(|c| c.repair_expansions as f64 / c.astar_expansions as f64)
        .collect();
    let repair_time: Duration = carried.iter().map(|c| c.repair_time).sum();
    let astar_time: Duration = carried.iter().map(|c| c.astar_time).sum();
    println!(
        "{name} carried across the next batch's patches for {} queries: {} mismatches; repair expansions {} in all vs A* from scratch {} ({:.1} %; first searches {}); median per query {:.1} % (p90 {:.1} %); repair time {:.3} s vs A* {:.3} s",
        carried.len(),
        replay.mismatches.len(),
        sum(&|c| c.repair_expansions),
        sum(&|c| c.astar_expansions),
        100.0 * sum(&|c| c.repair_expansions) as f64 / sum(&|c| c.astar_expansions).max(1) as f64,
        sum(&|c| c.first_expansions),
        100.0 * quantile(&ratios, 0.5).unwrap_or(f64::NAN),
        100.0 * quantile(&ratios, 0.9).unwrap_or(f64::NAN),
        repair_time.as_secs_f64(),
        astar_time.as_secs_f64(),
    );
    for m in replay.mismatches.iter().take(10) {
        println!("  MISMATCH {m}");
    }
    if agree != replay.queries.len() || !replay.mismatches.is_empty() {
        std::process::exit(1);
    }
    Ok(())
}
