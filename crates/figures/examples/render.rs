//! Writes sample figures to a folder (default `/tmp/gridplan-figures`) to look at:
//!
//! ```text
//! cargo run -p planner-figures --example render [OUT_DIR]
//! for f in /tmp/gridplan-figures/*.svg; do rsvg-convert "$f" -o "${f%.svg}.png"; done
//! ```
//!
//! Figures: `map01_bfs` (one path, seed 000's map 1), `map10_comparison` (two shortest
//! paths in panels), `map10_three` (three panels, one without a path, a label needing
//! escapes), `room_any_angle` (8-connected and any-angle paths), `random512_overlay` and
//! `random512_bfs` (a 512x512 map, overlay and single), `map10_coverage`,
//! `den520d_coverage` and `random512_coverage` (timelines with markers).
//!
//! Paths are made here with a plain breadth-first search (two neighbour orders give two
//! different shortest paths), a greedy line-of-sight shortcut of one of them (an
//! any-angle path) and a row-by-row sweep (a coverage path); no planner crate is used.

use std::collections::VecDeque;
use std::error::Error;
use std::path::{Path as FsPath, PathBuf};

use planner_api::{segment_is_free, Cell, Connectivity, Grid, MoveSet, Path};
use planner_figures::{draw_comparison, draw_path, draw_timeline, Layer, Marker, Style};

/// A Moving AI map: four header lines, then rows where `.`, `G` and `S` are free.
fn read_map(path: &FsPath) -> Result<Grid, Box<dyn Error>> {
    let text = std::fs::read_to_string(path)?;
    let rows: Vec<&str> = text
        .lines()
        .skip(4)
        .map(str::trim_end)
        .filter(|r| !r.is_empty())
        .collect();
    let width = rows.first().ok_or("empty map")?.len();
    let mut free = Vec::with_capacity(width * rows.len());
    for row in &rows {
        if row.len() != width {
            return Err("ragged map".into());
        }
        free.extend(row.bytes().map(|b| matches!(b, b'.' | b'G' | b'S')));
    }
    Ok(Grid::from_free_cells(
        u32::try_from(width)?,
        u32::try_from(rows.len())?,
        free,
    )?)
}

/// Breadth-first search with moves tried in `order`: a shortest path on unit moves.
fn bfs(grid: &Grid, start: Cell, goal: Cell, order: &[(i32, i32)]) -> Option<Path> {
    let mut parent = vec![usize::MAX; grid.len()];
    let mut queue = VecDeque::from([start]);
    parent[grid.index(start)] = grid.index(start);
    while let Some(c) = queue.pop_front() {
        if c == goal {
            let mut cells = vec![c];
            let mut i = grid.index(c);
            while parent[i] != i {
                i = parent[i];
                cells.push(grid.cell(i));
            }
            cells.reverse();
            return Some(Path::new(cells));
        }
        for &(dx, dy) in order {
            if let Some(n) = grid.offset(c, dx, dy) {
                if grid.is_free(n) && parent[grid.index(n)] == usize::MAX {
                    parent[grid.index(n)] = grid.index(c);
                    queue.push_back(n);
                }
            }
        }
    }
    None
}

/// Breadth-first search on 8-connected moves without corner cutting: fewest moves.
fn bfs8(grid: &Grid, start: Cell, goal: Cell) -> Option<Path> {
    let moves = MoveSet::standard(Connectivity::Eight);
    let mut parent = vec![usize::MAX; grid.len()];
    let mut queue = VecDeque::from([start]);
    parent[grid.index(start)] = grid.index(start);
    while let Some(c) = queue.pop_front() {
        if c == goal {
            let mut cells = vec![c];
            let mut i = grid.index(c);
            while parent[i] != i {
                i = parent[i];
                cells.push(grid.cell(i));
            }
            cells.reverse();
            return Some(Path::new(cells));
        }
        for mv in moves.moves() {
            if let Some(n) = moves.apply(grid, c, mv) {
                if parent[grid.index(n)] == usize::MAX {
                    parent[grid.index(n)] = grid.index(c);
                    queue.push_back(n);
                }
            }
        }
    }
    None
}

