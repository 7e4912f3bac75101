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
//! with the traversal stepped inline on the packed rows: a fitness evaluation walks every
//! segment of its path, so this loop is most of CAPSO's time.

use planner_api::{for_each_segment_cell, Cell, Grid};

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

/// The grid's blocked cells packed one bit per cell, row by row (each row padded to whole
/// 64-bit words), kept between searches and rebuilt only when the grid's
/// [`revision`](Grid::revision) changes.
#[derive(Debug, Clone, Default)]
pub struct BitGrid {
    width: u32,
    height: u32,
    words_per_row: usize,
    blocked: Vec<u64>,
    /// Per cell, the Chebyshev distance to the nearest blocked cell, capped at
    /// [`MAX_CLEARANCE`] (0 for a blocked cell; cells outside the grid do not count).
    clearance: Vec<u8>,
    revision: Option<u64>,
}

/// The cap of the stored clearance.
pub const MAX_CLEARANCE: u8 = 255;

impl BitGrid {
    /// An empty bit grid; [`BitGrid::load`] fills it.
    pub fn new() -> BitGrid {
        BitGrid::default()
    }

    /// The bytes [`BitGrid::load`] allocates for `grid`: the packed rows and a clearance
    /// byte per cell.
    pub fn bytes_for(grid: &Grid) -> u64 {
        (u64::from(grid.width()).div_ceil(64) * 8 + u64::from(grid.width()))
            * u64::from(grid.height())
    }

    /// Makes this the packed copy of `grid` (nothing to do when it already is).
    pub fn load(&mut self, grid: &Grid) {
        if self.revision == Some(grid.revision())
            && (self.width, self.height) == (grid.width(), grid.height())
        {
            return;
        }
        self.width = grid.width();
        self.height = grid.height();
        self.words_per_row = (grid.width() as usize).div_ceil(64);
        self.blocked.clear();
        self.blocked
            .resize(self.words_per_row * grid.height() as usize, 0);
        for (row, free) in grid.free_cells().chunks(grid.width() as usize).enumerate() {
            let words = &mut self.blocked[row * self.words_per_row..(row + 1) * self.words_per_row];
            for (x, &free) in free.iter().enumerate() {
                if !free {
                    words[x / 64] |= 1 << (x % 64);
                }
            }
        }
        self.load_clearance(grid);
        self.revision = Some(grid.revision());
    }

    /// The chessboard distance transform (Rosenfeld and Pfaltz 1966): a forward pass over
    /// the rows with the four neighbours before a cell and a backward pass with the four
    /// after it give every cell its exact Chebyshev distance to the nearest blocked cell.
    fn load_clearance(&mut self, grid: &Grid) {
        let (w, h) = (grid.width() as usize, grid.height() as usize);
        let c = &mut self.clearance;
        c.clear();
        c.extend(
            grid.free_cells()
                .iter()
                .map(|&free| if free { MAX_CLEARANCE } else { 0 }),
        );
        for y in 0..h {
            for x in 0..w {
                let i = y * w + x;
                let mut d = c[i];
                if x > 0 {
                    d = d.min(c[i - 1].saturating_add(1));
                }
                if y > 0 {
                    d = d.min(c[i - w].saturating_add(1));
                    if x > 0 {
                        d = d.min(c[i - w - 1].saturating_add(1));
                    }
                    if x + 1 < w {
                        d = d.min(c[i - w + 1].saturating_add(1));
                    }
                }
                c[i] = d;
            }
        }
        for y in (0..h).rev() {
            for x in (0..w).rev() {
                let i = y * w + x;
                let mut d = c[i];
                if x + 1 < w {
                    d = d.min(c[i + 1].saturating_add(1));
                }
                if y + 1 < h {
                    d = d.min(c[i + w].saturating_add(1));
                    if x + 1 < w {
                        d = d.min(c[i + w + 1].saturating_add(1));
                    }
                    if x > 0 {
                        d = d.min(c[i + w - 1].saturating_add(1));
                    }
                }
                c[i] = d;
            }
        }
    }

    /// The Chebyshev distance from `(x, y)` to the nearest blocked cell, capped at
    /// [`MAX_CLEARANCE`]. Precondition: the cell lies in the grid.
    pub fn clearance(&self, x: u32, y: u32) -> u8 {
        self.clearance[y as usize * self.width as usize + x as usize]
    }

