//! Line of sight over a bit-packed grid, one masked word test per row (or column) of the
//! segment instead of one step per cell.
//!
//! The cells that [`planner_api::walk_segment`] visits between the centres of `a` and `b`
//! (planner-api's exact traversal, [`planner_api::for_each_segment_cell`]) are the cells
//! the closed segment touches. Take the axis along which the segment moves further as the
//! major one (x when `|dx| >= |dy|`): then every line of cells across the other axis (a row
//! when x is major) holds a contiguous run of touched cells, and consecutive lines' runs
//! overlap by one cell where the segment passes exactly through a grid vertex. With
//! `nu = |d major|`, `nv = |d minor| > 0`, line `k` (`0 <= k <= nv` steps from `a`) covers
//! the major offsets `lo_k ..= hi_k` from `a`, where
//!
//! - `hi_k = floor(((2k + 1) nu + nv) / (2 nv))` for `k < nv`, `hi_nv = nu`;
//! - `lo_0 = 0`, and `lo_(k+1) = hi_k - 1` when `((2k + 1) nu + nv)` is a multiple of
//!   `2 nv` (the segment leaves line `k` through a vertex), else `hi_k`.
//!
//! So a check reads one or two words per line, `min(|dx|, |dy|) + 1` lines, with an early
//! exit at the first line that has a blocked cell. The grid is stored twice, by rows and by
//! columns, so the lines are always along the major axis.
//!
//! The counters need the walk's own count of cells up to the first blocked one. Along rows
//! (x major) the walk visits the lines in order, each run in order of x, so the count is
//! the cells of the earlier rows plus the blocked cell's place in its run. Along columns
//! the walk's order differs in one way only: at a vertex it visits the x side cell (the
//! first cell of the next column) before the y side cell (the last of the current column);
//! [`SightGrid::walk`] swaps those two back. `tests/sight.rs` checks
//! [`SightGrid::walk`] against [`planner_api::walk_segment`] on random maps and segments.
//!
//! Free space is skipped with a summed-area table of the blocked cells (four loads count
//! those in any rectangle). A segment across at least [`REST_CHECK`] lines whose bounding
//! box holds no blocked cell is free at once; otherwise, at line [`REST_CHECK`] and at every
//! power of two after it, the walk asks whether the box from that line's first cell to the
//! segment's end is free (Theta\*'s segments start at a parent on an obstacle's corner and
//! often leave it behind in a few lines). The cell count of a free segment is then the
//! closed form of [`cells_touched`]. On the Moving AI bench (`cargo bench -p
//! planner-theta_star --bench movingai`) this took about 8 % off Theta\*'s and Lazy
//! Theta\*'s time on den520d; on random512-10-0, whose obstacles are scattered so that boxes
//! are seldom free, the two searches execute about 1 % more instructions (callgrind).
//!
//! The scan is compiled once per pair of directions (whether the major and the minor
//! coordinate grow), so that the line loop holds no test of them: callgrind counted the
//! walk's instructions on den520d's scenarios (both searches) at 8.16 billion before and
//! 7.00 billion after (PERFORMANCE.md, issue 30's Theta\* section).

use planner_api::{walk_segment, BlockedBits, Cell, Grid, SegmentWalk};

/// A grid's cells as bits, 1 = blocked, stored by rows and by columns (module docs).
///
/// ```
/// use planner_api::{walk_segment, Cell, Grid};
/// use planner_theta_star::SightGrid;
///
/// let grid = Grid::from_ascii("
///     ......
///     .###..
///     ......
/// ").unwrap();
/// let sight = SightGrid::new(&grid);
/// for (a, b) in [(Cell::new(0, 0), Cell::new(5, 2)), (Cell::new(0, 2), Cell::new(5, 0))] {
///     assert_eq!(sight.walk(&grid, a, b), walk_segment(&grid, a, b));
/// }
/// assert!(!sight.walk(&grid, Cell::new(0, 0), Cell::new(5, 2)).free);
/// ```
#[derive(Debug, Clone, Default)]
pub struct SightGrid {
    /// The bits by rows and by columns and their summed-area table (planner-api's; they
    /// know the grid revision they were built from).
    bits: BlockedBits,
}

