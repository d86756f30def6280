//! Schedules exported for robots and other simulators (DESIGN.md §7): the old entry point, now
//! written by [`crate::exchange::schedule_file`] (columns with units, boundary rows marked,
//! impulses of rate jumps, orientation to the exact engine's tolerance; see there).

use crate::exchange::{write_schedule, ExchangeError, ExportOptions};
use crate::problem::Problem;
use crate::schedule::Schedule;

pub use crate::exchange::schedule_file::header;

/// The schedule as CSV with `steps` intervals per phase.
pub fn schedule_csv(problem: &Problem, schedule: &Schedule, steps: usize) -> Result<String, ExchangeError> {
    let options = ExportOptions { rate_hz: None, steps_per_piece: steps };
    Ok(write_schedule(problem, schedule, "schedule", &options)?.csv)
}
