//! The final measurement of a trajectory by the reference engines, never by the optimiser's
//! model: flip by [`crate::engines::exact::flip`], peak by [`crate::engines::torque::peak_torques`], energy by
//! Gauss–Legendre quadrature of [`crate::engines::torque::joint_torques`] (for a cat other than the
//! paper's, the general core's [`crate::engines::models::TwoMotorCat::flip`] and
//! [`crate::engines::models::TwoMotorCat::joint_torques`], [`WholeCat`]), the bend's shape, and
//! what it asks of the motors by [`crate::engines::motors::motor_demand`], and how cleanly the
//! torques switch ([`Chatter`]).

use std::f64::consts::{PI, TAU};

use serde::Serialize;

use super::cat::WholeCat;
use super::spline::BSpline;
use super::torques::ExactTorques;
use crate::model::motor::{motors_beyond, MotorsBeyond};
use nalgebra::Vector3;

use crate::engines::exact::Flip;
use crate::engines::motors::{motor_demand_from, MotorDemand};
use crate::engines::torque::{peak_torques_from, piece_samples};
use crate::model::motor::Motors;
use crate::schedule::Trajectory;

/// Samples per knot span of the peak search (each peak then refined by golden section).
pub const PEAK_SAMPLES_PER_SPAN: usize = 64;

/// What the reference engines say of a trajectory.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Measurement {
    /// The flip.
    pub flip: Flip,
    /// `| |twist| − π |`, rad.
    pub twist_error: f64,
    /// Peak `|τ|`, N·m.
    pub peak: f64,
    /// Its time, s.
    pub peak_time: f64,
    /// `∫ τ·τ dt`, N²·m²·s.
    pub energy: f64,
    /// Largest bend, rad.
    pub max_bend: f64,
    /// Turns of the bend direction about A's axis.
    pub bend_turns: f64,
    /// What it asks of the motors.
    pub motors: MotorDemand,
    /// How cleanly the torques switch between saturated arcs.
    pub chatter: Chatter,
}

/// How cleanly each joint's torque switches between saturated arcs, from [`CHATTER_SAMPLES`]
/// samples per knot span: a minimum-peak optimum should ride `±τ_max` and cross between them,
/// as an independent collocation does (`tests/reference/mintime.py`); a dip or spike between
/// the arcs is chatter a motor would be commanded.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct Chatter {
    /// Switches of `τ_j` from below `−τ_max/2` to above `τ_max/2` or back (`τ_max` the peak of
    /// every joint), one per motor.
    pub switches: Vec<usize>,
    /// The total variation of `τ_j` over the fall divided by that of a clean bang-bang profile
    /// with the same switches and end values, `2 τ_max n + (τ_max − |τ_j(0)|) + (τ_max − |τ_j(T)|)`,
    /// minus one: 0 for a clean profile.
    pub excess_variation: Vec<f64>,
    /// The least `|τ_j|/τ_max` farther than [`CHATTER_GUARD`] of the fall from `τ_j`'s own
    /// switches: the deepest dip of a saturated arc (1 for a clean profile).
    pub deepest_dip: Vec<f64>,
}

/// Samples per knot span of [`Chatter`].
pub const CHATTER_SAMPLES: usize = 16;

/// The share of the fall on either side of a switch that [`Chatter::deepest_dip`] leaves out.
pub const CHATTER_GUARD: f64 = 0.01;

/// The [`Chatter`] of the torques `tau` sampled at `times` (in order) over a fall of `duration` s.
pub fn chatter(times: &[f64], tau: &[Vec<f64>], duration: f64) -> Chatter {
    let peak = tau.iter().flatten().map(|t| t.abs()).fold(0.0, f64::max);
    let motors = tau.first().map_or(0, Vec::len);
    let mut out =
        Chatter { switches: vec![0; motors], excess_variation: vec![0.0; motors], deepest_dip: vec![0.0; motors] };
    if peak <= 0.0 || tau.is_empty() {
        return out;
    }
    for j in 0..motors {
        let x: Vec<f64> = tau.iter().map(|t| t[j]).collect();
        // The side (above +τ_max/2 or below −τ_max/2) last visited, none at first.
        let (mut side, mut switch_times): (Option<bool>, _) = (None, Vec::new());
        for (k, &v) in x.iter().enumerate() {
            if v.abs() > 0.5 * peak {
                if side.is_some_and(|above| above != (v > 0.0)) {
                    switch_times.push(times[k]);
                }
                side = Some(v > 0.0);
            }
        }
        let variation: f64 = x.windows(2).map(|w| (w[1] - w[0]).abs()).sum();
        let first = x[0].abs().min(peak);
        let last = x[x.len() - 1].abs().min(peak);
        let clean = 2.0 * peak * switch_times.len() as f64 + (peak - first) + (peak - last);
        out.switches[j] = switch_times.len();
        out.excess_variation[j] = if clean > 0.0 { variation / clean - 1.0 } else { 0.0 };
        let guard = CHATTER_GUARD * duration;
        out.deepest_dip[j] = times
            .iter()
            .zip(&x)
            .filter(|(t, _)| switch_times.iter().all(|s| (*t - s).abs() > guard))
            .map(|(_, v)| v.abs() / peak)
            .fold(1.0, f64::min);
    }
    out
}

/// Measures `spline` driven by `motors` (flip to `tolerance` rad).
pub fn measure(cat: &WholeCat, spline: &BSpline, motors: &Motors, tolerance: f64) -> Measurement {
    measure_spinning(cat, spline, motors, tolerance, &Vector3::zeros())
}

