//! The repository's real map files, end to end, and a no-panic fuzz test.
//!
//! Where the numbers come from:
//! - wpi: sizes, obstacle counts and pairs from maps/wpi/SOURCE.md, re-counted with
//!   `grep -v '^#' mapN.txt | grep -v '^$' | awk '{n+=gsub(/X/,"")} END{print n}'`
//!   (22, 64, 240); BFS lengths from the same SOURCE.md, checked here by a BFS of our own.
//! - paper: obstacle counts with `tail -n +5 mapNN.map | tr -cd '@' | wc -c`.
//! - movingai: sizes and scenario counts from maps/movingai/SOURCE.md; free cells with
//!   `tail -n +5 X.map | tr -d '\r\n' | fold -w1 | sort | uniq -c` (count of '.').
//! - arena's optimal lengths: the .scen file itself, against a Dijkstra written below.

use std::cmp::Reverse;
use std::collections::{BinaryHeap, VecDeque};
use std::path::PathBuf;

use planner_api::{Cell, Endpoint, Grid, Problem, ProblemError};
use planner_maps::{
    parse_matrix, parse_movingai, parse_scenarios, parse_seed003, read_map, read_scenarios,
    to_movingai, MapError, MapFormat, Scenario,
};

fn repo_file(relative: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../../maps")
        .join(relative)
}

fn read_text(relative: &str) -> String {
    std::fs::read_to_string(repo_file(relative)).unwrap()
}

// ---------------------------------------------------------------------------------------
// Independent reference searches (test code only).

/// 4-connected unit-cost BFS: number of moves, or None.
fn bfs4(grid: &Grid, start: Cell, goal: Cell) -> Option<u32> {
    let (w, h) = (grid.width() as i64, grid.height() as i64);
    let free = |x: i64, y: i64| {
        x >= 0 && y >= 0 && x < w && y < h && grid.is_free(Cell::new(x as u32, y as u32))
    };
    let mut dist = vec![u32::MAX; (w * h) as usize];
    let mut queue = VecDeque::new();
    dist[(start.y as i64 * w + start.x as i64) as usize] = 0;
    queue.push_back((start.x as i64, start.y as i64));
    while let Some((x, y)) = queue.pop_front() {
        let d = dist[(y * w + x) as usize];
        if (x, y) == (goal.x as i64, goal.y as i64) {
            return Some(d);
        }
        for (dx, dy) in [(1, 0), (-1, 0), (0, 1), (0, -1)] {
            let (nx, ny) = (x + dx, y + dy);
            if free(nx, ny) && dist[(ny * w + nx) as usize] == u32::MAX {
                dist[(ny * w + nx) as usize] = d + 1;
                queue.push_back((nx, ny));
            }
        }
    }
    None
}

/// 8-connected Dijkstra, costs 1 and sqrt 2, no corner cutting (a diagonal needs both
/// orthogonal neighbours free), as the Moving AI benchmark defines its optimal lengths.
fn octile_dijkstra(grid: &Grid, start: Cell, goal: Cell) -> Option<f64> {
    let (w, h) = (grid.width() as i64, grid.height() as i64);
    let free = |x: i64, y: i64| {
        x >= 0 && y >= 0 && x < w && y < h && grid.is_free(Cell::new(x as u32, y as u32))
    };
    let index = |x: i64, y: i64| (y * w + x) as usize;
    let mut dist = vec![f64::INFINITY; (w * h) as usize];
    // Non-negative f64s order like their bit patterns.
    let mut heap = BinaryHeap::new();
    dist[index(start.x as i64, start.y as i64)] = 0.0;
    heap.push(Reverse((0f64.to_bits(), start.x as i64, start.y as i64)));
    while let Some(Reverse((bits, x, y))) = heap.pop() {
        let d = f64::from_bits(bits);
        if d > dist[index(x, y)] {
            continue;
        }
        if (x, y) == (goal.x as i64, goal.y as i64) {
            return Some(d);
        }
        for dx in -1..=1 {
            for dy in -1..=1 {
                if (dx, dy) == (0, 0) || !free(x + dx, y + dy) {
                    continue;
                }
                let diagonal = dx != 0 && dy != 0;
                if diagonal && !(free(x + dx, y) && free(x, y + dy)) {
                    continue;
                }
                let nd = d + if diagonal {
                    std::f64::consts::SQRT_2
                } else {
                    1.0
                };
                let n = index(x + dx, y + dy);
                if nd < dist[n] {
                    dist[n] = nd;
                    heap.push(Reverse((nd.to_bits(), x + dx, y + dy)));
                }
            }
        }
    }
    None
}

