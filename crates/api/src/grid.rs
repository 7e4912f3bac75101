//! Cells and the occupancy grid.

use std::fmt;

use serde::{Deserialize, Deserializer, Serialize, Serializer};

use crate::cost::Cost;
use crate::error::GridError;
use crate::weights::{weighted_move_cost, CostRule, Weights};

/// A grid cell: `x` is the column, `y` the row, `(0, 0)` the top-left cell.
///
/// Serialized as the two-element array `[x, y]`, the form scripts expect.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Default)]
pub struct Cell {
    /// Column, counted from the left edge.
    pub x: u32,
    /// Row, counted from the top edge.
    pub y: u32,
}

impl Cell {
    /// The cell at column `x`, row `y`.
    pub const fn new(x: u32, y: u32) -> Cell {
        Cell { x, y }
    }

    /// Manhattan (L1) distance: the 4-connected step count on an open grid.
    pub fn manhattan(self, other: Cell) -> u64 {
        u64::from(self.x.abs_diff(other.x)) + u64::from(self.y.abs_diff(other.y))
    }

    /// Chebyshev (L-infinity) distance: the 8-connected step count on an open grid.
    pub fn chebyshev(self, other: Cell) -> u64 {
        u64::from(self.x.abs_diff(other.x).max(self.y.abs_diff(other.y)))
    }

    /// Octile distance: the 8-connected cost (1 per straight, sqrt 2 per diagonal move) on an open grid.
    pub fn octile(self, other: Cell) -> f64 {
        let dx = f64::from(self.x.abs_diff(other.x));
        let dy = f64::from(self.y.abs_diff(other.y));
        dx.max(dy) + (std::f64::consts::SQRT_2 - 1.0) * dx.min(dy)
    }

    /// Euclidean distance between the two cell centres: [`cell_hypot`] of the offsets,
    /// bit for bit what `f64::hypot` gives on glibc.
    #[inline]
    pub fn euclidean(self, other: Cell) -> f64 {
        cell_hypot(self.x.abs_diff(other.x), self.y.abs_diff(other.y))
    }

    /// The cell displaced by `(dx, dy)`, or `None` when a coordinate would be negative or overflow.
    ///
    /// The result is not checked against any grid; see [`Grid::offset`] for that.
    pub fn checked_offset(self, dx: i32, dy: i32) -> Option<Cell> {
        let x = self.x.checked_add_signed(dx)?;
        let y = self.y.checked_add_signed(dy)?;
        Some(Cell { x, y })
    }
}

impl fmt::Display for Cell {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "({}, {})", self.x, self.y)
    }
}

impl From<(u32, u32)> for Cell {
    fn from((x, y): (u32, u32)) -> Cell {
        Cell { x, y }
    }
}

impl Serialize for Cell {
    fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        [self.x, self.y].serialize(serializer)
    }
}

impl<'de> Deserialize<'de> for Cell {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Cell, D::Error> {
        let [x, y] = <[u32; 2]>::deserialize(deserializer)?;
        Ok(Cell { x, y })
    }
}

/// A rectangular occupancy grid in flat row-major storage.
///
/// Cell `(x, y)` lives at index `y * width + x`. Planners index the flat
/// slice from [`Grid::free_cells`] in their hot loops; the methods taking
/// [`Cell`] are for everything else.
///
/// A grid may carry a weight per cell ([`Grid::with_weights`], [`crate::weights`]); without
/// one every free cell has weight 1 and moves cost their length.
///
/// Equality and hashing compare the cells and weights. Every grid also carries a
/// [`revision`](Grid::revision), so that caches of derived data (move masks) can tell in
/// O(1) that a grid is the one they were built for, and a bounded log of the cells its
/// last edits changed ([`Grid::changed_since`]), so that such a cache can be brought up to
/// date instead of rebuilt.
pub struct Grid {
    width: u32,
    height: u32,
    free: Vec<bool>,
    weights: Option<Weights>,
    revision: u64,
    changes: ChangeLog,
}

