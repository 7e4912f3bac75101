//! Path costs in fixed point, so that equal path costs compare equal.
//!
//! A [`Cost`] is a non-negative number in units of `2^-32` held in a `u64`: sums are
//! integer additions (exact, associative, saturating at [`Cost::MAX`], about 4.29e9),
//! comparisons are integer comparisons. With `f64` costs, two paths of equal cost built
//! from different sums of `sqrt 2` can get `f` values that differ in the last bit, so a
//! tie rule such as "higher `g` first" is decided by rounding noise; with `Cost` they are
//! the same integer.
//!
//! # The representation
//! Every move `(dx, dy)` costs `round(sqrt(dx^2 + dy^2) * 2^32)` units ([`Cost::of_move`],
//! computed with integer arithmetic, so it is the exact nearest integer). Axis moves cost
//! exactly [`Cost::ONE`]; the diagonal costs [`Cost::SQRT_2`] = 6,074,001,000 units, which
//! is `sqrt 2 * 2^32` within `delta = 0.0479007` of a unit. A path with `a` axis moves and
//! `b` diagonals costs `a * ONE + b * SQRT_2` ([`Cost::octile`]) whatever their order, and
//! the octile heuristic is the same expression, so `f = g + h` stays in this form.
//!
//! # Exactness for 4 and 8 directions
//! Unit costs are integers times [`Cost::ONE`]: exact up to [`Cost::MAX`].
//!
//! For 8 directions, let `x = a1 + b1 sqrt 2` and `y = a2 + b2 sqrt 2` (integers
//! `a, b >= 0`) both be at most `C`, and `X`, `Y` their fixed-point values. With
//! `p = a1 - a2`, `q = b1 - b2` and `e = SQRT_2 - sqrt 2 * 2^32` (`|e| <= delta`):
//! `X - Y = 2^32 (p + q sqrt 2) + q e`.
//! - If `x = y` then `p = q = 0` (sqrt 2 is irrational), so `X = Y`: ties are exact for
//!   any values.
//! - Otherwise `p^2 - 2 q^2` is a non-zero integer, so
//!   `|p + q sqrt 2| = |p^2 - 2 q^2| / |p - q sqrt 2| >= 1 / (x + y) >= 1 / (2C)`, using
//!   `|p - q sqrt 2| <= |a1 - b1 sqrt 2| + |a2 - b2 sqrt 2| <= x + y`. And
//!   `|q e| <= (C / sqrt 2) delta`. The sign of `X - Y` is the sign of `x - y` when
//!   `2^32 / (2C) > C delta / sqrt 2`, that is `C^2 < 2^32 / (sqrt 2 delta)`:
//!   **every comparison of values up to [`Cost::EXACT_LIMIT`] = 251,797 is exact.**
//!
//! A* compares `g` and `f` values; with a consistent heuristic they stay below the goal's
//! cost plus two moves, and any path on a `W x H` grid costs at most `sqrt 2 (W H - 1)`, so
//! every 8-connected search on a grid of at most 178,000 cells (about 421 x 421), and every
//! search whose optimal cost is below 251,790 on any grid (the Moving AI maps' optima are
//! in the thousands), orders its nodes exactly. Beyond the limit the error of a value is
//! at most `b delta` units (`b` diagonals), under `1.2e-11` per diagonal move. The tests
//! check every pair with `a, b < 24` against an exact integer comparison, and the closest
//! pairs `p` vs `q sqrt 2` (`p^2 - 2 q^2 = +-1`) up to the limit and one beyond it, which
//! the fixed point gets wrong.
//!
//! # 16, 32 and 48 directions: exact ties, a documented epsilon otherwise
//! Their moves also cost `sqrt 5`, `sqrt 10`, `sqrt 13`, `sqrt 17` (and 5). The square
//! roots of distinct square-free integers are linearly independent over the rationals, so
//! two paths have equal real cost exactly when they use the same number of moves of each
//! length, and then their fixed-point costs are the same sum: **ties are exact**. Unequal
//! costs compare correctly whenever they differ by more than `(n1 + n2) / 2` units, `n`
//! being each path's number of irrational moves (each rounded by at most half a unit):
//! for two 1000-move paths, `2.3e-7`.
//!
//! Heuristics that are not of this form ([`Cost::euclidean`], a weight other than 0 or 1
//! through [`Cost::scaled`]) are rounded to the nearest unit, which can make unequal
//! values tie or misorder only when they lie within a unit or two (`2^-31`) of each other.
//!
//! ```
//! use planner_api::Cost;
//!
//! // Two diagonals then one axis move, or one axis move between the diagonals: equal.
//! let one_way = Cost::SQRT_2 + Cost::SQRT_2 + Cost::ONE;
//! let other_way = Cost::SQRT_2 + Cost::ONE + Cost::SQRT_2;
//! assert_eq!(one_way, other_way);
//! assert_eq!(one_way, Cost::octile(1, 2));
//! // With f64 the same sums differ in the last bit.
//! let s = std::f64::consts::SQRT_2;
//! assert_ne!(s + s + 1.0, s + 1.0 + s);
//! // 99 axis moves against 70 diagonals (98.99495): ordered exactly.
//! assert!(Cost::octile(0, 70) < Cost::octile(99, 0));
//! assert!((Cost::octile(0, 70).to_f64() - 70.0 * s).abs() < 1e-8);
//! ```