/// [`measure`] for a release with total angular momentum `spin` (N·m·s, world frame): the flip by
/// [`crate::engines::exact::flip_spinning`], every torque at the orientation of that motion
/// ([`WholeCat::torque_source`]); zero `spin` is [`measure`].
pub fn measure_spinning(
    cat: &WholeCat,
    spline: &BSpline,
    motors: &Motors,
    tolerance: f64,
    spin: &Vector3<f64>,
) -> Measurement {
    let (flip, history) = if spin.norm_squared() > 0.0 {
        let (f, h) = cat.spin_history(spline, spin, tolerance);
        (f, Some(h))
    } else {
        (cat.flip(spline, tolerance), None)
    };
    let torques = cat.exact_torques(history.as_ref());
    let torque = |piece: usize, s: f64| torques.at(spline, piece, s);
    let (peak, peak_time, demand) = match &torques {
        ExactTorques::TwoMotor(source) => {
            let peaks = peak_torques_from(source, spline, &vec![PEAK_SAMPLES_PER_SPAN; spline.piece_durations().len()]);
            let (peak, time) =
                peaks.per_piece.iter().flatten().map(|p| (p.value, p.time)).fold((0.0, 0.0), |best, p| {
                    if p.0 > best.0 {
                        p
                    } else {
                        best
                    }
                });
            let samples = piece_samples(spline, PEAK_SAMPLES_PER_SPAN);
            (peak, time, motor_demand_from(source, spline, &samples, motors))
        }
        ExactTorques::General(_) => {
            let limit = match motors_beyond(motors) {
                MotorsBeyond::Ideal => None,
                MotorsBeyond::TorqueLimit(limit) => Some(limit),
                MotorsBeyond::Other => {
                    unreachable!("other limits beyond two motors are refused before the optimiser (beyond_two_motors)")
                }
            };
            let (p, demand) = torques.peak_and_demand(spline, PEAK_SAMPLES_PER_SPAN, limit);
            (p.value, p.time, demand)
        }
    };
    // Five-point Gauss–Legendre on four parts of every span.
    let (a, b) = ((245.0 - 14.0 * 70f64.sqrt()).sqrt() / 21.0, (245.0 + 14.0 * 70f64.sqrt()).sqrt() / 21.0);
    let (wa, wb) = ((322.0 + 13.0 * 70f64.sqrt()) / 900.0, (322.0 - 13.0 * 70f64.sqrt()) / 900.0);
    let rule = [(-b, wb), (-a, wa), (0.0, 128.0 / 225.0), (a, wa), (b, wb)];
    let mut energy = 0.0;
    for (piece, d) in spline.piece_durations().into_iter().enumerate() {
        let h = d / 4.0;
        for part in 0..4 {
            for &(x, w) in &rule {
                let s = h * (part as f64 + 0.5 * (1.0 + x));
                let tau = torque(piece, s);
                energy += 0.5 * h * w * tau.iter().map(|t| t * t).sum::<f64>();
            }
        }
    }
    let (mut max_bend, mut turned, mut last): (f64, f64, Option<f64>) = (0.0, 0.0, None);
    let n = 64 * spline.spans();
    for k in 0..=n {
        let axis = cat.spine(&spline.angles(spline.duration() * k as f64 / n as f64));
        let bend = axis[2].clamp(-1.0, 1.0).acos();
        max_bend = max_bend.max(bend);
        if bend > 1f64.to_radians() {
            let dir = axis[1].atan2(axis[0]);
            if let Some(prev) = last {
                let mut d = dir - prev;
                d -= TAU * (d / TAU).round();
                turned += d;
            }
            last = Some(dir);
        }
    }
    let (mut times, mut samples) = (Vec::new(), Vec::new());
    let mut offset = 0.0;
    for (piece, d) in spline.piece_durations().into_iter().enumerate() {
        for k in 0..CHATTER_SAMPLES {
            let s = d * k as f64 / CHATTER_SAMPLES as f64;
            times.push(offset + s);
            samples.push(torque(piece, s));
        }
        offset += d;
    }
    times.push(spline.duration());
    samples.push(torques.at_end(spline));
    Measurement {
        chatter: chatter(&times, &samples, spline.duration()),
        twist_error: (flip.twist.abs() - PI).abs(),
        flip,
        peak,
        peak_time,
        energy,
        max_bend,
        bend_turns: turned / TAU,
        motors: demand,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `−1` until 0.3, `+1` until 0.7, `−1` after, the switches ramps of 0.01: clean; with a dip
    /// to 0.4 at 0.5 of one joint: that dip, and variation 2 × 0.6 over the clean 2 × 2.
    #[test]
    fn a_clean_bang_bang_profile_has_no_chatter_and_a_dip_is_measured() {
        let ramp = |t: f64, at: f64| ((t - at) / 0.005).clamp(-1.0, 1.0);
        let clean = |t: f64| ramp(t, 0.3) - ramp(t, 0.7) - 1.0;
        let times: Vec<f64> = (0..=10_000).map(|k| k as f64 / 10_000.0).collect();
        let tau: Vec<Vec<f64>> =
            times.iter().map(|&t| vec![clean(t), clean(t) + if (t - 0.5).abs() < 0.02 { -0.6 } else { 0.0 }]).collect();
        let c = chatter(&times, &tau, 1.0);
        assert_eq!(c.switches, vec![2, 2]);
        assert!(c.excess_variation[0].abs() < 1e-12, "{c:?}");
        assert!((c.deepest_dip[0] - 1.0).abs() < 1e-12, "{c:?}");
        assert!((c.excess_variation[1] - 1.2 / 4.0).abs() < 1e-12, "{c:?}");
        assert!((c.deepest_dip[1] - 0.4).abs() < 1e-12, "{c:?}");
    }
}
