//! `catflip optimize --whole`: the whole-manoeuvre optimum of a resolved problem
//! ([`crate::optimize::whole`]), measured as every schedule is.
//!
//! The optimiser decides with its own measurement of each start (its log, its status); the
//! optimum it returns is then measured by the one function every schedule goes through
//! ([`crate::engines::measured::Rig::measure`]: flip, peaks, motor demand, momentum, on the
//! problem's cat, release and motors), and those are the numbers reported, exported and verified.
//! The optimum has no phases of its own (it bends and circulates at once), so its peaks are also
//! given over the time windows of the problem's phases, for the peak-torque table; `max` is the
//! peak over the whole fall.

use serde::Serialize;

use crate::engines::measured::Measured;
use crate::engines::motors::LimitUse;
use crate::engines::peaks::PhasePeaks;
use crate::engines::rapier::{RapierError, Verification};
use crate::engines::resolved::Resolved;
use crate::optimize::whole::{
    optimize_whole_spinning, BSpline, Objective, WholeCat, WholeError, WholeOutcome, WholeSolution,
};
use crate::schedule::variant::ScheduleName;
use crate::schedule::Trajectory;

/// Samples per second of fall used to split the optimum's peaks over the phase windows (the
/// whole-fall maximum is the refined peak of the optimiser's re-measurement).
const WINDOW_SAMPLES: usize = 20_000;

/// A limit whose usage ratio is within this of 1 counts as active.
pub const ACTIVE_RATIO: f64 = 1e-3;

/// The whole-manoeuvre optimum of a problem.
#[derive(Clone, Debug, Serialize)]
pub struct WholeReport {
    /// Problem name.
    pub problem: String,
    /// The cat optimised, in words ([`crate::model::Cat::describe`]).
    pub cat: String,
    /// What was minimised.
    pub objective: Objective,
    /// How the best start ended (`converged` or `upper-bound`, [`crate::optimize::whole::WholeStatus`]),
    /// or why there is no optimum.
    pub status: String,
    /// Signed twist of the optimum, degrees (absent when no start flipped the cat).
    pub twist_deg: Option<f64>,
    /// Swing of the optimum, degrees.
    pub swing_deg: Option<f64>,
    /// Peak motor torques of the optimum, N·m: `max` over the whole fall, and over the time
    /// windows of the problem's phases.
    pub peak_torque_nm: Option<PhasePeaks>,
    /// `∫ τ·τ dt` of the optimum, N²·m²·s.
    pub energy: Option<f64>,
    /// Trust-region iterations of the best start.
    pub iterations: Option<usize>,
    /// The largest bend of the optimum (angle between the spine axes), degrees.
    pub max_bend_deg: Option<f64>,
    /// How far its bend direction turns over the fall, turns.
    pub bend_turns: Option<f64>,
    /// The optimum's fall time, s: the problem's, or with the objective `min-time` the least
    /// fall time within the motors.
    pub fall_time_s: Option<f64>,
    /// The drop height of that fall, `g T²/2`, m.
    pub drop_height_m: Option<f64>,
    /// Peak joint speeds of joints 1 and 2, rad/s.
    pub peak_speed_rad_s: Option<Vec<f64>>,
    /// Peak mechanical powers `|τ q̇|` of joints 1 and 2, W.
    pub peak_power_w: Option<Vec<f64>>,
    /// The motor limits the optimum reaches (usage within [`ACTIVE_RATIO`] of 1), where and when.
    pub active_limits: Vec<LimitUse>,
    /// The motors' verdict on the optimum, in words ("ideal motors" without `[actuator]`).
    pub motors: Option<String>,
    /// Every start's outcome, the best one included.
    pub outcome: WholeOutcome,
    /// The release's total angular momentum `drop.angular_momentum`, N·m·s, world frame (left
    /// out at zero): every number above is then that of the spinning motion.
    #[serde(skip_serializing_if = "is_zero3")]
    pub angular_momentum_nms: [f64; 3],
    /// The optimum measured (and, once [`WholeReport::verify`] ran, verified in rapier).
    #[serde(skip)]
    pub measured: Option<Measured<BSpline>>,
}

fn is_zero3(l: &[f64; 3]) -> bool {
    l.iter().all(|x| *x == 0.0)
}

impl WholeReport {
    /// Whether the cat is released with spin (every number is then the spinning motion's).
    pub fn spins(&self) -> bool {
        !is_zero3(&self.angular_momentum_nms)
    }

    /// The optimum, when a start ended on a result that flips the cat
    /// ([`crate::optimize::whole::WholeOutcome::best`]).
    pub fn best(&self) -> Option<&WholeSolution> {
        self.outcome.best()
    }

    /// The optimum's trajectory, when there is one.
    pub fn spline(&self) -> Option<&BSpline> {
        self.measured.as_ref().map(|m| &m.trajectory)
    }