fn n_blocked(grid: &Grid) -> usize {
    grid.len() - grid.n_free()
}

// ---------------------------------------------------------------------------------------
// WPI (seed 003) maps.

#[test]
fn wpi_maps() {
    // (file, cols, rows, obstacles, pairs with their lines, BFS lengths; None = blocked goal)
    type Pair = ((u32, u32), (u32, u32), usize, Option<u32>);
    let cases: [(&str, u32, u32, usize, [Pair; 3]); 3] = [
        (
            "map1.txt",
            10,
            10,
            22,
            [
                ((0, 0), (9, 9), 3, Some(18)),
                ((4, 1), (0, 9), 4, Some(14)),
                ((8, 7), (1, 0), 5, Some(16)),
            ],
        ),
        (
            "map2.txt",
            16,
            15,
            64,
            [
                ((0, 0), (14, 14), 3, Some(28)),
                ((3, 10), (12, 3), 4, None),
                ((13, 7), (0, 13), 5, Some(21)),
            ],
        ),
        (
            "map3.txt",
            50,
            20,
            240,
            [
                ((0, 0), (49, 19), 3, Some(70)),
                ((35, 5), (15, 16), 4, Some(39)),
                ((3, 2), (14, 12), 5, Some(41)),
            ],
        ),
    ];
    for (name, cols, rows, obstacles, pairs) in cases {
        let file = read_map(&repo_file(&format!("wpi/{name}"))).unwrap();
        assert_eq!(file.format, MapFormat::Seed003);
        assert_eq!(
            (file.grid.width(), file.grid.height()),
            (cols, rows),
            "{name}"
        );
        assert_eq!(n_blocked(&file.grid), obstacles, "{name}");
        assert_eq!(file.problems.len(), 3, "{name}");
        for (spec, (start, goal, line, bfs)) in file.problems.iter().zip(pairs) {
            assert_eq!(
                (spec.start, spec.goal, spec.line),
                (Cell::from(start), Cell::from(goal), line),
                "{name}"
            );
            match (spec.problem(&file.grid), bfs) {
                (Ok(problem), Some(moves)) => {
                    assert_eq!(
                        bfs4(&file.grid, problem.start(), problem.goal()),
                        Some(moves),
                        "{name} {spec:?}"
                    );
                }
                (Err(err), None) => assert_eq!(err.to_string(), "goal (12, 3) is blocked"),
                (other, _) => panic!("{name} {spec:?}: {other:?}"),
            }
        }
    }
}

#[test]
fn map2_blocked_goal_is_rejected_by_problem_new() {
    let file = read_map(&repo_file("wpi/map2.txt")).unwrap();
    let pair = file.problems[1];
    assert_eq!(
        (pair.start, pair.goal),
        (Cell::new(3, 10), Cell::new(12, 3))
    );
    let err = Problem::new(&file.grid, pair.start, pair.goal).unwrap_err();
    assert_eq!(
        err,
        ProblemError::Blocked {
            endpoint: Endpoint::Goal,
            cell: Cell::new(12, 3)
        }
    );
    assert_eq!(err.to_string(), "goal (12, 3) is blocked");
}

