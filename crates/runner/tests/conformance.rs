//! Every registered planner against the contract of `planner_api::Planner` (and
//! `CoveragePlanner`), on seeded random grids: no panic; the expansion budget honoured
//! (the search stops within it and says so); every returned path valid under the rule the
//! planner declares in its specs, from the start (to the goal); a reused planner gives the
//! outcome of a fresh one, also after the grid was edited in place; two runs give the same
//! counters; a `found` run has a path, and `no_path` is never said where a 4-connected
//! path exists. Every declared parameter at
//! the edges of its type is refused by key or keeps the same contract. What a planner
//! declares in its specs holds: an admissible one finds the oracle's optimum (a weighted one
//! on weighted grids too), a seeded one depends on its seed. Recording the expanded cells
//! changes nothing else, and lists one free cell per expansion. A planner gets this by
//! being registered.

use planner_api::{Budget, Cell, CoverageProblem, Grid, Problem, Status};
use planner_registry::Built;
use planner_registry::PLANNERS;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// The expansion budget of every run: enough for these grids, small enough that
/// exhaustive planners stay quick.
const BUDGET: u64 = 20_000;

/// Seeded random problems: several sizes and obstacle densities, start and goal made free
/// (possibly equal, often disconnected); first the degenerate shapes of [`degenerate`].
fn problems() -> Vec<(Grid, Cell, Cell)> {
    let mut rng = ChaCha8Rng::seed_from_u64(2026);
    let mut out = degenerate();
    for (w, h) in [(5, 5), (12, 9), (30, 20)] {
        for density in [0.0, 0.15, 0.3, 0.45] {
            for _ in 0..25 {
                let free: Vec<bool> = (0..w * h).map(|_| !rng.gen_bool(density)).collect();
                let mut grid = Grid::from_free_cells(w, h, free).unwrap();
                let start = Cell::new(rng.gen_range(0..w), rng.gen_range(0..h));
                let goal = Cell::new(rng.gen_range(0..w), rng.gen_range(0..h));
                grid.set_free(start, true);
                grid.set_free(goal, true);
                out.push((grid, start, goal));
            }
        }
    }
    out
}

/// Shapes at the edges of what a grid can be: one cell, one row, one column, a diagonal
/// that only corner cutting crosses, start and goal walled apart, start equal to goal.
fn degenerate() -> Vec<(Grid, Cell, Cell)> {
    let ascii = |text: &str| Grid::from_ascii(text).unwrap();
    let open = |w, h| Grid::from_free_cells(w, h, vec![true; (w * h) as usize]).unwrap();
    vec![
        (open(1, 1), Cell::new(0, 0), Cell::new(0, 0)),
        (open(9, 1), Cell::new(0, 0), Cell::new(8, 0)),
        (open(9, 1), Cell::new(8, 0), Cell::new(3, 0)),
        (open(1, 9), Cell::new(0, 0), Cell::new(0, 8)),
        (ascii(".#\n#."), Cell::new(0, 0), Cell::new(1, 1)),
        (
            ascii("..#..\n..#..\n..#.."),
            Cell::new(0, 1),
            Cell::new(4, 1),
        ),
        (ascii(".#.\n###\n.#."), Cell::new(0, 0), Cell::new(2, 2)),
        (open(6, 4), Cell::new(2, 3), Cell::new(2, 3)),
    ]
}

/// One run's observable result.
#[derive(Debug, Clone, PartialEq)]
struct Seen {
    status: Status,
    cells: Option<Vec<Cell>>,
    counters: planner_api::Counters,
}

fn run(
    built: &mut Built,
    grid: &Grid,
    start: Cell,
    goal: Cell,
    seed: Option<u64>,
    budget: &Budget,
) -> Seen {
    match built {
        Built::Path(p) => {
            if let Some(seed) = seed {
                p.reseed(seed);
            }
            p.prepare(grid);
            let problem = Problem::new(grid, start, goal).unwrap();
            let o = p.plan(&problem, budget);
            Seen {
                status: o.status,
                cells: o.path.map(|p| p.cells().to_vec()),
                counters: o.counters,
            }
        }
        Built::Coverage(c) => {
            let problem = CoverageProblem::new(grid, start).unwrap();
            let o = c.cover(&problem, budget);
            Seen {
                status: o.status,
                cells: Some(o.path.cells().to_vec()),
                counters: o.counters,
            }
        }
    }
}