    /// Verifies the optimum in rapier on the problem's rig (nothing when there is no optimum).
    pub fn verify(&mut self, r: &Resolved) -> Result<(), RapierError> {
        match self.measured.as_mut() {
            Some(m) => m.verify(r.rig()),
            None => Ok(()),
        }
    }

    /// rapier's verification of the optimum, once verified.
    pub fn verification(&self) -> Option<&Verification> {
        self.measured.as_ref().and_then(Measured::verification)
    }
}

/// Runs the whole-manoeuvre optimisation on a resolved problem (`[optimize.whole]`), on its cat
/// model ([`WholeCat`]: the paper's cat through the two-cylinder engine), and measures the
/// optimum.
pub fn whole(r: &Resolved) -> Result<WholeReport, WholeError> {
    let p = &r.problem;
    let settings = &p.optimize.whole;
    let cat = WholeCat::from(r.model());
    let outcome = optimize_whole_spinning(
        &cat,
        p.drop.fall_time(),
        &p.manoeuvre,
        settings,
        &p.actuator.motors(),
        p.exact.tolerance,
        &p.drop.spin(),
    )?;
    let best = outcome.best();
    let status = match best {
        Some(b) => b.status.to_string(),
        None => outcome.no_optimum(settings, p.exact.tolerance),
    };
    let measured = best.map(|b| r.measure(ScheduleName::WholeOptimum, b.spline.clone()));
    let e = measured.as_ref().map(|m| &m.exact);
    let peaks = measured.as_ref().map(|m| window_peaks(r, &cat, &m.trajectory, m.exact.peak()));
    let fall = best.map(|b| b.fall_time_s);
    Ok(WholeReport {
        problem: p.name.clone(),
        cat: cat.describe(),
        objective: settings.objective,
        status,
        twist_deg: e.map(|e| e.twist_deg()),
        swing_deg: e.map(|e| e.swing_deg()),
        peak_torque_nm: peaks,
        energy: best.map(|b| b.energy),
        iterations: best.map(|b| b.iterations),
        max_bend_deg: best.map(|b| b.max_bend_deg),
        bend_turns: best.map(|b| b.bend_turns),
        fall_time_s: fall,
        drop_height_m: fall.map(|t| p.drop.height_for(t)),
        peak_speed_rad_s: e.map(|e| e.motors.peak_speed_rad_s.iter().map(|x| x.value).collect()),
        peak_power_w: e.map(|e| e.motors.peak_power_w.iter().map(|x| x.value).collect()),
        active_limits: e
            .map(|e| e.motors.limits.iter().copied().filter(|l| l.ratio >= 1.0 - ACTIVE_RATIO).collect())
            .unwrap_or_default(),
        motors: e.map(|e| e.motors.verdict()),
        outcome,
        angular_momentum_nms: p.drop.angular_momentum,
        measured,
    })
}

/// The optimum's peaks over the time windows of the problem's phases (as fractions of its own
/// duration, which `min-time` makes shorter than the problem's fall); `max` is `peak`, the
/// refined whole-fall peak (at least every window's sampled peak).
fn window_peaks(r: &Resolved, cat: &WholeCat, spline: &BSpline, peak: f64) -> PhasePeaks {
    let total = spline.total_duration();
    let to_schedule = r.schedule.duration() / total;
    let n = ((WINDOW_SAMPLES as f64 * total).ceil() as usize).max(64);
    let mut w = [[0.0f64; 2]; 3];
    for (t, tau) in sampled_torques(r, cat, spline, n) {
        let window = &mut w[r.schedule.locate(t * to_schedule).0.index()];
        for (m, x) in window.iter_mut().zip(tau) {
            *m = m.max(x.abs());
        }
    }
    let sampled = w.iter().flatten().copied().fold(0.0, f64::max);
    PhasePeaks { bend: w[0], twist: w[1], unbend: w[2], max: peak.max(sampled) }
}

/// The motor torques `(t, [τ₁, τ₂])` of `spline` on `cat` at `n + 1` instants evenly spaced over
/// it, ends included, released as the problem says (with spin, at the orientations of the
/// spinning motion).
fn sampled_torques(r: &Resolved, cat: &WholeCat, spline: &BSpline, n: usize) -> Vec<(f64, [f64; 2])> {
    let total = spline.total_duration();
    let spin = r.problem.drop.spin();
    let history = r.problem.drop.spins().then(|| cat.spin_history(spline, &spin, r.problem.exact.tolerance).1);
    let source = cat.torque_source(history.as_ref());
    (0..=n)
        .map(|k| {
            let t = total * k as f64 / n as f64;
            let (piece, s) = spline.locate_piece(t);
            (t, source.at(spline, piece, s, &spline.piece_state(piece, s)).tau)
        })
        .collect()
}
