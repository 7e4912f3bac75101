//! The bit-packed grid and block-based straight jumps (Harabor and Grastien 2014, section
//! "Block-based Symmetry Breaking"): a straight jump reads 64 cells of its row and of the two
//! rows beside it per step, and finds the first blocked or forced cell with one
//! trailing- or leading-zero count. Vertical jumps read a transposed copy, so they are row
//! scans too.
//!
//! Layout: one bit per cell, 1 = free. Every row has 64 blocked padding cells on the left and
//! at least 64 on the right, and there is a blocked padding row above and below, so every
//! read near the border sees blocked cells and needs no bounds test. A cell at column `x`
//! of row `y` is bit position `x + 64` of padded row `y + 1`.

use planner_api::{packed_words, Cell, Grid};

/// Blocked padding cells left of every row: a whole word, so that a row's cells start one
/// ([`BitGrid::build`] writes them a word at a time).
const PAD: usize = 64;
const _: () = assert!(PAD % 64 == 0);

/// Bit-packed rows with blocked padding (see the module docs).
#[derive(Debug, Clone, Default)]
pub(crate) struct Rows {
    stride: usize,
    data: Vec<u64>,
}

impl Rows {
    /// All-blocked rows for `n_rows` rows of `len` cells.
    fn blocked(len: usize, n_rows: usize) -> Rows {
        // Left padding word, the cells, right padding, one spare word so that a
        // two-word read starting at any padded position stays inside the row.
        let stride = len.div_ceil(64) + 3;
        Rows {
            stride,
            data: vec![0; stride * (n_rows + 2)],
        }
    }

    /// Bit `p` of padded row `r`.
    #[inline(always)]
    fn bit(&self, r: usize, p: usize) -> bool {
        (self.data[r * self.stride + (p >> 6)] >> (p & 63)) & 1 != 0
    }

    /// Bits `p .. p + 64` of padded row `r`; bit `i` of the result is position `p + i`.
    #[inline(always)]
    fn window(&self, r: usize, p: usize) -> u64 {
        let i = r * self.stride + (p >> 6);
        let b = (p & 63) as u32;
        // The high word shifted in two steps, so that b = 0 shifts it out entirely.
        (self.data[i] >> b) | ((self.data[i + 1] << 1) << (63 - b))
    }

    /// A straight jump along padded row `r` from position `p0`, forwards (increasing
    /// positions) when `FORWARD`, else backwards. It stops at the first cell that is
    /// `target` (a position, or `usize::MAX` for none), forced, or blocked. A cell `q` is
    /// forced when a row beside it is free at `q` and blocked at the cell before `q` (one
    /// step back along the jump): the Moving AI rule's forced neighbour. Returns
    /// `(true, k)` for a jump point `k` cells on (the target or a forced cell), or
    /// `(false, k)` when the jump ends at a wall after `k` free cells.
    #[inline(always)]
    fn jump<const FORWARD: bool>(&self, r: usize, p0: usize, target: usize) -> (bool, usize) {
        // The rows beside are read once per window; their bits one step back along the
        // jump are the window shifted by one, plus the bit carried from the last window.
        if FORWARD {
            let mut p = p0 + 1;
            let mut up_carry = u64::from(self.bit(r - 1, p - 1));
            let mut down_carry = u64::from(self.bit(r + 1, p - 1));
            loop {
                let cur = self.window(r, p);
                let up = self.window(r - 1, p);
                let down = self.window(r + 1, p);
                let up_behind = (up << 1) | up_carry;
                let down_behind = (down << 1) | down_carry;
                let stop = !cur | (up & !up_behind) | (down & !down_behind);
                let end = if stop == 0 {
                    p + 64
                } else {
                    p + stop.trailing_zeros() as usize
                };
                if target >= p && target < end {
                    return (true, target - p0);
                }
                if stop != 0 {
                    return if (cur >> (end - p)) & 1 == 0 {
                        (false, end - 1 - p0)
                    } else {
                        (true, end - p0)
                    };
                }
                up_carry = up >> 63;
                down_carry = down >> 63;
                p += 64;
            }
        } else {
            // The window of positions p - 63 ..= p; bit 63 is position p.
            let mut p = p0 - 1;
            let mut up_carry = u64::from(self.bit(r - 1, p + 1)) << 63;
            let mut down_carry = u64::from(self.bit(r + 1, p + 1)) << 63;
            loop {
                let cur = self.window(r, p - 63);
                let up = self.window(r - 1, p - 63);
                let down = self.window(r + 1, p - 63);
                let up_behind = (up >> 1) | up_carry;
                let down_behind = (down >> 1) | down_carry;
                let stop = !cur | (up & !up_behind) | (down & !down_behind);
                // The stop position, or one below the window when none.
                let end = if stop == 0 {
                    p - 64
                } else {
                    p - stop.leading_zeros() as usize
                };
                if target <= p && target > end {
                    return (true, p0 - target);
                }
                if stop != 0 {
                    return if (cur >> (63 - (p - end))) & 1 == 0 {
                        (false, p0 - end - 1)
                    } else {
                        (true, p0 - end)
                    };
                }
                up_carry = (up & 1) << 63;
                down_carry = (down & 1) << 63;
                p -= 64;
            }
        }
    }
}

