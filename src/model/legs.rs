//! The cat's legs: two on each half's belly, the ones the plots draw and the landing's colliders
//! touch the ground with. Their direction defines "feet down".
//!
//! In a half's body frame (centre of mass at the origin, `z` along the spine to the head, length
//! `l`, radius `r`, `h = l/2`), the belly is `+y` (the inside of the bend). Each half carries two
//! legs, sides `s = ±1`, at the axial station `z_leg` (`+0.55 h` on A, the front legs; `−0.55 h`
//! on B, the hind legs): a leg runs from its hip on the surface,
//!
//! $$ \text{hip} = (s\,r/2,\; 0.87\,r,\; z_{leg}), \qquad
//!    \text{paw} = \text{hip} + 0.9\,h\,\frac{(0.2 s,\, 1,\, 0)}{\lVert(0.2 s, 1, 0)\rVert}, $$
//!
//! slightly splayed; the mean of a half's two legs points along `+y`. A half stands on its feet
//! when its `+y` points along gravity. Pure geometry: the legs carry no mass (the halves'
//! inertias are the cylinders').

use nalgebra::Vector3;

use super::Cylinder;

/// Which half a leg belongs to.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Half {
    /// The front half A.
    A,
    /// The rear half B.
    B,
}

/// Axial station of a half's legs as a fraction of its half length (`+` on A, `−` on B).
pub const LEG_STATION: f64 = 0.55;
/// Radius of a paw's drawn disc and of a leg's collider, as a fraction of the cat's radius.
pub const PAW_RADIUS: f64 = 0.45;

/// One leg in its half's body frame, m.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Leg {
    /// Where it leaves the body.
    pub hip: Vector3<f64>,
    /// Its far end.
    pub paw: Vector3<f64>,
}

/// The two legs of `half` (sides −1 then +1), in that half's body frame.
pub fn legs(cat: &Cylinder, half: Half) -> [Leg; 2] {
    let h = 0.5 * cat.length;
    let r = cat.radius;
    let z = match half {
        Half::A => LEG_STATION * h,
        Half::B => -LEG_STATION * h,
    };
    [-1.0, 1.0].map(|s| {
        let hip = Vector3::new(s * 0.5 * r, 0.87 * r, z);
        Leg { hip, paw: hip + 0.9 * h * Vector3::new(0.2 * s, 1.0, 0.0).normalize() }
    })
}

/// The direction the feet point in a half's body frame: the legs' mean direction.
pub fn feet_direction() -> Vector3<f64> {
    Vector3::y()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The legs' mean direction is `+y`, their sides mirror each other.
    #[test]
    fn the_legs_point_along_the_belly() {
        let cat = Cylinder::default();
        for half in [Half::A, Half::B] {
            let [l, r] = legs(&cat, half);
            let mean = (l.paw - l.hip + r.paw - r.hip).normalize();
            assert!((mean - feet_direction()).norm() < 1e-15, "{mean:?}");
            assert!((l.hip.x + r.hip.x).abs() < 1e-15 && (l.paw.x + r.paw.x).abs() < 1e-15);
        }
    }
}
