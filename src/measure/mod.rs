//! What each command computes, before anything is rendered: the application layer.
//!
//! Every schedule is measured by one function into one noun
//! ([`crate::engines::measured::Measured`], made by [`crate::engines::measured::Rig::measure`] and
//! verified by [`crate::engines::measured::Measured::verify`]); the modules here decide which
//! schedules a command measures and what else it computes, and [`crate::report`] renders what
//! they return (Markdown, CSV, JSON, plots).
//!
//! - [`simulate`]: the problem's schedule through the exact engine, or verified in rapier;
//! - [`import`]: a schedule file read back, checked and measured;
//! - [`whole`]: the whole-manoeuvre optimum, measured (and verified);
//! - [`retime`]: the certified convex retimings of a schedule along its path;
//! - [`audit`]: the paper's numbers, published, recomputed and corrected;
//! - [`run`]: everything `catflip run` computes, in parallel, before anything is written;
//! - [`mod@bench`]: run time against error for every engine and optimiser, and stress tests;
//! - [`timings`]: the wall-clock interval of each stage of a run; [`machine`]: where it ran.

pub mod audit;
pub mod bench;
pub mod import;
pub mod machine;
pub mod retime;
pub mod run;
pub mod simulate;
pub mod timings;
pub mod whole;
