//! The exact-dynamics refinement: the timing of a phase of least *exact* peak torque.
//!
//! The profile QP ([`crate::optimize::qp`]) minimises the paper's model `I* · max|ω̇|`, which ignores the
//! bend amplitude and the centripetal `φ̇²` terms that dominate the real torques. Here the timing
//! of one phase is improved along its fixed joint path, described by a progress variable `φ`
//! ([`Schedule::progress_state`]): the bend direction in the twist (`φ ∈ [0, D]`), joint 1's angle in the bend
//! (`φ ∈ [0, β]`), the fraction straightened in the unbend (`φ ∈ [0, 1]`). Its rate `ω = φ̇` at
//! `N` nodes (linear between them) is improved by sequential linear programming with a trust
//! region on the exact torques of Newton–Euler ([`crate::engines::torque`]):
//!
//! - samples: both ends and the midpoint of every interval of the phase, each with its
//!   interval's constant `φ̈`, for both joints; at node `k`, `φ_k = Σ` trapezoid weights `· ω`,
//!   `φ̇ = ω_k`; on interval `i`, `φ̈ = (ω_{i+1} − ω_i)/h`, and at its midpoint
//!   `φ = φ_i + (3h/8) ω_i + (h/8) ω_{i+1}`, `φ̇ = (ω_i + ω_{i+1})/2`;
//! - gradients: `∂τ/∂(φ, φ̇, φ̈)` by central differences of the exact torque (exact in `φ̈`,
//!   in which the torque is affine), chained with those linear maps;
//! - step: [`solve_linearised_step`] (Clarabel) with the integral, boundary and limit
//!   constraints on `ω + δ`; accepted when the exact twist-phase peak, evaluated densely by
//!   [`crate::engines::torque::peak_torques`] (not only at the samples), falls by at least a tenth of the
//!   predicted fall; the radius doubles after good agreement and, after poor, drops to half the
//!   rejected step's length (half the radius when the step filled the box), so that a step well
//!   inside the box is not proposed again and again (Nocedal and Wright, Alg. 4.1 and §4.1).
//!
//! Because the joint path (and so the flip) does not depend on the timing, the refinement
//! changes torques only, never twist or swing. Bend and unbend are always rest to rest; the
//! problem's rate and jerk limits apply to the twist phase.
//!
//! ## References
//! - J. Nocedal and S. J. Wright, *Numerical Optimization*, 2nd ed. (2006), §4 and §18.

mod step;

use serde::Serialize;

use crate::engines::torque::{joint_torques, piece_peaks, Peak};
use crate::model::Cylinder;
use crate::optimize::conic::{ConicError, QpSettings, QpStatus};
use crate::problem::settings::{ExactSettings, OptimizeSettings};
use crate::schedule::profile::Profile;
use crate::schedule::{Phase, Schedule};

pub use step::{solve_linearised_step, LinearisedStep, StepSolution, TorqueSample};

/// How the refinement ended.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum RefineStatus {
    /// The trust radius shrank below its floor: no step improves the peak any more.
    Converged,
    /// The last [`STALL_ITERATIONS`] iterations lowered the peak by less than
    /// [`STALL_FRACTION`] of it: the first-order model creeps (a minimax optimum with many
    /// nearly active peaks), so further iterations would buy less than that.
    Stalled,
    /// The iteration budget ran out while still improving.
    MaxIterations,
    /// The step QP failed in a way a smaller radius cannot mend.
    StepFailed(QpStatus),
}

impl std::fmt::Display for RefineStatus {
    /// The kebab-case name, as in the JSON results; a failed step names the QP's status.
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            RefineStatus::Converged => f.write_str("converged"),
            RefineStatus::Stalled => f.write_str("stalled"),
            RefineStatus::MaxIterations => f.write_str("max-iterations"),
            RefineStatus::StepFailed(qp) => write!(f, "step-failed ({qp})"),
        }
    }
}

/// One outer iteration.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct RefineIteration {
    /// Exact twist-phase peak before the step, N·m.
    pub peak: f64,
    /// The linear model's predicted peak after it, N·m.
    pub predicted: f64,
    /// Exact twist-phase peak after it, N·m.
    pub actual: f64,
    /// Trust radius, rad/s.
    pub radius: f64,
    /// Whether the step was taken.
    pub accepted: bool,
    /// How the step QP ended.
    pub status: QpStatus,
}

/// The refined profile and its history.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Refinement {
    /// Node rates, rad/s.
    pub rates: Vec<f64>,
    /// Exact twist-phase peak of the start (dense evaluation), N·m.
    pub start_peak: f64,
    /// Exact twist-phase peak of the result (dense evaluation), N·m.
    pub final_peak: f64,
    /// The iterations.
    pub iterations: Vec<RefineIteration>,
    /// How it ended.
    pub status: RefineStatus,
}

impl Refinement {
    /// The refined profile (normalised).
    pub fn to_profile(&self) -> Option<Profile> {
        Profile::from_rate_nodes(crate::schedule::variant::Origin::Refined.profile_name(), &self.rates)
    }
}

