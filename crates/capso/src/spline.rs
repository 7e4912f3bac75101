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
    t: Vec<f64>,
    x: Vec<f64>,
    y: Vec<f64>,
    /// Second derivatives of x(t) and y(t) at the knots.
    mx: Vec<f64>,
    my: Vec<f64>,
    /// Thomas algorithm scratch.
    scratch: Vec<f64>,
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
        self.t.clear();
        self.x.clear();
        self.y.clear();
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
            self.t.push(t);
            self.x.push(x);
            self.y.push(y);
        }
        let n = self.t.len();
        second_derivatives(
            &self.t,
            [&self.x, &self.y],
            [&mut self.mx, &mut self.my],
            &mut self.scratch,
        );
        n
    }

    /// Number of knots kept by the last fit.
    pub fn n_knots(&self) -> usize {
        self.t.len()
    }

    /// The parameter of knot `i` (its chord-length distance from the first knot).
    pub fn knot_parameter(&self, i: usize) -> f64 {
        self.t[i]
    }

    /// The point at parameter `t` on segment `i` (between knots `i` and `i + 1`).
    /// Precondition: at least two knots and `i + 1 < n_knots()`.
    pub fn eval(&self, i: usize, t: f64) -> (f64, f64) {
        let h = self.t[i + 1] - self.t[i];
        let a = self.t[i + 1] - t;
        let b = t - self.t[i];
        let value = |v: &[f64], m: &[f64]| {
            m[i] * a * a * a / (6.0 * h)
                + m[i + 1] * b * b * b / (6.0 * h)
                + (v[i] / h - m[i] * h / 6.0) * a
                + (v[i + 1] / h - m[i + 1] * h / 6.0) * b
        };
        (value(&self.x, &self.mx), value(&self.y, &self.my))
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
        let n = self.t.len();
        if n == 0 {
            return;
        }
        for i in 0..n - 1 {
            visit(self.x[i], self.y[i]);
            // The segment's cubic in powers of u = t - t_i (the same polynomial as
            // `eval`'s form, expanded once per segment and evaluated by Horner's rule):
            // v(u) = v_i + b u + (m_i / 2) u^2 + ((m_{i+1} - m_i) / (6 h)) u^3 with
            // b = (v_{i+1} - v_i) / h - h (2 m_i + m_{i+1}) / 6.
            let h = self.t[i + 1] - self.t[i];
            let cubic = |v: &[f64], m: &[f64]| {
                [
                    v[i],
                    (v[i + 1] - v[i]) / h - h * (2.0 * m[i] + m[i + 1]) / 6.0,
                    m[i] / 2.0,
                    (m[i + 1] - m[i]) / (6.0 * h),
                ]
            };
            let (cx, cy) = (cubic(&self.x, &self.mx), cubic(&self.y, &self.my));
            let step = h / per_segment as f64;
            for k in 1..per_segment {
                let u = step * k as f64;
                let horner = |c: [f64; 4]| c[0] + u * (c[1] + u * (c[2] + u * c[3]));
                visit(horner(cx), horner(cy));
            }
        }
        visit(self.x[n - 1], self.y[n - 1]);
    }
}

/// The natural spline's second derivatives `m` at the knots `(t_i, v_i)`: `m_0 = m_n = 0`
/// and, for the inner knots, `h_{i-1} m_{i-1} + 2 (h_{i-1} + h_i) m_i + h_i m_{i+1} =
/// 6 ((v_{i+1} - v_i) / h_i - (v_i - v_{i-1}) / h_{i-1})`, solved by the Thomas algorithm
/// (the system is strictly diagonally dominant). The matrix depends on `t` only, so both
/// coordinates' right-hand sides `v` are solved in one sweep into `m`.
fn second_derivatives(t: &[f64], v: [&[f64]; 2], m: [&mut Vec<f64>; 2], c: &mut Vec<f64>) {
    let n = t.len();
    let [mx, my] = m;
    for m in [&mut *mx, &mut *my] {
        m.clear();
        m.resize(n, 0.0);
    }
    if n < 3 {
        return;
    }
    c.clear();
    c.resize(n, 0.0);
    // Forward sweep over inner knots 1 ..= n - 2: c holds the modified super-diagonal,
    // m the modified right-hand sides.
    for i in 1..n - 1 {
        let h0 = t[i] - t[i - 1];
        let h1 = t[i + 1] - t[i];
        let diag = 2.0 * (h0 + h1);
        let (prev_c, prev_x, prev_y) = if i > 1 {
            (c[i - 1], mx[i - 1], my[i - 1])
        } else {
            (0.0, 0.0, 0.0)
        };
        let inverse = 1.0 / (diag - h0 * prev_c);
        c[i] = h1 * inverse;
        let rhs = |v: &[f64]| 6.0 * ((v[i + 1] - v[i]) / h1 - (v[i] - v[i - 1]) / h0);
        mx[i] = (rhs(v[0]) - h0 * prev_x) * inverse;
        my[i] = (rhs(v[1]) - h0 * prev_y) * inverse;
    }
    // The last inner knot's super-diagonal term multiplies m_{n-1} = 0.
    for i in (1..n - 1).rev() {
        mx[i] -= c[i] * mx[i + 1];
        my[i] -= c[i] * my[i + 1];
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
