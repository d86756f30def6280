//! What a trajectory asks of its motors: the motor-sizing figures (DESIGN.md §9).
//!
//! Per joint `j`, over the whole trajectory:
//! - the peak speed `max |q̇_j|` (rad/s) and the peak mechanical power `max |τ_j q̇_j|` (W), with
//!   the torques `τ` from Newton–Euler on the zero-momentum motion ([`crate::engines::torque`]);
//! - with limits ([`crate::model::motor`]), each limit's worst usage ratio `max ρ` (within when
//!   `ρ ≤ 1`; `1 − ρ` is the margin) and where it occurs;
//! - the largest stretch `k`: the factor by which the same path must be slowed to stay within
//!   every limit (`k ≤ 1`: within), so that the path's least duration is `k` times its own.
//!
//! Sampling follows the trajectory's own time scale, as the peak torques do
//! ([`crate::engines::torque::piece_samples`]), with both sides of every acceleration jump; the
//! largest sample of each quantity (and each piece's within 2 % of it) is refined by
//! golden-section search between its neighbours.

use serde::{Deserialize, Serialize};

use crate::engines::torque::{piece_peaks_sampled, Peak, PeakCollector, PeakTorques, PieceSamples, TorqueSource};
use crate::model::motor::{Limit, Motors};
use crate::model::Cylinder;
use crate::numeric::roots::golden_max;
use crate::schedule::Trajectory;

/// A usage ratio above `1 + RATIO_TOLERANCE` exceeds its limit (round-off of the measurement).
pub const RATIO_TOLERANCE: f64 = 1e-9;

/// A limit's worst usage over a trajectory.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct LimitUse {
    /// Which limit.
    pub limit: Limit,
    /// Which joint coordinate (its motor): 1 or 2; beyond two motors 1 to their number.
    pub joint: usize,
    /// `max ρ`, dimensionless (at most 1 within the limit).
    pub ratio: f64,
    /// When it occurs, s.
    pub time: f64,
}

impl LimitUse {
    /// Whether the limit is exceeded.
    pub fn exceeded(&self) -> bool {
        self.ratio > 1.0 + RATIO_TOLERANCE
    }

    /// The limit in words, e.g. "joint 2's speed limit at 0.712 s (112.0 %)".
    pub fn describe(&self) -> String {
        format!("joint {}'s {} limit at {:.3} s ({:.1} %)", self.joint, self.limit, self.time, 100.0 * self.ratio)
    }
}

/// The largest stretch over a trajectory ([`crate::model::motor`]).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct StretchPeak {
    /// `max k`, dimensionless.
    pub value: f64,
    /// When, s.
    pub time: f64,
    /// Which joint coordinate (its motor): 1 or 2; beyond two motors 1 to their number.
    pub joint: usize,
    /// Which limit.
    pub limit: Limit,
}

/// What a trajectory asks of its motors.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct MotorDemand {
    /// Peak `|q̇_j|` of each joint coordinate (joints 1 and 2; beyond two motors, every motor's), rad/s.
    pub peak_speed_rad_s: Vec<Peak>,
    /// Peak `|τ_j q̇_j|` of each joint coordinate, W.
    pub peak_power_w: Vec<Peak>,
    /// Each limit's worst usage, joint 1's limits first; empty with ideal motors.
    pub limits: Vec<LimitUse>,
    /// The largest stretch; none with ideal motors.
    pub stretch: Option<StretchPeak>,
}

impl MotorDemand {
    /// The limits exceeded.
    pub fn exceeded(&self) -> Vec<LimitUse> {
        self.limits.iter().copied().filter(LimitUse::exceeded).collect()
    }

    /// The limit with the least margin (largest ratio), if any.
    pub fn worst(&self) -> Option<LimitUse> {
        self.limits.iter().copied().max_by(|a, b| a.ratio.total_cmp(&b.ratio))
    }