use std::fmt;
use std::ops::{Add, AddAssign};

/// A non-negative path cost in units of `2^-32` (see the [module docs](self)).
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Default)]
pub struct Cost(u64);

impl Cost {
    /// Fractional bits: a unit is `2^-32`.
    pub const FRACTION_BITS: u32 = 32;
    /// Zero.
    pub const ZERO: Cost = Cost(0);
    /// One axis move.
    pub const ONE: Cost = Cost(1 << Self::FRACTION_BITS);
    /// One diagonal move: `sqrt 2` rounded to the nearest unit.
    pub const SQRT_2: Cost = Cost(6_074_001_000);
    /// The largest cost; sums saturate here.
    pub const MAX: Cost = Cost(u64::MAX);
    /// Comparisons of 8-connected costs (`a + b sqrt 2`) that are both at most this many
    /// axis moves are exact (see the module docs for the proof).
    pub const EXACT_LIMIT: u64 = 251_797;

    /// A cost of `units` units of `2^-32`.
    pub const fn from_units(units: u64) -> Cost {
        Cost(units)
    }

    /// The number of units of `2^-32`.
    pub const fn units(self) -> u64 {
        self.0
    }

    /// `n` axis moves (saturating).
    pub const fn steps(n: u64) -> Cost {
        Cost(n.saturating_mul(Self::ONE.0))
    }

    /// `straight` axis moves and `diagonal` diagonal moves (saturating): the 8-connected
    /// cost `straight + diagonal * sqrt 2`, and the octile heuristic of offsets `dx`, `dy`
    /// as `octile(max - min, min)`.
    pub const fn octile(straight: u64, diagonal: u64) -> Cost {
        Cost::steps(straight).saturating_add(Cost(diagonal.saturating_mul(Self::SQRT_2.0)))
    }

    /// The octile distance of offsets `dx`, `dy`: `max - min` axis moves and `min`
    /// diagonals.
    #[inline]
    pub fn octile_distance(dx: u32, dy: u32) -> Cost {
        let (low, high) = (dx.min(dy), dx.max(dy));
        Cost::octile(u64::from(high - low), u64::from(low))
    }

    /// `sqrt(dx^2 + dy^2)` rounded to the nearest unit, exactly (integer arithmetic; a
    /// value exactly halfway rounds up). This is the cost of the move `(dx, dy)`.
    pub fn euclidean(dx: u32, dy: u32) -> Cost {
        let n = u128::from(dx) * u128::from(dx) + u128::from(dy) * u128::from(dy);
        // round(sqrt(n) * 2^32) is the m with (2m - 1)^2 <= 4 n 2^64 < (2m + 1)^2, i.e.
        // m = floor((isqrt(n 2^66) + 1) / 2). n < 2^65, so n 2^66 may not fit in u128:
        // beyond, fall back to f64 (no grid has offsets that large: at most 2^31 cells).
        match n.checked_mul(1 << 66) {
            Some(scaled) if n < 1 << 61 => {
                let root = scaled.isqrt();
                Cost(root.div_ceil(2) as u64)
            }
            _ => Cost::from_f64((n as f64).sqrt()),
        }
    }

