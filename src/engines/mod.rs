//! The engines: what a schedule does to the cat.
//!
//! - [`exact`]: the momentum-map engine (zero angular momentum, joint path integrated by a
//!   sixth-order Magnus method) — the ground truth;
//! - [`reduction`]: the zero-momentum reduction of a tree of rigid bodies (locked inertia, shape
//!   momentum, joint torques), written once for every model;
//! - [`models`]: the exact engine and joint torques for any cat model (unequal halves, the
//!   universal, no-twist or spherical joint) on that reduction;
//! - [`shape`]: shape trajectories of any model (the library schedules among them);
//! - [`spin`]: the reorientation and torques of a release with spin;
//! - [`torque`]: the joint torques of that motion by Newton–Euler;
//! - [`jumps`]: the joint-rate jumps between pieces of any trajectory, with their impulses;
//! - [`calibrate`]: the circulation for which the exact engine turns the cat by exactly π;
//! - [`rapier`]: an independent multibody simulation in rapier3d-f64, for verification;
//! - [`rapier_check`]: rapier's check of a trajectory against the exact engine, as reports show it;
//! - [`motors`]: what a trajectory asks of its motors (peak speed, power, usage of each limit);
//! - [`peaks`]: the peak torques per phase and joint, one type for both engines;
//! - [`evaluate`]: one exact [`evaluate::Evaluation`] of any trajectory on any two-motor cat;
//! - [`measured`]: [`measured::Measured`], a named trajectory with its evaluation and its rapier
//!   verification: the one noun every command reports, made by [`resolved::Resolved::measure`];
//! - [`circulation`]: the circulation resolved once;
//! - [`resolved`]: [`resolved::Resolved`], the problem resolved around it, where every command
//!   starts;
//! - [`models`], [`reduction`], [`shape`]: the exact engine on any cat model (a tree of bodies).

pub mod calibrate;
pub mod circulation;
pub mod evaluate;
pub mod exact;
pub mod jumps;
pub mod measured;
pub mod models;
pub mod motors;
pub mod peaks;
pub mod rapier;
pub mod rapier_check;
pub mod reduction;
pub mod resolved;
pub mod shape;
pub mod spin;
pub mod torque;

use std::fmt;

use serde::Serialize;

/// Joint-rate jumps smaller than this, relative to the rates on either side, are round-off,
/// not jumps (used by both engines).
pub const JUMP_TOLERANCE: f64 = 1e-9;

/// An engine that runs a schedule.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Engine {
    /// The momentum-map engine ([`exact`]): the ground truth.
    Exact,
    /// The rapier3d-f64 multibody simulation ([`rapier`]).
    Rapier,
}

impl Engine {
    /// The name in files and tables: `exact`, `rapier`.
    pub fn name(self) -> &'static str {
        match self {
            Engine::Exact => "exact",
            Engine::Rapier => "rapier",
        }
    }

    /// The engine of a name written by [`Engine::name`].
    pub fn parse(s: &str) -> Option<Engine> {
        [Engine::Exact, Engine::Rapier].into_iter().find(|e| e.name() == s)
    }
}

impl fmt::Display for Engine {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl std::str::FromStr for Engine {
    type Err = String;

    /// `exact` or `rapier`, as on the command line.
    fn from_str(s: &str) -> Result<Engine, String> {
        [Engine::Exact, Engine::Rapier]
            .into_iter()
            .find(|e| e.name() == s)
            .ok_or_else(|| format!("unknown engine `{s}`: expected `exact` or `rapier`"))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn engine_names_round_trip() {
        for e in [Engine::Exact, Engine::Rapier] {
            assert_eq!(e.to_string().parse::<Engine>(), Ok(e));
        }
        assert!("magnus".parse::<Engine>().is_err());
    }
}