/// Fails, saying which: a reused planner's outcome (`reused`) differed from a fresh one's
/// (`fresh`); when a second fresh planner (`other`) differs from the first too, the planner
/// is not a function of its inputs and seed at all, else it keeps state between runs.
fn same_or_explained(what: &str, (reused, fresh, other): (&Seen, &Seen, &Seen)) {
    assert_eq!(
        fresh, other,
        "{what}: two fresh planners with the same seed differ (nondeterministic)"
    );
    assert_eq!(
        reused, fresh,
        "{what}: a reused planner differs from a fresh one (state kept between runs)"
    );
}

#[test]
fn every_registered_planner_keeps_the_contract() {
    let problems = problems();
    let budget = Budget::expansions(BUDGET);
    let mut n_checked = 0;
    for entry in PLANNERS {
        for (v, factory) in entry
            .variants()
            .expect("defaults must be valid")
            .into_iter()
            .enumerate()
        {
            let specs = factory.specs().clone();
            // Declared incremental exactly when registered so (the replanning experiments
            // trust the registry, the runner and reports the specs).
            assert_eq!(
                specs.incremental,
                factory.is_incremental(),
                "{} (variant {v}): specs and registry disagree on incremental",
                entry.name
            );
            let rule = specs.path_rule.clone();
            let coverage = matches!(factory.task(), planner_runner::Task::Coverage);
            let mut reused = factory.build().unwrap();
            for (i, (grid, start, goal)) in problems.iter().enumerate() {
                let what = format!("{} (variant {v}) problem {i}", entry.name);
                let seed = factory.seed_for(7, i as u32);
                let first = run(&mut reused, grid, *start, *goal, seed, &budget);
                let mut fresh = factory.build().unwrap();
                let again = run(&mut fresh, grid, *start, *goal, seed, &budget);
                if first != again {
                    let mut other = factory.build().unwrap();
                    let third = run(&mut other, grid, *start, *goal, seed, &budget);
                    same_or_explained(&what, (&first, &again, &third));
                }
                let twice = run(&mut fresh, grid, *start, *goal, seed, &budget);
                assert_eq!(again, twice, "{what}: two runs differ");

                if let Some(expanded) = first.counters.get("n_expanded") {
                    assert!(
                        expanded <= BUDGET,
                        "{what}: {expanded} expansions over the budget"
                    );
                    if expanded >= 2 {
                        let cut = Budget::expansions(expanded / 2);
                        let short = run(&mut reused, grid, *start, *goal, seed, &cut);
                        let n = short.counters.get("n_expanded").unwrap_or(0);
                        assert!(
                            n <= expanded / 2,
                            "{what}: {n} expansions over a budget of {}",
                            expanded / 2
                        );
                        if short.status != Status::BudgetExhausted {
                            // Stopping early without saying so is allowed only with a
                            // complete answer that needed no more work.
                            assert_eq!(short, first, "{what}: cut short without saying so");
                        }
                    }
                }

                check_path(&what, &first, grid, (*start, *goal), coverage, &rule);
                // `no_path` says the search proved there is none: not where a 4-connected
                // path (one every declared rule admits) exists.
                if first.status == Status::NoPath && !coverage {
                    let four = planner_api::MoveSet::standard(planner_api::Connectivity::Four);
                    let unweighted = Grid::from_free_cells(
                        grid.width(),
                        grid.height(),
                        grid.free_cells().to_vec(),
                    )
                    .unwrap();
                    assert!(
                        planner_testkit::weighted_dijkstra(&unweighted, &four, *start, *goal)
                            .is_none(),
                        "{what}: no_path, yet a 4-connected path exists"
                    );
                }
                n_checked += 1;
            }
        }
    }
    assert!(n_checked >= PLANNERS.len() * problems.len());
}

