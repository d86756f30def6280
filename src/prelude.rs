//! The main nouns and entry points, for `use catflip::prelude::*` (rapier's `prelude`): the
//! problem and its cat, the schedule, the problem resolved once ([`Resolved`], where every
//! command starts), the measured schedule ([`Measured`], made by [`Rig::measure`]: the exact
//! engine's [`Evaluation`], rapier's verification), the exact [`flip`], rapier's [`verify`], the
//! optimisers' entry points ([`optimize`], [`retime_schedule`], [`optimize_whole`]) and the
//! schedule files' [`read_schedule`] and [`write_schedule`].
//!
//! Nothing is defined here; each item keeps its home module, where its docs are.

pub use crate::engines::evaluate::Evaluation;
pub use crate::engines::exact::{flip, Flip};
pub use crate::engines::measured::{Measured, Rig};
pub use crate::engines::models::TwoMotorCat;
pub use crate::engines::peaks::PhasePeaks;
pub use crate::engines::rapier::{verify, Reference, Verification};
pub use crate::engines::resolved::Resolved;
pub use crate::engines::Engine;
pub use crate::exchange::{read_schedule, write_schedule, ExportOptions, ImportedSchedule};
pub use crate::model::motor::Motors;
pub use crate::model::{Cat, Cylinder, Joint};
pub use crate::optimize::retime::{retime_schedule, RetimeSettings, Retiming};
pub use crate::optimize::whole::{optimize_whole, WholeOutcome, WholeSettings};
pub use crate::optimize::{optimize, OptimizeReport};
pub use crate::problem::{CatSection, Problem, ProblemError};
pub use crate::schedule::variant::{ScheduleName, Variant};
pub use crate::schedule::{paper_circulation, JointState, Schedule, Trajectory};