/// The schedule with one phase's timing replaced by `profile`.
pub fn with_phase_profile(schedule: &Schedule, phase: Phase, profile: Profile) -> Schedule {
    match phase {
        Phase::Twist => schedule.with_profile(profile),
        Phase::Bend => Schedule { bend_profile: profile, ..schedule.clone() },
        Phase::Unbend => Schedule { unbend_profile: profile, ..schedule.clone() },
    }
}

/// Exact torque samples of one phase for node rates `w` of its progress variable, with their
/// gradients: at both ends and the midpoint of every interval, and at the phase-local instants
/// `extra` (s; the dense peaks, which may fall between those samples).
pub fn torque_samples(
    cat: &Cylinder,
    schedule: &Schedule,
    phase: Phase,
    w: &[f64],
    extra: &[f64],
) -> Vec<TorqueSample> {
    let n = w.len();
    let h = schedule.durations[phase.index()] / (n - 1) as f64;
    let phi: Vec<f64> = std::iter::once(0.0)
        .chain(w.windows(2).scan(0.0, |acc, p| {
            *acc += 0.5 * h * (p[0] + p[1]);
            Some(*acc)
        }))
        .collect();
    let tau = |a: f64, b: f64, c: f64| joint_torques(cat, &schedule.progress_state(phase, a, b, c)).tau;
    // φ's gradient at node k with respect to ω as (node, weight): the trapezoid weights.
    let phi_grad = |k: usize| -> Vec<(usize, f64)> {
        if k == 0 {
            return Vec::new();
        }
        let mut g = Vec::with_capacity(k + 3);
        g.push((0, 0.5 * h));
        g.extend((1..k).map(|m| (m, h)));
        g.push((k, 0.5 * h));
        g
    };
    let mut out = Vec::with_capacity(6 * (n - 1) + 2 * extra.len());
    // The sample at fraction σ ∈ [0, 1] of interval i, where ω is linear:
    // φ = φ_i + h(σ ω_i + σ²/2 (ω_{i+1} − ω_i)), φ̇ = (1 − σ) ω_i + σ ω_{i+1}, φ̈ = Δω/h.
    let mut sample = |i: usize, sigma: f64| {
        let acc = (w[i + 1] - w[i]) / h;
        let (wa, wb) = (h * (sigma - 0.5 * sigma * sigma), 0.5 * h * sigma * sigma);
        let a = phi[i] + wa * w[i] + wb * w[i + 1];
        let b = (1.0 - sigma) * w[i] + sigma * w[i + 1];
        let mut ga = phi_grad(i);
        ga.extend([(i, wa), (i + 1, wb)].into_iter().filter(|&(_, x)| x != 0.0));
        let gb = [(i, 1.0 - sigma), (i + 1, sigma)];
        let t0 = tau(a, b, acc);
        let (ea, eb) = (1e-6, 1e-6 * (1.0 + b.abs()));
        let (ap, am) = (tau(a + ea, b, acc), tau(a - ea, b, acc));
        let (bp, bm) = (tau(a, b + eb, acc), tau(a, b - eb, acc));
        let (cp, cm) = (tau(a, b, acc + 1.0), tau(a, b, acc - 1.0));
        for j in 0..2 {
            let d_phi = (ap[j] - am[j]) / (2.0 * ea);
            let d_rate = (bp[j] - bm[j]) / (2.0 * eb);
            let d_acc = (cp[j] - cm[j]) / 2.0;
            let mut g: Vec<(usize, f64)> = Vec::with_capacity(ga.len() + 4);
            g.extend(ga.iter().map(|&(k, x)| (k, x * d_phi)));
            g.extend(gb.iter().filter(|&&(_, x)| x != 0.0).map(|&(k, x)| (k, x * d_rate)));
            g.push((i + 1, d_acc / h));
            g.push((i, -d_acc / h));
            out.push(TorqueSample { value: t0[j], gradient: g });
        }
    };
    for i in 0..n - 1 {
        for sigma in [0.0, 0.5, 1.0] {
            sample(i, sigma);
        }
    }
    for &t in extra {
        let x = (t / h).clamp(0.0, (n - 1) as f64);
        let i = (x.floor() as usize).min(n - 2);
        sample(i, x - i as f64);
    }
    out
}

/// The refinement has stalled when [`STALL_ITERATIONS`] iterations lowered the peak by less
/// than this fraction of it.
pub const STALL_FRACTION: f64 = 1e-4;
/// See [`STALL_FRACTION`].
pub const STALL_ITERATIONS: usize = 8;

/// The exact peaks of one phase for node rates `w`, evaluated densely (`None` when the rates
/// do not make a profile).
fn phase_peaks(
    cat: &Cylinder,
    exact: &ExactSettings,
    schedule: &Schedule,
    phase: Phase,
    w: &[f64],
) -> Option<[Peak; 2]> {
    let p = Profile::from_rate_nodes("trial", w)?;
    Some(piece_peaks(cat, &with_phase_profile(schedule, phase, p), phase.index(), exact.torque_samples).peaks)
}

