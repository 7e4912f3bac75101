//! Maps with costs: graded ROS 2 navigation maps (`maps/ros-graded`, nav2's own images) read
//! with the documented weights, weight files with positioned errors, Moving AI terrain.

use std::path::PathBuf;

use planner_api::{Cell, CostRule};
use planner_maps::{
    read_map_with, read_weights, CostBands, CostOptions, ReadOptions, TerrainWeights,
};

fn maps() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../maps")
}

fn graded(bands: CostBands) -> ReadOptions {
    ReadOptions {
        costs: CostOptions {
            graded: true,
            bands,
            ..CostOptions::default()
        },
        ..ReadOptions::default()
    }
}

/// TenByTen.pgm's pixels (P5, 10 x 10, after the header), read here by hand.
fn ten_by_ten_pixels() -> Vec<u8> {
    let bytes = std::fs::read(maps().join("ros-nav2/TenByTen.pgm")).unwrap();
    bytes[bytes.len() - 100..].to_vec()
}

/// Every cell's weight (0 for blocked) of a read grid.
fn weights_of(grid: &planner_api::Grid) -> Vec<u16> {
    grid.cells()
        .map(|c| if grid.is_free(c) { grid.weight(c) } else { 0 })
        .collect()
}

#[test]
fn ten_by_ten_in_scale_mode_reads_with_the_documented_costs() {
    let read = read_map_with(
        &maps().join("ros-graded/TenByTen-scale.yaml"),
        &graded(CostBands::default()),
    )
    .unwrap();
    let grid = read.file.grid;
    assert!(grid.is_weighted());
    // By hand (maps/ros-graded/SOURCE.md): 255 free, 179 weight 56, darker blocked.
    let expect: Vec<u16> = ten_by_ten_pixels()
        .iter()
        .map(|&v| match v {
            255 => 1,
            179 => 56,
            0 | 26 | 51 => 0,
            other => panic!("unexpected pixel {other}"),
        })
        .collect();
    assert_eq!(weights_of(&grid), expect);
    assert_eq!(grid.weight(Cell::new(0, 5)), 56);
    // Without costs the same file reads unweighted, the graded cells blocked (value != 0).
    let plain = read_map_with(
        &maps().join("ros-graded/TenByTen-scale.yaml"),
        &ReadOptions::default(),
    )
    .unwrap();
    assert!(!plain.file.grid.is_weighted());
    assert!(!plain.file.grid.is_free(Cell::new(0, 5)));
}

#[test]
fn ten_by_ten_in_raw_mode_reads_with_the_documented_costs() {
    let path = maps().join("ros-graded/TenByTen-raw.yaml");
    let grid = read_map_with(&path, &graded(CostBands::default()))
        .unwrap()
        .file
        .grid;
    let expect: Vec<u16> = ten_by_ten_pixels()
        .iter()
        .map(|&v| match v {
            0 => 1,
            26 => 67,
            51 => 130,
            179 | 255 => 0,
            other => panic!("unexpected pixel {other}"),
        })
        .collect();
    assert_eq!(weights_of(&grid), expect);
    // Unknown cells at cost 200 (weight 201), as a planner allowing unknown space would.
    let bands = CostBands {
        lethal: 254,
        unknown: Some(200),
    };
    let grid = read_map_with(&path, &graded(bands)).unwrap().file.grid;
    assert_eq!(grid.n_free(), 100);
    assert_eq!(grid.weight(Cell::new(0, 0)), 201);
    // A lethal band of 100 blocks cost 129 (weight 130) but not 66.
    let bands = CostBands {
        lethal: 100,
        unknown: None,
    };
    let grid = read_map_with(&path, &graded(bands)).unwrap().file.grid;
    assert!(grid.is_free(Cell::new(7, 2)) && grid.weight(Cell::new(7, 2)) == 67);
    assert!(!grid.is_free(Cell::new(4, 3)));
}

#[test]
fn warehouse_in_scale_mode_weighs_unknown_grey() {
    let path = maps().join("ros-graded/warehouse-scale.yaml");
    let grid = read_map_with(&path, &graded(CostBands::default()))
        .unwrap()
        .file
        .grid;
    assert_eq!((grid.width(), grid.height()), (1006, 1674));
    // Pixel counts (maps/ros-nav2/SOURCE.md's independent count): 0: 30951, 205: 230801,
    // 254: 1318485, 255: 103807.
    let weights = weights_of(&grid);
    let count = |w: u16| weights.iter().filter(|&&x| x == w).count();
    assert_eq!(count(0), 30_951);
    assert_eq!(count(44), 230_801);
    assert_eq!(count(1), 1_318_485 + 103_807);
    assert_eq!(grid.weights().unwrap().min(), 1);
}

