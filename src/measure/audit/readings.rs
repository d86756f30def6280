//! Which reading of the paper's own ingredients gives §7's `ω ≈ 2.2514 rad/s`.
//!
//! §7 prints `ω = π/(Δt (1 − (I_z'z'/I_yy) sin²(θ/2))) ≈ 2.2514` and then
//! `max τ₂ = ω (π/Δt) I* ≈ 1.655`, but its formula with its own inputs gives 2.2215 (the
//! `omega_worked_example` entry). This module tries every combination of the ingredients the
//! paper offers, a small enumerated grid:
//!
//! | choice | options (paper section) |
//! |---|---|
//! | inertia values | printed rounded intermediates `I_y'y' ≈ 0.084`, `I_yy ≈ 0.0726`, `I* ≈ 0.3342` (§7); the slipped `m(r² + l²)/12`, `I* = m(r² + 4l²)/12` unrounded (§6.3, §7); the solid cylinder's `m(3r² + l²)/12`, `I* = m(3r² + 4l²)/12` (§2 eq. (2), §5) |
//! | moment standing for `I_yy` in `C` | one half's `I_yy = I_y'y' cos²(θ/2) + I_z'z' sin²(θ/2)` (§2 Claim 2, §7); the whole cat's `2 I_yy`, its locked inertia about `y` (§2 Claim 1); `I_y'y'` alone (§7's tensor); `I*` (§7, §8) |
//! | factor on `I_z'z'` | 1 (§6.3 code, §7); 2 (§4's `C = 1 − 2 (I_zz/I_cc) sin(θ/2)`) |
//! | power of the sine | `sin` (§6.3 code, §7's τ line); `sin²` (§7's ω line) |
//! | its angle | `θ/2` (§2–§7); `θ`; `β/2 = (π − θ)/2` (§8's amplitude; `sin(β/2) = cos(θ/2)`) |
//! | duration | the whole fall `Δt = √(2h/g)` (§7); `Δt` as printed, 1.428 s (§7); the twist phase `T₂ = 0.6 Δt` (§6.3); `0.6 × 1.428 s` |
//!
//! with `I_z'z' = m r²/2` (§7, printed 0.005 exactly), and for each computes
//!
//! $$ C = 1 - k \frac{I_{z'z'}}{I} \sin^p(a), \qquad \omega = \frac{\pi}{T\,C}, \qquad
//!    \tau = I_* \,\omega\, \frac{\pi}{T} $$
//!
//! (`τ` is §7's `ω (π/Δt) I*`, §8's bound `I* ω0 π/T2`: the peak of `I* dω/dt` for
//! `ω(t) = ω0 (1 − cos(π t/T))`, with `I*` from the same inertia values). Readings with
//! `C ≤ 0` give no rate and are left out. They are ranked by `|ω/2.2514 − 1|`.
//! `3 × 4 × 2 × 2 × 3 × 4 = 576` readings are tried.
//!
//! Only the §7 worked example has a printed ω to compare with ([`super::is_worked_example`]).
//!
//! ## References
//! - A. Rasmussen, S. Richardson, W. McDermott, *Cat Flipping*, §2, §4, §5, §6.3, §7, §8.

use std::f64::consts::PI;
use std::fmt::Write;

use serde::Serialize;

use super::formulas::{paper_end_transverse, paper_transverse};
use crate::model::BentMoments;
use crate::problem::Problem;

/// §7's printed rate, rad/s.
pub const OMEGA_PUBLISHED: f64 = 2.2514;
/// §7's printed peak twist torque, N·m.
pub const TAU_PUBLISHED: f64 = 1.655;
/// How many of the nearest readings the audit keeps.
pub const NEAREST: usize = 5;

/// §7's printed rounded intermediates.
const PRINTED_TRANSVERSE: f64 = 0.084;
const PRINTED_I_YY: f64 = 0.0726;
const PRINTED_I_STAR: f64 = 0.3342;
const PRINTED_FALL: f64 = 1.428;
/// §6.3's twist share of the fall, `step_3 − step_2 = (8 − 2)/10 · t_max`.
const TWIST_SHARE: f64 = 0.6;

