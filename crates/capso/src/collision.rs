//! The collision cost of a path segment, exact against the grid.
//!
//! A segment joins two cell centres. The cells it touches are those that
//! [`planner_api::for_each_segment_cell`] visits: every cell whose closed square meets the
//! segment, including the two side cells where it passes exactly through a grid vertex
//! (the rule [`planner_api::PathRule::AnyAngle`] checks). For the blocked ones among them
//! the cost counts the cells and the length of the segment inside each cell's square
//! (Liang-Barsky clipping), so a segment that only grazes a blocked corner still costs one
//! cell although its length inside is 0. A segment costs nothing exactly when
//! [`planner_api::segment_is_free`] holds for it.
//!
//! [`BitGrid`] is the planner's copy of the grid, one bit per cell, and
//! [`BitGrid::segment_collision`] the same measure as [`segment_collision`] (tested equal)
//! computed a row (or column) at a time with word masks: a fitness evaluation walks every
//! segment of its path, so this is a large part of CAPSO's time.

use planner_api::{for_each_segment_cell, BlockedBits, Cell, Grid};

/// What a segment or a path crosses of the blocked cells.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Collision {
    /// Blocked cells touched (per segment; a waypoint cell shared by two segments counts
    /// in both).
    pub cells: u64,
    /// Length inside blocked cells, in cell widths.
    pub length: f64,
}

impl Collision {
    /// Whether nothing blocked is touched.
    pub fn is_free(&self) -> bool {
        self.cells == 0
    }

    /// The penalty measure: one per blocked cell touched plus the length inside them.
    pub fn cost(&self) -> f64 {
        self.cells as f64 + self.length
    }

    /// Adds `other`'s cells and length.
    pub fn add(&mut self, other: Collision) {
        self.cells += other.cells;
        self.length += other.length;
    }
}

/// The blocked cells the segment between the centres of `a` and `b` touches and its length
/// inside them. Cells outside the grid count as blocked (as in `segment_is_free`); they
/// cannot occur when `a` and `b` are in the grid.
pub fn segment_collision(grid: &Grid, a: Cell, b: Cell) -> Collision {
    let mut collision = Collision::default();
    let mut fraction = 0.0;
    for_each_segment_cell(a, b, |cell| {
        if !grid.is_free(cell) {
            collision.cells += 1;
            fraction += clipped_fraction(a, b, cell);
        }
        true
    });
    if fraction > 0.0 {
        collision.length = fraction * a.euclidean(b);
    }
    collision
}

/// The planner's copy of the grid: planner-api's [`BlockedBits`] (the blocked cells packed
/// row by row and column by column, and their summed-area table), kept between searches
/// and rebuilt only when the grid's [`revision`](Grid::revision) changes, with the
/// segment walk below.
#[derive(Debug, Clone, Default)]
pub struct BitGrid {
    bits: BlockedBits,
}

/// Lines per chunk whose bounding box [`BitGrid::segment_collision`] tests at once.
pub const CHUNK_LINES: u32 = 8;

impl BitGrid {
    /// An empty bit grid; [`BitGrid::load`] fills it.
    pub fn new() -> BitGrid {
        BitGrid::default()
    }

    /// The bytes [`BitGrid::load`] allocates for `grid` ([`BlockedBits::bytes_for`]).
    pub fn bytes_for(grid: &Grid) -> u64 {
        BlockedBits::bytes_for(grid)
    }

    /// Makes this the packed copy of `grid` (nothing to do when it already is).
    pub fn load(&mut self, grid: &Grid) {
        self.bits.load(grid);
    }

    /// The blocked cells in the rectangle `x0 ..= x1` by `y0 ..= y1`, from the summed-area
    /// table. Precondition: `x0 <= x1 < W` and `y0 <= y1 < H`.
    #[inline]
    pub fn blocked_in(&self, x0: u32, x1: u32, y0: u32, y1: u32) -> u32 {
        self.bits.blocked_in(x0, x1, y0, y1)
    }

    /// Width in cells.
    pub fn width(&self) -> u32 {
        self.bits.width()
    }

    /// Height in cells.
    pub fn height(&self) -> u32 {
        self.bits.height()
    }

    /// Whether the cell `(x, y)` is blocked. Precondition: it lies in the grid.
    #[inline]
    pub fn is_blocked(&self, x: u32, y: u32) -> bool {
        self.bits.is_blocked(x, y)
    }

