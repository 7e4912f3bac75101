//! Every registered planner keeps within the memory budget: with `max_memory_mb = 1` on a
//! grid of a million cells, a planner either refuses to run, saying how much it needs
//! (`Outcome::memory`), or asks for at most that much memory (plus a little for its
//! answer) while it prepares and plans. What it asks for is counted by a global allocator
//! on the calling thread (the only `unsafe` of this crate's tests), so memory that the
//! system would commit only when touched counts in full: the budget is a promise about
//! what a planner allocates, not about what it happens to touch.
#![allow(unsafe_code)]

use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell as StdCell;

use planner_api::{Budget, Cell, CoverageProblem, Grid, Problem};
use planner_registry::{Built, PLANNERS};

struct Counting;

thread_local! {
    /// Bytes allocated and not yet freed on this thread, and the most since the last reset.
    static LIVE: StdCell<i64> = const { StdCell::new(0) };
    static PEAK: StdCell<i64> = const { StdCell::new(0) };
}

fn add(bytes: i64) {
    let _ = LIVE.try_with(|live| {
        let now = live.get() + bytes;
        live.set(now);
        let _ = PEAK.try_with(|peak| peak.set(peak.get().max(now)));
    });
}

// SAFETY: every call is forwarded unchanged to the system allocator; the bookkeeping
// touches only const-initialised thread-locals and never allocates.
unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        add(layout.size() as i64);
        unsafe { System.alloc(layout) }
    }

    unsafe fn alloc_zeroed(&self, layout: Layout) -> *mut u8 {
        add(layout.size() as i64);
        unsafe { System.alloc_zeroed(layout) }
    }

    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        add(-(layout.size() as i64));
        unsafe { System.dealloc(ptr, layout) }
    }

    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        add(new_size as i64 - layout.size() as i64);
        unsafe { System.realloc(ptr, layout, new_size) }
    }
}

#[global_allocator]
static GLOBAL: Counting = Counting;

/// The most a planner may ask for beyond the budget: its answer (a path, counters, a
/// series) and small fixed buffers.
const SLACK: i64 = 256 << 10;

/// Runs `f` and returns its result with the most bytes it had allocated at once on this
/// thread (beyond what was live before).
fn peak_of<T>(f: impl FnOnce() -> T) -> (T, i64) {
    let before = LIVE.with(StdCell::get);
    PEAK.with(|peak| peak.set(before));
    let out = f();
    (out, PEAK.with(StdCell::get) - before)
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

/// Each registry entry's defaults, and its 8-connected variant where its config takes
/// `moves = 8`.
fn factories() -> Vec<(&'static str, planner_registry::Factory)> {
    let eight: toml::Table = toml::from_str("moves = 8").unwrap();
    let mut out = Vec::new();
    for entry in PLANNERS {
        let defaults = (entry.factory)(&toml::Table::new()).expect("defaults must be valid");
        out.push((entry.name, defaults));
        if let Ok(f) = (entry.factory)(&eight) {
            out.push((entry.name, f));
        }
    }
    out
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
