//! Forward-mode dual numbers with `N` directions, and the small generic vector algebra the
//! differentiable model is written in.
//!
//! A [`Dual`] `a + Σ_k a_k ε_k` with `ε_j ε_k = 0` carries a value and its gradient with respect
//! to `N` seeded inputs; every operation applies the chain rule, so a function written once over
//! [`Real`] returns its value at `f64` and its exact first derivatives at `Dual<N>` (up to
//! round-off: no step size, no truncation error).
//!
//! ## References
//! - A. Griewank, A. Walther, *Evaluating Derivatives* (2nd ed., SIAM 2008), ch. 3 (forward mode).

use std::ops::{Add, Div, Mul, Neg, Sub};

/// A scalar the model can be evaluated in: `f64`, or a [`Dual`] carrying derivatives.
pub trait Real:
    Copy
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<Output = Self>
    + Div<Output = Self>
    + Neg<Output = Self>
    + Mul<f64, Output = Self>
    + Add<f64, Output = Self>
{
    /// A constant (zero derivative).
    fn cst(x: f64) -> Self;
    /// Sine and cosine.
    fn sin_cos(self) -> (Self, Self);
    /// Square root (of a positive value).
    fn sqrt(self) -> Self;
    /// The value without derivatives.
    fn value(self) -> f64;
}

impl Real for f64 {
    fn cst(x: f64) -> Self {
        x
    }
    fn sin_cos(self) -> (Self, Self) {
        f64::sin_cos(self)
    }
    fn sqrt(self) -> Self {
        f64::sqrt(self)
    }
    fn value(self) -> f64 {
        self
    }
}

/// A value and its derivatives with respect to `N` inputs.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Dual<const N: usize> {
    /// The value.
    pub re: f64,
    /// `∂/∂x_k` of the value.
    pub eps: [f64; N],
}

impl<const N: usize> Dual<N> {
    /// The `k`-th input with value `x`: derivative one in direction `k`.
    pub fn input(x: f64, k: usize) -> Self {
        let mut eps = [0.0; N];
        eps[k] = 1.0;
        Self { re: x, eps }
    }

    fn map(self, f: f64, df: f64) -> Self {
        Self { re: f, eps: self.eps.map(|e| df * e) }
    }
}

impl<const N: usize> Add for Dual<N> {
    type Output = Self;
    fn add(self, o: Self) -> Self {
        Self { re: self.re + o.re, eps: std::array::from_fn(|k| self.eps[k] + o.eps[k]) }
    }
}

impl<const N: usize> Sub for Dual<N> {
    type Output = Self;
    fn sub(self, o: Self) -> Self {
        Self { re: self.re - o.re, eps: std::array::from_fn(|k| self.eps[k] - o.eps[k]) }
    }
}

impl<const N: usize> Mul for Dual<N> {
    type Output = Self;
    // The product rule adds.
    #[allow(clippy::suspicious_arithmetic_impl)]
    fn mul(self, o: Self) -> Self {
        Self { re: self.re * o.re, eps: std::array::from_fn(|k| self.eps[k] * o.re + self.re * o.eps[k]) }
    }
}

impl<const N: usize> Div for Dual<N> {
    type Output = Self;
    // The quotient rule multiplies and subtracts.
    #[allow(clippy::suspicious_arithmetic_impl)]
    fn div(self, o: Self) -> Self {
        let inv = 1.0 / o.re;
        let re = self.re * inv;
        Self { re, eps: std::array::from_fn(|k| (self.eps[k] - re * o.eps[k]) * inv) }
    }
}

impl<const N: usize> Neg for Dual<N> {
    type Output = Self;
    fn neg(self) -> Self {
        Self { re: -self.re, eps: self.eps.map(|e| -e) }
    }
}

impl<const N: usize> Mul<f64> for Dual<N> {
    type Output = Self;
    fn mul(self, k: f64) -> Self {
        Self { re: self.re * k, eps: self.eps.map(|e| e * k) }
    }
}

impl<const N: usize> Add<f64> for Dual<N> {
    type Output = Self;
    fn add(self, k: f64) -> Self {
        Self { re: self.re + k, eps: self.eps }
    }
}

impl<const N: usize> Real for Dual<N> {
    fn cst(x: f64) -> Self {
        Self { re: x, eps: [0.0; N] }
    }
    fn sin_cos(self) -> (Self, Self) {
        let (s, c) = self.re.sin_cos();
        (self.map(s, c), self.map(c, -s))
    }
    fn sqrt(self) -> Self {
        let r = self.re.sqrt();
        self.map(r, 0.5 / r)
    }
    fn value(self) -> f64 {
        self.re
    }
}

/// A 3-vector over a [`Real`]. The helpers below take vectors by reference: a dual vector passed
/// by value is copied at every call (`Dual<12>`'s is 312 bytes).
pub type V3<T> = [T; 3];

/// `a + b`.
pub fn add<T: Real>(a: &V3<T>, b: &V3<T>) -> V3<T> {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
}

/// `a − b`.
pub fn sub<T: Real>(a: &V3<T>, b: &V3<T>) -> V3<T> {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

/// `k a`.
pub fn scale<T: Real>(k: T, a: &V3<T>) -> V3<T> {
    [k * a[0], k * a[1], k * a[2]]
}

/// `k a` for a constant `k`.
pub fn scale_by<T: Real>(k: f64, a: &V3<T>) -> V3<T> {
    [a[0] * k, a[1] * k, a[2] * k]
}

/// `a · b`.
pub fn dot<T: Real>(a: &V3<T>, b: &V3<T>) -> T {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// `a × b`.
pub fn cross<T: Real>(a: &V3<T>, b: &V3<T>) -> V3<T> {
    [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]
}

/// Solves `M x = b` for a symmetric 3×3 `M` given as its rows, by Cramer's rule (the locked
/// inertia is positive definite and well conditioned, so no pivoting is needed).
pub fn solve3<T: Real>(m: &[V3<T>; 3], b: &V3<T>) -> V3<T> {
    let c0 = cross(&m[1], &m[2]);
    let c1 = cross(&m[2], &m[0]);
    let c2 = cross(&m[0], &m[1]);
    let det = dot(&m[0], &c0);
    // x = (adj M) b / det, the adjugate's columns being the cross products of rows.
    let x = [dot(&c0, b), dot(&c1, b), dot(&c2, b)];
    [x[0] / det, x[1] / det, x[2] / det]
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    #[test]
    fn chain_rule_matches_hand_derivative() {
        // f(x, y) = sin(x) y / (1 + x y): ∂f/∂x = (cos x · y (1 + xy) − sin x · y²)/(1 + xy)².
        let (x, y) = (0.7, -1.3);
        let f = |x: Dual<2>, y: Dual<2>| x.sin_cos().0 * y / (x * y + 1.0);
        let d = f(Dual::input(x, 0), Dual::input(y, 1));
        let den = (1.0 + x * y) * (1.0 + x * y);
        assert_relative_eq!(d.eps[0], (x.cos() * y * (1.0 + x * y) - x.sin() * y * y) / den, max_relative = 1e-13);
        assert_relative_eq!(d.eps[1], x.sin() / den, max_relative = 1e-13);
    }

    #[test]
    fn solve3_solves() {
        let m = [[4.0, 1.0, 0.5], [1.0, 3.0, 0.2], [0.5, 0.2, 2.0]];
        let b = [1.0, -2.0, 0.5];
        let x = solve3(&m, &b);
        for (row, rhs) in m.iter().zip(b) {
            assert_relative_eq!(dot(row, &x), rhs, epsilon = 1e-14);
        }
    }
}
