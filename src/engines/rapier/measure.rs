//! Measurements on the rapier scene: angular momentum and joint torques inferred from motion.
//!
//! Rapier does not write back the impulses of a multibody's internal motors, so the joint
//! torques are recovered by Newton–Euler on the subsystem each joint drives, from finite
//! differences of the bodies' motion (see [`crate::engines::rapier`] for the equations).

use nalgebra::Vector3;

use super::bodies::{BodyState, MassModel, Snapshot, NDOFS};

/// Total angular momentum of `bodies` about their common centre of mass, N·m·s:
/// `H = Σ R I Rᵀ ω + m (x − c) × (v − v_c)`.
pub fn angular_momentum(masses: &MassModel, bodies: &[BodyState; 3]) -> Vector3<f64> {
    let total = masses.total();
    let mut c = Vector3::zeros();
    let mut vc = Vector3::zeros();
    for (b, m) in bodies.iter().zip(masses.mass) {
        c += m * b.position;
        vc += m * b.linvel;
    }
    c /= total;
    vc /= total;
    let mut h = Vector3::zeros();
    for (i, b) in bodies.iter().enumerate() {
        h += masses.world_inertia(i, &b.rotation) * b.angvel;
        h += masses.mass[i] * (b.position - c).cross(&(b.linvel - vc));
    }
    h
}

/// Kinetic energy of `bodies`, J.
pub fn kinetic_energy(masses: &MassModel, bodies: &[BodyState; 3]) -> f64 {
    bodies
        .iter()
        .enumerate()
        .map(|(i, b)| {
            let iw = masses.world_inertia(i, &b.rotation);
            0.5 * masses.mass[i] * b.linvel.norm_squared() + 0.5 * b.angvel.dot(&(iw * b.angvel))
        })
        .sum()
}

/// Angular momentum about a point `p` and linear momentum of the bodies in `set`.
fn momenta_about(
    masses: &MassModel,
    bodies: &[BodyState; 3],
    set: &[usize],
    p: &Vector3<f64>,
) -> (Vector3<f64>, Vector3<f64>) {
    let mut h = Vector3::zeros();
    let mut lin = Vector3::zeros();
    for &i in set {
        let b = &bodies[i];
        h += masses.world_inertia(i, &b.rotation) * b.angvel;
        h += masses.mass[i] * (b.position - p).cross(&b.linvel);
        lin += masses.mass[i] * b.linvel;
    }
    (h, lin)
}

/// What Newton–Euler needs at one record: momenta of the two driven subsystems about the joint
/// point ([`super::bodies::Layout::driven`]), and the point's velocity and the motor axes.
#[derive(Clone, Copy, Debug)]
struct Centred {
    t: f64,
    /// `H_P` of each motor's driven bodies ({cross, B} and {B} on the universal joint).
    h: [Vector3<f64>; 2],
    /// `v_P × p_S` of {cross, B} and of {B}.
    transport: [Vector3<f64>; 2],
    axes: [Vector3<f64>; 2],
}

/// Streams snapshots and returns the joint torques by central differences.
///
/// Record `k` has poses `x_k` and the generalized velocities `v_k` of the step that ended there
/// (symplectic Euler: `x_k = x_{k−1} ⊕ dt v_k`), so `v̄_k = (v_k + v_{k+1})/2` is the
/// second-order velocity at `t_k`. With it, `τ_k = a_k · [(H_{k+1} − H_{k−1})/(2 dt) + v_P × p]`.
#[derive(Clone, Debug, Default)]
pub struct TorqueEstimator {
    pending: Option<(f64, Snapshot)>,
    window: Vec<Centred>,
}

/// Joint torques at one instant.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct TorqueSample {
    /// Time, s.
    pub t: f64,
    /// `(τ1, τ2)`, N·m.
    pub tau: [f64; 2],
}

