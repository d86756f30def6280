//! Seeded random problems spanning decades, and the checks every engine must pass on them.
//!
//! A case draws (log-uniformly unless said): `r/l ∈ [1e-3, 1]` (`l = 1` m), `θ ∈ [10°, 179°]`
//! (uniform), mass `m ∈ [1e-3, 1e3]` kg, fall time `t_f ∈ [0.1, 10]` s (the height
//! `½ g t_f²`, `g = 9.8` m/s²), QP nodes `N ∈ [10, 1e5]`, the bend path and the profile
//! (uniform). Each case is a problem file plus `--set` overrides, so a refusal is the loader's.
//!
//! On an accepted case:
//! - the exact engine's twist, swing, peaks and momentum are finite; its flip met its
//!   tolerance or says it did not (a status, never a silent number);
//! - invariants that hold exactly in the model: the angular momentum stays zero (relative
//!   residual ≤ [`MOMENTUM_LIMIT`]), action = reaction at the joint (gap ≤
//!   [`ACTION_REACTION_LIMIT`] of the peak), the twist does not depend on the mass (the same
//!   case at 10× the mass twists the same within [`MASS_TWIST_LIMIT`] rad) and the torques
//!   scale with it (×10 within [`MASS_TORQUE_LIMIT`] relative);
//! - the profile QP at `N` nodes is solved (or ends with a status) and its peak is within
//!   [`QP_GAP_LIMIT`] of its closed form.
//!
//! A violation of any of these is a failure; a flip short of its tolerance, or a peak whose
//! stated accuracy is worse than 1e-6, is recorded as a degradation with its cause.
//!
//! The generator is SplitMix64 (Steele, Lea, Flood, *Fast splittable pseudorandom number
//! generators*, OOPSLA 2014): a seed gives the same cases on every machine.

use serde::Serialize;

use crate::engines::evaluate::Evaluation;
use crate::engines::resolved::Resolved;
use crate::problem::{Problem, ProfileKind};

/// Largest relative angular momentum residual accepted.
pub const MOMENTUM_LIMIT: f64 = 1e-6;
/// Largest action–reaction gap accepted, relative to the peak torque.
pub const ACTION_REACTION_LIMIT: f64 = 1e-6;
/// Largest change of the twist accepted when the mass is multiplied by 10, rad.
pub const MASS_TWIST_LIMIT: f64 = 1e-8;
/// Largest relative deviation of the peak torque from ×10 when the mass is multiplied by 10.
pub const MASS_TORQUE_LIMIT: f64 = 1e-6;
/// Largest relative gap of the QP's peak to its closed form.
pub const QP_GAP_LIMIT: f64 = 1e-4;

pub use crate::numeric::random::SplitMix64;

/// One drawn case.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct RandomCase {
    /// Its index in the seeded sequence.
    pub index: usize,
    /// The `--set` overrides that make it from the default problem.
    pub overrides: Vec<String>,
    /// QP nodes.
    pub nodes: usize,
}

/// Draws case `index` of the sequence of `seed` (each case from its own stream, so any case
/// can be rerun alone).
pub fn draw(seed: u64, index: usize) -> RandomCase {
    let mut g = SplitMix64::new(seed ^ (index as u64).wrapping_mul(0xD1B5_4A32_D192_ED03));
    let radius = g.log_uniform(1e-3, 1.0);
    let theta = g.uniform(10.0, 179.0);
    let mass = g.log_uniform(1e-3, 1e3);
    let fall = g.log_uniform(0.1, 10.0);
    let nodes = g.log_uniform(10.0, 1e5) as usize;
    let path = ["joint-circle", "cone"][g.index(2)];
    let profile = ProfileKind::ALL[g.index(ProfileKind::ALL.len())];
    let overrides = vec![
        "cat.length=1.0".to_string(),
        format!("cat.radius={radius:e}"),
        format!("cat.mass={mass:e}"),
        "drop.gravity=9.8".to_string(),
        format!("drop.height={:e}", 0.5 * 9.8 * fall * fall),
        format!("manoeuvre.theta_deg={theta:e}"),
        format!("manoeuvre.bend_path=\"{path}\""),
        format!("manoeuvre.profile=\"{}\"", profile.name()),
        "manoeuvre.circulation=\"paper\"".to_string(),
    ];
    RandomCase { index, overrides, nodes }
}

