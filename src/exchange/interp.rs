//! Piecewise polynomials through sampled joint angles: the interpolation schemes of an imported
//! schedule ([`crate::exchange::import`]).
//!
//! On each interval `[t_i, t_{i+1}]`, `h = t_{i+1} − t_i`, `u = (t − t_i)/h`, a joint angle is
//! `q(u) = Σ_k a_k u^k` (degree ≤ 5), so `q̇ = q'(u)/h`, `q̈ = q''(u)/h²`. Three schemes, chosen
//! by what the samples carry:
//!
//! - **quintic Hermite** (`q`, `q̇`, `q̈` given): matches all three at both ends of every interval,
//!   so `q ∈ C²`; with `P = q_{i+1} − q_i`, `V_j = h q̇_j`, `A_j = h² q̈_j`:
//!   `a_0 = q_i, a_1 = V_0, a_2 = A_0/2`,
//!   `a_3 = 10P − 6V_0 − 4V_1 − (3A_0 − A_1)/2`,
//!   `a_4 = −15P + 8V_0 + 7V_1 + (3A_0 − 2A_1)/2`,
//!   `a_5 = 6P − 3(V_0 + V_1) − (A_0 − A_1)/2`.
//!   Error (two-point Hermite remainder): `|q − q_true| ≤ h⁶ max|q⁽⁶⁾| / 46080`, `q̇` `O(h⁵)`, `q̈` `O(h⁴)`;
//! - **cubic Hermite** (`q`, `q̇` given): `a_2 = 3P − 2V_0 − V_1`, `a_3 = −2P + V_0 + V_1`;
//!   `q ∈ C¹`, `|q − q_true| ≤ h⁴ max|q⁽⁴⁾| / 384`, `q̇` `O(h³)`, and `q̈` (piecewise linear,
//!   discontinuous at the samples) `O(h²)`;
//! - **not-a-knot cubic spline** (`q` only; de Boor, *A Practical Guide to Splines*, ch. IV):
//!   `q ∈ C²` with `q'''` also continuous at the second and the last-but-one sample; needs at least
//!   four samples; errors `O(h⁴)`, `O(h³)`, `O(h²)` in `q`, `q̇`, `q̈`.
//!
//! ## References
//! - C. de Boor, *A Practical Guide to Splines* (1978), ch. IV (not-a-knot end conditions);
//! - the Hermite interpolation remainder, e.g. Burden & Faires, *Numerical Analysis*, §3.4.

/// Coefficients `a_0 … a_5` of one interval in its local variable `u ∈ [0, 1]`.
type Coefficients = [f64; 6];

/// A piecewise polynomial of degree ≤ 5 on strictly increasing knots.
#[derive(Clone, Debug, PartialEq)]
pub struct Piecewise {
    knots: Vec<f64>,
    coefficients: Vec<Coefficients>,
}

/// Value and first two derivatives with respect to time.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Derivatives {
    /// `q`.
    pub value: f64,
    /// `dq/dt`.
    pub rate: f64,
    /// `d²q/dt²`.
    pub accel: f64,
}

impl Piecewise {
    /// Quintic Hermite interpolation of values, rates and accelerations at `knots` (at least two,
    /// strictly increasing; all slices the same length).
    pub fn quintic_hermite(knots: &[f64], q: &[f64], qd: &[f64], qdd: &[f64]) -> Piecewise {
        Piecewise::hermite(knots, q, qd, |i, h, [p, v0, v1]| {
            let (a0, a1) = (h * h * qdd[i], h * h * qdd[i + 1]);
            [
                q[i],
                v0,
                0.5 * a0,
                10.0 * p - 6.0 * v0 - 4.0 * v1 - 0.5 * (3.0 * a0 - a1),
                -15.0 * p + 8.0 * v0 + 7.0 * v1 + 0.5 * (3.0 * a0 - 2.0 * a1),
                6.0 * p - 3.0 * (v0 + v1) - 0.5 * (a0 - a1),
            ]
        })
    }

