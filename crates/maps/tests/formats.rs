//! What each parser accepts, on small inline inputs whose grids are drawn with
//! `Grid::from_ascii` (`.` free, `#` blocked) for comparison.

use planner_api::{Cell, Grid};
use planner_maps::{
    movingai_passable, parse_matrix, parse_movingai, parse_scenarios, parse_seed003, to_movingai,
    MapFormat, ProblemSpec,
};

fn ascii(text: &str) -> Grid {
    Grid::from_ascii(text).unwrap()
}

/// `input` parsed as a Moving AI map must equal `expect` (ASCII).
fn check_movingai(input: &str, expect: &str) {
    let grid = parse_movingai(input, "t.map").unwrap_or_else(|e| panic!("{input:?}: {e}"));
    assert_eq!(grid, ascii(expect), "input {input:?}");
}

#[test]
fn movingai_accepts() {
    let expect = "..#\n#..";
    check_movingai("type octile\nheight 2\nwidth 3\nmap\n..@\n@..\n", expect);
    // Keys in any order, blank header lines, extra spaces, no final newline.
    check_movingai("width 3\n\nheight   2\ntype octile\nmap\n..@\n@..", expect);
    // CRLF, and trailing blank lines.
    check_movingai(
        "type octile\r\nheight 2\r\nwidth 3\r\nmap\r\n..@\r\n@..\r\n\r\n",
        expect,
    );
    check_movingai(
        "type octile\nheight 2\nwidth 3\nmap\n..@\n@..\n\n\n  \n",
        expect,
    );
    // Every symbol: . G S passable, @ O T W blocked.
    check_movingai(
        "type octile\nheight 2\nwidth 4\nmap\n.GS.\n@OTW\n",
        "....\n####",
    );
    for (symbol, passable) in [
        ('.', true),
        ('G', true),
        ('S', true),
        ('@', false),
        ('O', false),
        ('T', false),
        ('W', false),
    ] {
        assert_eq!(movingai_passable(symbol), Some(passable), "{symbol}");
    }
    assert_eq!(movingai_passable('#'), None);
}

#[test]
fn movingai_writer_round_trips() {
    // A seeded LCG (Knuth's MMIX constants) draws grids of assorted sizes and densities.
    let mut state: u64 = 0x5eed;
    let mut next = move || {
        state = state
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (state >> 33) as u32
    };
    for _ in 0..50 {
        let (w, h) = (1 + next() % 40, 1 + next() % 40);
        let density = next() % 100;
        let free: Vec<bool> = (0..w * h).map(|_| next() % 100 >= density).collect();
        let grid = Grid::from_free_cells(w, h, free).unwrap();
        let text = to_movingai(&grid);
        assert_eq!(parse_movingai(&text, "gen.map").unwrap(), grid);
        assert_eq!(text.lines().count(), 4 + h as usize);
    }
}