/// Where the inertia values come from.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Inertias {
    /// §7's printed rounded values: `I_y'y' ≈ 0.084`, `I_yy ≈ 0.0726`, `I* ≈ 0.3342`.
    Printed,
    /// The slipped `m(r² + l²)/12` and `I* = m(r² + 4l²)/12` of §6.3 and §7, unrounded.
    Slipped,
    /// The solid cylinder's `m(3r² + l²)/12` and `I* = m(3r² + 4l²)/12` (§2 eq. (2), §5).
    Correct,
}

/// Which moment stands for `I_yy` in `C`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Moment {
    /// One half's `I_yy = I_y'y' cos²(θ/2) + I_z'z' sin²(θ/2)` (§2 Claim 2, §7).
    HalfIyy,
    /// The whole cat's `2 I_yy`, its locked inertia about `y` (§2 Claim 1).
    WholeIyy,
    /// `I_y'y'` alone (§7's tensor), the `cos²` mix left out.
    Transverse,
    /// `I*`, a half's moment about its end (§7, §8).
    EndMoment,
}

/// The power of the sine in `C`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Power {
    /// `sin` (§6.3's code, §7's τ line).
    Sin,
    /// `sin²` (§7's ω line).
    SinSquared,
}

/// The sine's angle.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Angle {
    /// `θ/2` (§2–§7).
    HalfTheta,
    /// `θ`.
    Theta,
    /// `β/2 = (π − θ)/2` (§8's amplitude).
    HalfBend,
}

/// The duration the turn is spread over.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Span {
    /// The whole fall `Δt = √(2h/g)` (§7).
    Fall,
    /// `Δt` as printed, 1.428 s (§7).
    FallPrinted,
    /// The twist phase `T₂ = 0.6 Δt` (§6.3).
    Twist,
    /// `0.6 × 1.428 s`.
    TwistPrinted,
}

/// One combination of choices.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
pub struct Choices {
    /// Where the inertia values come from.
    pub inertias: Inertias,
    /// Which moment stands for `I_yy`.
    pub moment: Moment,
    /// The factor `k` on `I_z'z'`: 1 or 2.
    pub factor: u8,
    /// `sin` or `sin²`.
    pub power: Power,
    /// The sine's angle.
    pub angle: Angle,
    /// The duration.
    pub span: Span,
}

impl Choices {
    /// Every combination, in a fixed order.
    fn all() -> Vec<Choices> {
        let mut out = Vec::new();
        for inertias in [Inertias::Printed, Inertias::Slipped, Inertias::Correct] {
            for moment in [Moment::HalfIyy, Moment::WholeIyy, Moment::Transverse, Moment::EndMoment] {
                for factor in [1, 2] {
                    for power in [Power::Sin, Power::SinSquared] {
                        for angle in [Angle::HalfTheta, Angle::Theta, Angle::HalfBend] {
                            for span in [Span::Fall, Span::FallPrinted, Span::Twist, Span::TwistPrinted] {
                                out.push(Choices { inertias, moment, factor, power, angle, span });
                            }
                        }
                    }
                }
            }
        }
        out
    }

    /// The choices in words, with the paper's sections.
    pub fn words(&self) -> String {
        let moment = match self.moment {
            Moment::HalfIyy => "one half's I_yy (§2 Claim 2, §7)",
            Moment::WholeIyy => "the whole cat's 2 I_yy, its locked inertia about y (§2 Claim 1)",
            Moment::Transverse => "I_y'y' alone (the cos²/sin² mix of §7's I_yy left out)",
            Moment::EndMoment => "I*, a half's moment about its end (§7, §8)",
        };
        let inertias = match self.inertias {
            Inertias::Printed => "§7's printed values I_y'y' = 0.084, I_yy = 0.0726, I* = 0.3342",
            Inertias::Slipped => "the slipped m(r² + l²)/12, m(r² + 4l²)/12 unrounded (§6.3, §7)",
            Inertias::Correct => "the solid cylinder's m(3r² + l²)/12, m(3r² + 4l²)/12 (§2 eq. (2), §5)",
        };
        let (k, k_source) = if self.factor == 2 { ("2 ", "factor 2: §4") } else { ("", "factor 1: §6.3 code, §7") };
        let (trig, trig_source) = match self.power {
            Power::Sin => ("sin", "sin: §6.3 code, §7's τ line"),
            Power::SinSquared => ("sin²", "sin²: §7's ω line"),
        };
        let angle = match self.angle {
            Angle::HalfTheta => "θ/2",
            Angle::Theta => "θ",
            Angle::HalfBend => "(π − θ)/2",
        };
        let span = match self.span {
            Span::Fall => "the whole fall Δt = √(2h/g) (§7)",
            Span::FallPrinted => "Δt as printed, 1.428 s (§7)",
            Span::Twist => "the twist phase T2 = 0.6 Δt (§6.3)",
            Span::TwistPrinted => "the twist phase from the printed Δt, 0.6 × 1.428 s",
        };
        format!(
            "I = {moment} stands for I_yy; inertias: {inertias}; C = 1 − {k}(I_z'z'/I) {trig}({angle}) ({k_source}; {trig_source}); T = {span}"
        )
    }
}

