//! Every parser error path, through one data-driven `check`.
//!
//! Columns were counted by hand on the input strings (1-based, in characters); where a
//! line is long the count is spelled out next to the case.

use std::path::{Path, PathBuf};

use planner_api::{Cell, Grid};
use planner_maps::{
    parse_matrix, parse_movingai, parse_scenarios, parse_seed003, read_map, read_scenarios,
    MapError, Scenario,
};

#[derive(Clone, Copy, Debug)]
enum Format {
    MovingAi,
    Scen,
    Txt,
    Csv,
}

fn parse(format: Format, input: &str) -> Result<(), MapError> {
    match format {
        Format::MovingAi => parse_movingai(input, "t.map").map(drop),
        Format::Scen => parse_scenarios(input, "t.scen").map(drop),
        Format::Txt => parse_seed003(input, "t.txt").map(drop),
        Format::Csv => parse_matrix(input, "t.csv").map(drop),
    }
}

/// `input` in `format` must fail with exactly the message `expect`.
fn check(format: Format, input: &str, expect: &str) {
    match parse(format, input) {
        Ok(()) => panic!("{format:?} {input:?}: parsed, expected error {expect:?}"),
        Err(err) => assert_eq!(err.to_string(), expect, "{format:?} input {input:?}"),
    }
}

const HEAD: &str = "type octile\nheight 2\nwidth 3\nmap\n"; // rows start on line 5

