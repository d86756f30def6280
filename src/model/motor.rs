//! What a joint's motor can do (DESIGN.md §9), and how much of it a motion asks for.
//!
//! A motor has up to four limits on its torque `τ` and speed `q̇` (units N·m, rad/s, W):
//!
//! | limit | within when | usage ratio `ρ` |
//! |---|---|---|
//! | torque | `|τ| ≤ τ_max` | `|τ|/τ_max` |
//! | speed | `|q̇| ≤ ω_max` | `|q̇|/ω_max` |
//! | envelope (DC motor) | `|τ| ≤ τ_s (1 − |q̇|/ω_0)` | `|τ|/τ_s + |q̇|/ω_0` |
//! | power | `|τ q̇| ≤ P` | `|τ q̇|/P` |
//!
//! so a motion is within a limit where `ρ ≤ 1`, and `1 − ρ` is its margin.
//!
//! ## Slowing a motion down
//! At zero angular momentum the torques of a joint path traversed `k` times slower scale exactly
//! as `1/k²` and its speeds as `1/k` (DESIGN.md §9). The least factor `k` that brings one instant
//! `(τ, q̇)` within a limit is its **stretch**:
//!
//! $$ k_τ = \sqrt{|τ|/τ_{max}},\quad k_ω = |q̇|/ω_{max},\quad
//!    k_P = (|τ q̇|/P)^{1/3},\quad k_{env} = \tfrac12\big(u + \sqrt{u^2 + 4v}\big), $$
//!
//! with `u = |q̇|/ω_0`, `v = |τ|/τ_s` (the positive root of `v/k² + u/k = 1`). A motion is within
//! every limit iff its largest stretch is at most 1, and a path's least duration within the
//! motors is its duration times its largest stretch. [`Motor::stretch_squared`] gives `k²`
//! (proportional to the drop height) with its partial derivatives, which the whole-manoeuvre
//! optimiser linearises.

use serde::{Deserialize, Serialize};

/// Which limit of a motor.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Limit {
    /// `|τ| ≤ τ_max`.
    Torque,
    /// `|q̇| ≤ ω_max`.
    Speed,
    /// `|τ| ≤ τ_s (1 − |q̇|/ω_0)`.
    Envelope,
    /// `|τ q̇| ≤ P`.
    Power,
}

impl Limit {
    /// Every limit, in the order a motor lists them.
    pub const ALL: [Limit; 4] = [Limit::Torque, Limit::Speed, Limit::Envelope, Limit::Power];

    /// The name used in reports and JSON.
    pub fn name(self) -> &'static str {
        match self {
            Limit::Torque => "torque",
            Limit::Speed => "speed",
            Limit::Envelope => "envelope",
            Limit::Power => "power",
        }
    }
}

impl std::fmt::Display for Limit {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

/// One joint's motor; an absent limit is no limit.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize)]
pub struct Motor {
    /// `τ_max`, N·m.
    pub torque: Option<f64>,
    /// `ω_max`, rad/s.
    pub speed: Option<f64>,
    /// `(τ_s, ω_0)`: stall torque, N·m, and free speed, rad/s.
    pub envelope: Option<(f64, f64)>,
    /// `P`, W.
    pub power: Option<f64>,
}

/// A limit's usage at one instant — its ratio `ρ` or its stretch squared `k²` — and the partial
/// derivatives with respect to `|τ|` and `|q̇|` (both non-negative: every limit tightens as
/// either grows).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Usage {
    /// Which limit.
    pub limit: Limit,
    /// `ρ` or `k²`, dimensionless.
    pub value: f64,
    /// `∂/∂|τ|`, per N·m.
    pub d_torque: f64,
    /// `∂/∂|q̇|`, per rad/s.
    pub d_speed: f64,
}

impl Motor {
    /// Whether the motor has no limit.
    pub fn is_ideal(&self) -> bool {
        self.torque.is_none() && self.torque_only()
    }

    /// Whether the motor has no limit but (perhaps) a torque limit.
    pub fn torque_only(&self) -> bool {
        self.speed.is_none() && self.envelope.is_none() && self.power.is_none()
    }

