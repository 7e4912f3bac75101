//! Test helpers: the repository's maps (from planner-testkit) and the counter checks.
#![allow(dead_code, unused_imports)]

pub use planner_testkit::{
    first_scenario, maps_dir, movingai, movingai_maps, paper_maps, published, wpi,
};

/// Asserts the counter identities of a BFS or DFS run with `k` moves per cell (crate docs).
pub fn check_frontier_identities(what: &str, outcome: &planner_api::Outcome, k: u64) {
    use planner_api::Status;
    let c = &outcome.counters;
    let get = |name: &str| c.get(name).unwrap_or_else(|| panic!("{what}: no {name}"));
    let (exp, checks, blocked, skipped) = (
        get("n_expanded"),
        get("n_neighbor_checks"),
        get("n_blocked"),
        get("n_skipped"),
    );
    let (peak, inserted) = (get("peak_open"), get("n_open_insertions"));
    assert_eq!(
        checks,
        blocked + skipped + (inserted - 1),
        "{what}: checks = blk + skp + ins - 1; {c}"
    );
    assert!(
        peak >= 1 && peak <= inserted,
        "{what}: 1 <= peak_open <= insertions; {c}"
    );
    match outcome.status {
        Status::Found => assert_eq!(checks, k * (exp - 1), "{what}: checks = k (exp - 1); {c}"),
        Status::NoPath => {
            assert_eq!(checks, k * exp, "{what}: checks = k exp; {c}");
            assert_eq!(inserted, exp, "{what}: every inserted cell expanded; {c}");
        }
        Status::BudgetExhausted => {
            assert_eq!(checks, k * exp, "{what}: checks = k exp; {c}");
            assert!(inserted > exp, "{what}: cells left in the frontier; {c}");
        }
    }
}
