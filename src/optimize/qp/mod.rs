//! The profile QP: the circulation rate of least peak torque in the paper's model (DESIGN.md §5),
//! solved with Clarabel through the conic layer ([`crate::optimize::conic`]). The constraints on
//! the node rates are shared with the linearised step of the exact-dynamics refinement
//! ([`crate::optimize::refine::solve_linearised_step`]), which imposes them on `ω + δ`.
//!
//! ## The profile QP
//!
//! The paper bounds the twist-phase torque by `τ = I^* \dot ω` (§8, used for the number of §7).
//! The rate `ω` is discretised at `N` equally spaced nodes on the twist phase `[0, T]`, spacing
//! `h = T/(N−1)`, linear in between (the profile of [`Profile::from_rate_nodes`]), so
//! `\dot ω` is piecewise constant and the model's peak torque is `I^* \max_k |ω_{k+1} − ω_k|/h`.
//!
//! The QP is posed in normalised units: `u = s/T`, `\hat h = 1/(N−1)`, `v_k = ω_k T/D`
//! (`D` the circulation `∫ω ds`), and the peak coefficient `c = t T²/(I^* |D|)`, so that
//! every number is of order one whatever the cat and the fall:
//!
//! $$
//! \begin{aligned}
//! \min_{v \in \mathbb{R}^N,\; c}\quad & c + λ\, \hat h \sum_{k=1}^{N-2}
//!     \Big(\frac{v_{k+1} - 2 v_k + v_{k-1}}{\hat h^2}\Big)^2 \\
//! \text{s.t.}\quad & -c \le (v_{k+1} - v_k)/\hat h \le c, && k = 0, …, N-2, \\
//! & \textstyle \hat h \sum_{k=0}^{N-2} (v_k + v_{k+1})/2 = 1 && \text{(trapezoid rule)}, \\
//! & v_0 = 0, \quad (v_{N-1} = 0 \text{ for rest-to-rest}), \\
//! & |v_k| \le \hat R = R T/|D| && \text{(optional rate limit } R\text{)}, \\
//! & |v_{k+1} - 2 v_k + v_{k-1}| / \hat h^2 \le \hat J = J T^3/|D|
//!     && \text{(optional jerk limit } J\text{)}.
//! \end{aligned}
//! $$
//!
//! With a jerk limit the acceleration also starts and ends at zero (continuity of acceleration
//! at the ends): `|v_1 − v_0|/\hat h^2 ≤ \hat J` and `|v_{N−1} − v_{N−2}|/\hat h^2 ≤ \hat J`.
//! The smoothness weight `λ` is dimensionless: the second term is `∫ (P''')² du` of the
//! normalised motion `P` (its jerk), in the same normalised units as the peak coefficient `c`.
//! Then `ω_k = (D/T) v_k` and the peak torque is `I^* |D| c / T²`.
//!
//! In Clarabel's standard form `min ½xᵀPx + qᵀx` s.t. `Ax + s = b`, `s ∈ \{0\}^{m_1} ×
//! \mathbb{R}_+^{m_2}`, with `x = (v_0, …, v_{N−1}, c)`, every row has at most three nonzeros
//! except the integral row (`N`) and the column of `c` (`2(N−1)`): the data has `O(N)`
//! nonzeros and is built once from triplets. Inequality rows are kept in acceleration units,
//! so Clarabel's feasibility tolerance reads directly as a tolerance on the peak coefficient.
//! With a jerk limit, `x` also holds the accelerations `a_k = (v_{k+1} − v_k)/\hat h` (one
//! equality each); the peak rows become `|a_k| ≤ c` and the jerk rows the two-term
//! `|a_k − a_{k−1}| ≤ \hat h \hat J` (with `a_{−1} = a_{N−1} = 0`), which Clarabel solves in
//! a number of iterations that hardly grows with `N`.
//!
//! With rest-to-rest ends the QP is invariant under reversing time (`v_k ↔ v_{N−1−k}`,
//! `a_k ↔ −a_{N−2−k}`); being convex, it then has a reversal-symmetric optimum (the mean of any
//! optimum and its reverse). It is solved on those profiles only: half the variables, the
//! mirrored rows merged. The returned rates are symmetric; the peak, objective and status are
//! those of the full QP.
//!
//! ## Closed forms (exact for the discrete problem, without limits and with `λ = 0`)
//!
//! - **Rest-to-rest, `N` odd**: the triangle (bang-bang acceleration) `v_k = c \hat h
//!   \min(k, N−1−k)` with `c = 4`: peak torque `4 D I^*/T²`, the classic bang-bang value.
//! - **Rest-to-rest, `N` even**: the top of the triangle falls between two nodes; the two
//!   middle nodes share it and the middle interval does not accelerate. The trapezoid rule then
//!   gives `c = 4 (N−1)² / (N (N−2))`, which tends to 4 as `N → ∞`.
//! - **Start-at-rest** (the paper's boundary): `ω` rises with constant, maximal acceleration over
//!   the whole phase, `v_k = 2 k \hat h`, and ends at `2D/T`: `c = 2`, peak torque `2 D I^*/T²`,
//!   for every `N`.
//! - **Rate limit, rest-to-rest**: the trapezoid rule bounds the circulation by `\hat R`, so
//!   `R ≤ D/T` is infeasible (the mean rate over the phase is `D/T`). With `R = 3D/(2T)` and
//!   `N − 1` divisible by 3 the optimum is the trapezoid of thirds, `c = 9/2`.
//! - **Jerk limit, rest-to-rest, continuum limit**: the S-curve whose acceleration ramps at the
//!   full jerk, `c = \hat J/4 − \sqrt{\hat J²/16 − 2 \hat J}`, feasible for `\hat J ≥ 32`.
//!
//! ## References
//! - P. J. Goulart and Y. Chen, *Clarabel: An interior-point solver for conic programs with
//!   quadratic objectives*, arXiv:2405.12762 (2024);
//! - the paper, §4 (the circulation), §7 and §8 (the torque bound `τ₂ = I^* \dot ω₂`);
//! - H. A. Rothbart, *Cam Design Handbook* (2004), for the classic acceleration coefficients.
//!
//! [`Profile::from_rate_nodes`]: crate::schedule::profile::Profile::from_rate_nodes

