//! Scalar root finding: bracket expansion ([`Brackets`], each side's first sign change) and
//! Brent's method.
//!
//! ## References
//! - R. P. Brent, *Algorithms for Minimization without Derivatives* (1973), ch. 4.

use serde::Serialize;

/// How a root search ended.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum RootStatus {
    /// The bracket shrank below the tolerance.
    Converged,
    /// No sign change was found.
    NoBracket,
    /// The iteration budget ran out; the best iterate is returned.
    MaxIterations,
    /// The bracket closed, but the function there is not at the root to the tolerance (a sign
    /// change of an inaccurate evaluation, not a root).
    NotAtRoot,
}

impl RootStatus {
    /// The name in files and reports: `converged`, `no-bracket`, `max-iterations`, `not-at-root`.
    pub fn name(self) -> &'static str {
        match self {
            RootStatus::Converged => "converged",
            RootStatus::NoBracket => "no-bracket",
            RootStatus::MaxIterations => "max-iterations",
            RootStatus::NotAtRoot => "not-at-root",
        }
    }

    /// Whether the search found a root.
    pub fn is_converged(self) -> bool {
        self == RootStatus::Converged
    }
}

impl std::fmt::Display for RootStatus {
    /// How the search ended, in words.
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            RootStatus::Converged => "converged",
            RootStatus::NoBracket => "no sign change found, so no root was bracketed",
            RootStatus::MaxIterations => "iteration budget spent before converging",
            RootStatus::NotAtRoot => "the bracket closed on a jump, not on a root",
        })
    }
}

/// The outcome of a root search.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Root {
    /// Best abscissa found.
    pub x: f64,
    /// Function value there.
    pub fx: f64,
    /// Function evaluations used.
    pub evaluations: usize,
    /// How the search ended.
    pub status: RootStatus,
}

/// A bracket `((a, f(a)), (b, f(b)))` with `f(a) f(b) ≤ 0`.
pub type Bracket = ((f64, f64), (f64, f64));

/// Sign changes of `f` around `x0`, found by expanding `[x0 − s, x0 + s]` geometrically
/// (`s = step·2^k`, `k < max_doublings`): each side's first sign change between `x0` and `x0 ± s`,
/// in the order found (the nearer first; at one distance the upper side first). A side that has
/// given its bracket is no longer evaluated, so asking for the second bracket only when the
/// first held no root (a jump, not a zero) costs nothing in the common case.
#[derive(Clone, Debug)]
pub struct Brackets {
    x0: f64,
    f0: f64,
    s: f64,
    k: usize,
    side: usize,
    max_doublings: usize,
    open: [bool; 2],
}

impl Brackets {
    /// The expansion from `x0` (where `f = f0`) by `step`, at most `max_doublings` times.
    pub fn new(x0: f64, f0: f64, step: f64, max_doublings: usize) -> Brackets {
        Brackets { x0, f0, s: step, k: 0, side: 0, max_doublings, open: [true; 2] }
    }

    /// The next bracket, counting `f`'s evaluations in `evaluations`; `None` when the expansion
    /// is spent.
    pub fn next(&mut self, f: &mut impl FnMut(f64) -> f64, evaluations: &mut usize) -> Option<Bracket> {
        while self.k < self.max_doublings {
            while self.side < 2 {
                let side = self.side;
                self.side += 1;
                if !self.open[side] {
                    continue;
                }
                let x = if side == 0 { self.x0 + self.s } else { self.x0 - self.s };
                let fx = f(x);
                *evaluations += 1;
                if fx.is_finite() && fx * self.f0 <= 0.0 {
                    self.open[side] = false;
                    let (x0, f0) = (self.x0, self.f0);
                    return Some(if x > x0 { ((x0, f0), (x, fx)) } else { ((x, fx), (x0, f0)) });
                }
            }
            self.side = 0;
            self.k += 1;
            self.s *= 2.0;
        }
        None
    }
}