    /// The usage ratio `ρ` of each limit at torque `tau` (N·m) and speed `rate` (rad/s).
    pub fn ratios(&self, tau: f64, rate: f64) -> Vec<(Limit, f64)> {
        self.usage(tau, rate).into_iter().map(|u| (u.limit, u.value)).collect()
    }

    /// The usage ratio `ρ` of each limit (module docs) at `(tau, rate)`, with its partials: linear
    /// in `(|τ|, |q̇|)` but for the power limit's product.
    pub fn usage(&self, tau: f64, rate: f64) -> Vec<Usage> {
        let (a, w) = (tau.abs(), rate.abs());
        let mut out = Vec::with_capacity(4);
        let mut push = |limit, value, d_torque, d_speed| out.push(Usage { limit, value, d_torque, d_speed });
        if let Some(m) = self.torque {
            push(Limit::Torque, a / m, 1.0 / m, 0.0);
        }
        if let Some(m) = self.speed {
            push(Limit::Speed, w / m, 0.0, 1.0 / m);
        }
        if let Some((stall, free)) = self.envelope {
            push(Limit::Envelope, a / stall + w / free, 1.0 / stall, 1.0 / free);
        }
        if let Some(p) = self.power {
            push(Limit::Power, a * w / p, w / p, a / p);
        }
        out
    }

    /// The stretch squared `k²` of each limit (module docs) at `(tau, rate)`, with its partials.
    /// Where a partial does not exist (`k = 0` on the envelope or the power limit) it is zero: the
    /// instant is then as far from its limit as it can be; it is unbounded near there (the power
    /// limit's `∂k²/∂|τ|` as `τ → 0`).
    pub fn stretch_squared(&self, tau: f64, rate: f64) -> Vec<Usage> {
        let (a, w) = (tau.abs(), rate.abs());
        let mut out = Vec::with_capacity(4);
        if let Some(m) = self.torque {
            out.push(Usage { limit: Limit::Torque, value: a / m, d_torque: 1.0 / m, d_speed: 0.0 });
        }
        if let Some(m) = self.speed {
            out.push(Usage { limit: Limit::Speed, value: (w / m).powi(2), d_torque: 0.0, d_speed: 2.0 * w / (m * m) });
        }
        if let Some((stall, free)) = self.envelope {
            let (u, v) = (w / free, a / stall);
            let root = (u * u + 4.0 * v).sqrt();
            let k = 0.5 * (u + root);
            let (dk_du, dk_dv) = if root > 0.0 { (0.5 * (1.0 + u / root), 1.0 / root) } else { (0.0, 0.0) };
            out.push(Usage {
                limit: Limit::Envelope,
                value: k * k,
                d_torque: 2.0 * k * dk_dv / stall,
                d_speed: 2.0 * k * dk_du / free,
            });
        }
        if let Some(p) = self.power {
            let value = (a * w / p).cbrt().powi(2);
            let d = |x: f64| if x > 0.0 { 2.0 / 3.0 * value / x } else { 0.0 };
            out.push(Usage { limit: Limit::Power, value, d_torque: d(a), d_speed: d(w) });
        }
        out
    }

    /// The largest stretch `k` (not squared) at `(tau, rate)` and its limit; none when ideal.
    pub fn stretch(&self, tau: f64, rate: f64) -> Option<(Limit, f64)> {
        self.stretch_squared(tau, rate)
            .into_iter()
            .map(|s| (s.limit, s.value.sqrt()))
            .max_by(|x, y| x.1.total_cmp(&y.1))
    }
}

/// The motors of joint 1 and joint 2.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize)]
pub struct Motors {
    /// Joint 1's motor, then joint 2's.
    pub joints: [Motor; 2],
}

impl Motors {
    /// Ideal motors: any torque at any speed.
    pub fn ideal() -> Self {
        Self::default()
    }

    /// Whether neither motor has a limit.
    pub fn is_ideal(&self) -> bool {
        self.joints.iter().all(Motor::is_ideal)
    }
}

/// The motors a cat beyond two motors (the spherical joint, a tail, legs) is planned, measured and
/// verified with ([`motors_beyond`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum MotorsBeyond {
    /// Ideal motors.
    Ideal,
    /// One torque limit on every motor, N·m: the problem's `actuator.torque_limit_nm`, its only
    /// limit and the same for both of its joints.
    TorqueLimit(f64),
    /// Any other limits (not planned beyond two motors).
    Other,
}