mod nodes;
mod problemdata;
mod solution;

use crate::numeric::numfmt::{echo, num};
use crate::optimize::conic::{ConicError, QpStatus};

pub(crate) use nodes::NodeConstraints;
pub use problemdata::ProfileQp;
pub use solution::ProfileQpSolution;

/// Why the profile QP could not be set up, or why its answer does not exist. How a Clarabel solve
/// ended is the [`QpStatus`] of the solution; [`ProfileQpSolution::solved`] turns a status other
/// than solved into [`QpError::NotSolved`] for a caller that needs the profile.
#[derive(Debug, thiserror::Error)]
pub enum QpError {
    /// A closed-form bound proves the limits infeasible, before any solve (see
    /// [`ProfileQp::feasibility`]).
    #[error("{} = {}: infeasible: the {} {} {unit} is below the {} {unit} this move needs ({why})", limit.field(), echo(*given), limit.describe(), num(*given), num(*needed))]
    Infeasible {
        /// Which limit.
        limit: Limit,
        /// The limit given, in `unit`.
        given: f64,
        /// The least value for which a profile exists, in `unit`.
        needed: f64,
        /// Unit of both.
        unit: &'static str,
        /// Where the bound comes from.
        why: &'static str,
    },
    /// A limit so far above what the move needs that the normalised QP cannot resolve it (its
    /// rows would hold numbers beyond [`MEANINGFUL_LIMIT_FACTOR`] times the others).
    #[error("{} = {} {unit} is numerically meaningless: more than {} times the {} {unit} this move needs; leave it out for no limit", limit.field(), echo(*given), num(MEANINGFUL_LIMIT_FACTOR), num(*needed))]
    MeaninglessLimit {
        /// Which limit.
        limit: Limit,
        /// The limit given, in `unit`.
        given: f64,
        /// The least value for which a profile exists, in `unit`.
        needed: f64,
        /// Unit of both.
        unit: &'static str,
    },
    /// Clarabel ended without a solution (infeasible to its tolerances, iteration or time limit,
    /// numerical trouble): the asked-for profile does not exist.
    #[error("the profile QP has no solution: {status}")]
    NotSolved {
        /// How Clarabel ended.
        status: QpStatus,
    },
    /// An input the QP cannot use, or settings or data Clarabel refused.
    #[error(transparent)]
    Conic(#[from] ConicError),
}

/// A limit of the profile QP, as the problem file names it.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Limit {
    /// `optimize.rate_limit`, on `|ω|`.
    Rate,
    /// `optimize.jerk_limit`, on `|d²ω/ds²|`.
    Jerk,
}

impl Limit {
    /// The field of the problem file.
    pub fn field(self) -> &'static str {
        match self {
            Limit::Rate => "optimize.rate_limit",
            Limit::Jerk => "optimize.jerk_limit",
        }
    }

    /// In words.
    pub fn describe(self) -> &'static str {
        match self {
            Limit::Rate => "rate limit",
            Limit::Jerk => "jerk limit",
        }
    }
}

/// A limit more than this many times what the move needs is refused as numerically meaningless
/// ([`QpError::MeaninglessLimit`]): in the normalised QP its rows would carry bounds of this size
/// against coefficients of order one, which an interior-point method does not resolve (a rate
/// limit of `1e20` rad/s ended in NaN). No optimum comes near it: without limits the rate stays
/// below `2|D|/T` and the steps of the acceleration below `8(N−1)|D|/T³` per node spacing.
pub const MEANINGFUL_LIMIT_FACTOR: f64 = 1e4;