/// Brent's method on a bracket `[a, b]` with `f(a) f(b) ≤ 0`, to `|b − a| ≤ xtol` or `f = 0`.
pub fn brent(
    f: &mut impl FnMut(f64) -> f64,
    (a0, fa0): (f64, f64),
    (b0, fb0): (f64, f64),
    xtol: f64,
    max_iter: usize,
) -> Root {
    let (mut a, mut fa, mut b, mut fb) = (a0, fa0, b0, fb0);
    let mut evaluations = 0;
    if fa * fb > 0.0 {
        return Root { x: b, fx: fb, evaluations, status: RootStatus::NoBracket };
    }
    if fa.abs() < fb.abs() {
        std::mem::swap(&mut a, &mut b);
        std::mem::swap(&mut fa, &mut fb);
    }
    let (mut c, mut fc) = (a, fa);
    let mut d = b - a;
    let mut e = d;
    for _ in 0..max_iter {
        if fb == 0.0 {
            return Root { x: b, fx: fb, evaluations, status: RootStatus::Converged };
        }
        if fb.signum() == fc.signum() {
            c = a;
            fc = fa;
            d = b - a;
            e = d;
        }
        if fc.abs() < fb.abs() {
            a = b;
            b = c;
            c = a;
            fa = fb;
            fb = fc;
            fc = fa;
        }
        let tol = 2.0 * f64::EPSILON * b.abs() + 0.5 * xtol;
        let m = 0.5 * (c - b);
        if m.abs() <= tol {
            return Root { x: b, fx: fb, evaluations, status: RootStatus::Converged };
        }
        if e.abs() >= tol && fa.abs() > fb.abs() {
            let s = fb / fa;
            // Secant when only two distinct points are known (c was just reset to a): an exact
            // identity test, as in Brent's algorithm.
            #[allow(clippy::float_cmp)]
            let (mut p, mut q) = if a == c {
                (2.0 * m * s, 1.0 - s)
            } else {
                let qa = fa / fc;
                let r = fb / fc;
                (s * (2.0 * m * qa * (qa - r) - (b - a) * (r - 1.0)), (qa - 1.0) * (r - 1.0) * (s - 1.0))
            };
            if p > 0.0 {
                q = -q;
            } else {
                p = -p;
            }
            if 2.0 * p < (3.0 * m * q - (tol * q).abs()).min((e * q).abs()) {
                e = d;
                d = p / q;
            } else {
                d = m;
                e = m;
            }
        } else {
            d = m;
            e = m;
        }
        a = b;
        fa = fb;
        b += if d.abs() > tol { d } else { tol.copysign(m) };
        fb = f(b);
        evaluations += 1;
    }
    Root { x: b, fx: fb, evaluations, status: RootStatus::MaxIterations }
}

/// The first root of `f` on `[a, b]`: scans `steps` equal subintervals from `a` towards `b` for
/// the first sign change (or an exact zero on the grid) and refines that bracket with
/// [`brent`] to round-off. `None` when no subinterval changes sign, when `f` is not finite at a
/// grid point, or when the interval or `steps` is degenerate.
pub fn first_root(f: impl Fn(f64) -> f64, a: f64, b: f64, steps: usize) -> Option<f64> {
    if steps == 0 || !a.is_finite() || !b.is_finite() || b <= a {
        return None;
    }
    let h = (b - a) / steps as f64;
    let (mut x0, mut f0) = (a, f(a));
    for k in 1..=steps {
        if !f0.is_finite() {
            return None;
        }
        if f0 == 0.0 {
            return Some(x0);
        }
        let x1 = if k == steps { b } else { a + h * k as f64 };
        let f1 = f(x1);
        if !f1.is_finite() {
            return None;
        }
        if f0 * f1 <= 0.0 {
            let root = brent(&mut |x| f(x), (x0, f0), (x1, f1), 0.0, 200);
            return (root.status == RootStatus::Converged).then_some(root.x);
        }
        (x0, f0) = (x1, f1);
    }
    None
}

