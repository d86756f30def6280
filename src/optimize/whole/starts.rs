//! Starts of the optimisation: library schedules fitted to the spline.
//!
//! Each start is the problem's three-phase manoeuvre (its bend and phase split) on one bend path,
//! with its circulation calibrated on the exact engine ([`crate::engines::calibrate`]) so that it turns
//! the cat by π (up to the swing it leaves), then fitted to the clamped B-spline by least squares
//! ([`BSpline::fit`]) with the ends held straight and at rest. The mirror image `q2 → −q2`
//! (reflection through A's `yz`-plane, which reverses every twist) gives the other twist
//! direction. The cone start bends at most 60° (module constant), below the gimbal lock; with a
//! bend limit every start bends 2° less than it allows, and with a joint limit `q_max` every start
//! bends at most `q_max − 2°` (at least `q_max/2`), its control points clamped to `±q_max`:
//! a start outside the limits makes the first subproblem infeasible (the trust box cannot reach
//! the limit), which ended every start "PrimalInfeasible" at a 30° joint limit before.
//! None of them is the answer's shape: they bend and unbend in separate phases.

use super::settings::{StartKind, WholeSettings};
use super::spline::BSpline;
use nalgebra::Vector3;

use super::cat::WholeCat;
use crate::numeric::roots::RootStatus;
use crate::problem::manoeuvre::{BendPath, Manoeuvre, ProfileKind, CONE_GIMBAL_MARGIN_DEG};
use crate::schedule::profile::Profile;
use crate::schedule::{Schedule, ScheduleError};

/// The largest bend of the cone start, degrees.
pub const CONE_START_BEND_DEG: f64 = 60.0;

/// How far inside the bend limit a start bends, degrees.
pub const START_BEND_MARGIN_DEG: f64 = 2.0;

/// The straightest start, degrees between the halves: nearly straight halves need a
/// circulation of hundreds of radians to turn the cat (`π/C` with `C → 0`).
pub const MAX_START_THETA_DEG: f64 = 170.0;

/// A start: its name and its trajectory.
#[derive(Clone, Debug, PartialEq)]
pub struct NamedStart {
    /// The start's name.
    pub name: String,
    /// Its trajectory on the optimisation's spline.
    pub spline: BSpline,
}

/// The schedule a start is fitted to, with the circulation calibrated (the paper's `π/C` when the
/// calibration does not converge: a start only needs to be near a flip).
pub fn start_schedule(
    cat: impl Into<WholeCat>,
    duration: f64,
    manoeuvre: &Manoeuvre,
    kind: StartKind,
    min_angle_deg: Option<f64>,
    joint_limit_deg: Option<f64>,
) -> Result<Schedule, String> {
    start_schedule_spinning(&cat.into(), duration, manoeuvre, kind, min_angle_deg, joint_limit_deg, &Vector3::zeros())
}

/// [`start_schedule`] calibrated for a release with total angular momentum `spin` (world frame,
/// N·m·s; [`WholeCat::calibrate`]). A mirrored start is the mirror image of this schedule, so its
/// circulation is calibrated under the mirrored spin `(L_x, −L_y, −L_z)` (angular momentum is a
/// pseudovector: the reflection `x → −x` maps `L` to `−diag(−1, 1, 1) L`), and the start itself
/// turns by ±π under `spin`.
#[allow(clippy::too_many_arguments)]
pub fn start_schedule_spinning(
    cat: &WholeCat,
    duration: f64,
    manoeuvre: &Manoeuvre,
    kind: StartKind,
    min_angle_deg: Option<f64>,
    joint_limit_deg: Option<f64>,
    spin: &Vector3<f64>,
) -> Result<Schedule, String> {
    let (path, profile) = match kind {
        StartKind::Paper | StartKind::PaperMirrored => (BendPath::JointCircle, manoeuvre.profile),
        StartKind::Cone | StartKind::ConeMirrored => (BendPath::Cone, ProfileKind::Cycloidal),
    };
    // Beyond a 90° bend the cone's q1 runs past ±π/2 and its unbend `q = q_e(1 − P)` swings the
    // cat upside down (swing π): the cone start bends at most CONE_START_BEND_DEG.
    let mut theta_deg =
        if path == BendPath::Cone { manoeuvre.theta_deg.max(180.0 - CONE_START_BEND_DEG) } else { manoeuvre.theta_deg };
    // A start within the bend limit (neither path bends beyond β = 180° − θ).
    if let Some(limit) = min_angle_deg {
        if limit + START_BEND_MARGIN_DEG > MAX_START_THETA_DEG {
            return Err(format!(
                "optimize.whole.min_angle_deg = {limit} leaves a bend of at most {:.3}°; a start bends {START_BEND_MARGIN_DEG}° inside the limit and needs a bend of at least {:.0}°: lower optimize.whole.min_angle_deg to at most {}",
                180.0 - limit,
                180.0 - MAX_START_THETA_DEG,
                MAX_START_THETA_DEG - START_BEND_MARGIN_DEG
            ));
        }
        theta_deg = theta_deg.max(limit + START_BEND_MARGIN_DEG);
    }
    // Within the joint limit: both paths keep |q1|, |q2| at most the bend β = 180° − θ.
    let mut limited = None;
    if let Some(limit) = joint_limit_deg {
        let within = 180.0 - (limit - START_BEND_MARGIN_DEG).max(0.5 * limit);
        if within > theta_deg {
            theta_deg = within;
            limited = Some(limit);
        }
    }
    let manoeuvre = Manoeuvre { theta_deg, ..manoeuvre.clone() };
    if path == BendPath::Cone && (manoeuvre.bend().to_degrees() - 90.0).abs() < CONE_GIMBAL_MARGIN_DEG {
        return Err(format!("the cone path meets gimbal lock within {CONE_GIMBAL_MARGIN_DEG}° of a 90° bend"));
    }
    let circulation = cat.paper_circulation(manoeuvre.theta()).map_err(|e| match limited.filter(|_| matches!(e, ScheduleError::CirculationTooLarge(..))) {
        // The joint limit, not the manoeuvre, chose this bend: name it.
        Some(limit) => format!(
            "optimize.whole.joint_limit_deg = {limit} lets a start bend only {:.3}°, too little to turn the cat over (the paper's circulation there, π/C, exceeds the {} rad a schedule may circulate): raise optimize.whole.joint_limit_deg",
            180.0 - theta_deg,
            crate::problem::manoeuvre::MAX_CIRCULATION
        ),
        None => e.to_string(),
    })?;
    let schedule = Schedule {
        durations: manoeuvre.phases.map(|f| f * duration),
        bend: manoeuvre.bend(),
        path,
        profile: Profile::library(profile),
        circulation,
        bend_profile: Profile::harmonic(),
        unbend_profile: Profile::harmonic(),
    };
    let spin = if mirrored(kind) { Vector3::new(spin.x, -spin.y, -spin.z) } else { *spin };
    let cal = cat.calibrate(&schedule, &spin, 1e-9);
    Ok(if cal.status == RootStatus::Converged { schedule.with_circulation(cal.circulation) } else { schedule })
}