/// The cells that [`Grid::set_free`] and [`Grid::set_weight`] changed, oldest first, each
/// with the revision the grid had before the edit (increasing, as revisions are drawn from
/// one counter). Any other new revision empties it; past [`ChangeLog::limit`] entries the
/// older half is dropped, so a cache older than what is kept rebuilds.
#[derive(Debug, Clone, Default)]
struct ChangeLog {
    entries: Vec<(u64, u32)>,
}

impl ChangeLog {
    /// The most entries kept for a grid of `len` cells: 1/256 of the cells, between 1024
    /// and 65,536 (at most a megabyte).
    fn limit(len: usize) -> usize {
        (len / 256).clamp(1024, 65_536)
    }
}

impl Clone for Grid {
    fn clone(&self) -> Grid {
        Grid {
            width: self.width,
            height: self.height,
            free: self.free.clone(),
            weights: self.weights.clone(),
            revision: self.revision,
            changes: self.changes.clone(),
        }
    }

    /// Into the memory of `self`'s cells (and weights): a cache that keeps a copy of the
    /// grid it was built for (the adjacency's) takes a changed grid without allocating.
    fn clone_from(&mut self, source: &Grid) {
        (self.width, self.height, self.revision) = (source.width, source.height, source.revision);
        self.free.clone_from(&source.free);
        self.weights.clone_from(&source.weights);
        self.changes.entries.clone_from(&source.changes.entries);
    }
}

impl PartialEq for Grid {
    fn eq(&self, other: &Grid) -> bool {
        (self.width, self.height) == (other.width, other.height)
            && self.free == other.free
            && self.weights == other.weights
    }
}

impl Eq for Grid {}

impl std::hash::Hash for Grid {
    fn hash<H: std::hash::Hasher>(&self, state: &mut H) {
        (self.width, self.height, &self.free, &self.weights).hash(state);
    }
}

/// A new process-wide unique grid revision.
fn next_revision() -> u64 {
    static NEXT: std::sync::atomic::AtomicU64 = std::sync::atomic::AtomicU64::new(1);
    NEXT.fetch_add(1, std::sync::atomic::Ordering::Relaxed)
}

impl Grid {
    /// The largest number of cells a grid may have (2^31), so that every index fits in a `u32`.
    pub const MAX_CELLS: u64 = 1 << 31;

    /// An all-free grid of `width` columns and `height` rows.
    ///
    /// Errors when a side is zero or the grid has more than [`Grid::MAX_CELLS`] cells.
    pub fn new(width: u32, height: u32) -> Result<Grid, GridError> {
        let len = Self::checked_len(width, height)?;
        Ok(Grid {
            width,
            height,
            free: vec![true; len],
            weights: None,
            revision: next_revision(),
            changes: ChangeLog::default(),
        })
    }

    /// A grid from its row-major free flags (`true` = traversable).
    ///
    /// Errors when `free.len() != width * height`, or as [`Grid::new`].
    pub fn from_free_cells(width: u32, height: u32, free: Vec<bool>) -> Result<Grid, GridError> {
        let len = Self::checked_len(width, height)?;
        if free.len() != len {
            return Err(GridError::CellCount {
                expected: len,
                found: free.len(),
            });
        }
        Ok(Grid {
            width,
            height,
            free,
            weights: None,
            revision: next_revision(),
            changes: ChangeLog::default(),
        })
    }

    /// This grid with a weight per cell (row-major, as [`Grid::free_cells`]) and the move
    /// cost rule (see [`crate::weights`]).
    ///
    /// Errors when the number of weights is not the number of cells, or a weight is 0.
    pub fn with_weights(mut self, weights: Vec<u16>, rule: CostRule) -> Result<Grid, GridError> {
        if weights.len() != self.free.len() {
            return Err(GridError::CellCount {
                expected: self.free.len(),
                found: weights.len(),
            });
        }
        if let Some(index) = weights.iter().position(|&w| w == 0) {
            return Err(GridError::ZeroWeight { index });
        }
        self.weights = Some(Weights::new(weights, rule));
        self.renew();
        Ok(self)
    }