#[test]
fn wpi_crlf_and_report_style_read_alike() {
    let text = read_text("wpi/map1.txt");
    let file = parse_seed003(&text, "map1.txt").unwrap();
    let crlf = parse_seed003(&text.replace('\n', "\r\n"), "map1.txt").unwrap();
    assert_eq!(crlf, file);
    // The report's style: "# Start: (x,y) Goal: (x,y)", no numbers, no '|', no blank line.
    let report = text
        .replace("# 1. ", "# ")
        .replace("# 2. ", "# ")
        .replace("# 3. ", "# ")
        .replace(" | ", " ")
        .replace("\n\n", "\n");
    assert!(report.contains("# Start: (4,1) Goal: (0,9)\n# Start: (8,7) Goal: (1,0)\n..........\n"));
    let report = parse_seed003(&report, "map1-report.txt").unwrap();
    assert_eq!(report.grid, file.grid);
    let cells = |f: &planner_maps::MapFile| {
        f.problems
            .iter()
            .map(|p| (p.start, p.goal))
            .collect::<Vec<_>>()
    };
    assert_eq!(cells(&report), cells(&file));
}

// ---------------------------------------------------------------------------------------
// Seed 000's twelve paper maps.

#[test]
fn paper_maps() {
    let obstacles = [20, 12, 18, 19, 16, 13, 66, 73, 61, 65, 71, 61];
    for (i, &blocked) in obstacles.iter().enumerate() {
        let name = format!("paper/map{:02}.map", i + 1);
        let file = read_map(&repo_file(&name)).unwrap();
        assert_eq!(file.format, MapFormat::MovingAi);
        assert!(file.problems.is_empty());
        let n = if i < 6 { 6 } else { 12 };
        let grid = &file.grid;
        assert_eq!((grid.width(), grid.height()), (n, n), "{name}");
        assert_eq!(n_blocked(grid), blocked, "{name}");
        assert!(
            Problem::new(grid, Cell::new(0, 0), Cell::new(n - 1, n - 1)).is_ok(),
            "{name}"
        );
        // The writer reproduces these files byte for byte.
        assert_eq!(to_movingai(grid), read_text(&name), "{name}");
    }
}

// ---------------------------------------------------------------------------------------
// Moving AI maps and scenarios.

#[test]
fn movingai_maps_and_scenarios() {
    // (map, width, height, free cells, scenarios)
    let cases = [
        ("arena", 49, 49, 2054, 160),
        ("den520d", 256, 257, 28178, 888),
        ("random512-10-0", 512, 512, 235900, 1670),
        ("Berlin_0_256", 256, 256, 48147, 930),
        ("16room_000", 512, 512, 231854, 2010),
    ];
    for (name, width, height, n_free, n_scen) in cases {
        let map_path = repo_file(&format!("movingai/{name}.map"));
        let grid = read_map(&map_path).unwrap().grid;
        assert_eq!(
            (grid.width(), grid.height(), grid.n_free()),
            (width, height, n_free),
            "{name}"
        );
        let scen_path = repo_file(&format!("movingai/{name}.map.scen"));
        let scenarios = read_scenarios(&scen_path).unwrap();
        assert_eq!(scenarios.len(), n_scen, "{name}");
        for s in &scenarios {
            s.check_size(&grid, name).unwrap();
            assert_eq!(s.map_name(), format!("{name}.map"));
            assert!(
                s.problem_spec().problem(&grid).is_ok(),
                "{name} line {}",
                s.line
            );
            assert!(s.optimal_length >= 0.0);
        }
        // Lines are numbered from the file's first line ("version 1" is line 1).
        assert_eq!(scenarios[0].line, 2);
        assert!(scenarios.windows(2).all(|w| w[0].line < w[1].line));
        // The writer round-trips every real map.
        assert_eq!(
            parse_movingai(&to_movingai(&grid), "rt.map").unwrap(),
            grid,
            "{name}"
        );
    }
}