/// A planner reused on a grid edited in place between plans ([`Grid::set_free`], and
/// [`Grid::set_weight`] on weighted grids for the planners that honour weights) gives the
/// outcome a fresh planner gives on the edited grid: caches of per-grid tables brought up
/// to date from [`Grid::changed_since`] hold what a rebuild holds.
#[test]
fn a_planner_reused_on_an_edited_grid_gives_a_fresh_ones_outcome() {
    let mut rng = ChaCha8Rng::seed_from_u64(31);
    let budget = Budget::expansions(BUDGET);
    let bases: Vec<(Grid, Cell, Cell)> = problems()
        .into_iter()
        .filter(|(grid, ..)| grid.len() >= 100)
        .step_by(3)
        .collect();
    let weighted: Vec<(Grid, Cell, Cell)> = bases
        .iter()
        .step_by(2)
        .map(|(grid, start, goal)| {
            let weights = (0..grid.len()).map(|_| rng.gen_range(1..=9)).collect();
            let rule = planner_api::CostRule::Mean;
            (
                grid.clone().with_weights(weights, rule).unwrap(),
                *start,
                *goal,
            )
        })
        .collect();
    let mut n_checked = 0;
    for entry in PLANNERS {
        for (v, factory) in entry
            .variants()
            .expect("defaults must be valid")
            .into_iter()
            .enumerate()
        {
            let costs = factory.specs().cell_costs;
            let mut reused = factory.build().unwrap();
            let sets: &[&[(Grid, Cell, Cell)]] = if costs {
                &[&bases, &weighted]
            } else {
                &[&bases]
            };
            for (i, (base, start, goal)) in sets.iter().flat_map(|set| set.iter()).enumerate() {
                let mut grid = base.clone();
                for step in 0..4 {
                    let what = format!("{} (variant {v}) problem {i} step {step}", entry.name);
                    let seed = factory.seed_for(7, i as u32);
                    let first = run(&mut reused, &grid, *start, *goal, seed, &budget);
                    let mut fresh = factory.build().unwrap();
                    let again = run(&mut fresh, &grid, *start, *goal, seed, &budget);
                    if first != again {
                        let mut other = factory.build().unwrap();
                        let third = run(&mut other, &grid, *start, *goal, seed, &budget);
                        same_or_explained(&what, (&first, &again, &third));
                    }
                    n_checked += 1;
                    for _ in 0..rng.gen_range(1..=4) {
                        let cell = Cell::new(
                            rng.gen_range(0..grid.width()),
                            rng.gen_range(0..grid.height()),
                        );
                        if cell != *start && cell != *goal {
                            grid.set_free(cell, rng.gen_bool(0.5));
                        }
                        grid.set_weight(cell, rng.gen_range(1..=9));
                    }
                }
            }
        }
    }
    assert!(n_checked >= PLANNERS.len() * 4 * 40, "{n_checked} checks");
}

/// A run's path, if any, leaves the start, reaches the goal when found (not for coverage),
/// and keeps the rule its planner declares; a run that says found has a path.
fn check_path(
    what: &str,
    seen: &Seen,
    grid: &Grid,
    (start, goal): (Cell, Cell),
    coverage: bool,
    rule: &planner_api::PathSpec,
) {
    if seen.status == Status::Found {
        assert!(seen.cells.is_some(), "{what}: found, yet no path");
    }
    if let Some(cells) = &seen.cells {
        let path = planner_api::Path::new(cells.clone());
        assert_eq!(
            path.start(),
            Some(start),
            "{what}: path does not leave the start"
        );
        if !coverage && seen.status == Status::Found {
            assert_eq!(path.goal(), Some(goal), "{what}: path misses the goal");
        }
        if let Err(e) = path.validate(grid, rule.rule()) {
            panic!("{what}: the path breaks the declared rule: {e}");
        }
    }
}

/// A grid of `w` x `h` with a seeded third of its cells blocked and the goal walled in, so
/// that no planner finds a path and exhaustive ones search every reachable cell.
fn walled_in(w: u32, h: u32) -> (Grid, Cell, Cell) {
    let mut rng = ChaCha8Rng::seed_from_u64(28);
    let free: Vec<bool> = (0..w * h).map(|_| !rng.gen_bool(0.3)).collect();
    let mut grid = Grid::from_free_cells(w, h, free).unwrap();
    let (start, goal) = (Cell::new(0, 0), Cell::new(w - 2, h - 2));
    for y in h - 3..h {
        for x in w - 3..w {
            grid.set_free(Cell::new(x, y), false);
        }
    }
    grid.set_free(start, true);
    grid.set_free(goal, true);
    (grid, start, goal)
}

