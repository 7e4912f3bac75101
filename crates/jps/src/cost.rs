//! Exact octile path costs: a count of straight moves and a count of diagonal moves.
//!
//! A cost `s + d * sqrt 2` is kept as the pair `(s, d)`. Since `sqrt 2` is irrational, two
//! pairs denote the same real number only when they are equal, so equal path costs compare
//! equal, and the order ([`Ord`]) is decided exactly in integers.

use std::cmp::Ordering;
use std::ops::Add;

/// An octile cost `straight + diagonal * sqrt 2`, compared exactly.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Hash)]
pub struct Cost {
    /// Straight (unit) moves.
    pub straight: u32,
    /// Diagonal (`sqrt 2`) moves.
    pub diagonal: u32,
}

impl Cost {
    /// The cost of an unobstructed octile path over offsets `dx`, `dy`: `max - min`
    /// straight moves and `min` diagonal moves. It is also the octile heuristic.
    #[inline]
    pub fn octile(dx: u32, dy: u32) -> Cost {
        let (low, high) = if dx < dy { (dx, dy) } else { (dy, dx) };
        Cost {
            straight: high - low,
            diagonal: low,
        }
    }

    /// The cost as a real number, `straight + diagonal * sqrt 2`, rounded to `f64`.
    #[inline]
    pub fn value(self) -> f64 {
        f64::from(self.straight) + f64::from(self.diagonal) * std::f64::consts::SQRT_2
    }
}

impl Add for Cost {
    type Output = Cost;

    #[inline]
    fn add(self, other: Cost) -> Cost {
        Cost {
            straight: self.straight + other.straight,
            diagonal: self.diagonal + other.diagonal,
        }
    }
}

impl Ord for Cost {
    /// The sign of `ds + dd * sqrt 2` with `ds`, `dd` the differences of the two counts:
    /// decided by the signs alone when they agree, else by comparing `ds^2` with `2 dd^2`.
    fn cmp(&self, other: &Cost) -> Ordering {
        let ds = i128::from(self.straight) - i128::from(other.straight);
        let dd = i128::from(self.diagonal) - i128::from(other.diagonal);
        match (ds.signum(), dd.signum()) {
            (0, 0) => Ordering::Equal,
            (a, b) if a >= 0 && b >= 0 => Ordering::Greater,
            (a, b) if a <= 0 && b <= 0 => Ordering::Less,
            // ds > 0 > dd: positive when ds > |dd| sqrt 2.
            (1, _) => (ds * ds).cmp(&(2 * dd * dd)),
            // dd > 0 > ds: positive when dd sqrt 2 > |ds|.
            _ => (2 * dd * dd).cmp(&(ds * ds)),
        }
    }
}

impl PartialOrd for Cost {
    fn partial_cmp(&self, other: &Cost) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cost(straight: u32, diagonal: u32) -> Cost {
        Cost { straight, diagonal }
    }

    #[test]
    fn order_is_that_of_the_real_values() {
        // 3 < 2 sqrt 2 + ... : every pair with small counts against the f64 values, whose
        // gaps here (at least 0.01) are far above rounding.
        for a in 0..20 {
            for b in 0..20 {
                for c in 0..20 {
                    for d in 0..20 {
                        let (x, y) = (cost(a, b), cost(c, d));
                        let expected = if (a, b) == (c, d) {
                            Ordering::Equal
                        } else {
                            x.value().total_cmp(&y.value())
                        };
                        assert_eq!(x.cmp(&y), expected, "{x:?} vs {y:?}");
                    }
                }
            }
        }
        // 99 and 70 sqrt 2 = 98.9949...: a close call decided exactly.
        assert!(cost(99, 0) > cost(0, 70));
        assert!(cost(0, 70) + cost(1, 0) > cost(99, 0));
        assert_eq!(Cost::octile(5, 2), cost(3, 2));
        assert_eq!(Cost::octile(2, 5), cost(3, 2));
    }
}
