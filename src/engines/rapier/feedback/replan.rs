//! The re-plan of the rest of the fall ([`super`]'s docs, "The re-plan"): one iteration of
//! iterative LQR from the current estimate, warm-started from the policy in force.
//!
//! From node `c` and the estimate `x̂`, the policy in force `u_i = sat(−K_i x_i − κ_i)` is rolled
//! out through the exact error dynamics ([`super::linear::error_rate`], Heun's method over each
//! control step; the joints' double integrator exactly): that is the motion the regulator now
//! expects. The dynamics are linearised about it node by node ([`super::linear::linearise`]),
//! each control step's affine term `φ_i = x̄_{i+1} − F_i x̄_i − Γ_i ū_i` taken from the roll-out
//! itself, and the sweep ([`super::riccati::sweep`]) gives the new gains `K_i` and the full
//! step's offsets. The step is then searched: `u_i = sat(ū_i + α k_i − K_i (x_i − x̄_i))`,
//! `k_i` the full step's change of the input along the roll-out, is rolled out for
//! `α = 1, ½, ¼, …` and the first whose cost is below the roll-out's is kept (`α = 0`, the new
//! gains about the old motion, when none is). The cost is the plan's: the attitude error to the
//! plan's end attitude and the joints' return to its end pose, in the plan's coordinates,
//! evaluated along the exact roll-out. Nothing is allocated: the regulator's buffers are
//! overwritten from `c` on (before `c` they keep what was in force then, which the filter still
//! needs for the sensor's latency).

use nalgebra::{Vector2, Vector3};

use super::linear::{error_rate, linearise, parts, Linearisation, Node, State};
use super::riccati::{discrete, sweep, weights, Gain, Rollout};
use super::{FeedbackPlan, FeedbackSettings};

/// Step sizes the line search tries, largest first.
const STEPS: [f64; 4] = [1.0, 0.5, 0.25, 0.125];

/// A regulator of one run: the nodes, gains and offsets in force, node by node; the plan's
/// until the first re-plan.
#[derive(Clone, Debug, PartialEq)]
pub struct Regulator {
    /// The linearisation in force at each node `0 … N`.
    pub nodes: Vec<Node>,
    /// `K_i`, `i = 0 … N − 1`.
    pub gains: Vec<Gain>,
    /// `κ_i`, rad/s² (zero along the plan).
    pub offsets: Vec<Vector2<f64>>,
    /// The step the last re-plan's line search kept.
    pub last_step: f64,
    /// The cost of the last re-plan's kept policy along its roll-out (the cost-to-go it
    /// expects).
    pub expected_cost: f64,
    /// The cost of the policy in force before the last re-plan, along its roll-out from the same
    /// state: `expected_cost` is below it unless no step was kept (then equal).
    pub cost_before: f64,
    /// The roll-out `(x̄_i, ū_i)` (scratch).
    nominal: Vec<(State, Vector2<f64>)>,
    /// The roll-out's affine terms on the attitude rows (scratch).
    defects: Vec<Vector3<f64>>,
}

impl Regulator {
    /// The plan's regulator.
    pub fn of(fb: &FeedbackPlan) -> Regulator {
        let n = fb.gains.len();
        Regulator {
            nodes: fb.linearisation.nodes.clone(),
            gains: fb.gains.clone(),
            offsets: vec![Vector2::zeros(); n],
            last_step: 0.0,
            expected_cost: 0.0,
            cost_before: 0.0,
            nominal: vec![(State::zeros(), Vector2::zeros()); n + 1],
            defects: vec![Vector3::zeros(); n],
        }
    }

    /// The unsaturated input at node `i` for the state `x`: `−K_i x − κ_i` (zero beyond the
    /// last gain).
    pub fn input(&self, i: usize, x: &State) -> Vector2<f64> {
        match self.gains.get(i) {
            Some(k) => -(k * x) - self.offsets[i],
            None => Vector2::zeros(),
        }
    }

