//! Cells as bits in [`planner_api::Adjacency`]'s padded layout, read a 3 x 3
//! neighbourhood at a time, and tables from such a neighbourhood to a node's moves.
//!
//! A search over 8 moves of reach 1 needs two things per expansion besides the node
//! records: which moves are safe, and which lead to CLOSED cells. Read from bits, the first
//! costs three two-byte loads from an array of a bit per cell (33 KB for 512 x 512) instead
//! of an 8-byte load per cell from the adjacency's masks (2 MB), and the second masks the
//! moves to CLOSED cells out at once instead of a branch per neighbour on its record. Both
//! codes are read at the same offsets. Theta\* and Lazy Theta\* use both; A*, whose padded
//! layout and arrays are its own, uses the [`MoveTable`]s.
//!
//! ```
//! use planner_api::{Adjacency, Cell, Connectivity, Grid, MoveSet, NeighborOrder};
//! use planner_search::neighbourhood::{CellBits, MoveTable};
//!
//! let grid = Grid::from_ascii("
//!     ...
//!     .#.
//!     ...
//! ").unwrap();
//! let moves = MoveSet::new(Connectivity::Eight, false, &NeighborOrder::default()).unwrap();
//! let adjacency = Adjacency::build(&grid, &moves);
//! let mut free = CellBits::default();
//! free.fill_free(&grid, &adjacency);
//! let safe = MoveTable::safe(&moves);
//! let corner = adjacency.index(Cell::new(0, 0));
//! let code = free.code(corner, adjacency.stride());
//! assert_eq!(safe.get(code), adjacency.mask(corner));
//!
//! // Moves into CLOSED cells: here the one to (1, 0).
//! let mut closed = CellBits::default();
//! closed.clear(adjacency.padded_len());
//! closed.set(adjacency.index(Cell::new(1, 0)));
//! let targets = MoveTable::targets(&moves);
//! let to_closed = safe.get(code) & targets.get(closed.code(corner, adjacency.stride()));
//! assert_eq!(to_closed.count_ones(), 1);
//! ```

use planner_api::{packed_words, Adjacency, Cell, Grid, MoveSet};

/// The padded index of the first cell of grid row `y` in the layout with border `reach`
/// and rows of `stride` cells ([`Adjacency`]'s); the row's cell `x` is `x` further on.
fn padded_row(y: usize, reach: usize, stride: usize) -> usize {
    (y + reach) * stride + reach
}

/// Sets the bit of every free cell of `grid` in `bytes`, a bit per cell (bit `p % 8` of
/// byte `p / 8`) of the padded layout with border `reach` and row length `stride`
/// ([`Adjacency`]'s), whose other bits are left as they are. Row by row, 64 cells at a
/// time gathered in a register and OR-ed into the bytes they cover. Setting a bit per
/// cell at its index took a division per cell and a read-modify-write chain on each byte:
/// `cargo bench -p planner-registry --bench change` (A*'s next plan after one cell of a
/// 2048 x 2048 grid changed, 2026-12-06, when such a change rebuilt the bits; now its
/// `rebuild_ms`, a new grid, 1.9-2.2 ms) gave 30.0 ms that way and 2.3 ms this way. Bits
/// past the end of `bytes` are not set.
pub fn set_free_cells(bytes: &mut [u8], grid: &Grid, reach: usize, stride: usize) {
    let width = grid.width() as usize;
    for (y, row) in grid.free_cells().chunks_exact(width.max(1)).enumerate() {
        let start = padded_row(y, reach, stride);
        for (c, word) in packed_words(row).enumerate() {
            let bit = start + 64 * c;
            // The 64 bits from bit `bit % 8` of byte `bit / 8` on: nine bytes at most.
            let spread = u128::from(word) << (bit % 8);
            for (k, byte) in bytes.iter_mut().skip(bit / 8).take(9).enumerate() {
                *byte |= (spread >> (8 * k)) as u8;
            }
        }
    }
}

