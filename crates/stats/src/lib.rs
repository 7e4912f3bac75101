//! The statistics of seed 002's section 4.4 (Tables 11-14): a Shapiro-Wilk normality
//! check per sample, a Kruskal-Wallis test across planners, and Dunn's post-hoc test of
//! each planner against PA-star.
//!
//! - [`shapiro_wilk`]: W and its p-value by Royston's algorithm (Royston 1995, Applied
//!   Statistics algorithm AS R94, the `swilk` routine R and SciPy use), for 3 to 5000
//!   values: coefficients from normal quantiles with Royston's polynomial corrections,
//!   the exact p for n = 3, and Royston's normalizing transformations of `1 - W` for
//!   4 <= n <= 11 and n >= 12.
//! - [`kruskal_wallis`]: H on mid-ranks, divided by the tie correction
//!   `1 - sum(t^3 - t) / (N^3 - N)`, with the chi-square p-value on `k - 1` degrees of
//!   freedom (Kruskal and Wallis 1952).
//! - [`dunn`]: `z = (mean rank of b - mean rank of a) / sqrt((N (N + 1) / 12 -
//!   sum(t^3 - t) / (12 (N - 1))) (1/n_a + 1/n_b))` on the ranks of all groups together,
//!   and its two-sided p (Dunn 1964); [`bonferroni`] adjusts it.
//! - [`geometric_mean`]: the geometric mean of positive ratios with its confidence interval,
//!   Student's t interval of the mean of their logarithms taken back by `exp` (the usual
//!   summary of per-instance speedups: Fleming and Wallace, "How not to lie with
//!   statistics: the correct way to summarize benchmark results", CACM 1986).
//!
//! # Design
//! The distributions (normal CDF, survival function and quantile; chi-square survival
//! function) come from `statrs`, a maintained crate, so this crate holds only the tests'
//! own formulas. Every statistic is tested against SciPy 1.17.1 and scikit-posthocs 0.17.1
//! (values and sources in the tests) and, where small enough, by hand.
//!
//! Seed 002 reports Dunn's p-values Bonferroni-adjusted over all `k (k - 1) / 2` pairs:
//! its Table 12 pairs `Z = 6.94` with `p = 3.77e-11`, and `2 (1 - Phi(6.94)) * 10 =
//! 3.9e-11` for its five algorithms, where the unadjusted p would be `3.9e-12`.
//!
//! ```
//! use planner_stats::{bonferroni, dunn, kruskal_wallis};
//! // Three groups with ties (worked by hand in the tests).
//! let a = [1.0, 1.0, 2.0, 3.0];
//! let b = [2.0, 3.0, 3.0, 4.0];
//! let c = [4.0, 5.0, 5.0, 5.0];
//! let groups: [&[f64]; 3] = [&a, &b, &c];
//! let kw = kruskal_wallis(&groups).unwrap();
//! assert!((kw.h - 8.53).abs() < 1e-12);
//! assert_eq!(kw.df, 2);
//! let d = dunn(&groups, 0, 2).unwrap();
//! assert!((d.z - 2.9).abs() < 1e-12);
//! assert!((bonferroni(d.p, 3) - 0.011194879802304224).abs() < 1e-10);
//! ```
#![deny(missing_docs)]
#![cfg_attr(not(test), warn(clippy::unwrap_used))]

use statrs::distribution::{ChiSquared, ContinuousCDF, Normal, StudentsT};
use thiserror::Error;

/// Input a test cannot be computed on.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum StatsError {
    /// Shapiro-Wilk needs 3 to 5000 values.
    #[error("shapiro-wilk needs 3 to 5000 values, got {0}")]
    SampleSize(usize),
    /// All values are equal, so the statistic is undefined.
    #[error("all values are equal")]
    Constant,
    /// A value is NaN or infinite.
    #[error("a value is not finite")]
    NotFinite,
    /// Fewer than two groups, or an empty group.
    #[error("need at least two groups, none empty")]
    Groups,
    /// No values.
    #[error("no values")]
    Empty,
    /// A ratio that is not positive.
    #[error("a ratio is not positive")]
    NotPositive,
    /// A confidence level outside (0, 1).
    #[error("a confidence level is in (0, 1), got {0}")]
    Level(f64),
    /// A group index is out of range.
    #[error("group {0} does not exist")]
    NoGroup(usize),
}

