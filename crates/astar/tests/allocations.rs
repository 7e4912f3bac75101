//! "No allocation per expansion": once a planner has searched a grid, another search on it
//! allocates only the returned path, however many nodes it expands.
//!
//! This test binary installs a global allocator that counts allocations on the calling
//! thread (the only place this crate's tests use `unsafe`).
#![allow(unsafe_code)]

use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell as StdCell;

use planner_api::{Budget, Cell, Connectivity, Grid, Problem, Status};
use planner_astar::{AStar, Config, Heuristic, TieBreak};

struct Counting;

thread_local! {
    static ALLOCATIONS: StdCell<u64> = const { StdCell::new(0) };
}

// SAFETY: every call is forwarded unchanged to the system allocator; the bookkeeping
// touches only a const-initialised thread-local and never allocates.
unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        let _ = ALLOCATIONS.try_with(|n| n.set(n.get() + 1));
        unsafe { System.alloc(layout) }
    }

    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        unsafe { System.dealloc(ptr, layout) }
    }

    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        let _ = ALLOCATIONS.try_with(|n| n.set(n.get() + 1));
        unsafe { System.realloc(ptr, layout, new_size) }
    }
}

#[global_allocator]
static GLOBAL: Counting = Counting;

fn allocations() -> u64 {
    ALLOCATIONS.with(StdCell::get)
}

/// A 120 x 120 grid with a comb of walls, so that searches wander and improve nodes.
fn comb() -> Grid {
    let mut grid = Grid::new(120, 120).unwrap();
    for x in (10..110).step_by(10) {
        let gap = if x % 20 == 0 { 5 } else { 114 };
        for y in 0..120 {
            if y != gap && y != gap + 1 {
                grid.set_free(Cell::new(x, y), false);
            }
        }
    }
    grid
}

#[test]
fn repeated_searches_allocate_only_the_path() {
    let grid = comb();
    let problem = Problem::new(&grid, Cell::new(0, 60), Cell::new(119, 60)).unwrap();
    for (moves, heuristic, tie_break, weight) in [
        // The integer OPEN with each tie rule, then the general one.
        (
            Connectivity::Four,
            Heuristic::Manhattan,
            TieBreak::Fifo,
            1.0,
        ),
        (
            Connectivity::Four,
            Heuristic::Manhattan,
            TieBreak::Lifo,
            1.0,
        ),
        (
            Connectivity::Four,
            Heuristic::Manhattan,
            TieBreak::LowG,
            1.0,
        ),
        (
            Connectivity::Four,
            Heuristic::Manhattan,
            TieBreak::HighG,
            1.0,
        ),
        (Connectivity::Eight, Heuristic::Octile, TieBreak::HighG, 1.0),
        (Connectivity::Eight, Heuristic::Octile, TieBreak::Fifo, 2.5),
        (
            Connectivity::Sixteen,
            Heuristic::Euclidean,
            TieBreak::LowG,
            1.0,
        ),
    ] {
        let config = Config {
            moves,
            heuristic,
            tie_break,
            weight,
            ..Config::default()
        };
        let mut astar = AStar::new(config.clone()).unwrap();
        let first = astar.search(&problem, &Budget::unlimited());
        assert_eq!(first.status, Status::Found, "{config:?}");
        let before = allocations();
        let again = astar.search(&problem, &Budget::unlimited());
        let n_allocations = allocations() - before;
        assert_eq!(again, first, "{config:?}");
        // The path's cell list (built goal first, then reversed in place).
        let path_len = again.path.as_ref().map_or(0, |p| p.cells().len());
        assert!(
            n_allocations <= 1 + u64::from(usize::BITS - path_len.leading_zeros()),
            "{config:?}: {n_allocations} allocations for {} expansions",
            again.stats.n_expanded
        );
        assert!(again.stats.n_expanded > 1000, "{config:?}");
    }
}