/// What a case gave.
#[derive(Clone, Debug, PartialEq, Serialize)]
#[serde(rename_all = "kebab-case", tag = "verdict", content = "detail")]
pub enum Verdict {
    /// Every check passed.
    Passed,
    /// The loader or the resolution refused the case, with its one-line reason.
    Refused(String),
    /// Every check passed but accuracy degraded, with the cause.
    Degraded(String),
    /// A check failed: a non-finite number, or an invariant violated.
    Failed(String),
}

/// A case and its verdict, with the numbers behind it.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct RandomResult {
    /// The case.
    pub case: RandomCase,
    /// Its verdict.
    pub verdict: Verdict,
    /// Relative momentum residual (this and the numbers below are absent when refused, or
    /// when the case failed before they were measured).
    pub momentum: Option<f64>,
    /// Relative action–reaction gap.
    pub action_reaction: Option<f64>,
    /// Change of the twist at 10× the mass, rad.
    pub mass_twist: Option<f64>,
    /// Relative deviation of the peak torque from ×10 at 10× the mass.
    pub mass_torque: Option<f64>,
    /// Relative gap of the QP's peak to its closed form (absent when the QP has no solution or
    /// no closed form).
    pub qp_gap: Option<f64>,
}

/// Runs one case on the problem text `base` (TOML).
pub fn run_case(base: &str, case: &RandomCase) -> RandomResult {
    let mut out = RandomResult {
        case: case.clone(),
        verdict: Verdict::Passed,
        momentum: None,
        action_reaction: None,
        mass_twist: None,
        mass_torque: None,
        qp_gap: None,
    };
    let load = |extra: Option<String>| {
        let mut o = case.overrides.clone();
        o.extend(extra);
        Problem::from_toml(base, "stress.toml", &o).map_err(|e| e.to_string())
    };
    let resolved = load(None).and_then(|p| Resolved::new(&p).map_err(|e| e.to_string()));
    let r = match resolved {
        Ok(r) => r,
        Err(why) => {
            out.verdict = Verdict::Refused(why);
            return out;
        }
    };
    let p = &r.problem;
    let e = Evaluation::of_paper(&p.cat.half(), &r.schedule, &p.drop.spin(), &p.actuator.motors(), &p.exact);
    let heavy = match load(Some(format!("cat.mass={:e}", 10.0 * p.cat.mass))) {
        Ok(h) => h,
        Err(why) => {
            out.verdict = Verdict::Failed(format!("10× the mass refused: {why}"));
            return out;
        }
    };
    let e10 = Evaluation::of_paper(
        &heavy.cat.half(),
        &r.schedule,
        &heavy.drop.spin(),
        &heavy.actuator.motors(),
        &heavy.exact,
    );
    let (momentum, action_reaction) = (e.momentum_max, e.peaks.action_reaction_gap / e.peaks.max);
    let mass_twist = (e10.flip.twist - e.flip.twist).abs();
    let mass_torque = (e10.peaks.max / (10.0 * e.peaks.max) - 1.0).abs();
    let qp = qp_gap(&r, case.nodes);
    let finite = |x: f64| x.is_finite().then_some(x);
    out.momentum = finite(momentum);
    out.action_reaction = finite(action_reaction);
    out.mass_twist = finite(mass_twist);
    out.mass_torque = finite(mass_torque);
    out.qp_gap = qp.as_ref().ok().copied().and_then(finite);
    let numbers =
        [e.flip.twist, e.flip.swing, e.peaks.max, e.momentum_max, e.peaks.action_reaction_gap, e.peaks.accuracy];
    let numbers = numbers.iter().chain([&mass_twist, &mass_torque, &e10.peaks.max]);
    // Each check passes only on a finite number within its limit (`≤` is false for NaN); the
    // first check names a non-finite number, so no message below prints one.
    let checks = [
        (numbers.into_iter().all(|x| x.is_finite()), "a non-finite number from the exact engine".to_string()),
        (momentum <= MOMENTUM_LIMIT, format!("momentum residual {momentum:.1e}")),
        (action_reaction <= ACTION_REACTION_LIMIT, format!("action–reaction gap {action_reaction:.1e}")),
        (mass_twist <= MASS_TWIST_LIMIT, format!("twist changes by {mass_twist:.1e} rad at 10× the mass")),
        (mass_torque <= MASS_TORQUE_LIMIT, format!("torque off ×10 by {mass_torque:.1e} at 10× the mass")),
        match &qp {
            Ok(gap) if gap.is_finite() => {
                (*gap <= QP_GAP_LIMIT, format!("QP at N = {} off its closed form by {gap:.1e}", case.nodes))
            }
            Ok(_) => (false, format!("QP at N = {}: a non-finite gap to its closed form", case.nodes)),
            Err(why) => (false, format!("QP at N = {}: {why}", case.nodes)),
        },
    ];
    if let Some((_, why)) = checks.iter().find(|(ok, _)| !ok) {
        out.verdict = Verdict::Failed(why.clone());
    } else if !e.flip.converged {
        out.verdict = Verdict::Degraded(format!(
            "flip short of {:e} rad (estimate {:.1e}, {} steps per phase)",
            p.exact.tolerance, e.flip.error_estimate, e.flip.steps_per_phase
        ));
    } else if e.peaks.accuracy > 1e-6 {
        out.verdict = Verdict::Degraded(format!("peak torque accuracy {:.1e}", e.peaks.accuracy));
    }
    out
}

