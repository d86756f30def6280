//! Orientation bookkeeping: swing–twist decomposition and a continuous twist angle.
//!
//! A rotation `R` of A's frame is split as `R = R_swing · R_twist`, where `R_twist` turns about
//! the initial spine axis `ẑ` by the twist angle and `R_swing` tilts `ẑ` to `R ẑ` along the
//! great circle. For the unit quaternion `(w, x, y, z)` of `R`:
//!
//! $$ \text{twist} = 2\,\operatorname{atan2}(z, w), \qquad
//!    \text{swing} = 2\,\operatorname{atan2}\big(\sqrt{x^2 + y^2}, \sqrt{w^2 + z^2}\big), $$
//!
//! the swing being the angle between `ẑ` and `R ẑ`. Twist is signed, right-handed about `+ẑ`;
//! [`TwistTracker`] continues it past ±π along a history.

use std::f64::consts::{PI, TAU};

use nalgebra::UnitQuaternion;

/// Twist and swing of a rotation, rad.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SwingTwist {
    /// Signed twist about `+ẑ`, in `(−π, π]` unless continued by a [`TwistTracker`].
    pub twist: f64,
    /// Swing of the spine axis, in `[0, π]`.
    pub swing: f64,
}

/// Swing–twist decomposition of a rotation about `ẑ`.
pub fn swing_twist(r: &UnitQuaternion<f64>) -> SwingTwist {
    let (w, x, y, z) = (r.w, r.i, r.j, r.k);
    let mut twist = 2.0 * z.atan2(w);
    if twist > PI {
        twist -= TAU;
    } else if twist <= -PI {
        twist += TAU;
    }
    let swing = 2.0 * (x * x + y * y).sqrt().atan2((w * w + z * z).sqrt());
    SwingTwist { twist, swing }
}

/// Continues the twist angle along a sequence of nearby orientations.
#[derive(Clone, Copy, Debug, Default)]
pub struct TwistTracker {
    last: Option<f64>,
}

impl TwistTracker {
    /// The decomposition of `r` with the twist continued from the previous call's.
    pub fn update(&mut self, r: &UnitQuaternion<f64>) -> SwingTwist {
        let mut st = swing_twist(r);
        if let Some(prev) = self.last {
            st.twist += TAU * ((prev - st.twist) / TAU).round();
        }
        self.last = Some(st.twist);
        st
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;
    use nalgebra::{Unit, Vector3};

    #[test]
    fn composes_back() {
        // Build R = swing(about a horizontal axis) · twist(about z), then decompose.
        let twist = UnitQuaternion::from_axis_angle(&Vector3::z_axis(), 2.3);
        let axis = Unit::new_normalize(Vector3::new(0.3, -0.8, 0.0));
        let swing = UnitQuaternion::from_axis_angle(&axis, 0.7);
        let st = swing_twist(&(swing * twist));
        assert_relative_eq!(st.twist, 2.3, epsilon = 1e-14);
        assert_relative_eq!(st.swing, 0.7, epsilon = 1e-14);
    }

    #[test]
    fn tracker_continues_past_pi() {
        let mut tr = TwistTracker::default();
        let mut last = 0.0;
        for k in 0..=100 {
            let a = 4.0 * PI * k as f64 / 100.0;
            last = tr.update(&UnitQuaternion::from_axis_angle(&Vector3::z_axis(), a)).twist;
        }
        assert_relative_eq!(last, 4.0 * PI, epsilon = 1e-12);
    }
}