    /// The cost of the move `(dx, dy)`: [`Cost::euclidean`] of its offsets.
    pub fn of_move(dx: i32, dy: i32) -> Cost {
        Cost::euclidean(dx.unsigned_abs(), dy.unsigned_abs())
    }

    /// `value` rounded to the nearest unit; negative values and NaN give zero, values too
    /// large saturate.
    pub fn from_f64(value: f64) -> Cost {
        // Float-to-integer casts saturate and map NaN to zero.
        Cost((value * Self::ONE.0 as f64).round() as u64)
    }

    /// The value as `f64` (rounded to 53 bits).
    pub fn to_f64(self) -> f64 {
        self.0 as f64 / Self::ONE.0 as f64
    }

    /// `self * weight` rounded to the nearest unit (saturating): exact for weights 0 and
    /// 1. Precondition: `weight` is finite and `>= 0`.
    #[inline]
    pub fn scaled(self, weight: f64) -> Cost {
        if weight == 1.0 {
            self
        } else if weight == 0.0 {
            Cost::ZERO
        } else {
            Cost((self.0 as f64 * weight).round() as u64)
        }
    }

    /// `self * factor`, an exact integer product (saturating at [`Cost::MAX`]): a
    /// heuristic times a grid's smallest cell weight ([`crate::weights`]).
    #[inline]
    pub const fn times(self, factor: u64) -> Cost {
        Cost(self.0.saturating_mul(factor))
    }

    /// `self + other`, saturating at [`Cost::MAX`].
    #[inline]
    pub const fn saturating_add(self, other: Cost) -> Cost {
        Cost(self.0.saturating_add(other.0))
    }

    /// Whether this is a whole number of axis moves.
    pub const fn is_integral(self) -> bool {
        self.0 & (Self::ONE.0 - 1) == 0
    }

    /// The whole part, `floor(self)`.
    #[inline]
    pub const fn whole(self) -> u64 {
        self.0 >> Self::FRACTION_BITS
    }
}

impl Add for Cost {
    type Output = Cost;

    /// Saturating addition.
    #[inline]
    fn add(self, other: Cost) -> Cost {
        self.saturating_add(other)
    }
}

impl AddAssign for Cost {
    #[inline]
    fn add_assign(&mut self, other: Cost) {
        *self = self.saturating_add(other);
    }
}

