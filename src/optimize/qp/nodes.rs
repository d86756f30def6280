//! The constraints on the normalised node rates that the profile QP and the refinement's
//! linearised step share (the profile QP's module docs): the trapezoid integral, the boundary
//! conditions, the rate and jerk limits and the trust box, written once on `v = offset + x`.

use crate::optimize::conic::Assembly;
use crate::problem::settings::Boundary;

/// The constraints on normalised node rates `v = offset + x` (the first `nodes` variables `x`)
/// that the profile QP and the linearised step share; see the module docs. Limits are
/// normalised, `None` for none.
pub(crate) struct NodeConstraints<'a> {
    pub(crate) nodes: usize,
    pub(crate) boundary: Boundary,
    /// `\hat R`.
    pub(crate) rate_limit: Option<f64>,
    /// `\hat J`.
    pub(crate) jerk_limit: Option<f64>,
    /// Box `|x_k| ≤ trust` on the step.
    pub(crate) trust: Option<f64>,
    /// Current rates when `x` is a step; `None` when `x` is the rates themselves.
    pub(crate) offset: Option<&'a [f64]>,
    /// Column of `a_0`: with a jerk limit, the `N − 1` variables `a_k = (v_{k+1} − v_k)/ĥ` (the
    /// acceleration of the new rates) sit at `accel..accel + N − 1`; unused without one.
    pub(crate) accel: usize,
}

impl NodeConstraints<'_> {
    fn offset(&self, k: usize) -> f64 {
        self.offset.map_or(0.0, |o| o[k])
    }

    /// How many acceleration variables the rows use: `N − 1` with a jerk limit, else none.
    pub(crate) fn accel_count(&self) -> usize {
        if self.jerk_limit.is_some() {
            self.nodes - 1
        } else {
            0
        }
    }

    /// Adds the rows to `asm`.
    pub(crate) fn add_to(&self, asm: &mut Assembly) {
        let n = self.nodes;
        let h = 1.0 / (n - 1) as f64;
        let weight = |k: usize| if k == 0 || k == n - 1 { 0.5 * h } else { h };

        // Trapezoid integral of v is one.
        let current: f64 = (0..n).map(|k| weight(k) * self.offset(k)).sum();
        asm.equal((0..n).map(|k| (k, weight(k))), 1.0 - current);

        // Boundary conditions.
        asm.equal([(0, 1.0)], -self.offset(0));
        if self.boundary == Boundary::RestToRest {
            asm.equal([(n - 1, 1.0)], -self.offset(n - 1));
        }

        // Rate limit and trust box, one pair of rows per node.
        if self.rate_limit.is_some() || self.trust.is_some() {
            for k in 0..n {
                let (mut lower, mut upper) = (f64::NEG_INFINITY, f64::INFINITY);
                if let Some(r) = self.rate_limit {
                    lower = -r - self.offset(k);
                    upper = r - self.offset(k);
                }
                if let Some(t) = self.trust {
                    lower = lower.max(-t);
                    upper = upper.min(t);
                }
                asm.between(&[(k, 1.0)], lower, upper);
            }
        }

        // Jerk limit on acceleration variables, as change of acceleration per step ĥ Ĵ, from and
        // to zero acceleration at the ends. Posed as second differences of v, these rows slowed
        // Clarabel down badly as N grew (rest-to-rest, Ĵ = 80: 57 iterations at N = 2000, not
        // solved in 200 at N = 10⁵); on a_k they are two-term differences: 13, 25, 31, 36
        // iterations at N = 200, 2000, 20000, 10⁵.
        if let Some(j) = self.jerk_limit {
            let a = |k: usize| self.accel + k;
            for k in 0..n - 1 {
                let current = (self.offset(k + 1) - self.offset(k)) / h;
                asm.equal([(k + 1, 1.0 / h), (k, -1.0 / h), (a(k), -1.0)], -current);
            }
            let step = h * j;
            asm.between(&[(a(0), 1.0)], -step, step);
            for k in 1..n - 1 {
                asm.between(&[(a(k), 1.0), (a(k - 1), -1.0)], -step, step);
            }
            asm.between(&[(a(n - 2), 1.0)], -step, step);
        }
    }
}
