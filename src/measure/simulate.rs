//! `catflip simulate PROBLEM [--engine rapier]`: the problem's own schedule, measured by the exact
//! engine (the library's measurement of its profile, [`Resolved::own`]) and, for rapier,
//! verified against it ([`Measured::verify`]).

use crate::engines::measured::Measured;
use crate::engines::rapier::RapierError;
use crate::engines::resolved::Resolved;
use crate::engines::Engine;
use crate::schedule::Schedule;

/// The problem's schedule measured, and verified in rapier when `engine` is rapier. `Err` only
/// when rapier cannot run it (its settings or the cat); a verification without a usable run is
/// an outcome.
pub fn simulate(r: &Resolved, engine: Engine) -> Result<Measured<Schedule>, RapierError> {
    let measured = r.own().clone();
    match engine {
        Engine::Exact => Ok(measured),
        Engine::Rapier => measured.verified(r.rig()),
    }
}