#[test]
fn movingai_errors() {
    use Format::MovingAi as M;
    let header_eof = "expected a header ('type octile', 'height H', 'width W') ended by 'map', found end of file";
    check(M, "", &format!("t.map:1:1: {header_eof}"));
    check(
        M,
        "type octile\nheight 2\nwidth 2\n",
        &format!("t.map:4:1: {header_eof}"),
    );
    check(
        M,
        "type octile\nheigth 2\n",
        "t.map:2:1: expected 'type', 'height', 'width' or 'map', found 'heigth'",
    );
    check(
        M,
        "type octile\nheight\n",
        "t.map:2:7: expected a value after 'height', found end of line",
    );
    check(
        M,
        "type octile\nheight 2 3\n",
        "t.map:2:10: expected end of line after the height value, found '3'",
    );
    check(
        M,
        "type octile\nheight 2\nheight 3\n",
        "t.map:3:1: duplicate header key 'height', already given on line 2",
    );
    check(
        M,
        "type octile\ntype octile\n",
        "t.map:2:1: duplicate header key 'type', already given on line 1",
    );
    check(
        M,
        "type tile\n",
        "t.map:1:6: expected 'octile' as the type, found 'tile'",
    );
    check(
        M,
        "type octile\nheight abc\n",
        "t.map:2:8: expected an integer for height, found 'abc'",
    );
    check(
        M,
        "type octile\nwidth 1.5\n",
        "t.map:2:7: expected an integer for width, found '1.5'",
    );
    check(
        M,
        "type octile\nheight -3\n",
        "t.map:2:8: expected a non-negative integer for height, found '-3'",
    );
    check(
        M,
        "type octile\nheight +3\n",
        "t.map:2:8: expected an integer for height, found '+3'",
    );
    check(
        M,
        "type octile\nheight 99999999999\n",
        "t.map:2:8: height 99999999999 is too large (at most 4294967295)",
    );
    check(
        M,
        "type octile\nheight 0\n",
        "t.map:2:8: expected a positive integer for height, found '0'",
    );
    check(
        M,
        "height 2\nwidth 2\nmap\n..\n..\n",
        "t.map:3:1: missing header key 'type' before 'map'",
    );
    check(
        M,
        "type octile\nwidth 2\nmap\n",
        "t.map:3:1: missing header key 'height' before 'map'",
    );
    check(
        M,
        "type octile\nheight 2\nmap\n",
        "t.map:3:1: missing header key 'width' before 'map'",
    );
    check(
        M,
        "type octile\nheight 1\nwidth 1\nmap extra\n.\n",
        "t.map:4:5: expected end of line after 'map', found 'extra'",
    );
    // 65536 * 65536 = 2^32 cells > the default limit of 2^31 cells (the largest grid).
    check(
        M,
        "type octile\nheight 65536\nwidth 65536\nmap\n",
        "t.map:4:1: a 65536x65536 map has 4294967296 cells, more than the limit of 2147483648 cells",
    );
    // 16384 * 16384 = 2^28 cells is allowed; the missing rows are reported, nothing is allocated.
    check(
        M,
        "type octile\nheight 16384\nwidth 16384\nmap\n",
        "t.map:5:1: expected 16384 rows (height 16384), found 0",
    );
    // Too few rows: with a trailing newline (line 7 is the empty last line) and without.
    check(
        M,
        "type octile\nheight 3\nwidth 2\nmap\n..\n..\n",
        "t.map:7:1: expected 3 rows (height 3), found 2",
    );
    check(
        M,
        "type octile\nheight 3\nwidth 2\nmap\n..\n..",
        "t.map:6:3: expected 3 rows (height 3), found 2",
    );
    check(
        M,
        "type octile\nheight 3\nwidth 2\nmap\n..\n..\n\n  \n",
        "t.map:7:1: expected 3 rows (height 3), found 2",
    );
    // Too many rows.
    check(
        M,
        &format!("{HEAD}...\n...\n...\n"),
        "t.map:7:1: expected end of file after the last row (height 2), found '...'",
    );
    check(
        M,
        &format!("{HEAD}...\n...\n\n  @@\n"),
        "t.map:8:3: expected end of file after the last row (height 2), found '@@'",
    );
    // Short and long rows; a blank line inside the rows is a short row.
    check(
        M,
        &format!("{HEAD}...\n..\n"),
        "t.map:6:3: expected 3 cells (width 3), found 2",
    );
    check(
        M,
        &format!("{HEAD}....\n...\n"),
        "t.map:5:4: expected 3 cells (width 3), found 4",
    );
    check(
        M,
        &format!("{HEAD}\n...\n"),
        "t.map:5:1: expected 3 cells (width 3), found 0",
    );
    // Unknown symbols, including '#' and a space.
    let symbols = "expected one of '.', 'G', 'S' (passable) or '@', 'O', 'T', 'W' (blocked)";
    check(
        M,
        &format!("{HEAD}.x.\n...\n"),
        &format!("t.map:5:2: {symbols}, found 'x'"),
    );
    check(
        M,
        &format!("{HEAD}...\n..#\n"),
        &format!("t.map:6:3: {symbols}, found '#'"),
    );
    check(
        M,
        &format!("{HEAD}...\n. .\n"),
        &format!("t.map:6:2: {symbols}, found ' '"),
    );
    check(
        M,
        &format!("{HEAD}...\n.\t.\n"),
        &format!("t.map:6:2: {symbols}, found '\\t'"),
    );
    check(
        M,
        &format!("{HEAD}..é\n...\n"),
        &format!("t.map:5:3: {symbols}, found 'é'"),
    );
}

