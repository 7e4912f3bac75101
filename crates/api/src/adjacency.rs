//! Per-cell masks of the safe moves, built once per grid from a [`MoveSet`]: the hot-loop
//! form of a neighbourhood for searches that keep per-cell arrays.
//!
//! Cells are indexed in a *padded* row-major layout: the grid surrounded by a border of
//! `reach` cells (the longest move's Chebyshev length), so that every neighbour of every
//! cell has an index inside the arrays and per-neighbour flags (visited marks) can be read
//! without a bounds test. Bit `m` of `safe[p]` is set when move `m` of the set (in the set's
//! order) may be taken from cell `p`: the target is in bounds and free and every cell the
//! move passes through (`Move::via`) is free, exactly [`MoveSet::apply`]. The hot loop then
//! needs no obstacle test at all: a clear bit is a blocked check, a set bit gives the
//! neighbour as `p + delta[m]`. Masks are `u64`, enough for the largest set (48 moves).

use crate::grid::{packed_words, Cell, Grid};
use crate::moves::MoveSet;

/// A bit of every mask word that searches may use as a per-cell scratch flag (move masks
/// use bits 0..48 at most). [`Adjacency::build`] leaves it clear; a search that sets it
/// must clear it again before it returns.
pub const SCRATCH: u64 = 1 << 63;

/// The safe-move masks of one grid and the padded index offset of each move.
#[derive(Debug, Clone)]
pub struct Adjacency {
    /// The grid the masks were built for: the cache key.
    grid: Grid,
    /// The revision of the last grid found equal to `grid`: the fast cache check.
    revision: u64,
    /// Border width: the longest move's reach.
    reach: usize,
    /// Padded row length, `width + 2 * reach`.
    stride: usize,
    /// Bit `m` set when move `m` is safe from the padded cell (0 for blocked and border
    /// cells). Bit [`SCRATCH`] is the search's scratch mark, clear between searches.
    safe: Vec<u64>,
    /// Padded index offset `dy * stride + dx` of move `m`; entries past the set's size are 0.
    delta: [isize; 64],
    /// Number of moves in the set.
    n_moves: usize,
    /// All moves of the set: bits `0..n_moves`.
    all: u64,
}

impl Adjacency {
    /// Builds the masks of `grid` for `moves`.
    pub fn build(grid: &Grid, moves: &MoveSet) -> Adjacency {
        let mut adjacency = Adjacency {
            grid: grid.clone(),
            revision: grid.revision(),
            reach: 0,
            stride: 0,
            safe: Vec::new(),
            delta: [0; 64],
            n_moves: 0,
            all: 0,
        };
        adjacency.fill(grid, moves);
        adjacency
    }

    /// Makes these the masks of `grid` for `moves`, in the memory of the old ones: a
    /// changed grid's masks do not cost a new allocation (whose pages the operating system
    /// would fault in again, on a 2048 x 2048 grid most of a rebuild's time).
    pub fn rebuild(&mut self, grid: &Grid, moves: &MoveSet) {
        self.grid.clone_from(grid);
        self.revision = grid.revision();
        self.fill(grid, moves);
    }

    /// Whether `n_changed` edited cells are brought in by [`Adjacency::update`] rather than
    /// a rebuild: while the cells whose masks it recomputes one move at a time (the
    /// `(2 reach + 1)^2` around each edit) are at most 1/16 of the padded cells (a rebuild
    /// sets 64 cells' bits for a move in a few word operations).
    fn updates(&self, n_changed: usize) -> bool {
        let around = (2 * self.reach + 1).pow(2);
        n_changed.saturating_mul(around).saturating_mul(16) <= self.safe.len()
    }

