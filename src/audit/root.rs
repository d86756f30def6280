//! A robust bracketing root finder for scalar equations on an interval.
//!
//! [`first_root`] scans `[a, b]` on an even grid for the first sign change (or an exact zero)
//! and refines that bracket by bisection down to adjacent floating-point numbers. Bisection
//! halves the bracket every step, so it cannot diverge, and it needs no derivative: the equations
//! of the audit are cheap, and certainty matters more than speed here.

/// The first root of `f` on `[a, b]`, scanning `steps` equal subintervals from `a` towards `b`.
///
/// Returns `None` when no subinterval shows a sign change, when `f` is not finite at a grid
/// point, or when the interval or `steps` is degenerate. The root returned is the end of the
/// final bracket with the smaller `|f|`.
pub fn first_root(f: impl Fn(f64) -> f64, a: f64, b: f64, steps: usize) -> Option<f64> {
    if steps == 0 || !a.is_finite() || !b.is_finite() || b <= a {
        return None;
    }
    let h = (b - a) / steps as f64;
    let mut x0 = a;
    let mut f0 = f(x0);
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
        if f1 == 0.0 {
            return Some(x1);
        }
        if (f0 < 0.0) != (f1 < 0.0) {
            return Some(bisect(&f, x0, x1, f0));
        }
        x0 = x1;
        f0 = f1;
    }
    None
}

/// Bisection on a bracket `[lo, hi]` with `f(lo) = f_lo` of the opposite sign to `f(hi)`.
fn bisect(f: &impl Fn(f64) -> f64, mut lo: f64, mut hi: f64, mut f_lo: f64) -> f64 {
    let mut f_hi = f(hi);
    // 1100 halvings exhaust any double-precision bracket; the loop stops far earlier.
    for _ in 0..1100 {
        let mid = lo + 0.5 * (hi - lo);
        if mid <= lo || mid >= hi {
            break;
        }
        let fm = f(mid);
        if fm == 0.0 {
            return mid;
        }
        if (fm < 0.0) == (f_lo < 0.0) {
            lo = mid;
            f_lo = fm;
        } else {
            hi = mid;
            f_hi = fm;
        }
    }
    if f_lo.abs() <= f_hi.abs() {
        lo
    } else {
        hi
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

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
