//! The cat: two identical cylinders joined by a universal joint, and how to describe the
//! orientation of a body.
//!
//! - [`cylinder`]: one half's mass and moments, the joint rotation `R_AB(q) = Rx(q1) · Ry(q2)`
//!   and the bent configuration (DESIGN.md §1).
//! - [`legs`]: the legs on each half's belly, which define "feet down".
//! - [`motor`]: a joint motor's torque, speed, torque–speed and power limits (DESIGN.md §9).
//! - [`orientation`]: the swing–twist decomposition about the spine axis.

pub mod cylinder;
pub mod legs;
pub mod motor;
pub mod orientation;

pub use cylinder::*;