#[test]
fn scenario_errors() {
    use Format::Scen as S;
    let version = "expected 'version 1' on the first line";
    check(S, "", &format!("t.scen:1:1: {version}, found end of file"));
    check(
        S,
        "\nversion 1\n",
        &format!("t.scen:1:1: {version}, found a blank line"),
    );
    check(
        S,
        "verison 1\n",
        &format!("t.scen:1:1: {version}, found 'verison'"),
    );
    check(
        S,
        "0\tmaps/a.map\t2\t2\t0\t0\t1\t1\t1\n",
        &format!("t.scen:1:1: {version}, found '0'"),
    );
    check(
        S,
        "version\n",
        "t.scen:1:8: expected a version number after 'version', found end of line",
    );
    check(
        S,
        "version 2\n",
        "t.scen:1:9: expected version 1 or 1.0, found '2'",
    );
    check(
        S,
        "version 1 x\n",
        "t.scen:1:11: expected end of line after the version, found 'x'",
    );
    // A good line is "0\ta.map\t2\t2\t0\t0\t1\t1\t1": fields start at columns
    // 1, 3, 9, 11, 13, 15, 17, 19, 21 (each field one character except "a.map").
    let line = |fields: [&str; 9]| format!("version 1\n{}\n", fields.join("\t"));
    let good = ["0", "a.map", "2", "2", "0", "0", "1", "1", "1"];
    let with = |index: usize, value: &str| {
        let mut fields = good;
        fields[index] = value;
        line(fields)
    };
    assert!(parse_scenarios(&line(good), "t.scen").is_ok());
    // 8 fields: the line is 19 characters long, so the error is at column 20.
    check(
        S,
        "version 1\n0\ta.map\t2\t2\t0\t0\t1\t1\n",
        "t.scen:2:20: expected 9 tab-separated fields, found 8",
    );
    // 10 fields: the 10th starts at column 23.
    check(
        S,
        "version 1\n0\ta.map\t2\t2\t0\t0\t1\t1\t1\t5\n",
        "t.scen:2:23: expected 9 tab-separated fields, found 10",
    );
    check(
        S,
        "version 1\n0\ta.map\t2\t2\t0\t0\t1\t1\t1\t\n",
        "t.scen:2:23: expected 9 tab-separated fields, found 10",
    );
    // Spaces instead of tabs: one field of 21 characters.
    check(
        S,
        "version 1\n0 a.map 2 2 0 0 1 1 1\n",
        "t.scen:2:22: expected 9 tab-separated fields, found 1",
    );
    check(
        S,
        &with(0, "x"),
        "t.scen:2:1: expected an integer for bucket, found 'x'",
    );
    check(
        S,
        &with(1, ""),
        "t.scen:2:3: expected a map name, found an empty field",
    );
    check(
        S,
        &with(2, ""),
        "t.scen:2:9: expected an integer for width, found an empty field",
    );
    check(
        S,
        &with(3, "2.0"),
        "t.scen:2:11: expected an integer for height, found '2.0'",
    );
    check(
        S,
        &with(4, "-1"),
        "t.scen:2:13: expected a non-negative integer for start x, found '-1'",
    );
    check(
        S,
        &with(5, "y"),
        "t.scen:2:15: expected an integer for start y, found 'y'",
    );
    check(
        S,
        &with(6, "4294967296"),
        "t.scen:2:17: goal x 4294967296 is too large (at most 4294967295)",
    );
    check(
        S,
        &with(7, "-7"),
        "t.scen:2:19: expected a non-negative integer for goal y, found '-7'",
    );
    // Spaces around a value are tolerated; the column points at the value.
    check(
        S,
        &with(7, "  z"),
        "t.scen:2:21: expected an integer for goal y, found 'z'",
    );
    let length = "expected a non-negative number for the optimal length";
    check(
        S,
        &with(8, "abc"),
        &format!("t.scen:2:21: {length}, found 'abc'"),
    );
    check(
        S,
        &with(8, "-1.5"),
        &format!("t.scen:2:21: {length}, found '-1.5'"),
    );
    check(
        S,
        &with(8, "nan"),
        &format!("t.scen:2:21: {length}, found 'nan'"),
    );
    check(
        S,
        &with(8, "inf"),
        &format!("t.scen:2:21: {length}, found 'inf'"),
    );
    check(
        S,
        &with(8, "1e999"),
        &format!("t.scen:2:21: {length}, found '1e999'"),
    );
    check(
        S,
        &with(8, ""),
        &format!("t.scen:2:21: {length}, found an empty field"),
    );
    // The error names the line, after blank lines and good lines.
    let text = format!("{}\n{}", line(good), "0\ta.map\t2\t2\t0\t0\t1\t1\tx\n");
    check(S, &text, &format!("t.scen:4:21: {length}, found 'x'"));
}

