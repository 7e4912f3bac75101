//! Every registered planner keeps within the memory budget: with `max_memory_mb = 1` on a
//! grid of a million cells, a planner either refuses to run, saying how much it needs
//! (`Outcome::memory`), or asks for at most that much memory (plus a little for its
//! answer) while it prepares and plans. What it asks for is counted on the calling thread
//! by the runner's counting allocator ([`planner_runner::alloc`], installed for this test
//! binary), so memory that the system would commit only when touched counts in full: the
//! budget is a promise about what a planner allocates, not about what it happens to touch.

use planner_api::{Budget, Cell, CoverageProblem, Grid, Problem};
use planner_registry::{Built, PLANNERS};
use planner_runner::alloc;

#[global_allocator]
static GLOBAL: alloc::Counting = alloc::Counting;

/// The most a planner may ask for beyond the budget: its answer (a path, counters, a
/// series) and small fixed buffers.
const SLACK: i64 = 256 << 10;

/// Runs `f` and returns its result with the most bytes it had allocated at once on this
/// thread (beyond what was live before).
fn peak_of<T>(f: impl FnOnce() -> T) -> (T, i64) {
    let baseline = alloc::start();
    let out = f();
    (out, alloc::peak_since_start(baseline) as i64)
}

/// One run of `factory`'s planner on `grid` within `budget` (prepared through
/// `prepare_within`, as the runner does): the memory it said it needs when it refused, and
/// the most it allocated at once.
fn measured(
    factory: &planner_registry::Factory,
    grid: &Grid,
    (start, goal): (Cell, Cell),
    budget: &Budget,
) -> (Option<planner_api::MemoryShortfall>, i64) {
    let mut built = factory.build().unwrap();
    peak_of(|| match &mut built {
        Built::Path(p) => {
            if let Some(seed) = factory.seed_for(1, 0) {
                p.reseed(seed);
            }
            p.prepare_within(grid, budget);
            let problem = Problem::new(grid, start, goal).unwrap();
            p.plan(&problem, budget).memory
        }
        Built::Coverage(c) => {
            let problem = CoverageProblem::new(grid, start).unwrap();
            c.cover(&problem, budget).memory
        }
    })
}

/// Each registry entry's variants (`Entry::variants`: its defaults, and 8-connected moves
/// where its config takes them).
fn factories() -> Vec<(&'static str, planner_registry::Factory)> {
    PLANNERS
        .iter()
        .flat_map(|entry| {
            entry
                .variants()
                .expect("defaults must be valid")
                .into_iter()
                .map(move |f| (entry.name, f))
        })
        .collect()
}

/// A 1000 x 1000 open grid and a problem across it.
fn million() -> (Grid, (Cell, Cell)) {
    let (w, h) = (1000, 1000);
    let grid = Grid::from_free_cells(w, h, vec![true; (w * h) as usize]).unwrap();
    (grid, (Cell::new(0, 0), Cell::new(w - 1, h - 1)))
}

#[test]
fn every_registered_planner_keeps_within_its_memory_budget() {
    let (grid, ends) = million();
    let budget = Budget::expansions(200).with_memory_mb(1);
    let limit = (1 << 20) + SLACK;
    let factories = factories();
    assert!(factories.len() > PLANNERS.len());
    let mut over = Vec::new();
    for (name, factory) in &factories {
        let (refused, peak) = measured(factory, &grid, ends, &budget);
        if peak > limit {
            let said = if refused.is_some() {
                " (and then refused)"
            } else {
                ""
            };
            over.push(format!("{name} asked for {} KiB{said}", peak >> 10));
        }
    }
    assert!(
        over.is_empty(),
        "over a 1 MiB memory budget on a 1000 x 1000 grid without saying so: {}",
        over.join(", ")
    );
}

/// What a planner says it needs when it refuses is at least what it allocates when it
/// runs (the same problem, no memory limit): the shortfall is an upper bound, so a run
/// it would have refused never fits, and one it runs never needs more than it said.
#[test]
fn a_refusing_planner_says_at_least_what_it_would_allocate() {
    let (grid, ends) = million();
    let mut under = Vec::new();
    for (name, factory) in &factories() {
        let budget = Budget::expansions(200);
        let (_, peak) = measured(factory, &grid, ends, &budget);
        let (refused, _) = measured(factory, &grid, ends, &budget.with_memory_mb(1));
        if let Some(shortfall) = refused {
            if (shortfall.needed_bytes as i64) < peak - SLACK {
                under.push(format!(
                    "{name} said {} KiB and allocated {} KiB",
                    shortfall.needed_bytes >> 10,
                    peak >> 10
                ));
            }
        }
    }
    assert!(under.is_empty(), "needs under-stated: {}", under.join(", "));
}

/// A run's `peak_heap_bytes` counts what its planner holds as the search starts, the
/// buffers it kept from the worker's earlier runs included: after RRT grew a tree of
/// 200,000 nodes on one problem, its next run (a neighbouring goal) said 688 bytes, while
/// the planner held megabytes. Now the next run's figure is at least what the worker's
/// planner holds (the thread's bytes after the first run's record is dropped, less the
/// workspace's own).
#[test]
fn peak_heap_counts_what_the_planner_kept_from_earlier_runs() {
    use planner_runner::run::{run_one, RunSpec, Workspace};
    let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join("gridplan-memory-kept");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    // An open map whose last column is walled off: the first goal is unreachable, so RRT
    // runs all its iterations.
    let row = format!("{}@.\n", ".".repeat(254));
    let map = format!(
        "type octile\nheight 256\nwidth 256\nmap\n{}",
        row.repeat(256)
    );
    std::fs::write(dir.join("open.map"), map).unwrap();
    let text = "name = \"kept\"\nfigures = \"none\"\n[[maps]]\nfiles = [\"open.map\"]\n\
                pairs = [{ start = [0, 0], goal = [255, 255] }, { start = [0, 0], goal = [1, 0] }]\n\
                [planners.r]\nplanner = \"rrt\"\nmax_iterations = 200000\n";
    let experiment = planner_runner::config::parse(&dir.join("kept.toml"), text).unwrap();
    let meter = alloc::Meter;
    let spec = |problem| RunSpec {
        map: 0,
        problem,
        planner: 0,
        repeat: 0,
    };
    let before = planner_runner::run::HeapMeter::current(&meter);
    let mut workspace = Workspace::default();
    let first = run_one(&experiment, &spec(0), &mut workspace, Some(&meter)).unwrap();
    assert_eq!(
        first.status,
        planner_runner::record::RunStatus::BudgetExhausted
    );
    drop(first);
    let holding = planner_runner::run::HeapMeter::current(&meter) - before;
    assert!(holding > 1 << 20, "the planner holds only {holding} bytes");
    let second = run_one(&experiment, &spec(1), &mut workspace, Some(&meter)).unwrap();
    // Less the workspace's own few bytes (its list of slots).
    assert!(
        second.peak_heap_bytes as i64 >= holding - 4096,
        "peak {} bytes, while the planner held {holding}",
        second.peak_heap_bytes
    );
    std::fs::remove_dir_all(&dir).unwrap();
}
