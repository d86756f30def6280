//! Numerics with no physics in them: scalar root finding and maximisation, and numbers written
//! for people ([`numfmt`]).
//!
//! The lowest layer of the crate: nothing here knows about cats, schedules or engines.

pub mod numfmt;
pub mod roots;