/// A Shapiro-Wilk result.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ShapiroWilk {
    /// W, in (0, 1]; near 1 for normal data.
    pub w: f64,
    /// The p-value of normality (small: not normal).
    pub p: f64,
}

/// A Kruskal-Wallis result.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct KruskalWallis {
    /// H, tie-corrected (the "chi-square" of Table 11).
    pub h: f64,
    /// Degrees of freedom, `k - 1`.
    pub df: usize,
    /// The chi-square p-value.
    pub p: f64,
}

/// One pair of Dunn's test.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Dunn {
    /// `(mean rank of b - mean rank of a) / SE`: positive when group b ranks higher.
    pub z: f64,
    /// Two-sided p-value, not adjusted.
    pub p: f64,
}

fn normal() -> Normal {
    match Normal::new(0.0, 1.0) {
        Ok(n) => n,
        Err(e) => unreachable!("the standard normal exists: {e}"),
    }
}

fn poly(c: &[f64], x: f64) -> f64 {
    c.iter().rev().fold(0.0, |acc, &ci| acc * x + ci)
}

/// Shapiro-Wilk's W and p (Royston's AS R94) for `values` (any order).
///
/// Errors when there are fewer than 3 or more than 5000 values, a value is not finite,
/// or all are equal.
pub fn shapiro_wilk(values: &[f64]) -> Result<ShapiroWilk, StatsError> {
    let n = values.len();
    if !(3..=5000).contains(&n) {
        return Err(StatsError::SampleSize(n));
    }
    if values.iter().any(|v| !v.is_finite()) {
        return Err(StatsError::NotFinite);
    }
    let mut x = values.to_vec();
    x.sort_by(f64::total_cmp);
    let range = x[n - 1] - x[0];
    if range <= 0.0 {
        return Err(StatsError::Constant);
    }
    let an = n as f64;
    let half = n / 2;
    // Coefficients a[0..half] for the upper half (the lower half is their negatives).
    let mut a = vec![0.0; half];
    if n == 3 {
        a[0] = std::f64::consts::FRAC_1_SQRT_2;
    } else {
        const C1: [f64; 6] = [0.0, 0.221157, -0.147981, -2.071190, 4.434685, -2.706056];
        const C2: [f64; 6] = [0.0, 0.042981, -0.293762, -1.752461, 5.682633, -3.582633];
        let norm = normal();
        let m: Vec<f64> = (1..=half)
            .map(|i| norm.inverse_cdf((i as f64 - 0.375) / (an + 0.25)))
            .collect();
        let summ2 = 2.0 * m.iter().map(|v| v * v).sum::<f64>();
        let ssumm2 = summ2.sqrt();
        let rsn = 1.0 / an.sqrt();
        let a1 = poly(&C1, rsn) - m[0] / ssumm2;
        let (first, fac) = if n > 5 {
            let a2 = -m[1] / ssumm2 + poly(&C2, rsn);
            let fac = ((summ2 - 2.0 * m[0] * m[0] - 2.0 * m[1] * m[1])
                / (1.0 - 2.0 * a1 * a1 - 2.0 * a2 * a2))
                .sqrt();
            a[1] = a2;
            (2, fac)
        } else {
            let fac = ((summ2 - 2.0 * m[0] * m[0]) / (1.0 - 2.0 * a1 * a1)).sqrt();
            (1, fac)
        };
        a[0] = a1;
        for i in first..half {
            a[i] = -m[i] / fac;
        }
    }
    // W as the squared correlation of the data with the coefficients, on data scaled by
    // the range, computed as 1 - W to keep precision near 1 (as swilk does).
    let coefficient = |i: usize| -> f64 {
        let j = n - 1 - i;
        if i < j {
            -a[i]
        } else if i > j {
            a[j]
        } else {
            0.0
        }
    };
    let mean_a = (0..n).map(coefficient).sum::<f64>() / an;
    let mean_x = x.iter().map(|v| v / range).sum::<f64>() / an;
    let (mut ssa, mut ssx, mut sax) = (0.0, 0.0, 0.0);
    for (i, xi) in x.iter().enumerate() {
        let da = coefficient(i) - mean_a;
        let dx = xi / range - mean_x;
        ssa += da * da;
        ssx += dx * dx;
        sax += da * dx;
    }
    let ssassx = (ssa * ssx).sqrt();
    let w1 = (ssassx - sax) * (ssassx + sax) / (ssa * ssx);
    let w = 1.0 - w1;
    if n == 3 {
        // Exact: p = 6/pi (asin(sqrt W) - pi/3).
        let p = 6.0 / std::f64::consts::PI * (w.sqrt().asin() - std::f64::consts::FRAC_PI_3);
        return Ok(ShapiroWilk { w, p: p.max(0.0) });
    }
    let y = w1.ln();
    let (y, mean, sd) = if n <= 11 {
        let gamma = poly(&[-2.273, 0.459], an);
        if y >= gamma {
            return Ok(ShapiroWilk { w, p: 1e-99 });
        }
        let y = -(gamma - y).ln();
        let mean = poly(&[0.5440, -0.39978, 0.025054, -6.714e-4], an);
        let sd = poly(&[1.3822, -0.77857, 0.062767, -0.0020322], an).exp();
        (y, mean, sd)
    } else {
        let ln_n = an.ln();
        let mean = poly(&[-1.5861, -0.31082, -0.083751, 0.0038915], ln_n);
        let sd = poly(&[-0.4803, -0.082676, 0.0030302], ln_n).exp();
        (y, mean, sd)
    };
    let p = normal().sf((y - mean) / sd);
    Ok(ShapiroWilk { w, p })
}