const RIGHT_FIRST: [(i32, i32); 4] = [(1, 0), (-1, 0), (0, 1), (0, -1)];
const DOWN_FIRST: [(i32, i32); 4] = [(0, 1), (0, -1), (1, 0), (-1, 0)];

/// Greedy line-of-sight shortcut: from each waypoint, jump to the farthest later cell seen.
fn shortcut(grid: &Grid, path: &Path) -> Path {
    let cells = path.cells();
    let mut out = vec![cells[0]];
    let mut i = 0;
    while i + 1 < cells.len() {
        let mut j = i + 1;
        for k in (i + 1..cells.len()).rev() {
            if segment_is_free(grid, cells[i], cells[k]) {
                j = k;
                break;
            }
        }
        out.push(cells[j]);
        i = j;
    }
    Path::new(out)
}

/// A sweep over every free cell, row by row in alternating directions; where the next
/// unvisited cell is not adjacent, a breadth-first detour to it, and a marker where a
/// detour longer than `marker_min` moves starts.
fn coverage(grid: &Grid, marker_min: usize) -> (Path, Vec<Marker>) {
    let mut order = Vec::new();
    for y in 0..grid.height() {
        let xs: Vec<u32> = if y % 2 == 0 {
            (0..grid.width()).collect()
        } else {
            (0..grid.width()).rev().collect()
        };
        order.extend(xs.into_iter().map(|x| Cell::new(x, y)));
    }
    let mut visited = vec![false; grid.len()];
    let mut cells: Vec<Cell> = Vec::new();
    let mut markers = Vec::new();
    for target in order.into_iter().filter(|&c| grid.is_free(c)) {
        if visited[grid.index(target)] {
            continue;
        }
        let before = cells.len();
        match cells.last().copied() {
            None => cells.push(target),
            Some(at) => {
                let Some(detour) = bfs(grid, at, target, &RIGHT_FIRST) else {
                    continue;
                };
                if detour.len() > marker_min + 1 {
                    markers.push(Marker {
                        cell: at,
                        label: format!("B{}", markers.len() + 1),
                    });
                }
                cells.extend_from_slice(&detour.cells()[1..]);
            }
        }
        // Cells passed on a detour count as covered too.
        for &c in &cells[before..] {
            visited[grid.index(c)] = true;
        }
    }
    (Path::new(cells), markers)
}

fn note(path: &Path) -> String {
    let m = path.metrics();
    format!("found, D={} T={} Score={}", m.steps, m.turns, m.score)
}

fn write(out: &FsPath, name: &str, svg: &str) -> Result<(), Box<dyn Error>> {
    let file = out.join(name);
    std::fs::write(&file, svg)?;
    println!("{:>9} bytes  {}", svg.len(), file.display());
    Ok(())
}

