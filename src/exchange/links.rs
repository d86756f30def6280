//! The cat's links, the numbers the model files ([`mod@crate::exchange::urdf`],
//! [`mod@crate::exchange::mjcf`]) write: A, the cross of the universal joint, B. On the no-twist
//! joint (a ball joint in the files) there is no cross: the files write A and B only, and the
//! cross's entries are not used.
//!
//! - **A** and **B**: each half's mass `m`, inertia about its centre of mass
//!   `diag(m(3r² + l²)/12, m(3r² + l²)/12, m r²/2)` in its body frame (`z` along the spine,
//!   towards the head), from its own [`Cylinder`] (the halves may differ, DESIGN.md §10);
//! - **the cross**: the same tiny body the rapier scene uses ([`MassModel`]): mass
//!   `f · m̄` with `f = rapier.cross_mass_fraction` and `m̄` the halves' mean mass, and the inertia
//!   `(2/5) f m̄ r̄²` of a solid sphere of their mean radius with that mass. A real universal joint's cross is massless; simulators
//!   need a body with positive mass between two revolute joints, and at `f = 10⁻⁶` it changes
//!   the flip by far less than the engines' tolerances;
//! - the universal joint: joint 1 about A's `x` at A's `(0, 0, −l_A/2)`, joint 2 about the
//!   cross's `y` at the same point, which is B's `(0, 0, +l_B/2)`: `R_AB = Rx(q1) · Ry(q2)`;
//! - the no-twist joint: B turns about the same point, `R_AB = exp([q1, q2, 0]×)`.
//!
//! Numbers are written with Rust's shortest round-trip formatting, so a parser reads back the
//! very `f64` written.

use crate::engines::rapier::MassModel;
use crate::model::{Cat, Cylinder, Joint};

/// Mass properties and geometry of the links (A, the cross, B), SI units.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Links {
    /// The front half A and the rear half B.
    pub halves: [Cylinder; 2],
    /// How B hangs from A (the model files build the universal and no-twist joints).
    pub joint: Joint,
    /// Masses of A, the cross and B, kg.
    pub mass: [f64; 3],
    /// Principal moments `(I_x, I_y, I_z)` of A, the cross and B about their centres, kg·m².
    pub inertia: [[f64; 3]; 3],
}

impl Links {
    /// The links of `cat` with a cross of mass `cross_mass_fraction · m̄` (as in the rapier
    /// scene; written on the universal joint only).
    ///
    /// # Panics
    /// On a [`Joint::Hinge`] between the halves, which no cat has (the problem file refuses
    /// `cat.joint = "hinge"`): the two-body files join the halves by the universal joint's two
    /// hinges or a ball.
    pub fn new(cat: &Cat, cross_mass_fraction: f64) -> Links {
        assert!(cat.joint != Joint::Hinge, "the halves are never joined by a hinge (an appendage's joint)");
        let masses = MassModel::new(cat, cross_mass_fraction);
        Links { halves: [cat.front, cat.rear], joint: cat.joint, mass: masses.mass, inertia: masses.inertia }
    }

    /// Whether the model files have a cross (the universal joint's two revolute joints).
    pub fn has_cross(&self) -> bool {
        self.joint == Joint::Universal
    }

    /// Half of each half's length, `(l_A/2, l_B/2)`, m: the joint point is `(0, 0, −l_A/2)` in A
    /// and `(0, 0, +l_B/2)` in B.
    pub fn half_lengths(&self) -> [f64; 2] {
        self.halves.map(|h| 0.5 * h.length)
    }
}

/// A number in a model or schedule file: the shortest text that parses back to the same `f64`
/// (with an exponent when very small or large, e.g. `4e-9`).
pub fn num(x: f64) -> String {
    format!("{x:?}")
}

/// A vector of numbers separated by spaces, as URDF and MJCF attributes want.
pub(crate) fn vec3(v: [f64; 3]) -> String {
    v.map(num).join(" ")
}

/// `text` with the five XML special characters escaped, for attribute values.
pub(crate) fn xml_escape(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    for c in text.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            '\'' => out.push_str("&apos;"),
            c => out.push(c),
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    #[test]
    fn numbers_round_trip() {
        for x in [0.1, 1.0 / 3.0, 4.0e-9, 1.0e300, -2.5] {
            let back: f64 = num(x).parse().expect("a number");
            assert_relative_eq!(back, x, max_relative = 0.0, epsilon = 0.0);
        }
    }

    #[test]
    fn escapes_markup() {
        assert_eq!(xml_escape("a<b & \"c\""), "a&lt;b &amp; &quot;c&quot;");
    }
}
