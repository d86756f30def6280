//! The profile QP's data: what the paper's model needs to know, in SI units.

use serde::{Deserialize, Serialize};

use super::nodes::NodeConstraints;
use super::solution::{max_abs_difference, ProfileQpSolution};
use super::{Limit, QpError, MEANINGFUL_LIMIT_FACTOR};
use crate::optimize::conic::{bad, positive, positive_opt, Assembly, Fold, QpSettings, QpStatus};
use crate::problem::settings::{Boundary, OptimizeSettings};

/// The profile QP of the module docs: the circulation rate on the twist phase with the least
/// peak of the model's torque `I* |dω/ds|`.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ProfileQp {
    /// Number of rate nodes `N`, equally spaced on the phase, ends included.
    pub nodes: usize,
    /// Duration `T` of the twist phase, s.
    pub duration: f64,
    /// Circulation `D = ∫ω ds` over the phase, rad (either sign, not zero).
    pub circulation: f64,
    /// Moment of inertia `I*` of the torque model `τ = I* dω/ds`, kg·m².
    pub inertia: f64,
    /// Boundary conditions of the rate.
    pub boundary: Boundary,
    /// Bound on `|ω|`, rad/s; none when absent.
    pub rate_limit: Option<f64>,
    /// Bound on `|d²ω/ds²|`, rad/s³; none when absent. When present, `dω/ds` is also zero at
    /// both ends.
    pub jerk_limit: Option<f64>,
    /// Dimensionless weight `λ` of the smoothness term (module docs); zero for none.
    pub smoothness: f64,
}

impl ProfileQp {
    /// The exact optimum of the discrete problem when it has a closed form (module docs): without
    /// limits or smoothing, `c = 4` (rest-to-rest, `N` odd), `4(N−1)²/(N(N−2))` (rest-to-rest,
    /// `N` even) or `2` (start-at-rest); the peak torque is `c I* |D| / T²`, N·m.
    pub fn closed_form_peak(&self) -> Option<f64> {
        if self.rate_limit.is_some() || self.jerk_limit.is_some() || self.smoothness > 0.0 || self.nodes < 3 {
            return None;
        }
        let n = self.nodes as f64;
        let c = match self.boundary {
            Boundary::StartAtRest => 2.0,
            Boundary::RestToRest if self.nodes % 2 == 1 => 4.0,
            Boundary::RestToRest => 4.0 * (n - 1.0).powi(2) / (n * (n - 2.0)),
        };
        Some(c * self.torque_scale())
    }

    /// The QP of the optimiser's settings for a twist phase of `duration` s, a circulation of
    /// `circulation` rad and the torque model's inertia `inertia` kg·m².
    pub fn new(settings: &OptimizeSettings, duration: f64, circulation: f64, inertia: f64) -> Self {
        Self {
            nodes: settings.nodes,
            duration,
            circulation,
            inertia,
            boundary: settings.boundary,
            rate_limit: settings.rate_limit,
            jerk_limit: settings.jerk_limit,
            smoothness: settings.smoothness,
        }
    }

    /// Checks every field; names the first one that is wrong.
    pub fn validate(&self) -> Result<(), QpError> {
        if self.nodes < 3 {
            return Err(bad("nodes", self.nodes, "must be at least 3").into());
        }
        positive("duration", self.duration)?;
        if !self.circulation.is_finite() || self.circulation == 0.0 {
            return Err(bad("circulation", self.circulation, "must be finite and non-zero").into());
        }
        positive("inertia", self.inertia)?;
        positive_opt("rate_limit", self.rate_limit)?;
        positive_opt("jerk_limit", self.jerk_limit)?;
        if !self.smoothness.is_finite() || self.smoothness < 0.0 {
            return Err(bad("smoothness", self.smoothness, "must be a finite, non-negative weight").into());
        }
        Ok(())
    }

