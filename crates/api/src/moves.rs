//! Move sets (neighbourhoods), their costs and validity, and exact segment traversal.
//!
//! # Neighbourhoods
//! - [`Connectivity::Four`]: seed 000's action set, unit cost. The default order is the
//!   paper's section 2.1: right, left, down, up, that is `(x+1)`, `(x-1)`, `(y+1)`, `(y-1)`.
//! - [`Connectivity::Eight`]: the four axis moves (cost 1) in the same order, then the
//!   diagonals (cost sqrt 2) down-right, down-left, up-right, up-left. Without corner
//!   cutting (the default, as the Moving AI benchmark defines it) a diagonal move needs
//!   both orthogonal cells it passes between to be free.
//! - [`Connectivity::Sixteen`], [`Connectivity::ThirtyTwo`], [`Connectivity::FortyEight`]:
//!   seed 002's `Connecting_distance` 2, 3 and 4 (Algorithm 2, Table 1). A move `(dx, dy)`
//!   belongs to `Connecting_distance k` when `max(|dx|, |dy|) <= k` and `gcd(dx, dy) = 1`,
//!   that is every *direction* reachable inside the `(2k+1) x (2k+1)` window once.
//!
//! ## The 48-direction choice
//! Algorithm 2 zeroes only the axis and diagonal cells of the window beyond the first ring;
//! that gives 8, 16, 32 directions for k = 1, 2, 3 (as Table 1), but 56 for k = 4, where
//! Table 1 says 48. The 8 extra cells of Algorithm 2 at k = 4 are `(±2, ±4)` and `(±4, ±2)`,
//! which repeat the directions of `(±1, ±2)` and `(±2, ±1)`. We follow Table 1 and the
//! text ("number of directions"): only primitive vectors, which agrees with Algorithm 2 for
//! k <= 3 and gives 48 for k = 4.
//!
//! # Validity of long moves
//! A move is valid when its target is free and the straight segment between the two cell
//! centres crosses no blocked cell. The segment's cells are found by exact traversal
//! ([`for_each_segment_cell`]), not by sampling. Where the segment passes exactly through a
//! grid vertex, it touches all four cells at that vertex, and the two side cells count as
//! crossed: this makes the 8-connected diagonal rule "no corner cutting" a special case of
//! the segment rule, so every neighbourhood beyond four shares one definition. With
//! `corner_cutting = true` (8-connected only) the side cells are not checked.
//!
//! Costs: 1 per step on the 4-connected grid; the Euclidean length `sqrt(dx^2 + dy^2)`
//! of the move otherwise ([`Move::cost`] as `f64`, [`Move::exact_cost`] in the fixed
//! point of [`crate::cost`], in which equal path costs are equal).

use std::fmt;
use std::str::FromStr;

use serde::{Deserialize, Serialize};

use crate::cost::Cost;
use crate::error::MoveOrderError;
use crate::grid::{Cell, Grid};

/// Which neighbourhood a planner expands.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize, Default)]
#[serde(try_from = "u32", into = "u32")]
pub enum Connectivity {
    /// Right, left, down, up; unit cost (seed 000).
    #[default]
    Four,
    /// The four axis moves and the four diagonals (seed 002's Connecting_distance 1).
    Eight,
    /// Seed 002's Connecting_distance 2.
    Sixteen,
    /// Seed 002's Connecting_distance 3.
    ThirtyTwo,
    /// Seed 002's Connecting_distance 4 (Table 1's 48 directions; see the module docs).
    FortyEight,
}

impl Connectivity {
    /// All neighbourhoods, smallest first.
    pub const ALL: [Connectivity; 5] = [
        Connectivity::Four,
        Connectivity::Eight,
        Connectivity::Sixteen,
        Connectivity::ThirtyTwo,
        Connectivity::FortyEight,
    ];

    /// Number of directions: 4, 8, 16, 32 or 48.
    pub fn n_directions(self) -> u32 {
        match self {
            Connectivity::Four => 4,
            Connectivity::Eight => 8,
            Connectivity::Sixteen => 16,
            Connectivity::ThirtyTwo => 32,
            Connectivity::FortyEight => 48,
        }
    }

    /// Seed 002's `Connecting_distance` for the neighbourhoods beyond four; `None` for four.
    pub fn connecting_distance(self) -> Option<u32> {
        match self {
            Connectivity::Four => None,
            Connectivity::Eight => Some(1),
            Connectivity::Sixteen => Some(2),
            Connectivity::ThirtyTwo => Some(3),
            Connectivity::FortyEight => Some(4),
        }
    }