/// A raised [`planner_api::CancelFlag`] stops every planner at its first periodic budget
/// check (every `BudgetClock::TIME_CHECK_INTERVAL` expansions): the outcome is
/// `budget_exhausted`, unless the search ended before its first check, when it is the
/// uncancelled run's. Searches that do more work than one interval must be cut.
#[test]
fn every_registered_planner_stops_when_cancelled() {
    let (grid, start, goal) = walled_in(120, 120);
    let flag = planner_api::CancelFlag::new();
    flag.cancel();
    let budget = Budget::expansions(BUDGET);
    let cancelled = budget.with_cancel(flag);
    let interval = u64::from(planner_api::BudgetClock::TIME_CHECK_INTERVAL);
    let mut n_cut = 0;
    for entry in PLANNERS {
        let factory = (entry.factory)(&toml::Table::new()).unwrap();
        let seed = factory.seed_for(7, 0);
        let mut planner = factory.build().unwrap();
        let whole = run(&mut planner, &grid, start, goal, seed, &budget);
        let cut = run(&mut planner, &grid, start, goal, seed, &cancelled);
        if cut.status == Status::BudgetExhausted && cut != whole {
            n_cut += 1;
            if let (Some(n), Some(all)) = (
                cut.counters.get("n_expanded"),
                whole.counters.get("n_expanded"),
            ) {
                // Work a planner does not count as expansions (CAPSO's guide route before
                // its swarm) is cut too: then another counter shows it.
                let other_work_cut = n == 0
                    && cut
                        .counters
                        .iter()
                        .any(|(k, v)| whole.counters.get(k).is_some_and(|w| v < w));
                assert!(
                    n < all || other_work_cut,
                    "{}: {n} of {all} expansions after a cancel",
                    entry.name
                );
            }
        } else {
            assert_eq!(cut, whole, "{}: cancelled, yet not cut short", entry.name);
            let n = whole.counters.get("n_expanded").unwrap_or(0);
            assert!(
                n < interval,
                "{}: {n} expansions, yet the cancel was never read",
                entry.name
            );
        }
    }
    // Most planners search this grid far longer than one interval.
    assert!(
        n_cut * 2 > PLANNERS.len(),
        "{n_cut} of {} cut",
        PLANNERS.len()
    );
}

/// Values for a declared parameter of JSON type `kind` (as `planner_registry::schema`
/// names it): the edges a typo or a generated sweep can reach, beside ordinary ones.
fn extreme_values(kind: &str) -> Vec<toml::Value> {
    let mut out = Vec::new();
    if kind.contains("integer") {
        let ints = [
            0,
            1,
            -1,
            2,
            3,
            7,
            1000,
            1 << 20,
            1 << 40,
            i64::MAX,
            i64::MIN,
        ];
        out.extend(ints.map(toml::Value::Integer));
    }
    if kind.contains("number") {
        let floats = [
            0.0,
            -0.0,
            1.0,
            -1.0,
            0.5,
            1e-310,
            1e6,
            1e308,
            -1e308,
            f64::NAN,
            f64::INFINITY,
            f64::NEG_INFINITY,
        ];
        out.extend(floats.map(toml::Value::Float));
    }
    if kind.contains("string") {
        out.push(toml::Value::String(String::new()));
        out.push(toml::Value::String("x".repeat(300)));
    }
    if kind.contains("boolean") {
        out.extend([true, false].map(toml::Value::Boolean));
    }
    out
}

