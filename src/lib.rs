//! # catflip
//!
//! A workbench for planning and checking how a falling cat turns itself over, after the
//! two-cylinder model of Rasmussen, Richardson and McDermott, *Cat Flipping* (the paper).
//!
//! The pipeline: problem file ([`problem`]) → model ([`model`]) → schedule ([`profile`],
//! [`schedule`]) → engines ([`exact`], [`torque`], [`rapier`]) → optimisers ([`qp`]) → report.
//!
//! Conventions (DESIGN.md §1): each half has its body frame at its centre of mass with `z`
//! along its axis towards the head; B relative to A is `R_AB(q) = Rx(q1) · Ry(q2)`; `q = 0` is
//! the straight cat. SI units: kg, m, s, rad, N·m. Twist is signed, right-handed about A's
//! initial `+z` (the head direction).
//!
//! ## References
//! - A. Rasmussen, S. Richardson, W. McDermott, *Cat Flipping* (student paper);
//! - T. R. Kane and M. P. Scher, *A dynamical explanation of the falling cat phenomenon*,
//!   Int. J. Solids Structures 5 (1969) 663–670.

#![warn(missing_docs)]
#![deny(clippy::float_cmp)]

pub mod audit;
pub mod benchmark;
pub mod calibrate;
pub mod compare;
pub mod exact;
pub mod export;
pub mod manoeuvre;
pub mod model;
pub mod optimize;
pub mod orientation;
pub mod plot;
pub mod problem;
pub mod profile;
pub mod provenance;
pub mod qp;
pub mod rapier;
pub mod refine;
pub mod roots;
pub mod run;
pub mod schedule;
pub mod settings;
pub mod simulate;
pub mod sweep;
pub mod torque;
