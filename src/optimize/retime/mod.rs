//! Certified retiming along a fixed joint path: the timing of least peak motor torque, as a
//! second-order-cone program solved by Clarabel (DESIGN.md §5, issue 13 §1).
//!
//! ## The reduced dynamics along a path
//!
//! A joint path `q(s)`, `s ∈ [0, S]`, with `q' = dq/ds` and `q'' = d²q/ds²`, is timed by `s(t)`:
//! `q̇ = q' ṡ`, `q̈ = q' s̈ + q'' ṡ²`. In the falling frame at zero angular momentum the motor
//! torques are `τ(q, q̇, q̈) = M(q) q̈ + c(q, q̇)` with `c` homogeneous quadratic in `q̇` (no gravity,
//! no potential), hence
//!
//! $$ τ(s) = a(s)\, \ddot s + b(s)\, \dot s^2, \qquad
//!    a = M(q)\, q' = τ(q, 0, q'), \quad b = M(q)\, q'' + c(q, q') = τ(q, q', q''), $$
//!
//! both evaluated by Newton–Euler ([`crate::engines::torque::ZeroMomentumTorques`]: the paper's
//! two-cylinder engine, or the general core for the other two-motor cats, unequal halves and the
//! no-twist joint of DESIGN.md §10) at the states `(q, q̇ = 0, q̈ = q')` and `(q, q̇ = q', q̈ = q'')`.
//! The reorientation is a geometric phase of the path ([`crate::engines::exact`]): no timing
//! changes twist or swing.
//!
//! ## The convex program
//!
//! With `x = ṡ²` and `u = s̈`, `dx/ds = 2u` (Verscheure et al. 2009). Each piece of the path has
//! a grid `s_0 < … < s_N` (graded along the joint path's arc length: [`PathPiece::sample`]),
//! widths `Δs_k`; `u_k` is constant on interval `k`, so `x` is linear in `s` there and
//! `x_{k+1} = x_k + 2 u_k Δs_k` exactly. The torques are bounded at both ends and
//! at the midpoint of every interval, both joints (at the midpoint `x = (x_k + x_{k+1})/2`
//! exactly, `x` being linear):
//!
//! $$ \min\; t \quad\text{s.t.}\quad |a_j(s_e)\, u_k + b_j(s_e)\, x(s_e)| \le t, \quad
//!    s_e \in \{s_k,\, \tfrac12 (s_k + s_{k+1}),\, s_{k+1}\},\; j \in \{1, 2\}, $$
//!
//! `x ≥ 0`, and the duration `Σ_k 2Δs_k/(√x_k + √x_{k+1}) ≤ T`, which is exact for piecewise
//! constant `s̈` (the mean speed of an interval is `(ṡ_k + ṡ_{k+1})/2`). It is written with cones:
//! `y_k ≤ √x_k` as `‖(2y_k, x_k − 1)‖ ≤ x_k + 1`, and `w_k (y_k + y_{k+1}) ≥ 2` as
//! `‖(2√2, w_k − y_k − y_{k+1})‖ ≤ w_k + y_k + y_{k+1}`, with `Σ Δs_k\, w_k ≤ T`. Everything is
//! posed in normalised units (`s` in units of the whole path `S`, time in units of `T`, the
//! torque in units of the largest coefficient) so that every number is of order one.
//!
//! Boundary conditions come from the tangents `q'`:
//! - at both ends of the trajectory the joints are at rest: `x = 0` where `q' ≠ 0` (where `q' = 0`
//!   the joints rest whatever `ṡ`, and `x` stays free: a path timed by a rest-to-rest profile has
//!   `q' = 0` at its ends);
//! - between pieces, where `q'` of both sides is non-zero and points the same way, the joint
//!   rates are continuous, `x_R |q'_R|² = x_L |q'_L|²`; at a kink (the tangent turns, e.g. the
//!   paper's phase boundaries) each side with `q' ≠ 0` comes to rest.
//!
//! The piece durations are either kept (each piece `i` takes `T S_i / S`: for a path timed by
//! its local time, the original split) or free (only the total is `T`).
//!
//! ## What is certified
//!
//! Clarabel's dual objective is a lower bound on the optimum of this discrete problem for this
//! path (weak duality, up to the reported dual residual): no timing on this grid has a smaller
//! peak. "Up to the residual" is measurable: a solution that finishes early is slowed to fill its
//! duration, which gives another timing on the grid, and on the paper's path at `N = 200` its
//! discrete peak lies up to 5 × 10⁻⁷ (relative) below the dual bound
//! (`cargo run --release --example retime_paper 200`), so the bound holds to about 10⁻⁶, not to
//! the duality gap. The timed trajectory ([`RetimedTrajectory`]) realises the discrete solution exactly
//! (`s(t)` of piecewise constant `s̈`), so its exact torques equal the program's at the grid
//! nodes; between nodes they differ by the discretisation error, which
//! [`Retiming::remeasure`] measures with the exact engine and which shrinks with `N`.
//!
//! ## Accuracy, and what is left
//!
//! Piecewise constant `s̈` cannot hold the torque at the bound across an interval, which the
//! optimum does on its arcs, so the program's optimum converges to the continuous one at first
//! order in `1/N` (a single joint alone: 0.8 %, 0.4 %, 0.2 % above its closed form at
//! `N = 100, 200, 400`, `tests/retime.rs`). Where the path parameter's own rate vanishes to higher
//! order (a phase timed by its local time and starting at rest has `q' ∝ s²`) the optimal
//! `x ∝ 1/s` is singular and the program so badly scaled that its "solved" optima depend on the
//! solver's settings (by 2 × 10⁻³ with the split free on the paper's path). A three-phase
//! schedule is therefore retimed along its path parametrised by the phases' progress variables
//! ([`retime_schedule`], [`PhasePath`]), on which the joints never stop inside a phase: the
//! bounds then agree to 10⁻⁸ whatever the settings (`tests/retime.rs`). [`retime`] takes any
//! trajectory's own parametrisation.
//!
//! ## References
//! - D. Verscheure, B. Demeulenaere, J. Swevers, J. De Schutter, M. Diehl, *Time-optimal path
//!   tracking for robots: a convex optimization approach*, IEEE Trans. Automatic Control 54
//!   (2009) 2318–2327;
//! - H. Pham and Q.-C. Pham, *A new approach to time-optimal path parameterization based on
//!   reachability analysis* (TOPP-RA), IEEE Trans. Robotics 34 (2018) 645–659;
//! - P. J. Goulart and Y. Chen, *Clarabel: An interior-point solver for conic programs with
//!   quadratic objectives*, arXiv:2405.12762 (2024);
//! - M. S. Lobo, L. Vandenberghe, S. Boyd, H. Lebret, *Applications of second-order cone
//!   programming*, Linear Algebra Appl. 284 (1998) 193–228 (hyperbolic constraints as cones).

