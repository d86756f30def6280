//! The Cholesky factor of a symmetric matrix that is banded but for its last row and column:
//! the Newton matrix of the interior-point method, whose control points couple only within a
//! sample's support (ordered time first, so within `(p + 1) J` of each other) and whose peak
//! bound couples with all of them.
//!
//! With `H = [[B, b], [bᵀ, β]]`, `B` banded of half-width `w`: `B = L_B L_Bᵀ` by the banded
//! Cholesky algorithm (`O(n w²)`), `l = L_B⁻¹ b` and `λ = √(β − lᵀl)`, so that
//! `H = [[L_B, 0], [lᵀ, λ]] [[L_B, 0], [lᵀ, λ]]ᵀ`.

use nalgebra::DVector;

/// A symmetric matrix of order `n + 1`: banded of half-width `width` on its first `n` rows and
/// columns, full on its last.
#[derive(Clone, Debug)]
pub(crate) struct Arrow {
    n: usize,
    width: usize,
    /// The lower band: entry `(i, j)`, `i − width ≤ j ≤ i`, at `i (width + 1) + i − j`.
    band: Vec<f64>,
    /// The last column's first `n` entries.
    edge: Vec<f64>,
    /// The last diagonal entry.
    corner: f64,
}

impl Arrow {
    /// Zeros, of order `n + 1` and half-width `width`.
    pub(crate) fn zeros(n: usize, width: usize) -> Arrow {
        Arrow { n, width, band: vec![0.0; n * (width + 1)], edge: vec![0.0; n], corner: 0.0 }
    }

    /// Adds `value` at `(i, j)` and `(j, i)` once (an entry of the lower triangle, `i ≥ j`, with
    /// `n` for the last row); entries above the diagonal are ignored, so that a symmetric sum
    /// given in full counts once. Panics outside the band.
    pub(crate) fn add(&mut self, i: usize, j: usize, value: f64) {
        if i < j {
            return;
        }
        if i == self.n {
            if j == self.n {
                self.corner += value;
            } else {
                self.edge[j] += value;
            }
            return;
        }
        assert!(i - j <= self.width, "entry ({i}, {j}) outside the half-width {}", self.width);
        self.band[i * (self.width + 1) + i - j] += value;
    }

    /// The factor of the matrix with `shift` added to its first `n` diagonal entries; none when
    /// that is not positive definite.
    pub(crate) fn cholesky(&self, shift: f64) -> Option<ArrowCholesky> {
        let (n, w) = (self.n, self.width);
        let stride = w + 1;
        let mut l = self.band.clone();
        for i in 0..n {
            l[i * stride] += shift;
        }
        for i in 0..n {
            let first = i.saturating_sub(w);
            for j in first..=i {
                // L[i][j] = (A[i][j] − Σ_k L[i][k] L[j][k]) / L[j][j], k from max(first, j − w).
                let from = first.max(j.saturating_sub(w));
                let mut sum = l[i * stride + i - j];
                for k in from..j {
                    sum -= l[i * stride + i - k] * l[j * stride + j - k];
                }
                if i == j {
                    if sum.is_nan() || sum <= 0.0 {
                        return None;
                    }
                    l[i * stride] = sum.sqrt();
                } else {
                    l[i * stride + i - j] = sum / l[j * stride];
                }
            }
        }
        let mut factor = ArrowCholesky { n, width: w, band: l, edge: Vec::new(), corner: 0.0 };
        let edge = factor.forward(self.edge.clone());
        let rest = self.corner - edge.iter().map(|x| x * x).sum::<f64>();
        if rest.is_nan() || rest <= 0.0 {
            return None;
        }
        factor.edge = edge;
        factor.corner = rest.sqrt();
        Some(factor)
    }
}

/// The factor `[[L_B, 0], [lᵀ, λ]]` of an [`Arrow`].
#[derive(Clone, Debug)]
pub(crate) struct ArrowCholesky {
    n: usize,
    width: usize,
    band: Vec<f64>,
    edge: Vec<f64>,
    corner: f64,
}

