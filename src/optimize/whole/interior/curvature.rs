//! The torques' exact curvature on the control points, sample by sample.
//!
//! A torque sample `τ_j(q, q̇, q̈)` at time `t_k` depends on the control points of the spans
//! around `t_k` only, through the basis `q = Σ N_m c_m`, `q̇ = Σ N'_m c_m`, `q̈ = Σ N''_m c_m`
//! ([`BSpline::basis`]). The weighted sum `Σ_j w_j τ_j` therefore has the Hessian
//!
//! $$ ∇²_c \Big(\sum_j w_j τ_j\Big) = Bᵀ H B, \qquad
//!    H = ∇²_{(q, q̇, q̈)} \sum_j w_j τ_j, $$
//!
//! with `B` the basis map of the sample (`3J × (p+1)J`, `J` coordinates): a block of the
//! Lagrangian's Hessian local to the sample, so the whole is banded. Released without spin the
//! reduced dynamics are `τ = M(q) q̈ + Q(q)[q̇, q̇]`, linear in `q̈` and a quadratic form in `q̇`,
//! so `H` needs differences along the angles only:
//! - the columns along each angle `q_j`, every block's, by forward differences of the exact
//!   dual-number gradients ([`WholeCat::torque_partials`]), the rows of `q̇` and `q̈` then mirrored
//!   into the angles' (the `q̈`-`q̇` and `q̈`-`q̈` blocks vanish);
//! - the `q̇`-`q̇` block, `2S` for `Σ_j w_j τ_j(q, q̇, 0) = q̇ᵀ S q̇`, exactly from the torques at
//!   the unit rates and their pairwise sums (polarisation), in plain floating point.
//!
//! That is `J` gradients and `J(J+1)/2` torques besides the sample's own gradient, which the
//! iterate's evaluation has already made and keeps
//! ([`grid_partials`](super::super::sensitivity::grid_partials)), against the `2J` gradients of
//! differences along the rates too: the tailed cat's curvature on 469 samples in 26–27 ms against
//! 34–35 on one thread, the own gradient then made again (scratch timing, best of eight,
//! 2026-12-07).
//!
//! The differences and the torques at the unit rates do not depend on the weights: they are made
//! once per sample for each torque ([`SampleCurvature`], [`torque_curvatures`]) and weighed
//! afterwards ([`weighted_torque_hessian`]), so that the method can weigh the curvature it holds
//! with new multipliers while the control points stay near where it was made
//! (`super::CURVATURE_KEPT`).
//!
//! The step `10⁻⁶` rad, for angles of order one, leaves a truncation error of about `10⁻⁶` of the
//! curvature and a round-off of the gradients' (about `10⁻¹²` of them) over the step: measured
//! against central differences of the gradients, 3.7·10⁻⁷ of the curvature on the spherical
//! joint, 7.6·10⁻⁷ with a tail and 9.3·10⁻⁷ with legs (`tests.rs`, 2026-12-07).

use rayon::prelude::*;

use super::super::cat::{Partials, WholeCat, MAX_JOINTS};
use super::super::sensitivity::{GridPoint, Layout};
use super::super::spline::BSpline;

/// The forward-difference step on an angle, rad.
const STEP_ANGLE: f64 = 1e-6;

/// One sample's torque curvature, before the weights: each torque's second derivatives along
/// the angles and its quadratic form in the rates (module docs). It depends on the control
/// points only, so the Lagrangian's curvature at new multipliers is its weighted sum.
#[derive(Clone, Debug)]
pub(crate) struct SampleCurvature {
    /// `∂(∂τ_i/∂x_{b,k})/∂q_j` (`x_b` the angles, rates and accelerations) at index
    /// `((j J + i) 3 + b) J + k`.
    angles: Vec<f64>,
    /// `τ_i(q, e_a + e_b, 0)` for `b ≤ a` at index `(a (a + 1)/2 + b) J + i`.
    forms: Vec<f64>,
}

/// Each sample's [`SampleCurvature`] on `spline` at the samples of `grid`, from each sample's own
/// torque partials `own[k]` ([`grid_partials`](super::super::sensitivity::grid_partials)), in
/// parallel.
pub(crate) fn torque_curvatures(
    cat: &WholeCat,
    spline: &BSpline,
    joints: usize,
    grid: &[GridPoint],
    own: &[Vec<Partials>],
) -> Vec<SampleCurvature> {
    grid.par_iter()
        .zip(own)
        .with_min_len(16)
        .map(|(&(span, time, _), at)| sample_curvature(cat, spline, joints, (span, time), at))
        .collect()
}