    /// The neighbourhood of seed 002's `Connecting_distance` 1 to 4.
    pub fn from_connecting_distance(distance: u32) -> Option<Connectivity> {
        Connectivity::ALL
            .into_iter()
            .find(|c| c.connecting_distance() == Some(distance))
    }

    /// Whether every move has unit cost (only the 4-connected grid).
    pub fn is_unit_cost(self) -> bool {
        self == Connectivity::Four
    }
}

impl TryFrom<u32> for Connectivity {
    type Error = String;

    fn try_from(n: u32) -> Result<Connectivity, String> {
        Connectivity::ALL
            .into_iter()
            .find(|c| c.n_directions() == n)
            .ok_or_else(|| {
                format!("unsupported connectivity {n}, expected one of 4, 8, 16, 32, 48")
            })
    }
}

impl From<Connectivity> for u32 {
    fn from(c: Connectivity) -> u32 {
        c.n_directions()
    }
}

impl fmt::Display for Connectivity {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}-connected", self.n_directions())
    }
}

/// One of the eight unit moves, used to spell a neighbour order such as `"R L D U"`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Direction {
    /// `(x+1, y)`, token `R`.
    Right,
    /// `(x-1, y)`, token `L`.
    Left,
    /// `(x, y+1)`, token `D` (rows grow downwards).
    Down,
    /// `(x, y-1)`, token `U`.
    Up,
    /// `(x+1, y+1)`, token `DR`.
    DownRight,
    /// `(x-1, y+1)`, token `DL`.
    DownLeft,
    /// `(x+1, y-1)`, token `UR`.
    UpRight,
    /// `(x-1, y-1)`, token `UL`.
    UpLeft,
}

impl Direction {
    /// The paper's order for the 4-connected moves, then the diagonals.
    pub const DEFAULT_ORDER: [Direction; 8] = [
        Direction::Right,
        Direction::Left,
        Direction::Down,
        Direction::Up,
        Direction::DownRight,
        Direction::DownLeft,
        Direction::UpRight,
        Direction::UpLeft,
    ];

    /// The `(dx, dy)` offset of this move.
    pub fn offset(self) -> (i32, i32) {
        match self {
            Direction::Right => (1, 0),
            Direction::Left => (-1, 0),
            Direction::Down => (0, 1),
            Direction::Up => (0, -1),
            Direction::DownRight => (1, 1),
            Direction::DownLeft => (-1, 1),
            Direction::UpRight => (1, -1),
            Direction::UpLeft => (-1, -1),
        }
    }

    /// The token used in order strings: `R`, `L`, `D`, `U`, `DR`, `DL`, `UR`, `UL`.
    pub fn token(self) -> &'static str {
        match self {
            Direction::Right => "R",
            Direction::Left => "L",
            Direction::Down => "D",
            Direction::Up => "U",
            Direction::DownRight => "DR",
            Direction::DownLeft => "DL",
            Direction::UpRight => "UR",
            Direction::UpLeft => "UL",
        }
    }

    fn is_diagonal(self) -> bool {
        let (dx, dy) = self.offset();
        dx != 0 && dy != 0
    }
}

impl FromStr for Direction {
    type Err = MoveOrderError;

    fn from_str(token: &str) -> Result<Direction, MoveOrderError> {
        Direction::DEFAULT_ORDER
            .into_iter()
            .find(|d| d.token().eq_ignore_ascii_case(token))
            .ok_or_else(|| MoveOrderError::UnknownToken(token.to_string()))
    }
}

/// The order in which a planner tries the unit moves, e.g. `"R L D U"` or `"U,D,L,R"`.
///
/// For 4-connected moves it lists `R`, `L`, `D`, `U` once each; for 8-connected and larger
/// neighbourhoods it may list only those four (the diagonals then follow in the default
/// order `DR DL UR UL`) or all eight. Moves longer than one cell (16 directions and up)
/// always follow the unit moves, ordered by ring (Chebyshev length) and then clockwise
/// from the positive x axis (rows grow downwards, so clockwise on screen).
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct NeighborOrder(Vec<Direction>);

impl NeighborOrder {
    /// The given order, as is; checked against a neighbourhood by [`MoveSet::new`].
    pub fn new(directions: Vec<Direction>) -> NeighborOrder {
        NeighborOrder(directions)
    }

    /// The directions in order.
    pub fn directions(&self) -> &[Direction] {
        &self.0
    }
}

impl Default for NeighborOrder {
    fn default() -> NeighborOrder {
        NeighborOrder(Direction::DEFAULT_ORDER[..4].to_vec())
    }
}

impl FromStr for NeighborOrder {
    type Err = MoveOrderError;