    /// This grid with its weights' move cost rule replaced by `rule` (unchanged when
    /// unweighted).
    pub fn with_rule(mut self, rule: CostRule) -> Grid {
        if let Some(weights) = &mut self.weights {
            weights.set_rule(rule);
            self.renew();
        }
        self
    }

    /// The same cells without weights.
    pub fn without_weights(&self) -> Grid {
        Grid {
            width: self.width,
            height: self.height,
            free: self.free.clone(),
            weights: None,
            revision: next_revision(),
            changes: ChangeLog::default(),
        }
    }

    /// The weight layer, when the grid has one.
    pub fn weights(&self) -> Option<&Weights> {
        self.weights.as_ref()
    }

    /// Whether the grid carries weights.
    pub fn is_weighted(&self) -> bool {
        self.weights.is_some()
    }

    /// The weight of `cell` (1 on an unweighted grid). Precondition: `self.contains(cell)`.
    pub fn weight(&self, cell: Cell) -> u16 {
        self.weights
            .as_ref()
            .map_or(1, |w| w.cells()[self.index(cell)])
    }

    /// The cost of the move from `from` to `to` (their offsets give its length, as
    /// [`Cost::of_move`]) under the grid's weights and rule; the length itself on an
    /// unweighted grid. Whether the move is allowed is not checked. Precondition: both cells
    /// are inside the grid.
    pub fn move_cost(&self, from: Cell, to: Cell) -> Cost {
        let dx = i64::from(to.x) - i64::from(from.x);
        let dy = i64::from(to.y) - i64::from(from.y);
        let length = Cost::euclidean(dx.unsigned_abs() as u32, dy.unsigned_abs() as u32);
        match &self.weights {
            None => length,
            Some(w) => weighted_move_cost(
                length,
                w.cells()[self.index(from)],
                w.cells()[self.index(to)],
                w.rule(),
            ),
        }
    }

    /// The cost of the path through `cells` (the sum of [`Grid::move_cost`] of its steps;
    /// its Euclidean length in [`Cost`] units on an unweighted grid). Precondition: every
    /// cell is inside the grid.
    pub fn path_cost(&self, cells: &[Cell]) -> Cost {
        cells.windows(2).fold(Cost::ZERO, |sum, pair| {
            sum + self.move_cost(pair[0], pair[1])
        })
    }

    /// The cost of the path through `cells` as an `f64` sum of its moves' costs: the same
    /// value as [`Grid::path_cost`] (to within `f64` rounding) while that stays below
    /// [`Cost::MAX`], and the true cost beyond it, where [`Grid::path_cost`] saturates
    /// (each move's cost is exact; only weights make a path cost so much). Precondition:
    /// every cell is inside the grid.
    pub fn path_cost_f64(&self, cells: &[Cell]) -> f64 {
        cells
            .windows(2)
            .map(|pair| self.move_cost(pair[0], pair[1]).to_f64())
            .sum()
    }

    /// A grid drawn in ASCII, for tests and examples: one line per row, `.` free, `#` blocked.
    ///
    /// Leading and trailing blank lines and the indentation of each row are ignored, so the
    /// map can be written in an indented raw string. Every row must have the same width.
    ///
    /// ```
    /// use planner_api::{Cell, Grid};
    /// let grid = Grid::from_ascii("
    ///     ..#
    ///     ...
    /// ").unwrap();
    /// assert_eq!((grid.width(), grid.height()), (3, 2));
    /// assert!(!grid.is_free(Cell::new(2, 0)));
    /// ```
    pub fn from_ascii(text: &str) -> Result<Grid, GridError> {
        let rows: Vec<&str> = text
            .lines()
            .map(str::trim)
            .skip_while(|row| row.is_empty())
            .collect();
        let rows: Vec<&str> = match rows.iter().rposition(|row| !row.is_empty()) {
            Some(last) => rows[..=last].to_vec(),
            None => return Err(GridError::Empty),
        };
        let width = rows[0].chars().count();
        let mut free = Vec::with_capacity(width * rows.len());
        for (row_index, row) in rows.iter().enumerate() {
            let row_width = row.chars().count();
            if row_width != width {
                return Err(GridError::RaggedRow {
                    row: row_index,
                    expected: width,
                    found: row_width,
                });
            }
            for (column, ch) in row.chars().enumerate() {
                match ch {
                    '.' => free.push(true),
                    '#' => free.push(false),
                    other => {
                        return Err(GridError::UnknownCell {
                            row: row_index,
                            column,
                            found: other,
                        })
                    }
                }
            }
        }
        let width = u32::try_from(width).map_err(|_| GridError::TooLarge)?;
        let height = u32::try_from(rows.len()).map_err(|_| GridError::TooLarge)?;
        Grid::from_free_cells(width, height, free)
    }