#[test]
fn scen_styles_and_trailing_blank_lines() {
    // Old style: directory in the map name, 5-6 significant digits.
    let arena = read_scenarios(&repo_file("movingai/arena.map.scen")).unwrap();
    let first = &arena[0];
    assert_eq!(
        (first.bucket, first.map.as_str(), first.width, first.height),
        (0, "maps/dao/arena.map", 49, 49)
    );
    assert_eq!(
        (first.start, first.goal, first.optimal_length),
        (Cell::new(1, 11), Cell::new(1, 12), 1.0)
    );
    let last = &arena[159];
    assert_eq!(
        (last.bucket, last.line, last.start, last.goal),
        (15, 161, Cell::new(1, 7), Cell::new(47, 46))
    );
    assert_eq!(last.optimal_length, 62.1543);
    // New style: bare map name, 8 decimals.
    let berlin = read_scenarios(&repo_file("movingai/Berlin_0_256.map.scen")).unwrap();
    let first = &berlin[0];
    assert_eq!((first.bucket, first.map.as_str()), (0, "Berlin_0_256.map"));
    assert_eq!(
        (first.start, first.goal, first.optimal_length),
        (Cell::new(248, 165), Cell::new(249, 164), 2.0)
    );
    // den520d ends with two blank lines: 891 lines, the last scenario on line 889.
    let den = read_scenarios(&repo_file("movingai/den520d.map.scen")).unwrap();
    assert_eq!((den.len(), den[887].line), (888, 889));
}

#[test]
fn berlin_crlf_reads_like_lf() {
    let text = read_text("movingai/Berlin_0_256.map");
    assert!(text.starts_with("type octile\r\nheight 256\r\n"));
    let crlf = parse_movingai(&text, "Berlin_0_256.map").unwrap();
    let lf = parse_movingai(&text.replace("\r\n", "\n"), "Berlin_0_256.map").unwrap();
    assert_eq!(crlf, lf);
}

/// Checks `scenarios` on `grid` against the independent Dijkstra; returns the largest
/// relative error.
fn check_optimal(grid: &Grid, scenarios: &[&Scenario]) -> f64 {
    let mut worst: f64 = 0.0;
    for s in scenarios {
        let length = octile_dijkstra(grid, s.start, s.goal)
            .unwrap_or_else(|| panic!("line {}: no path", s.line));
        let rel = (length - s.optimal_length).abs() / s.optimal_length.max(1.0);
        assert!(
            rel <= 1e-5,
            "line {}: dijkstra {length}, scen {}",
            s.line,
            s.optimal_length
        );
        worst = worst.max(rel);
    }
    worst
}

#[test]
fn arena_optimal_lengths_match_an_independent_dijkstra() {
    let grid = read_map(&repo_file("movingai/arena.map")).unwrap().grid;
    let scenarios = read_scenarios(&repo_file("movingai/arena.map.scen")).unwrap();
    assert_eq!(scenarios.len(), 160);
    let all: Vec<&Scenario> = scenarios.iter().collect();
    let worst = check_optimal(&grid, &all);
    eprintln!("arena: 160 scenarios, worst relative error {worst:e}");
    // Six significant digits: the largest relative rounding error is below 1e-5.
    assert!(worst < 1e-5, "{worst}");
}

#[test]
fn berlin_sample_optimal_lengths_match_an_independent_dijkstra() {
    // Every 31st scenario and the last (31 of 930): the CRLF map, the 8-decimal scen style.
    let grid = read_map(&repo_file("movingai/Berlin_0_256.map"))
        .unwrap()
        .grid;
    let scenarios = read_scenarios(&repo_file("movingai/Berlin_0_256.map.scen")).unwrap();
    let mut sample: Vec<&Scenario> = scenarios.iter().step_by(31).collect();
    sample.extend(scenarios.last());
    assert_eq!(sample.len(), 31);
    let worst = check_optimal(&grid, &sample);
    eprintln!(
        "berlin: {} scenarios, worst relative error {worst:e}",
        sample.len()
    );
    assert!(worst < 1e-7, "{worst}");
}

