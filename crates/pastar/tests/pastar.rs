//! PA-star end to end: the paper's exact lengths, hand-checked pipelines, the fallback,
//! the budget, the config, and a property test against plain A* on random grids.

use planner_api::{Budget, Cell, Connectivity, Grid, PathRule, Planner, Problem, Status};
use planner_astar::{AStar, Heuristic};
use planner_pastar::{Config, ConfigError, PaStar, Radius, Report};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

fn map(name: &str) -> Grid {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../maps/pastar")
        .join(name);
    planner_maps::read_map(&path).unwrap().grid
}

fn run(grid: &Grid, start: (u32, u32), goal: (u32, u32), config: Config) -> Report {
    let problem = Problem::new(grid, start.into(), goal.into()).unwrap();
    PaStar::new(config)
        .unwrap()
        .plan_detailed(&problem, &Budget::unlimited())
}

fn length(report: &Report) -> f64 {
    report.outcome.path.as_ref().unwrap().metrics().length
}

fn counter(report: &Report, name: &str) -> u64 {
    report.outcome.counters.get(name).unwrap()
}

/// Section 4.3.1, Table 6: without obstacles PA-star is the straight line and TA-star
/// (8-connected A*) is 50 diagonal plus 50 straight moves.
#[test]
fn no_obstacle_lengths_are_exact() {
    let grid = map("open-140x120.map");
    let report = run(&grid, (20, 10), (70, 110), Config::default());
    assert_eq!(
        report.outcome.path.as_ref().unwrap().cells(),
        &[Cell::new(20, 10), Cell::new(70, 110)]
    );
    // sqrt(50^2 + 100^2) = 111.8034 (Table 6 prints 111.8404, a slip).
    assert!((length(&report) - 12_500f64.sqrt()).abs() < 1e-9);
    assert_eq!(format!("{:.2}", length(&report)), "111.80");
    assert_eq!(counter(&report, "n_expanded"), 0);
    assert_eq!(counter(&report, "n_local_segments"), 0);

    let mut ta_star = AStar::new(planner_astar::Config {
        moves: Connectivity::Eight,
        heuristic: Heuristic::Manhattan,
        ..Default::default()
    })
    .unwrap();
    let problem = Problem::new(&grid, Cell::new(20, 10), Cell::new(70, 110)).unwrap();
    let ta = ta_star.plan(&problem, &Budget::unlimited());
    let ta_length = ta.path.unwrap().metrics().length;
    // 50 * sqrt 2 + 50 = 120.7107 (Table 6).
    assert!((ta_length - (50.0 * 2f64.sqrt() + 50.0)).abs() < 1e-9);
    assert_eq!(format!("{ta_length:.4}"), "120.7107");
}

/// Table 1 through PA-star's own config: Connecting_distance 1, 2, 3 (and 4) give 8, 16,
/// 32 (and 48) directions.
#[test]
fn connecting_distance_neighbourhoods() {
    for (k, n) in [(1, 8), (2, 16), (3, 32), (4, 48)] {
        let pastar = PaStar::new(Config {
            connecting_distance: k,
            ..Config::default()
        })
        .unwrap();
        assert_eq!(pastar.local_moves().moves().len(), n, "k = {k}");
    }
}

fn check_config_error(config: Config, expect: &str) {
    let error: ConfigError = PaStar::new(config).unwrap_err();
    assert_eq!(error.to_string(), expect);
}