    /// Cubic Hermite interpolation of values and rates at `knots` (at least two).
    pub fn cubic_hermite(knots: &[f64], q: &[f64], qd: &[f64]) -> Piecewise {
        Piecewise::hermite(knots, q, qd, |i, _, [p, v0, v1]| {
            [q[i], v0, 3.0 * p - 2.0 * v0 - v1, -2.0 * p + v0 + v1, 0.0, 0.0]
        })
    }

    /// A Hermite interpolant whose interval `i` of length `h` has the coefficients
    /// `coefficients(i, h, [P, V_0, V_1])`, `P = q_{i+1} − q_i`, `V_j = h q̇_j`.
    fn hermite(
        knots: &[f64],
        q: &[f64],
        qd: &[f64],
        coefficients: impl Fn(usize, f64, [f64; 3]) -> Coefficients,
    ) -> Piecewise {
        let coefficients = knots
            .windows(2)
            .enumerate()
            .map(|(i, w)| {
                let h = w[1] - w[0];
                coefficients(i, h, [q[i + 1] - q[i], h * qd[i], h * qd[i + 1]])
            })
            .collect();
        Piecewise { knots: knots.to_vec(), coefficients }
    }

    /// The not-a-knot cubic spline through values at `knots`; `None` with fewer than four knots.
    ///
    /// Unknowns are the second derivatives `M_i`; the interior rows are
    /// `h_{i−1} M_{i−1} + 2(h_{i−1} + h_i) M_i + h_i M_{i+1} = 6(δ_i − δ_{i−1})`, the end rows
    /// `h_1 M_0 − (h_0 + h_1) M_1 + h_0 M_2 = 0` (and its mirror) say `q'''` is continuous at the
    /// second knot. `M_0` and `M_{n−1}` are eliminated, leaving a tridiagonal system for the
    /// interior, solved by the Thomas algorithm.
    pub fn not_a_knot(knots: &[f64], q: &[f64]) -> Option<Piecewise> {
        let n = knots.len();
        if n < 4 {
            return None;
        }
        let h: Vec<f64> = knots.windows(2).map(|w| w[1] - w[0]).collect();
        let delta: Vec<f64> = (0..n - 1).map(|i| (q[i + 1] - q[i]) / h[i]).collect();
        // Tridiagonal system for M_1 … M_{n−2}: sub[k] M_{k} + diag[k] M_{k+1} + sup[k] M_{k+2} = rhs[k].
        let m = n - 2;
        let mut sub = vec![0.0; m];
        let mut diag = vec![0.0; m];
        let mut sup = vec![0.0; m];
        let mut rhs = vec![0.0; m];
        for k in 0..m {
            let i = k + 1;
            sub[k] = h[i - 1];
            diag[k] = 2.0 * (h[i - 1] + h[i]);
            sup[k] = h[i];
            rhs[k] = 6.0 * (delta[i] - delta[i - 1]);
        }
        // M_0 = ((h0 + h1) M_1 − h0 M_2)/h1 folded into the first interior row.
        diag[0] += h[0] * (h[0] + h[1]) / h[1];
        sup[0] -= h[0] * h[0] / h[1];
        // M_{n−1} = ((h_{n−2} + h_{n−3}) M_{n−2} − h_{n−2} M_{n−3})/h_{n−3} into the last.
        let (a, b) = (h[n - 2], h[n - 3]);
        diag[m - 1] += a * (a + b) / b;
        sub[m - 1] -= a * a / b;
        let interior = thomas(&sub, &diag, &sup, &rhs)?;
        let mut second = Vec::with_capacity(n);
        second.push(((h[0] + h[1]) * interior[0] - h[0] * interior[1.min(m - 1)]) / h[1]);
        second.extend_from_slice(&interior);
        second.push(((a + b) * interior[m - 1] - a * interior[m.saturating_sub(2)]) / b);
        let coefficients = (0..n - 1)
            .map(|i| {
                let hi = h[i];
                let (m0, m1) = (second[i], second[i + 1]);
                let b1 = delta[i] - hi * (2.0 * m0 + m1) / 6.0;
                [q[i], b1 * hi, 0.5 * m0 * hi * hi, (m1 - m0) * hi * hi / 6.0, 0.0, 0.0]
            })
            .collect();
        Some(Piecewise { knots: knots.to_vec(), coefficients })
    }