/// Brings the bits that [`set_free_cells`] set for an earlier revision of `grid` up to
/// date after the edits of `changed` cells ([`Grid::changed_since`]): each one's bit set
/// when it is free and cleared when it is blocked. Bits past the end of `bytes` are not
/// touched.
pub fn update_free_cells(
    bytes: &mut [u8],
    grid: &Grid,
    changed: impl Iterator<Item = Cell>,
    reach: usize,
    stride: usize,
) {
    for cell in changed {
        let p = padded_row(cell.y as usize, reach, stride) + cell.x as usize;
        if let Some(byte) = bytes.get_mut(p / 8) {
            let bit = 1 << (p % 8);
            *byte = if grid.is_free(cell) {
                *byte | bit
            } else {
                *byte & !bit
            };
        }
    }
}

/// A weighted grid's weights in a padded layout (border `reach`, rows of `stride` cells,
/// [`Adjacency`]'s form; 0 outside the grid and for a grid without weights), kept between
/// searches: copied a row at a time for a new grid, and after edits in place
/// ([`Grid::changed_since`]) only the edited cells' weights.
#[derive(Debug, Clone, Default)]
pub struct PaddedWeights {
    revision: Option<u64>,
    reach: usize,
    stride: usize,
    cells: Vec<u16>,
}

impl PaddedWeights {
    /// The weights of `grid` in the layout of `padded_len` cells with border `reach` and
    /// rows of `stride` cells.
    pub fn get_or_build(
        &mut self,
        grid: &Grid,
        reach: usize,
        stride: usize,
        padded_len: usize,
    ) -> &[u16] {
        let same_layout =
            (self.reach, self.stride, self.cells.len()) == (reach, stride, padded_len);
        let changed = match self.revision {
            Some(revision) if same_layout => grid.changed_since(revision),
            _ => None,
        };
        match changed {
            Some(changed) => {
                if grid.weights().is_some() {
                    for cell in changed {
                        let p = padded_row(cell.y as usize, reach, stride) + cell.x as usize;
                        self.cells[p] = grid.weight(cell);
                    }
                }
            }
            None => {
                self.cells.clear();
                self.cells.resize(padded_len, 0);
                if let Some(weights) = grid.weights() {
                    // A copy per row, no division per cell.
                    let width = grid.width() as usize;
                    for (y, row) in weights.cells().chunks_exact(width.max(1)).enumerate() {
                        let start = padded_row(y, reach, stride);
                        self.cells[start..start + row.len()].copy_from_slice(row);
                    }
                }
                (self.reach, self.stride) = (reach, stride);
            }
        }
        self.revision = Some(grid.revision());
        &self.cells
    }

    /// The weights as [`PaddedWeights::get_or_build`] last made them.
    pub fn cells(&self) -> &[u16] {
        &self.cells
    }
}

/// A bit per padded cell (bit `p % 8` of byte `p / 8`), with two bytes of slack so that
/// every grid cell's neighbourhood reads as three two-byte loads.
#[derive(Debug, Clone, Default)]
pub struct CellBits {
    bytes: Vec<u8>,
}

impl CellBits {
    /// Every bit of a layout of `padded_len` cells clear (the memory kept).
    pub fn clear(&mut self, padded_len: usize) {
        self.bytes.clear();
        self.bytes.resize(padded_len / 8 + 3, 0);
    }

    /// Sizes the bits for a layout of `padded_len` cells, all clear, unless they already
    /// have that size (then they are left as they are: a search clears the bits it set,
    /// [`CellBits::unset`], so that it costs the cells it touches, not the grid). Returns
    /// whether they were cleared.
    pub fn fit(&mut self, padded_len: usize) -> bool {
        if self.bytes.len() == padded_len / 8 + 3 {
            return false;
        }
        self.clear(padded_len);
        true
    }