    /// Whether every limit holds (true with ideal motors).
    pub fn within(&self) -> bool {
        self.exceeded().is_empty()
    }

    /// The verdict in words: within the motors (with the least margin), or which limits the
    /// trajectory exceeds, by how much and when; "ideal motors" without limits.
    pub fn verdict(&self) -> String {
        let exceeded = self.exceeded();
        if !exceeded.is_empty() {
            let list: Vec<String> = exceeded.iter().map(LimitUse::describe).collect();
            return format!("exceeds {}", list.join(", "));
        }
        match self.worst() {
            Some(w) => {
                format!("within the motors (least margin {:.1} %: {})", 100.0 * (1.0 - w.ratio).max(0.0), w.describe())
            }
            None => "ideal motors".to_string(),
        }
    }

    /// The worst usage as a table cell: `—` with ideal motors, else the largest ratio and its
    /// limit, e.g. `82.1 % (joint 2 speed)`, with `EXCEEDS` in front when above 100 %.
    pub fn usage_cell(&self) -> String {
        match self.worst() {
            None => "—".to_string(),
            Some(w) => format!(
                "{}{:.1} % (joint {} {})",
                if w.exceeded() { "EXCEEDS " } else { "" },
                100.0 * w.ratio,
                w.joint,
                w.limit
            ),
        }
    }

    /// The CSV header of [`MotorDemand::csv_fields`].
    pub const CSV_HEADER: [&'static str; 7] = [
        "peak_speed1_rad_s",
        "peak_speed2_rad_s",
        "peak_power1_w",
        "peak_power2_w",
        "motor_worst_ratio",
        "motor_worst_limit",
        "within_motors",
    ];

    /// The motor-sizing figures as CSV fields (the last three empty with ideal motors): joints 1
    /// and 2 (more motors' are in [`MotorDemand::peak_speed_rad_s`] and [`MotorDemand::peak_power_w`]).
    pub fn csv_fields(&self) -> [String; 7] {
        let w = self.worst();
        [
            format!("{:.9}", self.peak_speed_rad_s[0].value),
            format!("{:.9}", self.peak_speed_rad_s[1].value),
            format!("{:.9}", self.peak_power_w[0].value),
            format!("{:.9}", self.peak_power_w[1].value),
            w.map_or(String::new(), |w| format!("{:.9}", w.ratio)),
            w.map_or(String::new(), |w| format!("joint {} {}", w.joint, w.limit)),
            w.map_or(String::new(), |_| self.within().to_string()),
        ]
    }

    /// The largest motor's peak speed, rad/s.
    pub fn max_speed(&self) -> f64 {
        self.peak_speed_rad_s.iter().map(|p| p.value).fold(0.0, f64::max)
    }

    /// The largest motor's peak power, W.
    pub fn max_power(&self) -> f64 {
        self.peak_power_w.iter().map(|p| p.value).fold(0.0, f64::max)
    }
}

/// One sampled quantity.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Channel {
    Speed(usize),
    Power(usize),
    Ratio(usize, Limit),
    Stretch,
}

impl Channel {
    fn value(self, motors: &Motors, tau: [f64; 2], qd: [f64; 2]) -> f64 {
        match self {
            Channel::Speed(j) => qd[j].abs(),
            Channel::Power(j) => (tau[j] * qd[j]).abs(),
            Channel::Ratio(j, limit) => {
                motors.joints[j].ratios(tau[j], qd[j]).into_iter().find(|r| r.0 == limit).map_or(0.0, |r| r.1)
            }
            Channel::Stretch => {
                (0..2).filter_map(|j| motors.joints[j].stretch(tau[j], qd[j]).map(|s| s.1)).fold(0.0, f64::max)
            }
        }
    }
}

/// The best sample of a channel: value, piece, position in the piece, and the bracket
/// `[lo, hi]` (local times) its refinement searches, empty for a one-sided limit.
#[derive(Clone, Copy, Debug)]
struct Best {
    value: f64,
    piece: usize,
    s: f64,
    lo: f64,
    hi: f64,
}

