//! Exact quantiles of many multisets of numbers in memory bounded by the number of
//! multisets, not by their sizes: radix selection over repeated passes over the values.
//!
//! The caller numbers its multisets (a report's groups: label x map x bucket, and a
//! quantity such as `n_expanded` or the search time), knows each one's size (from a first
//! pass that counted them) and asks for type 7 quantiles ([`crate::median_iqr`]'s rule:
//! linear interpolation between the order statistics `floor(h)` and `ceil(h)`, `h = (n - 1)
//! p`). [`quantiles`] then calls the caller's pass function as often as it needs, each time
//! receiving every value again as `(set, value)`. Each wanted order statistic keeps a
//! 256-entry histogram of the next 8 bits of the values' keys (their `f64::total_cmp` order
//! as a `u64`) among the values that share the bits fixed so far, and fixes 8 more bits per
//! pass; once at most [`COLLECT`] values share its prefix, the next pass collects them and
//! sorts. A set of at most [`COLLECT`] values is collected in the first pass. At most 9
//! passes, usually 2 to 4; memory is about 6 KiB per wanted order statistic, whatever the
//! number of values.
//!
//! ```
//! use planner_report::exact::quantiles;
//! use planner_report::median_iqr;
//!
//! // Two sets: 0..10_000 (shuffled) and {7}.
//! let values: Vec<f64> = (0..10_000).map(|i| f64::from((i * 7919) % 10_000)).collect();
//! let got = quantiles(&[10_000, 1], &[&[0.5, 0.25, 0.75], &[0.5]], &mut |emit| {
//!     for &v in &values {
//!         emit(0, v);
//!     }
//!     emit(1, 7.0);
//!     Ok(())
//! })
//! .unwrap();
//! let (m, q1, q3) = median_iqr(&values).unwrap();
//! assert_eq!(got, vec![vec![m, q1, q3], vec![7.0]]);
//! ```

use planner_runner::RunnerError;

/// A prefix shared by at most this many values is collected and sorted in the next pass.
pub const COLLECT: u64 = 512;

/// The `f64::total_cmp` order of `value` as an unsigned integer.
fn key(value: f64) -> u64 {
    let bits = value.to_bits();
    if bits >> 63 == 1 {
        !bits
    } else {
        bits | 1 << 63
    }
}

/// The value of `key` ([`key`]'s inverse).
fn value(key: u64) -> f64 {
    if key >> 63 == 1 {
        f64::from_bits(key & !(1 << 63))
    } else {
        f64::from_bits(!key)
    }
}

/// One wanted order statistic: rank `rank` (0-based) of its set.
struct Target {
    /// The rank among the values that share `prefix` (the ranks below it subtracted).
    rank: u64,
    /// The key bits fixed so far (the top `bits` bits).
    prefix: u64,
    bits: u32,
    counts: Vec<u64>,
    /// `Some` while collecting the values that share the prefix.
    collected: Option<Vec<u64>>,
    answer: Option<u64>,
}

impl Target {
    fn matches(&self, key: u64) -> bool {
        self.bits == 0 || key >> (64 - self.bits) == self.prefix >> (64 - self.bits)
    }

    fn feed(&mut self, key: u64) {
        if self.answer.is_some() || !self.matches(key) {
            return;
        }
        match &mut self.collected {
            Some(values) => values.push(key),
            None => self.counts[((key >> (56 - self.bits)) & 0xff) as usize] += 1,
        }
    }

    /// Ends a pass: fixes 8 more bits or, after collecting, the answer.
    fn end_pass(&mut self, set: usize) -> Result<(), RunnerError> {
        if self.answer.is_some() {
            return Ok(());
        }
        if let Some(mut values) = self.collected.take() {
            values.sort_unstable();
            let Some(&k) = values.get(self.rank as usize) else {
                return Err(changed(set));
            };
            self.answer = Some(k);
            return Ok(());
        }
        let mut below = 0u64;
        let mut digit = None;
        for (d, &c) in self.counts.iter().enumerate() {
            if self.rank < below + c {
                digit = Some((d as u64, c));
                break;
            }
            below += c;
        }
        let Some((d, c)) = digit else {
            return Err(changed(set));
        };
        self.rank -= below;
        self.prefix |= d << (56 - self.bits);
        self.bits += 8;
        self.counts.iter_mut().for_each(|c| *c = 0);
        if self.bits == 64 {
            self.answer = Some(self.prefix);
        } else if c <= COLLECT {
            self.collected = Some(Vec::with_capacity(c as usize));
        }
        Ok(())
    }
}

/// What a pass of [`quantiles`] calls with each value: `(set, value)`.
pub type Emit<'a> = &'a mut dyn FnMut(usize, f64);

fn changed(set: usize) -> RunnerError {
    planner_runner::readback::ResultsError::QuantilesChanged { set }.into()
}