/// Golden-section search for the maximum of a locally unimodal `f` on `[lo, hi]`;
/// returns the abscissa and value of the better final point.
pub fn golden_max(f: impl Fn(f64) -> f64, mut lo: f64, mut hi: f64, iters: usize) -> (f64, f64) {
    let g = 0.5 * (5f64.sqrt() - 1.0);
    let mut x1 = hi - g * (hi - lo);
    let mut x2 = lo + g * (hi - lo);
    let (mut f1, mut f2) = (f(x1), f(x2));
    for _ in 0..iters {
        if f1 < f2 {
            lo = x1;
            x1 = x2;
            f1 = f2;
            x2 = lo + g * (hi - lo);
            f2 = f(x2);
        } else {
            hi = x2;
            x2 = x1;
            f2 = f1;
            x1 = hi - g * (hi - lo);
            f1 = f(x1);
        }
    }
    if f1 > f2 {
        (x1, f1)
    } else {
        (x2, f2)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    #[test]
    fn finds_cube_root_of_two() {
        // Reference: 2^(1/3) = 1.259921049894873… (closed form).
        let mut f = |x: f64| x * x * x - 2.0;
        let r = brent(&mut f, (0.0, -2.0), (2.0, 6.0), 1e-14, 100);
        assert_eq!(r.status, RootStatus::Converged);
        assert_relative_eq!(r.x, 2f64.cbrt(), epsilon = 1e-13);
    }

    #[test]
    fn bracket_expands_to_a_far_root() {
        let mut n = 0;
        let mut f = |x: f64| x - 37.0;
        let ((a, _), (b, _)) = Brackets::new(1.0, -36.0, 0.5, 20).next(&mut f, &mut n).expect("bracket");
        assert!(a <= 37.0 && 37.0 <= b, "[{a}, {b}] should hold 37");
    }

    #[test]
    fn each_side_gives_its_bracket_the_nearer_first() {
        // A jump of sign at x = 2 (upper side) and a root at x = −3 (lower side), from x0 = 0.
        let mut f = |x: f64| if (-3.0..=2.0).contains(&x) { -1.0 } else { 1.0 };
        let (mut n, mut brackets) = (0, Brackets::new(0.0, -1.0, 1.0, 10));
        let ((a, _), (b, _)) = brackets.next(&mut f, &mut n).expect("the upper bracket");
        assert!((a, b) == (0.0, 4.0) && n == 5, "[{a}, {b}] after {n} evaluations");
        let ((a, _), (b, _)) = brackets.next(&mut f, &mut n).expect("the lower bracket");
        assert!((a, b) == (-4.0, 0.0) && n == 6, "[{a}, {b}] after {n} evaluations");
        assert!(brackets.next(&mut f, &mut n).is_none());
        assert_eq!(n, 6, "a closed side is not evaluated again");
    }

    #[test]
    fn reports_missing_bracket() {
        let mut f = |x: f64| x * x + 1.0;
        let r = brent(&mut f, (-1.0, 2.0), (1.0, 2.0), 1e-12, 50);
        assert_eq!(r.status, RootStatus::NoBracket);
    }

    #[test]
    fn finds_sqrt_two_to_round_off() {
        let r = first_root(|x| x * x - 2.0, 0.0, 2.0, 7);
        assert_relative_eq!(r.unwrap_or(f64::NAN), 2f64.sqrt(), max_relative = 4.0 * f64::EPSILON);
    }

    #[test]
    fn returns_the_first_of_several_roots() {
        // sin has roots at π, 2π, 3π in (1, 10): the scan must return π.
        let r = first_root(f64::sin, 1.0, 10.0, 100).unwrap_or(f64::NAN);
        assert_relative_eq!(r, std::f64::consts::PI, max_relative = 4.0 * f64::EPSILON);
    }

    #[test]
    fn none_without_a_sign_change_or_on_nan() {
        assert!(first_root(|x| x * x + 1.0, -3.0, 3.0, 50).is_none());
        assert!(first_root(|_| f64::NAN, 0.0, 1.0, 10).is_none());
        assert!(first_root(|x| x, 1.0, 0.0, 10).is_none());
    }

    #[test]
    fn exact_zero_on_the_grid_is_returned() {
        let r = first_root(|x| x - 0.5, 0.0, 1.0, 4).unwrap_or(f64::NAN);
        assert_relative_eq!(r, 0.5);
    }
}