    /// Parses tokens separated by spaces or commas: `"R L D U"`, `"R,L,D,U"`.
    fn from_str(text: &str) -> Result<NeighborOrder, MoveOrderError> {
        let directions = text
            .split(|c: char| c == ',' || c.is_whitespace())
            .filter(|token| !token.is_empty())
            .map(Direction::from_str)
            .collect::<Result<Vec<_>, _>>()?;
        Ok(NeighborOrder(directions))
    }
}

impl fmt::Display for NeighborOrder {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let tokens: Vec<&str> = self.0.iter().map(|d| d.token()).collect();
        f.write_str(&tokens.join(" "))
    }
}

impl Serialize for NeighborOrder {
    fn serialize<S: serde::Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        serializer.collect_str(self)
    }
}

impl<'de> Deserialize<'de> for NeighborOrder {
    fn deserialize<D: serde::Deserializer<'de>>(
        deserializer: D,
    ) -> Result<NeighborOrder, D::Error> {
        let text = String::deserialize(deserializer)?;
        text.parse().map_err(serde::de::Error::custom)
    }
}

/// One move of a [`MoveSet`]: its offset, cost, and the cells its segment passes through.
#[derive(Debug, Clone, PartialEq)]
pub struct Move {
    /// Column offset.
    pub dx: i32,
    /// Row offset.
    pub dy: i32,
    /// Cost: 1 on the 4-connected grid, else the Euclidean length.
    pub cost: f64,
    /// Offsets of the cells strictly between origin and target that must be free
    /// (empty for axis moves and for diagonals with corner cutting allowed).
    pub via: Vec<(i32, i32)>,
}

impl Move {
    /// The cost in fixed point, [`Cost::of_move`] of the offset: exactly [`Cost::ONE`]
    /// for axis moves and [`Cost::SQRT_2`] for diagonals (see [`crate::cost`]).
    pub fn exact_cost(&self) -> Cost {
        Cost::of_move(self.dx, self.dy)
    }
}

/// A neighbourhood with its moves in a fixed, documented order.
///
/// Built once per planner; planners iterate [`MoveSet::moves`] in their hot loop.
#[derive(Debug, Clone, PartialEq)]
pub struct MoveSet {
    connectivity: Connectivity,
    corner_cutting: bool,
    moves: Vec<Move>,
}

impl MoveSet {
    /// The moves of `connectivity` in `order` (see [`NeighborOrder`]).
    ///
    /// `corner_cutting` is allowed only with [`Connectivity::Eight`]; longer moves always
    /// check their whole segment.
    pub fn new(
        connectivity: Connectivity,
        corner_cutting: bool,
        order: &NeighborOrder,
    ) -> Result<MoveSet, MoveOrderError> {
        if corner_cutting && connectivity != Connectivity::Eight {
            return Err(MoveOrderError::CornerCutting(connectivity));
        }
        let unit = Self::unit_order(connectivity, order)?;
        let mut offsets: Vec<(i32, i32)> = unit.iter().map(|d| d.offset()).collect();
        if let Some(k) = connectivity.connecting_distance() {
            offsets.extend(long_offsets(k as i32));
        }
        let moves = offsets
            .into_iter()
            .map(|(dx, dy)| {
                let cost = if connectivity.is_unit_cost() {
                    1.0
                } else {
                    crate::cell_hypot(dx.unsigned_abs(), dy.unsigned_abs())
                };
                let via = if corner_cutting {
                    Vec::new()
                } else {
                    segment_via(dx, dy)
                };
                Move { dx, dy, cost, via }
            })
            .collect();
        Ok(MoveSet {
            connectivity,
            corner_cutting,
            moves,
        })
    }

    /// The moves of `connectivity` in the default order, without corner cutting.
    pub fn standard(connectivity: Connectivity) -> MoveSet {
        let order = NeighborOrder::default();
        // The default order is valid for every neighbourhood, so this cannot fail.
        match MoveSet::new(connectivity, false, &order) {
            Ok(set) => set,
            Err(_) => unreachable!("the default neighbour order is valid for {connectivity}"),
        }
    }

