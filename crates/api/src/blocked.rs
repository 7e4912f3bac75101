//! The blocked cells of any rectangle of a grid in four loads: a summed-area table (Crow,
//! "Summed-area tables for texture mapping", SIGGRAPH 1984).
//!
//! Planners that walk segments through a grid (Theta\*'s line of sight, CAPSO's collision
//! measure) ask it whether a box around part of a segment is free before they walk the
//! segment's cells one line at a time.
//!
//! ```
//! use planner_api::{BlockedCounts, Grid};
//!
//! let grid = Grid::from_ascii("
//!     ..#.
//!     #...
//!     ...#
//! ").unwrap();
//! let counts = BlockedCounts::new(&grid);
//! assert_eq!(counts.in_rect(0, 3, 0, 2), 3);
//! assert_eq!(counts.in_rect(1, 2, 1, 2), 0);
//! assert_eq!(counts.in_rect(2, 2, 0, 0), 1);
//! ```

use crate::Grid;

/// A grid's summed-area table of blocked cells: entry `y * (width + 1) + x` counts those
/// in columns `0..x` of rows `0..y`, modulo 2^32 (the differences in [`BlockedCounts::in_rect`]
/// are then exact for any grid of fewer than 2^32 cells in a rectangle).
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct BlockedCounts {
    width: u32,
    table: Vec<u32>,
}

impl BlockedCounts {
    /// The table of `grid`.
    pub fn new(grid: &Grid) -> BlockedCounts {
        let mut counts = BlockedCounts::default();
        counts.load(grid);
        counts
    }

    /// Makes this the table of `grid`, reusing its memory.
    pub fn load(&mut self, grid: &Grid) {
        let (w, h) = (grid.width() as usize, grid.height() as usize);
        let stride = w + 1;
        self.width = grid.width();
        self.table.clear();
        self.table.resize(stride * (h + 1), 0);
        for (y, free) in grid.free_cells().chunks(w.max(1)).enumerate() {
            let mut row = 0u32;
            for (x, &free) in free.iter().enumerate() {
                row = row.wrapping_add(u32::from(!free));
                self.table[(y + 1) * stride + x + 1] =
                    self.table[y * stride + x + 1].wrapping_add(row);
            }
        }
    }

    /// The bytes of `grid`'s table: 4 per cell, plus a row and a column.
    pub fn bytes_for(grid: &Grid) -> u64 {
        4 * (u64::from(grid.width()) + 1) * (u64::from(grid.height()) + 1)
    }

    /// The blocked cells in columns `x0 ..= x1` of rows `y0 ..= y1`. Precondition:
    /// `x0 <= x1 < width` and `y0 <= y1 < height` (outside, the missing entries count as 0).
    #[inline(always)]
    pub fn in_rect(&self, x0: u32, x1: u32, y0: u32, y1: u32) -> u32 {
        let stride = self.width as usize + 1;
        let (x0, x1, y0, y1) = (x0 as usize, x1 as usize + 1, y0 as usize, y1 as usize + 1);
        let at = |x: usize, y: usize| self.table.get(y * stride + x).copied().unwrap_or(0);
        // Inclusion-exclusion; wrapping only for the order of the terms.
        at(x1, y1)
            .wrapping_sub(at(x1, y0))
            .wrapping_sub(at(x0, y1))
            .wrapping_add(at(x0, y0))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every rectangle of a patterned grid against a count of its cells.
    #[test]
    fn every_rectangle_counts_its_blocked_cells() {
        let (w, h) = (11u32, 7u32);
        let rows: Vec<String> = (0..h)
            .map(|y| {
                (0..w)
                    .map(|x| {
                        if (x * 7 + y * 13 + x * y) % 5 == 0 {
                            '#'
                        } else {
                            '.'
                        }
                    })
                    .collect()
            })
            .collect();
        let grid = Grid::from_ascii(&rows.join("\n")).unwrap();
        let counts = BlockedCounts::new(&grid);
        for (x0, x1) in (0..w).flat_map(|a| (a..w).map(move |b| (a, b))) {
            for (y0, y1) in (0..h).flat_map(|a| (a..h).map(move |b| (a, b))) {
                let by_hand = (x0..=x1)
                    .flat_map(|x| (y0..=y1).map(move |y| (x, y)))
                    .filter(|&(x, y)| !grid.is_free(crate::Cell::new(x, y)))
                    .count() as u32;
                assert_eq!(
                    counts.in_rect(x0, x1, y0, y1),
                    by_hand,
                    "{x0}..={x1} x {y0}..={y1}"
                );
            }
        }
        assert_eq!(
            counts.table.len() as u64 * 4,
            BlockedCounts::bytes_for(&grid)
        );
    }
}