/// Every declared parameter of every planner, alone at each of [`extreme_values`] and at
/// each value it allows: the planner refuses it with an error naming that key (as its key,
/// or in its message when the value breaks a bound set by another key), or builds
/// and keeps the contract (no panic, the expansion budget, valid paths) on every 20th of
/// [`problems`]. Parameters are validated where they are read, whatever a config says.
#[test]
fn every_declared_parameter_at_its_extremes_is_refused_by_key_or_kept_in_bounds() {
    let problems: Vec<_> = problems().into_iter().step_by(20).collect();
    let budget = Budget::expansions(BUDGET);
    let (mut n_refused, mut n_run) = (0, 0);
    for entry in PLANNERS {
        let declared = planner_registry::schema::declared(entry.name).unwrap();
        assert!(
            !declared.is_empty(),
            "{}: no declared parameter",
            entry.name
        );
        for param in &declared {
            let mut values = extreme_values(&param.kind);
            values.extend(
                param
                    .allowed
                    .iter()
                    .filter_map(|v| toml::Value::try_from(v.clone()).ok()),
            );
            for value in values {
                let what = format!("{} with {} = {value}", entry.name, param.key);
                let table = toml::Table::from_iter([(param.key.clone(), value)]);
                let factory = match (entry.factory)(&table).and_then(|f| f.build().map(|_| f)) {
                    Ok(factory) => factory,
                    Err(e) => {
                        // A bound between two keys may be reported under the other one
                        // (a declared key); its message then names both.
                        let names = |key: &str| e.message.contains(key);
                        assert!(
                            e.key == param.key
                                || (declared.iter().any(|p| p.key == e.key)
                                    && names(&e.key)
                                    && names(&param.key)),
                            "{what}: refused under key `{}` without naming both keys: {e}",
                            e.key
                        );
                        n_refused += 1;
                        continue;
                    }
                };
                let rule = factory.specs().path_rule.clone();
                let coverage = matches!(factory.task(), planner_runner::Task::Coverage);
                for (i, (grid, start, goal)) in problems.iter().enumerate() {
                    let what = format!("{what}, problem {i}");
                    let seed = factory.seed_for(7, i as u32);
                    let seen = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
                        let mut built = factory.build().unwrap();
                        run(&mut built, grid, *start, *goal, seed, &budget)
                    }))
                    .unwrap_or_else(|_| panic!("{what}: the planner panicked"));
                    let expanded = seen.counters.get("n_expanded").unwrap_or(0);
                    assert!(expanded <= BUDGET, "{what}: {expanded} expansions");
                    check_path(&what, &seen, grid, (*start, *goal), coverage, &rule);
                    n_run += 1;
                }
            }
        }
    }
    // Both outcomes occur: the values reach past what planners accept, and not only that.
    assert!(
        n_refused > 100 && n_run > 1000,
        "{n_refused} refused, {n_run} runs"
    );
}

/// The grids of [`every_admissible_or_cost_honouring_planner_matches_the_oracle`]: the
/// unweighted [`problems`], then the test kit's random weighted ones (weights 1-255, both
/// cost rules), each also with every weight at the type's top (65535) or every third one
/// at it and the rest 1, where a move costs about 2^48 units and overflow would show.
fn oracle_problems() -> Vec<(Grid, Cell, Cell)> {
    let mut out = problems();
    for (k, p) in planner_testkit::random_weighted_problems(0xc057, 200)
        .into_iter()
        .enumerate()
    {
        let rule = p.grid.weights().map(|w| w.rule()).unwrap_or_default();
        let extreme: Vec<u16> = (0..p.grid.len())
            .map(|i| {
                if k % 2 == 0 || i % 3 == 0 {
                    u16::MAX
                } else {
                    1
                }
            })
            .collect();
        let mut heavy = Grid::from_free_cells(
            p.grid.width(),
            p.grid.height(),
            p.grid.free_cells().to_vec(),
        )
        .and_then(|g| g.with_weights(extreme, rule))
        .unwrap();
        heavy.set_free(p.start, true);
        heavy.set_free(p.goal, true);
        out.push((p.grid, p.start, p.goal));
        out.push((heavy, p.start, p.goal));
    }
    out
}

