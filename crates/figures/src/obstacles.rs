//! Marked cells (blocked, unknown) as few rectangles: runs of marked cells in a row,
//! merged downwards while the next row has a run with exactly the same columns.

/// An axis-aligned block of marked cells, in cell units.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
pub(crate) struct Block {
    /// Top row.
    pub y: u32,
    /// Left column.
    pub x: u32,
    /// Number of columns.
    pub w: u32,
    /// Number of rows.
    pub h: u32,
}

/// The cells flagged in `marked` (row-major, `width` a row) as disjoint rectangles
/// covering exactly those cells, sorted by (top row, left column).
///
/// Each row is split into maximal runs of marked cells; a run whose columns equal those of
/// a run in the row above extends that rectangle instead of starting a new one.
pub(crate) fn blocks(width: usize, marked: &[bool]) -> Vec<Block> {
    let mut done = Vec::new();
    // Rectangles still open at the previous row, sorted by x (runs in a row are disjoint).
    let mut open: Vec<Block> = Vec::new();
    for (y, row) in marked.chunks(width.max(1)).enumerate() {
        let y = y as u32; // height <= u32::MAX
        let runs = row_runs(row);
        let mut next_open = Vec::with_capacity(runs.len());
        let mut previous = open.into_iter().peekable();
        for (x, w) in runs {
            // Close every open rectangle that starts left of this run or matches it badly.
            while let Some(block) = previous.next_if(|b| b.x < x || (b.x == x && b.w != w)) {
                done.push(block);
            }
            match previous.next_if(|b| b.x == x && b.w == w) {
                Some(mut block) => {
                    block.h += 1;
                    next_open.push(block);
                }
                None => next_open.push(Block { y, x, w, h: 1 }),
            }
        }
        done.extend(previous);
        open = next_open;
    }
    done.extend(open);
    done.sort_unstable();
    done
}

/// Maximal runs of marked cells in one row, as (first column, length).
fn row_runs(row: &[bool]) -> Vec<(u32, u32)> {
    let mut runs = Vec::new();
    let mut start = None;
    for (x, &marked) in row.iter().enumerate() {
        match (marked, start) {
            (true, None) => start = Some(x),
            (false, Some(s)) => {
                runs.push((s as u32, (x - s) as u32));
                start = None;
            }
            _ => {}
        }
    }
    if let Some(s) = start {
        runs.push((s as u32, (row.len() - s) as u32));
    }
    runs
}

#[cfg(test)]
mod tests {
    use super::*;
    use planner_api::{Cell, Grid};

    /// The blocked cells of `grid` as rectangles.
    fn blocked(grid: &Grid) -> Vec<Block> {
        let marked: Vec<bool> = grid.free_cells().iter().map(|&free| !free).collect();
        blocks(grid.width() as usize, &marked)
    }

    fn check(ascii: &str, expect: &[(u32, u32, u32, u32)]) {
        let grid = Grid::from_ascii(ascii).unwrap();
        let got: Vec<_> = blocked(&grid)
            .iter()
            .map(|b| (b.x, b.y, b.w, b.h))
            .collect();
        assert_eq!(got, expect, "{ascii}");
        // Independent check: the rectangles cover exactly the blocked cells, once each.
        let mut covered = vec![0u32; grid.len()];
        for b in blocked(&grid) {
            for y in b.y..b.y + b.h {
                for x in b.x..b.x + b.w {
                    covered[grid.index(Cell::new(x, y))] += 1;
                }
            }
        }
        for cell in grid.cells() {
            let expect = u32::from(!grid.is_free(cell));
            assert_eq!(covered[grid.index(cell)], expect, "{cell}");
        }
    }

    #[test]
    fn runs_merge_by_hand() {
        // Expected (x, y, w, h) read off the drawings.
        check("....\n....", &[]);
        check("####\n####", &[(0, 0, 4, 2)]);
        // A row run of three and a lone cell; the lone cell continues down one row.
        check("###.#\n....#\n.....", &[(0, 0, 3, 1), (4, 0, 1, 2)]);
        // Same columns two rows apart do not merge across the free row.
        check("##..\n....\n##..", &[(0, 0, 2, 1), (0, 2, 2, 1)]);
        // Different extents never merge: (0..2) then (0..3).
        check("##.\n###", &[(0, 0, 2, 1), (0, 1, 3, 1)]);
        // Checkerboard: no two blocked cells share a run.
        check(
            "#.#\n.#.\n#.#",
            &[
                (0, 0, 1, 1),
                (2, 0, 1, 1),
                (1, 1, 1, 1),
                (0, 2, 1, 1),
                (2, 2, 1, 1),
            ],
        );
        // A wall with a gap, then a column: 2 + 1 run rectangles, the column merges.
        check(
            "##.##\n..#..\n..#..",
            &[(0, 0, 2, 1), (3, 0, 2, 1), (2, 1, 1, 2)],
        );
    }
}
