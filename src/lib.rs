//! # catflip
//!
//! A workbench for planning and checking how a falling cat turns itself over, after the
//! two-cylinder model of Rasmussen, Richardson and McDermott, *Cat Flipping* (the paper).
//!
//! The pipeline: problem file ([`problem`]) → model ([`model`]) → schedule ([`schedule`]) →
//! engines ([`engines`]) → optimisers ([`optimize`]) → what each command computes ([`measure`])
//! → report ([`report`]); [`numeric`] holds the math with no physics in it. Every schedule is
//! measured by one function into one noun, a [`engines::measured::Measured`] schedule.
//! [`prelude`] re-exports the main nouns (`use catflip::prelude::*`).
//!
//! Conventions (DESIGN.md §1): each half has its body frame at its centre of mass with `z`
//! along its axis towards the head; B relative to A is `R_AB(q) = Rx(q1) · Ry(q2)`; `q = 0` is
//! the straight cat. SI units: kg, m, s, rad, N·m. Twist is signed, right-handed about A's
//! initial `+z` (the head direction).
//!
//! ## Example
//!
//! Load a problem from TOML (every field has a default), resolve it once (its schedule and
//! circulation), measure the schedule with the exact engine and read the twist:
//!
//! ```
//! use catflip::prelude::*;
//!
//! let toml = r#"
//! name = "example"
//! [manoeuvre]
//! profile = "cycloidal"
//! circulation = "paper"
//! "#;
//! let problem = Problem::from_toml(toml, "example.toml", &[]).expect("a valid problem");
//! let resolved = Resolved::new(&problem).expect("the paper's circulation exists for this cat");
//! let measured = resolved.measure(ScheduleName::Problem, resolved.schedule.clone());
//! let e = &measured.exact;
//! println!("twist {:+.6}°, swing {:.6}°, peak torque {:.4} N·m", e.twist_deg(), e.swing_deg(), e.peaks.max);
//! // The paper's circulation π/C turns the default cat by about 174°, not 180° (DESIGN.md §3).
//! assert!((e.twist_deg().abs() - 174.07).abs() < 0.01);
//! assert!(e.flip.converged);
//! ```
//!
//! ## References
//! - A. Rasmussen, S. Richardson, W. McDermott, *Cat Flipping* (student paper);
//! - T. R. Kane and M. P. Scher, *A dynamical explanation of the falling cat phenomenon*,
//!   Int. J. Solids Structures 5 (1969) 663–670.

#![warn(missing_docs)]
#![deny(clippy::float_cmp)]

pub mod compare_models;
pub mod engines;
pub mod exchange;
pub mod measure;
pub mod model;
pub mod numeric;
pub mod optimize;
pub mod prelude;
pub mod problem;
pub mod report;
pub mod robust;
pub mod schedule;
pub mod sweep;