    /// Refuses limits that no profile can meet, by closed-form bounds of the continuous move, and
    /// limits too large to mean anything ([`QpError::MeaninglessLimit`]).
    ///
    /// - **Rate**: rates bounded by `R` cover at most `R T` in time `T`, and less when the rate
    ///   starts at rest; the trapezoid rule on the `N` nodes with `ω_0 = 0` covers at most
    ///   `R T (1 − ĥ/2)`, and `R T (1 − ĥ)` with `ω_{N−1} = 0` too (`ĥ = 1/(N−1)`). So the
    ///   move needs `R ≥ |D| / (T (1 − ĥ))` rest-to-rest and `|D| / (T (1 − ĥ/2))` start-at-rest.
    /// - **Jerk** (with zero acceleration at both ends): the distance reached under `|φ⃛| ≤ J`
    ///   is largest for bang-bang jerk. Rest-to-rest that is `+J, −J, −J, +J` over quarters of
    ///   `T`, covering `J T³/32`, so the move needs `J ≥ 32 |D|/T³` (the double-S profile with
    ///   neither speed nor acceleration limit reached, Biagiotti & Melchiorri, *Trajectory
    ///   Planning for Automatic Machines and Robots*, Springer 2008, §3.4: `T = 4 T_j`,
    ///   `D = 2 J T_j³`). Start-at-rest (final rate free): `D = ∫ (T − t)²/2 · φ⃛ dt` with
    ///   `∫ φ⃛ dt = 0` is largest for `+J` then `−J` over halves, `J T³/8`, so `J ≥ 8 |D|/T³`.
    ///   (The discrete QP may need a little more; Clarabel's status says so.)
    pub fn feasibility(&self) -> Result<(), QpError> {
        let (t, d) = (self.duration, self.circulation.abs());
        let h = 1.0 / (self.nodes as f64 - 1.0);
        if let Some(r) = self.rate_limit {
            let (needed, why) = match self.boundary {
                Boundary::RestToRest => {
                    (d / (t * (1.0 - h)), "rates bounded by R cover at most R·T(1 − 1/(N−1)) from rest to rest")
                }
                Boundary::StartAtRest => {
                    (d / (t * (1.0 - 0.5 * h)), "rates bounded by R cover at most R·T(1 − 1/(2(N−1))) from rest")
                }
            };
            check(Limit::Rate, r, needed, "rad/s", why)?;
        }
        if let Some(j) = self.jerk_limit {
            let (needed, why) = match self.boundary {
                Boundary::RestToRest => (32.0 * d / t.powi(3), "32|D|/T³: bang-bang jerk over quarters of the phase"),
                Boundary::StartAtRest => (8.0 * d / t.powi(3), "8|D|/T³: bang-bang jerk over halves of the phase"),
            };
            check(Limit::Jerk, j, needed, "rad/s³", why)?;
        }
        Ok(())
    }

    /// Node spacing `h = T/(N − 1)`, s.
    pub fn spacing(&self) -> f64 {
        self.duration / (self.nodes as f64 - 1.0)
    }

    /// The rate unit of the normalised problem, `D/T`, rad/s (signed).
    pub fn rate_scale(&self) -> f64 {
        self.circulation / self.duration
    }

    /// The torque unit of the normalised problem, `I* |D| / T²`, N·m: the peak torque is this
    /// times the peak coefficient (4 for bang-bang).
    pub fn torque_scale(&self) -> f64 {
        self.inertia * self.circulation.abs() / self.duration.powi(2)
    }

    /// Solves with the default [`QpSettings`].
    pub fn solve(&self) -> Result<ProfileQpSolution, QpError> {
        self.solve_with(&QpSettings::default())
    }

