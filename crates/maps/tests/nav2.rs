//! The real `map_server` maps of ROS 2's navigation stack (`maps/ros-nav2/`, see its
//! SOURCE.md): every one reads, with the expected warnings, and plans.
//!
//! The cell counts were computed independently of this crate, by a short Python script
//! that parses the PGM header and inflates the PNG's IDAT by hand, then applies the
//! threshold rule (`p = (255 - mean) / 255`; free below `free_thresh`, occupied above
//! `occupied_thresh`). The plans are checked against a breadth-first search written here.

use std::collections::VecDeque;
use std::path::{Path, PathBuf};

use planner_api::{Budget, Cell, Connectivity, Grid, MoveSet, PathRule, Planner, Problem, Status};
use planner_astar::{AStar, Config};
use planner_maps::{read_map_with, read_ros_map, MapFormat, ReadOptions, RosOptions};

fn dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../maps/ros-nav2")
}

/// Breadth-first distances (4-connected) from `start`; `u32::MAX` where unreachable.
fn bfs(grid: &Grid, start: Cell) -> Vec<u32> {
    let mut distance = vec![u32::MAX; grid.len()];
    distance[grid.index(start)] = 0;
    let mut queue = VecDeque::from([start]);
    while let Some(cell) = queue.pop_front() {
        let d = distance[grid.index(cell)];
        for (dx, dy) in [(1, 0), (-1, 0), (0, 1), (0, -1)] {
            if let Some(next) = grid.offset(cell, dx, dy) {
                if grid.is_free(next) && distance[grid.index(next)] == u32::MAX {
                    distance[grid.index(next)] = d + 1;
                    queue.push_back(next);
                }
            }
        }
    }
    distance
}

/// Reads `yaml` and checks its size, cell counts (free, occupied, unknown) and warnings;
/// then plans with A* (4-connected, Manhattan: optimal) from the first free cell to the
/// farthest cell reachable from it and compares the length with the BFS distance.
fn check(yaml: &str, size: (u32, u32), counts: (usize, usize, usize), warnings: &[&str]) {
    let path = dir().join(yaml);
    let read = read_map_with(&path, &ReadOptions::default()).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(read.file.format, MapFormat::Ros);
    let got: Vec<String> = read.warnings.iter().map(|w| w.to_string()).collect();
    let want: Vec<String> = warnings
        .iter()
        .map(|w| format!("{}:{w}", path.display()))
        .collect();
    assert_eq!(got, want, "{yaml}");
    let map = read_ros_map(&path, &RosOptions::default()).unwrap();
    let grid = &map.grid;
    assert_eq!(grid, &read.file.grid);
    assert_eq!((grid.width(), grid.height()), size, "{yaml}");
    let count = |f: fn(i8) -> bool| map.occupancy.iter().filter(|&&v| f(v)).count();
    let occupancy = (count(|v| v == 0), count(|v| v == 100), count(|v| v == -1));
    assert_eq!(occupancy, counts, "{yaml}");
    assert_eq!(grid.n_free(), counts.0);

    let start = grid.cells().find(|&c| grid.is_free(c)).unwrap();
    let distance = bfs(grid, start);
    let (goal_index, &farthest) = distance
        .iter()
        .enumerate()
        .filter(|(_, &d)| d != u32::MAX)
        .max_by_key(|&(i, &d)| (d, std::cmp::Reverse(i)))
        .unwrap();
    let goal = grid.cell(goal_index);
    let problem = Problem::new(grid, start, goal).unwrap();
    let mut astar = AStar::new(Config::default()).unwrap();
    let outcome = astar.plan(&problem, &Budget::unlimited());
    assert_eq!(outcome.status, Status::Found, "{yaml}: {start} to {goal}");
    let plan = outcome.path.as_ref().unwrap();
    plan.validate(
        grid,
        PathRule::Moves(&MoveSet::standard(Connectivity::Four)),
    )
    .unwrap();
    assert_eq!(plan.metrics().steps, u64::from(farthest), "{yaml}");
    assert!(farthest > 0, "{yaml}");
}