mod assembly;
mod phases;
mod problemdata;
mod settings;
mod solution;
mod trajectory;

pub use phases::{retime_schedule, PhasePath};
pub use problemdata::{PathNode, PathPiece, PathProblem};
pub use settings::{RetimeSettings, Split};
pub use solution::{PieceTiming, RetimeSolution, RetimeStatus};
pub use trajectory::{retime, Remeasurement, RetimedTrajectory, Retiming};

use crate::optimize::conic::ConicError;

/// Why a retiming could not be set up. How a solve ended (including infeasibility) is not an
/// error: it is the [`RetimeStatus`] of the solution.
#[derive(Debug, thiserror::Error)]
pub enum RetimeError {
    /// An input has a value the program cannot use.
    #[error("{field} = {value}: {reason}")]
    BadInput {
        /// The input's name, e.g. `duration`.
        field: &'static str,
        /// The value found.
        value: String,
        /// Why it is rejected.
        reason: String,
    },
    /// The path's coefficients are not finite at a grid node.
    #[error("the path is not finite at piece {piece}, s = {s}: {what}")]
    NonFinitePath {
        /// The piece.
        piece: usize,
        /// The path parameter of the node.
        s: f64,
        /// Which quantity.
        what: &'static str,
    },
    /// Clarabel refused the data or the settings.
    #[error(transparent)]
    Solver(#[from] ConicError),
}

/// A [`RetimeError::BadInput`].
fn bad(field: &'static str, value: impl std::fmt::Display, reason: &str) -> RetimeError {
    RetimeError::BadInput { field, value: value.to_string(), reason: reason.to_string() }
}

/// Requires a finite, strictly positive value.
fn positive(field: &'static str, value: f64) -> Result<(), RetimeError> {
    crate::problem::error::not_positive(value).map_or(Ok(()), |reason| Err(bad(field, value, reason)))
}
