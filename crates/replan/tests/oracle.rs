//! The oracle on every replan: 10,000 seeded small random grids with random change
//! sequences, LPA* and D* Lite, 4- and 8-connected, every replan's cost equal to A* from
//! scratch and every path valid; navigation in unknown terrain on small grids; and random
//! operation sequences, refused ones and budget-cut replans among them.

use planner_api::{Budget, Cell, CellChange, CostRule, Grid, IncrementalPlanner, Problem, Status};
use planner_replan::{navigate, planners, toggles, Mismatch, MismatchKind, Oracle};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rayon::prelude::*;

use crate::wrap::{Change, Wrapped};

/// A random grid of 3..=10 columns and rows with 0-35 % blocked cells, and two free
/// cells (start, goal; they may coincide); `None` when fewer than one cell is free.
fn random_problem(rng: &mut ChaCha8Rng) -> Option<(Grid, Cell, Cell)> {
    let (w, h) = (rng.gen_range(3..=10u32), rng.gen_range(3..=10u32));
    let density = rng.gen_range(0.0..0.35);
    let free: Vec<bool> = (0..w * h).map(|_| !rng.gen_bool(density)).collect();
    let grid = Grid::from_free_cells(w, h, free).ok()?;
    let cells: Vec<Cell> = grid.cells().filter(|&c| grid.is_free(c)).collect();
    if cells.is_empty() {
        return None;
    }
    let start = cells[rng.gen_range(0..cells.len())];
    let goal = cells[rng.gen_range(0..cells.len())];
    Some((grid, start, goal))
}

