//! The curvature that the subproblems' models leave out, estimated from the accepted steps: the
//! orientation constraint's for the energy (damped BFGS), the Lagrangian's for the peak
//! (a scalar).
//!
//! The energy subproblem ([`super::subproblem`]) models `J = Σ_k w_k |τ_k|²` by Gauss–Newton and
//! the orientation constraint `e(x) = 0` by its linearisation. The Hessian of the Lagrangian
//! `ℒ = J + λᵀe` also has the constraint's curvature `W = Σ_i λ_i ∇²e_i`. A step along the tangent
//! of `e = 0` leaves the manifold by `O(|δ|²)`; the second-order correction of [`super::scvx`]
//! brings it back at a cost `½ δᵀWδ` in `J` that the model does not predict, so near the optimum,
//! where the reduced gradient is small, every ratio test falls to about a third and the trust
//! region crawls (measured on a fat cat, r/l = 0.25, from the `paper` start: 200 iterations at
//! radii near 5·10⁻⁴ rad, ratios 0.3–0.4, still descending).
//!
//! `W` is estimated from the accepted steps by the secant condition on the constraint's part of
//! `∇ℒ` (N&W §18.3; the structured form of Dennis, Gay & Welsch): with `s = x₊ − x` and the
//! least-squares multipliers `λ₊ = −(J_e J_eᵀ)⁻¹ J_e ∇J` at `x₊`,
//!
//! $$ y = (J_{e+} − J_e)ᵀ λ₊ , $$
//!
//! and `B ≈ W` is updated by BFGS with Powell's damping (N&W Procedure 18.2), which keeps `B`
//! positive definite so that the subproblem stays convex: where `W` has negative curvature the
//! model is conservative, never non-convex. `B₀ = (sᵀy/sᵀs) I` at the first pair with positive
//! curvature; before it the model is Gauss–Newton alone. The torques' own second derivatives,
//! which Gauss–Newton also leaves out, are not estimated: adding them to `y` (measured) slowed the
//! paper's energy optimum from the `paper` start from 22 to 54 iterations.
//!
//! ## The peak
//!
//! The peak's subproblem is a linear program (minimax on the linearised torques), and where its
//! optimum is not a vertex (fewer torque samples at the peak than free directions: the no-twist
//! joint's optimum) successive linear programming crawls: measured on `problems/kane-scher.toml`
//! from the `paper` start, 150 iterations at radii near 10⁻⁴ rad with ratios of 0.15–0.2, the peak
//! falling by 10⁻⁸ N·m per iteration, and the iteration limit reached. The peak's model therefore
//! also takes a curvature, from the secant pair of its Lagrangian's torque and flip terms
//! `ℒ = t + Σ z_r (±τ_r − t) + λᵀe` with the multipliers `z`, `λ` of the subproblem that made the
//! step (the bend and motor-limit rows' multipliers are left out), `y = Σ ±z_r (∇τ_r(x₊) − ∇τ_r(x)) + (J_{e+} − J_e)ᵀλ` (the torques' curvature is what the
//! linear model lacks most; the constraint's alone, tried, left the crawl as it was). Kept as the
//! full BFGS matrix it ends the crawl (51 iterations) but makes `P` dense and each iteration 2.5
//! times slower (10.3 s for that problem); kept as the scalar `σ = sᵀy/sᵀs` (the Lagrangian's
//! curvature along the last step, `B = σ𝟙`: a proximal term) it ends the crawl as well, converging
//! from both starts (92 and 49 iterations), for 3.0 s. The paper's cat reaches the same optimum
//! as without it.
//!
//! ## References
//! - J. E. Dennis, D. M. Gay, R. E. Welsch, *An adaptive nonlinear least-squares algorithm*,
//!   ACM TOMS 7 (1981) 348–368;
//! - J. Nocedal, S. J. Wright, *Numerical Optimization* (2nd ed., 2006), §18.3 and Procedure 18.2.

use nalgebra::{DMatrix, DVector, Vector3};

use super::reach::Reach;
use super::sensitivity::TorqueSample;
use crate::optimize::conic::Assembly;

/// Powell's damping threshold: the update keeps `sᵀr ≥ 0.2 sᵀBs`.
const DAMPING: f64 = 0.2;

