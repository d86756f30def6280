//! The regulator's discrete model and its backward Riccati sweep ([`super`]'s docs): the plan's
//! gains, and a re-plan's gains and offsets about its expected motion.

use std::ops::AddAssign;

use nalgebra::{Matrix2, SMatrix, Vector2, Vector3};

use super::linear::{Linearisation, Node, State};
use super::FeedbackSettings;

/// The time scale that weighs the joint rate against the joint angle, s.
const RATE_SCALE: f64 = 0.1;

pub(super) type Square = SMatrix<f64, 10, 10>;
type Input = SMatrix<f64, 10, 2>;
/// A gain `K_i`: `u = −K_i x − κ_i`.
pub type Gain = SMatrix<f64, 2, 10>;

/// The discrete model over `Δ` at `node`: `x⁺ = F x + Γ u` (plus the node's affine term).
pub(super) fn discrete(node: &Node, dt: f64) -> (Square, SMatrix<f64, 10, 2>) {
    let mut f = Square::identity();
    f.fixed_view_mut::<3, 3>(0, 0).add_assign(&(node.a * dt));
    f.fixed_view_mut::<3, 2>(0, 3).copy_from(&(node.bq * dt));
    f.fixed_view_mut::<3, 2>(0, 5).copy_from(&(node.bqd * dt));
    f.fixed_view_mut::<3, 3>(0, 7).copy_from(&(node.g * dt));
    for j in 0..2 {
        f[(3 + j, 5 + j)] = dt;
    }
    let mut gamma = Input::zeros();
    gamma.fixed_view_mut::<3, 2>(0, 0).copy_from(&(node.bqd * (0.5 * dt * dt)));
    for j in 0..2 {
        gamma[(3 + j, j)] = 0.5 * dt * dt;
        gamma[(5 + j, j)] = dt;
    }
    (f, gamma)
}

/// The state weights `(running, terminal)` and the input weight of `settings` (module docs).
pub(super) fn weights(settings: &FeedbackSettings, dt: f64, duration: f64) -> (Square, Square, f64) {
    let mut terminal = Square::zeros();
    for i in 0..3 {
        terminal[(i, i)] = settings.attitude.powi(-2);
    }
    for j in 0..2 {
        terminal[(3 + j, 3 + j)] = settings.joint.powi(-2);
        terminal[(5 + j, 5 + j)] = (RATE_SCALE / settings.joint).powi(2);
    }
    let share = dt / duration.max(dt);
    (terminal * share, terminal, share * settings.accel.powi(-2))
}

/// What a re-plan's sweep knows besides the nodes: the roll-out it linearised about.
pub(super) struct Rollout<'a> {
    /// The discrete model's affine terms `φ_i` on the attitude rows.
    pub defects: &'a [Vector3<f64>],
    /// The roll-out's `(x̄_i, ū_i)`.
    pub nominal: &'a [(State, Vector2<f64>)],
    /// The bound `|u_j| ≤ a`, rad/s².
    pub bound: f64,
}

/// The backward sweep over `nodes[from..]` (the last node is `T`'s); along the plan (`rollout`
/// none) the plain Riccati recursion, about a re-plan's roll-out the affine one with the inputs'
/// bound (module docs). Hands each node's `(K_i, κ_i)` to `store`, from the last to `from`. A
/// gain the sweep cannot form (a singular `R + ΓᵀPΓ`, impossible with `accel` finite) is zero: no
/// correction rather than a wrong one.
pub(super) fn sweep(
    nodes: &[Node],
    dt: f64,
    duration: f64,
    settings: &FeedbackSettings,
    from: usize,
    rollout: Option<&Rollout>,
    mut store: impl FnMut(usize, Gain, Vector2<f64>),
) {
    let (running, mut p, r) = weights(settings, dt, duration);
    // The value's linear part: V_i(x) = xᵀ P_i x + 2 p_iᵀ x + const.
    let mut lin = State::zeros();
    let last = nodes.len().saturating_sub(1);
    for i in (from..last).rev() {
        let (f, gamma) = discrete(&nodes[i], dt);
        let pg = p * gamma;
        let s = gamma.transpose() * pg + Matrix2::identity() * r;
        let Some(s_inv) = s.try_inverse() else {
            p = running + f.transpose() * p * f;
            p = 0.5 * (p + p.transpose());
            lin = f.transpose() * lin;
            store(i, Gain::zeros(), Vector2::zeros());
            continue;
        };
        let k = s_inv * pg.transpose() * f;
        let Some(ro) = rollout else {
            p = running + f.transpose() * p * (f - gamma * k);
            p = 0.5 * (p + p.transpose());
            store(i, k, Vector2::zeros());
            continue;
        };
        // p̃ = p + P φ: the next value's slope where the model lands.
        let mut tilde = lin;
        tilde += p.fixed_columns::<3>(0) * ro.defects[i];
        let gp = gamma.transpose() * tilde;
        let gpf = pg.transpose() * f;
        let (xbar, _) = ro.nominal[i];
        let (u, clamped) = box_qp(&s, &(gpf * xbar + gp), ro.bound);
        if clamped == [false; 2] {
            // The unconstrained step: κ = S⁻¹ Γᵀ p̃, p ← (F − Γ K)ᵀ p̃, P as along the plan.
            lin = (f - gamma * k).transpose() * tilde;
            p = running + f.transpose() * p * (f - gamma * k);
            p = 0.5 * (p + p.transpose());
            store(i, k, s_inv * gp);
            continue;
        }
        // The clamped inputs held at their bound, the free one optimal given them.
        let mut k = Gain::zeros();
        let mut kappa = -u;
        for j in 0..2 {
            let o = 1 - j;
            if !clamped[j] {
                let held = if clamped[o] { s[(j, o)] * u[o] } else { 0.0 };
                k.set_row(j, &(gpf.row(j) / s[(j, j)]));
                kappa[j] = (held + gp[j]) / s[(j, j)];
            }
        }
        // The value under the policy u = −K x − κ: P ← Q + F̃ᵀ P F̃ + Kᵀ R K, p ← F̃ᵀ(p̃ − P Γ κ) + Kᵀ R κ.
        let closed = f - gamma * k;
        lin = closed.transpose() * (tilde - pg * kappa) + k.transpose() * kappa * r;
        p = running + closed.transpose() * p * closed + k.transpose() * k * r;
        p = 0.5 * (p + p.transpose());
        store(i, k, kappa);
    }
}

