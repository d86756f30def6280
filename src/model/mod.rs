//! The cat: its halves, the joint between them, and how to describe the orientation of a body.
//!
//! - [`cylinder`]: one half's mass and moments, the paper's universal joint rotation
//!   `R_AB(q) = Rx(q1) · Ry(q2)` and the bent configuration (DESIGN.md §1); [`Cylinder`] is
//!   also the paper's cat, two equal halves on that joint, for every engine built on it.
//! - [`joint`]: the joint models, universal, no-twist and spherical, and an appendage's hinge
//!   (DESIGN.md §10).
//! - [`cat`]: a cat of two possibly unequal halves on any [`Joint`], and its appendages (a tail,
//!   legs) as a tree of bodies.
//! - [`tree`]: a tree of rigid bodies and how its bodies move relative to the base, which the
//!   general reduction ([`crate::engines::reduction`]) consumes.
//! - [`shape`]: shape coordinates of any model and their trajectories.
//! - [`legs`]: the legs drawn on each half's belly, which define "feet down" (and where the
//!   legs of [`cat::Appendages`] hang).
//! - [`motor`]: a joint motor's torque, speed, torque–speed and power limits (DESIGN.md §9).
//! - [`orientation`]: the swing–twist decomposition about the spine axis.

pub mod cat;
pub mod cylinder;
pub mod joint;
pub mod legs;
pub mod motor;
pub mod orientation;
pub mod shape;
pub mod tree;

pub use cat::Cat;
pub use cylinder::*;
pub use joint::Joint;