// ---------------------------------------------------------------------------------------
// Fuzz: truncated and mutated real files never panic, and errors point inside the text.

fn parse_all(text: &str) -> Vec<Result<(), MapError>> {
    vec![
        parse_movingai(text, "f").map(drop),
        parse_scenarios(text, "f").map(drop),
        parse_seed003(text, "f").map(drop),
        parse_matrix(text, "f").map(drop),
    ]
}

/// Runs every parser on `text`; each error must name a position inside the text (a
/// line that exists, a column at most one past its end).
fn no_panic(text: &str) {
    let lines: Vec<&str> = text
        .strip_prefix('\u{feff}')
        .unwrap_or(text)
        .split('\n')
        .collect();
    for result in parse_all(text) {
        if let Err(err) = result {
            assert!(
                err.line >= 1 && err.line <= lines.len(),
                "{err} in {text:?}"
            );
            let line = lines[err.line - 1]
                .strip_suffix('\r')
                .unwrap_or(lines[err.line - 1]);
            assert!(
                err.column >= 1 && err.column <= line.chars().count() + 1,
                "{err} in {text:?}"
            );
        }
    }
}

#[test]
fn fuzz_truncated_and_mutated_files_never_panic() {
    let scen_head: String = read_text("movingai/arena.map.scen")
        .lines()
        .take(12)
        .map(|l| format!("{l}\n"))
        .collect();
    let berlin_head: String = read_text("movingai/Berlin_0_256.map")
        .split_inclusive('\n')
        .take(8)
        .collect();
    let csv: String = read_text("paper/map07.map")
        .lines()
        .skip(4)
        .map(|row| {
            row.chars()
                .map(|c| if c == '.' { "1" } else { "0" })
                .collect::<Vec<_>>()
                .join(",")
                + "\n"
        })
        .collect();
    assert!(parse_matrix(&csv, "map07.csv").is_ok());
    let bases = [
        read_text("wpi/map1.txt"),
        read_text("wpi/map2.txt"),
        read_text("paper/map07.map"),
        read_text("movingai/arena.map"),
        scen_head,
        berlin_head,
        csv,
    ];
    let replacements = [
        '\n', '\r', '\t', ' ', '-', '0', '9', 'Q', '#', '(', ',', '|', '@', 'é', '\0',
    ];
    let mut state: u64 = 0xf0f0;
    let mut next = move |n: usize| {
        state = state
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        ((state >> 33) as usize) % n.max(1)
    };
    let mut runs = 0;
    for base in &bases {
        let chars: Vec<char> = base.chars().collect();
        // Every truncation for the small files, every 7th for the larger ones.
        let step = if chars.len() > 1000 { 7 } else { 1 };
        for cut in (0..=chars.len()).step_by(step) {
            no_panic(&chars[..cut].iter().collect::<String>());
            runs += 1;
        }
        // 200 random single-character edits: replace, delete, insert.
        for _ in 0..200 {
            let mut edited = chars.clone();
            let at = next(edited.len());
            let ch = replacements[next(replacements.len())];
            match next(3) {
                0 if !edited.is_empty() => edited[at] = ch,
                1 if !edited.is_empty() => {
                    edited.remove(at);
                }
                _ => edited.insert(at, ch),
            }
            no_panic(&edited.iter().collect::<String>());
            runs += 1;
        }
        // Duplicated and dropped lines.
        let lines: Vec<&str> = base.split_inclusive('\n').collect();
        for i in 0..lines.len() {
            let mut dup = lines.clone();
            dup.insert(i, lines[i]);
            no_panic(&dup.concat());
            let mut drop_one = lines.clone();
            drop_one.remove(i);
            no_panic(&drop_one.concat());
            runs += 2;
        }
    }
    assert!(runs > 3000, "{runs}");
}