    /// Width in cells.
    pub fn width(&self) -> u32 {
        self.width
    }

    /// Height in cells.
    pub fn height(&self) -> u32 {
        self.height
    }

    /// Whether the cell `(x, y)` is blocked. Precondition: it lies in the grid.
    #[inline]
    pub fn is_blocked(&self, x: u32, y: u32) -> bool {
        let word = self.blocked[y as usize * self.words_per_row + x as usize / 64];
        word >> (x % 64) & 1 == 1
    }

    /// [`segment_collision`] on the packed grid: the blocked cells that the segment
    /// between the centres of `a` and `b` touches (the cells of
    /// [`for_each_segment_cell`], in the same order, by the same integer decision
    /// variable) and its length inside them. Precondition: `a` and `b` lie in the grid, so
    /// every visited cell does (they lie in the two cells' bounding box).
    ///
    /// Free stretches are skipped by clearance: at a cell of clearance `r >= 3` every
    /// cell within Chebyshev distance `r - 1` is free, and the walk's next cells up to
    /// `j = r - 2` crossings further along the major axis lie within it (the minor
    /// coordinate advances at most once between two major crossings, so at most `j + 1`),
    /// so the walk jumps to the state right after the `j`-th major crossing: major count
    /// `k`, and minor count the number of minor crossings at or before it,
    /// `floor(((2 k - 1) n_minor + n_major) / (2 n_major))` (crossing `k` of an axis with
    /// `n` steps is at parameter `(2 k - 1) / (2 n)`). The blocked cells visited, and
    /// their order, are those of the full walk (tested against it).
    pub fn segment_collision(&self, a: Cell, b: Cell) -> Collision {
        let nx = i64::from(a.x.abs_diff(b.x));
        let ny = i64::from(a.y.abs_diff(b.y));
        let sx: i64 = if b.x >= a.x { 1 } else { -1 };
        let sy: i64 = if b.y >= a.y { 1 } else { -1 };
        let width = self.width as i64;
        // Flat index steps; every visited cell lies in the bounding box of a and b, so
        // every index is in range.
        let (step_x, step_y) = (sx, sy * width);
        let mut index = i64::from(a.y) * width + i64::from(a.x);
        let mut collision = Collision::default();
        let mut fraction = 0.0;
        let (mut ix, mut iy) = (0i64, 0i64);
        // (1 + 2 ix) ny - (1 + 2 iy) nx, kept up to date with ix and iy.
        let mut decision = ny - nx;
        loop {
            let clearance = self.clearance[index as usize];
            if clearance == 0 {
                self.blocked_cell(a, b, index, &mut collision, &mut fraction);
            }
            if ix >= nx && iy >= ny {
                break;
            }
            if clearance >= 3 {
                let j = i64::from(clearance) - 2;
                let jumped = if nx >= ny && ix < nx {
                    ix = (ix + j).min(nx);
                    iy = (((2 * ix - 1) * ny + nx) / (2 * nx)).min(ny);
                    true
                } else if ny > nx && iy < ny {
                    iy = (iy + j).min(ny);
                    ix = (((2 * iy - 1) * nx + ny) / (2 * ny)).min(nx);
                    true
                } else {
                    false
                };
                if jumped {
                    index = (i64::from(a.y) + sy * iy) * width + i64::from(a.x) + sx * ix;
                    decision = (1 + 2 * ix) * ny - (1 + 2 * iy) * nx;
                    continue;
                }
            }
            // The next crossing: a vertical grid line when decision < 0, a horizontal one
            // when > 0, both at a vertex (the two side cells first).
            if decision == 0 {
                for side in [index + step_x, index + step_y] {
                    if self.clearance[side as usize] == 0 {
                        self.blocked_cell(a, b, side, &mut collision, &mut fraction);
                    }
                }
                index += step_x + step_y;
                ix += 1;
                iy += 1;
                decision += 2 * (ny - nx);
            } else if decision < 0 {
                index += step_x;
                ix += 1;
                decision += 2 * ny;
            } else {
                index += step_y;
                iy += 1;
                decision -= 2 * nx;
            }
        }
        if fraction > 0.0 {
            collision.length = fraction * a.euclidean(b);
        }
        collision
    }

