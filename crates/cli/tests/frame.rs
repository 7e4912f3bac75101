//! `gridplan plan` in a ROS map's map frame: `--start-world` and `--goal-world` in metres,
//! the run printed in metres too, and the errors of points outside the map or of a map
//! without a frame.

use crate::common::{self, root};

/// Runs gridplan with `args` from the repository's root; returns its exit code, stdout
/// and stderr.
fn gridplan(args: &[&str]) -> (i32, String, String) {
    let out = common::gridplan(&root(), args);
    (out.code.unwrap_or(-1), out.stdout, out.stderr)
}

/// TurtleBot3's sandbox map of nav2: 384 x 384 cells of 0.05 m, origin (-10, -10).
const SANDBOX: &str = "maps/ros-nav2/tb3_sandbox.yaml";

/// The cells of points worked out by hand: column `floor((x + 10) / 0.05)`, and the row
/// `floor((y + 10) / 0.05)` rows above the bottom one (row 383): (-1.5, -0.5) is column
/// 170, 190 rows up, row 193; (1.5, 0.5) column 230, 210 up, row 173; (-1.51, -0.51) lies
/// in the cell below and left of the first.
#[test]
fn points_of_the_map_frame_plan_as_their_cells() {
    let (code, out, err) = gridplan(&[
        "plan",
        SANDBOX,
        "--planner",
        "astar",
        "--start-world",
        "-1.5,-0.5",
        "--goal-world",
        "1.5,0.5",
        "--json",
    ]);
    assert_eq!(code, 0, "{err}");
    let by_world: serde_json::Value = serde_json::from_str(&out).unwrap();
    let (code, out, err) = gridplan(&[
        "plan",
        SANDBOX,
        "--planner",
        "astar",
        "--start",
        "170,193",
        "--goal",
        "230,173",
        "--json",
    ]);
    assert_eq!(code, 0, "{err}");
    let by_cell: serde_json::Value = serde_json::from_str(&out).unwrap();
    // The same run, and the frame beside it.
    assert_eq!(by_world, by_cell);
    let frame = &by_world["map_frame"];
    assert_eq!(frame["resolution"], 0.05);
    assert_eq!(frame["origin"], serde_json::json!([-10.0, -10.0, 0.0]));
    let path = by_world["path"].as_array().unwrap();
    let points = frame["path"].as_array().unwrap();
    assert_eq!(points.len(), path.len());
    for (cell, point) in path.iter().zip(points) {
        // Cell centres: half a cell in from the cell's corner.
        let (x, y) = (cell[0].as_f64().unwrap(), cell[1].as_f64().unwrap());
        let expect = [-10.0 + 0.05 * (x + 0.5), -10.0 + 0.05 * (383.0 - y + 0.5)];
        for (got, expect) in point.as_array().unwrap().iter().zip(expect) {
            assert!(
                (got.as_f64().unwrap() - expect).abs() < 1e-9,
                "{point} {cell}"
            );
        }
    }
    assert_eq!(frame["start"], points[0]);
    assert_eq!(&frame["goal"], points.last().unwrap());

    let (code, out, err) = gridplan(&[
        "plan",
        SANDBOX,
        "--planner",
        "astar",
        "--start-world=-1.51,-0.51",
        "--goal-world",
        "1.5,0.5",
    ]);
    assert_eq!(code, 0, "{err}");
    assert!(out.contains("(169, 194) -> (230, 173): found"), "{out}");
    assert!(
        out.contains("map frame (metres, cell centres): start (-1.525, -0.525) -> goal (1.525, 0.525), path "),
        "{out}"
    );
}