    fn checked_len(width: u32, height: u32) -> Result<usize, GridError> {
        if width == 0 || height == 0 {
            return Err(GridError::Empty);
        }
        let len = u64::from(width) * u64::from(height);
        if len > Self::MAX_CELLS {
            return Err(GridError::TooLarge);
        }
        usize::try_from(len).map_err(|_| GridError::TooLarge)
    }

    /// Number of columns.
    pub fn width(&self) -> u32 {
        self.width
    }

    /// Number of rows.
    pub fn height(&self) -> u32 {
        self.height
    }

    /// Number of cells, `width * height`.
    pub fn len(&self) -> usize {
        self.free.len()
    }

    /// Always false: a grid has at least one cell. Present for API symmetry with `len`.
    pub fn is_empty(&self) -> bool {
        self.free.is_empty()
    }

    /// Number of free cells.
    pub fn n_free(&self) -> usize {
        self.free.iter().filter(|&&free| free).count()
    }

    /// The row-major free flags; index with [`Grid::index`].
    pub fn free_cells(&self) -> &[bool] {
        &self.free
    }

    /// Whether `cell` lies inside the grid.
    pub fn contains(&self, cell: Cell) -> bool {
        cell.x < self.width && cell.y < self.height
    }

    /// Whether the signed coordinates lie inside the grid.
    pub fn contains_signed(&self, x: i64, y: i64) -> bool {
        x >= 0 && y >= 0 && x < i64::from(self.width) && y < i64::from(self.height)
    }

    /// Whether `cell` is inside the grid and traversable: seed 000's `Safe(x, y)`.
    pub fn is_free(&self, cell: Cell) -> bool {
        self.contains(cell) && self.free[self.index(cell)]
    }

    /// Flat index of `cell`. Precondition: `self.contains(cell)`.
    pub fn index(&self, cell: Cell) -> usize {
        cell.y as usize * self.width as usize + cell.x as usize
    }

    /// The cell at flat index `index`. Precondition: `index < self.len()`.
    pub fn cell(&self, index: usize) -> Cell {
        let width = self.width as usize;
        // Both quotient and remainder are below u32::MAX because len <= MAX_CELLS.
        Cell {
            x: (index % width) as u32,
            y: (index / width) as u32,
        }
    }

    /// The cell displaced from `cell` by `(dx, dy)`, or `None` when it leaves the grid.
    pub fn offset(&self, cell: Cell, dx: i32, dy: i32) -> Option<Cell> {
        cell.checked_offset(dx, dy).filter(|&c| self.contains(c))
    }

    /// Marks `cell` blocked (`free = false`) or free (its weight, if any, is kept).
    /// Precondition: `self.contains(cell)`.
    pub fn set_free(&mut self, cell: Cell, free: bool) {
        let index = self.index(cell);
        self.free[index] = free;
        self.record(index);
    }

