//! The two-cylinder cat: mass properties of each half and of the whole.
//!
//! Each half is a solid cylinder of mass `m`, length `l` and radius `r`, with its body frame at
//! its centre of mass and `z` along its axis, pointing to the head. About that centre,
//!
//! $$ I = \operatorname{diag}\big(m(3r^2 + l^2)/12,\; m(3r^2 + l^2)/12,\; m r^2/2\big). $$
//!
//! The halves are joined by a universal joint at A's rear end `(0, 0, -l/2)` and B's front end
//! `(0, 0, +l/2)`; B relative to A is `R_AB(q) = Rx(q1) · Ry(q2)`. Vectors returned by this
//! module are expressed in A's body frame unless a name says otherwise. SI units throughout.
//!
//! ## References
//! - the paper, §2–§3 and §7 (`../shared/paper/cat-flipping.txt`);
//! - any table of moments of inertia for the solid cylinder.

use nalgebra::{Matrix3, Rotation3, Vector3};
use serde::{Deserialize, Serialize};

/// One half of the cat: a solid, uniform cylinder.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct Cylinder {
    /// Mass of one half, kg.
    pub mass: f64,
    /// Length of one half, m.
    pub length: f64,
    /// Radius of one half, m.
    pub radius: f64,
}

impl Default for Cylinder {
    fn default() -> Self {
        Self { mass: 1.0, length: 1.0, radius: 0.1 }
    }
}

impl Cylinder {
    /// The cylinder whose mass, length and radius are the means of this one's and `other`'s.
    pub fn mean(&self, other: &Cylinder) -> Cylinder {
        Cylinder {
            mass: 0.5 * (self.mass + other.mass),
            length: 0.5 * (self.length + other.length),
            radius: 0.5 * (self.radius + other.radius),
        }
    }

    /// Moment of inertia about a transverse axis through the centre of mass,
    /// `m(3r² + l²)/12`, kg·m².
    pub fn transverse(&self) -> f64 {
        self.mass * (3.0 * self.radius.powi(2) + self.length.powi(2)) / 12.0
    }

    /// Moment of inertia about the cylinder's own axis, `m r²/2`, kg·m².
    pub fn axial(&self) -> f64 {
        0.5 * self.mass * self.radius.powi(2)
    }

    /// Moment of inertia about a transverse axis through one end (parallel axis theorem),
    /// `m(3r² + 4l²)/12`: the paper's `I*`, corrected.
    pub fn end_transverse(&self) -> f64 {
        self.transverse() + self.mass * (0.5 * self.length).powi(2)
    }

    /// The inertia tensor about the centre of mass in the body frame.
    pub fn inertia(&self) -> Matrix3<f64> {
        let t = self.transverse();
        Matrix3::from_diagonal(&Vector3::new(t, t, self.axial()))
    }

    /// Whether the paper's stability assumption `L ≥ √3 R` (so that `I_x'x' ≥ I_z'z'`) holds.
    pub fn is_long_enough(&self) -> bool {
        self.length >= 3f64.sqrt() * self.radius
    }
}

/// Rotation about the x axis by `a` radians.
pub fn rot_x(a: f64) -> Matrix3<f64> {
    Rotation3::from_axis_angle(&Vector3::x_axis(), a).into_inner()
}

/// Rotation about the y axis by `a` radians.
pub fn rot_y(a: f64) -> Matrix3<f64> {
    Rotation3::from_axis_angle(&Vector3::y_axis(), a).into_inner()
}

/// The joint rotation `R_AB(q) = Rx(q1) · Ry(q2)`: B's frame in A's frame.
pub fn joint_rotation(q: [f64; 2]) -> Matrix3<f64> {
    rot_x(q[0]) * rot_y(q[1])
}

/// Skew-symmetric matrix `[v]×` with `[v]× w = v × w`.
pub fn skew(v: &Vector3<f64>) -> Matrix3<f64> {
    v.cross_matrix()
}

/// Mass properties of the whole cat in a given joint configuration, in A's frame.
#[derive(Clone, Copy, Debug)]
pub struct Configuration {
    /// `R_AB(q)`.
    pub rotation: Matrix3<f64>,
    /// B's inertia about its centre, in A's frame: `R_AB I_B R_ABᵀ`.
    pub inertia_b: Matrix3<f64>,
    /// Position of B's centre relative to A's centre, `p`.
    pub offset: Vector3<f64>,
    /// Locked inertia of the whole cat about the common centre of mass,
    /// `I_A + R I_B Rᵀ − μ [p]×²` with `μ = m/2`.
    pub locked_inertia: Matrix3<f64>,
}

impl Cylinder {
    /// Mass properties of the two-cylinder cat at joint angles `q`.
    pub fn configuration(&self, q: [f64; 2]) -> Configuration {
        let rotation = joint_rotation(q);
        let inertia = self.inertia();
        let inertia_b = rotation * inertia * rotation.transpose();
        let offset = self.offset(&rotation);
        let mu = self.reduced_mass();
        let px = skew(&offset);
        let locked_inertia = inertia + inertia_b - mu * px * px;
        Configuration { rotation, inertia_b, offset, locked_inertia }
    }

