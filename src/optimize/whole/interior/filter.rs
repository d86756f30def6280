//! The filter that accepts or rejects a trial point of the line search (Wächter and Biegler
//! 2006, §2.3).
//!
//! A trial point is measured by its constraint violation `θ` (`|e|₁ + Σ|g − s|`) and its barrier
//! objective `φ = t − μ Σ ln s`. It is acceptable when no earlier pair dominates it and it
//! improves on the current point: in `θ` or in `φ` by a margin of `θ`; where the current point is
//! nearly feasible and the step is a descent direction of `φ` that outweighs the violation (the
//! switching condition), by an Armijo decrease of `φ` alone, and such a step leaves the filter as
//! it was. Every other accepted step adds the current pair, with its margins, to the filter (the
//! paper spares the filter also a step that meets both the switching and the Armijo conditions
//! above `θ_min`; adding it there is only more cautious). A new barrier parameter starts a new
//! filter.

/// `γ_θ`: the share of the violation a step must remove.
const GAMMA_THETA: f64 = 1e-5;
/// `γ_φ`: the barrier objective's margin per unit violation.
const GAMMA_PHI: f64 = 1e-8;
/// `η_φ`: the Armijo constant.
const ETA_PHI: f64 = 1e-8;
/// `s_φ`: the switching condition's exponent of the slope.
const SWITCH_PHI: f64 = 2.3;
/// `s_θ`: the switching condition's exponent of the violation.
const SWITCH_THETA: f64 = 1.1;

/// The pairs `(θ, φ)` that trial points must not be dominated by.
#[derive(Clone, Debug, Default)]
pub(crate) struct Filter {
    pairs: Vec<(f64, f64)>,
    /// Violation above which no trial is accepted.
    theta_max: f64,
    /// Violation below which the switching condition may apply.
    theta_min: f64,
}

/// The current point of a line search: its violation, barrier objective, and the directional
/// derivative of the barrier objective along the step.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Current {
    pub(crate) theta: f64,
    pub(crate) phi: f64,
    pub(crate) slope: f64,
}

/// A trial accepted by the filter, and whether the current pair joins it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Verdict {
    /// Rejected.
    Reject,
    /// Accepted by the Armijo condition: the filter stays.
    Armijo,
    /// Accepted by the filter: the current pair joins it.
    Filter,
}

impl Filter {
    /// An empty filter for a stage that starts at violation `theta0`.
    pub(crate) fn new(theta0: f64) -> Filter {
        Filter { pairs: Vec::new(), theta_max: 1e4 * theta0.max(1.0), theta_min: 1e-4 * theta0.max(1.0) }
    }

    /// A new barrier parameter: the pairs are dropped.
    pub(crate) fn clear(&mut self) {
        self.pairs.clear();
    }

    /// The verdict on a trial `(theta, phi)` reached with step length `alpha` from `current`.
    pub(crate) fn judge(&self, current: Current, theta: f64, phi: f64, alpha: f64) -> Verdict {
        if theta > self.theta_max || self.pairs.iter().any(|&(t, p)| theta >= t && phi >= p) {
            return Verdict::Reject;
        }
        let switching =
            current.slope < 0.0 && alpha * (-current.slope).powf(SWITCH_PHI) > current.theta.powf(SWITCH_THETA);
        if switching && current.theta <= self.theta_min {
            if phi <= current.phi + ETA_PHI * alpha * current.slope {
                Verdict::Armijo
            } else {
                Verdict::Reject
            }
        } else if theta <= (1.0 - GAMMA_THETA) * current.theta || phi <= current.phi - GAMMA_PHI * current.theta {
            Verdict::Filter
        } else {
            Verdict::Reject
        }
    }

    /// Adds the current pair, with its margins, after a step the filter accepted.
    pub(crate) fn add(&mut self, current: Current) {
        self.pairs.push(((1.0 - GAMMA_THETA) * current.theta, current.phi - GAMMA_PHI * current.theta));
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_dominated_trial_is_rejected_and_a_better_one_accepted() {
        let mut f = Filter::new(1.0);
        let current = Current { theta: 1e-2, phi: 1.0, slope: -1e-9 };
        // Less violation: accepted by the filter, and the pair joins it.
        assert_eq!(f.judge(current, 5e-3, 1.1, 1.0), Verdict::Filter);
        f.add(current);
        // From a worse point later, a trial that improves on it but that the stored pair
        // dominates (more violation and a higher objective than the pair) is rejected...
        let later = Current { theta: 3e-2, phi: 1.5, slope: -1e-9 };
        assert_eq!(f.judge(later, 1.5e-2, 1.1, 1.0), Verdict::Reject);
        // ...and the same trial without the pair is accepted.
        assert_eq!(Filter::new(1.0).judge(later, 1.5e-2, 1.1, 1.0), Verdict::Filter);
        // More violation at a lower objective than the pair: not dominated, and an improvement.
        assert_eq!(f.judge(later, 2e-2, 0.99, 1.0), Verdict::Filter);
        // Beyond the largest violation the filter allows: rejected whatever the objective.
        assert_eq!(f.judge(current, 2e4, 0.0, 1.0), Verdict::Reject);
    }

    #[test]
    fn a_feasible_descent_step_needs_an_armijo_decrease() {
        let f = Filter::new(1.0);
        let current = Current { theta: 0.0, phi: 1.0, slope: -1.0 };
        assert_eq!(f.judge(current, 0.0, 1.0 - 1e-3, 1.0), Verdict::Armijo);
        assert_eq!(f.judge(current, 0.0, 1.0, 1.0), Verdict::Reject);
    }
}
