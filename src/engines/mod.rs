//! The engines: what a schedule does to the cat.
//!
//! - [`exact`]: the momentum-map engine (zero angular momentum, joint path integrated by a
//!   sixth-order Magnus method) — the ground truth;
//! - [`torque`]: the joint torques of that motion by Newton–Euler;
//! - [`calibrate`]: the circulation for which the exact engine turns the cat by exactly π;
//! - [`rapier`]: an independent multibody simulation in rapier3d-f64, for verification.

pub mod calibrate;
pub mod exact;
pub mod rapier;
pub mod torque;