    /// [`segment_collision`] on the packed grid: the blocked cells that the segment
    /// between the centres of `a` and `b` touches (the cells of
    /// [`for_each_segment_cell`]) and its length inside them. Precondition: `a` and `b`
    /// lie in the grid, so every touched cell does (they lie in the two cells' bounding
    /// box).
    ///
    /// The segment is cut along its major axis `M` (the longer extent `n_M`; x on a tie)
    /// into the lines of its minor axis `m` (`n_m + 1` rows or columns). On line `j` it
    /// spans the major parameter `[n_M (2 j - 1), n_M (2 j + 1)] / (2 n_m)` (clipped to
    /// `[0, n_M]`), so the closed squares it meets there are the major offsets from
    /// `ceil((n_M (2 j - 1) - n_m) / (2 n_m))` to `floor((n_M (2 j + 1) + n_m) / (2 n_m))`,
    /// kept exactly by an integer quotient and remainder stepped once per line. Each such
    /// range is tested with one word mask on the packed line (more when it spans words;
    /// [`BitGrid`] keeps the columns packed too, for segments whose major axis is y), and
    /// only where it holds blocked cells are they counted, a run of consecutive blocked
    /// cells at a time: the segment's length inside a run is clipped once against the
    /// run's rectangle (the cells' pieces are consecutive intervals of the segment, so
    /// their sum is the rectangle's piece). The cells are those of the cell-by-cell walk
    /// and the length equals its sum to rounding (tested). Free stretches are skipped by
    /// the summed-area table: first the segment's bounding box, then a box around each
    /// chunk of [`CHUNK_LINES`] lines; a box without a blocked cell skips its lines (the
    /// quotient and remainder jump over the chunk at once, stepped by a third `divmod`).
    pub fn segment_collision(&self, a: Cell, b: Cell) -> Collision {
        self.segment_collision_of_length(a, b, || distance(a, b))
    }