/// Mid-ranks (1-based; ties share the mean of their ranks) of all values of `groups`
/// pooled, per group, and `sum(t^3 - t)` over the tie groups.
fn pooled_ranks(groups: &[&[f64]]) -> Result<(Vec<Vec<f64>>, f64), StatsError> {
    if groups.len() < 2 || groups.iter().any(|g| g.is_empty()) {
        return Err(StatsError::Groups);
    }
    let mut all: Vec<(f64, usize, usize)> = Vec::new();
    for (g, group) in groups.iter().enumerate() {
        for (i, &v) in group.iter().enumerate() {
            if !v.is_finite() {
                return Err(StatsError::NotFinite);
            }
            all.push((v, g, i));
        }
    }
    all.sort_by(|a, b| a.0.total_cmp(&b.0));
    let mut ranks: Vec<Vec<f64>> = groups.iter().map(|g| vec![0.0; g.len()]).collect();
    let mut ties = 0.0;
    let mut start = 0;
    while start < all.len() {
        let mut end = start + 1;
        while end < all.len() && all[end].0 == all[start].0 {
            end += 1;
        }
        let t = (end - start) as f64;
        let rank = (start + end + 1) as f64 / 2.0; // mean of start+1 ..= end
        for &(_, g, i) in &all[start..end] {
            ranks[g][i] = rank;
        }
        ties += t * t * t - t;
        start = end;
    }
    Ok((ranks, ties))
}

/// The Kruskal-Wallis test of `groups` (two or more, none empty).
///
/// Errors when there are fewer than two groups, a group is empty, a value is not
/// finite, or every value is equal.
pub fn kruskal_wallis(groups: &[&[f64]]) -> Result<KruskalWallis, StatsError> {
    let (ranks, ties) = pooled_ranks(groups)?;
    let n: f64 = groups.iter().map(|g| g.len() as f64).sum();
    let correction = 1.0 - ties / (n * n * n - n);
    if correction <= 0.0 {
        return Err(StatsError::Constant);
    }
    let sum: f64 = ranks
        .iter()
        .map(|r| r.iter().sum::<f64>().powi(2) / r.len() as f64)
        .sum();
    let h = (12.0 / (n * (n + 1.0)) * sum - 3.0 * (n + 1.0)) / correction;
    let df = groups.len() - 1;
    let p = match ChiSquared::new(df as f64) {
        Ok(chi) => chi.sf(h),
        Err(e) => unreachable!("df >= 1 is valid: {e}"),
    };
    Ok(KruskalWallis { h, df, p })
}

/// Dunn's test of group `b` against group `a`, on the ranks of all `groups` together.
///
/// Errors as [`kruskal_wallis`], or when `a` or `b` is not a group.
pub fn dunn(groups: &[&[f64]], a: usize, b: usize) -> Result<Dunn, StatsError> {
    for g in [a, b] {
        if g >= groups.len() {
            return Err(StatsError::NoGroup(g));
        }
    }
    let (ranks, ties) = pooled_ranks(groups)?;
    let n: f64 = groups.iter().map(|g| g.len() as f64).sum();
    let mean = |g: usize| ranks[g].iter().sum::<f64>() / ranks[g].len() as f64;
    let variance = n * (n + 1.0) / 12.0 - ties / (12.0 * (n - 1.0));
    if variance <= 0.0 {
        return Err(StatsError::Constant);
    }
    let se = (variance * (1.0 / ranks[a].len() as f64 + 1.0 / ranks[b].len() as f64)).sqrt();
    let z = (mean(b) - mean(a)) / se;
    let p = (2.0 * normal().sf(z.abs())).min(1.0);
    Ok(Dunn { z, p })
}