#[test]
fn config_is_validated_and_reads_toml() {
    let base = Config::default;
    check_config_error(
        Config {
            connecting_distance: 5,
            ..base()
        },
        "parameter `connecting_distance` must be 1, 2, 3 or 4, got 5",
    );
    check_config_error(
        Config {
            connecting_distance: 0,
            ..base()
        },
        "parameter `connecting_distance` must be 1, 2, 3 or 4, got 0",
    );
    check_config_error(
        Config {
            beta: -1.0,
            ..base()
        },
        "parameter `beta` must be a finite number >= 0, got -1",
    );
    check_config_error(
        Config {
            radius: Radius::Cells(0.0),
            ..base()
        },
        "parameter `radius` must be \"size\" or a finite number > 0, got 0",
    );
    check_config_error(
        Config {
            r_threshold: f64::NAN,
            ..base()
        },
        "parameter `r_threshold` must be a finite number >= 0, got NaN",
    );
    let parse = |text: &str| toml::from_str::<Config>(text);
    assert_eq!(parse("radius = \"size\"").unwrap().radius, Radius::Size);
    assert_eq!(parse("radius = 4").unwrap().radius, Radius::Cells(4.0));
    assert_eq!(parse("radius = 2.5").unwrap().radius, Radius::Cells(2.5));
    assert!(parse("radius = \"big\"")
        .unwrap_err()
        .to_string()
        .contains("expected \"size\" or a number of cells"));
    assert!(parse("beta_ = 1.0").is_err());
    // Defaults: Table 5 (beta 1, Connecting_distance 2, r 4) and R_threshold 13 (4.3.2).
    let d = Config::default();
    assert_eq!(
        (d.beta, d.connecting_distance, d.radius, d.r_threshold),
        (1.0, 2, Radius::Cells(4.0), 13.0)
    );
    // The serialized form reads back.
    let text = serde_json::to_string(&Config {
        radius: Radius::Size,
        ..d.clone()
    })
    .unwrap();
    assert!(text.contains(r#""radius":"size""#), "{text}");
}

/// A horizontal line through a 2 x 2 block, worked by hand.
#[test]
fn one_block_by_hand() {
    let grid = Grid::from_ascii(
        "
        ..........
        ..........
        ....##....
        ....##....
        ..........
        ",
    )
    .unwrap();
    let report = run(&grid, (0, 2), (9, 2), Config::default());
    assert_eq!(report.obstacles.len(), 1);
    let o = &report.obstacles[0];
    // Cells (4,2) (5,2) (4,3) (5,3): size sqrt 2, centroid (4.5, 2.5).
    assert_eq!((o.n_cells, o.first_cell), (4, Cell::new(4, 2)));
    assert!((o.size - 2f64.sqrt()).abs() < 1e-12);
    assert_eq!(o.centre, (4.5, 2.5));
    // Circle r = 4 on y = 2: (x - 4.5)^2 + 0.25 = 16, x = 4.5 -+ sqrt(15.75), t = x / 9.
    let (t_m, t_n) = o.circle.unwrap();
    assert!((t_m - (4.5 - 15.75f64.sqrt()) / 9.0).abs() < 1e-12);
    assert!((t_n - (4.5 + 15.75f64.sqrt()) / 9.0).abs() < 1e-12);
    // x = 0.53 and 8.47 snap to the line cells (1, 2) and (8, 2).
    assert_eq!(
        (report.line[o.handover.0], report.line[o.handover.1]),
        (Cell::new(1, 2), Cell::new(8, 2))
    );
    assert_eq!(report.segments.len(), 1);
    // The local A* (16 directions) goes (1,2) (3,1) .. (6,1) (8,2) or an equal-cost
    // variant: 3 + 2 sqrt 5; the straight pieces add 1 + 1.
    assert!((length(&report) - (5.0 + 2.0 * 5f64.sqrt())).abs() < 1e-9);
    assert_eq!(counter(&report, "n_obstacles_crossed"), 1);
    assert_eq!(counter(&report, "n_local_segments"), 1);
    assert_eq!(counter(&report, "n_merged"), 0);
    assert_eq!(counter(&report, "n_fallbacks"), 0);
    assert!(counter(&report, "n_expanded") > 0);
}

/// Equation 9 on a line through two single blocked cells 7 apart (radius 1).
#[test]
fn merging_follows_r_threshold() {
    let grid = Grid::from_ascii(
        "
        ....................
        .....#......#.......
        ....................
        ",
    )
    .unwrap();
    let config = |r_threshold| Config {
        radius: Radius::Cells(1.0),
        r_threshold,
        ..Config::default()
    };
    // Circles of radius 1 give handover cells (4,1)-(6,1) and (11,1)-(13,1): 5 apart.
    let apart = run(&grid, (0, 1), (19, 1), config(4.9));
    let ends: Vec<(Cell, Cell)> = apart.segments.iter().map(|s| (s.start, s.goal)).collect();
    assert_eq!(
        ends,
        vec![
            (Cell::new(4, 1), Cell::new(6, 1)),
            (Cell::new(11, 1), Cell::new(13, 1))
        ]
    );
    // Each local path steps off the line, two along, and back: 4; straight 4 + 5 + 6.
    assert!((length(&apart) - 23.0).abs() < 1e-9);
    assert_eq!(counter(&apart, "n_merged"), 0);
    let merged = run(&grid, (0, 1), (19, 1), config(5.0));
    let ends: Vec<(Cell, Cell)> = merged.segments.iter().map(|s| (s.start, s.goal)).collect();
    assert_eq!(ends, vec![(Cell::new(4, 1), Cell::new(13, 1))]);
    assert_eq!(merged.segments[0].n_obstacles, 2);
    assert_eq!(counter(&merged, "n_merged"), 1);
    assert_eq!(counter(&merged, "n_local_segments"), 1);
    // The outcome marks the handover cells the path uses, after merging.
    let marks = |report: &planner_pastar::Report| -> Vec<(String, Cell)> {
        let marks = &report.outcome.marks;
        marks.iter().map(|m| (m.label.clone(), m.cell)).collect()
    };
    let named = |pairs: &[(&str, (u32, u32))]| -> Vec<(String, Cell)> {
        let cell = |(x, y)| Cell::new(x, y);
        pairs
            .iter()
            .map(|&(l, c)| (l.to_string(), cell(c)))
            .collect()
    };
    assert_eq!(
        marks(&apart),
        named(&[
            ("H1", (4, 1)),
            ("H1'", (6, 1)),
            ("H2", (11, 1)),
            ("H2'", (13, 1))
        ])
    );
    assert_eq!(marks(&merged), named(&[("H1", (4, 1)), ("H1'", (13, 1))]));
    // One search over both: up, along row 0, down: 1 + 9 + 1 at most.
    assert!(length(&merged) <= 4.0 + 11.0 + 6.0 + 1e-9);
}

/// The paper's two-obstacle map: 12 does not merge, 13 does (Fig. 13's step), and the
/// merged path is shorter.
#[test]
fn two_obstacle_map_merges_at_13() {
    let grid = map("two-140x120.map");
    let at = |r_threshold| {
        run(
            &grid,
            (20, 10),
            (70, 110),
            Config {
                r_threshold,
                ..Config::default()
            },
        )
    };
    let (twelve, thirteen) = (at(12.0), at(13.0));
    assert_eq!(counter(&twelve, "n_local_segments"), 2);
    assert_eq!(counter(&thirteen, "n_local_segments"), 1);
    assert_eq!(counter(&thirteen, "n_merged"), 1);
    let o = &thirteen.obstacles;
    let gap = thirteen.line[o[0].handover.1].euclidean(thirteen.line[o[1].handover.0]);
    // (38, 47) to (48, 66)... as snapped: sqrt(6^2 + 11^2) = 12.53.
    assert!((gap - 157f64.sqrt()).abs() < 1e-9, "{gap}");
    assert!(length(&thirteen) < length(&twelve));
}

/// Cells touching at a corner are one obstacle; a line touching a side cell at a vertex
/// crosses it.
#[test]
fn obstacles_are_8_connected_and_vertices_count() {
    let grid = Grid::from_ascii(
        "
        ......#...
        .....#....
        ..........
        ",
    )
    .unwrap();
    let report = run(&grid, (0, 1), (9, 1), Config::default());
    assert_eq!(report.obstacles.len(), 1);
    assert_eq!(report.obstacles[0].n_cells, 2);
    assert!((report.obstacles[0].size - 2f64.sqrt()).abs() < 1e-12);
    // (0,0) -> (2,2) passes the vertex at (0.5, 0.5) and so touches (1, 0).
    let grid = Grid::from_ascii(
        "
        .#..
        ....
        ....
        ",
    )
    .unwrap();
    let report = run(&grid, (0, 0), (2, 2), Config::default());
    assert_eq!(counter(&report, "n_obstacles_crossed"), 1);
    let path = report.outcome.path.unwrap();
    assert!(path.validate(&grid, PathRule::AnyAngle).is_ok());
}

/// Equation 6 compares x only; ordering along S-E also works for vertical lines and for
/// goals left of the start.
#[test]
fn vertical_and_reversed_lines() {
    let grid = Grid::from_ascii(
        "
        .......
        .......
        .......
        ..###..
        .......
        .......
        .......
        ",
    )
    .unwrap();
    for (start, goal) in [((3, 0), (3, 6)), ((3, 6), (3, 0)), ((6, 6), (0, 0))] {
        let report = run(&grid, start, goal, Config::default());
        let segment = &report.segments[0];
        let path = report.outcome.path.as_ref().unwrap();
        assert_eq!(path.start(), Some(start.into()));
        assert_eq!(path.goal(), Some(goal.into()));
        assert!(path.validate(&grid, PathRule::AnyAngle).is_ok());
        // The local start is the handover cell nearer S.
        let s = Cell::from(start);
        assert!(s.euclidean(segment.start) < s.euclidean(segment.goal));
    }
}

#[test]
fn start_equals_goal() {
    let grid = Grid::new(3, 3).unwrap();
    let report = run(&grid, (1, 1), (1, 1), Config::default());
    assert_eq!(report.outcome.path.unwrap().cells(), &[Cell::new(1, 1)]);
}

/// A walled-in start: the local search fails, the fallback A* confirms there is no path.
#[test]
fn failed_local_search_falls_back() {
    let grid = Grid::from_ascii(
        "
        .....
        .###.
        .#.#.
        .###.
        .....
        ",
    )
    .unwrap();
    let report = run(&grid, (2, 2), (4, 4), Config::default());
    assert_eq!(report.outcome.status, Status::NoPath);
    assert_eq!(counter(&report, "n_fallbacks"), 1);
    // The path need not pass the handover cells: none are marked.
    assert!(report.outcome.marks.is_empty());
    assert_eq!(counter(&report, "n_local_segments"), 1);
    // The start cell alone is expanded, once by the local search and once by the fallback.
    assert_eq!(counter(&report, "n_expanded"), 2);
}

/// The budget is shared: the second local search gets what the first left.
#[test]
fn budget_spans_local_searches() {
    let grid = map("two-140x120.map");
    let problem = Problem::new(&grid, Cell::new(20, 10), Cell::new(70, 110)).unwrap();
    let mut pastar = PaStar::new(Config {
        r_threshold: 0.0,
        ..Config::default()
    })
    .unwrap();
    let full = pastar.plan_detailed(&problem, &Budget::unlimited());
    assert_eq!(full.segments.len(), 2);
    let first = full.segments[0].path.as_ref().unwrap();
    assert!(!first.is_empty());
    let total = full.stats.search.n_expanded;
    // Enough for everything: found, the same counters.
    let exact = pastar.plan_detailed(&problem, &Budget::expansions(total));
    assert_eq!(exact.outcome, full.outcome);
    // One fewer: the second search runs out.
    let short = pastar.plan_detailed(&problem, &Budget::expansions(total - 1));
    assert_eq!(short.outcome.status, Status::BudgetExhausted);
    assert_eq!(short.outcome.path, None);
    assert_eq!(short.stats.search.n_expanded, total - 1);
    assert_eq!(short.stats.n_local_segments, 2);
    // Counters are a pure function of the input: the same query again gives the same.
    assert_eq!(pastar.plan(&problem, &Budget::unlimited()), full.outcome);
}

/// The memory limit is checked up front, as every planner checks it: over it, PA-star
/// refuses with the shortfall (it ran the local A* and reported budget_exhausted with no
/// reason, and on a free line it answered found), whether or not the line is free.
#[test]
fn memory_budget_is_checked_up_front() {
    let blocked = Grid::from_ascii(".......\n...#...\n...#...\n...#...\n.......").unwrap();
    let free = Grid::from_ascii(".......\n.......\n.......\n.......\n.......").unwrap();
    let mut pastar = PaStar::new(Config::default()).unwrap();
    for grid in [&blocked, &free] {
        let problem = Problem::new(grid, Cell::new(0, 2), Cell::new(6, 2)).unwrap();
        let needed = pastar.memory_bytes_for(grid);
        let astar = AStar::new(planner_astar::Config {
            moves: Connectivity::from_connecting_distance(Config::default().connecting_distance)
                .unwrap(),
            ..planner_astar::Config::default()
        })
        .unwrap();
        assert!(needed > astar.memory_bytes_for(grid), "{needed}");
        let refused = pastar.plan_detailed(&problem, &Budget::unlimited().with_memory_mb(0));
        assert_eq!(refused.outcome.status, Status::BudgetExhausted);
        assert_eq!(refused.outcome.path, None);
        let shortfall = refused.outcome.memory.as_ref().expect("a memory shortfall");
        assert_eq!(shortfall.needed_bytes, needed);
        assert_eq!(shortfall.max_memory_mb, 0);
        assert_eq!(refused.stats.search.n_expanded, 0);
        assert_eq!(refused.stats.n_local_segments, 0);
        // Within the limit: the same answer as without one.
        let fits = pastar.plan(&problem, &Budget::unlimited().with_memory_mb(1));
        assert_eq!(fits.status, Status::Found);
        assert_eq!(fits, pastar.plan(&problem, &Budget::unlimited()));
    }
}

/// On random grids PA-star finds a valid path exactly when A* does, never needs the
/// fallback when one exists, and its segment counts add up.
#[test]
fn random_grids_against_astar() {
    let mut rng = ChaCha8Rng::seed_from_u64(5);
    let configs = [
        Config::default(),
        Config {
            radius: Radius::Size,
            connecting_distance: 1,
            ..Config::default()
        },
        Config {
            radius: Radius::Cells(1.5),
            connecting_distance: 3,
            r_threshold: 0.0,
            beta: 2.0,
            ..Config::default()
        },
    ];
    let mut astar = AStar::new(planner_astar::Config {
        moves: Connectivity::Eight,
        heuristic: Heuristic::Octile,
        ..Default::default()
    })
    .unwrap();
    let mut planners: Vec<PaStar> = configs
        .iter()
        .map(|c| PaStar::new(c.clone()).unwrap())
        .collect();
    let mut searched = 0;
    for _ in 0..300 {
        let (w, h) = (rng.gen_range(5..40), rng.gen_range(5..40));
        let density = rng.gen_range(0.05..0.4);
        let free: Vec<bool> = (0..w * h).map(|_| !rng.gen_bool(density)).collect();
        let grid = Grid::from_free_cells(w, h, free).unwrap();
        let pick = |rng: &mut ChaCha8Rng| loop {
            let c = Cell::new(rng.gen_range(0..w), rng.gen_range(0..h));
            if grid.is_free(c) {
                break c;
            }
        };
        let (s, e) = (pick(&mut rng), pick(&mut rng));
        let problem = Problem::new(&grid, s, e).unwrap();
        let reference = astar.plan(&problem, &Budget::unlimited()).status;
        for planner in &mut planners {
            let report = planner.plan_detailed(&problem, &Budget::unlimited());
            assert_eq!(report.outcome.status, reference, "{grid:?} {s} -> {e}");
            let stats = report.stats;
            if reference == Status::Found {
                let path = report.outcome.path.as_ref().unwrap();
                assert_eq!((path.start(), path.goal()), (Some(s), Some(e)));
                assert!(path.validate(&grid, PathRule::AnyAngle).is_ok());
                assert_eq!(stats.n_fallbacks, 0, "{grid:?} {s} -> {e}");
                assert_eq!(
                    stats.n_local_segments,
                    stats.n_obstacles_crossed - stats.n_merged
                );
                searched += u64::from(stats.n_local_segments > 0);
            } else {
                assert_eq!(stats.n_fallbacks, 1);
            }
        }
    }
    assert!(
        searched > 300,
        "most problems need a local search: {searched}"
    );
}