/// The one torque limit, N·m, that a cat of `joints` motors beyond two is held to: planned as
/// the least peak with ideal motors, then slowed to the limit; none on two motors or for other
/// limits.
pub fn held_to_torque_limit(joints: usize, motors: &Motors) -> Option<f64> {
    match motors_beyond(motors) {
        MotorsBeyond::TorqueLimit(limit) if joints > 2 => Some(limit),
        _ => None,
    }
}

/// How the problem's two motors `motors` extend to every motor of a cat beyond two motors.
pub fn motors_beyond(motors: &Motors) -> MotorsBeyond {
    if motors.is_ideal() {
        return MotorsBeyond::Ideal;
    }
    let [a, b] = motors.joints;
    match (a.torque, b.torque) {
        (Some(x), Some(y)) if x.total_cmp(&y).is_eq() && a.torque_only() && b.torque_only() => {
            MotorsBeyond::TorqueLimit(x)
        }
        _ => MotorsBeyond::Other,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const MOTOR: Motor = Motor { torque: Some(0.5), speed: Some(6.0), envelope: Some((0.6, 12.0)), power: Some(2.0) };

    /// Each stretch is the factor that puts the slowed instant `(τ/k², q̇/k)` exactly on its limit.
    #[test]
    fn the_stretch_puts_the_slowed_motion_on_its_limit() {
        for &(tau, rate) in &[(0.9, 3.0), (-0.2, 14.0), (1.7, -0.4), (0.05, 20.0)] {
            for s in MOTOR.stretch_squared(tau, rate) {
                let k = s.value.sqrt();
                let slowed = MOTOR.ratios(tau / (k * k), rate / k);
                let (_, rho) = slowed.iter().find(|(l, _)| *l == s.limit).copied().unwrap_or((s.limit, f64::NAN));
                assert!((rho - 1.0).abs() < 1e-12, "{:?} at ({tau}, {rate}): slowed ratio {rho}", s.limit);
            }
        }
    }

    /// The partials of `k²` and of `ρ` against central differences.
    #[test]
    fn usage_partials_match_finite_differences() {
        let h = 1e-6;
        let forms: [fn(f64, f64) -> Vec<Usage>; 2] = [|t, r| MOTOR.stretch_squared(t, r), |t, r| MOTOR.usage(t, r)];
        for (&(tau, rate), at) in
            [(0.9, 3.0), (-0.2, 14.0), (1.7, -0.4)].iter().flat_map(|x| forms.iter().map(move |f| (x, f)))
        {
            for (i, s) in at(tau, rate).into_iter().enumerate() {
                let dt = (at(tau + h, rate)[i].value - at(tau - h, rate)[i].value) / (2.0 * h);
                let dr = (at(tau, rate + h)[i].value - at(tau, rate - h)[i].value) / (2.0 * h);
                let (d_tau, d_rate) = (s.d_torque * tau.signum(), s.d_speed * rate.signum());
                assert!((dt - d_tau).abs() < 1e-6 * (1.0 + dt.abs()), "{:?} ∂τ: {dt} vs {d_tau}", s.limit);
                assert!((dr - d_rate).abs() < 1e-6 * (1.0 + dr.abs()), "{:?} ∂q̇: {dr} vs {d_rate}", s.limit);
            }
        }
    }

    /// The envelope's stretch reduces to the torque and speed stretches at its ends.
    #[test]
    fn envelope_reduces_to_stall_and_free_speed() {
        let m = Motor { envelope: Some((0.6, 12.0)), ..Motor::default() };
        let k_stall = m.stretch(0.24, 0.0).map(|x| x.1).unwrap_or(f64::NAN);
        let k_free = m.stretch(0.0, 6.0).map(|x| x.1).unwrap_or(f64::NAN);
        assert!((k_stall - (0.24f64 / 0.6).sqrt()).abs() < 1e-15, "{k_stall}");
        assert!((k_free - 0.5).abs() < 1e-15, "{k_free}");
    }
}