/// Every registered planner that declares itself admissible finds exactly the optimum of
/// the test kit's oracle (a plain Dijkstra over its moves), on weighted grids too when it
/// declares it honours cell weights, and reports no path exactly when there is none; every
/// weight-honouring planner's path keeps its declared rule on weighted grids. A planner
/// gets this by being registered.
#[test]
fn every_admissible_or_cost_honouring_planner_matches_the_oracle() {
    let problems = oracle_problems();
    let mut n_exact = 0;
    for entry in PLANNERS {
        for (v, factory) in entry
            .variants()
            .expect("defaults must be valid")
            .into_iter()
            .enumerate()
        {
            let specs = factory.specs().clone();
            let exact = specs.admissible == Some(true);
            if !(specs.cell_costs || exact)
                || matches!(factory.task(), planner_runner::Task::Coverage)
            {
                continue;
            }
            let moves = match &specs.path_rule {
                planner_api::PathSpec::Moves(moves) => moves.clone(),
                planner_api::PathSpec::AnyAngle => continue,
            };
            let Built::Path(mut planner) = factory.build().unwrap() else {
                continue;
            };
            for (i, (grid, start, goal)) in problems.iter().enumerate() {
                if grid.is_weighted() && !specs.cell_costs {
                    continue;
                }
                let what = format!("{} (variant {v}) problem {i}", entry.name);
                planner.prepare(grid);
                let problem = Problem::new(grid, *start, *goal).unwrap();
                let outcome = planner.plan(&problem, &Budget::unlimited());
                let oracle = planner_testkit::weighted_dijkstra(grid, &moves, *start, *goal);
                if let Some(path) = &outcome.path {
                    path.validate(grid, planner_api::PathRule::Moves(&moves))
                        .unwrap_or_else(|e| panic!("{what}: {e}"));
                    assert_eq!(path.start(), Some(*start), "{what}");
                }
                if exact {
                    let cost = outcome.path.as_ref().map(|p| grid.path_cost(p.cells()));
                    assert_eq!(cost, oracle, "{what}: not the oracle's cost");
                    assert_eq!(outcome.status == Status::NoPath, oracle.is_none(), "{what}");
                    n_exact += 1;
                }
            }
        }
    }
    // A* (its default heuristic is admissible on 4 moves only), bidirectional A*, LPA* and
    // D* Lite (4 and 8 moves each) on every grid, JPS on the unweighted ones, at least.
    assert!(n_exact >= 7 * problems.len(), "{n_exact} exact comparisons");
}

/// Costs beyond `Cost::MAX` (planner-api's weights docs, "The range"): a corridor of 66,000
/// cells of weight 65,535 costs 4.33e9. Every planner that honours weights reaches its
/// goal: a valid path, or (LPA*, D* Lite) an outcome that says its costs saturated; never
/// `no_path` (bidirectional A*, LPA* and D* Lite said so, their infinity being the
/// saturated sum).
#[test]
fn every_cost_honouring_planner_reaches_a_goal_beyond_the_cost_range() {
    let n = 66_000u32;
    let grid = Grid::new(n, 1)
        .unwrap()
        .with_weights(vec![65_535; n as usize], planner_api::CostRule::Mean)
        .unwrap();
    let (start, goal) = (Cell::new(0, 0), Cell::new(n - 1, 0));
    let true_cost = f64::from(n - 1) * 65_535.0;
    assert!(grid.path_cost(&[start, Cell::new(1, 0)]) < planner_api::Cost::MAX);
    assert!((grid.path_cost_f64(&[start, Cell::new(1, 0)]) - 65_535.0).abs() < 1e-6);
    let mut n_checked = 0;
    for entry in PLANNERS {
        let factory = (entry.factory)(&toml::Table::new()).expect("defaults must be valid");
        if !factory.specs().cell_costs {
            continue;
        }
        let Built::Path(mut planner) = factory.build().unwrap() else {
            continue;
        };
        let problem = Problem::new(&grid, start, goal).unwrap();
        let outcome = planner.plan(&problem, &Budget::unlimited());
        let what = entry.name;
        match (&outcome.path, outcome.status) {
            (Some(path), Status::Found) => {
                assert_eq!(
                    (path.start(), path.goal()),
                    (Some(start), Some(goal)),
                    "{what}"
                );
                assert_eq!(
                    grid.path_cost(path.cells()),
                    planner_api::Cost::MAX,
                    "{what}"
                );
                let cost = grid.path_cost_f64(path.cells());
                assert!((cost - true_cost).abs() < 1e-3, "{what}: {cost}");
                assert!(!outcome.cost_overflow, "{what}");
            }
            (None, Status::BudgetExhausted) => assert!(outcome.cost_overflow, "{what}"),
            other => panic!("{what}: {other:?}"),
        }
        n_checked += 1;
    }
    // A*, bidirectional A*, weighted JPS, lexastar, LPA*, D* Lite at least.
    assert!(n_checked >= 6, "{n_checked} planners");
}

