//! Test helpers: the repository's maps (from planner-testkit) and the counter checks.
#![allow(dead_code, unused_imports)]

pub use planner_testkit::{
    first_scenario, maps_dir, movingai, movingai_maps, paper_maps, published, wpi,
};

/// Asserts the counter identities of a Backtracking run with `k` moves per cell (crate docs):
/// exact for a complete run; for a truncated one the second holds exactly and the other
/// two within the bounds that the open path of `L` cells allows.
pub fn check_identities(what: &str, c: &planner_api::Counters, k: u64, complete: bool) {
    let get = |name: &str| c.get(name).unwrap_or_else(|| panic!("{what}: no {name}"));
    let (exp, checks, blocked, skipped) = (
        get("n_expanded"),
        get("n_neighbor_checks"),
        get("n_blocked"),
        get("n_skipped"),
    );
    let (sol, back, depth) = (get("n_solutions"), get("n_backtracks"), get("max_depth"));
    let pruned = c.get("n_pruned").unwrap_or(0);
    if exp == 0 {
        assert!(!complete, "{what}: a complete run expands the root");
        assert!(c.iter().all(|(_, v)| v == 0), "{what}: {c}");
        return;
    }
    assert_eq!(
        checks,
        blocked + skipped + pruned + (exp - 1),
        "{what}: checks = blk + skp + exp - 1; {c}"
    );
    if complete {
        assert_eq!(
            checks,
            k * (exp - sol),
            "{what}: checks = k (exp - sol); {c}"
        );
        assert_eq!(back, exp - 1, "{what}: back = exp - 1; {c}");
    } else {
        // L = exp - back cells were on the path when the budget stopped the search.
        let open = exp - back;
        assert!(
            (1..=depth).contains(&open),
            "{what}: 1 <= exp - back <= max_depth; {c}"
        );
        let unchecked = k * (exp - sol) - checks;
        assert!(
            (1..=(k - 1) * (open - 1) + k).contains(&unchecked),
            "{what}: 1 <= k (exp - sol) - checks <= (k - 1)(L - 1) + k; {c}"
        );
    }
}