    /// Sets the weight of `cell` to `weight` (a costmap's update); the extremes
    /// ([`Weights::min`], [`Weights::max`]) follow, in constant time unless the cell was the
    /// last holding one of them and leaves it (then the weights are rescanned). Nothing
    /// happens on an unweighted grid or for a weight of 0 (both `false`). Precondition:
    /// `self.contains(cell)`.
    ///
    /// ```
    /// use planner_api::{Cell, CostRule, Grid};
    /// let mut grid = Grid::from_ascii("...").unwrap();
    /// assert!(!grid.set_weight(Cell::new(0, 0), 4)); // unweighted
    /// let mut grid = grid.with_weights(vec![1, 3, 5], CostRule::Mean).unwrap();
    /// assert!(grid.set_weight(Cell::new(0, 0), 4));
    /// let w = grid.weights().unwrap();
    /// assert_eq!((w.min(), w.max()), (3, 5));
    /// assert!(grid.set_weight(Cell::new(2, 0), 2));
    /// let w = grid.weights().unwrap();
    /// assert_eq!((w.min(), w.max()), (2, 4));
    /// assert!(!grid.set_weight(Cell::new(1, 0), 0));
    /// ```
    pub fn set_weight(&mut self, cell: Cell, weight: u16) -> bool {
        let index = self.index(cell);
        match &mut self.weights {
            Some(weights) if weight > 0 => {
                weights.set(index, weight);
                self.record(index);
                true
            }
            _ => false,
        }
    }

    /// A number that identifies the grid's current cells within this process: it is new
    /// for every grid built and after every [`Grid::set_free`] and [`Grid::set_weight`],
    /// and a clone shares its original's. Equal revisions therefore mean equal grids (the
    /// converse need not hold). Caches of data derived from a grid key on it.
    pub fn revision(&self) -> u64 {
        self.revision
    }

    /// The cells that [`Grid::set_free`] and [`Grid::set_weight`] changed since the grid
    /// had revision `revision`, in the order of the edits (a cell edited twice comes twice;
    /// none when `revision` is the current one), or `None` when that is not known: the
    /// revision is not one this grid passed through by those edits alone, or more edits
    /// followed it than the grid keeps (1/256 of its cells, at least 1024 and at most
    /// 65,536). A cache of data derived from the grid at `revision` updates the data
    /// around these cells, or rebuilds it on `None`.
    ///
    /// ```
    /// use planner_api::{Cell, Grid};
    /// let mut grid = Grid::from_ascii("...").unwrap();
    /// let before = grid.revision();
    /// grid.set_free(Cell::new(1, 0), false);
    /// grid.set_free(Cell::new(2, 0), false);
    /// let changed: Vec<Cell> = grid.changed_since(before).unwrap().collect();
    /// assert_eq!(changed, [Cell::new(1, 0), Cell::new(2, 0)]);
    /// assert_eq!(grid.changed_since(grid.revision()).unwrap().count(), 0);
    /// // Not a revision of this grid's edits.
    /// assert!(grid.changed_since(before + 1_000_000).is_none());
    /// ```
    pub fn changed_since(&self, revision: u64) -> Option<impl Iterator<Item = Cell> + '_> {
        let entries = &self.changes.entries;
        let first = if revision == self.revision {
            entries.len()
        } else {
            let at = entries.partition_point(|&(before, _)| before < revision);
            entries.get(at).filter(|&&(before, _)| before == revision)?;
            at
        };
        Some(
            entries[first..]
                .iter()
                .map(|&(_, index)| self.cell(index as usize)),
        )
    }

    /// A new revision after an edit of the cell at `index`, logged
    /// ([`Grid::changed_since`]).
    fn record(&mut self, index: usize) {
        let log = &mut self.changes.entries;
        if log.len() >= ChangeLog::limit(self.free.len()) {
            log.drain(..log.len() / 2);
        }
        // Indices fit in 32 bits (`Grid::MAX_CELLS`).
        log.push((self.revision, index as u32));
        self.revision = next_revision();
    }

    /// A new revision after a change the log does not describe: it is emptied.
    fn renew(&mut self) {
        self.changes.entries.clear();
        self.revision = next_revision();
    }

    /// Iterates over every cell in row-major order.
    pub fn cells(&self) -> impl Iterator<Item = Cell> + '_ {
        (0..self.len()).map(|index| self.cell(index))
    }

    /// The grid drawn with `.` for free and `#` for blocked cells, one line per row.
    pub fn to_ascii(&self) -> String {
        let mut out = String::with_capacity(self.len() + self.height as usize);
        for row in self.free.chunks(self.width as usize) {
            out.extend(row.iter().map(|&free| if free { '.' } else { '#' }));
            out.push('\n');
        }
        out
    }
}