    /// The bits of `grid`'s free cells in `adjacency`'s layout (every other bit clear).
    pub fn fill_free(&mut self, grid: &Grid, adjacency: &Adjacency) {
        self.clear(adjacency.padded_len());
        set_free_cells(&mut self.bytes, grid, adjacency.reach(), adjacency.stride());
    }

    /// Makes these the bits of `grid`'s free cells in `adjacency`'s layout, as
    /// [`CellBits::fill_free`], when they are those of the grid at revision `built` (or
    /// `None`): brought up to date from [`Grid::changed_since`] when it knows the cells
    /// edited since, else filled anew.
    pub fn follow_free(&mut self, grid: &Grid, adjacency: &Adjacency, built: Option<u64>) {
        let padded_len = adjacency.padded_len();
        match built.and_then(|revision| grid.changed_since(revision)) {
            Some(changed) if self.bytes.len() == padded_len / 8 + 3 => {
                let (reach, stride) = (adjacency.reach(), adjacency.stride());
                update_free_cells(&mut self.bytes, grid, changed, reach, stride);
            }
            _ => self.fill_free(grid, adjacency),
        }
    }

    /// The bytes these bits take.
    pub fn bytes_for(padded_len: usize) -> u64 {
        (padded_len / 8 + 3) as u64
    }

    /// Sets padded cell `p`'s bit (nothing outside the layout).
    #[inline(always)]
    pub fn set(&mut self, p: usize) {
        if let Some(byte) = self.bytes.get_mut(p / 8) {
            *byte |= 1 << (p % 8);
        }
    }

    /// Clears padded cell `p`'s bit.
    #[inline(always)]
    pub fn unset(&mut self, p: usize) {
        if let Some(byte) = self.bytes.get_mut(p / 8) {
            *byte &= !(1 << (p % 8));
        }
    }

    /// Padded cell `p`'s bit (false outside the layout).
    #[inline(always)]
    pub fn get(&self, p: usize) -> bool {
        self.bytes
            .get(p / 8)
            .is_some_and(|&b| b >> (p % 8) & 1 == 1)
    }

    /// The 3 x 3 neighbourhood of padded cell `p` in rows of `stride` cells: bit
    /// `3 (dy + 1) + dx + 1` is the cell at offset `(dx, dy)`. Precondition: `p` is a grid
    /// cell of a layout with a border of at least one cell (out of range reads as clear).
    #[inline(always)]
    pub fn code(&self, p: usize, stride: usize) -> usize {
        let three = |at: usize| match self.bytes.get(at / 8..at / 8 + 2) {
            Some(&[low, high]) => (usize::from(u16::from_le_bytes([low, high])) >> (at % 8)) & 7,
            _ => 0,
        };
        let above = p.wrapping_sub(stride + 1);
        three(above) | three(p.wrapping_sub(1)) << 3 | three(p + stride - 1) << 6
    }
}

/// A node's moves by the 3 x 3 neighbourhood code of [`CellBits::code`], for a move set of
/// at most 8 moves of reach 1 (its moves' bits in the set's order, as
/// [`Adjacency::mask`]'s). The default table is empty: every code has no moves.
#[derive(Debug, Clone, Default)]
pub struct MoveTable {
    moves: Vec<u8>,
}

impl MoveTable {
    /// For a code of free cells: the safe moves, whose target and every cell passed
    /// through ([`planner_api::Move`]'s `via`) are free, as [`Adjacency::mask`].
    /// Precondition: at most 8 moves of reach 1.
    pub fn safe(moves: &MoveSet) -> MoveTable {
        MoveTable::build(moves, true)
    }

    /// For a code of marked cells (CLOSED ones, say): the moves whose target is marked.
    /// Precondition: at most 8 moves of reach 1.
    pub fn targets(moves: &MoveSet) -> MoveTable {
        MoveTable::build(moves, false)
    }