/// The type 7 quantiles `probabilities[s]` of each set `s` of `sizes[s]` values, exact:
/// `pass` is called once per pass and must emit every value of every set, `(set,
/// value)`, the same values at every pass (in any order). A set of size 0 gets no
/// quantiles (an empty list). NaN values order by `f64::total_cmp`.
pub fn quantiles(
    sizes: &[u64],
    probabilities: &[&[f64]],
    pass: &mut dyn FnMut(Emit<'_>) -> Result<(), RunnerError>,
) -> Result<Vec<Vec<f64>>, RunnerError> {
    // Per set: its targets (rank, index into `targets`), ranks deduplicated.
    let mut targets: Vec<Target> = Vec::new();
    let mut by_set: Vec<Vec<(u64, usize)>> = vec![Vec::new(); sizes.len()];
    for (s, (&n, ps)) in sizes.iter().zip(probabilities).enumerate() {
        if n == 0 {
            continue;
        }
        for &p in *ps {
            let h = (n - 1) as f64 * p;
            for rank in [h.floor() as u64, h.ceil() as u64] {
                if by_set[s].iter().any(|&(r, _)| r == rank) {
                    continue;
                }
                by_set[s].push((rank, targets.len()));
                targets.push(Target {
                    rank,
                    prefix: 0,
                    bits: 0,
                    counts: if n <= COLLECT {
                        Vec::new()
                    } else {
                        vec![0; 256]
                    },
                    collected: (n <= COLLECT).then(|| Vec::with_capacity(n as usize)),
                    answer: None,
                });
            }
        }
    }
    let mut emitted = vec![0u64; sizes.len()];
    while targets.iter().any(|t| t.answer.is_none()) {
        emitted.iter_mut().for_each(|n| *n = 0);
        let mut bad = None;
        pass(&mut |set, v| {
            let Some(wanted) = by_set.get(set) else {
                bad = Some(set);
                return;
            };
            emitted[set] += 1;
            let k = key(v);
            for &(_, t) in wanted {
                targets[t].feed(k);
            }
        })?;
        if let Some(set) = bad {
            return Err(changed(set));
        }
        if let Some(set) = (0..sizes.len()).find(|&s| emitted[s] != sizes[s]) {
            return Err(changed(set));
        }
        for (s, wanted) in by_set.iter().enumerate() {
            for &(_, t) in wanted {
                targets[t].end_pass(s)?;
            }
        }
    }
    Ok(sizes
        .iter()
        .zip(probabilities)
        .enumerate()
        .map(|(s, (&n, ps))| {
            if n == 0 {
                return Vec::new();
            }
            let at = |rank: u64| {
                by_set[s]
                    .iter()
                    .find(|&&(r, _)| r == rank)
                    .and_then(|&(_, t)| targets[t].answer)
                    .map_or(f64::NAN, value)
            };
            ps.iter()
                .map(|&p| {
                    // The arithmetic of `median_iqr`, so that the results are equal bit for bit.
                    let h = (n - 1) as f64 * p;
                    let lo = h.floor();
                    let (a, b) = (at(lo as u64), at(h.ceil() as u64));
                    a + (h - lo) * (b - a)
                })
                .collect()
        })
        .collect())
}

#[cfg(test)]
mod tests {
    use super::{key, quantiles, value};
    use crate::median_iqr;

    #[test]
    fn keys_order_as_total_cmp_and_invert() {
        let values = [-1e300, -2.5, -0.0, 0.0, 1e-300, 3.0, f64::INFINITY];
        for w in values.windows(2) {
            assert!(key(w[0]) < key(w[1]), "{w:?}");
        }
        for v in values {
            assert_eq!(value(key(v)).to_bits(), v.to_bits());
        }
    }

    /// Sets larger than `COLLECT`, with ties and negative values, equal the sort.
    #[test]
    fn large_sets_with_ties_equal_the_sort() {
        let a: Vec<f64> = (0..100_003u64)
            .map(|i| ((i * 2_654_435_761) % 1_000) as f64 * 0.37 - 50.0)
            .collect();
        let b: Vec<f64> = (0..5_000u64).map(|i| (i % 3) as f64).collect();
        let c: Vec<f64> = (0..2_000u64)
            .map(|i| f64::from_bits(0x3ff0_0000_0000_0000 + i * 977))
            .collect();
        let sets = [&a, &b, &c];
        let ps: &[f64] = &[0.5, 0.25, 0.75, 0.1];
        let got = quantiles(
            &[a.len() as u64, b.len() as u64, c.len() as u64],
            &[ps, ps, ps],
            &mut |emit| {
                for (s, values) in sets.iter().enumerate() {
                    for &v in values.iter() {
                        emit(s, v);
                    }
                }
                Ok(())
            },
        )
        .unwrap();
        for (s, values) in sets.iter().enumerate() {
            let (m, q1, q3) = median_iqr(values).unwrap();
            assert_eq!(&got[s][..3], &[m, q1, q3], "set {s}");
            let mut sorted = values.to_vec();
            sorted.sort_by(f64::total_cmp);
            let h = (sorted.len() - 1) as f64 * 0.1;
            let lo = h.floor() as usize;
            let want = sorted[lo] + (h - lo as f64) * (sorted[h.ceil() as usize] - sorted[lo]);
            assert_eq!(got[s][3], want, "set {s}");
        }
    }

    #[test]
    fn a_pass_that_changes_is_an_error() {
        let mut pass = 0;
        let result = quantiles(&[2_000], &[&[0.5]], &mut |emit| {
            pass += 1;
            for i in 0..2_000 + pass {
                emit(0, f64::from(i));
            }
            Ok(())
        });
        assert!(result.is_err());
        assert!(quantiles(&[0], &[&[0.5]], &mut |_| Ok(())).unwrap()[0].is_empty());
    }
}