    /// [`BitGrid::segment_collision`] with the segment's length, [`distance`]`(a, b)`,
    /// from `length` (called only when the segment has a length inside blocked cells).
    #[inline]
    pub fn segment_collision_of_length(
        &self,
        a: Cell,
        b: Cell,
        length: impl FnOnce() -> f64,
    ) -> Collision {
        // The segment's bounding box first: many segments have no blocked cell near.
        if self.blocked_in(a.x.min(b.x), a.x.max(b.x), a.y.min(b.y), a.y.max(b.y)) == 0 {
            return Collision::default();
        }
        let (nx, ny) = (a.x.abs_diff(b.x), a.y.abs_diff(b.y));
        let x_major = nx >= ny;
        // The touched cells and the length inside them do not depend on the direction,
        // so the segment is taken from the end with the smaller major coordinate.
        let (a, b) = if (x_major && b.x < a.x) || (!x_major && b.y < a.y) {
            (b, a)
        } else {
            (a, b)
        };
        let (n_major, n_minor, a_major, a_minor, minor_forward) = if x_major {
            (nx, ny, a.x, a.y, b.y >= a.y)
        } else {
            (ny, nx, a.y, a.x, b.x >= a.x)
        };
        let (lines, words_per_line) = if x_major {
            self.bits.rows()
        } else {
            self.bits.columns()
        };
        let mut hits = Hits {
            a_major,
            a_minor,
            n_major,
            n_minor,
            collision: Collision::default(),
            fraction: 0.0,
        };
        let d = 2 * n_minor;
        // (q, r) = divmod(n_M (2 j + 1), 2 n_m) for the current line j, q offset by a's
        // major coordinate, stepped by divmod(2 n_M, 2 n_m) (derived from the first
        // quotient: one division).
        let (mut q, mut r) = match (n_major.checked_div(d), n_major.checked_rem(d)) {
            (Some(q), Some(r)) => (q, r),
            _ => (0, 0),
        };
        let (step_q, step_r) = if d > 0 && 2 * r >= d {
            (2 * q + 1, 2 * r - d)
        } else {
            (2 * q, 2 * r)
        };
        q += a_major;
        let mut line = a_minor;
        let mut start = line as usize * words_per_line;
        let mut first = a_major;
        // Tests the cells first ..= last of the line that starts at word `start`.
        let test = |start: usize, line: u32, first: u32, last: u32, hits: &mut Hits| {
            let (w0, w1) = (first / 64, last / 64);
            // The run's bits when it lies in one word (else the slow path reads them).
            let word =
                lines[start + w0 as usize] & (!0u64 << (first % 64)) & (!0u64 >> (63 - last % 64));
            if (w0 != w1) | (word != 0) {
                hits.run(&lines[start..start + words_per_line], line, first, last);
            }
        };
        let end = a_major + n_major;
        // The rectangle major0 ..= major1 by the minor lines m0 ..= m1 (in either order),
        // as x and y ranges for the summed-area table.
        let blocked_in = |major0: u32, major1: u32, m0: u32, m1: u32| {
            let (m0, m1) = (m0.min(m1), m0.max(m1));
            if x_major {
                self.blocked_in(major0, major1, m0, m1)
            } else {
                self.blocked_in(m0, m1, major0, major1)
            }
        };
        let n_lines = n_minor + 1;
        // The step of (q, r) over CHUNK_LINES - 1 lines, for skipping a free chunk (only
        // used when there is more than one chunk, so n_minor > 0 and d > 0).
        let skip = || {
            let (q7, r7) = (
                u64::from(CHUNK_LINES - 1) * u64::from(step_q),
                u64::from(CHUNK_LINES - 1) * u64::from(step_r),
            );
            let d = u64::from(d.max(1));
            // Both fit: they are at most the line offsets' span, n_M + 1.
            ((q7 + r7 / d) as u32, (r7 % d) as u32)
        };
        let (line_step, word_step) = if minor_forward {
            (1isize, words_per_line as isize)
        } else {
            (-1, -(words_per_line as isize))
        };
        // Adds the step (dq, dr) to the quotient and remainder (q, r) of a division by d
        // (r, dr < d).
        let advance = |q: &mut u32, r: &mut u32, dq: u32, dr: u32| {
            *q += dq;
            *r += dr;
            if *r >= d {
                *r -= d;
                *q += 1;
            }
        };
        let mut j = 0;
        while j < n_lines {
            let k = CHUNK_LINES.min(n_lines - j);
            let last_chunk = j + k == n_lines;
            // A box around the chunk's cells: line j' >= j ends at most at
            // q_j' + 1 <= q_j + (j' - j) (step_q + 1) + 1, and the last line at the end.
            let high = if last_chunk {
                end
            } else {
                (q + (k - 1) * (step_q + 1) + 1).min(end)
            };
            let far = if minor_forward {
                line + (k - 1)
            } else {
                line - (k - 1)
            };
            if blocked_in(first, high, line, far) == 0 {
                if last_chunk {
                    break;
                }
                // A free full chunk: (q, r) jumps to its last line, whose range gives the
                // next chunk's first cell, and steps once more, as the line walk would.
                let (skip_q, skip_r) = skip();
                advance(&mut q, &mut r, skip_q, skip_r);
                first = q + u32::from(r > n_minor);
                advance(&mut q, &mut r, step_q, step_r);
                // In the grid: the chunk's next line is a line of the segment.
                line = line.wrapping_add_signed(k as i32 * line_step as i32);
                start = start.wrapping_add_signed(k as isize * word_step);
                j += k;
                continue;
            }
            // The chunk's lines but the segment's last, which ends at the segment's end.
            for _ in 0..k - u32::from(last_chunk) {
                test(
                    start,
                    line,
                    first,
                    q + u32::from(r + n_minor >= d),
                    &mut hits,
                );
                first = q + u32::from(r > n_minor);
                advance(&mut q, &mut r, step_q, step_r);
                line = line.wrapping_add_signed(line_step as i32);
                start = start.wrapping_add_signed(word_step);
            }
            if last_chunk {
                test(start, line, first, end, &mut hits);
            }
            j += k;
        }
        let mut collision = hits.collision;
        if hits.fraction > 0.0 {
            collision.length = hits.fraction * length();
        }
        collision
    }

    /// Whether the segment between the centres of `a` and `b` touches no blocked cell
    /// ([`planner_api::segment_is_free`] on the packed grid). Precondition as
    /// [`BitGrid::segment_collision`].
    pub fn segment_is_free(&self, a: Cell, b: Cell) -> bool {
        self.segment_collision(a, b).is_free()
    }
}