impl TorqueEstimator {
    /// Feeds the record at time `t`; returns the torques at the record two before, once known.
    pub fn push(&mut self, masses: &MassModel, t: f64, snap: &Snapshot) -> Option<TorqueSample> {
        let prev = self.pending.replace((t, *snap));
        let (t_prev, s_prev) = prev?;
        let mut v = [0.0; NDOFS];
        for (k, vk) in v.iter_mut().enumerate() {
            *vk = 0.5 * (s_prev.velocities[k] + snap.velocities[k]);
        }
        let bodies = s_prev.bodies_with(masses, &v);
        let p = s_prev.joint_point(masses);
        let v_p = bodies[1].linvel;
        let mut h = [Vector3::zeros(); 2];
        let mut transport = [Vector3::zeros(); 2];
        for (j, set) in s_prev.layout.driven().iter().enumerate() {
            let (hj, lin) = momenta_about(masses, &bodies, set, &p);
            h[j] = hj;
            transport[j] = v_p.cross(&lin);
        }
        self.window.push(Centred { t: t_prev, h, transport, axes: s_prev.joint_axes() });
        if self.window.len() > 3 {
            self.window.remove(0);
        }
        if self.window.len() < 3 {
            return None;
        }
        let (a, m, b) = (&self.window[0], &self.window[1], &self.window[2]);
        let span = b.t - a.t;
        let tau = std::array::from_fn(|j| {
            let dh = (b.h[j] - a.h[j]) / span;
            m.axes[j].dot(&(dh + m.transport[j]))
        });
        Some(TorqueSample { t: m.t, tau })
    }
}

/// Observed orders of convergence `log(e_i/e_{i+1}) / log(dt_i/dt_{i+1})` between successive
/// runs; `NaN` where an error is zero or not finite.
pub fn observed_orders(dts: &[f64], errors: &[f64]) -> Vec<f64> {
    dts.windows(2)
        .zip(errors.windows(2))
        .map(|(d, e)| {
            if e[0] > 0.0 && e[1] > 0.0 && e.iter().all(|x| x.is_finite()) {
                (e[0] / e[1]).ln() / (d[0] / d[1]).ln()
            } else {
                f64::NAN
            }
        })
        .collect()
}

/// Gathers the torque samples around one jump of the schedule's joint rates and adds up the
/// impulse they carry above the smooth torque (interpolated linearly between the last sample
/// before the window and the first after it).
#[derive(Clone, Debug)]
pub(crate) struct JumpWindow {
    /// Time of the jump, s.
    pub time: f64,
    /// Half-width of the window, s.
    pub half_width: f64,
    before: Option<TorqueSample>,
    inside: Vec<TorqueSample>,
    after: Option<TorqueSample>,
}

impl JumpWindow {
    pub fn new(time: f64, half_width: f64) -> Self {
        Self { time, half_width, before: None, inside: Vec::new(), after: None }
    }

    /// Offers a sample; returns whether it falls inside the window.
    pub fn offer(&mut self, s: &TorqueSample) -> bool {
        if s.t < self.time - self.half_width {
            self.before = Some(*s);
            false
        } else if s.t <= self.time + self.half_width {
            self.inside.push(*s);
            true
        } else {
            if self.after.is_none() {
                self.after = Some(*s);
            }
            false
        }
    }

    /// `(peak |τ_i|, Σ (τ_i − smooth_i) dt)` of the samples inside.
    pub fn finish(&self, dt: f64) -> ([f64; 2], [f64; 2]) {
        let mut peak = [0.0f64; 2];
        let mut impulse = [0.0f64; 2];
        let base = |t: f64, i: usize| match (self.before, self.after) {
            (Some(a), Some(b)) => a.tau[i] + (b.tau[i] - a.tau[i]) * (t - a.t) / (b.t - a.t),
            (Some(a), None) => a.tau[i],
            (None, Some(b)) => b.tau[i],
            (None, None) => 0.0,
        };
        for s in &self.inside {
            for i in 0..2 {
                peak[i] = peak[i].max(s.tau[i].abs());
                impulse[i] += (s.tau[i] - base(s.t, i)) * dt;
            }
        }
        (peak, impulse)
    }
}