    /// Reduced mass of the two halves, `μ = m/2`.
    pub fn reduced_mass(&self) -> f64 {
        0.5 * self.mass
    }

    /// B's centre relative to A's centre: `p = (0,0,−l/2) − R_AB (0,0,l/2)`.
    pub fn offset(&self, rotation: &Matrix3<f64>) -> Vector3<f64> {
        let half = 0.5 * self.length;
        Vector3::new(0.0, 0.0, -half) - rotation * Vector3::new(0.0, 0.0, half)
    }
}

/// Principal moments of the *bent* two-cylinder cat as the paper's §2–§3 define them, per half,
/// for halves meeting at angle `θ` (π = straight), in the paper's axes (`y` in the plane of the bend,
/// perpendicular to the bisector of θ and through both halves' centres; `z` along the bisector;
/// `x` normal to the plane of the bend).
///
/// `transverse` and `axial` are the half's `I_x'x' = I_y'y'` and `I_z'z'`; passing the paper's
/// slipped `m(r² + l²)/12` reproduces its numbers, passing [`Cylinder::transverse`] corrects them.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct BentMoments {
    /// `I_xx = I_x'x'`.
    pub xx: f64,
    /// `I_yy = I_y'y' cos²(θ/2) + I_z'z' sin²(θ/2)`.
    pub yy: f64,
    /// `I_zz = I_y'y' sin²(θ/2) + I_z'z' cos²(θ/2)`.
    pub zz: f64,
}

impl BentMoments {
    /// The paper's §3 principal values for one half at bend angle `theta` (radians).
    pub fn new(transverse: f64, axial: f64, theta: f64) -> Self {
        let (s, c) = (0.5 * theta).sin_cos();
        Self { xx: transverse, yy: transverse * c * c + axial * s * s, zz: transverse * s * s + axial * c * c }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    /// A cylinder's inertia by direct numerical quadrature over its volume (midpoint rule in
    /// cylindrical coordinates): a second derivation of the closed forms.
    fn quadrature_inertia(c: &Cylinder) -> (f64, f64) {
        let (nr, nth, nz) = (60, 64, 60);
        let vol = std::f64::consts::PI * c.radius.powi(2) * c.length;
        let rho = c.mass / vol;
        let (mut ixx, mut izz) = (0.0, 0.0);
        for i in 0..nr {
            let r = (i as f64 + 0.5) / nr as f64 * c.radius;
            let dr = c.radius / nr as f64;
            for j in 0..nth {
                let th = (j as f64 + 0.5) / nth as f64 * std::f64::consts::TAU;
                let dth = std::f64::consts::TAU / nth as f64;
                for k in 0..nz {
                    let z = ((k as f64 + 0.5) / nz as f64 - 0.5) * c.length;
                    let dv = r * dr * dth * c.length / nz as f64;
                    let (y, x) = (r * th.sin(), r * th.cos());
                    let _ = x;
                    ixx += rho * dv * (y * y + z * z);
                    izz += rho * dv * r * r;
                }
            }
        }
        (ixx, izz)
    }

    #[test]
    fn cylinder_inertia_matches_volume_quadrature() {
        let c = Cylinder { mass: 2.0, length: 0.7, radius: 0.3 };
        let (ixx, izz) = quadrature_inertia(&c);
        // Midpoint quadrature error is O(h²) ≈ 1e-4 relative at these resolutions.
        assert_relative_eq!(c.transverse(), ixx, max_relative = 1e-3);
        assert_relative_eq!(c.axial(), izz, max_relative = 1e-3);
    }

    #[test]
    fn end_inertia_is_parallel_axis() {
        // Hand calculation: m = 1, l = 1, r = 0.1 → (3·0.01 + 4)/12 = 0.335833…
        let c = Cylinder::default();
        assert_relative_eq!(c.end_transverse(), 4.03 / 12.0, max_relative = 1e-15);
    }

    #[test]
    fn straight_cat_locked_inertia_is_two_cylinders_end_to_end() {
        // A straight cat is one cylinder of mass 2m, length 2l: transverse 2m(3r² + 4l²)/12.
        let c = Cylinder { mass: 1.5, length: 0.8, radius: 0.12 };
        let whole = Cylinder { mass: 3.0, length: 1.6, radius: 0.12 };
        let cfg = c.configuration([0.0, 0.0]);
        assert_relative_eq!(cfg.locked_inertia, whole.inertia(), max_relative = 1e-14);
    }

    #[test]
    fn bent_moments_rotate_the_tensor() {
        // I_yy of the paper is ŷᵀ I' ŷ with ŷ = (0, cos θ/2, sin θ/2) in the half's principal axes.
        let (t, a, theta) = (0.3, 0.05, 1.1);
        let b = BentMoments::new(t, a, theta);
        let y = Vector3::new(0.0, (0.5 * theta).cos(), (0.5 * theta).sin());
        let i = Matrix3::from_diagonal(&Vector3::new(t, t, a));
        assert_relative_eq!(b.yy, (y.transpose() * i * y)[0], max_relative = 1e-14);
        assert_relative_eq!(b.yy + b.zz, t + a, max_relative = 1e-14);
    }
}