    /// Re-plans the rest of the fall from node `from` and the estimate `x` (module docs).
    pub fn replan(&mut self, lin: &Linearisation, settings: &FeedbackSettings, from: usize, x: &State) {
        let last = self.nodes.len() - 1;
        if from >= last {
            return;
        }
        let (dt, a) = (lin.dt, settings.accel);
        let cost = Cost::new(settings, dt, lin.duration);
        // The roll-out of the policy in force, linearised as it goes.
        let mut xbar = *x;
        let mut before = 0.0;
        for i in from..=last {
            let (node, rate) = linearise(&lin.cat, &lin.points[i], &lin.spin, &xbar);
            self.nodes[i] = node;
            if i == last {
                before += cost.terminal(&xbar);
                self.nominal[i] = (xbar, Vector2::zeros());
                break;
            }
            let u = self.input(i, &xbar).map(|v| v.clamp(-a, a));
            before += cost.running(&xbar, &u);
            let next = heun(lin, i, &xbar, &u, &rate);
            let (f, gamma) = discrete(&node, dt);
            self.defects[i] = (next - f * xbar - gamma * u).fixed_rows::<3>(0).into();
            self.nominal[i] = (xbar, u);
            xbar = next;
        }
        let (gains, offsets) = (&mut self.gains, &mut self.offsets);
        let rollout = Rollout { defects: &self.defects, nominal: &self.nominal, bound: a };
        sweep(&self.nodes, dt, lin.duration, settings, from, Some(&rollout), |i, k, kappa| {
            gains[i] = k;
            offsets[i] = kappa;
        });
        // The line search: u = ū + α k − K (x − x̄), k = −K x̄ − κ − ū the full step's change.
        let nominal = &self.nominal;
        let gains = &self.gains;
        let offsets = &self.offsets;
        let step_input = |alpha: f64, i: usize, x: &State| {
            let (xb, ub) = nominal[i];
            let change = -(gains[i] * xb) - offsets[i] - ub;
            ub + change * alpha - gains[i] * (x - xb)
        };
        let (mut kept, mut expected) = (0.0, before);
        for alpha in STEPS {
            let mut xs = *x;
            let mut total = 0.0;
            for i in from..last {
                let u = step_input(alpha, i, &xs).map(|v| v.clamp(-a, a));
                total += cost.running(&xs, &u);
                if total >= before {
                    break;
                }
                let rate = error_rate(&lin.cat, &lin.points[i], &lin.spin, &xs);
                xs = heun(lin, i, &xs, &u, &rate);
            }
            total += cost.terminal(&xs);
            if total < before {
                (kept, expected) = (alpha, total);
                break;
            }
        }
        for i in from..last {
            let (xb, ub) = self.nominal[i];
            // u = −K x − κ_α with κ_α = α κ + (1 − α)(−K x̄ − ū).
            self.offsets[i] = self.offsets[i] * kept - (self.gains[i] * xb + ub) * (1.0 - kept);
        }
        self.last_step = kept;
        self.expected_cost = expected;
        self.cost_before = before;
    }
}

/// `x` one control step on from node `i` under `u` held, `rate = f(x)`: the joints' double
/// integrator exactly, the attitude error by Heun's method on the exact error rate.
fn heun(lin: &Linearisation, i: usize, x: &State, u: &Vector2<f64>, rate: &Vector3<f64>) -> State {
    let dt = lin.dt;
    let (e, dq, dqd, _) = parts(x);
    let mut next = *x;
    next.fixed_rows_mut::<2>(3).copy_from(&(dq + dqd * dt + u * (0.5 * dt * dt)));
    next.fixed_rows_mut::<2>(5).copy_from(&(dqd + u * dt));
    next.fixed_rows_mut::<3>(0).copy_from(&(e + rate * dt));
    let predicted = error_rate(&lin.cat, &lin.points[i + 1], &lin.spin, &next);
    next.fixed_rows_mut::<3>(0).copy_from(&(e + (rate + predicted) * (0.5 * dt)));
    next
}

/// The regulator's cost along a motion, by its diagonal weights.
struct Cost {
    running: [f64; 10],
    terminal: [f64; 10],
    input: f64,
}

impl Cost {
    fn new(settings: &FeedbackSettings, dt: f64, duration: f64) -> Cost {
        let (running, terminal, input) = weights(settings, dt, duration);
        Cost {
            running: std::array::from_fn(|i| running[(i, i)]),
            terminal: std::array::from_fn(|i| terminal[(i, i)]),
            input,
        }
    }

    fn running(&self, x: &State, u: &Vector2<f64>) -> f64 {
        x.iter().zip(&self.running).map(|(v, w)| w * v * v).sum::<f64>() + self.input * u.norm_squared()
    }

    fn terminal(&self, x: &State) -> f64 {
        x.iter().zip(&self.terminal).map(|(v, w)| w * v * v).sum()
    }
}