    /// The knots.
    pub fn knots(&self) -> &[f64] {
        &self.knots
    }

    /// Value, rate and acceleration at `t` (clamped to the knots' span; at an inner knot the
    /// interval to its right is used — every scheme is at least C¹ there).
    pub fn eval(&self, t: f64) -> Derivatives {
        let last = self.coefficients.len() - 1;
        self.eval_on(self.knots.partition_point(|&k| k <= t).saturating_sub(1).min(last), t)
    }

    /// As [`Piecewise::eval`], but at an inner knot the interval to its left: the left limits,
    /// where the cubic Hermite's `q̈` jumps.
    pub fn eval_before(&self, t: f64) -> Derivatives {
        let last = self.coefficients.len() - 1;
        self.eval_on(self.knots.partition_point(|&k| k < t).saturating_sub(1).min(last), t)
    }

    /// Value and derivatives at `t` by interval `i`'s polynomial (`u` clamped to `[0, 1]`).
    fn eval_on(&self, i: usize, t: f64) -> Derivatives {
        let h = self.knots[i + 1] - self.knots[i];
        let u = ((t - self.knots[i]) / h).clamp(0.0, 1.0);
        let a = &self.coefficients[i];
        let mut value = 0.0;
        let mut d1 = 0.0;
        let mut d2 = 0.0;
        for k in (0..6).rev() {
            // Horner for the polynomial and its two derivatives.
            d2 = d2 * u + 2.0 * d1;
            d1 = d1 * u + value;
            value = value * u + a[k];
        }
        Derivatives { value, rate: d1 / h, accel: d2 / (h * h) }
    }
}

