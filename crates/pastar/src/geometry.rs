//! Obstacle size (seed 002, Algorithm 1): the largest distance between two of an
//! obstacle's cells, by convex hull and rotating calipers instead of the double loop.
//!
//! Cells are points at their centres, with integer coordinates `(x, y)`; all arithmetic
//! up to the final square root is exact in `i64`.
//!
//! The farthest pair of a point set is a pair of its convex hull's vertices, and the hull
//! of a set of grid cells is the hull of each row's leftmost and rightmost cell. So
//! [`diameter_squared`] keeps at most two cells per row (`O(n)` after sorting by row),
//! builds the hull with Andrew's monotone chain (`O(h log h)`), and walks it with rotating
//! calipers (`O(h)`), where Algorithm 1 compares all `n^2` pairs
//! ([`diameter_squared_naive`], kept for the tests).

/// A point with integer coordinates: a cell centre.
pub type Point = (i64, i64);

fn cross(o: Point, a: Point, b: Point) -> i64 {
    (a.0 - o.0) * (b.1 - o.1) - (a.1 - o.1) * (b.0 - o.0)
}

fn dist2(a: Point, b: Point) -> i64 {
    (a.0 - b.0).pow(2) + (a.1 - b.1).pow(2)
}

/// The squared largest distance between two of `points`, by the double loop of
/// Algorithm 1 (`O(n^2)`); 0 for fewer than two points.
pub fn diameter_squared_naive(points: &[Point]) -> i64 {
    let mut best = 0;
    for (i, &a) in points.iter().enumerate() {
        for &b in &points[i + 1..] {
            best = best.max(dist2(a, b));
        }
    }
    best
}

/// The convex hull of `points` in counter-clockwise order (in a y-up frame), without
/// collinear vertices; a single point or two points when the set is that degenerate.
///
/// `points` is sorted and deduplicated in place. Empty input gives an empty hull.
pub fn convex_hull(points: &mut Vec<Point>, hull: &mut Vec<Point>) {
    points.sort_unstable();
    points.dedup();
    hull.clear();
    if points.len() <= 2 {
        hull.extend_from_slice(points);
        return;
    }
    // Andrew's monotone chain: the lower hull left to right, then the upper right to left.
    for &p in points.iter() {
        while hull.len() >= 2 && cross(hull[hull.len() - 2], hull[hull.len() - 1], p) <= 0 {
            hull.pop();
        }
        hull.push(p);
    }
    let lower = hull.len() + 1;
    for &p in points.iter().rev().skip(1) {
        while hull.len() >= lower && cross(hull[hull.len() - 2], hull[hull.len() - 1], p) <= 0 {
            hull.pop();
        }
        hull.push(p);
    }
    hull.pop(); // The first point again. Collinear sets end as their two ends.
}

/// The squared diameter of a convex polygon given counter-clockwise without collinear
/// vertices (as [`convex_hull`] returns it), by rotating calipers.
pub fn hull_diameter_squared(hull: &[Point]) -> i64 {
    let n = hull.len();
    match n {
        0 | 1 => return 0,
        2 => return dist2(hull[0], hull[1]),
        _ => {}
    }
    let mut best = 0;
    let mut j = 1;
    for i in 0..n {
        let next = (i + 1) % n;
        // Advance the antipodal vertex while it gets farther from edge (i, next).
        while cross(hull[i], hull[next], hull[(j + 1) % n]) > cross(hull[i], hull[next], hull[j]) {
            j = (j + 1) % n;
        }
        best = best
            .max(dist2(hull[i], hull[j]))
            .max(dist2(hull[next], hull[j]));
    }
    best
}