/// A direct-mapped cache of [`BitGrid::segment_collision`] per segment: the swarm's
/// particles share waypoints and keep them between iterations, so the same segment is
/// measured again and again (15 to 24 % of the segments on seed 002's maps with 512
/// entries, the bench's `segments cached`; an unbounded set answered 25 to 36 %). Segment
/// `a -> b` lives in slot `(k * 0x9e3779b97f4a7c15) >> 52` (the product wrapping, taken
/// modulo [`SEGMENT_CACHE_ENTRIES`]) of `k = ax << 48 ^ ay << 32 ^ bx << 16 ^ by`; a lookup
/// is a hit (`n_segment_cache_hits`) when that slot holds the same segment from this
/// generation, and a miss measures the segment and overwrites the slot. An entry is valid
/// in one generation only; [`SegmentCache::clear`] starts a new one, which a search must
/// do whenever the grid may have changed. A hit returns the value the walk computed, so
/// the cache changes no result.
#[derive(Debug, Clone, Default)]
pub struct SegmentCache {
    entries: Vec<Entry>,
    generation: u32,
    /// Lookups answered from the cache since the last clear.
    pub hits: u64,
    /// Lookups since the last clear.
    pub lookups: u64,
}

#[derive(Debug, Clone, Copy, Default)]
struct Entry {
    generation: u32,
    a: Cell,
    b: Cell,
    length: f64,
    collision: Collision,
}

/// The cache's entries (a power of two). 512 entries of 48 bytes fit the first-level data
/// cache; on the 200 x 200 maps 4096 entries took 6 % fewer instructions per search but
/// missed the first-level data cache 4 times as often (callgrind, issue 34: 272 M against
/// 290 M instructions, 182 k against 43 k misses, 6 searches), and the timings under
/// load did not separate them.
pub const SEGMENT_CACHE_ENTRIES: usize = 512;

impl SegmentCache {
    /// Forgets every entry (a new generation) and zeroes the counts.
    pub fn clear(&mut self) {
        if self.entries.is_empty() {
            self.entries.resize(SEGMENT_CACHE_ENTRIES, Entry::default());
        }
        self.generation = self.generation.wrapping_add(1);
        if self.generation == 0 {
            // The generations wrapped: entries of generation 0 may be stale.
            self.entries.fill(Entry::default());
            self.generation = 1;
        }
        self.hits = 0;
        self.lookups = 0;
    }

    /// The length of the segment between the centres of `a` and `b` and
    /// `grid.segment_collision(a, b)`, from the cache when this generation measured the
    /// segment already and the entry was not overwritten since. Precondition: cleared at
    /// least once, and not since `grid` changed.
    #[inline]
    pub fn segment(&mut self, grid: &BitGrid, a: Cell, b: Cell) -> (f64, Collision) {
        self.lookups += 1;
        let hash =
            (u64::from(a.x) << 48 ^ u64::from(a.y) << 32 ^ u64::from(b.x) << 16 ^ u64::from(b.y))
                .wrapping_mul(0x9e37_79b9_7f4a_7c15);
        let slot = (hash >> 52) as usize & (SEGMENT_CACHE_ENTRIES - 1);
        let entry = &mut self.entries[slot];
        if entry.generation == self.generation && entry.a == a && entry.b == b {
            self.hits += 1;
            return (entry.length, entry.collision);
        }
        let length = distance(a, b);
        let collision = grid.segment_collision_of_length(a, b, || length);
        *entry = Entry {
            generation: self.generation,
            a,
            b,
            length,
            collision,
        };
        (length, collision)
    }
}

/// The Euclidean distance between the centres of `a` and `b` as the square root of the
/// sum of squares (exact in the integers below it; `Cell::euclidean`'s `hypot` is a library
/// call, and this runs once per new segment of every evaluation).
pub fn distance(a: Cell, b: Cell) -> f64 {
    let dx = f64::from(a.x.abs_diff(b.x));
    let dy = f64::from(a.y.abs_diff(b.y));
    (dx * dx + dy * dy).sqrt()
}

/// The blocked cells met so far by the segment `a` -> `b` of
/// [`BitGrid::segment_collision`], in its major and minor axes (`a` the end with the
/// smaller major coordinate).
struct Hits {
    a_major: u32,
    a_minor: u32,
    n_major: u32,
    n_minor: u32,
    collision: Collision,
    /// The sum of the blocked runs' fractions of the segment.
    fraction: f64,
}