/// A planner that declares itself seeded does depend on its seed: on some of the random
/// problems two seeds give different outcomes (a seed the planner ignored would make the
/// runner's repeats copies of one run).
#[test]
fn every_seeded_planner_depends_on_its_seed() {
    let problems = problems();
    let budget = Budget::expansions(BUDGET);
    let mut n_seeded = 0;
    for entry in PLANNERS {
        let factory = (entry.factory)(&toml::Table::new()).unwrap();
        if !factory.specs().seeded {
            assert_eq!(factory.seed_for(7, 0), None, "{}", entry.name);
            continue;
        }
        n_seeded += 1;
        // The runner sets a label's seed under one key: a seed parameter of another name
        // would be shown as resolved and never used.
        let declared = planner_registry::schema::declared(entry.name).unwrap();
        assert!(
            declared.iter().any(|p| p.key == planner_api::SEED_PARAM),
            "{}: seeded, but its config declares no `{}` parameter: the runner reads a \
             label's seed under that key (planner_api::SEED_PARAM) and reseeds the planner \
             with it; a seed parameter under another name is ignored",
            entry.name,
            planner_api::SEED_PARAM
        );
        let with_seed = |seed: i64| {
            let table =
                toml::Table::from_iter([(planner_api::SEED_PARAM.to_string(), seed.into())]);
            (entry.factory)(&table).unwrap().seed_for(7, 0)
        };
        assert_ne!(
            with_seed(5),
            with_seed(6),
            "{}: `seed` is not used",
            entry.name
        );
        let mut planner = factory.build().unwrap();
        let differ = problems
            .iter()
            .filter(|(grid, start, goal)| {
                let one = run(&mut planner, grid, *start, *goal, Some(1), &budget);
                let two = run(&mut planner, grid, *start, *goal, Some(2), &budget);
                one != two
            })
            .count();
        assert!(
            differ * 4 > problems.len(),
            "{}: seeds 1 and 2 differ on {differ} of {} problems",
            entry.name,
            problems.len()
        );
    }
    // rrt, rrt_star, rrt_connect and capso at least.
    assert!(n_seeded >= 4, "{n_seeded} seeded planners");
}

/// Recording the expanded cells ([`Budget::record_expanded`]) changes nothing else: the
/// status, path and counters are those of the same run without it (the runner draws a
/// sweep's expanded cells from such a second run, and refuses one that differs). A planner
/// that lists them lists one per `n_expanded`, each a free cell of the grid.
#[test]
fn recording_the_expanded_cells_changes_nothing_and_lists_one_per_expansion() {
    let problems = problems();
    let budget = Budget::expansions(BUDGET);
    let recording = budget.recording_expanded(true);
    let mut n_listing = 0;
    for entry in PLANNERS {
        for (v, factory) in entry
            .variants()
            .expect("defaults must be valid")
            .into_iter()
            .enumerate()
        {
            let Built::Path(mut planner) = factory.build().unwrap() else {
                continue;
            };
            let mut listed = false;
            for (i, (grid, start, goal)) in problems.iter().enumerate() {
                let what = format!("{} (variant {v}) problem {i}", entry.name);
                let seed = factory.seed_for(7, i as u32);
                let mut outcome = |budget: &Budget| {
                    if let Some(seed) = seed {
                        planner.reseed(seed);
                    }
                    planner.prepare(grid);
                    let problem = Problem::new(grid, *start, *goal).unwrap();
                    planner.plan(&problem, budget)
                };
                let plain = outcome(&budget);
                let recorded = outcome(&recording);
                assert!(
                    plain.expanded.is_empty(),
                    "{what}: listed without being asked"
                );
                assert_eq!(
                    (plain.status, &plain.path, &plain.counters),
                    (recorded.status, &recorded.path, &recorded.counters),
                    "{what}: recording changed the run"
                );
                if recorded.expanded.is_empty() {
                    continue;
                }
                listed = true;
                if let Some(n) = recorded.counters.get("n_expanded") {
                    assert_eq!(
                        recorded.expanded.len() as u64,
                        n,
                        "{what}: listed cells against n_expanded"
                    );
                }
                for cell in &recorded.expanded {
                    assert!(
                        cell.x < grid.width() && cell.y < grid.height() && grid.is_free(*cell),
                        "{what}: listed {cell}, not a free cell of the grid"
                    );
                }
            }
            n_listing += usize::from(listed);
        }
    }
    // A*, BFS, DFS, lexastar, bidirectional A* and JPS, each in both variants, at least.
    assert!(
        n_listing >= 12,
        "{n_listing} planner variants list their expanded cells"
    );
}