/// The squared largest distance between two cells of `cells` (Algorithm 1's `Max`,
/// squared), by row extremes, convex hull and rotating calipers.
///
/// `scratch` and `hull` are reusable buffers. The row extremes are found in one pass over
/// the cells into a slot per row of their span (`O(n + rows)`; an 8-connected obstacle has
/// a cell in every row of its span, so there are at most `n` rows), where sorting the
/// cells by row took `O(n log n)`: without the sort PA-star's median fell by 8-9 % on seed
/// 002's 200 x 200 maps and 15-22 % on its 500 x 500 ones (`cargo bench -p planner-capso
/// --bench seed002`, 2026-12-06).
pub fn diameter_squared(cells: &[Point], scratch: &mut Vec<Point>, hull: &mut Vec<Point>) -> i64 {
    let Some(&(_, first_row)) = cells.first() else {
        return 0;
    };
    let (low, high) = cells
        .iter()
        .fold((first_row, first_row), |(low, high), &(_, y)| {
            (low.min(y), high.max(y))
        });
    // Each row's leftmost and rightmost column, in `hull` until the hull is built; a row
    // without cells keeps (MAX, MIN). Points spread over more rows than there are points
    // (not an obstacle's cells) are sorted instead, so memory follows the input.
    let rows = usize::try_from(high - low).map_or(usize::MAX, |span| span.saturating_add(1));
    if rows > cells.len() {
        scratch.clear();
        scratch.extend_from_slice(cells);
        scratch.sort_unstable_by_key(|&(x, y)| (y, x));
        // Each row's first and last point, compacted in place (a row gives at most two
        // and takes at least one, so the write index never passes the read index).
        let (mut write, mut i) = (0, 0);
        while i < scratch.len() {
            let row = scratch[i].1;
            let mut j = i;
            while j + 1 < scratch.len() && scratch[j + 1].1 == row {
                j += 1;
            }
            let (left, right) = (scratch[i], scratch[j]);
            scratch[write] = left;
            write += 1;
            if j > i {
                scratch[write] = right;
                write += 1;
            }
            i = j + 1;
        }
        scratch.truncate(write);
        convex_hull(scratch, hull);
        return hull_diameter_squared(hull);
    }
    hull.clear();
    hull.resize(rows, (i64::MAX, i64::MIN));
    for &(x, y) in cells {
        let slot = &mut hull[(y - low) as usize];
        *slot = (slot.0.min(x), slot.1.max(x));
    }
    scratch.clear();
    for (row, &(left, right)) in (low..).zip(hull.iter()) {
        if left <= right {
            scratch.push((left, row));
            if right > left {
                scratch.push((right, row));
            }
        }
    }
    convex_hull(scratch, hull);
    hull_diameter_squared(hull)
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{Rng, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    fn fast(points: &[Point]) -> i64 {
        diameter_squared(points, &mut Vec::new(), &mut Vec::new())
    }

    #[test]
    fn by_hand() {
        // A 4 x 3 rectangle of cells: the diagonal between centres (0,0) and (3,2) is 13.
        let rect: Vec<Point> = (0..3).flat_map(|y| (0..4).map(move |x| (x, y))).collect();
        assert_eq!(fast(&rect), 13);
        assert_eq!(diameter_squared_naive(&rect), 13);
        // One cell: 0. Two cells: their distance. A line: its ends.
        assert_eq!(fast(&[(5, 5)]), 0);
        assert_eq!(fast(&[(1, 1), (4, 5)]), 25);
        assert_eq!(fast(&[(0, 0), (1, 1), (2, 2), (3, 3)]), 18);
        assert_eq!(fast(&[(0, 7), (0, 2), (0, 4)]), 25);
        // Points over more rows than points (the sorting path), one of them twice, and
        // far apart: the slots per row would be a million.
        let sparse = [(3, 1_000_000), (0, 0), (7, 0), (3, 1_000_000)];
        assert_eq!(fast(&sparse), 16 + 1_000_000i64.pow(2));
        assert_eq!(diameter_squared_naive(&sparse), 16 + 1_000_000i64.pow(2));
        // An L shape: (0,0)..(0,4) and (0,4)..(3,4); farthest (0,0)-(3,4) = 25.
        let l: Vec<Point> = (0..5)
            .map(|y| (0, y))
            .chain((1..4).map(|x| (x, 4)))
            .collect();
        assert_eq!(fast(&l), 25);
    }

    #[test]
    fn agrees_with_algorithm_1_on_random_obstacles() {
        let mut rng = ChaCha8Rng::seed_from_u64(2);
        for trial in 0..500 {
            let n = rng.gen_range(1..80);
            let spread = rng.gen_range(1..40);
            let points: Vec<Point> = (0..n)
                .map(|_| (rng.gen_range(0..spread), rng.gen_range(0..spread)))
                .collect();
            assert_eq!(
                fast(&points),
                diameter_squared_naive(&points),
                "trial {trial}: {points:?}"
            );
        }
    }

    #[test]
    fn agrees_on_random_blobs() {
        // Random connected blobs grown cell by cell, like real obstacles.
        let mut rng = ChaCha8Rng::seed_from_u64(7);
        for _ in 0..200 {
            let mut cells: Vec<Point> = vec![(0, 0)];
            let target = rng.gen_range(2..200);
            while cells.len() < target {
                let (x, y) = cells[rng.gen_range(0..cells.len())];
                let next = match rng.gen_range(0..4) {
                    0 => (x + 1, y),
                    1 => (x - 1, y),
                    2 => (x, y + 1),
                    _ => (x, y - 1),
                };
                if !cells.contains(&next) {
                    cells.push(next);
                }
            }
            assert_eq!(fast(&cells), diameter_squared_naive(&cells));
        }
    }
}