/// The QP's relative gap to its closed form at `nodes` on the twist phase of `r`, or why it has
/// none.
fn qp_gap(r: &Resolved, nodes: usize) -> Result<f64, String> {
    let qp = super::optimizers::twist_qp(&r.problem.cat.half(), &r.schedule, nodes);
    let exact = qp.closed_form_peak().ok_or("no closed form")?;
    let s = qp.solve().map_err(|e| e.to_string())?;
    let peak = s.peak_torque.filter(|_| s.status.is_solved()).ok_or_else(|| format!("Clarabel ended {}", s.status))?;
    Ok((peak - exact).abs() / exact)
}

/// Counts of verdicts.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize)]
pub struct Tally {
    /// Cases run.
    pub cases: usize,
    /// Passed.
    pub passed: usize,
    /// Refused with a reason.
    pub refused: usize,
    /// Degraded accuracy, with a cause.
    pub degraded: usize,
    /// Failed a check.
    pub failed: usize,
    /// Worst relative momentum residual over the accepted cases.
    pub worst_momentum: f64,
    /// Worst relative action–reaction gap.
    pub worst_action_reaction: f64,
    /// Worst change of the twist at 10× the mass, rad.
    pub worst_mass_twist: f64,
    /// Worst deviation of the peak torque from ×10 at 10× the mass (relative).
    pub worst_mass_torque: f64,
    /// Worst QP gap to its closed form (relative).
    pub worst_qp_gap: f64,
}

/// Runs cases `0..count` of `seed` on `base`; returns every result and the tally.
pub fn run_many(base: &str, seed: u64, count: usize) -> (Vec<RandomResult>, Tally) {
    let mut tally = Tally::default();
    let results: Vec<RandomResult> = (0..count)
        .map(|i| {
            let r = run_case(base, &draw(seed, i));
            tally.cases += 1;
            let worst = |w: &mut f64, x: Option<f64>| {
                if let Some(x) = x {
                    *w = w.max(x);
                }
            };
            worst(&mut tally.worst_momentum, r.momentum);
            worst(&mut tally.worst_action_reaction, r.action_reaction);
            worst(&mut tally.worst_mass_twist, r.mass_twist);
            worst(&mut tally.worst_mass_torque, r.mass_torque);
            worst(&mut tally.worst_qp_gap, r.qp_gap);
            match r.verdict {
                Verdict::Passed => tally.passed += 1,
                Verdict::Refused(_) => tally.refused += 1,
                Verdict::Degraded(_) => tally.degraded += 1,
                Verdict::Failed(_) => tally.failed += 1,
            }
            r
        })
        .collect();
    (results, tally)
}
