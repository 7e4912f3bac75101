//! ROS map_server maps: small PGM and PNG images written here, read back through the YAML.

use std::path::{Path, PathBuf};

use planner_api::Cell;
use planner_maps::{
    parse_ros_yaml, read_map, read_ros_map, MapErrorKind, MapFormat, RosMode, RosOptions,
};

/// A fresh directory for one test's files.
fn dir(name: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR"))
        .join("ros")
        .join(name);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

const YAML: &str = "\
# written by map_saver
image: map.pgm
resolution: 0.050000
origin: [-1.000000, -2.000000, 0.000000]
negate: 0
occupied_thresh: 0.65
free_thresh: 0.196
";

/// A 4 x 3 binary PGM (P5): white (254) free, black (0) occupied, grey (205) unknown.
///   254 254   0 254
///   254 205 254 254
///     0 254 254 254
fn write_pgm(dir: &Path) {
    let mut bytes = b"P5\n# gridplan test\n4 3\n255\n".to_vec();
    bytes.extend([254, 254, 0, 254, 254, 205, 254, 254, 0, 254, 254, 254]);
    std::fs::write(dir.join("map.pgm"), bytes).unwrap();
}

#[test]
fn pgm_trinary_by_hand() {
    let dir = dir("trinary");
    write_pgm(&dir);
    std::fs::write(dir.join("map.yaml"), YAML).unwrap();
    let map = read_ros_map(&dir.join("map.yaml"), &RosOptions::default()).unwrap();
    assert_eq!(map.yaml.mode, RosMode::Trinary);
    assert_eq!(map.occupancy, [0, 0, 100, 0, 0, -1, 0, 0, 100, 0, 0, 0]);
    // Unknown is blocked: 12 cells - 2 occupied - 1 unknown.
    assert_eq!(
        map.grid.to_ascii(),
        "\
..#.
.#..
#...
"
    );
    // Cell (0, 2) is the image's bottom-left pixel: the origin cell, centre at +0.025 m.
    let (x, y) = map.world(Cell::new(0, 2));
    assert!((x - -0.975).abs() < 1e-12 && (y - -1.975).abs() < 1e-12);
    let (x, y) = map.world(Cell::new(3, 0));
    assert!((x - -0.825).abs() < 1e-12 && (y - -1.875).abs() < 1e-12);

    // read_map dispatches on the extension, with default options.
    let file = read_map(&dir.join("map.yaml")).unwrap();
    assert_eq!(file.format, MapFormat::Ros);
    assert_eq!(file.grid, map.grid);
    assert!(file.problems.is_empty());

    // Inflation by one cell blocks the 4-neighbours of the two occupied cells only.
    let inflated = read_ros_map(
        &dir.join("map.yaml"),
        &RosOptions {
            inflation_radius: 1,
            inflate_unknown: false,
        },
    )
    .unwrap();
    assert_eq!(
        inflated.grid.to_ascii(),
        "\
.###
###.
##..
"
    );
}

#[test]
fn ascii_pgm_negated() {
    let dir = dir("negated");
    // P2 (ASCII) with maxval 255; negated, so black (0) is free and white occupied.
    std::fs::write(dir.join("map.pgm"), "P2\n3 2\n255\n0 0 255\n0 255 0\n").unwrap();
    let yaml = YAML.replace("negate: 0", "negate: 1");
    std::fs::write(dir.join("map.yaml"), yaml).unwrap();
    let map = read_ros_map(&dir.join("map.yaml"), &RosOptions::default()).unwrap();
    assert_eq!(map.grid.to_ascii(), "..#\n.#.\n");
}

#[test]
fn png_scale_with_alpha() {
    let dir = dir("png");
    // Grey + alpha: free white, occupied black, mid grey 170 (p = 1/3 -> value 30, a partly
    // occupied cell, blocked), and a transparent mid grey (unknown in scale mode).
    let img =
        image::GrayAlphaImage::from_raw(4, 1, vec![255, 255, 0, 255, 170, 255, 170, 0]).unwrap();
    img.save(dir.join("map.png")).unwrap();
    let yaml = YAML.replace("map.pgm", "\"map.png\"") + "mode: scale  # partly occupied\n";
    std::fs::write(dir.join("map.yaml"), yaml).unwrap();
    let map = read_ros_map(&dir.join("map.yaml"), &RosOptions::default()).unwrap();
    assert_eq!(map.yaml.mode, RosMode::Scale);
    assert_eq!(map.occupancy, [0, 100, 30, -1]);
    assert_eq!(map.grid.to_ascii(), ".###\n");
}

/// Parses `text` and compares the error's display with `expect`.
fn check(text: &str, expect: &str) {
    let err = parse_ros_yaml(text, "m.yaml").unwrap_err();
    assert_eq!(err.to_string(), expect, "{text}");
}

#[test]
fn yaml_errors_name_line_and_column() {
    check(
        &YAML.replace("resolution: 0.050000", "resolution: fast"),
        "m.yaml:3:13: expected a number for 'resolution', found 'fast'",
    );
    check(
        &YAML.replace("negate: 0", "negate: 2"),
        "m.yaml:5:9: expected 0, 1, true or false for 'negate', found '2'",
    );
    check(
        &YAML.replace("[-1.000000, -2.000000, 0.000000]", "[-1.0, x, 0.0]"),
        "m.yaml:4:16: expected a number in 'origin', found 'x'",
    );
    check(
        &YAML.replace("[-1.000000, -2.000000, 0.000000]", "[-1.0, 2.0]"),
        "m.yaml:4:9: expected three numbers [x, y, yaw] for 'origin', found 2 items",
    );
    check(
        &YAML.replace("free_thresh: 0.196", "free_tresh: 0.196"),
        "m.yaml:7:1: expected one of the keys image, resolution, origin, occupied_thresh, free_thresh, negate, mode, found 'free_tresh'",
    );
    check(
        &YAML.replace("free_thresh: 0.196\n", ""),
        "m.yaml: missing key 'free_thresh'",
    );
    check(
        &(YAML.to_owned() + "image: other.pgm\n"),
        "m.yaml:8:1: duplicate header key 'image', already given on line 2",
    );
    check(
        &YAML.replace("negate: 0", "negate:\n  - 0"),
        "m.yaml:5:8: expected a value for 'negate', found end of line",
    );
    check(
        &YAML.replace("free_thresh: 0.196", "free_thresh: 0.8"),
        "m.yaml:7:14: expected 'free_thresh' at most 'occupied_thresh' (0.65), found 0.8",
    );
    check(
        &YAML.replace("occupied_thresh: 0.65", "occupied_thresh: 1.5"),
        "m.yaml:6:18: expected a number in [0, 1] for 'occupied_thresh', found '1.5'",
    );
    check(
        &YAML
            .replace("mode", "x")
            .replace("negate: 0", "negate: 0\nmode: ternary"),
        "m.yaml:6:7: expected trinary, scale or raw for 'mode', found 'ternary'",
    );
    check(
        "  image: a.pgm\n",
        "m.yaml:1:1: expected a top-level 'key: value' (a map_server YAML file is flat), found an indented line",
    );
    // Comments after values and quoted '#' are fine.
    let ok = parse_ros_yaml(
        &YAML.replace("image: map.pgm", "image: 'a #1.pgm'  # the map"),
        "m.yaml",
    )
    .unwrap();
    assert_eq!(ok.image, "a #1.pgm");
    assert_eq!(ok.origin, [-1.0, -2.0, 0.0]);
}

#[test]
fn image_errors_name_the_image() {
    let dir = dir("bad-image");
    std::fs::write(dir.join("map.yaml"), YAML).unwrap();
    let err = read_ros_map(&dir.join("map.yaml"), &RosOptions::default()).unwrap_err();
    assert!(err.file.ends_with("map.pgm"), "{err}");
    assert!(matches!(err.kind, MapErrorKind::Io { .. }), "{err}");
    std::fs::write(dir.join("map.pgm"), "P5\n4 3\n255\n\x01").unwrap();
    let err = read_ros_map(&dir.join("map.yaml"), &RosOptions::default()).unwrap_err();
    assert!(err.file.ends_with("map.pgm"), "{err}");
    assert!(matches!(err.kind, MapErrorKind::Image { .. }), "{err}");
    assert!(err.to_string().contains("cannot decode the image"), "{err}");
}