#[test]
fn seed003_errors() {
    use Format::Txt as T;
    check(
        T,
        "",
        "t.txt:1:1: expected map rows of '.' and 'X', found end of file",
    );
    check(
        T,
        "# Map 1\n# Start: (0,0) Goal: (1,1)\n",
        "t.txt:3:1: expected map rows of '.' and 'X', found end of file",
    );
    check(T, "..\n.Q\n", "t.txt:2:2: expected '.' or 'X', found 'Q'");
    // '#' inside a row is no obstacle; lowercase 'x' is not 'X'; a leading space is no cell.
    check(T, ".#\n", "t.txt:1:2: expected '.' or 'X', found '#'");
    check(T, "..\n.x\n", "t.txt:2:2: expected '.' or 'X', found 'x'");
    check(T, " ..\n", "t.txt:1:1: expected '.' or 'X', found ' '");
    check(
        T,
        "...\n..\n",
        "t.txt:2:3: expected 3 cells (as in the first row, line 1), found 2",
    );
    check(
        T,
        "# c\n\n..\n...\n",
        "t.txt:4:3: expected 2 cells (as in the first row, line 3), found 3",
    );
    check(T, "..\n\n..\n", "t.txt:2:1: expected no blank line between map rows (rows continue on line 3), found a blank line");
    // Pair lines. "# Start: (0,0) Goal: (1,1)": '(' at 10, x at 11, ',' at 12, y at 13,
    // ')' at 14, "Goal:" at 16, '(' at 22, x at 23, ',' at 24, y at 25, ')' at 26.
    let pair = |line: &str| format!("{line}\n..\n..\n");
    check(
        T,
        &pair("# Start: 0,0) Goal: (1,1)"),
        "t.txt:1:10: expected '(', found '0'",
    );
    check(
        T,
        &pair("# Start: (a,0) Goal: (1,1)"),
        "t.txt:1:11: expected an integer for start x, found 'a'",
    );
    check(
        T,
        &pair("# Start: (,0) Goal: (1,1)"),
        "t.txt:1:11: expected an integer for start x, found ','",
    );
    check(
        T,
        &pair("# Start: (-,0) Goal: (1,1)"),
        "t.txt:1:11: expected an integer for start x, found '-'",
    );
    check(
        T,
        &pair("# Start: (-1,0) Goal: (1,1)"),
        "t.txt:1:11: expected a non-negative integer for start x, found '-1'",
    );
    check(
        T,
        &pair("# Start: (0;0) Goal: (1,1)"),
        "t.txt:1:12: expected ',', found ';'",
    );
    check(
        T,
        &pair("# Start: (0,) Goal: (1,1)"),
        "t.txt:1:13: expected an integer for start y, found ')'",
    );
    check(
        T,
        &pair("# Start: (0,0 Goal: (1,1)"),
        "t.txt:1:15: expected ')', found 'G'",
    );
    check(
        T,
        &pair("# Start: (0,0) Gaol: (1,1)"),
        "t.txt:1:16: expected 'Goal:', found 'Gaol:'",
    );
    check(
        T,
        &pair("# Start: (0,0)"),
        "t.txt:1:15: expected 'Goal:', found end of line",
    );
    check(
        T,
        &pair("# Start: (0,0) | | Goal: (1,1)"),
        "t.txt:1:18: expected 'Goal:', found '|'",
    );
    check(
        T,
        &pair("# Start: (0,0) Goal: 1,1)"),
        "t.txt:1:22: expected '(', found '1'",
    );
    check(
        T,
        &pair("# Start: (0,0) Goal: (1,99999999999)"),
        "t.txt:1:25: goal y 99999999999 is too large (at most 4294967295)",
    );
    check(
        T,
        &pair("# Start: (0,0) Goal: (1,1"),
        "t.txt:1:26: expected ')', found end of line",
    );
    check(
        T,
        &pair("# Start: (0,0) Goal: (1,1) extra"),
        "t.txt:1:28: expected end of line after the goal, found 'extra'",
    );
    // The numbered style: "# 2. Start: (4,1) | Goal: (0,x)" has the goal's y at column 30.
    check(
        T,
        &pair("# 2. Start: (4,1) | Goal: (0,x)"),
        "t.txt:1:30: expected an integer for goal y, found 'x'",
    );
}

