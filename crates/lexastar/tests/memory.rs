//! Memory follows the work (issue 18): lexastar's per-state records are allocated in pages
//! on first write, and a memory budget refuses a grid before allocating.

use planner_api::{Budget, Cell, Grid, Planner, Problem, Status};
use planner_lexastar::{Config, LexAStar};

#[test]
fn a_thousand_expansions_on_a_4000_square_hold_megabytes_not_gigabytes() {
    // Before: 16 million cells x 4 headings x 24 bytes and 24 bytes per cell, 1.9 GB,
    // allocated and written before the first expansion.
    let grid = Grid::new(4000, 4000).unwrap();
    let problem = Problem::new(&grid, Cell::new(0, 0), Cell::new(3999, 3999)).unwrap();
    let mut planner = LexAStar::new(Config::default()).unwrap();
    assert_eq!(planner.memory_bytes_for(&grid), 1_920_000_000 + 625_000);
    let outcome = planner.plan(&problem, &Budget::expansions(1000));
    assert_eq!(outcome.status, Status::BudgetExhausted);
    assert_eq!(outcome.counters.get("n_expanded"), Some(1000));
    let resident = planner.resident_bytes();
    // The page tables (62,500 + 15,625 pointers, 8 bytes each) and about a thousand
    // 24 KiB pages: a page holds 256 cells of one row, and this search runs down the
    // first column (straight lines have no turns), so it touches one page per row.
    assert!(resident > 625_000, "{resident}");
    assert!(
        resident < 40_000_000,
        "{resident} bytes after 1000 expansions"
    );
    // A second search on the same grid reuses the pages.
    planner.plan(&problem, &Budget::expansions(1000));
    assert_eq!(planner.resident_bytes(), resident);
}

#[test]
fn a_memory_budget_refuses_before_allocating() {
    let grid = Grid::new(4000, 4000).unwrap();
    let problem = Problem::new(&grid, Cell::new(0, 0), Cell::new(3999, 3999)).unwrap();
    let mut planner = LexAStar::new(Config::default()).unwrap();
    let outcome = planner.plan(&problem, &Budget::unlimited().with_memory_mb(1000));
    assert_eq!(outcome.status, Status::BudgetExhausted);
    assert_eq!(outcome.counters.get("n_expanded"), Some(0));
    assert_eq!(
        outcome.memory.unwrap().to_string(),
        "needs 1832 MB for a 4000 x 4000 grid, over the max_memory_mb = 1000 budget"
    );
    assert_eq!(planner.resident_bytes(), 0);
    // Recording lists the cell of every expanded state.
    let small = Grid::new(30, 30).unwrap();
    let problem = Problem::new(&small, Cell::new(0, 0), Cell::new(29, 29)).unwrap();
    let outcome = planner.plan(&problem, &Budget::unlimited().recording_expanded(true));
    assert_eq!(outcome.status, Status::Found);
    let n_expanded = outcome.counters.get("n_expanded").unwrap();
    assert_eq!(outcome.expanded.len() as u64, n_expanded);
    assert_eq!(outcome.expanded.last(), Some(&Cell::new(29, 29)));
}
