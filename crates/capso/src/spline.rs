//! Natural cubic splines through 2-D knots, parameterised by chord length.
//!
//! For knots `p_0 .. p_m` the parameter is the cumulative chord length,
//! `t_0 = 0`, `t_{i+1} = t_i + |p_{i+1} - p_i|`, and `x(t)`, `y(t)` are each the natural
//! cubic spline (second derivative 0 at both ends) through `(t_i, x_i)` and `(t_i, y_i)`.
//! Chord length rather than the knot index makes the curve's speed roughly uniform when
//! the control points are unevenly spaced, so a sample count per segment gives samples
//! about evenly spread along the curve; and collinear knots in order along their line give
//! exactly the straight line (a natural spline reproduces linear data). Knots closer than
//! [`MIN_CHORD`] to the previous kept knot are dropped (a zero chord has no parameter
//! interval).

/// Knots nearer than this to the previous knot are dropped before fitting.
pub const MIN_CHORD: f64 = 1e-9;

/// A natural cubic spline through 2-D knots, reusable across fits without allocating.
#[derive(Debug, Clone, Default)]
pub struct Spline {
    knots: Vec<Knot>,
}

/// A kept knot and what the fit derives for it, together so that a fit walks one array.
#[derive(Debug, Clone, Copy, Default)]
struct Knot {
    /// The chord-length parameter and the point.
    t: f64,
    x: f64,
    y: f64,
    /// For the interval to the next knot (0 at the last knot): its length
    /// `h = t_{i+1} - t_i`, its reciprocal, and the slopes `(x_{i+1} - x_i) / h` and
    /// `(y_{i+1} - y_i) / h`, derived once per fit for both the solve and the sampling (as
    /// products with the reciprocal: one division per interval).
    h: f64,
    inverse_h: f64,
    sx: f64,
    sy: f64,
    /// The second derivatives of x(t) and y(t) here.
    mx: f64,
    my: f64,
    /// The Thomas algorithm's modified super-diagonal.
    c: f64,
}

impl Spline {
    /// An empty spline.
    pub fn new() -> Spline {
        Spline::default()
    }

    /// Fits the spline through `knots` (chord-length parameter, natural end conditions).
    /// Returns the number of knots kept after dropping near-duplicates.
    pub fn fit(&mut self, knots: &[(f64, f64)]) -> usize {
        self.fit_iter(knots.iter().copied())
    }

    /// [`Spline::fit`] through the knots `knots` yields, without collecting them first.
    pub fn fit_iter(&mut self, knots: impl IntoIterator<Item = (f64, f64)>) -> usize {
        self.knots.clear();
        // The last kept knot and its parameter.
        let mut last: Option<(f64, f64, f64)> = None;
        for (x, y) in knots {
            let t = match last {
                Some((px, py, pt)) => {
                    // sqrt of the sum of squares rather than `hypot`, whose overflow care
                    // costs a library call per knot; coordinates are grid-sized.
                    let chord = ((x - px) * (x - px) + (y - py) * (y - py)).sqrt();
                    if chord < MIN_CHORD {
                        continue;
                    }
                    pt + chord
                }
                None => 0.0,
            };
            last = Some((x, y, t));
            self.knots.push(Knot {
                t,
                x,
                y,
                ..Knot::default()
            });
        }
        second_derivatives(&mut self.knots);
        self.knots.len()
    }

    /// Number of knots kept by the last fit.
    pub fn n_knots(&self) -> usize {
        self.knots.len()
    }

    /// The parameter of knot `i` (its chord-length distance from the first knot).
    pub fn knot_parameter(&self, i: usize) -> f64 {
        self.knots[i].t
    }

    /// The point at parameter `t` on segment `i` (between knots `i` and `i + 1`).
    /// Precondition: at least two knots and `i + 1 < n_knots()`.
    pub fn eval(&self, i: usize, t: f64) -> (f64, f64) {
        let (k0, k1) = (&self.knots[i], &self.knots[i + 1]);
        let h = k1.t - k0.t;
        let a = k1.t - t;
        let b = t - k0.t;
        let value = |v0: f64, v1: f64, m0: f64, m1: f64| {
            m0 * a * a * a / (6.0 * h)
                + m1 * b * b * b / (6.0 * h)
                + (v0 / h - m0 * h / 6.0) * a
                + (v1 / h - m1 * h / 6.0) * b
        };
        (
            value(k0.x, k1.x, k0.mx, k1.mx),
            value(k0.y, k1.y, k0.my, k1.my),
        )
    }

