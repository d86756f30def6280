//! Which directions of the final orientation error the controls can move.
//!
//! The orientation error `e ∈ ℝ³` moves by `δe = J δ` for a step `δ` on the control points. On
//! the paper's cat `J` has full rank: every direction of `e` can be reached. On a symmetric cat
//! it need not: with equal halves on the no-twist joint the cat cannot swing its spine, the
//! swing's rows of `J` are round-off (~10⁻¹² of the twist's) and the error there is round-off
//! too. Asking for `e + Jδ = 0` in such a direction is asking for a huge step to cancel noise:
//! Clarabel reports the subproblem primal infeasible at every trust radius, and a Newton step
//! `δ = −Jᵀ(JJᵀ)⁻¹e` is useless. Both therefore work on the eigenvectors `u` of `JJᵀ` whose
//! eigenvalues are at least [`RANK_RATIO`] of the largest (singular values of `J` above `10⁻⁶`
//! of the largest), and leave the others out: there `e` is noise the controls cannot move.
//!
//! Where `J` has full rank the rows are `J`'s own, so the paper's cat sees the same numbers as
//! before this distinction was made.

use nalgebra::{DMatrix, Matrix3, Vector3};

/// The ratio of the smallest to the largest eigenvalue of `JJᵀ` below which a direction counts
/// as out of the controls' reach (module docs).
pub const RANK_RATIO: f64 = 1e-12;

/// The reachable directions of the orientation error.
#[derive(Clone, Debug, PartialEq)]
pub enum Reach {
    /// `J` has full rank: every direction, in `J`'s own rows.
    Full,
    /// `J` is rank-deficient: the unit eigenvectors of `JJᵀ` that the controls reach, each with
    /// its eigenvalue (none when `J` vanishes).
    Directions(Vec<(Vector3<f64>, f64)>),
}

impl Reach {
    /// The reach of a 3 × n Jacobian.
    pub fn of(jacobian: &DMatrix<f64>) -> Reach {
        let jjt: Matrix3<f64> = Matrix3::from_fn(|a, b| jacobian.row(a).dot(&jacobian.row(b)));
        let eigen = jjt.symmetric_eigen();
        let largest = eigen.eigenvalues.amax();
        let smallest = eigen.eigenvalues.iter().fold(f64::INFINITY, |m, x| m.min(x.abs()));
        if smallest > RANK_RATIO * largest {
            return Reach::Full;
        }
        let kept = eigen
            .eigenvalues
            .iter()
            .enumerate()
            .filter(|&(_, l)| largest > 0.0 && *l > RANK_RATIO * largest)
            .map(|(i, &l)| (eigen.eigenvectors.column(i).into_owned(), l))
            .collect();
        Reach::Directions(kept)
    }

    /// The linearised constraint `e + Jδ = 0` restricted to the reachable directions, as rows
    /// `(a, b)` meaning `a · δ = b`: `J`'s rows and `−e` when `J` has full rank, otherwise
    /// `uᵀJ` and `−uᵀe` for each reachable `u`.
    pub fn constraint_rows(&self, jacobian: &DMatrix<f64>, error: &Vector3<f64>) -> Vec<(Vec<f64>, f64)> {
        let n = jacobian.ncols();
        match self {
            Reach::Full => (0..3).map(|i| ((0..n).map(|v| jacobian[(i, v)]).collect(), -error[i])).collect(),
            Reach::Directions(dirs) => dirs
                .iter()
                .map(|(u, _)| ((0..n).map(|v| (0..3).map(|i| u[i] * jacobian[(i, v)]).sum()).collect(), -u.dot(error)))
                .collect(),
        }
    }

    /// `y = (JJᵀ)⁻¹ e` of the minimum-norm Newton step `δ = −Jᵀ y`: the inverse when `J` has
    /// full rank, else the pseudo-inverse on the reachable directions; none when `JJᵀ` cannot
    /// be inverted or `J` vanishes.
    pub fn newton_multipliers(&self, jacobian: &DMatrix<f64>, error: &Vector3<f64>) -> Option<Vector3<f64>> {
        match self {
            Reach::Full => {
                let jjt: Matrix3<f64> = Matrix3::from_fn(|a, b| jacobian.row(a).dot(&jacobian.row(b)));
                jjt.try_inverse().map(|inv| inv * error)
            }
            Reach::Directions(dirs) if dirs.is_empty() => None,
            Reach::Directions(dirs) => Some(dirs.iter().map(|(u, l)| u * (u.dot(error) / l)).sum()),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_full_rank_jacobian_keeps_its_own_rows_and_inverse() {
        let j = DMatrix::from_row_slice(3, 4, &[1.0, 0.0, 2.0, 0.0, 0.0, 3.0, 0.0, 1.0, 1.0, 1.0, 0.0, 0.0]);
        let e = Vector3::new(0.1, -0.2, 0.3);
        let reach = Reach::of(&j);
        assert_eq!(reach, Reach::Full);
        let rows = reach.constraint_rows(&j, &e);
        assert_eq!(rows[1], (vec![0.0, 3.0, 0.0, 1.0], 0.2));
        // The Newton step δ = −Jᵀy cancels e exactly.
        let y = reach.newton_multipliers(&j, &e).unwrap();
        let moved = e - &j * (j.transpose() * y);
        assert!(moved.norm() < 1e-14, "{moved}");
    }

    #[test]
    fn an_unreachable_direction_is_left_out_of_the_rows_and_the_step() {
        // Row 3 is round-off (1e-9 of the others): the controls cannot move e_z.
        let j = DMatrix::from_row_slice(3, 3, &[1.0, 0.5, 0.0, 0.0, 2.0, 1.0, 1e-9, 0.0, 0.0]);
        let e = Vector3::new(0.1, -0.2, 1e-10);
        let reach = Reach::of(&j);
        let Reach::Directions(dirs) = &reach else { panic!("expected a rank-deficient reach") };
        assert_eq!(dirs.len(), 2);
        let rows = reach.constraint_rows(&j, &e);
        assert_eq!(rows.len(), 2);
        // A step meeting the two rows cancels e in the reachable plane (x and y), within round-off.
        let y = reach.newton_multipliers(&j, &e).unwrap();
        let step = -(j.transpose() * y);
        for (a, b) in &rows {
            let lhs: f64 = a.iter().zip(step.iter()).map(|(a, d)| a * d).sum();
            assert!((lhs - b).abs() < 1e-12, "{lhs} against {b}");
        }
        let moved = e + &j * &step;
        assert!(moved.x.abs() < 1e-12 && moved.y.abs() < 1e-12, "{moved}");
        // The step stays of the size of e, instead of the 1e-10/1e-9 a full inverse would need.
        assert!(step.norm() < 1.0, "step {}", step.norm());
    }

    #[test]
    fn a_vanishing_jacobian_has_no_newton_step() {
        let j = DMatrix::zeros(3, 2);
        let reach = Reach::of(&j);
        assert_eq!(reach, Reach::Directions(Vec::new()));
        assert!(reach.newton_multipliers(&j, &Vector3::new(1.0, 0.0, 0.0)).is_none());
        assert!(reach.constraint_rows(&j, &Vector3::new(1.0, 0.0, 0.0)).is_empty());
    }
}
