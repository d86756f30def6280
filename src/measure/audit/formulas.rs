//! The paper's formulas, literal and corrected, as plain functions of the inertias and angles.
//!
//! Moments are per half, in kg·m², in the paper's §2 axes (`x` normal to the plane of the bend,
//! `y` in it and perpendicular to the bisector of `θ`, `z` along the bisector); angles in rad.
//! `transverse` is a half's `I_x'x' = I_y'y'`, `axial` its `I_z'z'`.

use crate::model::{BentMoments, Cylinder};

/// The transverse moment the paper's §6.3 code and §7 use, `m(r² + l²)/12` (the slip: the solid
/// cylinder's is `m(3r² + l²)/12`, [`Cylinder::transverse`]).
pub fn paper_transverse(cat: &Cylinder) -> f64 {
    cat.mass * (cat.radius.powi(2) + cat.length.powi(2)) / 12.0
}

/// The paper's §7 `I* = m(r² + 4l²)/12` (corrected: [`Cylinder::end_transverse`]).
pub fn paper_end_transverse(cat: &Cylinder) -> f64 {
    cat.mass * (cat.radius.powi(2) + 4.0 * cat.length.powi(2)) / 12.0
}

/// Principal moments per half about the *whole cat's* centre of mass: §3's values plus the
/// parallel-axis term `m (l/2)² sin²(θ/2)` on `x` and `z` (each half's centre lies `(l/2) sin(θ/2)`
/// from the cat's centre along `y`, so `I_yy` gets none).
pub fn whole_cat_moments(transverse: f64, axial: f64, mass: f64, length: f64, theta: f64) -> BentMoments {
    let b = BentMoments::new(transverse, axial, theta);
    let shift = mass * (0.5 * length * (0.5 * theta).sin()).powi(2);
    BentMoments { xx: b.xx + shift, yy: b.yy, zz: b.zz + shift }
}

/// §4's `C = 1 − 2 (I_zz/I_cc) sin(θ/2)` read with `I_zz = I_z'z'` and `I_cc` the code's `ic`,
/// the per-half `I_yy`.
pub fn c_section4(transverse: f64, axial: f64, theta: f64) -> f64 {
    let yy = BentMoments::new(transverse, axial, theta).yy;
    1.0 - 2.0 * axial * (0.5 * theta).sin() / yy
}

/// §7's ω line: `C = 1 − (I_z'z'/I_yy) sin²(θ/2)`.
pub fn c_worked_example(transverse: f64, axial: f64, theta: f64) -> f64 {
    let yy = BentMoments::new(transverse, axial, theta).yy;
    1.0 - axial * (0.5 * theta).sin().powi(2) / yy
}

/// The `−√` root (in the form below) of `(I_y − I_z) x² + k I_z x − I_y = 0`, i.e. of `k I_z x = I_yy(x)` with
/// `I_yy = I_y (1 − x²) + I_z x²` and `x = sin(θ/2)`, in the cancellation-free form
/// `x = I_y / (k I_z/2 + √((k I_z/2)² + I_y (I_y − I_z)))`.
///
/// For `k > 1` the residual is `−I_y < 0` at `x = 0` and `(k − 1) I_z > 0` at `x = 1`, and the
/// quadratic's other root lies outside `[−1, 1]`, so this is the only root in `(0, 1)`.
pub fn sin_half_root(transverse: f64, axial: f64, k: f64) -> Option<f64> {
    let b = 0.5 * k * axial;
    let disc = b * b + transverse * (transverse - axial);
    let x = transverse / (b + disc.sqrt());
    (disc >= 0.0 && x.is_finite() && (0.0..=1.0).contains(&x)).then_some(x)
}

/// §9's equation as printed, `(α + 1) (2 I_z'z'/I_yy(θ)) sin(θ/2) − 1` (zero at its root).
pub fn one_turn_residual_paper(transverse: f64, axial: f64, alpha: f64, theta: f64) -> f64 {
    let yy = BentMoments::new(transverse, axial, theta).yy;
    (alpha + 1.0) * 2.0 * axial * (0.5 * theta).sin() / yy - 1.0
}

/// `k` of [`sin_half_root`] for §9's equation as printed: `2(α + 1)`.
pub fn k_paper(alpha: f64) -> f64 {
    2.0 * (alpha + 1.0)
}

/// The condition consistent with the code's `C`: `C(θ) = α`, i.e. `I_z'z' sin(θ/2)/I_yy = 1 − α`,
/// as a residual `C(θ) − α` ([`crate::schedule::paper_c`]).
pub fn one_turn_residual_consistent(transverse: f64, axial: f64, alpha: f64, theta: f64) -> f64 {
    crate::schedule::paper_c(transverse, axial, theta) - alpha
}

/// `k` of [`sin_half_root`] for `C(θ) = α`: `1/(1 − α)`.
pub fn k_consistent(alpha: f64) -> f64 {
    1.0 / (1.0 - alpha)
}

/// §9's printed arcsin argument
/// `(I_z'z'(α + 1) + √(I_z'z'²(α + 1)² − I_y'y'(I_z'z' − I_y'y'))) / (I_z'z' − I_y'y')`;
/// `None` when the square root or the division is undefined.
pub fn one_turn_printed_argument(transverse: f64, axial: f64, alpha: f64) -> Option<f64> {
    let b = axial * (alpha + 1.0);
    let disc = b * b - transverse * (axial - transverse);
    let x = (b + disc.sqrt()) / (axial - transverse);
    (disc >= 0.0 && x.is_finite()).then_some(x)
}

