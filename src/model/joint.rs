//! The joint between two bodies: its rotation `R(q)`, relative rate and motor axes (DESIGN.md §10).
//!
//! A joint turns the child's frame relative to the parent's by `R(q)`; its relative angular
//! velocity `ω_rel` is defined by `Ṙ Rᵀ = [ω_rel]×` (the parent's frame), and `ω̇_rel` is the
//! derivative of its parent-frame components. Three joints:
//!
//! - **universal** (the paper's, catflip's first model), `q = (q1, q2)`:
//!   `R = Rx(q1) Ry(q2)`, `ω_rel = q̇1 x̂ + q̇2 Rx(q1) ŷ`,
//!   `ω̇_rel = q̈1 x̂ + q̈2 Rx(q1) ŷ + q̇1 q̇2 x̂ × Rx(q1) ŷ`; motors on `x̂` and `Rx(q1) ŷ`.
//! - **no-twist** (Kane and Scher 1969, a constant-velocity joint), `q = (q1, q2)` the rotation
//!   vector `v = (q1, q2, 0)` of the child relative to the parent, perpendicular to the spine:
//!   `R = exp([v]×) = 𝟙 + (sin θ/θ)[v]× + a [v]×²`, `θ = |v|` the bend, and
//!   `ω_rel = J(v) v̇ = v̇ + a v × v̇ + b v × (v × v̇)` (the left Jacobian of SO(3)) with
//!   `a = (1 − cos θ)/θ²`, `b = (θ − sin θ)/θ³`; its derivative
//!   `ω̇_rel = J v̈ + ȧ v × v̇ + ḃ v × (v × v̇) + b v̇ × (v × v̇)`, `ȧ = (a'/θ)(v·v̇)`,
//!   `ḃ = (b'/θ)(v·v̇)`. The child's spine `R ẑ` makes the angle `θ` with the parent's, and the
//!   halves never twist relative to each other. Motors on the parent's `x̂` and `ŷ`.
//! - **hinge** (an appendage's, one motor), `q = (q1)`: `R = Rx(q1)`, `ω_rel = q̇1 x̂`,
//!   `ω̇_rel = q̈1 x̂`; its motor on `x̂`. Not a joint between the halves (a cat bent in one plane
//!   cannot turn over at zero momentum): the legs' hips ([`crate::model::cat::Appendages`]) and a
//!   one-motor tail.
//! - **spherical** (the paper's words), `q = (q1, q2, q3)`: `R = exp([v]×) Rz(q3)`, the no-twist
//!   joint followed by a relative twist `q3` about the child's spine `e = exp([v]×) ẑ`:
//!   `ω_rel = J(v) v̇ + q̇3 e`, `ω̇_rel = (no-twist) + q̈3 e + q̇3 (J v̇) × e`. Motors on `x̂`,
//!   `ŷ` and `e` (the three are dependent at a bend of exactly 90°, where `e ⊥ ẑ`).
//!
//! The coefficients `a, b` and `a'/θ, b'/θ` are taken from their Taylor series below `θ = 1`
//! (no cancellation near the straight cat) and in closed form above. Angles in rad.
//!
//! ## References
//! - T. R. Kane and M. P. Scher, *A dynamical explanation of the falling cat phenomenon*,
//!   Int. J. Solids Structures 5 (1969) 663–670 (the no-twist joint);
//! - G. S. Chirikjian, *Stochastic Models, Information Theory, and Lie Groups*, vol. 2 (2012),
//!   §10.6 (the Jacobians of the exponential map).

use nalgebra::{Matrix3, Vector3};
use serde::{Deserialize, Serialize};

use crate::model::{joint_rotation, rot_x};

/// How the two halves are joined.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Joint {
    /// `R = Rx(q1) Ry(q2)`: the paper's universal joint, which twists the halves as it bends.
    #[default]
    Universal,
    /// `R = exp([q1, q2, 0]×)`: Kane and Scher's joint, which bends and never twists.
    NoTwist,
    /// `R = exp([q1, q2, 0]×) Rz(q3)`: bend and relative twist about the child's spine.
    Spherical,
    /// `R = Rx(q1)`: one motor about the parent's `x` (an appendage's joint, never the halves').
    Hinge,
}