/// A grid as bit-packed rows and columns, built once per grid and reused across queries.
#[derive(Debug, Clone, Default)]
pub(crate) struct BitGrid {
    width: u32,
    height: u32,
    revision: u64,
    rows: Rows,
    columns: Rows,
}

/// Directions, indexed as everywhere in this crate: east, west, south, north (y grows
/// downwards), then south-east, south-west, north-east, north-west.
pub(crate) const DX: [i32; 8] = [1, -1, 0, 0, 1, -1, 1, -1];
/// The y offsets of the directions (see [`DX`]).
pub(crate) const DY: [i32; 8] = [0, 0, 1, -1, 1, 1, -1, -1];

/// The diagonal direction with signs `dx`, `dy` (both nonzero).
#[inline(always)]
pub(crate) const fn diagonal(dx: i32, dy: i32) -> usize {
    4 + (dx < 0) as usize + 2 * (dy < 0) as usize
}

impl BitGrid {
    /// The bit grid of `grid`.
    pub(crate) fn build(grid: &Grid) -> BitGrid {
        let (w, h) = (grid.width() as usize, grid.height() as usize);
        let mut rows = Rows::blocked(w, h);
        let mut columns = Rows::blocked(h, w);
        // A word at a time (the padding is a whole word, so a row's cells start a word):
        // a division per cell for its coordinates and a bit set per cell took most of a
        // rebuild after a grid change. The columns a band of 64 rows at a time, each
        // column's word of the band built in `band` row by row (sequential reads; reading
        // each column down the band was slower, rows a power of two apart sharing cache
        // sets) and then stored.
        let w1 = w.max(1);
        for (y, row) in grid.free_cells().chunks_exact(w1).enumerate() {
            let start = (y + 1) * rows.stride + PAD / 64;
            for (c, word) in packed_words(row).enumerate() {
                rows.data[start + c] = word;
            }
        }
        let mut band = vec![0u64; w];
        for (b, band_rows) in grid.free_cells().chunks(64 * w1).enumerate() {
            band.fill(0);
            for (k, row) in band_rows.chunks_exact(w1).enumerate() {
                for (word, &free) in band.iter_mut().zip(row) {
                    *word |= u64::from(free) << k;
                }
            }
            for (x, &word) in band.iter().enumerate() {
                columns.data[(x + 1) * columns.stride + PAD / 64 + b] = word;
            }
        }
        BitGrid {
            width: grid.width(),
            height: grid.height(),
            revision: grid.revision(),
            rows,
            columns,
        }
    }