/// The larger of two joints' peaks, N·m; infinite when there are none.
fn larger(peaks: Option<[Peak; 2]>) -> f64 {
    peaks.map_or(f64::INFINITY, |[a, b]| a.value.max(b.value))
}

/// The instants of the peaks, s from the phase's start.
fn instants(peaks: Option<[Peak; 2]>) -> Vec<f64> {
    peaks.map_or_else(Vec::new, |p| p.iter().map(|x| x.time).collect())
}

/// Node rates of a profile scaled to a phase: `ω_k = (D/T) V(k/(N−1))`.
pub fn rate_nodes(profile: &Profile, distance: f64, duration: f64, nodes: usize) -> Vec<f64> {
    let nodes = nodes.max(2);
    (0..nodes).map(|k| distance / duration * profile.at(k as f64 / (nodes - 1) as f64).rate).collect()
}

fn sampled_peak(samples: &[TorqueSample]) -> f64 {
    samples.iter().map(|s| s.value.abs()).fold(0.0, f64::max)
}

/// Refines the node rates `start` of one phase's progress variable against that phase's exact
/// peak torque (the rate and jerk limits of the problem apply to the twist phase only).
pub fn refine(
    cat: &Cylinder,
    exact: &ExactSettings,
    opt: &OptimizeSettings,
    schedule: &Schedule,
    phase: Phase,
    start: &[f64],
) -> Result<Refinement, ConicError> {
    let t2 = schedule.durations[phase.index()];
    let distance = schedule.progress_distance(phase);
    // Bend and unbend must start and end at rest; the twist phase takes the user's boundary.
    let boundary = if phase == Phase::Twist { opt.boundary } else { crate::problem::settings::Boundary::RestToRest };
    let unit = distance.abs() / t2;
    let mut w = start.to_vec();
    let start_peaks = phase_peaks(cat, exact, schedule, phase, &w);
    let start_peak = larger(start_peaks);
    if unit == 0.0 {
        // A phase that does not move (the bend of a straight cat) has no timing to improve.
        return Ok(Refinement {
            rates: w,
            start_peak,
            final_peak: start_peak,
            iterations: Vec::new(),
            status: RefineStatus::Converged,
        });
    }
    let mut samples = torque_samples(cat, schedule, phase, &w, &instants(start_peaks));
    let mut peak = start_peak;
    let mut radius = 0.25 * unit;
    let floor = 1e-7 * unit;
    let mut iterations = Vec::new();
    let settings = QpSettings::default();
    let mut status = RefineStatus::MaxIterations;
    for _ in 0..opt.refine_iterations {
        let step = solve_linearised_step(
            &LinearisedStep {
                rates: &w,
                samples: &samples,
                trust_radius: radius,
                duration: t2,
                circulation: distance,
                boundary,
                rate_limit: if phase == Phase::Twist { opt.rate_limit } else { None },
                jerk_limit: if phase == Phase::Twist { opt.jerk_limit } else { None },
            },
            &settings,
        )?;
        let mut record = RefineIteration {
            peak,
            predicted: step.predicted_peak,
            actual: f64::NAN,
            radius,
            accepted: false,
            status: step.status,
        };
        if !step.status.is_solved() {
            if step.status.is_infeasible() && radius > floor {
                radius *= 0.5;
                iterations.push(record);
                continue;
            }
            iterations.push(record);
            status = RefineStatus::StepFailed(step.status);
            break;
        }
        let trial: Vec<f64> = w.iter().zip(&step.step).map(|(a, d)| a + d).collect();
        let trial_peaks = phase_peaks(cat, exact, schedule, phase, &trial);
        let actual = larger(trial_peaks);
        let predicted_fall = sampled_peak(&samples) - step.predicted_peak;
        let ratio = if predicted_fall > 0.0 { (peak - actual) / predicted_fall } else { -1.0 };
        record.actual = actual;
        if ratio > 0.1 {
            record.accepted = true;
            samples = torque_samples(cat, schedule, phase, &trial, &instants(trial_peaks));
            w = trial;
            peak = actual;
            if ratio > 0.75 {
                radius *= 2.0;
            }
        } else {
            // A step smaller than the box would come back unchanged from a merely halved box:
            // shrink below the rejected step itself.
            let length = step.step.iter().fold(0.0, |m: f64, d| m.max(d.abs()));
            radius = 0.5 * radius.min(length);
        }
        iterations.push(record);
        if radius < floor || predicted_fall <= 1e-12 * peak {
            status = RefineStatus::Converged;
            break;
        }
        if let Some(before) = iterations.len().checked_sub(STALL_ITERATIONS).map(|k| iterations[k].peak) {
            if before - peak < STALL_FRACTION * peak {
                status = RefineStatus::Stalled;
                break;
            }
        }
    }
    Ok(Refinement { rates: w, start_peak, final_peak: peak, iterations, status })
}