impl Hits {
    /// Counts the blocked cells of `words` (the packed line `line`) at major coordinates
    /// `first ..= last`, a run of consecutive blocked cells at a time.
    /// Precondition: `first <= last < 64 words.len()`.
    #[cold]
    #[inline(never)]
    fn run(&mut self, words: &[u64], line: u32, first: u32, last: u32) {
        let (w0, w1) = ((first / 64) as usize, (last / 64) as usize);
        let bounds = self.line_bounds(line);
        if w0 == w1 {
            // The usual case: the line's cells in one word.
            let mask = (!0u64 << (first % 64)) & (!0u64 >> (63 - last % 64));
            if let Some(&word) = words.get(w0) {
                self.word(word & mask, w0, bounds);
            }
            return;
        }
        for (w, &word) in words.iter().enumerate().take(w1 + 1).skip(w0) {
            let mut word = word;
            if w == w0 {
                word &= !0u64 << (first % 64);
            }
            if w == w1 {
                word &= !0u64 >> (63 - last % 64);
            }
            self.word(word, w, bounds);
        }
    }

    /// Counts the blocked cells `word` of word `w` of a line whose minor parameter
    /// bounds are `bounds` ([`Hits::line_bounds`]), a run of consecutive blocked cells at
    /// a time.
    #[inline]
    fn word(&mut self, mut word: u64, w: usize, bounds: (Bound, Bound)) {
        while word != 0 {
            let start = word.trailing_zeros();
            // At least 1; the run ends at the word's end at the latest.
            let length = (!(word >> start)).trailing_zeros().min(64 - start);
            let low = (w * 64) as u32 + start;
            self.collision.cells += u64::from(length);
            self.fraction += self.run_fraction(bounds, low, low + length - 1);
            word = if start + length >= 64 {
                0
            } else {
                word & (!0u64 << (start + length))
            };
        }
    }

    /// The segment's parameter interval on line `line` (its offset `k` from `a`'s):
    /// `[2 k - 1, 2 k + 1] / (2 n_m)` within `[0, 1]` (all of it when `n_m = 0`).
    #[inline]
    fn line_bounds(&self, line: u32) -> (Bound, Bound) {
        let (mut t0, mut t1) = (Bound::ZERO, Bound::ONE);
        if self.n_minor > 0 {
            let k = i64::from(line.abs_diff(self.a_minor));
            let n = 2 * i64::from(self.n_minor);
            t0 = t0.max(Bound::new(2 * k - 1, n));
            t1 = t1.min(Bound::new(2 * k + 1, n));
        }
        (t0, t1)
    }

    /// The fraction of the segment inside the rectangle of the cells `low ..= high` of a
    /// line whose bounds are `bounds`: Liang-Barsky clipping with the parameter bounds of
    /// each axis, the major one `[2 o_0 - 1, 2 o_1 + 1] / (2 n_M)` for the run's offsets
    /// `o_0 <= o_1` from `a` along the segment, the minor one `bounds`. The bounds are
    /// compared as exact fractions and only the two winners divided: the same values as
    /// dividing all of them and comparing the quotients (rounding is monotone).
    #[inline]
    fn run_fraction(&self, bounds: (Bound, Bound), low: u32, high: u32) -> f64 {
        if self.n_major == 0 {
            // A single point: no length.
            return 0.0;
        }
        let (o0, o1) = (
            i64::from(low - self.a_major),
            i64::from(high - self.a_major),
        );
        let m = 2 * i64::from(self.n_major);
        let t0 = bounds.0.max(Bound::new(2 * o0 - 1, m)).value();
        let t1 = bounds.1.min(Bound::new(2 * o1 + 1, m)).value();
        (t1 - t0).max(0.0)
    }
}

/// A parameter bound along a segment as the exact fraction `num / den` (`den > 0`, both
/// below 2^33, so that the products of a comparison fit and the conversions to `f64` are
/// exact).
#[derive(Debug, Clone, Copy)]
struct Bound {
    num: i64,
    den: i64,
}

impl Bound {
    const ZERO: Bound = Bound { num: 0, den: 1 };
    const ONE: Bound = Bound { num: 1, den: 1 };

    #[inline]
    fn new(num: i64, den: i64) -> Bound {
        Bound { num, den }
    }

    /// The larger of the two (`self` when equal).
    #[inline]
    fn max(self, other: Bound) -> Bound {
        if other.num * self.den > self.num * other.den {
            other
        } else {
            self
        }
    }

    /// The smaller of the two (`self` when equal).
    #[inline]
    fn min(self, other: Bound) -> Bound {
        if other.num * self.den < self.num * other.den {
            other
        } else {
            self
        }
    }

    /// The quotient, rounded once: the same `f64` as dividing the converted parts.
    #[inline]
    fn value(self) -> f64 {
        self.num as f64 / self.den as f64
    }
}