    fn build(moves: &MoveSet, with_via: bool) -> MoveTable {
        let moves = (0..512u32)
            .map(|code| {
                let set = |dx: i32, dy: i32| code >> (3 * (dy + 1) + dx + 1) & 1 == 1;
                let mut mask = 0u8;
                for (m, mv) in moves.moves().iter().enumerate().take(8) {
                    if set(mv.dx, mv.dy)
                        && (!with_via || mv.via.iter().all(|&(vx, vy)| set(vx, vy)))
                    {
                        mask |= 1 << m;
                    }
                }
                mask
            })
            .collect();
        MoveTable { moves }
    }

    /// The bytes the table takes.
    pub fn bytes(&self) -> usize {
        self.moves.len()
    }

    /// The moves of neighbourhood `code` (below 512).
    #[inline(always)]
    pub fn get(&self, code: usize) -> u64 {
        u64::from(self.moves.get(code).copied().unwrap_or(0))
    }
}

/// The number of set bits of every byte (the baseline x86-64 target has no popcount
/// instruction): a [`MoveTable`] mask's moves are `BIT_COUNT[mask as usize]`.
pub const BIT_COUNT: [u8; 256] = {
    let mut counts = [0u8; 256];
    let mut byte = 0;
    while byte < 256 {
        counts[byte] = (byte as u8).count_ones() as u8;
        byte += 1;
    }
    counts
};