#[test]
fn points_off_the_map_and_maps_without_a_frame_are_refused() {
    for (args, code, message) in [
        (
            vec![SANDBOX, "--start-world", "-10.01,0", "--goal-world", "1,1"],
            4,
            "--start-world -10.01,0 lies outside the map, which spans x from -10 to 9.2 and y from -10 to 9.2",
        ),
        (
            vec![SANDBOX, "--start-world", "-1.5,-0.5", "--goal-world", "9.21,1"],
            4,
            "--goal-world 9.21,1 lies outside the map",
        ),
        // A huge number is written short (it was written with its 301 digits).
        (
            vec![SANDBOX, "--start-world", "1e300,0", "--goal-world", "1,1"],
            4,
            "--start-world 1e300,0 lies outside the map",
        ),
        (
            vec!["maps/paper/map10.map", "--start-world", "1,1", "--goal-world", "2,2"],
            2,
            "--start-world is a point of a ROS map's map frame, and maps/paper/map10.map has none",
        ),
        (
            vec![SANDBOX, "--start-world", "1,nan", "--goal-world", "2,2"],
            2,
            "\"nan\" is not a finite number of metres",
        ),
        (
            vec![SANDBOX, "--start-world", "1,1", "--start", "3,3", "--goal", "2,2"],
            2,
            "cannot be used with",
        ),
        (
            vec![SANDBOX, "--start-world", "-1.5,-0.5"],
            2,
            "--start and --goal go together",
        ),
    ] {
        let mut all = vec!["plan", "--planner", "astar"];
        all.extend(&args);
        let (got, out, err) = gridplan(&all);
        assert_eq!(got, code, "{args:?}: {err}");
        assert!(err.contains(message), "{args:?}: {err}");
        assert!(out.is_empty(), "{args:?}: {out}");
    }
}

/// Points in metres on a YAML whose resolution places no cell: the error says why the
/// frame is unusable (it said the map had no frame and asked for a map_server .yaml map,
/// which it was).
#[test]
fn points_on_a_yaml_without_a_usable_frame_say_why() {
    let dir = common::scratch("frame", "unusable");
    std::fs::copy(
        root().join("maps/ros-nav2/tb3_sandbox.pgm"),
        dir.join("tb3_sandbox.pgm"),
    )
    .unwrap();
    let yaml = dir.join("zero.yaml");
    std::fs::write(
        &yaml,
        "image: tb3_sandbox.pgm\nresolution: 0\norigin: [0, 0, 0]\nnegate: 0\noccupied_thresh: 0.65\nfree_thresh: 0.196\n",
    )
    .unwrap();
    let yaml = yaml.display().to_string();
    let (code, out, err) = gridplan(&[
        "plan",
        "--planner",
        "astar",
        &yaml,
        "--start-world",
        "1,1",
        "--goal-world",
        "2,2",
    ]);
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("--start-world is a point of the map frame, and the map frame of")
            && err.contains("is unusable (resolution 0 is not positive"),
        "{err}"
    );
    assert!(out.is_empty(), "{out}");
}