    /// Counts the blocked cell at flat `index` for the segment `a` -> `b`.
    #[cold]
    #[inline(never)]
    fn blocked_cell(
        &self,
        a: Cell,
        b: Cell,
        index: i64,
        collision: &mut Collision,
        fraction: &mut f64,
    ) {
        let width = self.width as i64;
        // A visited cell's flat index: in the grid, so the casts are exact.
        let cell = Cell::new((index % width) as u32, (index / width) as u32);
        collision.cells += 1;
        *fraction += clipped_fraction(a, b, cell);
    }

    /// Whether the segment between the centres of `a` and `b` touches no blocked cell
    /// ([`planner_api::segment_is_free`] on the packed grid). Precondition as
    /// [`BitGrid::segment_collision`].
    pub fn segment_is_free(&self, a: Cell, b: Cell) -> bool {
        self.segment_collision(a, b).is_free()
    }
}

/// The length of the segment between the centres of `a` and `b` inside the square of
/// `cell` (side 1, centred on the cell's centre), by Liang-Barsky clipping.
pub fn clipped_length(a: Cell, b: Cell, cell: Cell) -> f64 {
    clipped_fraction(a, b, cell) * a.euclidean(b)
}

/// The fraction of the segment between the centres of `a` and `b` that lies inside the
/// square of `cell`: the parameter interval `[t0, t1]` of Liang-Barsky clipping.
fn clipped_fraction(a: Cell, b: Cell, cell: Cell) -> f64 {
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

#[cfg(test)]
mod tests {
    use super::*;

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
        let packed = bits.segment_collision(a, b);
        assert_eq!(packed.cells, fast.cells, "{a:?} -> {b:?}");
        assert_eq!(
            packed.length.to_bits(),
            fast.length.to_bits(),
            "{a:?} -> {b:?}"
        );
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
        // A xorshift generator: random 12 x 9 and 70 x 9 grids (the packed rows span two
        // words) with about 35% blocked, random segments.
        let mut state = 0x9e37_79b9_7f4a_7c15u64;
        let mut next = move || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            state
        };
        let mut n_hits = 0;
        for round in 0..40 {
            let (w, h) = if round % 2 == 0 {
                (12u32, 9u32)
            } else {
                (70, 9)
            };
            let free: Vec<bool> = (0..w * h).map(|_| next() % 100 >= 35).collect();
            let grid = Grid::from_free_cells(w, h, free).unwrap();
            for _ in 0..50 {
                let a = Cell::new((next() % u64::from(w)) as u32, (next() % 9) as u32);
                let b = Cell::new((next() % u64::from(w)) as u32, (next() % 9) as u32);
                check(&grid, a, b);
                n_hits += u64::from(!segment_collision(&grid, a, b).is_free());
            }
        }
        assert!(n_hits > 500, "too few colliding segments to test: {n_hits}");
    }

    #[test]
    fn clearance_jumps_skip_only_free_cells() {
        // Sparse random grids (about 2% blocked, some blocked squares), where the walk
        // jumps: the packed walk must still agree with the full traversal bit for bit.
        let mut state = 0x2545_f491_4f6c_dd1du64;
        let mut next = move || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            state
        };
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
            // The clearance is the brute-force Chebyshev distance to a blocked cell.
            for cell in grid.cells().step_by(37) {
                let brute = grid
                    .cells()
                    .filter(|&c| !grid.is_free(c))
                    .map(|c| c.x.abs_diff(cell.x).max(c.y.abs_diff(cell.y)))
                    .min()
                    .unwrap_or(u32::MAX)
                    .min(u32::from(MAX_CLEARANCE));
                assert_eq!(u32::from(bits.clearance(cell.x, cell.y)), brute, "{cell:?}");
            }
            for _ in 0..300 {
                let a = Cell::new(
                    (next() % u64::from(w)) as u32,
                    (next() % u64::from(h)) as u32,
                );
                let b = Cell::new(
                    (next() % u64::from(w)) as u32,
                    (next() % u64::from(h)) as u32,
                );
                let exact = segment_collision(&grid, a, b);
                let packed = bits.segment_collision(a, b);
                assert_eq!(packed.cells, exact.cells, "{a:?} -> {b:?}");
                assert_eq!(
                    packed.length.to_bits(),
                    exact.length.to_bits(),
                    "{a:?} -> {b:?}"
                );
                n_hits += u64::from(!exact.is_free());
            }
        }
        assert!(n_hits > 500, "too few colliding segments to test: {n_hits}");
    }
}