impl fmt::Display for Cost {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}", self.to_f64())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::cmp::Ordering;

    /// The exact order of `a1 + b1 sqrt 2` and `a2 + b2 sqrt 2`: the sign of
    /// `p + q sqrt 2` (`p = a1 - a2`, `q = b1 - b2`) by comparing `p` with `-q sqrt 2`,
    /// squared when the signs do not decide.
    fn exact_order(a1: u64, b1: u64, a2: u64, b2: u64) -> Ordering {
        let p = i128::from(a1) - i128::from(a2);
        let q = i128::from(b1) - i128::from(b2);
        // Compare p with r = -q sqrt 2.
        match (p.signum(), (-q).signum()) {
            (s, t) if s != t => s.cmp(&t),
            (0, 0) => Ordering::Equal,
            (s, _) => {
                // Same sign: compare magnitudes |p| vs |q| sqrt 2 by squares.
                let by_size = (p * p).cmp(&(2 * q * q));
                if s > 0 {
                    by_size
                } else {
                    by_size.reverse()
                }
            }
        }
    }

    fn check(a1: u64, b1: u64, a2: u64, b2: u64) {
        assert_eq!(
            Cost::octile(a1, b1).cmp(&Cost::octile(a2, b2)),
            exact_order(a1, b1, a2, b2),
            "{a1} + {b1} sqrt 2 vs {a2} + {b2} sqrt 2"
        );
    }

    #[test]
    fn small_octile_costs_compare_exactly() {
        for a1 in 0..24 {
            for b1 in 0..24 {
                for a2 in 0..24 {
                    for b2 in 0..24 {
                        check(a1, b1, a2, b2);
                    }
                }
            }
        }
    }

    #[test]
    fn the_closest_pairs_compare_exactly_up_to_the_limit() {
        // Solutions of p^2 - 2 q^2 = +-1 (the convergents of sqrt 2) are the pairs
        // `p` vs `q sqrt 2` closest to a tie, at distance about 1 / (2p).
        let (mut p, mut q) = (1u64, 1u64);
        let mut n_checked = 0;
        while p <= Cost::EXACT_LIMIT {
            check(p, 0, 0, q);
            // Shifted by common moves, which leave the difference alone.
            let (a, b) = ((Cost::EXACT_LIMIT - p) / 2, (Cost::EXACT_LIMIT - p) / 4);
            check(p + a, b, a, q + b);
            (p, q) = (p + 2 * q, p + q);
            n_checked += 1;
        }
        assert_eq!(n_checked, 14);
        // The next but one convergent, 665857 vs 470832 sqrt 2, is beyond the limit, and
        // there the fixed point misorders: the limit is not far from tight.
        assert_eq!(exact_order(665_857, 0, 0, 470_832), Ordering::Greater);
        assert!(Cost::octile(665_857, 0) < Cost::octile(0, 470_832));
    }

    #[test]
    fn the_limit_follows_from_the_diagonal_rounding() {
        // delta = |SQRT_2 - sqrt 2 * 2^32| < 0.0479007, checked exactly: the squares of
        // SQRT_2 -+ 0.0479007 (in units of 10^-7) bracket 2 * 2^64 * 10^14.
        let target = (2u128 << 64) * 10u128.pow(14);
        let square = |offset: i128| {
            let v = i128::from(Cost::SQRT_2.0) * 10i128.pow(7) + offset;
            (v * v) as u128
        };
        assert!(square(-479_007) < target && target < square(479_007));
        // C^2 < 2^32 / (sqrt 2 delta) for C = EXACT_LIMIT: C^4 * 2 * delta^2 < 2^64, in
        // integers, with delta = 479007 / 10^7.
        let c = u128::from(Cost::EXACT_LIMIT);
        assert!(c.pow(4) * 2 * 479_007u128.pow(2) < (1u128 << 64) * 10u128.pow(14));
    }

    #[test]
    fn move_costs_are_the_nearest_units() {
        for (dx, dy) in [
            (1, 0),
            (1, 1),
            (2, 1),
            (3, 1),
            (3, 2),
            (4, 1),
            (4, 3),
            (0, 0),
        ] {
            let exact = f64::from(dx * dx + dy * dy).sqrt() * 2f64.powi(32);
            let cost = Cost::of_move(dx, -dy);
            assert!(
                (cost.units() as f64 - exact).abs() <= 0.5 + 1e-3,
                "({dx}, {dy})"
            );
        }
        assert_eq!(Cost::of_move(1, 1), Cost::SQRT_2);
        assert_eq!(Cost::of_move(-1, 0), Cost::ONE);
        assert_eq!(Cost::of_move(4, 3), Cost::steps(5));
        assert_eq!(Cost::euclidean(u32::MAX, u32::MAX), Cost::MAX);
        assert_eq!(Cost::euclidean(1 << 30, 0), Cost::steps(1 << 30));
    }

    #[test]
    fn conversions_round_and_saturate() {
        assert_eq!(Cost::from_f64(1.5), Cost::from_units(3 << 31));
        assert_eq!(Cost::from_f64(-2.0), Cost::ZERO);
        assert_eq!(Cost::from_f64(f64::NAN), Cost::ZERO);
        assert_eq!(Cost::from_f64(1e300), Cost::MAX);
        assert_eq!(Cost::MAX + Cost::ONE, Cost::MAX);
        assert_eq!(Cost::steps(3).scaled(1.5), Cost::from_f64(4.5));
        assert_eq!(Cost::SQRT_2.scaled(0.0), Cost::ZERO);
        assert_eq!(Cost::octile_distance(3, 7), Cost::octile(4, 3));
        assert!(Cost::steps(7).is_integral() && !Cost::SQRT_2.is_integral());
        assert_eq!(Cost::steps(7).whole(), 7);
        assert_eq!(Cost::octile(2, 0).to_string(), "2");
    }
}
