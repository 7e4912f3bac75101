//! The maps of `configs/coverage.toml` under `maps/coverage/` are exactly what the
//! documented generators give (`maps/coverage/SOURCE.md`). Regenerate them with
//! `GRIDPLAN_REGENERATE_MAPS=1 cargo test -p planner-coverage --test it maps::`.

use std::path::{Path, PathBuf};

use planner_api::{reachable_cells, Cell, Grid};
use planner_coverage::generate::{keep_component, random_blocks, random_cells, rooms, Rooms};
use planner_maps::{read_map, to_movingai};

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// The rows `y0..y0 + h` and columns `x0..x0 + w` of `grid`.
fn crop(grid: &Grid, x0: u32, y0: u32, w: u32, h: u32) -> Grid {
    let mut free = Vec::new();
    for y in y0..y0 + h {
        for x in x0..x0 + w {
            free.push(grid.is_free(Cell::new(x, y)));
        }
    }
    Grid::from_free_cells(w, h, free).unwrap()
}

/// Every generated map: file name, grid, start.
fn generated() -> Vec<(&'static str, Grid, Cell)> {
    let corner = Cell::new(0, 0);
    let mut maps = Vec::new();
    for seed in 1..=3 {
        let mut grid = random_blocks(30, 30, 12, 5, corner, seed).unwrap();
        keep_component(&mut grid, corner);
        let name = [
            "random30-blocks-1.map",
            "random30-blocks-2.map",
            "random30-blocks-3.map",
        ][seed as usize - 1];
        maps.push((name, grid, corner));
    }
    for seed in 1..=3 {
        let mut grid = random_blocks(30, 30, 4, 6, corner, seed).unwrap();
        keep_component(&mut grid, corner);
        let name = [
            "random30-sparse-1.map",
            "random30-sparse-2.map",
            "random30-sparse-3.map",
        ][seed as usize - 1];
        maps.push((name, grid, corner));
    }
    let mut grid = random_cells(30, 30, 0.1, corner, 1).unwrap();
    keep_component(&mut grid, corner);
    maps.push(("random30-cells-1.map", grid, corner));
    let (grid, start) = rooms(
        Rooms {
            cols: 3,
            rows: 3,
            cell: 10,
            extra: 0.25,
        },
        1,
    )
    .unwrap();
    maps.push(("rooms30-1.map", grid, start));
    let (grid, start) = rooms(
        Rooms {
            cols: 4,
            rows: 4,
            cell: 16,
            extra: 0.25,
        },
        1,
    )
    .unwrap();
    maps.push(("rooms64-1.map", grid, start));
    let room = read_map(&root().join("maps/movingai/16room_000.map"))
        .unwrap()
        .grid;
    maps.push((
        "16room_000-crop64.map",
        crop(&room, 0, 0, 64, 64),
        Cell::new(1, 1),
    ));
    maps
}

#[test]
fn committed_maps_are_the_generated_ones() {
    let regenerate = std::env::var_os("GRIDPLAN_REGENERATE_MAPS").is_some();
    let dir = root().join("maps/coverage");
    for (name, grid, start) in generated() {
        assert!(grid.is_free(start), "{name}: start {start} blocked");
        let text = to_movingai(&grid);
        let path = dir.join(name);
        if regenerate {
            std::fs::write(&path, &text).unwrap();
        }
        let committed =
            std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        assert_eq!(committed, text, "{name} differs from its generator");
        let reachable = reachable_cells(&grid, start).iter().filter(|&&r| r).count();
        println!(
            "{name}: {}x{}, {} free, {} reachable from {start}",
            grid.width(),
            grid.height(),
            grid.n_free(),
            reachable
        );
    }
}