    fn unit_order(
        connectivity: Connectivity,
        order: &NeighborOrder,
    ) -> Result<Vec<Direction>, MoveOrderError> {
        let given = order.directions();
        let mut seen = [false; 8];
        for &d in given {
            let slot = Direction::DEFAULT_ORDER
                .iter()
                .position(|&e| e == d)
                .unwrap_or(0);
            if seen[slot] {
                return Err(MoveOrderError::Repeated(d.token()));
            }
            seen[slot] = true;
        }
        let axis_given = given.iter().filter(|d| !d.is_diagonal()).count();
        let diagonal_given = given.len() - axis_given;
        if axis_given != 4 {
            return Err(MoveOrderError::Incomplete(connectivity));
        }
        match connectivity {
            Connectivity::Four if diagonal_given > 0 => {
                Err(MoveOrderError::DiagonalInFour(order.to_string()))
            }
            Connectivity::Four => Ok(given.to_vec()),
            _ if diagonal_given == 0 => {
                let mut all = given.to_vec();
                all.extend(Direction::DEFAULT_ORDER[4..].iter().copied());
                Ok(all)
            }
            _ if diagonal_given == 4 => Ok(given.to_vec()),
            _ => Err(MoveOrderError::Incomplete(connectivity)),
        }
    }

    /// The neighbourhood.
    pub fn connectivity(&self) -> Connectivity {
        self.connectivity
    }

    /// Whether diagonal moves may cut corners.
    pub fn corner_cutting(&self) -> bool {
        self.corner_cutting
    }

    /// The moves in order.
    pub fn moves(&self) -> &[Move] {
        &self.moves
    }

    /// The target of `mv` from `from` when the move is allowed on `grid`: target in bounds
    /// and free, and every cell its segment passes through free.
    pub fn apply(&self, grid: &Grid, from: Cell, mv: &Move) -> Option<Cell> {
        let to = grid.offset(from, mv.dx, mv.dy)?;
        if !grid.is_free(to) {
            return None;
        }
        let via_free = mv.via.iter().all(|&(vx, vy)| {
            grid.offset(from, vx, vy)
                .is_some_and(|cell| grid.is_free(cell))
        });
        via_free.then_some(to)
    }

    /// The move taking `from` to `to`, if this set has one.
    pub fn find(&self, from: Cell, to: Cell) -> Option<&Move> {
        let dx = i64::from(to.x) - i64::from(from.x);
        let dy = i64::from(to.y) - i64::from(from.y);
        self.moves
            .iter()
            .find(|m| i64::from(m.dx) == dx && i64::from(m.dy) == dy)
    }
}

/// A [`MoveSet`] compiled for one grid width: flat-index deltas for the hot loop.
///
/// Planners that index the grid's flat [`Grid::free_cells`] slice use
/// [`IndexedMoves::target`] instead of [`MoveSet::apply`]; both accept exactly the same
/// moves (tested). Build it once per grid (or whenever the grid's width changes).
#[derive(Debug, Clone, PartialEq)]
pub struct IndexedMoves {
    width: u32,
    height: u32,
    moves: Vec<IndexedMove>,
    via: Vec<isize>,
}

/// One compiled move: the offset, its flat-index delta, cost, and where its `via` cells are.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct IndexedMove {
    /// Column offset.
    pub dx: i32,
    /// Row offset.
    pub dy: i32,
    /// Flat-index delta, `dy * width + dx`.
    pub delta: isize,
    /// Move cost.
    pub cost: f64,
    via_start: u32,
    via_end: u32,
}

impl IndexedMoves {
    /// Compiles `set` for grids of `grid`'s size.
    pub fn new(set: &MoveSet, grid: &Grid) -> IndexedMoves {
        let width = grid.width() as isize;
        let mut via = Vec::new();
        let moves = set
            .moves()
            .iter()
            .map(|m| {
                let via_start = via.len() as u32;
                via.extend(
                    m.via
                        .iter()
                        .map(|&(vx, vy)| vy as isize * width + vx as isize),
                );
                IndexedMove {
                    dx: m.dx,
                    dy: m.dy,
                    delta: m.dy as isize * width + m.dx as isize,
                    cost: m.cost,
                    via_start,
                    via_end: via.len() as u32,
                }
            })
            .collect();
        IndexedMoves {
            width: grid.width(),
            height: grid.height(),
            moves,
            via,
        }
    }

    /// Whether this table was compiled for a grid of `grid`'s size.
    pub fn fits(&self, grid: &Grid) -> bool {
        self.width == grid.width() && self.height == grid.height()
    }

    /// The compiled moves, in the set's order.
    pub fn moves(&self) -> &[IndexedMove] {
        &self.moves
    }

    /// Number of moves.
    pub fn len(&self) -> usize {
        self.moves.len()
    }

    /// Whether the set has no move.
    pub fn is_empty(&self) -> bool {
        self.moves.is_empty()
    }