/// One reading: its choices, its `C`, `ω` and `τ`, and their distances from §7's numbers.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct OmegaReading {
    /// The combination of choices.
    pub choices: Choices,
    /// The choices in words.
    pub words: String,
    /// `C = 1 − k (I_z'z'/I) sinᵖ(a)`.
    pub c: f64,
    /// `ω = π/(T C)`, rad/s.
    pub omega: f64,
    /// `ω/2.2514 − 1`.
    pub omega_relative_error: f64,
    /// `τ = I* ω π/T`, N·m.
    pub tau: f64,
    /// `τ/1.655 − 1`.
    pub tau_relative_error: f64,
}

/// The search: how many readings were tried and the nearest ones, nearest first.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ReadingSearch {
    /// §7's printed ω, rad/s.
    pub omega_published: f64,
    /// §7's printed τ, N·m.
    pub tau_published: f64,
    /// Readings tried (those with `C > 0`).
    pub tried: usize,
    /// The [`NEAREST`] nearest readings by `|ω/2.2514 − 1|`, nearest first.
    pub nearest: Vec<OmegaReading>,
}

/// The ingredients of one inertia source: `(I_y'y', I_yy, I*)`, kg·m².
fn inertias(source: Inertias, p: &Problem) -> (f64, f64, f64) {
    let cat = &p.cat.half();
    let theta = p.manoeuvre.theta();
    match source {
        Inertias::Printed => (PRINTED_TRANSVERSE, PRINTED_I_YY, PRINTED_I_STAR),
        Inertias::Slipped => {
            let it = paper_transverse(cat);
            (it, BentMoments::new(it, cat.axial(), theta).yy, paper_end_transverse(cat))
        }
        Inertias::Correct => {
            let it = cat.transverse();
            (it, BentMoments::new(it, cat.axial(), theta).yy, cat.end_transverse())
        }
    }
}

/// The reading of `choices` for problem `p`, `None` when its `C ≤ 0`.
fn reading(choices: Choices, p: &Problem) -> Option<OmegaReading> {
    let (transverse, i_yy, i_star) = inertias(choices.inertias, p);
    let moment = match choices.moment {
        Moment::HalfIyy => i_yy,
        Moment::WholeIyy => 2.0 * i_yy,
        Moment::Transverse => transverse,
        Moment::EndMoment => i_star,
    };
    let theta = p.manoeuvre.theta();
    let a = match choices.angle {
        Angle::HalfTheta => 0.5 * theta,
        Angle::Theta => theta,
        Angle::HalfBend => 0.5 * (PI - theta),
    };
    let sine = match choices.power {
        Power::Sin => a.sin(),
        Power::SinSquared => a.sin().powi(2),
    };
    let fall = p.drop.fall_time();
    let t = match choices.span {
        Span::Fall => fall,
        Span::FallPrinted => PRINTED_FALL,
        Span::Twist => TWIST_SHARE * fall,
        Span::TwistPrinted => TWIST_SHARE * PRINTED_FALL,
    };
    let c = 1.0 - f64::from(choices.factor) * p.cat.half().axial() * sine / moment;
    let omega = PI / (t * c);
    let tau = i_star * omega * PI / t;
    (c > 0.0 && omega.is_finite() && tau.is_finite()).then(|| OmegaReading {
        choices,
        words: choices.words(),
        c,
        omega,
        omega_relative_error: omega / OMEGA_PUBLISHED - 1.0,
        tau,
        tau_relative_error: tau / TAU_PUBLISHED - 1.0,
    })
}