#[test]
fn matrix_errors() {
    use Format::Csv as C;
    check(
        C,
        "",
        "t.csv:1:1: expected rows of '0' and '1', found end of file",
    );
    check(
        C,
        "# header only\n",
        "t.csv:2:1: expected rows of '0' and '1', found end of file",
    );
    check(C, "1,2\n", "t.csv:1:3: expected '0' or '1', found '2'");
    check(C, "1,,0\n", "t.csv:1:3: expected '0' or '1', found ','");
    check(
        C,
        "1,0,\n",
        "t.csv:1:5: expected '0' or '1', found end of line",
    );
    check(C, ",1\n", "t.csv:1:1: expected '0' or '1', found ','");
    check(C, "10 1\n", "t.csv:1:1: expected '0' or '1', found '10'");
    check(
        C,
        "1 0 1\n1 0 -1\n",
        "t.csv:2:5: expected '0' or '1', found '-1'",
    );
    // Short row: "1 0" ends at column 3, so the error points at column 4.
    check(
        C,
        "1 0 1\n1 0\n",
        "t.csv:2:4: expected 3 cells (as in the first row, line 1), found 2",
    );
    // Long row: the third value of "1,0,1" is at column 5.
    check(
        C,
        "1,0\n1,0,1\n",
        "t.csv:2:5: expected 2 cells (as in the first row, line 1), found 3",
    );
    check(C, "1\n\n1\n", "t.csv:2:1: expected no blank line between matrix rows (rows continue on line 3), found a blank line");
}

fn tmp(name: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("planner-maps-errors");
    std::fs::create_dir_all(&dir).unwrap();
    dir.join(name)
}

#[test]
fn file_errors() {
    let map_list = "expected one of .map (Moving AI), .txt (seed 003), .csv (0/1 matrix), .yaml/.yml (ROS map_server), .pgm/.png (an occupancy image); .scen files hold scenarios, not maps";
    let err = read_map(Path::new("maps/x.gif")).unwrap_err();
    assert_eq!(
        err.to_string(),
        format!("maps/x.gif: unsupported file extension '.gif', {map_list}")
    );
    let err = read_map(Path::new("maps/noext")).unwrap_err();
    assert_eq!(
        err.to_string(),
        format!("maps/noext: unsupported file extension none, {map_list}")
    );
    let err = read_map(Path::new("maps/a.map.scen")).unwrap_err();
    assert_eq!(
        err.to_string(),
        format!("maps/a.map.scen: unsupported file extension '.scen', {map_list}")
    );
    let err = read_scenarios(Path::new("maps/a.map")).unwrap_err();
    assert_eq!(
        err.to_string(),
        "maps/a.map: unsupported file extension '.map', expected .scen"
    );

    let missing = tmp("missing.map");
    let err = read_map(&missing).unwrap_err();
    assert_eq!((err.line, err.column), (0, 0));
    assert!(
        err.to_string()
            .starts_with(&format!("{}: cannot read the file: ", missing.display())),
        "{err}"
    );

    // Invalid UTF-8: the error names the byte's position (line 2, column 2).
    let bad = tmp("bad.txt");
    std::fs::write(&bad, b"..\n.\xff\n").unwrap();
    let err = read_map(&bad).unwrap_err();
    assert_eq!(
        err.to_string(),
        format!(
            "{}:2:2: expected UTF-8 text, found byte 0xff",
            bad.display()
        )
    );

    // A parse error through read_map names the path.
    let q = tmp("q.txt");
    std::fs::write(
        &q,
        "# Map\n\n..........\n..........\n..........\n..........\n.........Q\n",
    )
    .unwrap();
    let err = read_map(&q).unwrap_err();
    assert_eq!(
        err.to_string(),
        format!("{}:7:10: expected '.' or 'X', found 'Q'", q.display())
    );
}