    /// The flat index reached by move `k` from cell `(x, y)` at flat `index`, when the move
    /// is allowed: target in bounds and free, and every `via` cell free.
    ///
    /// Preconditions: `free` is the grid's [`Grid::free_cells`] for a grid this table
    /// [`fits`](IndexedMoves::fits), `index = y * width + x` is in bounds, `k < self.len()`.
    #[inline]
    pub fn target(&self, free: &[bool], x: u32, y: u32, index: usize, k: usize) -> Option<usize> {
        let m = &self.moves[k];
        let nx = x as i64 + m.dx as i64;
        let ny = y as i64 + m.dy as i64;
        if nx < 0 || ny < 0 || nx >= self.width as i64 || ny >= self.height as i64 {
            return None;
        }
        let to = (index as isize + m.delta) as usize;
        if !free[to] {
            return None;
        }
        let via = &self.via[m.via_start as usize..m.via_end as usize];
        via.iter()
            .all(|&d| free[(index as isize + d) as usize])
            .then_some(to)
    }
}

/// The moves longer than one cell for `Connecting_distance k`: primitive vectors with
/// Chebyshev length 2..=k, by ring and then clockwise angle from the positive x axis.
fn long_offsets(k: i32) -> Vec<(i32, i32)> {
    let mut offsets = Vec::new();
    for ring in 2..=k {
        let mut ring_offsets: Vec<(i32, i32)> = (-ring..=ring)
            .flat_map(|dy| (-ring..=ring).map(move |dx| (dx, dy)))
            .filter(|&(dx, dy)| dx.abs().max(dy.abs()) == ring && gcd(dx.abs(), dy.abs()) == 1)
            .collect();
        ring_offsets.sort_by(|a, b| angle(*a).total_cmp(&angle(*b)));
        offsets.extend(ring_offsets);
    }
    offsets
}

/// Angle in [0, 2 pi) measured clockwise on screen (y grows downwards) from +x.
fn angle((dx, dy): (i32, i32)) -> f64 {
    let a = f64::from(dy).atan2(f64::from(dx));
    if a < 0.0 {
        a + std::f64::consts::TAU
    } else {
        a
    }
}

fn gcd(mut a: i32, mut b: i32) -> i32 {
    while b != 0 {
        (a, b) = (b, a % b);
    }
    a
}

/// The cells strictly between the origin and `(dx, dy)` that the centre-to-centre segment
/// touches, as offsets from the origin.
fn segment_via(dx: i32, dy: i32) -> Vec<(i32, i32)> {
    let origin = Cell::new(1 << 20, 1 << 20);
    let target = Cell::new(
        origin.x.wrapping_add_signed(dx),
        origin.y.wrapping_add_signed(dy),
    );
    let mut via = Vec::new();
    for_each_segment_cell(origin, target, |cell| {
        if cell != origin && cell != target {
            via.push((
                (i64::from(cell.x) - i64::from(origin.x)) as i32,
                (i64::from(cell.y) - i64::from(origin.y)) as i32,
            ));
        }
        true
    });
    via
}

/// Visits every cell the segment between the centres of `a` and `b` touches, in order
/// from `a` to `b`, both included; stops early when `visit` returns false.
///
/// Exact traversal in integer arithmetic (the "walk grid lines" form of Amanatides and
/// Woo). Where the segment passes exactly through a grid vertex, the two side cells at that
/// vertex are visited (before the diagonal cell), so that a segment never slips between two
/// blocked cells that share only a corner. Returns false when `visit` stopped the walk.
pub fn for_each_segment_cell(a: Cell, b: Cell, mut visit: impl FnMut(Cell) -> bool) -> bool {
    let nx = i64::from(a.x.abs_diff(b.x));
    let ny = i64::from(a.y.abs_diff(b.y));
    let sx: i64 = if b.x >= a.x { 1 } else { -1 };
    let sy: i64 = if b.y >= a.y { 1 } else { -1 };
    let (mut x, mut y) = (i64::from(a.x), i64::from(a.y));
    // Coordinates stay within the bounding box of a and b, so they fit in u32.
    let at = |x: i64, y: i64| Cell::new(x as u32, y as u32);
    if !visit(at(x, y)) {
        return false;
    }
    let (mut ix, mut iy) = (0i64, 0i64);
    while ix < nx || iy < ny {
        // Compare the parameter at which the segment crosses the next vertical line,
        // (0.5 + ix) / nx, with the next horizontal line, (0.5 + iy) / ny.
        let decision = (1 + 2 * ix) * ny - (1 + 2 * iy) * nx;
        if decision == 0 {
            if !visit(at(x + sx, y)) || !visit(at(x, y + sy)) {
                return false;
            }
            x += sx;
            y += sy;
            ix += 1;
            iy += 1;
        } else if decision < 0 {
            x += sx;
            ix += 1;
        } else {
            y += sy;
            iy += 1;
        }
        if !visit(at(x, y)) {
            return false;
        }
    }
    true
}