fn temp(name: &str, text: &str) -> PathBuf {
    let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join("gridplan-costs");
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join(name);
    std::fs::write(&path, text).unwrap();
    path
}

#[test]
fn weight_files_name_file_line_and_column() {
    let grid = planner_api::Grid::new(3, 2).unwrap();
    let read = |name: &str, text: &str| {
        let path = temp(name, text);
        read_weights(&path, grid.clone(), CostRule::Mean, &ReadOptions::default())
            .map_err(|e| e.to_string().replace(&path.display().to_string(), name))
    };
    let ok = read("ok.csv", "# terrain\n1, 2, 3\n4 5 65535\n").unwrap();
    assert_eq!(ok.weights().unwrap().cells(), [1, 2, 3, 4, 5, 65535]);
    let expected = "expected a weight (an integer from 1 to 65535), found";
    assert_eq!(
        read("zero.csv", "1,2,3\n4,0,6\n").unwrap_err(),
        format!("zero.csv:2:3: {expected} 0")
    );
    assert_eq!(
        read("negative.csv", "1,2,-3\n4,5,6\n").unwrap_err(),
        format!("negative.csv:1:5: {expected} '-3', a negative number")
    );
    assert_eq!(
        read("fraction.csv", "1,2,3\n4.5,5,6\n").unwrap_err(),
        format!("fraction.csv:2:1: {expected} '4.5', not an integer")
    );
    assert_eq!(
        read("overflow.csv", "1,2,3\n4,5,65536\n").unwrap_err(),
        format!("overflow.csv:2:5: {expected} '65536', above 65535")
    );
    assert_eq!(
        read("word.csv", "1,x,3\n4,5,6\n").unwrap_err(),
        format!("word.csv:1:3: {expected} 'x'")
    );
    assert!(read("short.csv", "1,2,3\n")
        .unwrap_err()
        .starts_with("short.csv:2:1: expected 2 rows"));
    assert!(read("long.csv", "1,2,3,4\n1,2,3\n")
        .unwrap_err()
        .starts_with("long.csv:1:7: expected end of line after 3 weights"));
}

#[test]
fn moving_ai_terrain_is_opt_in() {
    let text = "type octile\nheight 2\nwidth 4\nmap\n.SW@\nGSW.\n";
    let path = temp("terrain.map", text);
    let plain = read_map_with(&path, &ReadOptions::default())
        .unwrap()
        .file
        .grid;
    assert!(!plain.is_weighted());
    assert_eq!(plain.to_ascii(), "..##\n...#\n".replace("...#", "..#."));
    let options = |water| ReadOptions {
        costs: CostOptions {
            terrain: Some(TerrainWeights { swamp: 3, water }),
            ..CostOptions::default()
        },
        ..ReadOptions::default()
    };
    let land = read_map_with(&path, &options(None)).unwrap().file.grid;
    assert_eq!(land.to_ascii(), plain.to_ascii());
    assert_eq!(weights_of(&land), [1, 3, 0, 0, 1, 3, 0, 1]);
    let wet = read_map_with(&path, &options(Some(9))).unwrap().file.grid;
    assert_eq!(weights_of(&wet), [1, 3, 9, 0, 1, 3, 9, 1]);
}

/// Graded costs of a `mode: trinary` map (nav2's TenByTen.yaml) made an all-1 weighted
/// grid, which planners that do not honour costs then refused: it is an error, unless
/// unknown cells get a cost (the one thing graded bands change there).
#[test]
fn graded_costs_of_a_trinary_map_are_refused_unless_unknown_cells_get_one() {
    let trinary = maps().join("ros-nav2/TenByTen.yaml");
    let error = read_map_with(&trinary, &graded(CostBands::default())).unwrap_err();
    assert!(
        error.to_string().contains("this map is mode trinary"),
        "{error}"
    );
    let unknown = CostBands {
        unknown: Some(100),
        ..CostBands::default()
    };
    let read = read_map_with(&trinary, &graded(unknown)).unwrap();
    assert!(read.file.grid.is_weighted());
    // Without costs it reads as before.
    assert!(!read_map_with(&trinary, &ReadOptions::default())
        .unwrap()
        .file
        .grid
        .is_weighted());
}