    /// Appends `per_segment` samples per segment (at parameters `t_i + k h_i / per_segment`,
    /// `k = 0 .. per_segment - 1`) and then the last knot to `out`. With one knot, appends
    /// it alone. `per_segment` must be at least 1.
    pub fn sample(&self, per_segment: usize, out: &mut Vec<(f64, f64)>) {
        self.for_each_sample(per_segment, |x, y| out.push((x, y)));
    }

    /// Calls `visit` with the points [`Spline::sample`] appends, in the same order, without
    /// storing them.
    #[inline]
    pub fn for_each_sample(&self, per_segment: usize, mut visit: impl FnMut(f64, f64)) {
        let Some(end) = self.knots.last() else {
            return;
        };
        for pair in self.knots.windows(2) {
            let (k0, k1) = (&pair[0], &pair[1]);
            visit(k0.x, k0.y);
            if per_segment == 2 {
                // The default's one sample, the interval's midpoint, in closed form:
                // v(h / 2) = (v_i + v_{i+1}) / 2 - h^2 (m_i + m_{i+1}) / 16.
                let bend = k0.h * k0.h * (1.0 / 16.0);
                visit(
                    0.5 * (k0.x + k1.x) - bend * (k0.mx + k1.mx),
                    0.5 * (k0.y + k1.y) - bend * (k0.my + k1.my),
                );
                continue;
            }
            // The segment's cubic in powers of u = t - t_i (the same polynomial as
            // `eval`'s form, expanded once per segment and evaluated by Horner's rule):
            // v(u) = v_i + b u + (m_i / 2) u^2 + ((m_{i+1} - m_i) / (6 h)) u^3 with
            // b = (v_{i+1} - v_i) / h - h (2 m_i + m_{i+1}) / 6, the first term the slope.
            // Without a division: the sixths and the reciprocal of h are products.
            let (h, inverse_h) = (k0.h, k0.inverse_h);
            const SIXTH: f64 = 1.0 / 6.0;
            let cubic = |v: f64, s: f64, m0: f64, m1: f64| {
                [
                    v,
                    s - h * (2.0 * m0 + m1) * SIXTH,
                    m0 * 0.5,
                    (m1 - m0) * inverse_h * SIXTH,
                ]
            };
            let cx = cubic(k0.x, k0.sx, k0.mx, k1.mx);
            let cy = cubic(k0.y, k0.sy, k0.my, k1.my);
            let step = h / per_segment as f64;
            for k in 1..per_segment {
                let u = step * k as f64;
                let horner = |c: [f64; 4]| c[0] + u * (c[1] + u * (c[2] + u * c[3]));
                visit(horner(cx), horner(cy));
            }
        }
        visit(end.x, end.y);
    }
}

