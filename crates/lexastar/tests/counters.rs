//! Lexicographic A*'s counters, paths, budgets and config on hand-checked grids.

use planner_api::{Budget, Cell, Connectivity, Grid, Planner, Problem, Status};
use planner_lexastar::{Config, ConfigError, LexAStar, Objective};

/// Runs lexastar (with dominance pruning when `dominance`) from `start` to `goal` on `map`
/// within `budget` and compares the status, the path and the counters with `expect`, one
/// line per item.
fn check(
    map: &str,
    start: (u32, u32),
    goal: (u32, u32),
    dominance: bool,
    budget: Budget,
    expect: &str,
) {
    let grid = Grid::from_ascii(map).unwrap();
    let problem = Problem::new(&grid, start.into(), goal.into()).unwrap();
    let config = Config {
        dominance,
        ..Config::default()
    };
    let outcome = LexAStar::new(config).unwrap().plan(&problem, &budget);
    let actual = planner_testkit::outcome_text(&outcome);
    assert_eq!(actual.trim(), expect.trim(), "\n{actual}");
}

#[test]
fn corridor_by_hand() {
    // States are (cell, heading); f = (D + Manhattan, T + turn bound); order R L D U.
    // pop start (0,0), no heading: R -> ((1,0),R) g(1,0) f(2,0) inserted; L, D, U out.
    // pop ((1,0),R): R -> ((2,0),R) g(2,0) f(2,0); L -> ((0,0),L) g(2,1) (a turn),
    //   h = (2, 1) (heading away from the goal's only direction), f(4,2); D, U out.
    // pop ((2,0),R): goal. Expanded 3, checks 8, blocked 3 + 2, insertions 4 (start
    // included), relaxations 3; OPEN holds 1 then 2 states; cells (0,0) (1,0) (2,0).
    check(
        "...",
        (0, 0),
        (2, 0),
        false,
        Budget::unlimited(),
        "
status found
path (0,0) (1,0) (2,0)
n_expanded=3 n_neighbor_checks=8 n_blocked=5 n_skipped=0 n_open_insertions=4 n_relaxations=3 peak_open=2 n_dominated=0 n_cells_expanded=3
        ",
    );
    // With dominance, ((0,0),L) at g(2,1) is dropped: the start state of the same cell
    // has g(0,0), and (0,0) + (0,1) <= (2,1). One insertion and relaxation fewer.
    check(
        "...",
        (0, 0),
        (2, 0),
        true,
        Budget::unlimited(),
        "
status found
path (0,0) (1,0) (2,0)
n_expanded=3 n_neighbor_checks=8 n_blocked=5 n_skipped=0 n_open_insertions=3 n_relaxations=2 peak_open=1 n_dominated=1 n_cells_expanded=3
        ",
    );
}

#[test]
fn open_square_by_hand() {
    // 2x2 open grid, (0,0) to (1,1); pushes are numbered for FIFO.
    // pop start: R -> ((1,0),R) #1 g(1,0) h(1,1) (down still needed) f(2,1);
    //   D -> ((0,1),D) #2 f(2,1); L, U out.                                   OPEN 2
    // pop #1: R out; L -> ((0,0),L) #3 g(2,1) h(2,2) f(4,3); D -> ((1,1),D) #4 g(2,1)
    //   f(2,1); U out.                                                        OPEN 3
    // pop #2 (FIFO before #4): R -> ((1,1),R) #5 g(2,1) f(2,1) (another state of the same
    //   cell); L, D out; U -> ((0,0),U) #6 g(2,1) f(4,3).                     OPEN 4
    // pop #4: goal, reached from (1,0), one turn. Expanded 4, checks 12, blocked 2+2+2,
    // insertions 7, relaxations 6, peak OPEN 4, four distinct cells expanded.
    let map = "
        ..
        ..
        ";
    check(
        map,
        (0, 0),
        (1, 1),
        false,
        Budget::unlimited(),
        "
status found
path (0,0) (1,0) (1,1)
n_expanded=4 n_neighbor_checks=12 n_blocked=6 n_skipped=0 n_open_insertions=7 n_relaxations=6 peak_open=4 n_dominated=0 n_cells_expanded=4
        ",
    );
    // With dominance, #3 and #6 (back at the start cell, g(2,1)) are dropped; #5,
    // ((1,1),R) at g(2,1), is kept: the best g at (1,1) is #4's (2,1), and (2,2) > (2,1).
    // OPEN: 2, then 2 - 1 + 1, then 2 - 1 + 1.
    check(
        map,
        (0, 0),
        (1, 1),
        true,
        Budget::unlimited(),
        "
status found
path (0,0) (1,0) (1,1)
n_expanded=4 n_neighbor_checks=12 n_blocked=6 n_skipped=0 n_open_insertions=5 n_relaxations=4 peak_open=2 n_dominated=2 n_cells_expanded=4
        ",
    );
}