    /// Brings the masks up to date with `grid` after the edits of the `changed` cells
    /// ([`Grid::changed_since`] since the revision they were built for): the masks of the
    /// cells within `reach` of an edit, the only ones whose moves' targets or `via` cells
    /// it can change, from their definition ([`MoveSet::apply`]). Preconditions: `moves`
    /// is the set the masks were built for, and `grid` is the one they were built for
    /// but for those cells.
    fn update(&mut self, grid: &Grid, moves: &MoveSet, changed: &[Cell]) {
        for &cell in changed {
            self.grid.set_free(cell, grid.is_free(cell));
            self.grid.set_weight(cell, grid.weight(cell));
        }
        let reach = self.reach as u32;
        let (width, height) = (grid.width(), grid.height());
        for &cell in changed {
            let (x0, y0) = (cell.x.saturating_sub(reach), cell.y.saturating_sub(reach));
            let (x1, y1) = (
                (cell.x + reach).min(width - 1),
                (cell.y + reach).min(height - 1),
            );
            for y in y0..=y1 {
                for x in x0..=x1 {
                    let near = Cell::new(x, y);
                    let mask = match grid.is_free(near) {
                        true => moves
                            .moves()
                            .iter()
                            .enumerate()
                            .filter(|(_, mv)| moves.apply(grid, near, mv).is_some())
                            .fold(0, |mask, (m, _)| mask | 1 << m),
                        false => 0,
                    };
                    let p = self.index(near);
                    self.safe[p] = mask;
                }
            }
        }
        self.revision = grid.revision();
    }

    /// Sizes the layout for `grid` and `moves` and fills the masks.
    fn fill(&mut self, grid: &Grid, moves: &MoveSet) {
        let reach = reach_of(moves);
        let stride = grid.width() as usize + 2 * reach;
        self.delta = [0; 64];
        for (slot, mv) in self.delta.iter_mut().zip(moves.moves()) {
            // |dy * stride + dx| < 2^33, far inside isize on every supported target.
            *slot = (i64::from(mv.dy) * stride as i64 + i64::from(mv.dx)) as isize;
        }
        // The border's masks are 0 and `fill_masks` writes every grid cell's, so the same
        // layout needs no clearing (34 MB to write on a 2048 x 2048 grid).
        let padded_len = Adjacency::padded_len_for(grid, moves);
        if (self.safe.len(), self.stride, self.reach) != (padded_len, stride, reach) {
            self.safe.clear();
            self.safe.resize(padded_len, 0);
        }
        let (width, height) = (grid.width() as usize, grid.height() as usize);
        fill_masks(
            &mut self.safe,
            grid.free_cells(),
            width,
            height,
            reach,
            moves,
        );
        let n_moves = moves.moves().len();
        self.all = if n_moves >= 64 {
            u64::MAX
        } else {
            (1u64 << n_moves) - 1
        };
        (self.reach, self.stride, self.n_moves) = (reach, stride, n_moves);
    }

    /// The number of padded cells an adjacency of `grid` and `moves` has (its
    /// [`Adjacency::padded_len`]), computed without building it.
    pub fn padded_len_for(grid: &Grid, moves: &MoveSet) -> usize {
        let reach = reach_of(moves);
        (grid.width() as usize + 2 * reach) * (grid.height() as usize + 2 * reach)
    }

    /// The bytes an adjacency of `grid` and `moves` takes (its masks, its copy of the
    /// grid, and the packed copy of the free cells that the build frees when it returns),
    /// computed without building it: what a planner adds up before a
    /// [`Budget::check_memory`](crate::Budget::check_memory).
    pub fn bytes_for(grid: &Grid, moves: &MoveSet) -> u64 {
        let (width, height) = (grid.width() as usize, grid.height() as usize);
        let packed = PackedRows::words_for(width, height, reach_of(moves)) as u64 * 8;
        8 * Adjacency::padded_len_for(grid, moves) as u64 + grid.len() as u64 + packed
    }

    /// Whether these masks were built for `grid`.
    pub fn is_for(&self, grid: &Grid) -> bool {
        self.grid == *grid
    }

    /// Number of padded cells: the length of per-cell arrays indexed like `safe`.
    pub fn padded_len(&self) -> usize {
        self.safe.len()
    }

    /// The padded index of `cell`. Precondition: the cell is in the grid.
    pub fn index(&self, cell: Cell) -> usize {
        (cell.y as usize + self.reach) * self.stride + cell.x as usize + self.reach
    }

    /// The cell at padded index `p`. Precondition: `p` is a grid cell, not a border cell.
    pub fn cell(&self, p: usize) -> Cell {
        // Both coordinates are below the grid's u32 sides.
        Cell::new(
            (p % self.stride - self.reach) as u32,
            (p / self.stride - self.reach) as u32,
        )
    }
}