impl Joint {
    /// Every joint between the halves, in the order of the problem file's documentation
    /// ([`Joint::Hinge`] is an appendage's alone).
    pub const ALL: [Joint; 3] = [Joint::Universal, Joint::NoTwist, Joint::Spherical];

    /// The name in problem files: `universal`, `no-twist`, `spherical`, `hinge`.
    pub fn name(self) -> &'static str {
        match self {
            Joint::Universal => "universal",
            Joint::NoTwist => "no-twist",
            Joint::Spherical => "spherical",
            Joint::Hinge => "hinge",
        }
    }

    /// Number of shape coordinates (and motors): 2, 2, 3, 1.
    pub fn dof(self) -> usize {
        match self {
            Joint::Universal | Joint::NoTwist => 2,
            Joint::Spherical => 3,
            Joint::Hinge => 1,
        }
    }

    /// The child's frame in the parent's, `R(q)`; `q` holds [`Joint::dof`] coordinates.
    pub fn rotation(self, q: &[f64]) -> Matrix3<f64> {
        match self {
            Joint::Universal => joint_rotation([q[0], q[1]]),
            Joint::NoTwist => exp_so3(&bend_vector(q)),
            Joint::Spherical => exp_so3(&bend_vector(q)) * rot_z(q[2]),
            Joint::Hinge => rot_x(q[0]),
        }
    }

    /// `ω_rel` in the parent's frame for coordinates `q` and rates `qd`.
    pub fn relative_rate(self, q: &[f64], qd: &[f64]) -> Vector3<f64> {
        match self {
            Joint::Universal => {
                let (s, c) = q[0].sin_cos();
                Vector3::new(qd[0], qd[1] * c, qd[1] * s)
            }
            Joint::NoTwist => exp_rate(&bend_vector(q), &bend_vector(qd)),
            Joint::Spherical => {
                let v = bend_vector(q);
                exp_rate(&v, &bend_vector(qd)) + spine(&v) * qd[2]
            }
            Joint::Hinge => Vector3::x() * qd[0],
        }
    }

    /// `ω̇_rel`, the derivative of [`Joint::relative_rate`]'s parent-frame components.
    pub fn relative_accel(self, q: &[f64], qd: &[f64], qdd: &[f64]) -> Vector3<f64> {
        match self {
            Joint::Universal => {
                let a2 = rot_x(q[0]) * Vector3::y();
                Vector3::x() * qdd[0] + a2 * qdd[1] + Vector3::x().cross(&a2) * (qd[0] * qd[1])
            }
            Joint::NoTwist => exp_accel(&bend_vector(q), &bend_vector(qd), &bend_vector(qdd)),
            Joint::Spherical => {
                let (v, vd) = (bend_vector(q), bend_vector(qd));
                let e = spine(&v);
                exp_accel(&v, &vd, &bend_vector(qdd)) + e * qdd[2] + exp_rate(&v, &vd).cross(&e) * qd[2]
            }
            Joint::Hinge => Vector3::x() * qdd[0],
        }
    }

    /// The motor axes in the parent's frame, one per coordinate: the joint's torque on the child
    /// is reported as its projections on these.
    pub fn motor_axes(self, q: &[f64]) -> Vec<Vector3<f64>> {
        match self {
            Joint::Universal => vec![Vector3::x(), rot_x(q[0]) * Vector3::y()],
            Joint::NoTwist => vec![Vector3::x(), Vector3::y()],
            Joint::Spherical => vec![Vector3::x(), Vector3::y(), spine(&bend_vector(q))],
            Joint::Hinge => vec![Vector3::x()],
        }
    }

    /// The [`Joint::motor_axes`] in words, one per coordinate (`A's x`, `the cross's y`, …), for
    /// labels.
    pub fn motor_axis_names(self) -> &'static [&'static str] {
        match self {
            Joint::Universal => &["A's x", "the cross's y"],
            Joint::NoTwist => &["A's x", "A's y"],
            Joint::Spherical => &["A's x", "A's y", "B's spine"],
            Joint::Hinge => &["A's x"],
        }
    }
}