/// The natural spline's second derivatives `m` at the knots, with the intervals `h_i` and
/// slopes `s_i = (v_{i+1} - v_i) / h_i` they need: `m_0 = m_n = 0` and, for the inner
/// knots, `h_{i-1} m_{i-1} + 2 (h_{i-1} + h_i) m_i + h_i m_{i+1} = 6 (s_i - s_{i-1})`,
/// solved by the Thomas algorithm (the system is strictly diagonally dominant). The matrix
/// depends on `h` only, so both coordinates' right-hand sides are solved in one sweep.
fn second_derivatives(knots: &mut [Knot]) {
    for i in 1..knots.len() {
        let (x, y, t) = (knots[i].x, knots[i].y, knots[i].t);
        let k = &mut knots[i - 1];
        k.h = t - k.t;
        k.inverse_h = 1.0 / k.h;
        k.sx = (x - k.x) * k.inverse_h;
        k.sy = (y - k.y) * k.inverse_h;
    }
    let Some((_, inner)) = knots.split_last_mut() else {
        return;
    };
    let Some((first, inner)) = inner.split_first_mut() else {
        return;
    };
    // The sweep's pivots `beta_i = diag_i - h_{i-1} c_{i-1}` (c the modified
    // super-diagonal, `c_i = h_i / beta_i`) are ratios of the leading principal minors,
    // `beta_i = D_i / D_{i-1}` with `D_i = diag_i D_{i-1} - h_{i-1}^2 D_{i-2}` (`D_0 = 1`):
    // a recurrence of products, so that the divisions `D_{i-1} / D_i` do not wait for each
    // other (with the pivots' chain of divisions this function had 6.6 % of CAPSO's samples
    // on seed 002's first 200 x 200 map; without it CAPSO took 1 to 2 % less time).
    // Only the ratios of consecutive minors count, so both are scaled by a power of two
    // (exactly) when they leave `[2^-500, 2^500]`: any number of knots stays in range.
    const HUGE: f64 = 3.273_390_607_896_142e150; // 2^500
    const TINY: f64 = 1.0 / HUGE;
    let (mut minor, mut before) = (1.0, 0.0);
    let mut h_before = first.h;
    for k in inner.iter_mut() {
        let mut next = 2.0 * (h_before + k.h) * minor - h_before * h_before * before;
        // Kept in `c` until the sweep below turns it into the super-diagonal.
        k.c = minor / next;
        if !(TINY..=HUGE).contains(&next) {
            let scale = if next > HUGE { TINY } else { HUGE };
            (minor, next) = (minor * scale, next * scale);
        }
        (before, minor, h_before) = (minor, next, k.h);
    }
    // Forward sweep over the inner knots: c becomes the modified super-diagonal, m the
    // modified right-hand sides (the end knots' are 0 from the fit's defaults).
    let mut prev = *first;
    for k in inner.iter_mut() {
        let (h0, inverse) = (prev.h, k.c);
        k.c = k.h * inverse;
        k.mx = (6.0 * (k.sx - prev.sx) - h0 * prev.mx) * inverse;
        k.my = (6.0 * (k.sy - prev.sy) - h0 * prev.my) * inverse;
        prev = *k;
    }
    // The last inner knot's super-diagonal term multiplies m_{n-1} = 0.
    let (mut next_x, mut next_y) = (0.0, 0.0);
    for k in inner.iter_mut().rev() {
        k.mx -= k.c * next_x;
        k.my -= k.c * next_y;
        (next_x, next_y) = (k.mx, k.my);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: (f64, f64), b: (f64, f64)) -> bool {
        (a.0 - b.0).abs() < 1e-12 && (a.1 - b.1).abs() < 1e-12
    }

    /// Fits `knots`, evaluates at parameter `t`, and compares with `expect`.
    fn check(knots: &[(f64, f64)], t: f64, expect: (f64, f64)) {
        let mut spline = Spline::new();
        spline.fit(knots);
        let segment = (0..spline.n_knots() - 1)
            .find(|&i| t <= spline.knot_parameter(i + 1))
            .unwrap_or(spline.n_knots() - 2);
        let got = spline.eval(segment, t);
        assert!(
            close(got, expect),
            "{knots:?} at {t}: {got:?} vs {expect:?}"
        );
    }

    #[test]
    fn hand_computed_values() {
        // (0,0), (3,4), (6,0): chords 5 and 5, t = 0, 5, 10. x is linear in t (0.6 t).
        // y: 2 (5 + 5) M1 = 6 ((0 - 4) / 5 - (4 - 0) / 5) gives M1 = -0.48; at t = 2.5
        // y = M1 2.5^3 / 30 + (4 / 5 - M1 5 / 6) 2.5 = -0.25 + 3 = 2.75.
        check(&[(0.0, 0.0), (3.0, 4.0), (6.0, 0.0)], 2.5, (1.5, 2.75));
        check(&[(0.0, 0.0), (3.0, 4.0), (6.0, 0.0)], 5.0, (3.0, 4.0));
        check(&[(0.0, 0.0), (3.0, 4.0), (6.0, 0.0)], 7.5, (4.5, 2.75));
        // (0,0), (4,3), (4,8): chords 5 and 5. x: 20 M1 = 6 (0 - 4 / 5), M1 = -0.24,
        // x(2.5) = -0.24 * 15.625 / 30 + (0.8 + 0.2) 2.5 = 2.375. y: 20 M1 = 6 (1 - 0.6),
        // M1 = 0.12, y(2.5) = 0.12 * 15.625 / 30 + (0.6 - 0.1) 2.5 = 1.3125.
        check(&[(0.0, 0.0), (4.0, 3.0), (4.0, 8.0)], 2.5, (2.375, 1.3125));
        // Two knots: the straight segment.
        check(&[(1.0, 1.0), (4.0, 5.0)], 2.5, (2.5, 3.0));
    }

    #[test]
    fn four_knots_by_hand() {
        // Collinear knots in order along their line give the line itself: y = t.
        check(
            &[(0.0, 0.0), (0.0, 2.0), (0.0, 4.0), (0.0, 6.0)],
            3.3,
            (0.0, 3.3),
        );
        // Three equal chords of 5 with x = 0, 3, 6, 9 and y = 0, 4, 0, 4 ((3, 4) steps):
        // t = 0, 5, 10, 15, x = 0.6 t. For y, the system is
        // 20 M1 + 5 M2 = 6 (-4/5 - 4/5) = -9.6 and 5 M1 + 20 M2 = 6 (4/5 + 4/5) = 9.6,
        // so M1 = -M2 = -9.6 / 15 = -0.64. At t = 7.5 (middle of segment 1) y =
        // (M1 + M2) 2.5^3 / 30 + (4 / 5 - M1 5 / 6 + 0 - M2 5 / 6) 2.5 = 0 + 0.8 * 2.5 = 2.
        // At t = 2.5: M1 2.5^3 / 30 + (0.8 - M1 5 / 6) 2.5 = -0.3333.. + 3.3333.. = 3.
        let knots = [(0.0, 0.0), (3.0, 4.0), (6.0, 0.0), (9.0, 4.0)];
        check(&knots, 7.5, (4.5, 2.0));
        check(&knots, 2.5, (1.5, 3.0));
    }

    /// The classic Thomas sweep (a division per pivot) that `second_derivatives` replaced.
    fn reference_second_derivatives(knots: &[Knot]) -> Vec<(f64, f64)> {
        let n = knots.len();
        let (mut c, mut mx, mut my) = (vec![0.0; n], vec![0.0; n], vec![0.0; n]);
        for i in 1..n.saturating_sub(1) {
            let (h0, h1) = (knots[i - 1].h, knots[i].h);
            let inverse = 1.0 / (2.0 * (h0 + h1) - h0 * c[i - 1]);
            c[i] = h1 * inverse;
            mx[i] = (6.0 * (knots[i].sx - knots[i - 1].sx) - h0 * mx[i - 1]) * inverse;
            my[i] = (6.0 * (knots[i].sy - knots[i - 1].sy) - h0 * my[i - 1]) * inverse;
        }
        for i in (1..n.saturating_sub(1)).rev() {
            mx[i] -= c[i] * mx[i + 1];
            my[i] -= c[i] * my[i + 1];
        }
        mx.into_iter().zip(my).collect()
    }

    #[test]
    fn second_derivatives_match_the_division_sweep_for_any_knot_count() {
        // Chords from 1e-6 to 1e5 and up to 2000 knots: the minors would leave f64's range
        // without their rescaling.
        let mut state = 7u64;
        let mut next = || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            (state >> 11) as f64 / (1u64 << 53) as f64
        };
        for (count, scale) in [(3, 1.0), (8, 100.0), (22, 1e5), (500, 1e-6), (2000, 1e4)] {
            let knots: Vec<(f64, f64)> = (0..count)
                .map(|i| (i as f64 * scale + next() * scale, next() * scale))
                .collect();
            let mut spline = Spline::new();
            spline.fit(&knots);
            let expect = reference_second_derivatives(&spline.knots);
            for (k, (ex, ey)) in spline.knots.iter().zip(expect) {
                let close = |a: f64, b: f64| (a - b).abs() <= 1e-9 * (1.0 + b.abs());
                assert!(
                    close(k.mx, ex) && close(k.my, ey),
                    "{count} knots: {:?} vs {:?}",
                    (k.mx, k.my),
                    (ex, ey)
                );
            }
        }
    }

    #[test]
    fn two_samples_per_interval_are_the_midpoints() {
        let mut spline = Spline::new();
        spline.fit(&[(0.0, 0.0), (3.0, 4.0), (6.0, 0.0), (9.0, 4.0), (20.0, 1.0)]);
        let mut out = Vec::new();
        spline.sample(2, &mut out);
        assert_eq!(out.len(), 2 * (spline.n_knots() - 1) + 1);
        for i in 0..spline.n_knots() - 1 {
            let (t0, t1) = (spline.knot_parameter(i), spline.knot_parameter(i + 1));
            assert!(close(out[2 * i + 1], spline.eval(i, (t0 + t1) / 2.0)));
        }
    }

    #[test]
    fn duplicates_are_dropped_and_samples_end_at_the_knots() {
        let mut spline = Spline::new();
        assert_eq!(spline.fit(&[(0.0, 0.0), (0.0, 0.0), (3.0, 4.0)]), 2);
        let mut out = Vec::new();
        spline.sample(5, &mut out);
        assert_eq!(out.len(), 6);
        assert_eq!(out[0], (0.0, 0.0));
        assert_eq!(out[5], (3.0, 4.0));
        assert!(close(out[1], (0.6, 0.8)));
        let mut one = Vec::new();
        spline.fit(&[(2.0, 2.0)]);
        spline.sample(5, &mut one);
        assert_eq!(one, [(2.0, 2.0)]);
    }
}
