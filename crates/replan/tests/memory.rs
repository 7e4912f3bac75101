//! Memory that does not grow with the work's records: a GPPC replay holds the map as
//! patched so far and the pending batch's map, two at most (`planner_replan::gppc::replay`);
//! a run of an experiment holds none of its replans, and the experiment a bounded summary.
//! Allocations are counted on the calling thread by the runner's counting allocator
//! ([`planner_runner::alloc`], installed for this test binary; other tests' threads keep
//! their own counts).

use std::fmt::Write as _;

use planner_api::IncrementalPlanner;
use planner_maps::gppc::{parse_gppc_patches, parse_gppc_scenario};
use planner_replan::experiment;
use planner_replan::gppc::replay;
use planner_replan::planners;
use planner_runner::alloc;

use crate::wrap::{Change, Wrapped};

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

/// A config of a `dynamic` experiment on arena: one scenario, D* Lite alone, one seed,
/// `events` events of 5 toggles each.
fn dynamic_config(name: &str, events: u32) -> (std::path::PathBuf, experiment::ExperimentConfig) {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let arena = root.join("maps/movingai/arena.map");
    let text = format!(
        "kind = \"dynamic\"\nname = \"mem\"\ncompare = [\"dstar_lite\"]\n\
         [[maps]]\nmap = {:?}\nscen = {:?}\nscenarios = 1\n\
         [toggles]\nevents = {events}\nk = 5\nradius = 5\nseeds = [1]\n",
        arena.display().to_string(),
        format!("{}.scen", arena.display()),
    );
    let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR"))
        .join(format!("replan-memory-{name}-{events}"));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("mem.toml");
    std::fs::write(&path, &text).unwrap();
    let config = experiment::parse(&path, &text).unwrap();
    (path, config)
}

fn one_thread() -> experiment::RunOptions {
    experiment::RunOptions {
        test: false,
        timing: false,
        threads: 1,
        stop: None,
    }
}

/// Measures the heap of its run's thread: from its making (by the experiment's planner
/// factory, on the run's thread, as the run starts) to its drop (as the run ends, on the
/// same thread); the peak goes to [`RUN_PEAK`].
struct Measured {
    baseline: isize,
}

static RUN_PEAK: std::sync::Mutex<Option<u64>> = std::sync::Mutex::new(None);

impl Drop for Measured {
    fn drop(&mut self) {
        *RUN_PEAK.lock().unwrap() = Some(alloc::peak_since_start(self.baseline));
    }
}

impl Change for Measured {}

/// The heap the run of [`dynamic_config`] held on its own thread, and its replans.
fn run_peak(events: u32) -> (u64, u64) {
    let (path, config) = dynamic_config("run", events);
    let make = |name: &str, eight: bool| -> Box<dyn IncrementalPlanner> {
        let inner = planners::by_name(name, eight).unwrap();
        Box::new(Wrapped {
            inner,
            change: Measured {
                baseline: alloc::start(),
            },
        })
    };
    let out = path.with_file_name("out");
    let done = experiment::run_config_with(&config, &path, &out, &one_thread(), &make).unwrap();
    assert_eq!((done.runs, done.mismatches), (1, 0));
    (RUN_PEAK.lock().unwrap().take().unwrap(), done.replans)
}

/// A run writes its replans out as they happen: its heap does not grow with its events.
/// It held them all until it ended, each with its counters, before (a run of 100,000
/// events on arena took 243 MB beside its 237 MB of replans.jsonl).
#[test]
fn a_run_keeps_none_of_its_replans() {
    let (few, few_replans) = run_peak(100);
    let (many, many_replans) = run_peak(10_000);
    assert_eq!((few_replans, many_replans), (101, 10_001));
    assert!(
        many < few + (64 << 10),
        "peak {many} bytes for {many_replans} replans against {few} for {few_replans}"
    );
}

/// The heap a `dynamic` experiment held on its calling thread, where the tables are
/// written and the summary gathered, and its replans.
fn experiment_peak(events: u32) -> (u64, u64) {
    let (path, config) = dynamic_config("experiment", events);
    let baseline = alloc::start();
    let done =
        experiment::run_config(&config, &path, &path.with_file_name("out"), &one_thread()).unwrap();
    let peak = alloc::peak_since_start(baseline);
    assert_eq!((done.runs, done.mismatches), (1, 0));
    (peak, done.replans)
}

/// An experiment keeps what its summary and chart need in bounded memory: a histogram of
/// expansions per replan (one count per distinct value) and at most `CHART_POINTS`
/// points. With 40,000 replans after the first the chart shows every 2nd, with 160,000
/// every 8th, 20,000 points both: the 120,000 more replans cost it no more than 64 KiB. It
/// kept a few numbers per replan before, and two more copies of them for the chart at the
/// end.
#[test]
fn an_experiment_keeps_a_bounded_summary() {
    let (few, few_replans) = experiment_peak(40_000);
    let (many, many_replans) = experiment_peak(160_000);
    assert_eq!((few_replans, many_replans), (40_001, 160_001));
    assert!(
        many < few + (64 << 10),
        "peak {many} bytes for {many_replans} replans against {few} for {few_replans}"
    );
}