impl Adjacency {
    /// The padded index reached from `p` by move `m` (`m < n_moves`; only meaningful when
    /// bit `m` of `mask(p)` is set).
    #[inline]
    pub fn neighbor(&self, p: usize, m: u32) -> usize {
        p.wrapping_add_signed(self.delta[(m & 63) as usize])
    }

    /// The move mask of padded cell `p` (0 for blocked and border cells).
    #[inline]
    pub fn mask(&self, p: usize) -> u64 {
        self.safe[p]
    }

    /// Every padded cell's mask.
    pub fn masks(&self) -> &[u64] {
        &self.safe
    }

    /// The masks, mutable for the [`SCRATCH`] bit, and the move deltas.
    pub fn split_mut(&mut self) -> (&mut [u64], &[isize; 64]) {
        (&mut self.safe, &self.delta)
    }

    /// The padded index offset of each move (entries past [`Adjacency::n_moves`] are 0).
    pub fn deltas(&self) -> &[isize; 64] {
        &self.delta
    }

    /// Number of moves in the set.
    pub fn n_moves(&self) -> usize {
        self.n_moves
    }

    /// Bits `0..n_moves`: every move of the set.
    pub fn all(&self) -> u64 {
        self.all
    }

    /// Padded row length, `width + 2 * reach`.
    pub fn stride(&self) -> usize {
        self.stride
    }

    /// Border width.
    pub fn reach(&self) -> usize {
        self.reach
    }

    /// Returns the masks in `cache` when they were built for `grid`, brought up to date
    /// when `grid` is theirs edited in place ([`Grid::changed_since`]), else rebuilt.
    /// Precondition: `moves` is the same set every time the cache is used.
    pub fn cached<'a>(
        cache: &'a mut Option<Adjacency>,
        grid: &Grid,
        moves: &MoveSet,
    ) -> &'a mut Adjacency {
        cached(cache, grid, moves)
    }
}

