//! The GPPC 2023 dynamic sample (`maps/gppc-dynamic/`): read and validated, its counts as
//! the start kit states them, a sample of queries checked against the recorded optimum
//! and A* on the patched map, and D* Lite carried across patches (the full replay is the
//! `gppc_dynamic` example).

use std::path::PathBuf;

use planner_maps::gppc::{parse_gppc_patches, parse_gppc_scenario, GppcCommand};
use planner_replan::gppc::replay;
use planner_replan::planners;

#[test]
fn sample_reads_and_replays_exactly() {
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../maps/gppc-dynamic");
    let scen_text =
        std::fs::read_to_string(dir.join("switch_sc1_Aurora_TheFrozenSea.scen")).unwrap();
    let scenario = parse_gppc_scenario(&scen_text, "switch.scen").unwrap();
    let patch_text = std::fs::read_to_string(dir.join(&scenario.patch_file)).unwrap();
    let patches = parse_gppc_patches(&patch_text, "switch.patch").unwrap();
    scenario.validate(&patches, "switch.scen").unwrap();
    assert_eq!((scenario.width, scenario.height), (1024, 1024));
    assert_eq!(patches.patches.len(), 5491);
    let p = scenario
        .commands
        .iter()
        .filter(|c| matches!(c, GppcCommand::Patch { .. }))
        .count();
    let q = scenario.commands.len() - p;
    assert_eq!((p, q), (7390, 2200));
    // Every 440th query by A* against the recorded optimum; every 880th carried by D* Lite.
    let mut dstar = planners::by_name("dstar_lite", true).unwrap();
    let replay = replay(&scenario, &patches, dstar.as_mut(), 440, 880).unwrap();
    assert_eq!(replay.patches_applied, 7390);
    assert_eq!(replay.queries.len(), 2200 / 440);
    for query in &replay.queries {
        assert!(
            query.agrees,
            "line {}: recorded {:?}, A* {:?}",
            query.line,
            query.recorded,
            query.astar.map(|c| c.to_f64())
        );
    }
    assert!(replay.mismatches.is_empty(), "{}", replay.mismatches[0]);
    assert!(!replay.carried.is_empty());
}

/// A stop ends a replay before its next query, not at the end of the batch in progress: a
/// batch of 40 queries stopped after 3 checks no other. It was looked at between batches
/// alone before, so a batch of many queries on a large map held Ctrl-C for its whole length.
#[test]
fn a_stop_ends_a_replay_before_its_next_query() {
    use std::cell::Cell as Calls;
    let mut scen = String::from(
        "version 2\nheight 8\nwidth 8\ncost 1 octile\npatch t.patch\ncommands\nP 0 0 0 0\n",
    );
    for _ in 0..40 {
        scen.push_str("Q 0 0 0 7 0 7\n");
    }
    let scenario = parse_gppc_scenario(&scen, "t.scen").unwrap();
    let patches = parse_gppc_patches(
        "type patch\npatches 1\npatch 0\nheight 1\nwidth 1\nmap\n.\n",
        "t.patch",
    )
    .unwrap();
    let calls = Calls::new(0);
    let stop = || {
        calls.set(calls.get() + 1);
        calls.get() > 4
    };
    let mut planner = planners::by_name("astar", true).unwrap();
    let out =
        planner_replan::gppc::replay_until(&scenario, &patches, planner.as_mut(), 1, 0, &stop)
            .unwrap();
    assert_eq!(out.queries.len(), 3);
    assert!(out.queries.iter().all(|q| q.agrees));
}