/// Every reading with `C > 0`, nearest to §7's ω first (ties keep the grid's order).
pub fn ranked(p: &Problem) -> Vec<OmegaReading> {
    let mut all: Vec<OmegaReading> = Choices::all().into_iter().filter_map(|c| reading(c, p)).collect();
    all.sort_by(|a, b| a.omega_relative_error.abs().total_cmp(&b.omega_relative_error.abs()));
    all
}

/// The search for the §7 worked example; `None` for any other problem (no printed ω applies).
pub fn search(p: &Problem) -> Option<ReadingSearch> {
    if !super::is_worked_example(p) {
        return None;
    }
    let all = ranked(p);
    Some(ReadingSearch {
        omega_published: OMEGA_PUBLISHED,
        tau_published: TAU_PUBLISHED,
        tried: all.len(),
        nearest: all.into_iter().take(NEAREST).collect(),
    })
}

impl ReadingSearch {
    /// The search as a Markdown section: how it was done and the nearest readings.
    pub fn to_markdown(&self) -> String {
        let mut out = String::new();
        let _ = writeln!(out, "\n## Readings of §7's ω ≈ {} rad/s\n", self.omega_published);
        let _ = writeln!(
            out,
            "{} readings of the paper's own ingredients tried: inertia values printed (§7), slipped (§6.3, §7) or correct (§2, §5); one half's I_yy, the whole cat's 2 I_yy, I_y'y' or I* for I_yy; factor 1 (§6.3, §7) or 2 (§4) on I_z'z'; sin or sin² of θ/2, θ or (π − θ)/2; the whole fall Δt (exact or printed 1.428 s) or the twist phase 0.6 Δt (§6.3). ω = π/(T C), τ = I* ω π/T (§7, §8) with I* from the same inertia values. Nearest {} by |ω/{} − 1|:\n",
            self.tried,
            self.nearest.len(),
            self.omega_published
        );
        let _ = writeln!(
            out,
            "| rank | ω (rad/s) | ω vs {} | τ (N·m) | τ vs {} | C | reading |",
            self.omega_published, self.tau_published
        );
        let _ = writeln!(out, "|---:|---:|---:|---:|---:|---:|---|");
        for (i, r) in self.nearest.iter().enumerate() {
            let _ = writeln!(
                out,
                "| {} | {:.5} | {:+.4}% | {:.4} | {:+.3}% | {:.6} | {} |",
                i + 1,
                r.omega,
                100.0 * r.omega_relative_error,
                r.tau,
                100.0 * r.tau_relative_error,
                r.c,
                r.words.replace('|', "\\|")
            );
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    #[test]
    fn the_grid_has_every_combination_once() {
        let all = Choices::all();
        assert_eq!(all.len(), 3 * 4 * 2 * 2 * 3 * 4);
        for (i, a) in all.iter().enumerate() {
            assert!(all[i + 1..].iter().all(|b| b != a), "{a:?} twice");
        }
    }

    #[test]
    fn the_papers_own_formula_is_one_of_the_readings() {
        // §7's ω line as printed: slipped inertia, one half's I_yy, sin²(θ/2), the whole fall.
        let p = Problem::default();
        let choices = Choices {
            inertias: Inertias::Slipped,
            moment: Moment::HalfIyy,
            factor: 1,
            power: Power::SinSquared,
            angle: Angle::HalfTheta,
            span: Span::Fall,
        };
        let r = reading(choices, &p).map_or(f64::NAN, |r| r.omega);
        // Hand: π/(Δt (1 − (0.005/I_yy) sin²(π/8))), I_yy = 1.01/12 cos²(π/8) + 0.005 sin²(π/8).
        let (s2, c2) = ((2.0 - 2f64.sqrt()) / 4.0, (2.0 + 2f64.sqrt()) / 4.0);
        let iyy = 1.01 / 12.0 * c2 + 0.005 * s2;
        assert_relative_eq!(r, PI / ((20.0f64 / 9.8).sqrt() * (1.0 - 0.005 / iyy * s2)), max_relative = 1e-12);
    }
}
