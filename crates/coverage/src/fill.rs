//! The filling rules of seed 004 sections 2.1 (spiral) and 2.2 (zigzag), one move at a
//! time, on flat indices. A cell is open when it is inside the grid, free and unvisited;
//! everything else is an obstacle for the rules.

use crate::{Heading, Rotation, Side};

/// The four headings in clockwise order on screen (rows grow downwards): right, down,
/// left, up. Turning clockwise adds 1, counter-clockwise adds 3 (mod 4).
const STEPS: [(i64, i64); 4] = [(1, 0), (0, 1), (-1, 0), (0, -1)];

/// The grid as the rules see it: free flags, visited flags and the size.
pub(crate) struct Field<'a> {
    pub free: &'a [bool],
    pub visited: &'a [bool],
    pub width: usize,
    pub height: usize,
}

impl Field<'_> {
    /// The flat index one step from `index` towards heading `h` (0..4), if inside the grid.
    #[inline]
    pub fn step(&self, index: usize, h: usize) -> Option<usize> {
        let (dx, dy) = STEPS[h];
        let x = (index % self.width) as i64 + dx;
        let y = (index / self.width) as i64 + dy;
        (x >= 0 && y >= 0 && x < self.width as i64 && y < self.height as i64)
            .then(|| y as usize * self.width + x as usize)
    }

    /// Whether the neighbour of `index` towards `h` is open (inside, free, unvisited).
    #[inline]
    pub fn open(&self, index: usize, h: usize) -> bool {
        self.step(index, h)
            .is_some_and(|n| self.free[n] && !self.visited[n])
    }

    /// Whether any 4-neighbour of `index` is open: "not obstacle all around" (rule 1).
    #[inline]
    pub fn any_open(&self, index: usize) -> bool {
        (0..4).any(|h| self.open(index, h))
    }
}

/// Heading index (0 right, 1 down, 2 left, 3 up) of a [`Heading`].
pub(crate) fn heading_index(h: Heading) -> usize {
    match h {
        Heading::Right => 0,
        Heading::Down => 1,
        Heading::Left => 2,
        Heading::Up => 3,
    }
}

/// The spiral rules' sides as turns: `(rls, ols)` added to a heading index.
/// Left of a heading is a counter-clockwise quarter turn (+3), right a clockwise one (+1).
fn turns(side: Side) -> (usize, usize) {
    match side {
        Side::Left => (3, 1),
        Side::Right => (1, 3),
    }
}

/// The heading a spiral phase starts with at `index`: scanning `first`, then turning
/// towards the OLS, the first heading whose front is open and whose RLS is an obstacle
/// (the robot stands along an obstacle, as the rules expect); if none, the first heading
/// whose front is open; `first` itself when nothing is open.
pub(crate) fn spiral_start(field: &Field<'_>, index: usize, side: Side, first: usize) -> usize {
    let (rls, ols) = turns(side);
    let scan = (0..4).map(|k| (first + k * ols) % 4);
    scan.clone()
        .find(|&h| field.open(index, h) && !field.open(index, (h + rls) % 4))
        .or_else(|| scan.clone().find(|&h| field.open(index, h)))
        .unwrap_or(first)
}

/// One spiral move (section 2.1) from `index` with heading `*heading`; updates the heading.
///
/// Rule 1: no open neighbour, the spiral ends (`None`). Rule 2: an open RLS: turn to the
/// RLS and move forward. Rule 3: an obstacle in front: turn to the OLS (and apply the rules
/// again, without moving). Rule 4: move forward.
pub(crate) fn spiral_move(
    field: &Field<'_>,
    index: usize,
    heading: &mut usize,
    side: Side,
) -> Option<usize> {
    if !field.any_open(index) {
        return None; // Rule 1.
    }
    let (rls, ols) = turns(side);
    // Some neighbour is open, so within four turns rule 2 or rule 4 moves: after a turn to
    // the OLS the new RLS is the old front, an obstacle, so only the new front is tested.
    for _ in 0..4 {
        let to_rls = (*heading + rls) % 4;
        if field.open(index, to_rls) {
            *heading = to_rls; // Rule 2.
            return field.step(index, to_rls);
        }
        if !field.open(index, *heading) {
            *heading = (*heading + ols) % 4; // Rule 3.
            continue;
        }
        return field.step(index, *heading); // Rule 4.
    }
    None
}

/// The zigzag order (section 2.2): `first`, then the other headings in `rotation` order on
/// screen. Counter-clockwise from right is right, up, left, down.
pub(crate) fn zigzag_order(rotation: Rotation, first: usize) -> [usize; 4] {
    let turn = match rotation {
        Rotation::CounterClockwise => 3,
        Rotation::Clockwise => 1,
    };
    [
        first,
        (first + turn) % 4,
        (first + 2 * turn) % 4,
        (first + 3 * turn) % 4,
    ]
}

/// One zigzag move (section 2.2): rule 1, no open neighbour ends the zigzag (`None`);
/// rule 2, move to the first open neighbour in `order`.
pub(crate) fn zigzag_move(field: &Field<'_>, index: usize, order: &[usize; 4]) -> Option<usize> {
    order
        .iter()
        .find(|&&h| field.open(index, h))
        .and_then(|&h| field.step(index, h))
}
