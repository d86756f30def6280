//! The conic layer: every optimiser's call to Clarabel, and nothing of what they optimise.
//!
//! Each optimiser here (the profile QP, the refinement's linearised step, the retiming, the
//! whole manoeuvre's subproblems) poses its program in Clarabel's standard form
//!
//! $$
//! \min_{x \in \mathbb{R}^n}\; \tfrac12 x^{\mathsf T} P x + q^{\mathsf T} x
//! \quad\text{s.t.}\quad A x + s = b,\quad s \in \mathcal{K}
//!     = \{0\}^{m_1} \times \mathbb{R}_+^{m_2} \times \mathrm{SOC}(3)^{m_3},
//! $$
//!
//! `P` symmetric positive semidefinite (Clarabel takes its upper triangle), `\{0\}` the zero cone
//! of the equalities, `\mathbb{R}_+` the nonnegative cone of the inequalities, `\mathrm{SOC}(3)`
//! the second-order cone `\{(t, u) : \|u\|_2 \le t\}`, `u ∈ \mathbb{R}^2`, of the retiming's
//! rows (`Y ≤ √X` and `W ≥ 2/(Y_k + Y_{k+1})`). Every program is normalised by its caller so
//! that its numbers are of order one; the layer holds no units.
//!
//! What it holds (the crate-internal items, which the optimisers build on, unlinked):
//! - [`QpSettings`]: how hard Clarabel (version 0.11) works, with the defaults in one place;
//! - `solve_clarabel`: the one call to Clarabel (first without iterative refinement of the KKT
//!   solves, again with it only when that ends short of a full answer);
//! - `Assembly` and `Rows`: the sparse data, built from triplets and joined once into one
//!   `CscMatrix` per matrix (`from_triplets`, Clarabel's constructor entry for entry, faster),
//!   with `Fold` to solve on a subspace that holds an optimum and `active_sides` to leave out
//!   rows of a minimax epigraph that cannot bind, and `Assembly::solve_by_active_set`, which
//!   answers a QP with a dense `P` whose binding inequalities are bounds on single variables by
//!   its KKT system on an active set of bounds, exactly, where Clarabel would factor the dense
//!   block at every interior-point iteration;
//! - [`QpStatus`] and [`SolveInfo`]: how a solve ended and Clarabel's account of it;
//! - [`ConicError`]: why a program could not be set up.
//!
//! ## Status, not error
//!
//! How a solve ended is a status in the result, never an `Err`: [`QpStatus`] is Clarabel's
//! `SolverStatus` one for one (solved, almost solved, primal or dual infeasible to full or reduced
//! accuracy, the iteration or time limit, numerical error, insufficient progress, a callback),
//! and [`QpStatus::is_solved`] accepts the reduced-accuracy solution too. An `Err`
//! ([`ConicError`]) means that the program was never solved: an input it cannot use, or
//! settings or data that Clarabel refused.
//!
//! This layer imports nothing from the optimisers above it.
//!
//! ## References
//! - P. J. Goulart and Y. Chen, *Clarabel: An interior-point solver for conic programs with
//!   quadratic objectives*, arXiv:2405.12762 (2024).

mod assembly;
mod csc;
mod error;
mod settings;
mod solution;
mod solve;

pub(crate) use assembly::{active_sides, Assembly, Fold, Rows};
pub(crate) use csc::from_triplets;
pub use error::ConicError;
pub(crate) use error::{bad, positive, positive_opt};
pub use settings::QpSettings;
pub use solution::{QpStatus, SolveInfo};
pub(crate) use solve::solve_clarabel;