#[derive(Default)]
struct Tally {
    runs: u64,
    replans: u64,
    found: u64,
    no_path: u64,
    toggled: u64,
    mismatches: Vec<(u64, &'static str, bool, Mismatch)>,
}

impl Tally {
    /// The sums of both, `self`'s mismatches first.
    fn merge(mut self, other: Tally) -> Tally {
        self.runs += other.runs;
        self.replans += other.replans;
        self.found += other.found;
        self.no_path += other.no_path;
        self.toggled += other.toggled;
        self.mismatches.extend(other.mismatches);
        self
    }
}

#[test]
fn ten_thousand_grids_every_replan_exact() {
    // The problems in seed order (a seed whose grid has no free cell is skipped), then
    // checked on rayon's threads, each with its own oracles; the tallies are sums, and the
    // reduction keeps the mismatches in seed order.
    let mut problems = Vec::with_capacity(10_000);
    let mut seed = 0u64;
    while problems.len() < 10_000 {
        seed += 1;
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        let Some((grid, start, goal)) = random_problem(&mut rng) else {
            continue;
        };
        let config = toggles::ToggleConfig {
            events: rng.gen_range(4..=10),
            k: rng.gen_range(1..=4),
            radius: rng.gen_range(1..=3),
            drive: rng.gen_range(0..=2),
            seed,
        };
        problems.push((seed, grid, start, goal, config));
    }
    let grids = problems.len();
    let tally = problems
        .par_iter()
        .map_init(
            || [Oracle::new(false), Oracle::new(true)],
            |oracles, &(seed, ref grid, start, goal, config)| {
                let mut tally = Tally::default();
                let problem = Problem::new(grid, start, goal).unwrap();
                for name in ["lpastar", "dstar_lite"] {
                    for (eight, oracle) in [false, true].into_iter().zip(oracles.iter_mut()) {
                        let mut planner = planners::by_name(name, eight).unwrap();
                        let run = toggles::run(
                            planner.as_mut(),
                            oracle,
                            &problem,
                            &config,
                            &Budget::unlimited(),
                        );
                        tally.runs += 1;
                        tally.replans += run.replans.len() as u64;
                        tally.toggled += run.toggled;
                        tally.found += run
                            .replans
                            .iter()
                            .filter(|r| r.status == Status::Found)
                            .count() as u64;
                        tally.no_path += run
                            .replans
                            .iter()
                            .filter(|r| r.status == Status::NoPath)
                            .count() as u64;
                        for m in run.mismatches {
                            tally.mismatches.push((seed, name, eight, m));
                        }
                    }
                }
                tally
            },
        )
        .reduce(Tally::default, Tally::merge);
    eprintln!(
        "{grids} grids, {} runs, {} replans ({} found, {} no path), {} cells toggled, {} mismatches",
        tally.runs,
        tally.replans,
        tally.found,
        tally.no_path,
        tally.toggled,
        tally.mismatches.len()
    );
    for (seed, name, eight, m) in tally.mismatches.iter().take(10) {
        eprintln!("seed {seed} {name} eight={eight}: {m}");
    }
    assert!(tally.mismatches.is_empty());
    assert_eq!(tally.runs, 40_000);
    // The sequences exercise both outcomes many times.
    assert!(
        tally.found > 100_000 && tally.no_path > 1_000,
        "{} {}",
        tally.found,
        tally.no_path
    );
}

/// A random weighted copy of `grid`: weights in `1..=top` (`top` 9 or 255, so that equal
/// costs tie often or rarely), under either move cost rule.
fn weighted(grid: &Grid, rng: &mut ChaCha8Rng) -> Grid {
    let top = if rng.gen_bool(0.5) { 9 } else { 255 };
    let weights = (0..grid.len()).map(|_| rng.gen_range(1..=top)).collect();
    let rule = if rng.gen_bool(0.5) {
        CostRule::Mean
    } else {
        CostRule::Entered
    };
    grid.clone().with_weights(weights, rule).unwrap()
}

/// Costmaps that change: 4,000 seeded random weighted grids, LPA* and D* Lite, 4- and
/// 8-connected, each through 4-10 rounds of a replan checked by the oracle (A* from
/// scratch on the planner's current map, under its weights), the agent driving 0-2 cells
/// along the path (D* Lite's key modifier grows; LPA* restarts), and 1-4 changes: a new
/// weight (sometimes below the map's smallest, which ends the session), a blocked or freed
/// cell, or both.
#[test]
fn weighted_maps_with_weight_changes_every_replan_exact() {
    let mut oracles = [Oracle::new(false), Oracle::new(true)];
    let (mut replans, mut found, mut reweighted, mut restarts) = (0u64, 0u64, 0u64, 0u64);
    let mut grids = 0u64;
    let mut seed = 0u64;
    while grids < 4_000 {
        seed += 1;
        let mut rng = ChaCha8Rng::seed_from_u64(2_000_000 + seed);
        let Some((grid, start, goal)) = random_problem(&mut rng) else {
            continue;
        };
        grids += 1;
        let grid = weighted(&grid, &mut rng);
        let rounds = rng.gen_range(4..=10);
        for name in ["lpastar", "dstar_lite"] {
            for (eight, oracle) in [false, true].into_iter().zip(oracles.iter_mut()) {
                let mut rng = ChaCha8Rng::seed_from_u64(seed << 8 | u64::from(eight));
                let mut planner = planners::by_name(name, eight).unwrap();
                assert!(IncrementalPlanner::specs(planner.as_ref()).cell_costs);
                planner.reset(&Problem::new(&grid, start, goal).unwrap());
                let (mut map, mut agent) = (grid.clone(), start);
                for round in 0..rounds {
                    let outcome = planner.replan(&Budget::unlimited());
                    replans += 1;
                    found += u64::from(outcome.status == Status::Found);
                    if let Err(m) = oracle.check(&map, agent, goal, &outcome, round) {
                        panic!("seed {seed} {name} eight={eight}: {m}");
                    }
                    // The agent drives up to two cells along its path.
                    if let Some(path) = &outcome.path {
                        let cells = path.cells();
                        let next = cells[rng.gen_range(0..=2).min(cells.len() - 1)];
                        if next != agent {
                            agent = next;
                            planner.move_start(agent).unwrap();
                        }
                    }
                    let min = map.weights().unwrap().min();
                    let mut changes = Vec::new();
                    for _ in 0..rng.gen_range(1..=4) {
                        let cell = map.cell(rng.gen_range(0..map.len()));
                        let mut change = match rng.gen_range(0..3) {
                            0 => CellChange {
                                cell,
                                free: map.is_free(cell),
                                weight: None,
                            },
                            _ => CellChange {
                                cell,
                                free: !map.is_free(cell),
                                weight: None,
                            },
                        };
                        if change.free == map.is_free(cell) || rng.gen_bool(0.3) {
                            let weight = if rng.gen_bool(0.1) {
                                (min - 1).max(1)
                            } else {
                                rng.gen_range(1..=255)
                            };
                            restarts += u64::from(weight < min);
                            reweighted += 1;
                            change = change.with_weight(weight);
                        }
                        if let Some(weight) = change.weight {
                            map.set_weight(cell, weight);
                        }
                        map.set_free(cell, change.free);
                        changes.push(change);
                    }
                    planner.apply(&changes).unwrap();
                }
            }
        }
    }
    eprintln!(
        "{grids} weighted grids, {replans} replans ({found} found), {reweighted} weight \
         changes ({restarts} below the smallest weight)"
    );
    assert!(found > replans / 2 && reweighted > 50_000 && restarts > 1_000);
}

/// Navigation in unknown terrain on `seeds` small random grids (seeded from `first`),
/// weighted ones (the agent assuming weight 1 where it has not looked) when `weighted`:
/// every incremental planner and A* from scratch, 4 and 8 moves, every replan and every
/// step that sensed a change checked, the driven path legal on the true map, the goal
/// reached exactly when it is reachable. Returns runs, replans, extra checks and runs that
/// reached the goal.
fn navigate_small_grids(first: u64, seeds: u64, weighted_maps: bool) -> [u64; 4] {
    let mut oracles = [Oracle::new(false), Oracle::new(true)];
    let (mut runs, mut replans, mut extra, mut reached) = (0u64, 0u64, 0u64, 0u64);
    for seed in 0..seeds {
        let mut rng = ChaCha8Rng::seed_from_u64(first + seed);
        let Some((grid, start, goal)) = random_problem(&mut rng) else {
            continue;
        };
        let truth = match weighted_maps {
            true => weighted(&grid, &mut rng),
            false => grid,
        };
        // Radius 0 too: the agent senses only the cells of each move it tries.
        let radius = rng.gen_range(0..=3);
        let entered = truth
            .weights()
            .is_some_and(|w| w.rule() == CostRule::Entered);
        for name in planners::names() {
            if entered && name == "astar_backward" {
                // Exact under the mean rule only (planner-replan's `restart` docs).
                continue;
            }
            for (eight, oracle) in [false, true].into_iter().zip(oracles.iter_mut()) {
                let mut planner = planners::by_name(name, eight).unwrap();
                let config = navigate::NavConfig {
                    radius,
                    max_steps: None,
                    check_every_change: true,
                };
                let run = navigate::run(
                    planner.as_mut(),
                    Some(oracle),
                    &truth,
                    start,
                    goal,
                    &config,
                    &Budget::unlimited(),
                )
                .unwrap();
                assert!(
                    run.mismatches.is_empty(),
                    "seed {seed} {name} eight={eight}: {}",
                    run.mismatches[0]
                );
                assert!(!run.hit_step_limit);
                // The driven path is made of legal moves on the true map.
                let driven = planner_api::Path::new(run.path.clone());
                driven
                    .validate(&truth, planner_api::PathRule::Moves(oracle.moves()))
                    .unwrap();
                // Reached exactly when the goal is reachable on the true map.
                assert_eq!(
                    run.reached,
                    oracle.optimum(&truth, start, goal).is_some(),
                    "seed {seed} {name}"
                );
                runs += 1;
                replans += run.replans.len() as u64;
                extra += run.extra_checks;
                reached += u64::from(run.reached);
            }
        }
    }
    [runs, replans, extra, reached]
}

#[test]
fn navigation_on_small_grids_is_exact_at_every_change() {
    let [runs, replans, extra, reached] = navigate_small_grids(1_000_000, 1_500, false);
    eprintln!("{runs} navigation runs, {replans} replans, {extra} extra checks, {reached} reached");
    assert!(replans > runs + 3_000 && extra > 1_000 && reached > runs / 2);
}

/// Navigation on costmaps: the same on small random weighted grids, whose weights the agent
/// senses as it drives.
#[test]
fn navigation_on_small_weighted_grids_is_exact_at_every_change() {
    let [runs, replans, extra, reached] = navigate_small_grids(3_000_000, 1_000, true);
    eprintln!("{runs} weighted navigation runs, {replans} replans, {extra} extra checks");
    assert!(replans > runs + 3_000 && extra > 1_000 && reached > runs / 2);
}

/// The oracle can fail: a planner that ignores the changes it is told is caught.
/// A sensor radius beyond the map (up to `u32::MAX`, which a config accepts) senses the
/// whole map at once: the same run as a radius of the map's size, and it ends (the square
/// is clipped to the grid before it is walked, so the work is the map's cells).
#[test]
fn a_radius_beyond_the_map_is_the_whole_map() {
    let mut rng = ChaCha8Rng::seed_from_u64(31);
    let mut compared = 0;
    while compared < 20 {
        let Some((grid, start, goal)) = random_problem(&mut rng) else {
            continue;
        };
        let drive = |radius| {
            let mut planner = planners::by_name("dstar_lite", true).unwrap();
            let config = navigate::NavConfig {
                radius,
                ..navigate::NavConfig::default()
            };
            let run = navigate::run(
                planner.as_mut(),
                None,
                &grid,
                start,
                goal,
                &config,
                &Budget::unlimited(),
            )
            .unwrap();
            let expansions: Vec<u64> = run.replans.iter().map(|r| r.expansions).collect();
            (run.reached, run.steps, run.path, expansions)
        };
        let whole = drive(grid.width().max(grid.height()));
        assert_eq!(drive(u32::MAX), whole);
        assert_eq!(drive(1 << 20), whole);
        compared += 1;
    }
}

/// A wall across the row between start and goal: `.......` / `...#...` / `.......`.
fn wall() -> (Grid, Cell, Cell) {
    let grid = Grid::from_ascii(
        "
        .......
        ...#...
        .......
        ",
    )
    .unwrap();
    (grid, Cell::new(0, 1), Cell::new(6, 1))
}

/// At sensor radius 0 the agent senses nothing around it, yet never enters a blocked cell:
/// trying the move into the wall reveals it, and the agent replans where it stands (it
/// drove through the wall and reported the goal reached, with no failed check). Every
/// planner, 4 and 8 moves.
#[test]
fn a_radius_of_zero_never_enters_a_blocked_cell() {
    let (truth, start, goal) = wall();
    for name in planners::names() {
        for eight in [false, true] {
            let mut planner = planners::by_name(name, eight).unwrap();
            let mut oracle = Oracle::new(eight);
            let config = navigate::NavConfig {
                radius: 0,
                max_steps: None,
                check_every_change: true,
            };
            let run = navigate::run(
                planner.as_mut(),
                Some(&mut oracle),
                &truth,
                start,
                goal,
                &config,
                &Budget::unlimited(),
            )
            .unwrap();
            assert!(
                run.mismatches.is_empty(),
                "{name} {eight}: {:?}",
                run.mismatches
            );
            assert!(run.reached, "{name} {eight}");
            assert!(
                !run.path.contains(&Cell::new(3, 1)),
                "{name} {eight}: {:?}",
                run.path
            );
            planner_api::Path::new(run.path.clone())
                .validate(&truth, planner_api::PathRule::Moves(oracle.moves()))
                .unwrap();
            // The first plan runs straight through the wall; the bump is a second plan.
            assert_eq!(run.replans.len(), 2, "{name} {eight}");
            assert_eq!(run.replans[1].step, 2, "{name} {eight}");
            assert_eq!(run.steps, run.path.len() as u64 - 1);
        }
    }
}

/// Radius 1 senses the eight neighbours before the first move and after every move: a
/// wall cell diagonal to the start is in the first plan already, so no replan follows;
/// at radius 0 the same wall is found by trying to cross it.
#[test]
fn a_radius_of_one_senses_the_eight_neighbours_before_a_move() {
    let truth = Grid::from_ascii(
        "
        ....
        .#..
        ....
        ",
    )
    .unwrap();
    let (start, goal) = (Cell::new(0, 0), Cell::new(2, 2));
    let mut oracle = Oracle::new(true);
    let optimum = oracle.optimum(&truth, start, goal);
    let drive = |radius| {
        let mut planner = planners::by_name("dstar_lite", true).unwrap();
        let config = navigate::NavConfig {
            radius,
            ..navigate::NavConfig::default()
        };
        navigate::run(
            planner.as_mut(),
            Some(&mut Oracle::new(true)),
            &truth,
            start,
            goal,
            &config,
            &Budget::unlimited(),
        )
        .unwrap()
    };
    let one = drive(1);
    assert!(one.reached && one.mismatches.is_empty());
    assert_eq!(one.replans.len(), 1);
    assert_eq!(one.replans[0].cost, optimum);
    let zero = drive(0);
    assert!(zero.reached && zero.mismatches.is_empty());
    assert_eq!(zero.replans.len(), 2);
    assert!(zero.replans[0].cost < optimum);
    assert!(!zero.path.contains(&Cell::new(1, 1)));
}

/// A planner that keeps a path through a cell the agent found blocked is a failed check,
/// and the agent does not drive it: with the oracle (its path is invalid on the agent's
/// map) and without one (the step is not a legal move there). At radius 0 such a run
/// drove through the wall with no failed check.
#[test]
fn a_path_through_a_blocked_cell_is_a_failed_check_not_a_move() {
    let (truth, start, goal) = wall();
    for with_oracle in [true, false] {
        let mut deaf = deaf();
        let mut oracle = Oracle::new(true);
        let config = navigate::NavConfig {
            radius: 0,
            ..navigate::NavConfig::default()
        };
        let run = navigate::run(
            &mut deaf,
            with_oracle.then_some(&mut oracle),
            &truth,
            start,
            goal,
            &config,
            &Budget::unlimited(),
        )
        .unwrap();
        assert!(!run.reached, "oracle {with_oracle}");
        assert_eq!(
            run.path.last(),
            Some(&Cell::new(2, 1)),
            "oracle {with_oracle}"
        );
        assert_eq!(run.mismatches.len(), 1, "oracle {with_oracle}");
        let m = &run.mismatches[0];
        assert_eq!((m.step, m.start), (2, Cell::new(2, 1)));
        assert!(
            matches!(&m.kind, MismatchKind::InvalidPath(why) if why.contains("(3, 1)")),
            "oracle {with_oracle}: {m}"
        );
        // The failed replan's record has A*'s expansions at that replan: a check runs A*
        // whether or not the replan passes (it said 0).
        let failed = run.replans.last().unwrap();
        match with_oracle {
            true => assert!(failed.oracle_expansions.unwrap() > 0, "{failed:?}"),
            false => assert_eq!(failed.oracle_expansions, None),
        }
    }
}

/// A toggle script drives only a path that passed its check: a planner that plans as if
/// every cell were free (its path runs through the wall) leaves the agent where it stands,
/// every replan a failed check from the start; the agent drove the failed path through the
/// wall to the goal, where the checks then passed.
#[test]
fn a_toggle_script_never_drives_a_path_that_failed_its_check() {
    /// A planner reset on a map of the same size with every cell free.
    struct Blind;
    impl Change for Blind {
        fn name(&self) -> Option<&str> {
            Some("blind")
        }
        fn reset(
            &mut self,
            inner: &mut dyn IncrementalPlanner,
            problem: &Problem<'_>,
            budget: &Budget,
        ) {
            let grid = problem.grid();
            let free = Grid::new(grid.width(), grid.height()).unwrap();
            let problem = Problem::new(&free, problem.start(), problem.goal()).unwrap();
            inner.reset_within(&problem, budget)
        }
    }
    let (grid, start, goal) = wall();
    let problem = Problem::new(&grid, start, goal).unwrap();
    let config = toggles::ToggleConfig {
        events: 3,
        k: 0,
        radius: 0,
        drive: 6,
        seed: 1,
    };
    let mut blind = Wrapped {
        inner: planners::by_name("dstar_lite", true).unwrap(),
        change: Blind,
    };
    let run = toggles::run(
        &mut blind,
        &mut Oracle::new(true),
        &problem,
        &config,
        &Budget::unlimited(),
    );
    assert_eq!(run.replans.len(), 4);
    assert_eq!(run.mismatches.len(), 4, "{:?}", run.mismatches);
    assert!(run.mismatches.iter().all(|m| m.start == start));
    assert_eq!(run.steps, 0);
}

/// A planner that is told no change: it plans on the map it was reset with.
struct Deaf;

impl Change for Deaf {
    fn name(&self) -> Option<&str> {
        Some("deaf")
    }
    fn apply(
        &mut self,
        _: &mut dyn IncrementalPlanner,
        _: &[CellChange],
    ) -> Result<(), planner_api::ChangeError> {
        Ok(())
    }
}

/// [`Deaf`] around D* Lite (8-connected).
fn deaf() -> Wrapped<Deaf> {
    Wrapped {
        inner: planners::by_name("dstar_lite", true).unwrap(),
        change: Deaf,
    }
}

#[test]
fn a_planner_that_ignores_changes_is_caught() {
    let mut caught = 0;
    for seed in 0..200u64 {
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        let Some((grid, start, goal)) = random_problem(&mut rng) else {
            continue;
        };
        let problem = Problem::new(&grid, start, goal).unwrap();
        let config = toggles::ToggleConfig {
            events: 6,
            k: 3,
            radius: 2,
            drive: 1,
            seed,
        };
        let mut deaf = deaf();
        let run = toggles::run(
            &mut deaf,
            &mut Oracle::new(true),
            &problem,
            &config,
            &Budget::unlimited(),
        );
        caught += run.mismatches.len();
        assert!(run
            .mismatches
            .iter()
            .all(|m| !matches!(m.kind, MismatchKind::Rejected(_))));
    }
    assert!(caught > 50, "{caught}");
}

/// A change far from the path is repaired with a handful of expansions, not a new search.
#[test]
fn repairs_instead_of_restarting() {
    let grid = Grid::new(64, 64).unwrap();
    let problem = Problem::new(&grid, Cell::new(2, 30), Cell::new(61, 34)).unwrap();
    for name in ["lpastar", "dstar_lite"] {
        for eight in [false, true] {
            let mut planner = planners::by_name(name, eight).unwrap();
            planner.reset(&problem);
            let first = planner.replan(&Budget::unlimited());
            let first_expanded = first.counters.get("n_expanded").unwrap();
            // Block a cell on the path: the repair is a fraction of the first search.
            let on_path = first.path.unwrap().cells()[30];
            planner.apply(&[CellChange::blocked(on_path)]).unwrap();
            let repair = planner.replan(&Budget::unlimited());
            let repaired = repair.counters.get("n_expanded").unwrap();
            assert_eq!(repair.status, Status::Found);
            assert!(
                repaired * 2 < first_expanded,
                "{name} {eight}: {repaired} vs {first_expanded}"
            );
            // And the repaired cost is A*'s.
            let mut oracle = Oracle::new(eight);
            let map = planner.grid().unwrap().clone();
            oracle
                .check(&map, Cell::new(2, 30), Cell::new(61, 34), &repair, 1)
                .unwrap();
        }
    }
}

/// An expansion budget stops a repair part-way; the next replan finishes it exactly.
#[test]
fn a_budget_stops_and_the_next_replan_continues() {
    let grid = Grid::new(40, 40).unwrap();
    let problem = Problem::new(&grid, Cell::new(0, 0), Cell::new(39, 39)).unwrap();
    for name in ["lpastar", "dstar_lite"] {
        let mut planner = planners::by_name(name, true).unwrap();
        planner.reset(&problem);
        let stopped = planner.replan(&Budget::expansions(5));
        assert_eq!(stopped.status, Status::BudgetExhausted);
        assert_eq!(stopped.counters.get("n_expanded"), Some(5));
        let finished = planner.replan(&Budget::unlimited());
        let mut oracle = Oracle::new(true);
        oracle
            .check(&grid, Cell::new(0, 0), Cell::new(39, 39), &finished, 1)
            .unwrap();
    }
}

/// Changes outside the map, weights that cannot be, and moves onto blocked cells are
/// errors naming the cell.
#[test]
fn bad_changes_are_errors() {
    let grid = Grid::from_ascii("...\n.#.\n...").unwrap();
    let problem = Problem::new(&grid, Cell::new(0, 0), Cell::new(2, 2)).unwrap();
    for name in planners::names() {
        let mut planner = planners::by_name(name, true).unwrap();
        assert_eq!(
            planner
                .apply(&[CellChange::blocked(Cell::new(0, 0))])
                .unwrap_err(),
            planner_api::ChangeError::NotStarted
        );
        planner.reset(&problem);
        let err = planner
            .apply(&[CellChange::blocked(Cell::new(3, 1))])
            .unwrap_err();
        assert_eq!(
            err.to_string(),
            "changed cell (3, 1) is outside the 3x3 map"
        );
        let err = planner.move_start(Cell::new(1, 1)).unwrap_err();
        assert_eq!(
            err.to_string(),
            "new start (1, 1) is outside the map or blocked"
        );
        // A weight on an unweighted map, and a weight of 0 on a weighted one; nothing of
        // the batch is applied.
        let reweight = CellChange::freed(Cell::new(2, 0)).with_weight(5);
        let err = planner
            .apply(&[CellChange::blocked(Cell::new(1, 0)), reweight])
            .unwrap_err();
        assert_eq!(
            err.to_string(),
            "changed cell (2, 0) gets a weight, but the map has no weights"
        );
        assert!(planner.grid().unwrap().is_free(Cell::new(1, 0)));
        let weighted = grid
            .clone()
            .with_weights(vec![2; 9], CostRule::Mean)
            .unwrap();
        planner.reset(&Problem::new(&weighted, Cell::new(0, 0), Cell::new(2, 2)).unwrap());
        let err = planner
            .apply(&[CellChange::freed(Cell::new(2, 1)).with_weight(0)])
            .unwrap_err();
        assert_eq!(
            err.to_string(),
            "changed cell (2, 1) gets weight 0; weights are at least 1"
        );
        planner.apply(&[reweight]).unwrap();
        assert_eq!(planner.grid().unwrap().weight(Cell::new(2, 0)), 5);
    }
    assert!(planners::by_name("dstar", true).is_err());
}

/// One planner kept across many runs (as the bench and a robot keep it): grids of the
/// same size (the map brought up to date in place by the reset) and of other shapes with
/// the same number of padded cells (3 x 5 and 5 x 3: the padded map's border must be
/// blocked again), every first plan and every replan exact.
#[test]
fn a_kept_planner_stays_exact_across_runs_and_shapes() {
    let mut rng = ChaCha8Rng::seed_from_u64(31);
    for name in ["lpastar", "dstar_lite"] {
        for eight in [false, true] {
            let mut planner = planners::by_name(name, eight).unwrap();
            let mut oracle = Oracle::new(eight);
            let mut checked = 0;
            for round in 0..400u64 {
                let (w, h) = match round % 4 {
                    0 => (3, 5),
                    1 => (5, 3),
                    _ => (7, 6),
                };
                let density = rng.gen_range(0.0..0.4);
                let free: Vec<bool> = (0..w * h).map(|_| !rng.gen_bool(density)).collect();
                let grid = Grid::from_free_cells(w, h, free).unwrap();
                let cells: Vec<Cell> = grid.cells().filter(|&c| grid.is_free(c)).collect();
                if cells.is_empty() {
                    continue;
                }
                let start = cells[rng.gen_range(0..cells.len())];
                let goal = cells[rng.gen_range(0..cells.len())];
                let problem = Problem::new(&grid, start, goal).unwrap();
                let config = toggles::ToggleConfig {
                    events: 4,
                    k: 2,
                    radius: 2,
                    drive: 1,
                    seed: round,
                };
                let run = toggles::run(
                    planner.as_mut(),
                    &mut oracle,
                    &problem,
                    &config,
                    &Budget::unlimited(),
                );
                assert!(
                    run.mismatches.is_empty(),
                    "{name} eight={eight} round {round}: {}",
                    run.mismatches[0]
                );
                checked += run.replans.len();
                // The run changed the planner's map; a reset brings back exactly `grid`.
                planner.reset(&problem);
                assert_eq!(planner.grid(), Some(&grid));
            }
            assert!(checked > 1_000, "{checked}");
        }
    }
}

/// One random operation on an incremental planner: a batch of changes (cells outside the
/// map, weights of 0 or on an unweighted map, the start's and the goal's cells among
/// them), a move of the start (anywhere, blocked or outside included), a replan cut short
/// by a budget of a few expansions, or a full replan.
fn random_operation(rng: &mut ChaCha8Rng, (w, h): (u32, u32), weighted: bool) -> Operation {
    let cell = |rng: &mut ChaCha8Rng| Cell::new(rng.gen_range(0..=w), rng.gen_range(0..=h));
    match rng.gen_range(0..4) {
        0 => Operation::Apply(
            (0..rng.gen_range(0..6))
                .map(|_| {
                    let c = cell(rng);
                    let change = match rng.gen_bool(0.5) {
                        true => CellChange::blocked(c),
                        false => CellChange::freed(c),
                    };
                    match (weighted, rng.gen_range(0..10)) {
                        (true, 0..=4) => {
                            change.with_weight([1, 2, u16::MAX, 0][rng.gen_range(0..4)])
                        }
                        (false, 0) => change.with_weight(3),
                        _ => change,
                    }
                })
                .collect(),
        ),
        1 => Operation::MoveStart(cell(rng)),
        2 => Operation::Cut(rng.gen_range(0..5)),
        _ => Operation::Replan,
    }
}

#[derive(Debug)]
enum Operation {
    Apply(Vec<CellChange>),
    MoveStart(Cell),
    Cut(u64),
    Replan,
}

/// Random sequences of operations, invalid ones among them, on every replanning planner:
/// a refused batch or move changes nothing (the planner's map stays the model's), a replan
/// cut short leaves the next full one exact, and every full replan's cost is A*'s from
/// scratch on the model (no path when the start or goal is blocked), on 1-9 x 1-9 maps,
/// weighted ones with weights up to 65535 under both rules.
#[test]
fn random_operation_sequences_keep_every_replan_exact() {
    let mut rng = ChaCha8Rng::seed_from_u64(99);
    let mut compared = 0u64;
    for round in 0..3_000u64 {
        let (w, h) = (rng.gen_range(1..=9u32), rng.gen_range(1..=9u32));
        let free: Vec<bool> = (0..w * h).map(|_| rng.gen_bool(0.75)).collect();
        let mut grid = Grid::from_free_cells(w, h, free).unwrap();
        let weighted = round % 2 == 1;
        if weighted {
            let weights = (0..w * h)
                .map(|_| match rng.gen_bool(0.2) {
                    true => u16::MAX,
                    false => rng.gen_range(1..=300),
                })
                .collect();
            let rule = [CostRule::Mean, CostRule::Entered][(round / 2 % 2) as usize];
            grid = grid.with_weights(weights, rule).unwrap();
        }
        let start = Cell::new(rng.gen_range(0..w), rng.gen_range(0..h));
        let goal = Cell::new(rng.gen_range(0..w), rng.gen_range(0..h));
        grid.set_free(start, true);
        grid.set_free(goal, true);
        let eight = rng.gen_bool(0.5);
        for name in planners::names() {
            if weighted && name == "astar_backward" {
                continue; // Exact under the mean rule only (`restart` docs).
            }
            let what = format!("round {round}, {name}, eight = {eight}");
            let mut planner = planners::by_name(name, eight).unwrap();
            let mut oracle = Oracle::new(eight);
            planner.reset(&Problem::new(&grid, start, goal).unwrap());
            let (mut model, mut at) = (grid.clone(), start);
            for _ in 0..12 {
                match random_operation(&mut rng, (w, h), weighted) {
                    Operation::Apply(changes) => {
                        if planner.apply(&changes).is_ok() {
                            for change in &changes {
                                model.set_free(change.cell, change.free);
                                if let Some(weight) = change.weight {
                                    model.set_weight(change.cell, weight);
                                }
                            }
                        }
                    }
                    Operation::MoveStart(cell) => {
                        if planner.move_start(cell).is_ok() {
                            at = cell;
                        }
                    }
                    Operation::Cut(n) => {
                        planner.replan(&Budget::expansions(n));
                    }
                    Operation::Replan => {
                        let outcome = planner.replan(&Budget::unlimited());
                        assert!(planner.grid() == Some(&model), "{what}: maps differ");
                        let optimum = match model.is_free(at) && model.is_free(goal) {
                            true => oracle.optimum(&model, at, goal),
                            false => None,
                        };
                        let cost = outcome.path.as_ref().map(|p| model.path_cost(p.cells()));
                        assert_eq!(cost, optimum, "{what}: {:?}", outcome.status);
                        if optimum.is_none() {
                            assert_eq!(outcome.status, Status::NoPath, "{what}");
                        }
                        compared += 1;
                    }
                }
            }
        }
    }
    assert!(compared > 20_000, "{compared} replans compared");
}

/// The restart baseline builds A*'s per-grid tables when it is reset and when a change is
/// applied, before any replan's own memory check: within the session's memory limit
/// only, else not at all (the replan then refuses by A*'s check).
#[test]
fn the_restart_baseline_builds_its_tables_within_the_sessions_memory_limit() {
    // 2048 x 2048 free cells: A*'s state is about 13 bytes a cell, far over 1 MiB.
    let grid = Grid::from_free_cells(2048, 2048, vec![true; 2048 * 2048]).unwrap();
    let problem = Problem::new(&grid, Cell::new(0, 0), Cell::new(2047, 2047)).unwrap();
    let tight = Budget {
        max_memory_mb: Some(1),
        ..Budget::unlimited()
    };
    let mut restart = planner_replan::restart::Restart::new(true, false);
    restart.reset_within(&problem, &tight);
    assert_eq!(restart.table_bytes(), 0);
    restart
        .apply(&[CellChange::blocked(Cell::new(5, 5))])
        .unwrap();
    assert_eq!(restart.table_bytes(), 0);
    let outcome = restart.replan(&tight);
    assert_eq!(outcome.status, Status::BudgetExhausted);
    assert!(outcome.memory.is_some());
    assert_eq!(restart.table_bytes(), 0);
    // Without a limit the tables are built at the reset, and the replan finds the path.
    let mut restart = planner_replan::restart::Restart::new(true, false);
    restart.reset_within(&problem, &Budget::unlimited());
    assert!(restart.table_bytes() >= 2048 * 2048 / 8);
    assert_eq!(restart.replan(&Budget::unlimited()).status, Status::Found);
}