/// `∇J = 2 Σ_k w_k Σ_j τ_kj ∇τ_kj` over `n` variables.
pub fn energy_gradient(samples: &[TorqueSample], n: usize) -> DVector<f64> {
    let mut g = DVector::zeros(n);
    for s in samples {
        for (tau, gradient) in s.tau.iter().zip(&s.gradient) {
            for &(v, c) in gradient {
                g[v] += 2.0 * s.weight * tau * c;
            }
        }
    }
    g
}

/// The least-squares multipliers `λ = −(J_e J_eᵀ)⁻¹ J_e g` of the orientation constraint with
/// Jacobian `jacobian` (3 × n) for the objective gradient `g`. Where `J_e` is rank deficient
/// (equal halves on the no-twist joint cannot swing) the inverse is taken on the directions the
/// controls reach ([`Reach`]): the full inverse would divide by round-off and give multipliers
/// of `10¹²`, and a curvature estimate built on them misleads every later subproblem. None when
/// `J_e` vanishes or `J_e J_eᵀ` cannot be factored.
pub fn multipliers(gradient: &DVector<f64>, jacobian: &DMatrix<f64>) -> Option<Vector3<f64>> {
    let rhs = jacobian * gradient;
    match Reach::of(jacobian) {
        Reach::Full => {
            let jjt = jacobian * jacobian.transpose();
            let solved = jjt.lu().solve(&rhs)?;
            Some(-Vector3::new(solved[0], solved[1], solved[2]))
        }
        reach => reach.newton_multipliers(jacobian, &Vector3::new(rhs[0], rhs[1], rhs[2])).map(|y| -y),
    }
}

/// One side of a secant pair: an iterate's values, torque samples (for the multipliers) and
/// constraint Jacobian.
#[derive(Clone, Copy)]
pub struct Point<'a> {
    /// The free control points, rad.
    pub values: &'a [f64],
    /// Torques and gradients on the energy grid.
    pub samples: &'a [TorqueSample],
    /// `∂e/∂x`, 3 × n.
    pub jacobian: &'a DMatrix<f64>,
}

/// How an estimate is kept (module docs).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Form {
    /// Damped BFGS, a dense matrix (the energy's).
    #[default]
    Bfgs,
    /// A multiple of the identity, the Rayleigh quotient of the last pair with positive
    /// curvature (the peak's).
    Scalar,
}

/// An estimate `B` over the `n` variables of a step.
#[derive(Clone, Debug, PartialEq)]
pub enum Estimate {
    /// A dense symmetric matrix ([`Form::Bfgs`]).
    Dense(DMatrix<f64>),
    /// `σ𝟙` ([`Form::Scalar`]).
    Scalar {
        /// `σ`, in the objective's units per rad².
        sigma: f64,
        /// The number of variables.
        n: usize,
    },
}

impl Estimate {
    /// `δᵀBδ`.
    pub fn quadratic_form(&self, step: &DVector<f64>) -> f64 {
        match self {
            Estimate::Dense(b) => step.dot(&(b * step)),
            Estimate::Scalar { sigma, .. } => step.dot(&(step * *sigma)),
        }
    }

    /// Adds `½ weight · δᵀBδ` to the objective of `asm` (`δ` its first `n` variables).
    pub(crate) fn add_to(&self, asm: &mut Assembly, weight: f64) {
        match self {
            Estimate::Dense(b) => asm.quadratic_cost(b, weight),
            Estimate::Scalar { sigma, n } => asm.identity_cost(*n, weight * sigma),
        }
    }
}

/// The estimate `B` (module docs); none until a pair with positive curvature.
#[derive(Clone, Debug, Default)]
pub struct Curvature {
    form: Form,
    estimate: Option<Estimate>,
}

impl Curvature {
    /// An empty estimate kept in `form`.
    pub fn new(form: Form) -> Self {
        Curvature { form, estimate: None }
    }

    /// The estimate, when there is one.
    pub fn estimate(&self) -> Option<&Estimate> {
        self.estimate.as_ref()
    }

    /// Updates the estimate with the accepted move from `from` to `to`, with the energy's
    /// least-squares multipliers at `to`.
    pub fn update(&mut self, from: Point<'_>, to: Point<'_>) {
        let n = from.values.len();
        let Some(lambda) = multipliers(&energy_gradient(to.samples, n), to.jacobian) else { return };
        self.update_with(from, to, &lambda, &[]);
    }

