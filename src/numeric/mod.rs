//! Numerics with no physics in them: scalar root finding and maximisation.
//!
//! The lowest layer of the crate: nothing here knows about cats, schedules or engines.

pub mod roots;