/// Measures what `traj` asks of `motors` on `samples[i] + 1` points of piece `i` (module docs).
pub fn motor_demand(cat: &Cylinder, traj: &impl Trajectory, samples: &[usize], motors: &Motors) -> MotorDemand {
    motor_demand_from(&TorqueSource::zero_momentum(cat), traj, samples, motors)
}

/// [`motor_demand`] with the torques of `source`.
pub fn motor_demand_from(
    source: &TorqueSource,
    traj: &impl Trajectory,
    samples: &[usize],
    motors: &Motors,
) -> MotorDemand {
    let mut demand = DemandCollector::new(motors);
    for (piece, dur) in traj.piece_durations().into_iter().enumerate() {
        let sampled = PieceSamples::of_duration(source, traj, piece, dur, samples.get(piece).copied().unwrap_or(2));
        demand.push(piece, &sampled);
    }
    demand.finish(source, traj)
}

/// The peak torques ([`crate::engines::torque::peak_torques_from`]) and the motor demand
/// ([`motor_demand_from`]) of `traj` on the same samples, each sample's torques computed once
/// for both: the same numbers as the two calls.
pub fn peaks_and_demand(
    source: &TorqueSource,
    traj: &impl Trajectory,
    samples: &[usize],
    motors: &Motors,
) -> (PeakTorques, MotorDemand) {
    let mut peaks = PeakCollector::default();
    let mut demand = DemandCollector::new(motors);
    for (piece, dur) in traj.piece_durations().into_iter().enumerate() {
        let sampled = PieceSamples::of_duration(source, traj, piece, dur, samples.get(piece).copied().unwrap_or(2));
        peaks.push(piece_peaks_sampled(source, traj, piece, &sampled), dur);
        demand.push(piece, &sampled);
    }
    (peaks.finish(), demand.finish(source, traj))
}

/// [`motor_demand_from`]'s pieces gathered one by one, then refined.
struct DemandCollector<'m> {
    motors: &'m Motors,
    channels: Vec<Channel>,
    /// Per piece, per channel: the best sample.
    per_piece: Vec<Vec<Best>>,
}

impl<'m> DemandCollector<'m> {
    fn new(motors: &'m Motors) -> Self {
        let mut channels = vec![Channel::Speed(0), Channel::Speed(1), Channel::Power(0), Channel::Power(1)];
        for (j, m) in motors.joints.iter().enumerate() {
            channels.extend(m.ratios(0.0, 0.0).into_iter().map(|(l, _)| Channel::Ratio(j, l)));
        }
        if !motors.is_ideal() {
            channels.push(Channel::Stretch);
        }
        Self { motors, channels, per_piece: Vec::new() }
    }

    /// The next piece, `piece`, from its samples.
    fn push(&mut self, piece: usize, sampled: &PieceSamples) {
        let (motors, channels) = (self.motors, &self.channels);
        let values = |tau: [f64; 2], qd: [f64; 2]| channels.iter().map(move |c| c.value(motors, tau, qd));
        let (h, dur) = (sampled.h, sampled.dur);
        let mut best = vec![Best { value: f64::NEG_INFINITY, piece, s: 0.0, lo: 0.0, hi: 0.0 }; channels.len()];
        // Where q̈ jumps inside the piece the channels are smooth only between the jumps: each
        // segment's samples are refined within their segment, and its ends (both sides of every
        // jump) are one-sided limits; a smooth piece's samples are refined between neighbours.
        for (s, st, jt) in &sampled.points {
            // Between the neighbours, within the sample's own segment.
            let segments = &sampled.segments;
            let k = segments.partition_point(|seg| seg.b <= *s).min(segments.len().saturating_sub(1));
            let (a, b) = segments.get(k).map_or((0.0, dur), |seg| (seg.a, seg.b));
            take(&mut best, values(jt.tau, st.qd), *s, ((s - h).max(a), (s + h).min(b)));
        }
        for seg in &sampled.segments {
            let m = seg.points.len() - 1;
            for (k, (s, st, jt)) in seg.points.iter().enumerate() {
                let bracket = if k == 0 || k == m { (*s, *s) } else { (seg.at(k - 1), seg.at(k + 1)) };
                take(&mut best, values(jt.tau, st.qd), *s, bracket);
            }
        }
        self.per_piece.push(best);
    }