impl ArrowCholesky {
    /// `L_B⁻¹ y`.
    fn forward(&self, mut y: Vec<f64>) -> Vec<f64> {
        let stride = self.width + 1;
        for i in 0..self.n {
            let first = i.saturating_sub(self.width);
            let row = &self.band[i * stride..(i + 1) * stride];
            let sum = y[i] - (first..i).map(|k| row[i - k] * y[k]).sum::<f64>();
            y[i] = sum / row[0];
        }
        y
    }

    /// `L_B⁻ᵀ y`.
    fn backward(&self, mut y: Vec<f64>) -> Vec<f64> {
        let stride = self.width + 1;
        for i in (0..self.n).rev() {
            let last = (i + self.width).min(self.n - 1);
            let sum = y[i] - (i + 1..=last).map(|k| self.band[k * stride + k - i] * y[k]).sum::<f64>();
            y[i] = sum / self.band[i * stride];
        }
        y
    }

    /// `H⁻¹ r` for `r` of order `n + 1`.
    pub(crate) fn solve(&self, r: &DVector<f64>) -> DVector<f64> {
        let n = self.n;
        let y = self.forward(r.as_slice()[..n].to_vec());
        let yt = (r[n] - self.edge.iter().zip(&y).map(|(a, b)| a * b).sum::<f64>()) / self.corner;
        let xt = yt / self.corner;
        let top: Vec<f64> = y.iter().zip(&self.edge).map(|(y, l)| y - l * xt).collect();
        let mut x = self.backward(top);
        x.push(xt);
        DVector::from_vec(x)
    }
}

#[cfg(test)]
mod tests {
    use nalgebra::DMatrix;

    use super::*;
    use crate::numeric::random::SplitMix64;

    /// A random symmetric positive definite arrow matrix, as an [`Arrow`] and densely.
    fn random_arrow(n: usize, width: usize, seed: u64) -> (Arrow, DMatrix<f64>) {
        let mut rng = SplitMix64::new(seed);
        let mut dense = DMatrix::zeros(n + 1, n + 1);
        for i in 0..=n {
            for j in 0..=i {
                if i == n || i - j <= width {
                    let v = rng.uniform(-1.0, 1.0);
                    dense[(i, j)] = v;
                    dense[(j, i)] = v;
                }
            }
        }
        // Diagonally dominant, so positive definite.
        for i in 0..=n {
            dense[(i, i)] = dense.row(i).iter().map(|x| x.abs()).sum::<f64>() + 1.0;
        }
        let mut arrow = Arrow::zeros(n, width);
        for i in 0..=n {
            for j in 0..=n {
                if dense[(i, j)] != 0.0 {
                    arrow.add(i, j, dense[(i, j)]);
                }
            }
        }
        (arrow, dense)
    }

    #[test]
    fn the_arrow_factor_solves_as_the_dense_matrix_does() {
        for (n, width, seed) in [(1, 0, 1), (7, 2, 2), (40, 11, 3), (30, 29, 4)] {
            let (arrow, dense) = random_arrow(n, width, seed);
            let r = DVector::from_fn(n + 1, |i, _| (i as f64 * 0.37).sin());
            let x = arrow.cholesky(0.0).expect("positive definite").solve(&r);
            let residual = (&dense * &x - &r).amax();
            assert!(residual < 1e-12, "n = {n}, width = {width}: residual {residual:.1e}");
        }
    }

    #[test]
    fn an_indefinite_matrix_has_no_factor_until_shifted() {
        let mut a = Arrow::zeros(2, 1);
        a.add(0, 0, 1.0);
        a.add(1, 0, 2.0);
        a.add(1, 1, 1.0);
        a.add(2, 2, 1.0);
        assert!(a.cholesky(0.0).is_none(), "[[1, 2], [2, 1]] is indefinite");
        assert!(a.cholesky(2.0).is_some(), "[[3, 2], [2, 3]] is positive definite");
    }
}