    /// The cached bit grid of `grid`, and whether its cells changed: only when `grid` has
    /// other cells than the one `cache` holds (checked by revision, then cells). The bits
    /// of a grid edited in place since they were built ([`Grid::changed_since`]) follow its
    /// edited cells; any other grid's are built anew.
    pub(crate) fn cached<'a>(cache: &'a mut Option<BitGrid>, grid: &Grid) -> (&'a BitGrid, bool) {
        let mut rebuilt = false;
        match cache {
            Some(bits) if bits.revision == grid.revision() => {}
            Some(bits) => match grid.changed_since(bits.revision) {
                Some(changed) => {
                    for cell in changed {
                        bits.set(cell, grid.is_free(cell));
                    }
                    bits.revision = grid.revision();
                    rebuilt = true;
                }
                None if bits.is_for(grid) => bits.revision = grid.revision(),
                None => {
                    *bits = BitGrid::build(grid);
                    rebuilt = true;
                }
            },
            None => {
                *cache = Some(BitGrid::build(grid));
                rebuilt = true;
            }
        }
        match cache {
            Some(bits) => (bits, rebuilt),
            None => unreachable!("the bit grid cache was just filled"),
        }
    }

    /// Sets the bit of `cell` (a cell of the grid) in its row and its column to `free`.
    fn set(&mut self, cell: Cell, free: bool) {
        let (x, y) = (cell.x as usize, cell.y as usize);
        for (rows, line, at) in [(&mut self.rows, y, x), (&mut self.columns, x, y)] {
            let p = at + PAD;
            let word = &mut rows.data[(line + 1) * rows.stride + p / 64];
            *word = (*word & !(1 << (p % 64))) | u64::from(free) << (p % 64);
        }
    }

    /// Whether this is the bit grid of `grid`.
    pub(crate) fn is_for(&self, grid: &Grid) -> bool {
        let w = grid.width() as usize;
        (self.width, self.height) == (grid.width(), grid.height())
            && (0..)
                .zip(grid.free_cells().chunks_exact(w.max(1)))
                .all(|(y, row): (usize, _)| {
                    let start = (y + 1) * self.rows.stride + PAD / 64;
                    packed_words(row)
                        .zip(&self.rows.data[start..])
                        .all(|(word, &have)| word == have)
                })
    }

    /// The width in cells.
    pub(crate) fn width(&self) -> u32 {
        self.width
    }

    /// The height in cells.
    pub(crate) fn height(&self) -> u32 {
        self.height
    }

    /// Whether cell `(x, y)` is free; `x` may be -1 or the width, `y` -1 or the height
    /// (the padding, blocked).
    #[inline(always)]
    pub(crate) fn free(&self, x: i32, y: i32) -> bool {
        self.rows.bit((y + 1) as usize, (x + PAD as i32) as usize)
    }

    /// Whether the move from cell `(x, y)` in direction `dir` is allowed: its target is
    /// free and, for a diagonal, both orthogonal cells beside it (no corner cutting).
    /// `(x, y)` may lie in the padding's reach as for [`BitGrid::free`].
    #[inline(always)]
    pub(crate) fn allowed(&self, x: i32, y: i32, dir: usize) -> bool {
        let (nx, ny) = (x + DX[dir], y + DY[dir]);
        self.free(nx, ny) && (dir < 4 || (self.free(nx, y) && self.free(x, ny)))
    }

    /// The 3 x 3 cells around `(x, y)` (a cell of the grid), bit `3 (dy + 1) + dx + 1`
    /// set for a free cell at offset `(dx, dy)`: one window read per row.
    #[inline(always)]
    pub(crate) fn neighbourhood(&self, x: u32, y: u32) -> usize {
        // Padded row y + 1 holds row y; position x + PAD - 1 is the cell left of (x, y).
        let (r, p) = (y as usize + 1, x as usize + PAD - 1);
        let row = |r: usize| (self.rows.window(r, p) & 7) as usize;
        row(r - 1) | row(r) << 3 | row(r + 1) << 6
    }

    /// The straight jump from `(x, y)` in direction `dir` (0 to 3): `(true, k)` when it
    /// reaches a jump point (a forced cell or the goal) `k` cells on, `(false, k)` when it
    /// ends at a wall after `k` free cells.
    #[inline(always)]
    pub(crate) fn jump(&self, x: u32, y: u32, dir: usize, goal: Cell) -> (bool, u32) {
        let (x, y) = (x as usize, y as usize);
        let (k_found, k) = match dir {
            0 | 1 => {
                let target = if goal.y as usize == y {
                    goal.x as usize + PAD
                } else {
                    usize::MAX
                };
                if dir == 0 {
                    self.rows.jump::<true>(y + 1, x + PAD, target)
                } else {
                    self.rows.jump::<false>(y + 1, x + PAD, target)
                }
            }
            _ => {
                let target = if goal.x as usize == x {
                    goal.y as usize + PAD
                } else {
                    usize::MAX
                };
                if dir == 2 {
                    self.columns.jump::<true>(x + 1, y + PAD, target)
                } else {
                    self.columns.jump::<false>(x + 1, y + PAD, target)
                }
            }
        };
        (k_found, k as u32)
    }

    /// Whether the straight move `dir` (0 to 3) onto the free cell `(x, y)` makes it a jump
    /// point by the forced-neighbour rule (see `Rows::jump`).
    #[inline]
    pub(crate) fn forced(&self, x: i32, y: i32, dir: usize) -> bool {
        let (dx, dy) = (DX[dir], DY[dir]);
        if dy == 0 {
            (self.free(x, y - 1) && !self.free(x - dx, y - 1))
                || (self.free(x, y + 1) && !self.free(x - dx, y + 1))
        } else {
            (self.free(x - 1, y) && !self.free(x - 1, y - dy))
                || (self.free(x + 1, y) && !self.free(x + 1, y - dy))
        }
    }

    /// Bytes held (both copies).
    pub(crate) fn memory_bytes(&self) -> usize {
        (self.rows.data.len() + self.columns.data.len()) * std::mem::size_of::<u64>()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The straight jump cell by cell, from the definitions: the reference for the
    /// block-based one.
    fn naive(bits: &BitGrid, x: u32, y: u32, dir: usize, goal: Cell) -> (bool, u32) {
        let (mut cx, mut cy, mut k) = (x as i32, y as i32, 0);
        loop {
            let (nx, ny) = (cx + DX[dir], cy + DY[dir]);
            if !bits.free(nx, ny) {
                return (false, k);
            }
            k += 1;
            if (nx as u32, ny as u32) == (goal.x, goal.y) || bits.forced(nx, ny, dir) {
                return (true, k);
            }
            (cx, cy) = (nx, ny);
        }
    }

    /// Every row and column bit, padding included, against the grid, on grids whose rows
    /// and columns cross the packed words' boundaries; and `is_for` tells the grid from one
    /// that differs in a single cell.
    #[test]
    fn rows_and_columns_are_the_grid() {
        use rand::{Rng, SeedableRng};
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(64);
        for (w, h) in [(1, 1), (63, 2), (64, 65), (65, 130), (3, 200)] {
            let density = rng.gen_range(0.0..1.0);
            let free: Vec<bool> = (0..w * h).map(|_| !rng.gen_bool(density)).collect();
            let grid = Grid::from_free_cells(w, h, free).unwrap();
            let bits = BitGrid::build(&grid);
            for y in -1..=h as i32 {
                for x in -1..=w as i32 {
                    let expect = x >= 0 && y >= 0 && grid.is_free(Cell::new(x as u32, y as u32));
                    assert_eq!(bits.free(x, y), expect, "{w}x{h} row bit ({x}, {y})");
                    let column = bits
                        .columns
                        .bit((x + 1) as usize, (y + PAD as i32) as usize);
                    assert_eq!(column, expect, "{w}x{h} column bit ({x}, {y})");
                }
            }
            assert!(bits.is_for(&grid));
            let mut other = grid.clone();
            let cell = Cell::new(w - 1, h - 1);
            other.set_free(cell, !grid.is_free(cell));
            assert!(!bits.is_for(&other), "{w}x{h}");
        }
    }

    /// Edits in place between lookups: the cached bits follow into the rows and columns
    /// a new build gives, and say the cells changed.
    #[test]
    fn cached_bits_follow_edits_in_place() {
        use rand::{Rng, SeedableRng};
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(65);
        for (w, h) in [(1, 1), (63, 2), (64, 65), (65, 130), (3, 200)] {
            let free: Vec<bool> = (0..w * h).map(|_| rng.gen_bool(0.7)).collect();
            let mut grid = Grid::from_free_cells(w, h, free).unwrap();
            let mut cache = None;
            assert!(BitGrid::cached(&mut cache, &grid).1);
            for _ in 0..30 {
                for _ in 0..rng.gen_range(1..4) {
                    let cell = Cell::new(rng.gen_range(0..w), rng.gen_range(0..h));
                    grid.set_free(cell, rng.gen_bool(0.5));
                }
                let (bits, changed) = BitGrid::cached(&mut cache, &grid);
                let built = BitGrid::build(&grid);
                assert!(changed);
                assert_eq!(bits.rows.data, built.rows.data, "{w}x{h}");
                assert_eq!(bits.columns.data, built.columns.data, "{w}x{h}");
                assert!(!BitGrid::cached(&mut cache, &grid).1);
            }
        }
    }

    #[test]
    fn block_jumps_agree_with_cell_by_cell_jumps() {
        // Deterministic pseudo-random grids of several widths around multiples of 64.
        let mut state = 0x9e37_79b9_7f4a_7c15u64;
        let mut next = move || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            state
        };
        for (w, h, density) in [
            (1, 1, 0),
            (70, 3, 5),
            (130, 5, 2),
            (64, 64, 20),
            (200, 9, 60),
        ] {
            let free: Vec<bool> = (0..w * h).map(|_| next() % 100 >= density).collect();
            let grid = Grid::from_free_cells(w, h, free).unwrap();
            let bits = BitGrid::build(&grid);
            for cell in grid.cells().filter(|&c| grid.is_free(c)) {
                let goal = grid.cell((next() % grid.len() as u64) as usize);
                for dir in 0..4 {
                    for target in [goal, Cell::new(cell.x, goal.y), Cell::new(goal.x, cell.y)] {
                        assert_eq!(
                            bits.jump(cell.x, cell.y, dir, target),
                            naive(&bits, cell.x, cell.y, dir, target),
                            "{w}x{h} from {cell} dir {dir} target {target}"
                        );
                    }
                }
            }
        }
    }
}