impl SightGrid {
    /// The bits of `grid`.
    pub fn new(grid: &Grid) -> SightGrid {
        SightGrid {
            bits: BlockedBits::new(grid),
        }
    }

    /// Whether these bits are `grid`'s: built from its revision, or holding its cells.
    pub fn is_for(&self, grid: &Grid) -> bool {
        self.bits.is_for_revision(grid)
            || ((self.bits.width(), self.bits.height()) == (grid.width(), grid.height())
                && self.bits.rows() == BlockedBits::new(grid).rows())
    }

    /// The bits in `cache`, made `grid`'s ([`BlockedBits::load`]: rebuilt in place unless
    /// they were built from its revision).
    pub fn cached<'a>(cache: &'a mut Option<SightGrid>, grid: &Grid) -> &'a SightGrid {
        match cache {
            Some(sight) => {
                sight.bits.load(grid);
                sight
            }
            None => cache.insert(SightGrid::new(grid)),
        }
    }

    /// [`walk_segment`]`(grid, a, b)`, the same answer and cell count. Precondition: these
    /// are `grid`'s bits ([`SightGrid::is_for`]). Ends outside the grid go to
    /// [`walk_segment`] itself.
    #[inline]
    pub fn walk(&self, grid: &Grid, a: Cell, b: Cell) -> SegmentWalk {
        let inside = |c: Cell| c.x < self.bits.width() && c.y < self.bits.height();
        if !inside(a) || !inside(b) {
            return walk_segment(grid, a, b);
        }
        let nx = a.x.abs_diff(b.x) as usize;
        let ny = a.y.abs_diff(b.y) as usize;
        // A segment across fewer than `REST_CHECK` lines is walked at once: the table's
        // loads would cost about what they might save.
        if nx.min(ny) >= REST_CHECK && self.blocked_in_box(a, b) == 0 {
            return SegmentWalk {
                free: true,
                n_cells: cells_touched(nx.max(ny), nx.min(ny)),
            };
        }
        if nx >= ny {
            let rest_free =
                |u: usize, v: usize| self.blocked_in_box(Cell::new(u as u32, v as u32), b) == 0;
            let (rows, words_per_row) = self.bits.rows();
            let found = scan_any(
                rows,
                words_per_row,
                (a.x as usize, a.y as usize),
                (nx, ny),
                (b.x >= a.x, b.y >= a.y),
                rest_free,
            );
            match found {
                Scan::Free(n_cells) => SegmentWalk {
                    free: true,
                    n_cells,
                },
                Scan::Blocked { at, .. } => SegmentWalk {
                    free: false,
                    n_cells: at,
                },
            }
        } else {
            let rest_free =
                |u: usize, v: usize| self.blocked_in_box(Cell::new(v as u32, u as u32), b) == 0;
            let (columns, words_per_column) = self.bits.columns();
            let found = scan_any(
                columns,
                words_per_column,
                (a.y as usize, a.x as usize),
                (ny, nx),
                (b.y >= a.y, b.x >= a.x),
                rest_free,
            );
            match found {
                Scan::Free(n_cells) => SegmentWalk {
                    free: true,
                    n_cells,
                },
                Scan::Blocked {
                    at,
                    place,
                    next_first_blocked,
                } => {
                    // The walk visits the first cell of the next column before the last
                    // of this one at a vertex (module docs).
                    let n_cells = match place {
                        Place::LastBeforeVertex if next_first_blocked => at,
                        Place::LastBeforeVertex => at + 1,
                        Place::FirstAfterVertex => at - 1,
                        Place::Other => at,
                    };
                    SegmentWalk {
                        free: false,
                        n_cells,
                    }
                }
            }
        }
    }

    /// The blocked cells in the rectangle with corners `a` and `b`. Precondition: both
    /// inside the grid.
    #[inline(always)]
    fn blocked_in_box(&self, a: Cell, b: Cell) -> u32 {
        let (x0, x1) = (a.x.min(b.x), a.x.max(b.x));
        let (y0, y1) = (a.y.min(b.y), a.y.max(b.y));
        self.bits.blocked_in(x0, x1, y0, y1)
    }
}

