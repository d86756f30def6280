//! The motors at the two joints (`[actuator]` in a problem file, DESIGN.md §9).
//!
//! Each limit is given for both joints at once (a number) or per joint (a pair `[joint 1,
//! joint 2]`); an absent limit is no limit, and a problem without `[actuator]` has ideal motors.
//! The limits, per joint `j`:
//!
//! $$ |τ_j| ≤ τ_{max}, \qquad |q̇_j| ≤ ω_{max}, \qquad
//!    |τ_j| ≤ τ_s \Big(1 − \frac{|q̇_j|}{ω_0}\Big), \qquad |τ_j q̇_j| ≤ P, $$
//!
//! the torque limit, the speed limit, the DC motor's torque–speed line between its stall torque
//! `τ_s` and free speed `ω_0` (which also bounds `|q̇_j| ≤ ω_0`), and the mechanical power limit.
//! What the limits mean for a trajectory is [`crate::model::motor`].

use serde::{Deserialize, Serialize};

use super::error::{bad, positive, ProblemError};
use crate::model::motor::{Motor, Motors};

/// A limit for both joints (a number) or for each (a pair `[joint 1, joint 2]`).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(untagged)]
pub enum PerJoint {
    /// The same value for both joints.
    Both(f64),
    /// Joint 1's value, then joint 2's.
    Each([f64; 2]),
}

impl PerJoint {
    /// As the file gives it: a number, or the pair `[joint 1, joint 2]`.
    pub fn echo(self) -> String {
        use crate::numeric::numfmt::echo;
        match self {
            PerJoint::Both(v) => echo(v),
            PerJoint::Each([a, b]) => format!("[{}, {}]", echo(a), echo(b)),
        }
    }

    /// The value for joint `j` (0 or 1).
    pub fn joint(self, j: usize) -> f64 {
        match self {
            PerJoint::Both(v) => v,
            PerJoint::Each(v) => v[j.min(1)],
        }
    }
}

/// The motors' limits. Field docs give each limit's unit; every limit is optional.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct Actuator {
    /// Torque limit `τ_max`, N·m.
    pub torque_limit_nm: Option<PerJoint>,
    /// Speed limit `ω_max`, rad/s.
    pub speed_limit_rad_s: Option<PerJoint>,
    /// Stall torque `τ_s` of the DC-motor envelope, N·m (with `free_speed_rad_s`).
    pub stall_torque_nm: Option<PerJoint>,
    /// Free-running speed `ω_0` of the DC-motor envelope, rad/s (with `stall_torque_nm`).
    pub free_speed_rad_s: Option<PerJoint>,
    /// Mechanical power limit `P`, W.
    pub power_limit_w: Option<PerJoint>,
}

impl Actuator {
    /// Checks every field; names the first one that is wrong.
    pub fn validate(&self) -> Result<(), ProblemError> {
        let fields = [
            ("actuator.torque_limit_nm", self.torque_limit_nm),
            ("actuator.speed_limit_rad_s", self.speed_limit_rad_s),
            ("actuator.stall_torque_nm", self.stall_torque_nm),
            ("actuator.free_speed_rad_s", self.free_speed_rad_s),
            ("actuator.power_limit_w", self.power_limit_w),
        ];
        for (field, value) in fields {
            match value {
                None => {}
                Some(PerJoint::Both(v)) => positive(field, v)?,
                Some(PerJoint::Each(v)) => {
                    for (j, x) in v.into_iter().enumerate() {
                        // Counted from 0, as every list of the file is; the joint named too.
                        positive(&format!("{field}[{j}] (joint {})", j + 1), x)?;
                    }
                }
            }
        }
        match (self.stall_torque_nm, self.free_speed_rad_s) {
            (Some(stall), None) => Err(bad(
                "actuator.stall_torque_nm",
                stall.echo(),
                "the DC-motor envelope needs actuator.free_speed_rad_s too",
            )),
            (None, Some(free)) => Err(bad(
                "actuator.free_speed_rad_s",
                free.echo(),
                "the DC-motor envelope needs actuator.stall_torque_nm too",
            )),
            _ => Ok(()),
        }
    }

    /// The motors these limits describe.
    pub fn motors(&self) -> Motors {
        let at = |v: Option<PerJoint>, j: usize| v.map(|v| v.joint(j));
        Motors {
            joints: [0, 1].map(|j| Motor {
                torque: at(self.torque_limit_nm, j),
                speed: at(self.speed_limit_rad_s, j),
                envelope: at(self.stall_torque_nm, j).zip(at(self.free_speed_rad_s, j)),
                power: at(self.power_limit_w, j),
            }),
        }
    }
}