    /// Solves with the given settings. A solve that ends without a solution is not an error: its
    /// status says how it ended.
    pub fn solve_with(&self, settings: &QpSettings) -> Result<ProfileQpSolution, QpError> {
        self.validate()?;
        self.feasibility()?;
        let n = self.nodes;
        let h = 1.0 / (n - 1) as f64;
        let (t, scale) = (self.duration, self.circulation.abs());
        let peak = n; // the column of the peak coefficient c, then the accelerations if any
        let rows = NodeConstraints {
            nodes: n,
            boundary: self.boundary,
            rate_limit: self.rate_limit.map(|r| r * t / scale),
            jerk_limit: self.jerk_limit.map(|j| j * t.powi(3) / scale),
            trust: None,
            offset: None,
            accel: peak + 1,
        };
        let mut asm = Assembly::new(n + 1 + rows.accel_count());
        asm.linear_cost(peak, 1.0);
        rows.add_to(&mut asm);
        for k in 0..n - 1 {
            if rows.accel_count() > 0 {
                asm.abs_at_most([(rows.accel + k, 1.0)].into_iter(), 0.0, peak);
            } else {
                asm.abs_at_most([(k, -1.0 / h), (k + 1, 1.0 / h)].into_iter(), 0.0, peak);
            }
        }
        if self.smoothness > 0.0 {
            // λ ĥ ((v_{k+1} − 2v_k + v_{k−1})/ĥ²)² = λ/ĥ³ (v_{k+1} − 2v_k + v_{k−1})²
            let weight = self.smoothness / h.powi(3);
            for k in 1..n - 1 {
                asm.square_cost(&[(k - 1, 1.0), (k, -2.0), (k + 1, 1.0)], weight);
            }
        }

        let solved = if self.boundary == Boundary::RestToRest {
            // Reversing time maps the problem to itself, so (convexity) the average of an optimum
            // and its reverse is an optimum: solve on the symmetric profiles, half the size.
            let fold = reversal(n, rows.accel_count());
            let mut solved = asm.fold(&fold).solve(settings)?;
            solved.x = fold.expand(&solved.x);
            solved
        } else {
            asm.solve(settings)?
        };
        let rates: Vec<f64> = solved.x[..n].iter().map(|v| v * self.rate_scale()).collect();
        // A solved status with non-finite numbers is no solution either.
        let finite = rates.iter().all(|w| w.is_finite()) && solved.objective.is_finite();
        let status = if solved.status.is_solved() && !finite { QpStatus::NumericalError } else { solved.status };
        let torque = self.torque_scale();
        let (peak_torque, objective) = if status.is_solved() {
            (Some(self.inertia * max_abs_difference(&rates) / self.spacing()), Some(solved.objective * torque))
        } else {
            (None, None)
        };
        let mut info = solved.info;
        info.duality_gap *= torque;
        Ok(ProfileQpSolution { status, rates, peak_torque, objective, info })
    }
}

/// Refuses a limit below what the move needs, or meaninglessly far above it.
fn check(limit: Limit, given: f64, needed: f64, unit: &'static str, why: &'static str) -> Result<(), QpError> {
    if given < needed {
        return Err(QpError::Infeasible { limit, given, needed, unit, why });
    }
    if given > MEANINGFUL_LIMIT_FACTOR * needed {
        return Err(QpError::MeaninglessLimit { limit, given, needed, unit });
    }
    Ok(())
}

/// The substitution onto reversal-symmetric variables of `x = (v_0 … v_{N−1}, c, a_0 … a_{m−1})`:
/// `v_k = v_{N−1−k}` (even), `a_k = −a_{m−1−k}` (odd; a middle one is zero), `c` alone.
fn reversal(nodes: usize, accels: usize) -> Fold {
    let half = nodes.div_ceil(2); // distinct rates
    let mut map: Vec<Option<(usize, f64)>> = (0..nodes).map(|k| Some((k.min(nodes - 1 - k), 1.0))).collect();
    map.push(Some((half, 1.0)));
    for k in 0..accels {
        let mirror = accels - 1 - k;
        map.push(match k.cmp(&mirror) {
            std::cmp::Ordering::Less => Some((half + 1 + k, 1.0)),
            std::cmp::Ordering::Greater => Some((half + 1 + mirror, -1.0)),
            std::cmp::Ordering::Equal => None,
        });
    }
    Fold { map, n: half + 1 + accels / 2 }
}