/// A geometric mean with its confidence interval ([`geometric_mean`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GeometricMean {
    /// `exp(mean(ln r))`.
    pub mean: f64,
    /// The interval's ends, `exp(mean(ln r) -+ t s / sqrt(n))`; `None` for one value.
    pub interval: Option<(f64, f64)>,
}

/// The geometric mean of `ratios` and its two-sided `level` confidence interval (0.95 for
/// 95 %): with `l = ln r`, `exp(mean(l) -+ t_(1 - (1 - level) / 2, n - 1) s(l) / sqrt(n))`,
/// `s` the sample standard deviation (Student's t interval on the logarithms).
///
/// Errors when `ratios` is empty, or a ratio is not finite and positive, or `level` is not
/// in (0, 1).
///
/// ```
/// use planner_stats::geometric_mean;
/// // ln 1, ln 2, ln 4 = (0, 1, 2) ln 2: mean ln 2, s = ln 2, t(0.975, 2) = 4.302653.
/// let g = geometric_mean(&[1.0, 2.0, 4.0], 0.95).unwrap();
/// assert!((g.mean - 2.0).abs() < 1e-12);
/// let (low, high) = g.interval.unwrap();
/// let half = 4.302652729911275 / 3f64.sqrt();
/// assert!((low - 2f64.powf(1.0 - half)).abs() < 1e-9);
/// assert!((high - 2f64.powf(1.0 + half)).abs() < 1e-9);
/// ```
pub fn geometric_mean(ratios: &[f64], level: f64) -> Result<GeometricMean, StatsError> {
    if ratios.is_empty() {
        return Err(StatsError::Empty);
    }
    if !(level > 0.0 && level < 1.0) {
        return Err(StatsError::Level(level));
    }
    if ratios.iter().any(|r| !r.is_finite()) {
        return Err(StatsError::NotFinite);
    }
    if ratios.iter().any(|r| *r <= 0.0) {
        return Err(StatsError::NotPositive);
    }
    let n = ratios.len() as f64;
    let logs: Vec<f64> = ratios.iter().map(|r| r.ln()).collect();
    let mean = logs.iter().sum::<f64>() / n;
    if ratios.len() == 1 {
        return Ok(GeometricMean {
            mean: mean.exp(),
            interval: None,
        });
    }
    let variance = logs.iter().map(|l| (l - mean).powi(2)).sum::<f64>() / (n - 1.0);
    let t = match StudentsT::new(0.0, 1.0, n - 1.0) {
        Ok(t) => t.inverse_cdf(1.0 - (1.0 - level) / 2.0),
        Err(e) => unreachable!("Student's t exists for n - 1 >= 1 degrees of freedom: {e}"),
    };
    let half = t * (variance / n).sqrt();
    Ok(GeometricMean {
        mean: mean.exp(),
        interval: Some(((mean - half).exp(), (mean + half).exp())),
    })
}