/// Solves a tridiagonal system (`sub[0]` and `sup[last]` unused); `None` on a zero pivot.
fn thomas(sub: &[f64], diag: &[f64], sup: &[f64], rhs: &[f64]) -> Option<Vec<f64>> {
    let n = diag.len();
    let mut c = vec![0.0; n];
    let mut d = vec![0.0; n];
    let mut pivot = diag[0];
    if pivot.abs() < f64::MIN_POSITIVE {
        return None;
    }
    c[0] = sup[0] / pivot;
    d[0] = rhs[0] / pivot;
    for i in 1..n {
        pivot = diag[i] - sub[i] * c[i - 1];
        if pivot.abs() < f64::MIN_POSITIVE {
            return None;
        }
        c[i] = sup[i] / pivot;
        d[i] = (rhs[i] - sub[i] * d[i - 1]) / pivot;
    }
    for i in (0..n - 1).rev() {
        d[i] -= c[i] * d[i + 1];
    }
    Some(d)
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    fn uneven_knots() -> Vec<f64> {
        vec![0.0, 0.13, 0.3, 0.31, 0.6, 0.75, 1.0]
    }

    #[test]
    fn quintic_hermite_reproduces_a_quintic() {
        // Any quintic is its own two-point Hermite interpolant: exact up to round-off.
        let f = |t: f64| [1.0 - 2.0 * t + 0.5 * t.powi(3) - 3.0 * t.powi(5), -2.0 + 1.5 * t * t - 15.0 * t.powi(4)];
        let fdd = |t: f64| 3.0 * t - 60.0 * t.powi(3);
        let k = uneven_knots();
        let q: Vec<f64> = k.iter().map(|&t| f(t)[0]).collect();
        let qd: Vec<f64> = k.iter().map(|&t| f(t)[1]).collect();
        let qdd: Vec<f64> = k.iter().map(|&t| fdd(t)).collect();
        let p = Piecewise::quintic_hermite(&k, &q, &qd, &qdd);
        for t in [0.05, 0.2, 0.305, 0.5, 0.99] {
            let d = p.eval(t);
            assert_relative_eq!(d.value, f(t)[0], epsilon = 1e-13);
            assert_relative_eq!(d.rate, f(t)[1], epsilon = 1e-12);
            assert_relative_eq!(d.accel, fdd(t), epsilon = 1e-10);
        }
    }

    #[test]
    fn cubic_schemes_reproduce_a_cubic() {
        // A cubic satisfies the not-a-knot conditions and is its own cubic Hermite interpolant.
        let f = |t: f64| 0.3 - t + 2.0 * t * t - 0.7 * t.powi(3);
        let fd = |t: f64| -1.0 + 4.0 * t - 2.1 * t * t;
        let fdd = |t: f64| 4.0 - 4.2 * t;
        let k = uneven_knots();
        let q: Vec<f64> = k.iter().map(|&t| f(t)).collect();
        let qd: Vec<f64> = k.iter().map(|&t| fd(t)).collect();
        let spline = Piecewise::not_a_knot(&k, &q).expect("seven knots");
        let hermite = Piecewise::cubic_hermite(&k, &q, &qd);
        for p in [spline, hermite] {
            for t in [0.0, 0.07, 0.2, 0.305, 0.5, 0.8, 1.0] {
                let d = p.eval(t);
                assert_relative_eq!(d.value, f(t), epsilon = 1e-12);
                assert_relative_eq!(d.rate, fd(t), epsilon = 1e-10);
                assert_relative_eq!(d.accel, fdd(t), epsilon = 1e-8);
            }
        }
    }

    #[test]
    fn eval_before_takes_the_left_interval_at_a_knot() {
        // Cubic Hermite of t² with wrong rates: q̈ jumps at the inner knot; both sides are seen.
        let k = [0.0, 1.0, 2.0];
        let p = Piecewise::cubic_hermite(&k, &[0.0, 1.0, 4.0], &[0.0, 0.0, 0.0]);
        let (left, right) = (p.eval_before(1.0), p.eval(1.0));
        assert_relative_eq!(left.value, right.value, epsilon = 1e-15);
        assert_relative_eq!(left.accel, -6.0, epsilon = 1e-12);
        assert_relative_eq!(right.accel, 18.0, epsilon = 1e-12);
    }

    #[test]
    fn not_a_knot_on_four_knots_is_the_interpolating_cubic() {
        let k = [0.0, 0.5, 1.5, 2.0];
        let f = |t: f64| t.powi(3) - t;
        let q: Vec<f64> = k.iter().map(|&t| f(t)).collect();
        let p = Piecewise::not_a_knot(&k, &q).expect("four knots");
        assert_relative_eq!(p.eval(1.0).value, f(1.0), epsilon = 1e-13);
        assert!(Piecewise::not_a_knot(&k[..3], &q[..3]).is_none());
    }

    #[test]
    fn spline_error_falls_as_h_to_the_fourth() {
        // sin on [0, 2] with n and 2n intervals: the error ratio is ≈ 16 for an O(h⁴) scheme.
        let err = |n: usize| {
            let k: Vec<f64> = (0..=n).map(|i| 2.0 * i as f64 / n as f64).collect();
            let q: Vec<f64> = k.iter().map(|t| t.sin()).collect();
            let p = Piecewise::not_a_knot(&k, &q).expect("enough knots");
            (0..1000)
                .map(|j| 2.0 * (j as f64 + 0.5) / 1000.0)
                .map(|t| (p.eval(t).value - t.sin()).abs())
                .fold(0.0, f64::max)
        };
        let ratio = err(20) / err(40);
        assert!((12.0..20.0).contains(&ratio), "error ratio {ratio}, expected ≈ 16");
    }
}
