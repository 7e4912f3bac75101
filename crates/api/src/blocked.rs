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

    /// Adds `delta` (1 for a cell that became blocked, `u32::MAX` for one freed) to the
    /// counts of every rectangle holding cell `(x, y)`: the entries right of and below it.
    fn add_cell(&mut self, x: u32, y: u32, delta: u32) {
        let stride = self.width as usize + 1;
        for row in self.table.chunks_exact_mut(stride).skip(y as usize + 1) {
            for count in &mut row[x as usize + 1..] {
                *count = count.wrapping_add(delta);
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

/// A grid's blocked cells packed one bit per cell twice, row by row and column by column
/// (each line padded to whole 64-bit words), beside their [`BlockedCounts`]: what the
/// planners that walk segments a line at a time read (Theta\*'s line of sight, CAPSO's
/// collision measure), kept between searches and rebuilt only when the grid's
/// [`revision`](Grid::revision) or size changes.
///
/// ```
/// use planner_api::{BlockedBits, Grid};
///
/// let grid = Grid::from_ascii("
///     ..#.
///     #...
/// ").unwrap();
/// let bits = BlockedBits::new(&grid);
/// let (rows, words_per_row) = bits.rows();
/// assert_eq!((rows[0], words_per_row), (0b0100, 1));
/// let (columns, words_per_column) = bits.columns();
/// assert_eq!((columns[0], words_per_column), (0b10, 1));
/// assert!(bits.is_blocked(2, 0) && !bits.is_blocked(3, 1));
/// assert_eq!(bits.blocked_in(0, 3, 0, 1), 2);
/// ```
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct BlockedBits {
    width: u32,
    height: u32,
    revision: Option<u64>,
    words_per_row: usize,
    /// Bit `x % 64` of word `y * words_per_row + x / 64` is set when `(x, y)` is blocked.
    rows: Vec<u64>,
    words_per_column: usize,
    /// Bit `y % 64` of word `x * words_per_column + y / 64` is set when `(x, y)` is blocked.
    columns: Vec<u64>,
    counts: BlockedCounts,
}

impl BlockedBits {
    /// The bits of `grid`.
    pub fn new(grid: &Grid) -> BlockedBits {
        let mut bits = BlockedBits::default();
        bits.load(grid);
        bits
    }

    /// The bytes [`BlockedBits::load`] allocates for `grid`: the packed rows and columns
    /// and the summed-area table.
    pub fn bytes_for(grid: &Grid) -> u64 {
        let (w, h) = (u64::from(grid.width()), u64::from(grid.height()));
        (w.div_ceil(64) * h + h.div_ceil(64) * w) * 8 + BlockedCounts::bytes_for(grid)
    }

    /// Makes these `grid`'s bits, reusing their memory (nothing to do when they are
    /// already: the same revision and size). When they were loaded from `grid` before it
    /// was edited in place ([`Grid::changed_since`]), the edited cells' bits follow, and
    /// the summed-area table's entries right of and below each cell that changed state
    /// (for at most [`BlockedBits::FLIPS_ADDED`] such cells; the table is filled anew past
    /// that).
    pub fn load(&mut self, grid: &Grid) {
        if self.is_for_revision(grid) {
            return;
        }
        let same_size = (self.width, self.height) == (grid.width(), grid.height());
        if let Some(changed) = self
            .revision
            .filter(|_| same_size)
            .and_then(|revision| grid.changed_since(revision))
        {
            let mut flips = Vec::new();
            for cell in changed {
                let blocked = !grid.is_free(cell);
                if self.is_blocked(cell.x, cell.y) != blocked {
                    self.flip(cell.x, cell.y);
                    flips.push((cell, blocked));
                }
            }
            if flips.len() <= Self::FLIPS_ADDED {
                for (cell, blocked) in flips {
                    let delta = if blocked { 1 } else { u32::MAX };
                    self.counts.add_cell(cell.x, cell.y, delta);
                }
            } else {
                self.counts.load(grid);
            }
            self.revision = Some(grid.revision());
            return;
        }
        let (w, h) = (grid.width() as usize, grid.height() as usize);
        self.width = grid.width();
        self.height = grid.height();
        self.words_per_row = w.div_ceil(64);
        self.words_per_column = h.div_ceil(64);
        self.rows.clear();
        self.rows.resize(self.words_per_row * h, 0);
        self.columns.clear();
        self.columns.resize(self.words_per_column * w, 0);
        for (y, free) in grid.free_cells().chunks(w.max(1)).enumerate() {
            for (x, &free) in free.iter().enumerate() {
                if !free {
                    self.rows[y * self.words_per_row + x / 64] |= 1 << (x % 64);
                    self.columns[x * self.words_per_column + y / 64] |= 1 << (y % 64);
                }
            }
        }
        self.counts.load(grid);
        self.revision = Some(grid.revision());
    }

    /// Cells that changed state since the last load, up to which [`BlockedBits::load`]
    /// adds to the summed-area table's entries after each (a quarter of the table on
    /// average) rather than filling it anew (one pass, but a dependent chain of additions).
    pub const FLIPS_ADDED: usize = 2;

    /// Toggles cell `(x, y)`'s bit in the rows and the columns.
    fn flip(&mut self, x: u32, y: u32) {
        let (x, y) = (x as usize, y as usize);
        self.rows[y * self.words_per_row + x / 64] ^= 1 << (x % 64);
        self.columns[x * self.words_per_column + y / 64] ^= 1 << (y % 64);
    }

    /// Whether these bits were loaded from `grid`'s revision, at its size.
    pub fn is_for_revision(&self, grid: &Grid) -> bool {
        self.revision == Some(grid.revision())
            && (self.width, self.height) == (grid.width(), grid.height())
    }

    /// Width in cells.
    pub fn width(&self) -> u32 {
        self.width
    }

    /// Height in cells.
    pub fn height(&self) -> u32 {
        self.height
    }

    /// The packed rows and the words per row.
    #[inline]
    pub fn rows(&self) -> (&[u64], usize) {
        (&self.rows, self.words_per_row)
    }

    /// The packed columns and the words per column.
    #[inline]
    pub fn columns(&self) -> (&[u64], usize) {
        (&self.columns, self.words_per_column)
    }

    /// Whether the cell `(x, y)` is blocked. Precondition: it lies in the grid.
    #[inline]
    pub fn is_blocked(&self, x: u32, y: u32) -> bool {
        let word = self.rows[y as usize * self.words_per_row + x as usize / 64];
        word >> (x % 64) & 1 == 1
    }

    /// The blocked cells in the rectangle `x0 ..= x1` by `y0 ..= y1`
    /// ([`BlockedCounts::in_rect`]). Precondition: `x0 <= x1 < width`, `y0 <= y1 < height`.
    #[inline(always)]
    pub fn blocked_in(&self, x0: u32, x1: u32, y0: u32, y1: u32) -> u32 {
        self.counts.in_rect(x0, x1, y0, y1)
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

    /// Every row and column bit against the grid, on sizes that cross the words'
    /// boundaries both ways.
    #[test]
    fn rows_and_columns_are_the_blocked_cells() {
        let mut next = crate::test_rng::xorshift(0x2545_f491_4f6c_dd1d);
        for (w, h) in [(1, 1), (1, 200), (200, 1), (65, 130), (130, 65), (64, 64)] {
            let free = (0..w * h).map(|_| next() % 3 != 0).collect();
            let grid = Grid::from_free_cells(w, h, free).unwrap();
            let bits = BlockedBits::new(&grid);
            let ((rows, per_row), (columns, per_column)) = (bits.rows(), bits.columns());
            for cell in grid.cells() {
                let (x, y) = (cell.x as usize, cell.y as usize);
                let blocked = !grid.is_free(cell);
                assert_eq!(rows[y * per_row + x / 64] >> (x % 64) & 1 == 1, blocked);
                assert_eq!(
                    columns[x * per_column + y / 64] >> (y % 64) & 1 == 1,
                    blocked
                );
            }
            // Nothing set past the grid in a line's last word.
            let row_bits: u32 = rows.iter().map(|w| w.count_ones()).sum();
            let column_bits: u32 = columns.iter().map(|w| w.count_ones()).sum();
            let n_blocked = grid.cells().filter(|&c| !grid.is_free(c)).count() as u32;
            assert_eq!((row_bits, column_bits), (n_blocked, n_blocked));
        }
    }

    /// Random edits in place (a cell at a time, a few between loads, sometimes more than
    /// [`BlockedBits::FLIPS_ADDED`] cells changing state, sometimes a cell edited twice)
    /// give bits and a table equal to a new load's.
    #[test]
    fn edits_in_place_follow_into_the_bits_and_the_table() {
        let mut next = crate::test_rng::xorshift(0x0b10_cced);
        for (w, h) in [(1, 1), (3, 70), (70, 3), (65, 66), (130, 9)] {
            let free = (0..w * h).map(|_| next() % 4 != 0).collect();
            let mut grid = Grid::from_free_cells(w, h, free).unwrap();
            let mut bits = BlockedBits::new(&grid);
            for step in 0..60 {
                for _ in 0..1 + next() % 4 {
                    let cell = crate::Cell::new(
                        (next() % u64::from(w)) as u32,
                        (next() % u64::from(h)) as u32,
                    );
                    grid.set_free(cell, next() % 2 == 0);
                }
                bits.load(&grid);
                assert!(bits.is_for_revision(&grid));
                assert_eq!(bits, BlockedBits::new(&grid), "{w} x {h}, step {step}");
            }
        }
    }

    /// Loading a changed grid (a new revision) makes the bits and the table its own.
    #[test]
    fn a_changed_grid_is_loaded_anew() {
        let mut grid = Grid::from_ascii("....\n.#..").unwrap();
        let mut bits = BlockedBits::new(&grid);
        assert!(bits.is_blocked(1, 1) && !bits.is_blocked(3, 0));
        grid.set_free(crate::Cell::new(1, 1), true);
        grid.set_free(crate::Cell::new(3, 0), false);
        assert!(!bits.is_for_revision(&grid));
        bits.load(&grid);
        assert!(bits.is_for_revision(&grid));
        assert!(!bits.is_blocked(1, 1) && bits.is_blocked(3, 0));
        assert_eq!(bits.columns().0[3], 0b01);
        assert_eq!(bits.blocked_in(0, 3, 0, 1), 1);
        assert_eq!(bits, BlockedBits::new(&grid));
    }
}