/// Writes `safe[p]` for every grid cell `p` of the padded layout of [`Adjacency`] (the
/// border's entries are left as they are): bit `m` set when `p` is free and move `m` is
/// safe from it, its target and every `via` cell free grid cells. Word-parallel: the free
/// cells are packed a bit per cell into rows of the padded width with zero words around
/// them, so a move's safe bits for 64 cells of a row are the AND of the row's word and one
/// shifted word per offset (target and `via`), and each cell's mask gathers its moves'
/// bits eight cells and eight moves at a time ([`SPREAD`]). `cargo bench -p planner-api
/// --bench adjacency` (2026-12-06, two runs): on its 512 x 512 grid 0.8 ms (8 moves) to
/// 5.4 ms (48 moves), on its 2048 x 2048 grid 26.3-26.7 to 99-100 ms (rebuilt in place
/// for another grid 12.9-13.1 to 85.7-86.7 ms; after one cell edited in place,
/// [`Adjacency::update`], 0.001 to 0.017 ms), where the build before it, cell by cell with
/// a bounds test per offset, took 11.0 to 124 ms and 185 to 1919 ms (2026-12-05).
fn fill_masks(
    safe: &mut [u64],
    free: &[bool],
    width: usize,
    height: usize,
    reach: usize,
    moves: &MoveSet,
) {
    let stride = width + 2 * reach;
    let (margin, row_words) = PackedRows::shape(width, reach);
    let mut bits = vec![0u64; PackedRows::words_for(width, height, reach)];
    for (y, row) in free.chunks_exact(width.max(1)).enumerate().take(height) {
        let base = (y + reach) * row_words * 64 + margin * 64 + reach;
        // 64 cells at a time gathered in a register and stored as the (at most) two words
        // they straddle.
        for (c, word) in packed_words(row).enumerate() {
            let bit = base + 64 * c;
            bits[bit / 64] |= word << (bit % 64);
            if bit % 64 != 0 {
                bits[bit / 64 + 1] |= word >> (64 - bit % 64);
            }
        }
    }
    // The 64 columns of padded row `row` from column `column` on (which may be negative,
    // down to `-margin * 64`).
    let word_at = |row: usize, column: isize| -> u64 {
        // In range: `column + margin * 64 >= 0`, and the trailing zero words cover the end.
        let bit = row * row_words * 64 + (column + (margin * 64) as isize) as usize;
        let (word, shift) = (bit / 64, bit % 64);
        let low = bits.get(word).copied().unwrap_or(0) >> shift;
        let high = match shift {
            0 => 0,
            _ => bits.get(word + 1).copied().unwrap_or(0) << (64 - shift),
        };
        low | high
    };
    let offsets: Vec<Vec<(isize, isize)>> = moves
        .moves()
        .iter()
        .map(|mv| {
            std::iter::once((mv.dx, mv.dy))
                .chain(mv.via.iter().copied())
                .map(|(dx, dy)| (dx as isize, dy as isize))
                .collect()
        })
        .collect();
    let mut words = vec![0u64; offsets.len()];
    for y in reach..reach + height {
        for start in (reach..reach + width).step_by(64) {
            let own = word_at(y, start as isize);
            let cells = (reach + width - start).min(64);
            let row = &mut safe[y * stride + start..y * stride + start + cells];
            if own == 0 {
                row.fill(0);
                continue;
            }
            for (word, offsets) in words.iter_mut().zip(&offsets) {
                *word = offsets.iter().fold(own, |acc, &(dx, dy)| {
                    // Rows and columns inside the padded grid: |dx|, |dy| <= reach.
                    acc & word_at(y.wrapping_add_signed(dy), start as isize + dx)
                });
            }
            for (j, chunk) in row.chunks_mut(8).enumerate() {
                // Eight cells, eight moves at a time: byte i of `flags` holds moves
                // 8 g .. 8 g + 8 of cell 8 j + i, stored into the masks in place. (Masks
                // gathered in an array and then copied became a call to `memcpy` per
                // eight cells, a third of a rebuild's time; an array of the groups' flags
                // read back as vectors stalled on the stores.)
                for (g, group) in words.chunks(8).enumerate() {
                    let flags = group.iter().enumerate().fold(0, |flags, (k, &word)| {
                        flags | SPREAD[(word >> (8 * j) & 0xff) as usize] << k
                    });
                    if g == 0 {
                        for (i, mask) in chunk.iter_mut().enumerate() {
                            *mask = flags >> (8 * i) & 0xff;
                        }
                    } else {
                        for (i, mask) in chunk.iter_mut().enumerate() {
                            *mask |= (flags >> (8 * i) & 0xff) << (8 * g);
                        }
                    }
                }
            }
        }
    }
}

/// `SPREAD[b]` has bit `i` of `b` at bit `8 i`: a byte of eight cells' flags spread to a
/// flag per byte, so that eight moves' flags shifted by their index gather into a byte
/// per cell.
const SPREAD: [u64; 256] = {
    let mut table = [0u64; 256];
    let mut b = 0;
    while b < 256 {
        let mut i = 0;
        while i < 8 {
            table[b] |= ((b as u64 >> i) & 1) << (8 * i);
            i += 1;
        }
        b += 1;
    }
    table
};

/// The shape of [`fill_masks`]'s packed rows.
struct PackedRows;

impl PackedRows {
    /// The zero words before each packed row (a shifted read of a row's word stays inside
    /// the row for offsets up to `margin * 64` columns) and the words per row: the padded
    /// width's, a margin on both sides and one more for reads past the end.
    fn shape(width: usize, reach: usize) -> (usize, usize) {
        let margin = reach.div_ceil(64);
        let stride = width + 2 * reach;
        (margin, stride.div_ceil(64) + 2 * margin + 1)
    }

    /// The words of every padded row.
    fn words_for(width: usize, height: usize, reach: usize) -> usize {
        Self::shape(width, reach).1 * (height + 2 * reach)
    }
}

/// The longest move's Chebyshev length (1 for an empty set): the border's width.
fn reach_of(moves: &MoveSet) -> usize {
    moves
        .moves()
        .iter()
        .map(|m| m.dx.unsigned_abs().max(m.dy.unsigned_abs()) as usize)
        .max()
        .unwrap_or(1)
}