    /// Every channel's largest sample (and each piece's within 2 % of it) refined, as the demand.
    fn finish(self, source: &TorqueSource, traj: &impl Trajectory) -> MotorDemand {
        let Self { motors, channels, per_piece } = self;
        let durations = traj.piece_durations();
        let mut t0 = 0.0;
        let starts: Vec<f64> = durations
            .iter()
            .map(|d| {
                let s = t0;
                t0 += d;
                s
            })
            .collect();
        let refined: Vec<(f64, f64)> = (0..channels.len())
            .map(|c| {
                let top = per_piece.iter().map(|b| b[c].value).fold(f64::NEG_INFINITY, f64::max);
                let mut out = (f64::NEG_INFINITY, 0.0);
                for b in per_piece.iter().map(|b| b[c]).filter(|b| b.value >= top - 0.02 * top.abs()) {
                    let mut candidate = (b.value, b.s);
                    if b.hi > b.lo {
                        let f = |s: f64| {
                            let st = traj.piece_state(b.piece, s);
                            channels[c].value(motors, source.at(traj, b.piece, s, &st).tau, st.qd)
                        };
                        let (s, v) = golden_max(f, b.lo, b.hi, 40);
                        if v > candidate.0 {
                            candidate = (v, s);
                        }
                    }
                    if candidate.0 > out.0 {
                        out = (candidate.0, starts[b.piece] + candidate.1);
                    }
                }
                out
            })
            .collect();
        demand_of(motors, &channels, &refined, source, traj)
    }
}

/// Keeps, per channel, the larger of its best sample and `values` (the channels' values at `s`,
/// in order; `(lo, hi)` the bracket its refinement searches, empty for a one-sided limit).
fn take(best: &mut [Best], values: impl Iterator<Item = f64>, s: f64, (lo, hi): (f64, f64)) {
    for (b, v) in best.iter_mut().zip(values) {
        if v > b.value {
            *b = Best { value: v, piece: b.piece, s, lo, hi };
        }
    }
}

/// The demand from each channel's refined `(value, time)`.
fn demand_of(
    motors: &Motors,
    channels: &[Channel],
    refined: &[(f64, f64)],
    source: &TorqueSource,
    traj: &impl Trajectory,
) -> MotorDemand {
    let peak = |c: usize| Peak { value: refined[c].0.max(0.0), time: refined[c].1 };
    let mut limits = Vec::new();
    let mut stretch = None;
    for (c, ch) in channels.iter().enumerate() {
        match *ch {
            Channel::Ratio(j, limit) => {
                limits.push(LimitUse { limit, joint: j + 1, ratio: refined[c].0.max(0.0), time: refined[c].1 })
            }
            Channel::Stretch => {
                let (value, time) = refined[c];
                let (piece, s) = traj.locate_piece(time);
                let st = traj.piece_state(piece, s);
                let tau = source.at(traj, piece, s, &st).tau;
                let (joint, limit) = (0..2)
                    .filter_map(|j| motors.joints[j].stretch(tau[j], st.qd[j]).map(|(l, k)| (j, l, k)))
                    .max_by(|a, b| a.2.total_cmp(&b.2))
                    .map_or((1, Limit::Torque), |(j, l, _)| (j + 1, l));
                stretch = Some(StretchPeak { value: value.max(0.0), time, joint, limit });
            }
            _ => {}
        }
    }
    MotorDemand { peak_speed_rad_s: vec![peak(0), peak(1)], peak_power_w: vec![peak(2), peak(3)], limits, stretch }
}