#[test]
fn dead_end_skips_a_closed_state() {
    // Without dominance:
    // pop start (0,0): R -> ((1,0),R); L, D, U out.                      blocked 3
    // pop ((1,0),R): R blocked; L -> ((0,0),L); D, U out.                blocked 3
    // pop ((0,0),L): R -> ((1,0),R) is CLOSED (skipped); L, D, U out.    blocked 3
    // OPEN empty: no path. Cell (0,0) was expanded twice (two states).
    check(
        "..#.",
        (0, 0),
        (3, 0),
        false,
        Budget::unlimited(),
        "
status no_path
path -
n_expanded=3 n_neighbor_checks=12 n_blocked=9 n_skipped=1 n_open_insertions=3 n_relaxations=2 peak_open=1 n_dominated=0 n_cells_expanded=2
        ",
    );
    // With dominance ((0,0),L) is never inserted, so the search ends after two expansions.
    check(
        "..#.",
        (0, 0),
        (3, 0),
        true,
        Budget::unlimited(),
        "
status no_path
path -
n_expanded=2 n_neighbor_checks=8 n_blocked=6 n_skipped=0 n_open_insertions=2 n_relaxations=1 peak_open=1 n_dominated=1 n_cells_expanded=2
        ",
    );
}

#[test]
fn start_equals_goal() {
    check(
        "..",
        (1, 0),
        (1, 0),
        true,
        Budget::unlimited(),
        "
status found
path (1,0)
n_expanded=1 n_neighbor_checks=0 n_blocked=0 n_skipped=0 n_open_insertions=1 n_relaxations=0 peak_open=1 n_dominated=0 n_cells_expanded=1
        ",
    );
}

#[test]
fn budget_counts_state_expansions() {
    // The 2x2 trace of `open_square_by_hand` stopped after two expansions: the start and
    // ((1,0),R). Without dominance insertions #0-#4, OPEN peaks at 3; with it #3 is dropped.
    let map = "
        ..
        ..
        ";
    check(
        map,
        (0, 0),
        (1, 1),
        false,
        Budget::expansions(2),
        "
status budget_exhausted
path -
n_expanded=2 n_neighbor_checks=8 n_blocked=4 n_skipped=0 n_open_insertions=5 n_relaxations=4 peak_open=3 n_dominated=0 n_cells_expanded=2
        ",
    );
    check(
        map,
        (0, 0),
        (1, 1),
        true,
        Budget::expansions(2),
        "
status budget_exhausted
path -
n_expanded=2 n_neighbor_checks=8 n_blocked=4 n_skipped=0 n_open_insertions=4 n_relaxations=3 peak_open=2 n_dominated=1 n_cells_expanded=2
        ",
    );
    check(
        "..",
        (0, 0),
        (1, 0),
        true,
        Budget::expansions(0),
        "
status budget_exhausted
path -
n_expanded=0 n_neighbor_checks=0 n_blocked=0 n_skipped=0 n_open_insertions=1 n_relaxations=0 peak_open=1 n_dominated=0 n_cells_expanded=0
        ",
    );
}