#[test]
fn seed003_both_pair_styles() {
    let grid = ascii("..#\n...\n#..");
    // The real files' style: numbered, '|' between start and goal, blank line before rows.
    let real = "# Map 1\n# Start goal pairs:\n# 1. Start: (0,0) | Goal: (2,2)\n# 1. Start: (2,1) | Goal: (0,1)\n\n..X\n...\nX..\n";
    // The report's style, with spaces inside the pairs and no blank line.
    let report = "# Start goal pairs:\n# Start: (0, 0) Goal: (2, 2)\n#Start:(2,1)Goal:(0,1)\n..X\n...\nX..\n";
    let spec = |sx, sy, gx, gy, line| ProblemSpec {
        start: Cell::new(sx, sy),
        goal: Cell::new(gx, gy),
        line,
    };
    let file = parse_seed003(real, "real.txt").unwrap();
    assert_eq!(file.grid, grid);
    assert_eq!(file.format, MapFormat::Seed003);
    assert_eq!(
        file.problems,
        vec![spec(0, 0, 2, 2, 3), spec(2, 1, 0, 1, 4)]
    );
    let file = parse_seed003(report, "report.txt").unwrap();
    assert_eq!(file.grid, grid);
    assert_eq!(
        file.problems,
        vec![spec(0, 0, 2, 2, 2), spec(2, 1, 0, 1, 3)]
    );
    // CRLF, trailing whitespace, comments after the rows, trailing blank lines.
    let crlf = "# 1) Start: (0,0) | Goal: (2,2)  \r\n..X \r\n...\r\nX..\t\r\n# end\r\n\r\n\r\n";
    let file = parse_seed003(crlf, "crlf.txt").unwrap();
    assert_eq!(file.grid, grid);
    assert_eq!(file.problems, vec![spec(0, 0, 2, 2, 1)]);
    // Other comments, even with digits or the word "Start", are not pairs.
    let file = parse_seed003(
        "# 2024 notes\n# Start goal pairs:\n# Starting: here\n.\n",
        "c.txt",
    )
    .unwrap();
    assert!(file.problems.is_empty());
    assert_eq!(file.grid, ascii("."));
}

#[test]
fn matrix_accepts() {
    // 1 = traversable, 0 = obstacle (seed 000 equation (1)).
    let expect = ascii("..#\n#..");
    for input in [
        "1,1,0\n0,1,1\n",
        "1 1 0\n0 1 1",
        "1, 1, 0\r\n0 ,1\t1\r\n",
        "# occupancy, 1 = free\n\n  1 1,0\n0 1 1  \n\n",
    ] {
        assert_eq!(parse_matrix(input, "t.csv").unwrap(), expect, "{input:?}");
    }
    let file = MapFormat::Matrix.parse("1,0\n", "t.csv").unwrap();
    assert!(file.problems.is_empty());
    assert_eq!(file.grid, ascii(".#"));
}

#[test]
fn scenarios_accept() {
    // Both styles, "version 1.0", CRLF, blank lines between and after.
    let text = "version 1.0\r\n\
                0\tmaps/dao/x.map\t3\t2\t0\t0\t2\t1\t2.41421\r\n\
                \r\n\
                7\tx.map\t3\t2\t2\t1\t0\t0\t2.41421356\r\n\r\n\r\n";
    let scenarios = parse_scenarios(text, "x.map.scen").unwrap();
    assert_eq!(scenarios.len(), 2);
    let (a, b) = (&scenarios[0], &scenarios[1]);
    assert_eq!(
        (a.bucket, a.map.as_str(), a.map_name()),
        (0, "maps/dao/x.map", "x.map")
    );
    assert_eq!((a.width, a.height, a.line), (3, 2, 2));
    assert_eq!((a.start, a.goal), (Cell::new(0, 0), Cell::new(2, 1)));
    assert_eq!(a.optimal_length, 2.41421);
    assert_eq!((b.bucket, b.map_name(), b.line), (7, "x.map", 4));
    // The width's column, where a size mismatch points: after "0\tmaps/dao/x.map\t".
    assert_eq!((a.size_column, b.size_column), (18, 9));
    let small = Grid::new(2, 2).unwrap();
    assert_eq!(
        b.check_size(&small, "x.map.scen").unwrap_err().to_string(),
        "x.map.scen:4:9: the scenario is for a 3x2 map, but the grid is 2x2"
    );
    assert_eq!(b.optimal_length, 2.41421356);
    assert_eq!(
        b.problem_spec(),
        ProblemSpec {
            start: Cell::new(2, 1),
            goal: Cell::new(0, 0),
            line: 4
        }
    );
    // No scenarios at all is fine.
    assert!(parse_scenarios("version 1\n", "e.scen").unwrap().is_empty());
    // Serializes for result files.
    let json = serde_json::to_string(&b.problem_spec()).unwrap();
    assert_eq!(json, r#"{"start":[2,1],"goal":[0,0],"line":4}"#);
}