/// `2 arcsin(x)`, rad, or `None` when `x` is outside `[−1, 1]`.
pub fn theta_from_sin_half(x: f64) -> Option<f64> {
    (-1.0..=1.0).contains(&x).then(|| 2.0 * x.asin())
}

/// The smallest `θ` (rad) from which `y` is the least principal axis, `I_zz − I_yy ≥ 0`, where
/// `I_zz − I_yy = −(I_x'x' − I_z'z') cos θ + (shift/2)(1 − cos θ)` and `shift = m l²/4` is the
/// parallel-axis coefficient (0 in §3's own model). `None` unless `I_x'x' > I_z'z'`, which §3's
/// argument assumes (then the difference grows with `θ`).
pub fn stability_threshold(transverse: f64, axial: f64, shift: f64) -> Option<f64> {
    let d = transverse - axial;
    let h = 0.5 * shift;
    (d > 0.0 && h >= 0.0).then(|| (h / (d + h)).acos())
}

/// Which principal axis `y` is for given moments: least, greatest or intermediate, or tied with
/// another when the two moments agree to round-off (`10⁻¹²` of the largest: §3's model at
/// θ = 90°, where `I_zz − I_yy = −(I_x'x' − I_z'z') cos θ` is `10⁻¹⁷` with either sign).
pub fn y_axis_rank(b: &BentMoments) -> &'static str {
    let tie = 1e-12 * b.xx.abs().max(b.yy.abs()).max(b.zz.abs());
    if (b.yy - b.xx).abs() <= tie || (b.yy - b.zz).abs() <= tie {
        "neutral (its moment equal to another's to round-off)"
    } else if b.yy <= b.xx.min(b.zz) {
        "least (stable)"
    } else if b.yy >= b.xx.max(b.zz) {
        "greatest (stable)"
    } else {
        "intermediate (unstable)"
    }
}

/// The classic peak of `I* · d²/dt² [A (1 − cos(π t/T))]`: `I* A π²/T²`.
pub fn cosine_peak_torque(i_star: f64, amplitude: f64, duration: f64) -> f64 {
    i_star * amplitude * (std::f64::consts::PI / duration).powi(2)
}

/// The first root in `θ ∈ [0, π]` of a residual, by [`crate::numeric::roots::first_root`] on 720 steps.
pub fn first_root_theta(f: impl Fn(f64) -> f64) -> Option<f64> {
    crate::numeric::roots::first_root(f, 0.0, std::f64::consts::PI, 720)
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    #[test]
    fn a_y_moment_equal_to_another_to_round_off_is_neutral() {
        let m = |yy: f64| BentMoments { xx: 0.3, yy, zz: 0.2 };
        // Either side of I_zz within the tie (3e-13 here), and just outside it.
        assert_eq!(y_axis_rank(&m(0.2 + 2e-13)), "neutral (its moment equal to another's to round-off)");
        assert_eq!(y_axis_rank(&m(0.2 - 2e-13)), "neutral (its moment equal to another's to round-off)");
        assert_eq!(y_axis_rank(&m(0.2 - 1e-12)), "least (stable)");
        assert_eq!(y_axis_rank(&m(0.1)), "least (stable)");
        assert_eq!(y_axis_rank(&m(0.25)), "intermediate (unstable)");
        assert_eq!(y_axis_rank(&m(0.4)), "greatest (stable)");
    }

    #[test]
    fn stability_threshold_of_the_papers_model_is_a_right_angle() {
        let t = stability_threshold(0.3, 0.05, 0.0).unwrap_or(f64::NAN);
        assert_relative_eq!(t, std::f64::consts::FRAC_PI_2, max_relative = 1e-15);
        assert!(stability_threshold(0.05, 0.3, 0.1).is_none());
    }

    #[test]
    fn sin_half_root_with_k_one_includes_the_straight_cat() {
        // k = 1: k I_z x = I_yy holds at x = 1 (I_yy = I_z there); for I_y ≥ I_z that is the root
        // returned, for I_y < I_z the smaller root I_y/(I_z − I_y) (product of the roots) comes first.
        for (it, ia, want) in [(0.3, 0.05, 1.0), (0.2, 0.2, 1.0), (0.05, 0.3, 0.2)] {
            assert_relative_eq!(sin_half_root(it, ia, 1.0).unwrap_or(f64::NAN), want, max_relative = 1e-14);
        }
    }

    #[test]
    fn printed_argument_is_the_other_root_of_the_quadratic() {
        // Product of the roots of (I_y − I_z) x² + k I_z x − I_y = 0 is −I_y/(I_y − I_z).
        let (it, ia, alpha) = (1.01 / 12.0, 0.005, 0.5);
        let good = sin_half_root(it, ia, k_paper(alpha)).unwrap_or(f64::NAN);
        let other = one_turn_printed_argument(it, ia, alpha).unwrap_or(f64::NAN);
        assert_relative_eq!(good * other, -it / (it - ia), max_relative = 1e-13);
    }
}