/// Whether the segment between the centres of `a` and `b` crosses only free cells
/// (both ends included). Cells outside the grid count as blocked.
///
/// This is [`walk_segment`]'s answer, and so visits the cells of [`for_each_segment_cell`].
pub fn segment_is_free(grid: &Grid, a: Cell, b: Cell) -> bool {
    walk_segment(grid, a, b).free
}

/// What [`walk_segment`] found.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct SegmentWalk {
    /// Whether every cell of the segment is free (both ends included).
    pub free: bool,
    /// Cells looked at: all of them when free, else up to and including the first blocked
    /// (or outside) one.
    pub n_cells: u64,
}

/// Walks the segment between the centres of `a` and `b` over `grid`, visiting exactly the
/// cells of [`for_each_segment_cell`] in the same order, and stops at the first blocked
/// cell. Cells outside the grid count as blocked.
///
/// The fast form of `for_each_segment_cell(a, b, |c| grid.is_free(c))` for line-of-sight
/// checks (Theta\*): when both ends are in the grid, every cell of the walk lies in their
/// bounding box, so it steps a flat index with an incremental decision variable and needs
/// no bounds test. Tested against the generic walk cell for cell.
pub fn walk_segment(grid: &Grid, a: Cell, b: Cell) -> SegmentWalk {
    if !grid.contains(a) || !grid.contains(b) {
        let mut n_cells = 0;
        let free = for_each_segment_cell(a, b, |cell| {
            n_cells += 1;
            grid.is_free(cell)
        });
        return SegmentWalk { free, n_cells };
    }
    let free = grid.free_cells();
    let nx = i64::from(a.x.abs_diff(b.x));
    let ny = i64::from(a.y.abs_diff(b.y));
    let width = grid.width() as isize;
    let step_x: isize = if b.x >= a.x { 1 } else { -1 };
    let step_y: isize = if b.y >= a.y { width } else { -width };
    let mut index = grid.index(a);
    let blocked = |n_cells: u64| SegmentWalk {
        free: false,
        n_cells,
    };
    let mut n_cells = 1;
    if !free[index] {
        return blocked(n_cells);
    }
    // for_each_segment_cell's decision (1 + 2 ix) ny - (1 + 2 iy) nx, kept up to date.
    let mut decision = ny - nx;
    let (mut ix, mut iy) = (0i64, 0i64);
    while ix < nx || iy < ny {
        if decision == 0 {
            // Through a vertex: both side cells, then the diagonal one.
            n_cells += 2;
            if !free[index.wrapping_add_signed(step_x)] {
                return blocked(n_cells - 1);
            }
            if !free[index.wrapping_add_signed(step_y)] {
                return blocked(n_cells);
            }
            index = index.wrapping_add_signed(step_x + step_y);
            ix += 1;
            iy += 1;
            decision += 2 * (ny - nx);
        } else if decision < 0 {
            index = index.wrapping_add_signed(step_x);
            ix += 1;
            decision += 2 * ny;
        } else {
            index = index.wrapping_add_signed(step_y);
            iy += 1;
            decision -= 2 * nx;
        }
        n_cells += 1;
        if !free[index] {
            return blocked(n_cells);
        }
    }
    SegmentWalk {
        free: true,
        n_cells,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn offsets(set: &MoveSet) -> Vec<(i32, i32)> {
        set.moves().iter().map(|m| (m.dx, m.dy)).collect()
    }

    #[test]
    fn direction_counts_match_table_1() {
        for c in Connectivity::ALL {
            let set = MoveSet::standard(c);
            assert_eq!(set.moves().len() as u32, c.n_directions(), "{c}");
            let mut unique = offsets(&set);
            unique.sort();
            unique.dedup();
            assert_eq!(unique.len(), set.moves().len(), "{c} repeats a move");
        }
    }

    #[test]
    fn algorithm_2_agrees_for_k_up_to_3() {
        // Algorithm 2 of seed 002, transcribed literally (1-based matrix indices).
        #[allow(clippy::needless_range_loop)]
        fn algorithm_2(k: usize) -> Vec<(i32, i32)> {
            let n = 2 * k + 1;
            let mut check = vec![vec![1u8; n + 1]; n + 1];
            let dummy = 2 * k + 2;
            let mid = k + 1;
            for i in 1..k {
                for (r, c) in [
                    (i, i),
                    (dummy - i, i),
                    (i, dummy - i),
                    (dummy - i, dummy - i),
                    (mid, i),
                    (mid, dummy - i),
                    (i, mid),
                    (dummy - i, mid),
                ] {
                    check[r][c] = 0;
                }
            }
            check[mid][mid] = 0;
            let mut out = Vec::new();
            for r in 1..=n {
                for c in 1..=n {
                    if check[r][c] == 1 {
                        out.push((c as i32 - mid as i32, r as i32 - mid as i32));
                    }
                }
            }
            out.sort();
            out
        }
        for k in 1..=3u32 {
            let mut ours = offsets(&MoveSet::standard(
                Connectivity::from_connecting_distance(k).unwrap(),
            ));
            ours.sort();
            assert_eq!(ours, algorithm_2(k as usize), "k = {k}");
        }
        // At k = 4 Algorithm 2 gives 56 cells; Table 1 and we give 48 directions.
        assert_eq!(algorithm_2(4).len(), 56);
    }

    #[test]
    fn default_order_is_the_papers() {
        let four = MoveSet::standard(Connectivity::Four);
        assert_eq!(offsets(&four), vec![(1, 0), (-1, 0), (0, 1), (0, -1)]);
        assert!(four
            .moves()
            .iter()
            .all(|m| m.cost == 1.0 && m.via.is_empty()));
        let eight = MoveSet::standard(Connectivity::Eight);
        assert_eq!(offsets(&eight)[4..], [(1, 1), (-1, 1), (1, -1), (-1, -1)]);
        assert_eq!(eight.moves()[4].via, vec![(1, 0), (0, 1)]);
        assert!((eight.moves()[4].cost - 2f64.sqrt()).abs() < 1e-15);
    }

    #[test]
    fn custom_orders() {
        let order: NeighborOrder = "U, D, L, R".parse().unwrap();
        let set = MoveSet::new(Connectivity::Four, false, &order).unwrap();
        assert_eq!(offsets(&set), vec![(0, -1), (0, 1), (-1, 0), (1, 0)]);
        let bad = |text: &str, c| MoveSet::new(c, false, &text.parse().unwrap()).unwrap_err();
        assert_eq!(
            bad("R L D", Connectivity::Four),
            MoveOrderError::Incomplete(Connectivity::Four)
        );
        assert_eq!(
            bad("R L D D", Connectivity::Four),
            MoveOrderError::Repeated("D")
        );
        assert!(matches!(
            bad("R L D U DR", Connectivity::Four),
            MoveOrderError::DiagonalInFour(_)
        ));
        assert_eq!(
            "R X".parse::<NeighborOrder>(),
            Err(MoveOrderError::UnknownToken("X".into()))
        );
        assert_eq!(
            MoveSet::new(Connectivity::Sixteen, true, &NeighborOrder::default()).unwrap_err(),
            MoveOrderError::CornerCutting(Connectivity::Sixteen)
        );
    }

    #[test]
    fn indexed_moves_agree_with_apply() {
        let grid = Grid::from_ascii(
            "
            ..#....
            .#...#.
            ...#...
            #......
            ..##.#.
            ",
        )
        .unwrap();
        for c in Connectivity::ALL {
            let set = MoveSet::standard(c);
            let indexed = IndexedMoves::new(&set, &grid);
            assert!(indexed.fits(&grid));
            for cell in grid.cells() {
                let index = grid.index(cell);
                for (k, mv) in set.moves().iter().enumerate() {
                    let expected = set.apply(&grid, cell, mv).map(|t| grid.index(t));
                    let found = indexed.target(grid.free_cells(), cell.x, cell.y, index, k);
                    assert_eq!(found, expected, "{c} from {cell} by ({}, {})", mv.dx, mv.dy);
                }
            }
        }
    }

    fn traverse(a: (u32, u32), b: (u32, u32)) -> Vec<(u32, u32)> {
        let mut cells = Vec::new();
        for_each_segment_cell(a.into(), b.into(), |c| {
            cells.push((c.x, c.y));
            true
        });
        cells
    }

    #[test]
    fn traversal_by_hand() {
        // (0,0) to (2,1): the segment from (0.5,0.5) to (2.5,1.5) crosses x = 1 at y = 0.75,
        // y = 1 at x = 1.5, and x = 2 at y = 1.25.
        assert_eq!(
            traverse((0, 0), (2, 1)),
            vec![(0, 0), (1, 0), (1, 1), (2, 1)]
        );
        // Reversed, the same cells in reverse order.
        assert_eq!(
            traverse((2, 1), (0, 0)),
            vec![(2, 1), (1, 1), (1, 0), (0, 0)]
        );
        // A diagonal passes through vertices and touches both side cells.
        assert_eq!(
            traverse((0, 0), (2, 2)),
            vec![(0, 0), (1, 0), (0, 1), (1, 1), (2, 1), (1, 2), (2, 2)]
        );
        assert_eq!(
            traverse((3, 1), (3, 4)),
            vec![(3, 1), (3, 2), (3, 3), (3, 4)]
        );
        assert_eq!(traverse((5, 5), (5, 5)), vec![(5, 5)]);
        // (0,0) to (3,1): y = 0.5 + (x - 0.5) / 3 reaches the line y = 1 at x = 2, a vertex,
        // so both side cells (2,0) and (1,1) are touched.
        assert_eq!(
            traverse((0, 0), (3, 1)),
            vec![(0, 0), (1, 0), (2, 0), (1, 1), (2, 1), (3, 1)]
        );
    }

    #[test]
    fn traversal_matches_dense_sampling_away_from_vertices() {
        // Independent check: sample the segment finely; every sampled cell must be visited,
        // and every visited cell must be within a hair of the segment.
        for (a, b) in [
            ((0, 0), (7, 3)),
            ((9, 2), (1, 5)),
            ((4, 8), (6, 0)),
            ((0, 5), (9, 4)),
        ] {
            let visited = traverse(a, b);
            let (ax, ay) = (a.0 as f64 + 0.5, a.1 as f64 + 0.5);
            let (bx, by) = (b.0 as f64 + 0.5, b.1 as f64 + 0.5);
            for i in 0..=100_000 {
                let t = i as f64 / 100_000.0;
                let (x, y) = (ax + t * (bx - ax), ay + t * (by - ay));
                let cell = (x.floor() as u32, y.floor() as u32);
                assert!(visited.contains(&cell), "{a:?}->{b:?} misses {cell:?}");
            }
            assert_eq!(visited.first(), Some(&a));
            assert_eq!(visited.last(), Some(&b));
        }
    }

    #[test]
    fn walk_segment_agrees_with_the_generic_traversal() {
        // Seeded xorshift grids; segments between any two cells, some outside the grid.
        let mut next = crate::test_rng::xorshift(0x9e37_79b9_7f4a_7c15);
        let mut n_blocked = 0;
        for round in 0..300 {
            let (w, h) = (1 + (next() % 12) as u32, 1 + (next() % 12) as u32);
            let density = next() % 50;
            let free = (0..w * h).map(|_| next() % 100 >= density).collect();
            let grid = Grid::from_free_cells(w, h, free).unwrap();
            for _ in 0..40 {
                let mut cell = || {
                    Cell::new(
                        (next() % u64::from(w + 2)) as u32,
                        (next() % u64::from(h + 2)) as u32,
                    )
                };
                let (a, b) = (cell(), cell());
                let mut n_cells = 0;
                let free = for_each_segment_cell(a, b, |c| {
                    n_cells += 1;
                    grid.is_free(c)
                });
                let walk = walk_segment(&grid, a, b);
                assert_eq!(
                    walk,
                    SegmentWalk { free, n_cells },
                    "round {round}: {a} -> {b}"
                );
                assert_eq!(segment_is_free(&grid, a, b), free);
                n_blocked += usize::from(!free);
            }
        }
        assert!(n_blocked > 1000 && n_blocked < 11_000, "{n_blocked}");
    }

    #[test]
    fn segment_freedom() {
        let grid = Grid::from_ascii(
            "
            ....
            .#..
            ....
            ",
        )
        .unwrap();
        assert!(!segment_is_free(&grid, Cell::new(0, 0), Cell::new(2, 2)));
        assert!(segment_is_free(&grid, Cell::new(0, 2), Cell::new(3, 2)));
        assert!(!segment_is_free(&grid, Cell::new(0, 0), Cell::new(2, 1)));
        assert!(segment_is_free(&grid, Cell::new(2, 0), Cell::new(3, 2)));
        let eight = MoveSet::standard(Connectivity::Eight);
        let down_right = &eight.moves()[4];
        assert_eq!(eight.apply(&grid, Cell::new(0, 0), down_right), None);
        assert_eq!(
            eight.apply(&grid, Cell::new(2, 0), down_right),
            Some(Cell::new(3, 1))
        );
        // Up-right from (0, 1) passes the corner between free (1, 0) and blocked (1, 1).
        let up_right = &eight.moves()[6];
        assert_eq!((up_right.dx, up_right.dy), (1, -1));
        assert_eq!(eight.apply(&grid, Cell::new(0, 1), up_right), None);
        let cutting = MoveSet::new(Connectivity::Eight, true, &NeighborOrder::default()).unwrap();
        assert_eq!(
            cutting.apply(&grid, Cell::new(0, 1), &cutting.moves()[6]),
            Some(Cell::new(1, 0))
        );
        assert_eq!(
            cutting.apply(&grid, Cell::new(0, 0), &cutting.moves()[4]),
            None
        );
    }
}