fn main() -> Result<(), Box<dyn Error>> {
    let out = PathBuf::from(
        std::env::args()
            .nth(1)
            .unwrap_or_else(|| "/tmp/gridplan-figures".to_owned()),
    );
    std::fs::create_dir_all(&out)?;
    let maps = FsPath::new(env!("CARGO_MANIFEST_DIR")).join("../../maps");
    let style = Style::default();

    // 1. Seed 000's map 1 (6x6), one path, like Fig. 7.
    let grid = read_map(&maps.join("paper/map01.map"))?;
    let (s, g) = (Cell::new(0, 0), Cell::new(5, 5));
    let path = bfs(&grid, s, g, &RIGHT_FIRST).ok_or("map01: no path")?;
    let layer = Layer::new("bfs (right first)", Some(&path), note(&path));
    write(
        &out,
        "map01_bfs.svg",
        &draw_path(&grid, s, g, &layer, "map01 · problem 0 · bfs", &style),
    )?;

    // 2. Map 10 (12x12): two shortest paths side by side, like Figs. 13-18.
    let grid = read_map(&maps.join("paper/map10.map"))?;
    let (s, g) = (Cell::new(0, 0), Cell::new(11, 11));
    let a = bfs(&grid, s, g, &RIGHT_FIRST).ok_or("map10: no path")?;
    let b = bfs(&grid, s, g, &DOWN_FIRST).ok_or("map10: no path")?;
    let layers = [
        Layer::new("right first", Some(&a), note(&a)),
        Layer::new("down first", Some(&b), note(&b)),
    ];
    write(
        &out,
        "map10_comparison.svg",
        &draw_comparison(&grid, s, g, &layers, "map10 · problem 0", &style),
    )?;
    // The same with a third, failed layer and a hostile label, to see escaping and wrap.
    let layers3 = [
        Layer::new("right first", Some(&a), note(&a)),
        Layer::new("down first", Some(&b), note(&b)),
        Layer::new("<dfs & \"co\">", None, "budget exhausted"),
    ];
    write(
        &out,
        "map10_three.svg",
        &draw_comparison(&grid, s, g, &layers3, "map10 · three layers", &style),
    )?;

    // Diagonal and any-angle moves on a roomier hand-made 12x12 map: an 8-connected
    // breadth-first path (corners not cut) and its line-of-sight shortcut.
    let grid = Grid::from_ascii(
        "
        ............
        ............
        ..#######...
        ........#...
        ........#...
        ...##...#...
        ...##.......
        ............
        ######..####
        ............
        ............
        ............
        ",
    )?;
    let eight = bfs8(&grid, s, g).ok_or("hand-made: no 8-connected path")?;
    let any = shortcut(&grid, &eight);
    let layers = [
        Layer::new("8-connected", Some(&eight), note(&eight)),
        Layer::new(
            "any-angle",
            Some(&any),
            format!("{}, length {:.2}", note(&any), any.metrics().length),
        ),
    ];
    write(
        &out,
        "room_any_angle.svg",
        &draw_comparison(
            &grid,
            s,
            g,
            &layers,
            "12x12 room · diagonal and any-angle",
            &style,
        ),
    )?;

    // 3. A 512x512 random Moving AI map: overlay of a 4-connected and an any-angle path.
    let grid = read_map(&maps.join("movingai/random512-10-0.map"))?;
    let (s, g) = (Cell::new(3, 5), Cell::new(505, 500));
    let four = bfs(&grid, s, g, &RIGHT_FIRST).ok_or("random512: no path")?;
    let any = shortcut(&grid, &four);
    let layers = [
        Layer::new("bfs", Some(&four), note(&four)),
        Layer::new(
            "bfs + line-of-sight shortcut",
            Some(&any),
            format!("{}, length {:.1}", note(&any), any.metrics().length),
        ),
    ];
    write(
        &out,
        "random512_overlay.svg",
        &draw_comparison(&grid, s, g, &layers, "random512-10-0 · overlay", &style),
    )?;
    write(
        &out,
        "random512_bfs.svg",
        &draw_path(&grid, s, g, &layers[0], "random512-10-0 · bfs", &style),
    )?;

    // 4. Coverage timelines: map 10 and the den520d game map's top-left 64x48 corner.
    let grid = read_map(&maps.join("paper/map10.map"))?;
    let (path, markers) = coverage(&grid, 2);
    write(
        &out,
        "map10_coverage.svg",
        &draw_timeline(&grid, &path, &markers, "map10 · coverage sweep", &style),
    )?;
    let den = read_map(&maps.join("movingai/den520d.map"))?;
    let mut corner = Grid::new(64, 48)?;
    for c in corner.clone().cells() {
        corner.set_free(c, den.is_free(Cell::new(c.x + 80, c.y + 100)));
    }
    let (path, markers) = coverage(&corner, 3);
    write(
        &out,
        "den520d_coverage.svg",
        &draw_timeline(
            &corner,
            &path,
            &markers,
            "den520d (80,100)+64x48 · coverage sweep",
            &style,
        ),
    )?;
    let grid = read_map(&maps.join("movingai/random512-10-0.map"))?;
    let (path, markers) = coverage(&grid, 12);
    write(
        &out,
        "random512_coverage.svg",
        &draw_timeline(
            &grid,
            &path,
            &markers,
            "random512-10-0 · coverage sweep",
            &style,
        ),
    )?;
    Ok(())
}