impl fmt::Debug for Grid {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        writeln!(f, "Grid {}x{}", self.width, self.height)?;
        f.write_str(&self.to_ascii())
    }
}

/// `flags` (a row of [`Grid::free_cells`], say) packed 64 to a word: bit `i` of word `c`
/// is flag `64 c + i`, and the last word's bits past the end are 0. The packed copies of a
/// grid (the adjacency's rows, A*'s and Theta*'s bit grids, Jump Point Search's rows) are
/// built from these words, a store per 64 cells rather than a read-modify-write per cell.
pub fn packed_words(flags: &[bool]) -> impl Iterator<Item = u64> + '_ {
    flags.chunks(64).map(|chunk| {
        (0..)
            .zip(chunk)
            .fold(0u64, |word, (i, &flag)| word | u64::from(flag) << i)
    })
}

/// `hypot(dx, dy)` of two cell offsets as glibc computes it: the generic
/// `sysdeps/ieee754/dbl-64/e_hypot.c` without FMA (read off the disassembly of Debian 12's
/// glibc 2.36 for x86-64), Borges's algorithm ("An improved algorithm for hypot(a, b)",
/// Numerical Algorithms 2020): the correctly rounded square root of the sum of squares
/// (exact below 2^26) followed by one correction step, which leaves the result within one
/// unit in the last place and not always the nearest one. Written out with the same
/// operations in the same order (Rust contracts nothing into FMA); for cell offsets glibc
/// takes that kernel whenever `dy >= 1` (no offset is tiny or huge) and returns `dx` itself
/// for `dy = 0`. So the value equals `f64::hypot`'s on that glibc bit for bit (tested where
/// the target is glibc, over every offset below 4096 and a million random ones up to
/// 2^32), is the same on every platform whatever its libm, and is inlined: Theta* spent a
/// fifth of its time in the library call. The correction's division is left out where it
/// cannot change the result (almost always; tested against the kernel that always divides).
#[inline]
pub fn cell_hypot(dx: u32, dy: u32) -> f64 {
    hypot_kernel::<true>(dx, dy)
}

/// Glibc's kernel (see [`cell_hypot`]); with `SKIP_DIVISION` false, the division of the
/// correction step always done, as glibc does (the tests' reference).
#[inline(always)]
fn hypot_kernel<const SKIP_DIVISION: bool>(dx: u32, dy: u32) -> f64 {
    let (ax, ay) = (f64::from(dx.max(dy)), f64::from(dx.min(dy)));
    if ay == 0.0 {
        return ax;
    }
    let h = (ax * ax + ay * ay).sqrt();
    let (t1, t2) = if h <= 2.0 * ay {
        let delta = h - ay;
        (ax * (2.0 * delta - ax), (delta - 2.0 * (ax - ay)) * delta)
    } else {
        let delta = h - ax;
        (
            2.0 * delta * (ax - 2.0 * ay),
            (4.0 * delta - ay) * ay + delta * delta,
        )
    };
    let t = t1 + t2;
    if !SKIP_DIVISION {
        return h - t / (2.0 * h);
    }
    // `h - t / (2 h)` rounds back to `h` when the correction is below half the gap from `h`
    // to its neighbour on that side: then the division (long, on the searches' critical
    // path) is left out, with the same result. The gap is h's unit in the last place
    // (`h >= sqrt 2`, normal), halved below a power of two; the margin of 1e-9 is far
    // wider than the product's rounding. Near the halfway points the division decides.
    let bits = h.to_bits();
    let ulp = f64::from_bits(bits & EXPONENT_BITS) * f64::EPSILON;
    let gap = if t > 0.0 && bits & !EXPONENT_BITS == 0 {
        0.5 * ulp
    } else {
        ulp
    };
    if t.abs() < gap * h * (1.0 - 1e-9) {
        return h;
    }
    h - t / (2.0 * h)
}