/// The cells a segment touches over `nu >= nv` cells along its axes: the lines' runs
/// (module docs) overlap by one cell, or by two where the segment leaves a line through a
/// vertex, so `nu + nv + 1` plus the vertex passes. With `g = gcd(nu, nv)`, `nu = g a`
/// and `nv = g b`, line `k` is left through a vertex when `2 nv` divides
/// `(2k + 1) nu + nv`, that is when `b` divides `2k + 1` (`a`, `b` coprime) and the
/// quotient `m = (2k + 1) / b` makes `m a + 1` even: never unless `a` and `b` are odd,
/// and then for the `g` odd `m` below `2 g`.
fn cells_touched(nu: usize, nv: usize) -> u64 {
    let (nu, nv) = (nu as u64, nv as u64);
    if nv == 0 {
        return nu + 1;
    }
    // `a` and `b` are both odd exactly when `nu` and `nv` hold the same power of two
    // (then `g`'s): only then is `g` needed.
    let vertices = if nu.trailing_zeros() == nv.trailing_zeros() {
        gcd(nu, nv)
    } else {
        0
    };
    nu + nv + 1 + vertices
}

/// From this many lines on, [`scan`] asks whether the rest of the segment's box is free,
/// at every power of two (module docs). From line 4 on was about 2 % faster on den520d but
/// took 1.8 % more instructions on random512-10-0, whose boxes are seldom free (every 4
/// lines: 3.5 % more).
const REST_CHECK: usize = 8;

/// The greatest common divisor of two positive numbers (Stein's binary algorithm: shifts
/// and subtractions, no division).
fn gcd(mut a: u64, mut b: u64) -> u64 {
    let shift = (a | b).trailing_zeros();
    a >>= a.trailing_zeros();
    loop {
        b >>= b.trailing_zeros();
        if a > b {
            (a, b) = (b, a);
        }
        b -= a;
        if b == 0 {
            return a << shift;
        }
    }
}

/// Where a blocked cell sits in its line, as the column order needs to know.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Place {
    /// The last cell of a line left through a vertex.
    LastBeforeVertex,
    /// The first cell of a line entered through a vertex.
    FirstAfterVertex,
    /// Anywhere else.
    Other,
}

/// What [`scan`] found, counting cells in line order.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Scan {
    /// Every cell is free; the number of cells.
    Free(u64),
    /// The first blocked cell in line order is the `at`-th (from 1).
    Blocked {
        at: u64,
        place: Place,
        /// With [`Place::LastBeforeVertex`]: whether the next line's first cell is blocked.
        next_first_blocked: bool,
    },
}

/// Scans the lines of a segment from `a = (au, av)` over `n = (nu, nv)` cells (`nu >= nv`)
/// in directions `forward = (u grows, v grows)`, in `lines` of `stride` words each (line
/// `v`, bit `u`).
#[inline(always)]
fn scan_any(
    lines: &[u64],
    stride: usize,
    a: (usize, usize),
    n: (usize, usize),
    forward: (bool, bool),
    rest_free: impl Fn(usize, usize) -> bool,
) -> Scan {
    // One copy per direction, so that the directions are constants in the line loop.
    match forward {
        (true, true) => scan::<true, true>(lines, stride, a, n, rest_free),
        (true, false) => scan::<true, false>(lines, stride, a, n, rest_free),
        (false, true) => scan::<false, true>(lines, stride, a, n, rest_free),
        (false, false) => scan::<false, false>(lines, stride, a, n, rest_free),
    }
}