impl std::fmt::Display for Joint {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

/// The bend's rotation vector `(q1, q2, 0)`.
fn bend_vector(q: &[f64]) -> Vector3<f64> {
    Vector3::new(q[0], q[1], 0.0)
}

/// Rotation about the z axis by `a` radians.
fn rot_z(a: f64) -> Matrix3<f64> {
    let (s, c) = a.sin_cos();
    Matrix3::new(c, -s, 0.0, s, c, 0.0, 0.0, 0.0, 1.0)
}

/// The child's spine `exp([v]×) ẑ` for the bend vector `v`.
fn spine(v: &Vector3<f64>) -> Vector3<f64> {
    exp_so3(v) * Vector3::z()
}

/// Below this angle the coefficients come from their Taylor series.
const SERIES_BELOW: f64 = 1.0;

/// Terms of each Taylor series: the `k`-th term of each is below `1/(2k + 3)!`, which for
/// `k = 12` is `< 1e-28`.
const SERIES_TERMS: i32 = 12;

/// `Σ_k (−1)^k c_k θ^{2k}` for `c_k = 1/f(k)`.
fn series(theta2: f64, f: impl Fn(i32) -> f64) -> f64 {
    (0..SERIES_TERMS).rev().fold(0.0, |acc, k| acc * -theta2 + 1.0 / f(k))
}

/// `n!` as a float.
fn factorial(n: i32) -> f64 {
    (1..=n).map(f64::from).product()
}

/// The coefficients of the exponential map at angle `θ`: `sin θ/θ`, `a = (1 − cos θ)/θ²`,
/// `b = (θ − sin θ)/θ³`, `a'(θ)/θ` and `b'(θ)/θ`.
#[derive(Clone, Copy, Debug)]
struct ExpCoefficients {
    sinc: f64,
    a: f64,
    b: f64,
    da_over_theta: f64,
    db_over_theta: f64,
}

impl ExpCoefficients {
    fn at(theta: f64) -> ExpCoefficients {
        let t2 = theta * theta;
        if theta < SERIES_BELOW {
            // sin θ/θ = Σ (−1)^k θ^{2k}/(2k+1)!, a = Σ (−1)^k θ^{2k}/(2k+2)!,
            // b = Σ (−1)^k θ^{2k}/(2k+3)!; a'/θ = Σ_k≥1 (−1)^k 2k θ^{2k−2}/(2k+2)!, likewise b'.
            ExpCoefficients {
                sinc: series(t2, |k| factorial(2 * k + 1)),
                a: series(t2, |k| factorial(2 * k + 2)),
                b: series(t2, |k| factorial(2 * k + 3)),
                da_over_theta: -series(t2, |k| factorial(2 * k + 4) / f64::from(2 * k + 2)),
                db_over_theta: -series(t2, |k| factorial(2 * k + 5) / f64::from(2 * k + 2)),
            }
        } else {
            let (s, c) = theta.sin_cos();
            let a = (1.0 - c) / t2;
            let b = (theta - s) / (t2 * theta);
            ExpCoefficients {
                sinc: s / theta,
                a,
                b,
                // a' = (sin θ/θ − 2a)/θ and b' = (a − 3b)/θ, by differentiating a and b.
                da_over_theta: (s / theta - 2.0 * a) / t2,
                db_over_theta: (a - 3.0 * b) / t2,
            }
        }
    }
}

/// `exp([v]×) = 𝟙 + (sin θ/θ)[v]× + a [v]×²` (Rodrigues), `θ = |v|`.
pub fn exp_so3(v: &Vector3<f64>) -> Matrix3<f64> {
    let k = ExpCoefficients::at(v.norm());
    let x = v.cross_matrix();
    Matrix3::identity() + x * k.sinc + x * x * k.a
}

/// The spherical joint's coordinates `(q1, q2, q3)` of the child's frame `r` in the parent's: the
/// inverse of [`Joint::rotation`] for [`Joint::Spherical`], the swing that takes the parent's
/// spine `ẑ` to the child's `e = r ẑ` along the shortest arc, then the twist about `e`. The bend
/// `|(q1, q2)| = atan2(|ẑ × e|, e_z)` is below π unless the child's spine points straight back
/// (there the swing's axis is undefined and `(q1, q2)` is zero); the twist `q3` is the one of its
/// values `+ 2kπ` nearest `twist_near` (a path's previous value keeps it continuous).
pub fn spherical_coordinates(r: &Matrix3<f64>, twist_near: f64) -> [f64; 3] {
    let e = r * Vector3::z();
    let across = e.x.hypot(e.y);
    // atan2(|ẑ × e|, e_z)/|ẑ × e| → 1/e_z = 1 as the bend vanishes.
    let per_unit = if across > 0.0 { across.atan2(e.z) / across } else { 1.0 };
    let v = Vector3::new(-e.y, e.x, 0.0) * per_unit;
    let twist = exp_so3(&-v) * r;
    let q3 = twist[(1, 0)].atan2(twist[(0, 0)]);
    let turns = ((twist_near - q3) / std::f64::consts::TAU).round();
    [v.x, v.y, q3 + turns * std::f64::consts::TAU]
}

/// `J(v) v̇ = v̇ + a v × v̇ + b v × (v × v̇)`: the angular velocity, fixed frame, of `exp([v]×)`.
pub fn exp_rate(v: &Vector3<f64>, vd: &Vector3<f64>) -> Vector3<f64> {
    let k = ExpCoefficients::at(v.norm());
    let c = v.cross(vd);
    vd + c * k.a + v.cross(&c) * k.b
}

/// The derivative of [`exp_rate`] along `v(t)` with rates `vd` and accelerations `vdd`.
pub fn exp_accel(v: &Vector3<f64>, vd: &Vector3<f64>, vdd: &Vector3<f64>) -> Vector3<f64> {
    let k = ExpCoefficients::at(v.norm());
    let c = v.cross(vd);
    let vvd = v.dot(vd);
    vdd + (v.cross(vdd) * k.a + v.cross(&v.cross(vdd)) * k.b)
        + c * (k.da_over_theta * vvd)
        + v.cross(&c) * (k.db_over_theta * vvd)
        + vd.cross(&c) * k.b
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    #[test]
    fn series_and_closed_forms_meet_at_the_switch() {
        let below = ExpCoefficients::at(SERIES_BELOW * (1.0 - 1e-15));
        let above = ExpCoefficients::at(SERIES_BELOW);
        for (x, y) in [
            (below.sinc, above.sinc),
            (below.a, above.a),
            (below.b, above.b),
            (below.da_over_theta, above.da_over_theta),
            (below.db_over_theta, above.db_over_theta),
        ] {
            assert_relative_eq!(x, y, max_relative = 1e-13);
        }
    }

    /// The spherical joint's coordinates of its own rotation are the coordinates (bends up to
    /// 168°, a straight cat, a twist beyond π taken near its previous value), and of the universal
    /// joint's rotation they give that rotation back.
    #[test]
    fn spherical_coordinates_invert_the_spherical_rotation() {
        let cases = [[0.3, -1.2, 0.4], [1e-9, -2e-9, 1e-3], [0.0, 0.0, -0.7], [2.9, 0.4, 3.5], [-0.2, 0.1, -2.0]];
        for q in cases {
            let r = Joint::Spherical.rotation(&q);
            let back = spherical_coordinates(&r, q[2] + 0.5);
            for (b, q) in back.iter().zip(q) {
                assert_relative_eq!(*b, q, epsilon = 1e-12);
            }
        }
        for q in [[0.4, -0.9], [1.2, 0.7], [1e-7, 3e-7]] {
            let r = Joint::Universal.rotation(&q);
            assert_relative_eq!(Joint::Spherical.rotation(&spherical_coordinates(&r, 0.0)), r, epsilon = 1e-14);
        }
    }

    #[test]
    fn exp_so3_is_nalgebras_rotation() {
        for v in [Vector3::new(0.3, -1.2, 0.0), Vector3::new(1e-4, 2e-4, 0.0), Vector3::new(2.5, 0.4, 0.0)] {
            let r = nalgebra::Rotation3::from_scaled_axis(v).into_inner();
            assert_relative_eq!(exp_so3(&v), r, epsilon = 1e-15);
        }
    }
}