/// The exponent field of an `f64` (its sign bit clear): with the mantissa cleared, a
/// normal number becomes the power of two at or below it.
const EXPONENT_BITS: u64 = 0x7ff0_0000_0000_0000;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_change_log_answers_for_its_own_edits_only() {
        let mut grid = Grid::new(40, 40)
            .unwrap()
            .with_weights(vec![3; 1600], CostRule::Mean)
            .unwrap();
        let built = grid.revision();
        grid.set_weight(Cell::new(5, 6), 9);
        let middle = grid.revision();
        grid.set_free(Cell::new(7, 8), false);
        // A weight of 0 is refused: no edit, no new revision, nothing logged.
        assert!(!grid.set_weight(Cell::new(1, 1), 0));
        let cells = |grid: &Grid, r| grid.changed_since(r).map(|c| c.collect::<Vec<_>>());
        assert_eq!(
            cells(&grid, built),
            Some(vec![Cell::new(5, 6), Cell::new(7, 8)])
        );
        assert_eq!(cells(&grid, middle), Some(vec![Cell::new(7, 8)]));
        // A clone shares the log; its own edits go on from there, apart from the original's.
        let mut copy = grid.clone();
        copy.set_free(Cell::new(0, 0), false);
        assert_eq!(
            cells(&copy, middle),
            Some(vec![Cell::new(7, 8), Cell::new(0, 0)])
        );
        assert_eq!(cells(&grid, middle), Some(vec![Cell::new(7, 8)]));
        let mut target = Grid::new(2, 2).unwrap();
        target.clone_from(&copy);
        assert_eq!(cells(&target, built).map(|c| c.len()), Some(3));
        // A change the log does not describe empties it.
        let now = grid.revision();
        let grid = grid.with_rule(CostRule::Entered);
        assert_eq!(cells(&grid, built), None);
        assert_eq!(cells(&grid, now), None);
        assert_eq!(cells(&grid, grid.revision()), Some(vec![]));
        // Past the limit (1024 for 1600 cells) the older half goes.
        let mut grid = Grid::new(40, 40).unwrap();
        let first = grid.revision();
        let mut revisions = vec![first];
        for i in 0..1030u32 {
            grid.set_free(Cell::new(i % 40, i / 40), i % 2 == 0);
            revisions.push(grid.revision());
        }
        assert_eq!(cells(&grid, first), None);
        assert_eq!(cells(&grid, revisions[511]), None);
        assert_eq!(
            cells(&grid, revisions[512]).map(|c| c.len()),
            Some(1030 - 512)
        );
        assert_eq!(
            cells(&grid, revisions[1029]),
            Some(vec![Cell::new(1029 % 40, 1029 / 40)])
        );
    }

    #[test]
    fn packed_words_by_hand() {
        let flags: Vec<bool> = (0..130).map(|i| i % 3 == 0 || i == 64).collect();
        let words: Vec<u64> = packed_words(&flags).collect();
        assert_eq!(words.len(), 3);
        for (i, &flag) in flags.iter().enumerate() {
            assert_eq!(words[i / 64] >> (i % 64) & 1 == 1, flag, "flag {i}");
        }
        // The last word holds flags 128 (128 = 3 * 42 + 2: clear) and 129 (3 * 43: set),
        // and nothing past them.
        assert_eq!(words[2], 0b10);
        assert_eq!(packed_words(&[]).count(), 0);
    }

    /// A million pseudo-random offsets up to 2^32 (a xorshift sequence from `seed`), the
    /// second of each pair shifted right by a random amount so that all ratios occur.
    fn random_offsets(seed: u64) -> impl Iterator<Item = (u32, u32)> {
        let mut next = crate::test_rng::xorshift(seed);
        (0..1_000_000).map(move |_| (next() as u32, next() as u32 >> (next() % 32)))
    }

    /// `cell_hypot` equals glibc's `hypot` bit for bit: every offset below 4096 and a
    /// million pseudo-random ones up to 2^32 (a xorshift sequence, seeded). Only where the
    /// library is glibc: elsewhere `f64::hypot` is another algorithm.
    #[test]
    #[cfg(all(target_os = "linux", target_env = "gnu"))]
    fn cell_hypot_is_glibcs_hypot() {
        let (mut differ, mut not_nearest) = (0u64, 0u64);
        for dx in 0..4096u32 {
            for dy in 0..4096u32 {
                let expected = f64::from(dx).hypot(f64::from(dy));
                let got = cell_hypot(dx, dy);
                differ += u64::from(got.to_bits() != expected.to_bits());
                let nearest = (f64::from(dx * dx) + f64::from(dy * dy)).sqrt();
                not_nearest += u64::from(got.to_bits() != nearest.to_bits());
            }
        }
        for (dx, dy) in random_offsets(0x9e37_79b9_7f4a_7c15) {
            let expected = f64::from(dx).hypot(f64::from(dy));
            differ += u64::from(cell_hypot(dx, dy).to_bits() != expected.to_bits());
        }
        assert_eq!(differ, 0);
        // Not the correctly rounded root everywhere (the square root of the exact sum),
        // which is why the kernel is copied rather than replaced by `sqrt`.
        assert!(not_nearest > 0);
    }

    /// On every platform: `cell_hypot` equals the kernel that always divides, bit for
    /// bit, on every offset below 4096, a million pseudo-random ones up to 2^32, and the
    /// offsets whose root is next to a power of two.
    #[test]
    fn cell_hypot_divides_only_where_it_matters() {
        let mut differ = 0u64;
        let mut check = |dx: u32, dy: u32| {
            differ +=
                u64::from(cell_hypot(dx, dy).to_bits() != hypot_kernel::<false>(dx, dy).to_bits());
        };
        for dx in 0..4096u32 {
            for dy in 0..4096u32 {
                check(dx, dy);
            }
        }
        for (dx, dy) in random_offsets(0x2545_f491_4f6c_dd1d) {
            check(dx, dy);
        }
        // Roots just above and below 2^k: (2^k, small dy) and (2^k - 1, dy).
        for k in 1..32u32 {
            for dy in 1..2048u32 {
                check(1 << k, dy);
                check((1 << k) - 1, dy);
            }
        }
        assert_eq!(differ, 0);
    }

    #[test]
    fn ascii_round_trip() {
        let text = "..#\n#..\n";
        let grid = Grid::from_ascii(text).unwrap();
        assert_eq!(grid.to_ascii(), text);
        assert_eq!(grid.n_free(), 4);
        assert_eq!(grid.cell(grid.index(Cell::new(2, 1))), Cell::new(2, 1));
    }

    #[test]
    fn ascii_errors() {
        assert_eq!(Grid::from_ascii("\n  \n"), Err(GridError::Empty));
        assert_eq!(
            Grid::from_ascii("..\n...").unwrap_err(),
            GridError::RaggedRow {
                row: 1,
                expected: 2,
                found: 3
            }
        );
        assert_eq!(
            Grid::from_ascii("..\n.x").unwrap_err(),
            GridError::UnknownCell {
                row: 1,
                column: 1,
                found: 'x'
            }
        );
    }

    #[test]
    fn bounds() {
        let grid = Grid::new(3, 2).unwrap();
        assert!(grid.contains(Cell::new(2, 1)));
        assert!(!grid.contains(Cell::new(3, 1)));
        assert_eq!(grid.offset(Cell::new(0, 0), -1, 0), None);
        assert_eq!(grid.offset(Cell::new(0, 0), 2, 1), Some(Cell::new(2, 1)));
        assert_eq!(Grid::new(0, 3), Err(GridError::Empty));
        assert_eq!(Grid::new(1 << 16, 1 << 16), Err(GridError::TooLarge));
    }

    #[test]
    fn distances() {
        let a = Cell::new(1, 1);
        let b = Cell::new(4, 5);
        assert_eq!(a.manhattan(b), 7);
        assert_eq!(a.chebyshev(b), 4);
        assert_eq!(a.euclidean(b), 5.0);
        assert!((a.octile(b) - (4.0 + 3.0 * (2f64.sqrt() - 1.0))).abs() < 1e-12);
    }

    #[test]
    fn cell_serializes_as_pair() {
        assert_eq!(serde_json::to_string(&Cell::new(3, 4)).unwrap(), "[3,4]");
        let cell: Cell = serde_json::from_str("[5,6]").unwrap();
        assert_eq!(cell, Cell::new(5, 6));
    }
}