/// Whether `kind` is a mirror image (`q2 → −q2`).
fn mirrored(kind: StartKind) -> bool {
    matches!(kind, StartKind::PaperMirrored | StartKind::ConeMirrored)
}

/// The start `kind` on the spline of `settings`.
pub fn build_start(
    cat: impl Into<WholeCat>,
    duration: f64,
    manoeuvre: &Manoeuvre,
    kind: StartKind,
    settings: &WholeSettings,
) -> Result<NamedStart, String> {
    build_start_spinning(cat.into(), duration, manoeuvre, kind, settings, &Vector3::zeros())
}

/// [`build_start`] for a release with total angular momentum `spin` ([`start_schedule_spinning`]).
pub fn build_start_spinning(
    cat: impl Into<WholeCat>,
    duration: f64,
    manoeuvre: &Manoeuvre,
    kind: StartKind,
    settings: &WholeSettings,
    spin: &Vector3<f64>,
) -> Result<NamedStart, String> {
    let cat = &cat.into();
    // A spherical joint starts on its no-twist path (its relative twist held at zero).
    if let Some(bent) = cat.start_cat() {
        let start = build_start_spinning(bent, duration, manoeuvre, kind, settings, spin)?;
        let spline = start.spline.with_joints(cat.joints());
        return near_a_flip(cat, &spline, spin).map(|()| NamedStart { spline, ..start });
    }
    let schedule = start_schedule_spinning(
        cat,
        duration,
        manoeuvre,
        kind,
        settings.min_angle_deg,
        settings.joint_limit_deg,
        spin,
    )?;
    let sign = if mirrored(kind) { -1.0 } else { 1.0 };
    let mut spline = BSpline::fit(duration, settings.control_points, WholeSettings::DEGREE, settings.fixed(), 2, |t| {
        let q = schedule.state(t.min(duration)).q;
        vec![q[0], sign * q[1]]
    })
    // A cat with a tail or legs moves its halves alone, the appendages held still (its schedule
    // calibrated so, on the whole tree).
    .with_joints(cat.joints());
    // The fit may overshoot the path a little: the joint limit holds on the control points (and so
    // on the whole curve, by the convex-hull property) from the start.
    if let Some(limit) = settings.joint_limit_deg.map(f64::to_radians) {
        for c in spline.coefficients.iter_mut().flatten() {
            *c = c.clamp(-limit, limit);
        }
    }
    near_a_flip(cat, &spline, spin)?;
    Ok(NamedStart { name: kind.name().to_string(), spline })
}

/// Refuses a start that lands with a swing above 90°: the orientation error `log(R_zᵀ(π) R)` is
/// singular at a half-turn from the target.
fn near_a_flip(cat: &WholeCat, spline: &BSpline, spin: &Vector3<f64>) -> Result<(), String> {
    let f = cat.flip_spinning(spline, spin, 1e-6);
    if f.swing > 0.5 * std::f64::consts::PI {
        return Err(format!("the fitted start lands with swing {:.1}°, too far from a flip", f.swing.to_degrees()));
    }
    Ok(())
}