/// [`scan_any`] in the directions `(U_UP, V_UP)`.
#[inline(always)]
fn scan<const U_UP: bool, const V_UP: bool>(
    lines: &[u64],
    stride: usize,
    (au, av): (usize, usize),
    (nu, nv): (usize, usize),
    rest_free: impl Fn(usize, usize) -> bool,
) -> Scan {
    let (u_up, v_up) = (U_UP, V_UP);
    // The run of line k in absolute major coordinates.
    let span = |lo: usize, hi: usize| {
        if u_up {
            (au + lo, au + hi)
        } else {
            (au - hi, au - lo)
        }
    };
    let line_at = |k: usize| {
        let v = if v_up { av + k } else { av - k };
        &lines[v * stride..(v + 1) * stride]
    };
    if nv == 0 {
        let (l, h) = span(0, nu);
        return match first_blocked(line_at(0), l, h, u_up) {
            None => Scan::Free(nu as u64 + 1),
            Some(j) => Scan::Blocked {
                at: j as u64 + 1,
                place: Place::Other,
                next_first_blocked: false,
            },
        };
    }
    let two_nv = 2 * nv;
    let (step_q, step_r) = (nu / nv, 2 * (nu % nv));
    // hi_k and the remainder of ((2k + 1) nu + nv) / (2 nv).
    let (mut hi, mut rem) = ((nu + nv) / two_nv, (nu + nv) % two_nv);
    let mut lo = 0usize;
    let mut before = 0u64;
    let mut entered_by_vertex = false;
    let mut k = 0;
    // The next line at which the rest's box is checked: REST_CHECK, then every power of two
    // after it (one comparison a line instead of a power-of-two test).
    let mut check_at = REST_CHECK;
    // Line k's first word, stepped by a line at a time.
    let mut base = av * stride;
    loop {
        let last = k == nv;
        if k == check_at {
            // The box from this line's first cell to the segment's end holds the rest.
            let u = if u_up { au + lo } else { au - lo };
            let v = if v_up { av + k } else { av - k };
            if rest_free(u, v) {
                return Scan::Free(cells_touched(nu, nv));
            }
            check_at *= 2;
        }
        let h = if last { nu } else { hi };
        let (l, hh) = span(lo, h);
        let leaves_by_vertex = !last && rem == 0;
        if let Some(j) = first_blocked(&lines[base..base + stride], l, hh, u_up) {
            let run = h - lo;
            let place = if j == run && leaves_by_vertex {
                Place::LastBeforeVertex
            } else if j == 0 && entered_by_vertex {
                Place::FirstAfterVertex
            } else {
                Place::Other
            };
            let next_first_blocked = place == Place::LastBeforeVertex && {
                // The next line's first cell is at major offset hi - 1.
                let next = line_at(k + 1);
                let (u, _) = span(hi - 1, hi - 1);
                (next[u / 64] >> (u % 64)) & 1 != 0
            };
            return Scan::Blocked {
                at: before + j as u64 + 1,
                place,
                next_first_blocked,
            };
        }
        before += (h - lo) as u64 + 1;
        if last {
            return Scan::Free(before);
        }
        lo = if leaves_by_vertex { hi - 1 } else { hi };
        entered_by_vertex = leaves_by_vertex;
        hi += step_q;
        rem += step_r;
        if rem >= two_nv {
            rem -= two_nv;
            hi += 1;
        }
        k += 1;
        // Line k lies in the grid (k <= nv), so the next base does too.
        base = if v_up { base + stride } else { base - stride };
    }
}

/// The place (from 0, in the walk's direction: increasing when `forward`) of the first set
/// bit among bits `lo ..= hi` of `line`, if any.
#[inline(always)]
fn first_blocked(line: &[u64], lo: usize, hi: usize, forward: bool) -> Option<usize> {
    let (w0, w1) = (lo / 64, hi / 64);
    let lo_mask = !0u64 << (lo % 64);
    let hi_mask = !0u64 >> (63 - hi % 64);
    if w0 == w1 {
        let bits = line[w0] & lo_mask & hi_mask;
        if bits == 0 {
            return None;
        }
        return Some(if forward {
            w0 * 64 + bits.trailing_zeros() as usize - lo
        } else {
            hi - (w0 * 64 + 63 - bits.leading_zeros() as usize)
        });
    }
    if forward {
        let mut w = w0;
        let mut mask = lo_mask;
        loop {
            if w == w1 {
                mask &= hi_mask;
            }
            let bits = line[w] & mask;
            if bits != 0 {
                return Some(w * 64 + bits.trailing_zeros() as usize - lo);
            }
            if w == w1 {
                return None;
            }
            w += 1;
            mask = !0;
        }
    } else {
        let mut w = w1;
        let mut mask = hi_mask;
        loop {
            if w == w0 {
                mask &= lo_mask;
            }
            let bits = line[w] & mask;
            if bits != 0 {
                return Some(hi - (w * 64 + 63 - bits.leading_zeros() as usize));
            }
            if w == w0 {
                return None;
            }
            w -= 1;
            mask = !0;
        }
    }
}