#[cfg(test)]
mod tests {
    use super::*;
    use planner_api::{Connectivity, NeighborOrder};
    use rand::{Rng, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    /// Weights and free cells edited in place between lookups, some lookups in another
    /// layout: the kept weights equal a new copy's, and the free-cell bits brought up to
    /// date ([`update_free_cells`]) equal a new fill's.
    #[test]
    fn kept_weights_and_bits_follow_edits_in_place() {
        let mut rng = ChaCha8Rng::seed_from_u64(32);
        for (w, h) in [(1, 1), (9, 70), (70, 9), (65, 64)] {
            let free = (0..w * h).map(|_| rng.gen_bool(0.8)).collect();
            let weights = (0..w * h).map(|_| rng.gen_range(1..=255)).collect();
            let mut grid = Grid::from_free_cells(w, h, free)
                .and_then(|g| g.with_weights(weights, planner_api::CostRule::Mean))
                .unwrap();
            let mut kept = PaddedWeights::default();
            let (mut bits, mut built) = (Vec::new(), None);
            for step in 0..40 {
                for _ in 0..rng.gen_range(1..4) {
                    let cell = Cell::new(rng.gen_range(0..w), rng.gen_range(0..h));
                    grid.set_weight(cell, rng.gen_range(1..=255));
                    grid.set_free(cell, rng.gen_bool(0.7));
                }
                let reach = if step % 10 == 9 { 2 } else { 1 };
                let stride = w as usize + 2 * reach;
                let padded_len = stride * (h as usize + 2 * reach);
                let cells = kept.get_or_build(&grid, reach, stride, padded_len).to_vec();
                let new = PaddedWeights::default()
                    .get_or_build(&grid, reach, stride, padded_len)
                    .to_vec();
                assert_eq!(cells, new, "{w} x {h}, step {step}");
                // The free bits in a reach-1 layout, updated when the last fill's allows.
                let stride = w as usize + 2;
                let padded_len = stride * (h as usize + 2);
                match built.and_then(|r| grid.changed_since(r)) {
                    Some(changed) => update_free_cells(&mut bits, &grid, changed, 1, stride),
                    None => {
                        bits = vec![0; padded_len / 8 + 3];
                        set_free_cells(&mut bits, &grid, 1, stride);
                    }
                }
                built = Some(grid.revision());
                let mut filled = vec![0; padded_len / 8 + 3];
                set_free_cells(&mut filled, &grid, 1, stride);
                assert_eq!(bits, filled, "{w} x {h}, step {step}");
            }
        }
    }

    /// On random grids, with and without corner cutting, every cell's safe moves from the
    /// bits equal the adjacency's masks, and the CLOSED moves equal the moves whose target
    /// is marked, for random marks.
    #[test]
    fn codes_agree_with_the_adjacency() {
        let mut rng = ChaCha8Rng::seed_from_u64(7);
        for trial in 0..60 {
            let (w, h) = (rng.gen_range(1..40u32), rng.gen_range(1..12u32));
            let density = rng.gen_range(0.0..0.6);
            let text: String = (0..h)
                .map(|_| {
                    let row: String = (0..w)
                        .map(|_| if rng.gen_bool(density) { '#' } else { '.' })
                        .collect();
                    row + "\n"
                })
                .collect();
            let grid = Grid::from_ascii(&text).unwrap();
            let cutting = trial % 2 == 1;
            for (connectivity, cutting) in
                [(Connectivity::Four, false), (Connectivity::Eight, cutting)]
            {
                let moves = MoveSet::new(connectivity, cutting, &NeighborOrder::default()).unwrap();
                let adjacency = Adjacency::build(&grid, &moves);
                let mut free = CellBits::default();
                free.fill_free(&grid, &adjacency);
                let mut marked = CellBits::default();
                marked.clear(adjacency.padded_len());
                for cell in grid.cells() {
                    if rng.gen_bool(0.3) {
                        marked.set(adjacency.index(cell));
                    }
                }
                let (safe, targets) = (MoveTable::safe(&moves), MoveTable::targets(&moves));
                for cell in grid.cells() {
                    let p = adjacency.index(cell);
                    assert_eq!(free.get(p), grid.is_free(cell));
                    let code = free.code(p, adjacency.stride());
                    if !grid.is_free(cell) {
                        continue;
                    }
                    assert_eq!(safe.get(code), adjacency.mask(p), "{cell} in\n{text}");
                    let mut expect = 0;
                    for m in 0..moves.moves().len() as u32 {
                        if marked.get(adjacency.neighbor(p, m)) {
                            expect |= 1 << m;
                        }
                    }
                    let code = marked.code(p, adjacency.stride());
                    assert_eq!(targets.get(code), expect, "{cell}");
                }
            }
        }
    }

    /// Every padded bit is set exactly for a free grid cell, on rows of one to two and a
    /// half words and borders of one and two cells.
    #[test]
    fn free_cells_are_set_exactly() {
        let mut rng = ChaCha8Rng::seed_from_u64(11);
        for w in [1u32, 7, 63, 64, 65, 130] {
            for reach in [1usize, 2] {
                let h = rng.gen_range(1..6u32);
                let density = rng.gen_range(0.0..1.0);
                let free = (0..w * h).map(|_| !rng.gen_bool(density)).collect();
                let grid = Grid::from_free_cells(w, h, free).unwrap();
                let stride = w as usize + 2 * reach;
                let padded_len = stride * (h as usize + 2 * reach);
                let mut bits = CellBits::default();
                bits.clear(padded_len);
                set_free_cells(&mut bits.bytes, &grid, reach, stride);
                for p in 0..padded_len {
                    let (x, y) = (
                        (p % stride) as i64 - reach as i64,
                        (p / stride) as i64 - reach as i64,
                    );
                    let expect = x >= 0
                        && y >= 0
                        && grid.is_free(planner_api::Cell::new(x as u32, y as u32));
                    assert_eq!(
                        bits.get(p),
                        expect,
                        "width {w}, reach {reach}, cell ({x}, {y})"
                    );
                }
            }
        }
    }

    #[test]
    fn fit_keeps_the_bits_of_the_same_size_and_unset_clears_one() {
        let mut bits = CellBits::default();
        assert!(bits.fit(100));
        bits.set(7);
        bits.set(8);
        assert!(!bits.fit(100));
        assert!(bits.get(7) && bits.get(8));
        bits.unset(7);
        assert!(!bits.get(7) && bits.get(8));
        assert!(bits.fit(200));
        assert!(!bits.get(8));
    }

    #[test]
    fn bit_counts() {
        for (byte, &count) in BIT_COUNT.iter().enumerate() {
            assert_eq!(u32::from(count), byte.count_ones());
        }
    }
}