fn cached<'a>(cache: &'a mut Option<Adjacency>, grid: &Grid, moves: &MoveSet) -> &'a mut Adjacency {
    match cache {
        // Equal revisions mean equal grids: no need to compare the cells.
        Some(adjacency) if adjacency.revision == grid.revision() => {}
        Some(adjacency) => {
            let changed: Option<Vec<Cell>> = grid
                .changed_since(adjacency.revision)
                .map(Iterator::collect)
                .filter(|changed: &Vec<Cell>| adjacency.updates(changed.len()));
            match changed {
                Some(changed) => adjacency.update(grid, moves, &changed),
                None if adjacency.is_for(grid) => adjacency.revision = grid.revision(),
                None => adjacency.rebuild(grid, moves),
            }
        }
        None => *cache = Some(Adjacency::build(grid, moves)),
    }
    match cache {
        Some(adjacency) => adjacency,
        None => unreachable!("the adjacency cache was just filled"),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::moves::{Connectivity, NeighborOrder};

    /// Checks every mask bit of `grid`'s adjacency against [`MoveSet::apply`] (the
    /// definition, cell by cell) and every safe move's target against the move.
    fn check(grid: &Grid, moves: &MoveSet) {
        let adjacency = Adjacency::build(grid, moves);
        let mut n_safe = 0;
        for cell in grid.cells() {
            let index = adjacency.index(cell);
            assert_eq!(adjacency.cell(index), cell);
            for (m, mv) in moves.moves().iter().enumerate() {
                let expect = if grid.is_free(cell) {
                    moves.apply(grid, cell, mv)
                } else {
                    None
                };
                let bit = adjacency.mask(index) >> m & 1 == 1;
                assert_eq!(bit, expect.is_some(), "{grid:?} {cell} move {m}");
                if let Some(to) = expect {
                    n_safe += 1;
                    assert_eq!(
                        adjacency.cell(index.wrapping_add_signed(adjacency.deltas()[m])),
                        to
                    );
                }
            }
        }
        // The border's masks are 0 too.
        let total: u64 = adjacency
            .masks()
            .iter()
            .map(|m| u64::from(m.count_ones()))
            .sum();
        assert_eq!(total, n_safe);
    }

    /// Every neighbourhood, with and without corner cutting where it has diagonals.
    fn move_sets() -> Vec<MoveSet> {
        let mut sets = Vec::new();
        for connectivity in Connectivity::ALL {
            for cutting in [false, true] {
                if let Ok(moves) = MoveSet::new(connectivity, cutting, &NeighborOrder::default()) {
                    sets.push(moves);
                }
            }
        }
        sets
    }

    #[test]
    fn masks_agree_with_move_set_apply() {
        let grid = Grid::from_ascii(
            "
            ..#...
            .#..#.
            ......
            ##.#..
            ",
        )
        .unwrap();
        for moves in move_sets() {
            check(&grid, &moves);
        }
    }

    /// The word-parallel build on seeded random grids whose widths and heights put cells
    /// on both sides of the packed words' boundaries, at densities from empty to full.
    #[test]
    fn masks_agree_with_move_set_apply_on_random_grids() {
        let mut next = crate::test_rng::xorshift(0x5851_f42d_4c95_7f2d);
        let sets = move_sets();
        // One cache per move set across all the grids: every grid rebuilds the last one's
        // masks in place, whatever their sizes, and must equal a fresh build.
        let mut caches: Vec<Option<Adjacency>> = vec![None; sets.len()];
        for (w, h) in [
            (1, 1),
            (1, 9),
            (7, 1),
            (63, 3),
            (64, 5),
            (65, 4),
            (70, 6),
            (129, 3),
        ] {
            for density in [0, 10, 40, 90, 100] {
                let free = (0..w * h).map(|_| next() % 100 >= density).collect();
                let grid = Grid::from_free_cells(w, h, free).unwrap();
                for (moves, cache) in sets.iter().zip(&mut caches) {
                    check(&grid, moves);
                    let rebuilt = Adjacency::cached(cache, &grid, moves);
                    let built = Adjacency::build(&grid, moves);
                    assert_eq!(rebuilt.masks(), built.masks());
                    assert_eq!(rebuilt.deltas(), built.deltas());
                    assert_eq!(
                        (rebuilt.stride(), rebuilt.reach(), rebuilt.all()),
                        (built.stride(), built.reach(), built.all())
                    );
                }
            }
        }
    }

    /// Random edits in place brought in by [`Adjacency::update`] (through the cache) give
    /// the masks a build gives, for every move set, reaches 1 to 4.
    #[test]
    fn updated_masks_equal_built_ones() {
        let mut next = crate::test_rng::xorshift(0xada9_ce11);
        let sets = move_sets();
        let mut n_updates = 0;
        for round in 0..60 {
            let (w, h) = (20 + (next() % 100) as u32, 20 + (next() % 100) as u32);
            let density = next() % 40;
            let free = (0..w * h).map(|_| next() % 100 >= density).collect();
            let mut grid = Grid::from_free_cells(w, h, free).unwrap();
            if round % 2 == 0 {
                grid = grid
                    .with_weights(vec![2; (w * h) as usize], crate::CostRule::Mean)
                    .unwrap();
            }
            let mut caches: Vec<Option<Adjacency>> = vec![None; sets.len()];
            for step in 0..10 {
                for _ in 0..1 + next() % 3 {
                    let cell = Cell::new(
                        (next() % u64::from(w)) as u32,
                        (next() % u64::from(h)) as u32,
                    );
                    grid.set_free(cell, next() % 2 == 0);
                    grid.set_weight(cell, 1 + (next() % 5) as u16);
                }
                for (moves, cache) in sets.iter().zip(&mut caches) {
                    if let Some(adjacency) = cache {
                        let changed = grid.changed_since(adjacency.revision).map(Iterator::count);
                        n_updates += usize::from(changed.is_some_and(|n| adjacency.updates(n)));
                    }
                    let updated = Adjacency::cached(cache, &grid, moves);
                    let built = Adjacency::build(&grid, moves);
                    assert_eq!(updated.masks(), built.masks(), "round {round} step {step}");
                    assert!(updated.is_for(&grid));
                }
            }
        }
        // Of the 5,940 later lookups (the first of each grid builds), 2,969 update: 1,620,
        // 514, 461 and 374 of reach 1 to 4; the others edited too many cells for their
        // reach and rebuild.
        assert_eq!(n_updates, 2969);
    }

    /// `rebuild` takes any grid and move set, as `build` does.
    #[test]
    fn a_rebuild_with_other_moves_and_size_equals_a_build() {
        let sets = move_sets();
        let small = Grid::from_ascii("..#\n...").unwrap();
        let large = Grid::from_ascii(".....\n.#...\n.....\n...#.").unwrap();
        let mut adjacency = Adjacency::build(&large, &sets[sets.len() - 1]);
        for moves in &sets {
            adjacency.rebuild(&small, moves);
            let built = Adjacency::build(&small, moves);
            assert_eq!(adjacency.masks(), built.masks());
            assert_eq!(adjacency.deltas(), built.deltas());
            assert_eq!(adjacency.n_moves(), built.n_moves());
            assert!(adjacency.is_for(&small));
        }
    }

    #[test]
    fn the_cache_follows_the_grid_through_edits_and_copies() {
        let moves = MoveSet::new(Connectivity::Four, false, &NeighborOrder::default()).unwrap();
        let mut grid = Grid::from_ascii("...\n...").unwrap();
        let centre = |cache: &mut Option<Adjacency>, grid: &Grid| {
            let adjacency = Adjacency::cached(cache, grid, &moves);
            adjacency.mask(adjacency.index(Cell::new(1, 0)))
        };
        let mut cache = None;
        // Right, left and down are safe from (1, 0); up leaves the grid.
        assert_eq!(centre(&mut cache, &grid), 0b0111);
        // An edit in place gives a new revision, and the masks follow it.
        grid.set_free(Cell::new(2, 0), false);
        assert_eq!(centre(&mut cache, &grid), 0b0110);
        // A clone shares the revision; an equal grid built anew has its own but equal cells.
        let copy = grid.clone();
        assert_eq!(copy.revision(), grid.revision());
        let rebuilt = Grid::from_ascii("..#\n...").unwrap();
        assert_ne!(rebuilt.revision(), grid.revision());
        assert_eq!(rebuilt, grid);
        assert_eq!(centre(&mut cache, &copy), 0b0110);
        assert_eq!(centre(&mut cache, &rebuilt), 0b0110);
        grid.set_free(Cell::new(2, 0), true);
        assert_eq!(centre(&mut cache, &grid), 0b0111);
    }
}