    /// Updates the estimate with the accepted move from `from` to `to` and the multipliers of
    /// the subproblem that made it (as SQP takes them): `lambda` of the orientation constraint
    /// and `(sample, joint, ±z)` of the torque rows (the peak's; the secant pair is then that of
    /// the Lagrangian's torque and flip terms, module docs).
    pub fn update_with(
        &mut self,
        from: Point<'_>,
        to: Point<'_>,
        lambda: &Vector3<f64>,
        torques: &[(usize, usize, f64)],
    ) {
        let n = from.values.len();
        let s = DVector::from_iterator(n, to.values.iter().zip(from.values).map(|(a, b)| a - b));
        let mut y = (to.jacobian - from.jacobian).transpose() * lambda;
        for &(k, j, w) in torques {
            for &(v, c) in &to.samples[k].gradient[j] {
                y[v] += w * c;
            }
            for &(v, c) in &from.samples[k].gradient[j] {
                y[v] -= w * c;
            }
        }
        self.apply(&s, &y);
    }

    /// The update with the pair `(s, y)`: damped BFGS, or the scalar `sᵀy/sᵀs` when positive.
    fn apply(&mut self, s: &DVector<f64>, y: &DVector<f64>) {
        let ss = s.norm_squared();
        let sy = s.dot(y);
        if !(ss > 0.0 && sy.is_finite() && y.iter().all(|v| v.is_finite())) {
            return;
        }
        if self.form == Form::Scalar {
            if sy > 0.0 {
                self.estimate = Some(Estimate::Scalar { sigma: sy / ss, n: s.len() });
            }
            return;
        }
        let b = match self.estimate.take() {
            Some(Estimate::Dense(b)) => b,
            _ if sy > 0.0 => DMatrix::identity(s.len(), s.len()) * (sy / ss),
            _ => return,
        };
        let bs = &b * s;
        let sbs = s.dot(&bs);
        if sbs <= 0.0 || !sbs.is_finite() {
            self.estimate = Some(Estimate::Dense(b));
            return;
        }
        let theta = if sy >= DAMPING * sbs { 1.0 } else { (1.0 - DAMPING) * sbs / (sbs - sy) };
        let r = y * theta + &bs * (1.0 - theta);
        let sr = s.dot(&r);
        let updated = &b - &bs * bs.transpose() / sbs + &r * r.transpose() / sr;
        self.estimate = Some(Estimate::Dense(updated));
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The dense estimate of a BFGS curvature.
    fn dense(c: &Curvature) -> Option<&DMatrix<f64>> {
        match c.estimate() {
            Some(Estimate::Dense(b)) => Some(b),
            _ => None,
        }
    }

    /// On a quadratic with Hessian `A` the secant pairs are `y = A s`; every BFGS update
    /// satisfies the secant condition `B₊ s = y` (Nocedal & Wright, eq. 6.6).
    #[test]
    fn secant_condition_holds_after_each_update() {
        let a = DMatrix::from_row_slice(3, 3, &[4.0, 1.0, 0.0, 1.0, 3.0, 0.5, 0.0, 0.5, 2.0]);
        let mut c = Curvature::default();
        for s in [[1.0, 0.0, 0.0], [0.3, 1.0, -0.2], [0.1, -0.4, 1.0]] {
            let s = DVector::from_row_slice(&s);
            let y = &a * &s;
            c.apply(&s, &y);
            let b = dense(&c).expect("positive curvature gives an estimate");
            assert!((b * &s - &y).norm() <= 1e-12 * y.norm(), "B s = y after the update");
        }
    }

    #[test]
    fn negative_curvature_is_damped_and_the_estimate_stays_positive_definite() {
        let mut c = Curvature::default();
        c.apply(&DVector::from_row_slice(&[1.0, 0.0]), &DVector::from_row_slice(&[2.0, 0.0]));
        c.apply(&DVector::from_row_slice(&[0.0, 1.0]), &DVector::from_row_slice(&[0.0, -5.0]));
        let b = dense(&c).expect("an estimate");
        let eig = b.clone().symmetric_eigen().eigenvalues;
        assert!(eig.iter().all(|&l| l > 0.0), "eigenvalues {eig:?}");
    }

    #[test]
    fn no_estimate_before_positive_curvature() {
        let mut c = Curvature::default();
        c.apply(&DVector::from_row_slice(&[1.0, 0.0]), &DVector::from_row_slice(&[-1.0, 0.0]));
        assert!(c.estimate().is_none());
    }
}
