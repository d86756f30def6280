//! Numerics with no physics in them: scalar root finding and maximisation, a seeded random
//! generator ([`random`]), and numbers written for people ([`numfmt`]).
//!
//! The lowest layer of the crate: nothing here knows about cats, schedules or engines.

pub mod numfmt;
pub mod random;
pub mod roots;