/// One sample's [`SampleCurvature`]: `J` gradients along the angles and `J(J+1)/2` torques.
fn sample_curvature(
    cat: &WholeCat,
    spline: &BSpline,
    joints: usize,
    (span, time): (usize, f64),
    at: &[Partials],
) -> SampleCurvature {
    let basis = spline.basis(span, time);
    let [q, qd, qdd] = spline.values::<MAX_JOINTS>(&basis);
    let (q, qd, qdd) = (&q[..joints], &qd[..joints], &qdd[..joints]);
    let mut angles = Vec::with_capacity(3 * joints * joints * joints);
    for j in 0..joints {
        let mut moved_q = q.to_vec();
        moved_q[j] += STEP_ANGLE;
        let moved = cat.torque_partials(&moved_q, qd, qdd);
        for i in 0..joints {
            for b in 0..3 {
                angles.extend((0..joints).map(|k| (moved[i].d[b][k] - at[i].d[b][k]) / STEP_ANGLE));
            }
        }
    }
    let zero = vec![0.0; joints];
    let mut forms = Vec::with_capacity(joints * joints * (joints + 1) / 2);
    for a in 0..joints {
        for b in 0..=a {
            let mut rate = zero.clone();
            rate[a] += 1.0;
            rate[b] += 1.0;
            forms.extend(cat.torques(q, &rate, &zero));
        }
    }
    SampleCurvature { angles, forms }
}

/// `Σ_k ∇²_c Σ_j w_kj τ_kj` over the samples of `grid` with the weights `weights[k][j]`, as
/// `(row, column, value)` entries on the layout's variables (duplicates to be summed), from each
/// sample's curvature `curvatures[k]` ([`torque_curvatures`]; `spline` gives the samples' basis,
/// its knots alone). Samples whose weights all vanish are skipped.
pub(crate) fn weighted_torque_hessian(
    spline: &BSpline,
    layout: &Layout,
    grid: &[GridPoint],
    curvatures: &[SampleCurvature],
    weights: &[Vec<f64>],
) -> Vec<(usize, usize, f64)> {
    grid.par_iter()
        .zip(curvatures)
        .zip(weights)
        .with_min_len(16)
        .flat_map_iter(|((&(span, time, _), sample), w)| sample_hessian(spline, layout, (span, time), sample, w))
        .collect()
}

/// One sample's `Bᵀ H B` (module docs) as entries on the layout's variables.
fn sample_hessian(
    spline: &BSpline,
    layout: &Layout,
    (span, time): (usize, f64),
    sample: &SampleCurvature,
    w: &[f64],
) -> Vec<(usize, usize, f64)> {
    if w.iter().all(|&x| x == 0.0) {
        return Vec::new();
    }
    let joints = layout.joints;
    let basis = spline.basis(span, time);
    // H over (derivative order a, coordinate j) at index a·J + j.
    let size = 3 * joints;
    let mut h = vec![0.0; size * size];
    // The columns along each angle: every block's.
    for j in 0..joints {
        for b in 0..3 {
            for k in 0..joints {
                let d: f64 = (0..joints).map(|i| w[i] * sample.angles[((j * joints + i) * 3 + b) * joints + k]).sum();
                h[(b * joints + k) * size + j] = d;
            }
        }
    }
    // The angles' block averaged with its transpose; the rates' and accelerations' rows of the
    // angles' columns mirrored into the angles' rows.
    for r in 0..joints {
        for c in 0..r {
            let v = 0.5 * (h[r * size + c] + h[c * size + r]);
            h[r * size + c] = v;
            h[c * size + r] = v;
        }
    }
    for r in joints..size {
        for c in 0..joints {
            h[c * size + r] = h[r * size + c];
        }
    }
    // The rates' block: `Σ w τ` at rest in q̈ is the quadratic form `q̇ᵀ S q̇`, so `∂²/∂q̇² = 2S`
    // from its values at the unit rates and their sums (polarisation), exact.
    let form = |a: usize, b: usize| {
        let at = (a * (a + 1) / 2 + b) * joints;
        (0..joints).map(|i| w[i] * sample.forms[at + i]).sum::<f64>()
    };
    let diagonal: Vec<f64> = (0..joints).map(|a| form(a, a) / 4.0).collect();
    for a in 0..joints {
        h[(joints + a) * size + joints + a] = 2.0 * diagonal[a];
        for b in 0..a {
            let v = form(a, b) - diagonal[a] - diagonal[b];
            h[(joints + a) * size + joints + b] = v;
            h[(joints + b) * size + joints + a] = v;
        }
    }
    // The sample's block Bᵀ H B over (coordinate, basis function), then its free entries.
    let functions = basis.values[0].len();
    let local = joints * functions;
    let mut block = vec![0.0; local * local];
    for a in 0..3 {
        for j in 0..joints {
            for b in 0..3 {
                for k in 0..joints {
                    let hv = h[(a * joints + j) * size + b * joints + k];
                    if hv == 0.0 {
                        continue;
                    }
                    for m in 0..functions {
                        let left = basis.values[a][m] * hv;
                        for mp in 0..functions {
                            block[(j * functions + m) * local + k * functions + mp] += left * basis.values[b][mp];
                        }
                    }
                }
            }
        }
    }
    let variable = |i: usize| layout.variable(i / functions, basis.first + i % functions);
    let mut out = Vec::with_capacity(local * local);
    for r in 0..local {
        let Some(v) = variable(r) else { continue };
        for c in 0..local {
            if let Some(u) = variable(c) {
                out.push((v, u, block[r * local + c]));
            }
        }
    }
    out
}
