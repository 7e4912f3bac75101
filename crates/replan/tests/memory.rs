//! A GPPC replay's memory does not grow with the scenario's batches: it holds the map as
//! patched so far and the pending batch's map, two at most (`planner_replan::gppc::replay`).
//! Allocations are counted on the calling thread by the runner's counting allocator
//! ([`planner_runner::alloc`], installed for this test binary; other tests' threads keep
//! their own counts).

use std::fmt::Write as _;

use planner_maps::gppc::{parse_gppc_patches, parse_gppc_scenario};
use planner_replan::experiment;
use planner_replan::gppc::replay;
use planner_replan::planners;
use planner_runner::alloc;

#[global_allocator]
static GLOBAL: alloc::Counting = alloc::Counting;

/// A 512 x 512 map, `batches` batches of one patch each (a 2 x 2 block at (10, 10), walled
/// and freed by turns, so that every batch's map differs from the last) and one query along
/// the free top row, of cost 3. Every query checked, every 4th carried.
fn peak_for(batches: usize) -> (u64, usize, usize) {
    let mut scen =
        String::from("version 2\nheight 512\nwidth 512\ncost 1 octile\npatch t.patch\ncommands\n");
    for batch in 0..batches {
        writeln!(scen, "P {batch} {} 10 10", batch % 2).unwrap();
        writeln!(scen, "Q {batch} 0 0 3 0 3").unwrap();
    }
    let scenario = parse_gppc_scenario(&scen, "t.scen").unwrap();
    let patches = parse_gppc_patches(
        "type patch\npatches 2\npatch 0\nheight 2\nwidth 2\nmap\n@@\n@@\npatch 1\nheight 2\nwidth 2\nmap\n..\n..\n",
        "t.patch",
    )
    .unwrap();
    scenario.validate(&patches, "t.scen").unwrap();
    let mut planner = planners::by_name("dstar_lite", true).unwrap();
    let baseline = alloc::start();
    let out = replay(&scenario, &patches, planner.as_mut(), 1, 4).unwrap();
    let peak = alloc::peak_since_start(baseline);
    assert!(out.queries.iter().all(|q| q.agrees), "{:?}", out.queries);
    assert!(out.mismatches.is_empty(), "{}", out.mismatches[0]);
    (peak, out.queries.len(), out.carried.len())
}

#[test]
fn a_replay_holds_two_maps_whatever_its_batches() {
    let (few, queries, carried) = peak_for(8);
    // The 4th and 8th queries are selected; the 8th, in the last batch, has no next map.
    assert_eq!((queries, carried), (8, 1));
    let (many, queries, carried) = peak_for(200);
    assert_eq!((queries, carried), (200, 49));
    // A map is 262,144 cells (a byte each and more); holding every batch's map, 192 more
    // batches would take at least 48 MiB more. The records of 192 more queries are small.
    assert!(
        many < few + (1 << 20),
        "peak {many} bytes for 200 batches against {few} for 8"
    );
}

/// The heap a `navigate` experiment held on its calling thread, where the tables are
/// written, for `scenarios` scenarios of den520d (one radius, D* Lite alone), and its
/// replans.
fn navigate_peak(scenarios: usize) -> (u64, u64) {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let maps = root.join("maps/movingai");
    let text = format!(
        "kind = \"navigate\"\nname = \"mem\"\nradii = [1]\ncompare = [\"dstar_lite\"]\n\
         [[maps]]\nmap = {:?}\nscen = {:?}\nscenarios = {scenarios}\n",
        maps.join("den520d.map").display().to_string(),
        maps.join("den520d.map.scen").display().to_string(),
    );
    let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR"))
        .join(format!("replan-memory-{scenarios}"));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("mem.toml");
    std::fs::write(&path, &text).unwrap();
    let config = experiment::parse(&path, &text).unwrap();
    let options = experiment::RunOptions {
        test: false,
        timing: false,
        threads: 1,
        stop: None,
    };
    let baseline = alloc::start();
    let done = experiment::run_config(&config, &path, &dir.join("out"), &options).unwrap();
    let peak = alloc::peak_since_start(baseline);
    assert_eq!((done.runs, done.mismatches), (scenarios, 0));
    (peak, done.replans)
}

/// A `navigate` experiment writes its tables as its runs finish and keeps a few numbers a
/// replan: its heap grows by far less per replan than a replan's lines in the tables
/// (about 360 bytes in replans.jsonl alone), which it held whole before.
#[test]
fn a_navigate_experiment_keeps_few_bytes_per_replan() {
    let (few, few_replans) = navigate_peak(10);
    let (many, many_replans) = navigate_peak(40);
    assert!(
        many_replans > few_replans + 1000,
        "{few_replans} -> {many_replans}"
    );
    let per_replan = many.saturating_sub(few) as f64 / (many_replans - few_replans) as f64;
    assert!(
        per_replan < 64.0,
        "{per_replan:.0} bytes more per replan ({few} bytes for {few_replans} replans, {many} for {many_replans})"
    );
}