/// `p` adjusted by Bonferroni for `m` comparisons: `min(1, m p)`.
pub fn bonferroni(p: f64, m: usize) -> f64 {
    (p * m as f64).min(1.0)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// (values, W, p): SciPy 1.17.1 `scipy.stats.shapiro(values)`, which runs the same
    /// AS R94 code (swilk.f).
    fn check_shapiro(values: &[f64], w: f64, p: f64) {
        let r = shapiro_wilk(values).unwrap();
        assert!((r.w - w).abs() < 1e-9, "W {} vs {w}", r.w);
        assert!((r.p - p).abs() < 1e-6 * p.max(1e-3), "p {} vs {p}", r.p);
    }

    #[test]
    fn shapiro_wilk_matches_scipy() {
        // n = 3, exact p. By hand: W = 0.9642857 (= 27/28) for 1, 2, 4.
        check_shapiro(&[1.0, 2.0, 4.0], 0.9642857142857142, 0.6368868450289689);
        assert!((shapiro_wilk(&[1.0, 2.0, 4.0]).unwrap().w - 27.0 / 28.0).abs() < 1e-12);
        // n = 7 (the 4..11 branch).
        check_shapiro(
            &[2.1, 3.4, 1.9, 5.6, 4.4, 3.3, 2.8],
            0.9401366781979513,
            0.6399513746153818,
        );
        // n = 11: the weights of eleven men (Shapiro and Wilk 1965's example style data).
        let men = [
            148.0, 154.0, 158.0, 160.0, 161.0, 162.0, 166.0, 170.0, 182.0, 195.0, 236.0,
        ];
        check_shapiro(&men, 0.7888146948631716, 0.006703814061898823);
        // n = 20 and n = 50 (the n >= 12 branch), the latter with repeated values.
        let n20: Vec<f64> = (0..20).map(|i| f64::from((i * 7) % 20).powi(2)).collect();
        check_shapiro(&n20, 0.8949288620307665, 0.03316539297687834);
        let n50: Vec<f64> = (0..50)
            .map(|i| {
                let v = 0.2 + 0.01 * f64::from((i * 37) % 50) + 0.001 * f64::from(i % 7).powi(2);
                (v * 1e4).round() / 1e4
            })
            .collect();
        check_shapiro(&n50, 0.9617165527962243, 0.10490983660000819);
        assert_eq!(shapiro_wilk(&[1.0, 2.0]), Err(StatsError::SampleSize(2)));
        assert_eq!(shapiro_wilk(&[3.0; 5]), Err(StatsError::Constant));
    }

    #[test]
    fn kruskal_wallis_matches_scipy_and_hand() {
        // SciPy's documentation example (Hollander and Wolfe): H = 0.7714, p = 0.6800.
        let x = [2.9, 3.0, 2.5, 2.6, 3.2];
        let y = [3.8, 2.7, 4.0, 2.4];
        let z = [2.8, 3.4, 3.7, 2.2, 2.0];
        let r = kruskal_wallis(&[&x, &y, &z]).unwrap();
        assert!((r.h - 0.7714285714285722).abs() < 1e-12);
        assert!((r.p - 0.6799647735788936).abs() < 1e-10);
        assert_eq!(r.df, 2);
        // With ties, by hand: rank sums 12.5, 24, 41.5 of N = 12; uncorrected
        // H = 613.625 / 13 - 39 = 8.2019; sum(t^3 - t) = 66, correction 1 - 66/1716;
        // H = 8.53. SciPy: 8.530000000000003, p = 0.014051867133046016.
        let a = [1.0, 1.0, 2.0, 3.0];
        let b = [2.0, 3.0, 3.0, 4.0];
        let c = [4.0, 5.0, 5.0, 5.0];
        let r = kruskal_wallis(&[&a, &b, &c]).unwrap();
        assert!((r.h - 8.53).abs() < 1e-12);
        assert!((r.p / 0.014051867133046016 - 1.0).abs() < 1e-9);
        assert_eq!(kruskal_wallis(&[&a]), Err(StatsError::Groups));
        assert_eq!(
            kruskal_wallis(&[&[1.0, 1.0], &[1.0]]),
            Err(StatsError::Constant)
        );
    }

    #[test]
    fn chi_square_tail_matches_table_11() {
        // Seed 002 Table 11 (H rounded to two decimals there, df 4) and SciPy's
        // chi2.sf: 241.19 -> 5.13e-51 (SciPy 5.1425e-51), 239.19 -> 1.38e-50
        // (1.3864e-50), 233.36 -> 2.49e-49 (2.4959e-49), 230.17 -> 1.21e-48 (1.2134e-48).
        let chi = ChiSquared::new(4.0).unwrap();
        for (h, scipy, paper) in [
            (241.19, 5.142480717805487e-51, 5.13e-51),
            (239.19, 1.3863750649146844e-50, 1.38e-50),
            (233.36, 2.495873162728413e-49, 2.49e-49),
            (230.17, 1.2133767133528028e-48, 1.21e-48),
        ] {
            let p = chi.sf(h);
            assert!((p / scipy - 1.0).abs() < 1e-8, "{h}: {p} vs {scipy}");
            assert!(
                (p / paper - 1.0).abs() < 0.01,
                "{h}: {p} vs the paper's {paper}"
            );
        }
    }

    #[test]
    fn dunn_matches_hand_and_scikit_posthocs() {
        // By hand (ties example): SE = sqrt((13 - 66/132) * (1/4 + 1/4)) = 2.5; mean ranks
        // 3.125, 6, 10.375; z = 1.15, 2.9, 1.75. p from scikit-posthocs 0.17.1
        // `posthoc_dunn([a, b, c])` (unadjusted, then p_adjust="bonferroni").
        let a = [1.0, 1.0, 2.0, 3.0];
        let b = [2.0, 3.0, 3.0, 4.0];
        let c = [4.0, 5.0, 5.0, 5.0];
        let groups: [&[f64]; 3] = [&a, &b, &c];
        for (i, j, z, p, p_bonferroni) in [
            (0, 1, 1.15, 0.2501438712743007, 0.7504316138229021),
            (0, 2, 2.9, 0.003731626600768075, 0.011194879802304224),
            (1, 2, 1.75, 0.08011831372763417, 0.24035494118290252),
        ] {
            let d = dunn(&groups, i, j).unwrap();
            assert!((d.z - z).abs() < 1e-12, "{i} {j}: {}", d.z);
            // statrs' and SciPy's normal tails agree to about 1e-10 relative.
            assert!((d.p / p - 1.0).abs() < 1e-9, "{i} {j}: {}", d.p);
            assert!((bonferroni(d.p, 3) / p_bonferroni - 1.0).abs() < 1e-9);
            let back = dunn(&groups, j, i).unwrap();
            assert_eq!((back.z, back.p), (-d.z, d.p));
        }
        // Hollander and Wolfe's data, no ties: scikit-posthocs p = 0.5212453081148148,
        // 0.8205958397554408, 0.3924205244765818 (|z| = 0.6414, 0.2268, 0.8552).
        let x = [2.9, 3.0, 2.5, 2.6, 3.2];
        let y = [3.8, 2.7, 4.0, 2.4];
        let z = [2.8, 3.4, 3.7, 2.2, 2.0];
        let groups: [&[f64]; 3] = [&x, &y, &z];
        for (i, j, p) in [
            (0, 1, 0.5212453081148148),
            (0, 2, 0.8205958397554408),
            (1, 2, 0.3924205244765818),
        ] {
            assert!((dunn(&groups, i, j).unwrap().p / p - 1.0).abs() < 1e-9);
        }
        assert_eq!(dunn(&groups, 0, 3), Err(StatsError::NoGroup(3)));
        // Seed 002 Table 12's first row: Z = 6.94 with five algorithms (10 pairs) gives
        // p = 3.9e-11 Bonferroni-adjusted; the paper prints 3.77e-11 (Z was rounded).
        let p = 2.0 * normal().sf(6.94);
        assert!((bonferroni(p, 10) / 3.9209994210185174e-11 - 1.0).abs() < 1e-6);
    }

    #[test]
    fn geometric_means_and_their_intervals() {
        // Eleven ratios 2^k, k = -5 ..= 5: mean of logs 0, s = ln 2 sqrt(110 / 10), so
        // s / sqrt(11) = ln 2; t(0.975, 10) = 2.2281388519649385 (the tables' 2.228).
        let ratios: Vec<f64> = (-5..=5).map(|k| 2f64.powi(k)).collect();
        let g = geometric_mean(&ratios, 0.95).unwrap();
        assert!((g.mean - 1.0).abs() < 1e-12);
        let half = 2.2281388519649385 * 2f64.ln();
        let (low, high) = g.interval.unwrap();
        assert!((low - (-half).exp()).abs() < 1e-9, "{low}");
        assert!((high - half.exp()).abs() < 1e-9, "{high}");
        // Equal ratios: an interval of no width; one ratio: none.
        let g = geometric_mean(&[0.5, 0.5], 0.95).unwrap();
        assert_eq!(g.interval, Some((0.5, 0.5)));
        assert_eq!(geometric_mean(&[3.0], 0.95).unwrap().interval, None);
        assert_eq!(geometric_mean(&[], 0.95), Err(StatsError::Empty));
        assert_eq!(
            geometric_mean(&[1.0, 0.0], 0.95),
            Err(StatsError::NotPositive)
        );
        assert_eq!(
            geometric_mean(&[1.0, f64::NAN], 0.95),
            Err(StatsError::NotFinite)
        );
        assert_eq!(geometric_mean(&[1.0], 1.0), Err(StatsError::Level(1.0)));
    }
}