#[test]
fn every_nav2_map_reads_and_plans() {
    check("TenByTen.yaml", (10, 10), (78, 20, 2), &[]);
    check("depot.yaml", (604, 307), (179_481, 5_947, 0), &[]);
    // The one the hand-written reader rejected (issue 18): map_type is no map_server key.
    check(
        "map_circular.yaml",
        (384, 384),
        (7_930, 920, 138_606),
        &["7:1: key 'map_type' is not one map_server reads (image, resolution, origin, occupied_thresh, free_thresh, negate, mode): ignored"],
    );
    check("tb3_sandbox.yaml", (384, 384), (7_903, 870, 138_683), &[]);
    // testmap.yaml names the RGB PNG; quoted image and mode.
    check("testmap.yaml", (10, 10), (71, 29, 0), &[]);
    check(
        "warehouse.yaml",
        (1006, 1674),
        (1_422_292, 30_951, 230_801),
        &[],
    );
}

#[test]
fn nav2_images_read_directly_with_map_server_defaults() {
    // Issue 18: a .png or .pgm given directly failed; now map_server's defaults apply
    // (occupied 0.65, free 0.196, trinary), which are testmap.yaml's own values.
    let via_yaml = read_ros_map(&dir().join("testmap.yaml"), &RosOptions::default()).unwrap();
    for image in ["testmap.png", "testmap.pgm"] {
        let read = read_map_with(&dir().join(image), &ReadOptions::default()).unwrap();
        assert_eq!(read.file.format, MapFormat::Image);
        assert!(read.warnings.is_empty());
        assert_eq!(read.file.grid, via_yaml.grid, "{image}");
    }
    // TenByTen.yaml also uses the defaults.
    let ten = planner_maps::read_map(&dir().join("TenByTen.pgm")).unwrap();
    let ten_yaml = planner_maps::read_map(&dir().join("TenByTen.yaml")).unwrap();
    assert_eq!(ten.grid, ten_yaml.grid);
    assert_eq!(ten.grid.n_free(), 78);
}

#[test]
fn nav2_map_with_huge_inflation_finishes() {
    // Issue 18: `inflation = 100000` hung; now every cell is within reach of an occupied
    // one, so nothing is free.
    let options = RosOptions {
        inflation_radius: 100_000,
        inflate_unknown: false,
    };
    let map = read_ros_map(&dir().join("tb3_sandbox.yaml"), &options).unwrap();
    assert_eq!(map.grid.n_free(), 0);
}

/// A finite resolution and origin whose extent is not (`1e308` metres a cell): no map frame
/// (its positions were infinite: `start (inf, inf)`), and a warning that says why.
#[test]
fn a_frame_beyond_the_range_of_numbers_is_no_frame() {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("gridplan-nav2-huge");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::copy(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../../maps/ros-nav2/TenByTen.pgm"),
        dir.join("ten.pgm"),
    )
    .unwrap();
    let check = |resolution: &str, origin: &str| {
        let yaml = dir.join("huge.yaml");
        std::fs::write(
            &yaml,
            format!(
                "image: ten.pgm\nresolution: {resolution}\norigin: {origin}\nnegate: 0\n\
                 occupied_thresh: 0.65\nfree_thresh: 0.196\n"
            ),
        )
        .unwrap();
        read_map_with(&yaml, &ReadOptions::default()).unwrap()
    };
    let read = check("1e308", "[1.7e308, 0, 0]");
    assert!(read.file.frame.is_none());
    let warnings: Vec<String> = read.warnings.iter().map(|w| w.to_string()).collect();
    assert_eq!(warnings.len(), 1, "{warnings:?}");
    assert!(
        warnings[0].contains("beyond the range of numbers"),
        "{warnings:?}"
    );
    // Large but finite: a frame, no warning.
    let read = check("1e300", "[-1e300, 0, 0]");
    assert!(read.file.frame.is_some() && read.warnings.is_empty());
    std::fs::remove_dir_all(&dir).unwrap();
}
