//! Test-only map readers (the `planner-maps` crate is written elsewhere): Moving AI `.map`
//! files, seed 003's `.txt` maps, and the first line of a `.scen` file.
#![allow(dead_code)]

use std::path::PathBuf;

use planner_api::{Cell, Grid};

/// `maps/` at the repository root.
pub fn maps_dir() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../maps")
}

fn read(relative: &str) -> String {
    let path = maps_dir().join(relative);
    std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

/// A Moving AI map: skip the 4 header lines; `.` is free, anything else blocked.
pub fn movingai(relative: &str) -> Grid {
    let text = read(relative);
    let rows: Vec<&str> = text
        .lines()
        .skip(4)
        .map(str::trim_end)
        .filter(|r| !r.is_empty())
        .collect();
    let width = rows[0].len();
    assert!(
        rows.iter().all(|r| r.len() == width),
        "{relative}: ragged rows"
    );
    let free = rows
        .iter()
        .flat_map(|r| r.bytes().map(|b| b == b'.'))
        .collect();
    Grid::from_free_cells(width as u32, rows.len() as u32, free).unwrap()
}

/// A seed 003 map: `#` header lines with `# k. Start: (x,y) | Goal: (x,y)`, then rows of
/// `.` (free) and `X` (blocked), possibly after a blank line. Returns the grid and the pairs.
pub fn wpi(relative: &str) -> (Grid, Vec<(Cell, Cell)>) {
    let text = read(relative);
    let mut pairs = Vec::new();
    let mut rows = Vec::new();
    for line in text.lines().map(str::trim) {
        if let Some(comment) = line.strip_prefix('#') {
            if let (Some(s), Some(g)) = (comment.find("Start:"), comment.find("Goal:")) {
                pairs.push((
                    parse_cell(&comment[s + 6..g]),
                    parse_cell(&comment[g + 5..]),
                ));
            }
        } else if !line.is_empty() {
            rows.push(line);
        }
    }
    let width = rows[0].len();
    assert!(
        rows.iter().all(|r| r.len() == width),
        "{relative}: ragged rows"
    );
    let free = rows
        .iter()
        .flat_map(|r| r.bytes().map(|b| b == b'.'))
        .collect();
    (
        Grid::from_free_cells(width as u32, rows.len() as u32, free).unwrap(),
        pairs,
    )
}

fn parse_cell(text: &str) -> Cell {
    let inner = &text[text.find('(').unwrap() + 1..text.find(')').unwrap()];
    let (x, y) = inner.split_once(',').unwrap();
    Cell::new(x.trim().parse().unwrap(), y.trim().parse().unwrap())
}

/// Start and goal of the first scenario of a `.scen` file (fields 4..8 of line 2).
pub fn first_scenario(relative: &str) -> (Cell, Cell) {
    let text = read(relative);
    let line = text.lines().nth(1).unwrap();
    let f: Vec<u32> = line
        .split('\t')
        .skip(4)
        .take(4)
        .map(|v| v.trim().parse().unwrap())
        .collect();
    (Cell::new(f[0], f[1]), Cell::new(f[2], f[3]))
}

/// The paper's twelve maps: (name, grid), start (0,0), goal (N-1,N-1).
pub fn paper_maps() -> Vec<(String, Grid)> {
    (1..=12)
        .map(|i| {
            let name = format!("map{i:02}");
            let grid = movingai(&format!("paper/{name}.map"));
            (name, grid)
        })
        .collect()
}

/// `maps/paper/published.toml`.
pub fn published() -> toml::Table {
    read("paper/published.toml").parse().unwrap()
}

/// The Moving AI maps in the repository (those with a `.scen` next to them).
pub fn movingai_maps() -> Vec<String> {
    let mut names: Vec<String> = std::fs::read_dir(maps_dir().join("movingai"))
        .unwrap()
        .filter_map(|e| e.ok()?.file_name().into_string().ok())
        .filter(|n| n.ends_with(".map"))
        .collect();
    names.sort();
    names
}

/// Asserts the counter identities of a BFS or DFS run with `k` moves per cell (crate docs).
pub fn check_frontier_identities(what: &str, outcome: &planner_api::Outcome, k: u64) {
    use planner_api::Status;
    let c = &outcome.counters;
    let get = |name: &str| c.get(name).unwrap_or_else(|| panic!("{what}: no {name}"));
    let (exp, checks, blocked, skipped) = (
        get("n_expanded"),
        get("n_neighbor_checks"),
        get("n_blocked"),
        get("n_skipped"),
    );
    let (peak, inserted) = (get("peak_open"), get("n_open_insertions"));
    assert_eq!(
        checks,
        blocked + skipped + (inserted - 1),
        "{what}: checks = blk + skp + ins - 1; {c}"
    );
    assert!(
        peak >= 1 && peak <= inserted,
        "{what}: 1 <= peak_open <= insertions; {c}"
    );
    match outcome.status {
        Status::Found => assert_eq!(checks, k * (exp - 1), "{what}: checks = k (exp - 1); {c}"),
        Status::NoPath => {
            assert_eq!(checks, k * exp, "{what}: checks = k exp; {c}");
            assert_eq!(inserted, exp, "{what}: every inserted cell expanded; {c}");
        }
        Status::BudgetExhausted => {
            assert_eq!(checks, k * exp, "{what}: checks = k exp; {c}");
            assert!(inserted > exp, "{what}: cells left in the frontier; {c}");
        }
    }
}