/// The length of the segment between the centres of `a` and `b` inside the square of
/// `cell` (side 1, centred on the cell's centre), by Liang-Barsky clipping.
pub fn clipped_length(a: Cell, b: Cell, cell: Cell) -> f64 {
    clipped_fraction(a, b, cell) * a.euclidean(b)
}

/// The fraction of the segment between the centres of `a` and `b` that lies inside the
/// square of `cell`: the parameter interval `[t0, t1]` of Liang-Barsky clipping.
///
/// Each axis with `b != a` bounds `t` below by `(c - a - s/2) / (b - a)` and above by
/// `(c - a + s/2) / (b - a)` (`s` the axis' direction); on an axis with `b == a` the
/// segment meets the square only if `a == c`. The bounds are compared exactly as integer
/// fractions (coordinates doubled) and only the two that win are divided, so `t0` and
/// `t1` are the same floating-point values as Liang-Barsky's four divisions give (rounding
/// is monotone, and a quotient's rounding does not depend on scaling both sides by 2;
/// tested bit for bit against them).
fn clipped_fraction(a: Cell, b: Cell, cell: Cell) -> f64 {
    // The lower and upper bound as fractions `(numerator, denominator > 0)`.
    let (mut low, mut high) = ((0i64, 1i64), (1i64, 1i64));
    for (a, b, c) in [(a.x, b.x, cell.x), (a.y, b.y, cell.y)] {
        let (a, b, c) = (i64::from(a), i64::from(b), i64::from(c));
        if a == b {
            if a != c {
                return 0.0;
            }
            continue;
        }
        let offset = if b > a { 2 * (c - a) } else { 2 * (a - c) };
        let denominator = 2 * (b - a).abs();
        let (l, u) = (offset - 1, offset + 1);
        if l * low.1 > low.0 * denominator {
            low = (l, denominator);
        }
        if u * high.1 < high.0 * denominator {
            high = (u, denominator);
        }
    }
    // Exact integers (|values| < 2^53), so the conversions are exact.
    let t0 = low.0 as f64 / low.1 as f64;
    let t1 = high.0 as f64 / high.1 as f64;
    if t1 > t0 {
        t1 - t0
    } else {
        0.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Marsaglia's xorshift64 generator from the nonzero `state`: the tests' random grids
    /// and segments.
    fn xorshift(mut state: u64) -> impl FnMut() -> u64 {
        move || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            state
        }
    }

    /// Asserts that the packed walk of `bits` (loaded from `grid`) measures the segment
    /// `a` -> `b` as the cell-by-cell walk does, and returns the walk's measure.
    fn assert_packed_agrees(bits: &BitGrid, grid: &Grid, a: Cell, b: Cell) -> Collision {
        let exact = segment_collision(grid, a, b);
        let packed = bits.segment_collision(a, b);
        assert_eq!(packed.cells, exact.cells, "{a:?} -> {b:?}");
        assert!(
            (packed.length - exact.length).abs() < 1e-9,
            "{a:?} -> {b:?}: {} vs {}",
            packed.length,
            exact.length
        );
        exact
    }

    /// A cell of the `w` x `h` grid from two draws of `next`.
    fn random_cell(next: &mut impl FnMut() -> u64, w: u32, h: u32) -> Cell {
        let x = (next() % u64::from(w)) as u32;
        Cell::new(x, (next() % u64::from(h)) as u32)
    }

    /// Reference: the fraction of the segment between the centres of `a` and `b` that lies inside the
    /// square of `cell`: the parameter interval `[t0, t1]` of Liang-Barsky clipping.
    fn liang_barsky(a: Cell, b: Cell, cell: Cell) -> f64 {
        let (ax, ay) = (f64::from(a.x), f64::from(a.y));
        let (dx, dy) = (f64::from(b.x) - ax, f64::from(b.y) - ay);
        let (cx, cy) = (f64::from(cell.x), f64::from(cell.y));
        let (mut t0, mut t1) = (0.0f64, 1.0f64);
        // Each side: p t <= q must hold for the point a + t (dx, dy) to be inside.
        for (p, q) in [
            (-dx, ax - (cx - 0.5)),
            (dx, (cx + 0.5) - ax),
            (-dy, ay - (cy - 0.5)),
            (dy, (cy + 0.5) - ay),
        ] {
            if p == 0.0 {
                if q < 0.0 {
                    return 0.0;
                }
            } else {
                let r = q / p;
                if p < 0.0 {
                    t0 = t0.max(r);
                } else {
                    t1 = t1.min(r);
                }
            }
        }
        if t1 > t0 {
            t1 - t0
        } else {
            0.0
        }
    }

    #[test]
    fn clipping_equals_four_division_liang_barsky_bit_for_bit() {
        let mut draw = xorshift(0x0bad_5eed_1234_5678);
        let mut next = move |n: u64| (draw() % n) as u32;
        let mut n_inside = 0;
        for _ in 0..200_000 {
            let a = Cell::new(next(40), next(40));
            let b = Cell::new(next(40), next(40));
            // Near the segment's box, so that many cells are met.
            let cell = Cell::new(
                (a.x.min(b.x) + next(u64::from(a.x.abs_diff(b.x)) + 3)).saturating_sub(1),
                (a.y.min(b.y) + next(u64::from(a.y.abs_diff(b.y)) + 3)).saturating_sub(1),
            );
            let (fast, slow) = (clipped_fraction(a, b, cell), liang_barsky(a, b, cell));
            assert_eq!(fast.to_bits(), slow.to_bits(), "{a:?} -> {b:?} in {cell:?}");
            n_inside += u64::from(slow > 0.0);
        }
        assert!(n_inside > 20_000, "too few cells met: {n_inside}");
    }

    /// Whether the closed square of `cell` meets the closed segment between the centres
    /// of `a` and `b`, in exact integer arithmetic (coordinates doubled so that square
    /// corners are integers): the bounding boxes overlap and the square's corners are not
    /// all strictly on one side of the segment's line (the separating axis test).
    fn touches(a: Cell, b: Cell, cell: Cell) -> bool {
        let (ax, ay) = (2 * i64::from(a.x), 2 * i64::from(a.y));
        let (bx, by) = (2 * i64::from(b.x), 2 * i64::from(b.y));
        let (cx, cy) = (2 * i64::from(cell.x), 2 * i64::from(cell.y));
        if ax.max(bx) < cx - 1 || ax.min(bx) > cx + 1 || ay.max(by) < cy - 1 || ay.min(by) > cy + 1
        {
            return false;
        }
        let side = |px: i64, py: i64| ((bx - ax) * (py - ay) - (by - ay) * (px - ax)).signum();
        let sides = [
            side(cx - 1, cy - 1),
            side(cx + 1, cy - 1),
            side(cx - 1, cy + 1),
            side(cx + 1, cy + 1),
        ];
        !(sides.iter().all(|&s| s > 0) || sides.iter().all(|&s| s < 0))
    }

    /// The brute force: every cell of the grid tested for contact, and the length inside
    /// every blocked cell clipped, without the traversal.
    fn brute_force(grid: &Grid, a: Cell, b: Cell) -> Collision {
        let mut collision = Collision::default();
        for cell in grid.cells() {
            if !grid.is_free(cell) && touches(a, b, cell) {
                collision.cells += 1;
            }
            if !grid.is_free(cell) {
                collision.length += clipped_length(a, b, cell);
            }
        }
        collision
    }

    fn check(grid: &Grid, a: Cell, b: Cell) {
        let fast = segment_collision(grid, a, b);
        let slow = brute_force(grid, a, b);
        let mut bits = BitGrid::new();
        bits.load(grid);
        assert_packed_agrees(&bits, grid, a, b);
        assert_eq!(fast.cells, slow.cells, "{a:?} -> {b:?}");
        assert!(
            (fast.length - slow.length).abs() < 1e-9,
            "{a:?} -> {b:?}: {} vs {}",
            fast.length,
            slow.length
        );
        assert_eq!(
            fast.is_free(),
            planner_api::segment_is_free(grid, a, b),
            "{a:?} -> {b:?}"
        );
    }

    #[test]
    fn by_hand() {
        let grid = Grid::from_ascii(
            "
            ....
            .#..
            ..#.
            ....
            ",
        )
        .unwrap();
        let c = |x, y| Cell::new(x, y);
        // Along row 1 through the blocked (1, 1): one cell, length 1.
        let hit = segment_collision(&grid, c(0, 1), c(3, 1));
        assert_eq!((hit.cells, hit.length), (1, 1.0));
        // The diagonal (0,0) -> (3,3) crosses both blocked cells, sqrt 2 inside each.
        let diagonal = segment_collision(&grid, c(0, 0), c(3, 3));
        assert_eq!(diagonal.cells, 2);
        assert!((diagonal.length - 2.0 * 2f64.sqrt()).abs() < 1e-12);
        // (2, 0) -> (0, 2) crosses (1, 1) through its centre along the anti-diagonal;
        // the side cells at the two vertices it passes are free.
        let anti = segment_collision(&grid, c(2, 0), c(0, 2));
        assert_eq!(anti.cells, 1);
        assert!((anti.length - 2f64.sqrt()).abs() < 1e-12);
        // (1, 0) -> (3, 2) passes the vertices (1.5, 0.5) and (2.5, 1.5): it touches the
        // blocked (1, 1) and (2, 2) at a corner each, with length 0 inside.
        let graze = segment_collision(&grid, c(1, 0), c(3, 2));
        assert_eq!((graze.cells, graze.length), (2, 0.0));
        assert!(!planner_api::segment_is_free(&grid, c(1, 0), c(3, 2)));
        // (0, 3) -> (3, 0) passes the vertex (1.5, 1.5) between the two blocked cells.
        let between = segment_collision(&grid, c(0, 3), c(3, 0));
        assert_eq!((between.cells, between.length), (2, 0.0));
        // Free.
        assert_eq!(
            segment_collision(&grid, c(0, 3), c(3, 3)),
            Collision {
                cells: 0,
                length: 0.0
            }
        );
    }

    #[test]
    fn traversal_agrees_with_a_brute_force_cell_walk() {
        // A xorshift generator: random 12 x 9, 70 x 9 and 9 x 70 grids (the packed lines
        // span up to two words) with about 35% blocked, random segments.
        let mut next = xorshift(0x9e37_79b9_7f4a_7c15u64);
        let mut n_hits = 0;
        for round in 0..40 {
            // Columns of more than one word too (9 x 70).
            let (w, h) = [(12u32, 9u32), (70, 9), (9, 70)][round % 3];
            let free: Vec<bool> = (0..w * h).map(|_| next() % 100 >= 35).collect();
            let grid = Grid::from_free_cells(w, h, free).unwrap();
            for _ in 0..50 {
                let a = random_cell(&mut next, w, h);
                let b = random_cell(&mut next, w, h);
                check(&grid, a, b);
                n_hits += u64::from(!segment_collision(&grid, a, b).is_free());
            }
        }
        assert!(n_hits > 500, "too few colliding segments to test: {n_hits}");
    }

    #[test]
    fn summed_area_counts_by_brute_force() {
        let grid = Grid::from_ascii(
            "
            #....
            .#..#
            ..#..
            ",
        )
        .unwrap();
        let mut bits = BitGrid::new();
        bits.load(&grid);
        for (x0, x1, y0, y1) in [
            (0, 4, 0, 2),
            (1, 2, 1, 2),
            (3, 3, 0, 2),
            (2, 4, 0, 0),
            (0, 0, 0, 0),
        ] {
            let brute = grid
                .cells()
                .filter(|c| {
                    (x0..=x1).contains(&c.x) && (y0..=y1).contains(&c.y) && !grid.is_free(*c)
                })
                .count();
            assert_eq!(
                bits.blocked_in(x0, x1, y0, y1) as usize,
                brute,
                "{x0} {x1} {y0} {y1}"
            );
        }
        assert_eq!(bits.blocked_in(0, 4, 0, 2), 4);
    }

    #[test]
    fn long_runs_on_sparse_grids_agree_with_the_traversal() {
        // Sparse random grids (about 2% blocked, some blocked squares) 150 x 90, where the
        // runs of a line span up to three words: the packed walk must agree with the full
        // traversal.
        let mut next = xorshift(0x2545_f491_4f6c_dd1du64);
        let (w, h) = (150u32, 90u32);
        let mut n_hits = 0;
        for _ in 0..10 {
            let mut free: Vec<bool> = (0..w * h).map(|_| next() % 100 >= 2).collect();
            for _ in 0..6 {
                let (x0, y0, side) = (next() % 140, next() % 80, 1 + next() % 9);
                for y in y0..(y0 + side).min(u64::from(h)) {
                    for x in x0..(x0 + side).min(u64::from(w)) {
                        free[(y * u64::from(w) + x) as usize] = false;
                    }
                }
            }
            let grid = Grid::from_free_cells(w, h, free).unwrap();
            let mut bits = BitGrid::new();
            bits.load(&grid);
            for _ in 0..300 {
                let a = random_cell(&mut next, w, h);
                let b = random_cell(&mut next, w, h);
                let exact = assert_packed_agrees(&bits, &grid, a, b);
                n_hits += u64::from(!exact.is_free());
            }
        }
        assert!(n_hits > 500, "too few colliding segments to test: {n_hits}");
    }
}