#[test]
fn scenario_size_mismatch_names_the_line() {
    let grid = Grid::new(2, 2).unwrap();
    let scenario = Scenario {
        bucket: 0,
        map: "a.map".to_owned(),
        width: 3,
        height: 2,
        start: Cell::new(0, 0),
        goal: Cell::new(1, 1),
        optimal_length: 1.5,
        line: 7,
        size_column: 12,
    };
    let err = scenario.check_size(&grid, "a.map.scen").unwrap_err();
    assert_eq!(
        err.to_string(),
        "a.map.scen:7:12: the scenario is for a 3x2 map, but the grid is 2x2"
    );
    assert!(scenario
        .check_size(&Grid::new(3, 2).unwrap(), "a.map.scen")
        .is_ok());
}

/// A GPPC scenario's patch file that cannot be read is an error at the scenario's line and
/// column that name it (the `patch` line's value), with the path it resolves to; errors in
/// a patch file that is read name the patch file.
#[test]
fn a_patch_file_that_cannot_be_read_is_an_error_at_the_scenario_line() {
    use planner_maps::gppc::parse_gppc_scenario;
    use planner_maps::MapErrorKind;
    let scen_path = tmp("patched.scen");
    let text =
        "version 2\nheight 1\nwidth 2\ncost 1 octile\npatch  nope.patch\ncommands\nP 0 0 0 0\n";
    std::fs::write(&scen_path, text).unwrap();
    let scen_name = scen_path.display().to_string();
    let scenario = parse_gppc_scenario(text, &scen_name).unwrap();
    assert_eq!(scenario.patch_file_at, (5, 8));
    let patch_path = tmp("nope.patch");
    let _ = std::fs::remove_file(&patch_path);
    let err = scenario.read_patches(&scen_path, 1 << 20).unwrap_err();
    assert_eq!(
        (err.file.as_str(), err.line, err.column),
        (scen_name.as_str(), 5, 8)
    );
    assert!(
        matches!(&err.kind, MapErrorKind::NamedFile { what: "patch file", reason, .. }
            if matches!(**reason, MapErrorKind::Io { .. })),
        "{err}"
    );
    assert!(
        err.to_string().starts_with(&format!(
            "{scen_name}:5:8: patch file 'nope.patch' ({}): cannot read the file: ",
            patch_path.display()
        )),
        "{err}"
    );
    // Larger than the limit: the same place.
    std::fs::write(
        &patch_path,
        "type patch\npatches 1\npatch 0\nheight 1\nwidth 2\nmap\n.@\n",
    )
    .unwrap();
    let err = scenario.read_patches(&scen_path, 10).unwrap_err();
    assert_eq!((err.line, err.column), (5, 8), "{err}");
    assert!(
        err.to_string()
            .contains(": the file has 53 bytes, more than the limit of 10 bytes"),
        "{err}"
    );
    // Read: the patches; an error in the patch file's text names the patch file.
    let patches = scenario.read_patches(&scen_path, 1 << 20).unwrap();
    assert_eq!(patches.patches[0].free, [true, false]);
    std::fs::write(
        &patch_path,
        "type patch\npatches 1\npatch 0\nheight 1\nwidth 2\nmap\n.Q\n",
    )
    .unwrap();
    let err = scenario.read_patches(&scen_path, 1 << 20).unwrap_err();
    assert_eq!(
        err.to_string(),
        format!(
            "{}:7:2: expected a Moving AI map symbol ('.', 'G', 'S', '@', 'O', 'T', 'W'), found 'Q'",
            patch_path.display()
        )
    );
}
