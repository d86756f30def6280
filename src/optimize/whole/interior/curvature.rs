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
//! Lagrangian's Hessian local to the sample, so the whole is banded. `H` is taken by forward
//! differences of the exact dual-number gradients ([`WholeCat::torque_partials`]) along `q` and
//! `q̇`; the torques are linear in `q̈` (the reduced dynamics `τ = M(q) q̈ + c(q, q̇)`), so the
//! `q̈`-`q̈` block is zero and the `q̈` rows of the differences give the mixed blocks. The
//! difference steps (`10⁻⁶` rad, `10⁻⁵` rad/s, for angles of order one and rates of order ten)
//! leave a truncation error of about `10⁻⁶` of the curvature and a round-off of the gradients'
//! (about `10⁻¹²` of them) over the step: measured against central differences of the
//! gradients, 3·10⁻⁷ of the curvature on the spherical joint (`tests.rs`).

use rayon::prelude::*;

use super::super::cat::{WholeCat, MAX_JOINTS};
use super::super::sensitivity::{GridPoint, Layout};
use super::super::spline::BSpline;

/// The forward-difference step on an angle, rad.
const STEP_ANGLE: f64 = 1e-6;
/// The forward-difference step on a rate, rad/s.
const STEP_RATE: f64 = 1e-5;

/// `Σ_k ∇²_c Σ_j w_kj τ_kj` over the samples of `grid` with the weights `weights[k][j]`, as
/// `(row, column, value)` entries on the layout's variables (duplicates to be summed). Samples
/// whose weights all vanish are skipped.
pub(crate) fn weighted_torque_hessian(
    cat: &WholeCat,
    spline: &BSpline,
    layout: &Layout,
    grid: &[GridPoint],
    weights: &[Vec<f64>],
) -> Vec<(usize, usize, f64)> {
    grid.par_iter()
        .zip(weights)
        .with_min_len(16)
        .flat_map_iter(|(&(span, time, _), w)| sample_hessian(cat, spline, layout, span, time, w))
        .collect()
}

/// One sample's `Bᵀ H B` (module docs) as entries on the layout's variables.
fn sample_hessian(
    cat: &WholeCat,
    spline: &BSpline,
    layout: &Layout,
    span: usize,
    time: f64,
    w: &[f64],
) -> Vec<(usize, usize, f64)> {
    if w.iter().all(|&x| x == 0.0) {
        return Vec::new();
    }
    let joints = layout.joints;
    let basis = spline.basis(span, time);
    let [q, qd, qdd] = spline.values::<MAX_JOINTS>(&basis);
    let at = cat.torque_partials(&q[..joints], &qd[..joints], &qdd[..joints]);
    // H over (derivative order a, coordinate j) at index a·J + j.
    let size = 3 * joints;
    let mut h = vec![0.0; size * size];
    for order in 0..2 {
        for j in 0..joints {
            let (mut qq, mut qqd) = (q, qd);
            let step = if order == 0 { STEP_ANGLE } else { STEP_RATE };
            if order == 0 {
                qq[j] += step;
            } else {
                qqd[j] += step;
            }
            let moved = cat.torque_partials(&qq[..joints], &qqd[..joints], &qdd[..joints]);
            for b in 0..3 {
                for k in 0..joints {
                    let d: f64 = (0..joints).map(|i| w[i] * (moved[i].d[b][k] - at[i].d[b][k])).sum::<f64>() / step;
                    h[(b * joints + k) * size + order * joints + j] = d;
                }
            }
        }
    }
    // Symmetric: the (q, q̇) block averaged with its transpose, the q̈ rows mirrored.
    for r in 0..2 * joints {
        for c in 0..r {
            let v = 0.5 * (h[r * size + c] + h[c * size + r]);
            h[r * size + c] = v;
            h[c * size + r] = v;
        }
    }
    for r in 2 * joints..size {
        for c in 0..2 * joints {
            h[c * size + r] = h[r * size + c];
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
