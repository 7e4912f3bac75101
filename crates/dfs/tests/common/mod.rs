//! Test helpers: the repository's maps and the frontier counter checks, from planner-testkit.
#![allow(unused_imports)]

pub use planner_testkit::{
    check_budget_cut, check_frontier_identities, fewest_moves, first_scenario, frontier_counters,
    maps_dir, movingai, movingai_maps, paper_maps, published, small_random_problems, wpi,
};