#[test]
fn the_planner_is_reusable_across_grids() {
    // Same answers from a fresh planner and from one that has searched other grids.
    let mut reused = LexAStar::new(Config::default()).unwrap();
    for map in [
        "...\n...\n...",
        ".....\n.#.#.\n.....",
        "..\n..",
        "...\n...\n...",
    ] {
        let grid = Grid::from_ascii(map).unwrap();
        let goal = Cell::new(grid.width() - 1, grid.height() - 1);
        let problem = Problem::new(&grid, Cell::new(0, 0), goal).unwrap();
        let fresh = LexAStar::new(Config::default())
            .unwrap()
            .plan(&problem, &Budget::unlimited());
        for _ in 0..3 {
            assert_eq!(reused.plan(&problem, &Budget::unlimited()), fresh, "{map}");
        }
    }
}

#[test]
fn eight_connected_goes_straight_along_the_diagonal() {
    // Open 4x4, (0,0) to (3,3): three diagonal moves, no turn. With 4-connected moves: six
    // steps and one turn (along two sides).
    let grid = Grid::new(4, 4).unwrap();
    let problem = Problem::new(&grid, Cell::new(0, 0), Cell::new(3, 3)).unwrap();
    for (moves, expect) in [
        (Connectivity::Eight, (3, 0, 3)),
        (Connectivity::Four, (6, 1, 7)),
    ] {
        let config = Config {
            moves,
            ..Config::default()
        };
        let search = LexAStar::new(config)
            .unwrap()
            .search(&problem, &Budget::unlimited());
        let m = search.path.unwrap().metrics();
        assert_eq!((m.steps, m.turns, m.score), expect, "{moves}");
        let cost = search.cost.unwrap();
        assert_eq!((cost.steps, cost.turns, cost.score()), expect);
    }
}

#[test]
fn config_defaults_toml_and_errors() {
    assert_eq!(LexAStar::new(Config::default()).unwrap().name(), "lexastar");
    let parsed: Config = toml::from_str(
        r#"
        moves = 8
        order = "U D L R"
        objective = "weighted"
        lambda = 0.5
        dominance = true
        "#,
    )
    .unwrap();
    assert_eq!(parsed.moves, Connectivity::Eight);
    assert_eq!(parsed.objective, Objective::Weighted);
    assert_eq!(parsed.lambda, 0.5);
    assert_eq!(parsed.order.to_string(), "U D L R");
    assert!(!parsed.corner_cutting);
    assert!(parsed.dominance);
    let empty: Config = toml::from_str("").unwrap();
    assert_eq!(empty, Config::default());
    assert_eq!(empty.objective, Objective::Lexicographic);
    assert_eq!(empty.lambda, 1.0);
    assert!(toml::from_str::<Config>("weight = 2.0").is_err());
    assert!(toml::from_str::<Config>("objective = \"pareto\"").is_err());

    let error = |config: Config| LexAStar::new(config).unwrap_err();
    assert_eq!(
        error(Config {
            moves: Connectivity::Sixteen,
            ..Config::default()
        }),
        ConfigError::Moves(16)
    );
    assert_eq!(
        error(Config {
            lambda: -1.0,
            ..Config::default()
        })
        .to_string(),
        "parameter `lambda` must be a finite number >= 0, got -1"
    );
    assert!(matches!(
        error(Config {
            lambda: f64::NAN,
            ..Config::default()
        }),
        ConfigError::Lambda(_)
    ));
    assert!(matches!(
        error(Config {
            corner_cutting: true,
            ..Config::default()
        }),
        ConfigError::Order(_)
    ));
    // lambda is checked even in lexicographic mode, where it is otherwise ignored.
    assert!(LexAStar::new(Config {
        lambda: f64::INFINITY,
        ..Config::default()
    })
    .is_err());
    let status = LexAStar::new(Config {
        objective: Objective::Weighted,
        lambda: 0.0,
        ..Config::default()
    })
    .unwrap()
    .plan(
        &Problem::new(&Grid::new(3, 3).unwrap(), Cell::new(0, 0), Cell::new(2, 2)).unwrap(),
        &Budget::unlimited(),
    )
    .status;
    assert_eq!(status, Status::Found);
}
