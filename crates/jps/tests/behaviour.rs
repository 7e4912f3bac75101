//! Configuration errors, budgets, unreachable goals, marks and the grid cache.

use std::time::Duration;

use planner_api::{Budget, CancelFlag, Cell, Grid, Planner, Problem, Status};
use planner_jps::{Config, Jps, Variant};
use planner_testkit::outcome_text;

const VARIANTS: [Variant; 3] = [Variant::Jps, Variant::JpsPrime, Variant::JpsPlus];

fn jps(variant: Variant) -> Jps {
    Jps::new(Config {
        variant,
        ..Config::default()
    })
    .unwrap()
}

/// Builds a planner from TOML parameters as the registry does; `expect` is `ok` or the
/// error's text.
fn check(params: &str, expect: &str) {
    let table: toml::Table = params.parse().unwrap();
    let actual = Config::deserialize(toml::Value::Table(table))
        .map_err(|e| e.to_string())
        .and_then(|config| Jps::new(config).map_err(|e| e.to_string()))
        .map(|_| "ok".to_string())
        .unwrap_or_else(|e| e);
    assert!(
        actual.starts_with(expect),
        "{params}: got {actual:?}, expected {expect:?}"
    );
}

use serde::Deserialize;

#[test]
fn config_errors_name_the_key() {
    check("", "ok");
    check(r#"variant = "jps_prime""#, "ok");
    check(
        r#"variant = "jps_plus"
moves = 8
corner_cutting = false
marks = false"#,
        "ok",
    );
    check(
        "moves = 4",
        "parameter `moves`: JPS is defined here for 8-connected moves only, got 4",
    );
    check(
        "moves = 16",
        "parameter `moves`: JPS is defined here for 8-connected moves only, got 16",
    );
    check(
        "corner_cutting = true",
        "parameter `corner_cutting`: JPS is defined here without corner cutting",
    );
    check(r#"variant = "jps2""#, "unknown variant `jps2`");
    check("heuristic = \"octile\"", "unknown field `heuristic`");
}

#[test]
fn unreachable_goal_is_no_path() {
    let grid = Grid::from_ascii(
        "
        ...#..
        ...#..
        ..#...
        ",
    )
    .unwrap();
    // The wall is closed without corner cutting: (2, 2) and (3, 1) touch only at a corner.
    let problem = Problem::new(&grid, Cell::new(0, 0), Cell::new(5, 2)).unwrap();
    for variant in VARIANTS {
        let outcome = jps(variant).plan(&problem, &Budget::unlimited());
        assert_eq!(outcome.status, Status::NoPath, "{variant:?}");
        assert!(outcome.path.is_none() && outcome.marks.is_empty());
    }
    // The start expands its eight directions: east and south end at walls after 2 cells
    // each, five others fail at once; south-east steps to (1, 1) (1 cell), whose east and
    // south jumps end at walls after 1 cell each, and its next step would enter the
    // blocked (2, 2): 7 cells, and nothing enters OPEN but the start.
    let outcome = jps(Variant::Jps).plan(&problem, &Budget::unlimited());
    assert_eq!(
        outcome_text(&outcome),
        "status no_path\npath -\nn_expanded=1 n_scanned=7 n_open_insertions=1 n_relaxations=0 peak_open=1"
    );
}

#[test]
fn start_equal_to_goal() {
    let grid = Grid::from_ascii("..\n..").unwrap();
    let problem = Problem::new(&grid, Cell::new(1, 1), Cell::new(1, 1)).unwrap();
    for variant in VARIANTS {
        let outcome = jps(variant).plan(&problem, &Budget::unlimited());
        assert_eq!(outcome.status, Status::Found);
        assert_eq!(outcome.path.unwrap().cells(), [Cell::new(1, 1)]);
        assert_eq!(outcome.counters.get("n_expanded"), Some(1));
    }
}

#[test]
fn budget_is_honoured() {
    let grid = planner_testkit::movingai("movingai/den520d.map");
    let scenarios = planner_testkit::scenarios("movingai/den520d.map.scen");
    let s = scenarios.last().unwrap();
    let problem = Problem::new(&grid, s.start, s.goal).unwrap();
    for variant in VARIANTS {
        let mut planner = jps(variant);
        let full = planner.plan(&problem, &Budget::unlimited());
        assert_eq!(full.status, Status::Found);
        let n = full.counters.get("n_expanded").unwrap();
        assert!(n > 10, "{variant:?}: {n}");
        for cut in [0, 1, n / 2, n - 1] {
            let outcome = planner.plan(&problem, &Budget::expansions(cut));
            assert_eq!(outcome.status, Status::BudgetExhausted, "{variant:?} {cut}");
            assert_eq!(outcome.counters.get("n_expanded"), Some(cut));
            assert!(outcome.path.is_none());
        }
        let exact = planner.plan(&problem, &Budget::expansions(n));
        assert_eq!(exact, full, "{variant:?}: a budget of exactly n suffices");
    }
}

/// Goal bounding's build stops when the query's budget is cancelled (or out of time): the
/// query ends `budget_exhausted` with zero counters and keeps no boxes, and the next query
/// with a budget that allows it builds them and finds the path.
#[test]
fn goal_bounding_build_honours_the_budget() {
    let grid = Grid::from_ascii(
        "
        ..........
        .####.###.
        .#......#.
        .#.####.#.
        ..........
    ",
    )
    .unwrap();
    let problem = Problem::new(&grid, Cell::new(0, 0), Cell::new(9, 4)).unwrap();
    for variant in VARIANTS {
        let mut planner = Jps::new(Config {
            variant,
            goal_bounding: true,
            ..Config::default()
        })
        .unwrap();
        let flag = CancelFlag::new();
        flag.cancel();
        let stopped = planner.plan(&problem, &Budget::unlimited().with_cancel(flag));
        assert_eq!(stopped.status, Status::BudgetExhausted, "{variant:?}");
        assert_eq!(stopped.counters.get("n_expanded"), Some(0), "{variant:?}");
        let timed_out = planner.plan(&problem, &Budget::unlimited().with_time(Duration::ZERO));
        assert_eq!(timed_out.status, Status::BudgetExhausted, "{variant:?}");
        let found = planner.plan(&problem, &Budget::unlimited());
        assert_eq!(found.status, Status::Found, "{variant:?}");
        let plain = jps(variant).plan(&problem, &Budget::unlimited());
        let length = |o: &planner_api::Outcome| o.path.as_ref().map(|p| p.metrics().length);
        assert_eq!(length(&found), length(&plain), "{variant:?}");
    }
}

/// Whether a goal-bounded search fits a memory budget does not depend on the machine:
/// the need it declares, and its outcomes under budgets just below and at it, are the
/// same in a pool of 1 thread and of 6.
#[test]
fn goal_bounding_memory_need_is_the_same_for_any_pool() {
    let grid = planner_testkit::movingai("movingai/arena.map");
    let (start, goal) = planner_testkit::first_scenario("movingai/arena.map.scen");
    let problem = Problem::new(&grid, start, goal).unwrap();
    let config = Config {
        goal_bounding: true,
        ..Config::default()
    };
    let in_pool = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        pool.install(|| {
            let planner = Jps::new(config.clone()).unwrap();
            let need = planner.memory_bytes_for(&grid);
            // A budget of whole MiB below the need refuses; one that holds it runs.
            let mb = need.div_ceil(1 << 20);
            let below = Budget::unlimited().with_memory_mb(mb - 1);
            let refused = Jps::new(config.clone()).unwrap().plan(&problem, &below);
            let enough = Budget::unlimited().with_memory_mb(mb);
            let found = Jps::new(config.clone()).unwrap().plan(&problem, &enough);
            (need, outcome_text(&refused), outcome_text(&found))
        })
    };
    let (one, six) = (in_pool(1), in_pool(6));
    assert_eq!(one, six);
    assert!(one.1.contains("budget_exhausted"), "{}", one.1);
    assert!(one.2.contains("found"), "{}", one.2);
}

#[test]
fn marks_are_the_path_jump_points_and_optional() {
    let grid = planner_testkit::movingai("movingai/arena.map");
    let (start, goal) = planner_testkit::first_scenario("movingai/arena.map.scen");
    let scenarios = planner_testkit::scenarios("movingai/arena.map.scen");
    let s = scenarios.last().unwrap();
    for (start, goal) in [(start, goal), (s.start, s.goal)] {
        let problem = Problem::new(&grid, start, goal).unwrap();
        for variant in VARIANTS {
            let outcome = jps(variant).plan(&problem, &Budget::unlimited());
            let cells = outcome.path.as_ref().unwrap().cells();
            let mut at = 0;
            for (i, mark) in outcome.marks.iter().enumerate() {
                assert_eq!(mark.label, format!("J{}", i + 1));
                // Marks lie on the path, in order, strictly between start and goal.
                let found = cells[at + 1..cells.len() - 1]
                    .iter()
                    .position(|&c| c == mark.cell);
                at += 1 + found.unwrap_or_else(|| panic!("{variant:?}: {mark:?} off the path"));
            }
            let plain = Jps::new(Config {
                variant,
                marks: false,
                ..Config::default()
            })
            .unwrap()
            .plan(&problem, &Budget::unlimited());
            assert!(plain.marks.is_empty());
            assert_eq!(
                (plain.path, plain.counters),
                (outcome.path, outcome.counters)
            );
        }
    }
}

#[test]
fn an_edited_grid_is_planned_afresh() {
    let mut grid = Grid::from_ascii(
        "
        .....
        .....
        .....
        ",
    )
    .unwrap();
    for variant in VARIANTS {
        let mut planner = jps(variant);
        let length = |planner: &mut Jps, grid: &Grid| {
            let problem = Problem::new(grid, Cell::new(0, 1), Cell::new(4, 1)).unwrap();
            let outcome = planner.plan(&problem, &Budget::unlimited());
            outcome.path.map(|p| p.metrics().length)
        };
        let mut edited = grid.clone();
        assert_eq!(length(&mut planner, &edited), Some(4.0));
        edited.set_free(Cell::new(2, 1), false);
        let detour = 2.0 + 2.0 * 2f64.sqrt();
        assert!((length(&mut planner, &edited).unwrap() - detour).abs() < 1e-12);
        edited.set_free(Cell::new(2, 0), false);
        edited.set_free(Cell::new(2, 2), false);
        assert_eq!(length(&mut planner, &edited), None);
        // An equal grid with another revision reuses the cache and gets the same answer.
        grid.set_free(Cell::new(2, 1), true);
        assert_eq!(length(&mut planner, &grid), Some(4.0));
    }
}

#[test]
fn jumps_longer_than_the_table_entries_agree() {
    // A 70,000-cell corridor with a few pillars: JPS+'s 16-bit entries must chain far
    // entries (more than 32,766 cells) to give the online variants' answers.
    let (w, h) = (70_000u32, 3u32);
    let mut free = vec![true; (w * h) as usize];
    for x in [5u32, 40_000, 69_990] {
        free[(w + x) as usize] = false; // Pillars in the middle row.
    }
    let grid = Grid::from_free_cells(w, h, free).unwrap();
    for (start, goal) in [
        (Cell::new(0, 1), Cell::new(69_999, 1)),
        (Cell::new(69_999, 0), Cell::new(0, 2)),
        (Cell::new(3, 0), Cell::new(50_000, 2)),
        (Cell::new(2, 2), Cell::new(36_000, 2)),
    ] {
        let problem = Problem::new(&grid, start, goal).unwrap();
        let lengths: Vec<f64> = VARIANTS
            .iter()
            .map(|&v| {
                let outcome = jps(v).plan(&problem, &Budget::unlimited());
                assert_eq!(outcome.status, Status::Found, "{v:?} {start} -> {goal}");
                outcome.path.unwrap().metrics().length
            })
            .collect();
        let (dx, dy) = (start.x.abs_diff(goal.x), start.y.abs_diff(goal.y));
        assert!(lengths[0] >= start.octile(goal) - 1e-9 && lengths[0] <= f64::from(dx + dy) + 4.0);
        assert!(
            (lengths[1] - lengths[0]).abs() < 1e-6 && (lengths[2] - lengths[0]).abs() < 1e-6,
            "{start} -> {goal}: {lengths:?}"
        );
    }
}