/// `argmin ½ uᵀ S u + uᵀ b` over `|u_j| ≤ a` (`S` positive definite), and which bounds hold it:
/// the best of the feasible stationary points of each active set.
fn box_qp(s: &Matrix2<f64>, b: &Vector2<f64>, a: f64) -> (Vector2<f64>, [bool; 2]) {
    let objective = |u: &Vector2<f64>| 0.5 * u.dot(&(s * u)) + u.dot(b);
    let free = s.try_inverse().map(|inv| -(inv * b));
    if let Some(u) = free.filter(|u| u.amax() <= a) {
        return (u, [false; 2]);
    }
    let mut best: Option<(f64, Vector2<f64>, [bool; 2])> = None;
    let mut consider = |u: Vector2<f64>, clamped: [bool; 2]| {
        if u.amax() <= a * (1.0 + 1e-12) {
            let j = objective(&u);
            if best.is_none_or(|(b, _, _)| j < b) {
                best = Some((j, u, clamped));
            }
        }
    };
    for j in 0..2 {
        let o = 1 - j;
        for bound in [-a, a] {
            let mut u = Vector2::zeros();
            u[j] = bound;
            u[o] = -(b[o] + s[(o, j)] * bound) / s[(o, o)];
            let mut clamped = [false; 2];
            clamped[j] = true;
            consider(u, clamped);
        }
    }
    for u0 in [-a, a] {
        for u1 in [-a, a] {
            consider(Vector2::new(u0, u1), [true; 2]);
        }
    }
    best.map_or((Vector2::zeros(), [true; 2]), |(_, u, c)| (u, c))
}

/// The gains `K_i` for the nodes `from … N − 1` along the plan (the backward Riccati sweep from
/// `T`; module docs): `gains[i − from]` is node `i`'s.
pub fn lqr_gains(lin: &Linearisation, settings: &FeedbackSettings, from: usize) -> Vec<Gain> {
    let last = lin.nodes.len().saturating_sub(1);
    let mut gains = vec![Gain::zeros(); last.saturating_sub(from)];
    sweep(&lin.nodes, lin.dt, lin.duration, settings, from, None, |i, k, _| gains[i - from] = k);
    gains
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The box QP's answer is the best point of a fine grid of the box (to the grid's step),
    /// and says which bounds hold it.
    #[test]
    fn the_box_qp_is_the_grids_best() {
        let cases = [
            (Matrix2::new(2.0, 0.3, 0.3, 1.0), Vector2::new(-1.0, 0.5), 1.0),
            (Matrix2::new(2.0, 0.3, 0.3, 1.0), Vector2::new(-5.0, 0.5), 1.0),
            (Matrix2::new(1.0, 0.9, 0.9, 1.0), Vector2::new(3.0, -4.0), 1.0),
            (Matrix2::new(3.0, -1.0, -1.0, 0.5), Vector2::new(10.0, 10.0), 2.0),
        ];
        for (s, b, a) in cases {
            let (u, clamped) = box_qp(&s, &b, a);
            let objective = |u: &Vector2<f64>| 0.5 * u.dot(&(s * u)) + u.dot(&b);
            let n = 400;
            let grid = (0..=n).flat_map(|i| (0..=n).map(move |j| (i, j)));
            let best = grid
                .map(|(i, j)| Vector2::new(-a + 2.0 * a * i as f64 / n as f64, -a + 2.0 * a * j as f64 / n as f64))
                .map(|v| objective(&v))
                .fold(f64::INFINITY, f64::min);
            assert!(objective(&u) <= best + 1e-12, "{s} {b}: {u} worse than the grid's {best}");
            assert!(u.amax() <= a * (1.0 + 1e-12), "{u} outside the box");
            for j in 0..2 {
                assert!(clamped[j] == ((u[j].abs() - a).abs() < 1e-12), "{s} {b}: {u}, clamped {clamped:?}");
            }
        }
    }
}