/// A config's `points`: start-goal pairs in metres, run as the cells holding them (the
/// same runs as `pairs` of those cells), and refused with the key's position off the map
/// or on a map without a frame.
#[test]
fn a_map_sets_points_are_the_cells_holding_them() {
    let dir = common::scratch("frame", "points");
    for file in ["tb3_sandbox.yaml", "tb3_sandbox.pgm"] {
        std::fs::copy(root().join("maps/ros-nav2").join(file), dir.join(file)).unwrap();
    }
    std::fs::copy(root().join("maps/paper/map10.map"), dir.join("map10.map")).unwrap();
    let config = |map: &str, problems: &str| {
        format!("name = \"w\"\n[[maps]]\nfiles = [\"{map}\"]\n{problems}\n[planners.a]\nplanner = \"astar\"\n")
    };
    let points = "points = [{ start = [-1.5, -0.5], goal = [1.5, 0.5] }, { start = [-1.51, -0.51], goal = [1.5, 0.5] }]";
    let pairs = "pairs = [{ start = [170, 193], goal = [230, 173] }, { start = [169, 194], goal = [230, 173] }]";
    std::fs::write(dir.join("points.toml"), config("tb3_sandbox.yaml", points)).unwrap();
    std::fs::write(dir.join("pairs.toml"), config("tb3_sandbox.yaml", pairs)).unwrap();
    for name in ["points", "pairs"] {
        let out = common::gridplan(
            &dir,
            &[
                "experiment",
                &format!("{name}.toml"),
                "--output",
                name,
                "--quiet",
            ],
        );
        common::succeeded(&out);
    }
    let table = |name: &str| std::fs::read_to_string(dir.join(name).join("runs.csv")).unwrap();
    // Every column but the timings.
    let columns = |text: String| -> Vec<String> {
        text.lines()
            .map(|l| l.split(',').take(16).collect::<Vec<_>>().join(","))
            .collect()
    };
    let (by_points, by_pairs) = (columns(table("points")), columns(table("pairs")));
    assert_eq!(by_points, by_pairs);
    assert!(
        by_points[1].starts_with("tb3_sandbox.yaml,1,170,193,230,173,a,astar,"),
        "{by_points:?}"
    );

    let off = points.replace("goal = [1.5, 0.5] }]", "goal = [9.5, 0.5] }]");
    std::fs::write(dir.join("off.toml"), config("tb3_sandbox.yaml", &off)).unwrap();
    std::fs::write(dir.join("frameless.toml"), config("map10.map", points)).unwrap();
    let nan = points.replace("start = [-1.5, -0.5]", "start = [nan, -0.5]");
    std::fs::write(dir.join("nan.toml"), config("tb3_sandbox.yaml", &nan)).unwrap();
    for (name, message) in [
        ("off", "off.toml:4:56: maps[0]: key `points`: the goal [9.5, 0.5] lies outside tb3_sandbox.yaml, which spans x from -10 to 9.2"),
        ("frameless", "frameless.toml:4:10: maps[0]: key `points`: points are metres of a ROS map's map frame, and map10.map has none"),
        ("nan", "nan.toml:4:11: maps[0]: key `points`: the start [NaN, -0.5] is not a point: its coordinates must be finite"),
    ] {
        let out = common::gridplan(&dir, &["experiment", &format!("{name}.toml"), "--output", name]);
        common::refused(&out, 3, message);
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

/// A 6 x 4 trinary map_server map: `#` occupied (0 in the image), `?` unknown (205), `.`
/// free (254); rows top first, as the image stores them.
const ROWS: [&str; 4] = ["..?...", "..#??.", "......", "?....."];

/// The `(x, y)` of the cells the grey rectangles of an SVG figure cover (in cells: the
/// map is drawn in a group scaled to one unit a cell), row by row.
fn unknown_cells(svg: &str) -> Vec<(String, String)> {
    let doc = roxmltree::Document::parse(svg).unwrap();
    let number =
        |r: roxmltree::Node, key: &str| -> u32 { r.attribute(key).unwrap().parse().unwrap() };
    doc.descendants()
        .filter(|n| n.attribute("class") == Some("unknown"))
        .flat_map(|g| g.children().filter(|c| c.has_tag_name("rect")))
        .flat_map(|r| {
            let (x, y) = (number(r, "x"), number(r, "y"));
            let (w, h) = (number(r, "width"), number(r, "height"));
            (y..y + h).flat_map(move |y| (x..x + w).map(move |x| (x.to_string(), y.to_string())))
        })
        .collect()
}

/// A ROS map's unknown cells (occupancy -1) are drawn grey, apart from its walls, with
/// their key line, in a sweep's figures and in `plan --svg` alike (they were drawn as
/// walls: the mask never reached the figures).
#[test]
fn unknown_cells_of_a_ros_map_are_grey_in_sweep_and_plan_figures() {
    let dir = common::scratch("unknown-cells", "ros");
    planner_testkit::write_ros_map(&dir, "m", &ROWS);
    std::fs::write(
        dir.join("c.toml"),
        "name = \"unknown\"\n[[maps]]\nfiles = [\"m.yaml\"]\n\
         pairs = [{ start = [0, 0], goal = [5, 2] }]\n[planners.astar]\nplanner = \"astar\"\n",
    )
    .unwrap();
    let expect: Vec<(String, String)> = ROWS
        .iter()
        .enumerate()
        .flat_map(|(y, row)| {
            row.char_indices()
                .filter(|&(_, c)| c == '?')
                .map(move |(x, _)| (x.to_string(), y.to_string()))
        })
        .collect();
    assert_eq!(expect.len(), 4);
    let sweep = common::gridplan(
        &dir,
        &["experiment", "c.toml", "--output", "out", "--quiet"],
    );
    common::succeeded(&sweep);
    let plan = common::gridplan(
        &dir,
        &[
            "plan",
            "m.yaml",
            "--planner",
            "astar",
            "--start",
            "0,0",
            "--goal",
            "5,2",
            "--svg",
            "p.svg",
        ],
    );
    common::succeeded(&plan);
    for file in ["out/figures/m-1.svg", "p.svg"] {
        let svg = std::fs::read_to_string(dir.join(file)).unwrap();
        assert_eq!(unknown_cells(&svg), expect, "{file}");
        assert!(svg.contains(">unknown</text>"), "{file}: no key line");
    }
}
