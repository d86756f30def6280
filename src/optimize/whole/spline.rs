//! Clamped B-spline joint trajectories on `[0, T]`, the variables of the whole-manoeuvre
//! optimisation.
//!
//! One curve per shape coordinate: two on the universal and no-twist joints, three on the
//! spherical one ([`crate::model::Joint::dof`]), four on a cat with a tail or legs, up to six. Each coordinate is
//! `q_j(t) = Σ_i c_{j,i} N_{i,p}(t)` with `n` control points, degree `p` and the clamped uniform
//! knot vector (`p + 1` knots at `0` and at `T`, `n − p − 1` equally spaced
//! inside), so that `q(0) = c_0`, `q̇(0) = p (c_1 − c_0)/u_{p+1}` and likewise at `T`. Fixing the
//! first and last two control points at zero makes the cat straight and at rest at both ends;
//! fixing three also zeroes the end accelerations (and so the end torques).
//!
//! Basis functions by the Cox–de Boor recurrence
//! `N_{i,d} = (t − u_i)/(u_{i+d} − u_i) N_{i,d−1} + (u_{i+d+1} − t)/(u_{i+d+1} − u_{i+1}) N_{i+1,d−1}`
//! and their derivatives by `N'_{i,d} = d (N_{i,d−1}/(u_{i+d} − u_i) − N_{i+1,d−1}/(u_{i+d+1} − u_{i+1}))`
//! (0/0 read as 0), applied twice for `N''`. A knot span is one piece of the [`Trajectory`]:
//! `q⁽ᵖ⁾` jumps at knots, so engines never step across one.
//!
//! ## References
//! - C. de Boor, *A Practical Guide to Splines* (rev. ed., Springer 2001), ch. IX–X;
//! - L. Piegl, W. Tiller, *The NURBS Book* (2nd ed., 1997), §2.2–2.3.

use nalgebra::{DMatrix, DVector};
use serde::Serialize;

use crate::engines::shape::ShapeTrajectory;
use crate::model::shape::ShapeState;
use crate::schedule::{JointState, Trajectory};

/// Every joint coordinate's clamped B-spline over the whole fall.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct BSpline {
    /// Degree `p`.
    pub degree: usize,
    /// Knot vector `u_0 … u_{n+p}`, s.
    pub knots: Vec<f64>,
    /// Control points `c_{j,i}` of coordinate `j`, rad: one list per coordinate, all as long.
    pub coefficients: Vec<Vec<f64>>,
}

/// The highest degree a [`BSpline`] may have: its [`Basis`] lives on the stack, in arrays of
/// `MAX_DEGREE + 1` (the optimiser's splines are cubic, [`crate::problem::whole::WholeSettings::DEGREE`]).
pub const MAX_DEGREE: usize = 7;

/// The values of the `p + 1` non-vanishing functions at one instant (or of their derivatives),
/// kept on the stack: the basis is evaluated at every step of every integration of a spline, and
/// a heap allocation per list cost more than the arithmetic. Reads as a slice of `p + 1`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BasisRow {
    len: usize,
    /// The values, then zeros.
    data: [f64; MAX_DEGREE + 1],
}

impl std::ops::Deref for BasisRow {
    type Target = [f64];
    fn deref(&self) -> &[f64] {
        &self.data[..self.len]
    }
}

impl<'a> IntoIterator for &'a BasisRow {
    type Item = &'a f64;
    type IntoIter = std::slice::Iter<'a, f64>;
    fn into_iter(self) -> Self::IntoIter {
        self.data[..self.len].iter()
    }
}

/// The basis functions that do not vanish at one instant: `N_{first+k}` and its first two
/// derivatives for `k = 0..=p`.
#[derive(Clone, Debug, PartialEq)]
pub struct Basis {
    /// Index of the first non-vanishing function.
    pub first: usize,
    /// `[N, N', N'']` of the `p + 1` functions, 1, 1/s, 1/s².
    pub values: [BasisRow; 3],
}

impl BSpline {
    /// The straight cat at rest on a two-coordinate joint: `n` zero control points of degree `p`
    /// on `[0, duration]` per coordinate (more coordinates: [`BSpline::with_joints`]).
    /// Needs `n ≥ p + 1`, `p ≥ 1` and a positive duration (checked by the settings).
    ///
    /// # Panics
    /// If `degree` exceeds [`MAX_DEGREE`] (a programming error: the degree is the crate's
    /// constant, never a user's input).
    pub fn zero(duration: f64, control_points: usize, degree: usize) -> Self {
        assert!(degree <= MAX_DEGREE, "a B-spline of degree {degree} > {MAX_DEGREE}");
        let spans = control_points - degree;
        let mut knots = vec![0.0; degree + 1];
        knots.extend((1..spans).map(|k| duration * k as f64 / spans as f64));
        knots.extend(std::iter::repeat_n(duration, degree + 1));
        Self { degree, knots, coefficients: vec![vec![0.0; control_points]; 2] }
    }

    /// The same curves with `joints` coordinates: those added held at zero, those beyond dropped.
    pub fn with_joints(mut self, joints: usize) -> Self {
        let n = self.control_points();
        self.coefficients.resize(joints, vec![0.0; n]);
        self
    }

    /// Number of shape coordinates (curves).
    pub fn joints(&self) -> usize {
        self.coefficients.len()
    }

    /// Number of control points per joint.
    pub fn control_points(&self) -> usize {
        self.coefficients[0].len()
    }

    /// Number of knot spans (pieces).
    pub fn spans(&self) -> usize {
        self.control_points() - self.degree
    }

    /// Start and end of span `s`, s.
    pub fn span_bounds(&self, s: usize) -> (f64, f64) {
        (self.knots[self.degree + s], self.knots[self.degree + s + 1])
    }

    /// The widest knot span, s.
    pub fn widest_span(&self) -> f64 {
        (0..self.spans()).map(|s| self.span_bounds(s)).map(|(a, b)| b - a).fold(0.0, f64::max)
    }

    /// `per_widest` shared out by width: `per_widest` on the widest span, proportionally fewer
    /// (at least `least`) on span `s` of a spline whose widest span is `widest` s wide (the same
    /// count on every span of uniform knots).
    pub fn by_width(&self, s: usize, widest: f64, per_widest: usize, least: usize) -> usize {
        let (a, b) = self.span_bounds(s);
        ((per_widest as f64 * (b - a) / widest).round() as usize).clamp(least.min(per_widest), per_widest)
    }

    /// Total duration, s.
    pub fn duration(&self) -> f64 {
        self.knots[self.knots.len() - 1]
    }

    /// The same joint path traversed `factor` times slower (`factor > 0`): every knot scaled,
    /// the control points kept, so `q̇` scales as `1/factor` and `q̈` as `1/factor²`.
    pub fn stretched(&self, factor: f64) -> Self {
        Self { knots: self.knots.iter().map(|u| u * factor).collect(), ..self.clone() }
    }

    /// The span holding `t` (the later one at an inner knot).
    pub fn span_of(&self, t: f64) -> usize {
        let spans = self.spans();
        (0..spans).rev().find(|&s| t >= self.span_bounds(s).0).unwrap_or(0)
    }

    /// The non-vanishing basis functions and their derivatives at `t` in span `s`.
    pub fn basis(&self, s: usize, t: f64) -> Basis {
        let p = self.degree;
        let mu = p + s;
        let u = &self.knots[mu - p..=mu + p + 1];
        let ratio = |a: f64, b: f64| if b > 0.0 { a / b } else { 0.0 };
        // levels[d][j] = N_{mu−d+j, d}(t), j = 0..=d, in one triangular table; `u[i]` below is
        // the knot `u_{mu−p+i}`, so the function N_{mu−d+j} starts at `u[p−d+j]`.
        let mut levels = [[0.0; MAX_DEGREE + 1]; MAX_DEGREE + 1];
        levels[0][0] = 1.0;
        for d in 1..=p {
            let (done, rest) = levels.split_at_mut(d);
            let (prev, level) = (&done[d - 1], &mut rest[0]);
            for (j, value) in level[..=d].iter_mut().enumerate() {
                let i = p - d + j;
                let left = if j >= 1 { ratio(t - u[i], u[i + d] - u[i]) * prev[j - 1] } else { 0.0 };
                let right = if j < d { ratio(u[i + d + 1] - t, u[i + d + 1] - u[i + 1]) * prev[j] } else { 0.0 };
                *value = left + right;
            }
        }
        // The derivative of degree-d functions from a list over degree d − 1 (linear, so it
        // also maps derivatives to second derivatives).
        let differentiate = |d: usize, prev: &[f64; MAX_DEGREE + 1]| -> [f64; MAX_DEGREE + 1] {
            let mut out = [0.0; MAX_DEGREE + 1];
            for (j, value) in out[..=d].iter_mut().enumerate() {
                let i = p - d + j;
                let left = if j >= 1 { ratio(prev[j - 1], u[i + d] - u[i]) } else { 0.0 };
                let right = if j < d { ratio(prev[j], u[i + d + 1] - u[i + 1]) } else { 0.0 };
                *value = d as f64 * (left - right);
            }
            out
        };
        let row = |data: [f64; MAX_DEGREE + 1]| BasisRow { len: p + 1, data };
        let first_derivative = if p >= 1 { differentiate(p, &levels[p - 1]) } else { [0.0; MAX_DEGREE + 1] };
        let second_derivative =
            if p >= 2 { differentiate(p, &differentiate(p - 1, &levels[p - 2])) } else { [0.0; MAX_DEGREE + 1] };
        Basis { first: mu - p, values: [row(levels[p]), row(first_derivative), row(second_derivative)] }
    }

    /// `[q, q̇, q̈]` of the first `N` coordinates from a basis already evaluated at an instant
    /// (zero beyond the spline's own).
    pub fn values<const N: usize>(&self, basis: &Basis) -> [[f64; N]; 3] {
        let mut out = [[0.0; N]; 3];
        for j in 0..N.min(self.joints()) {
            let c = &self.coefficients[j][basis.first..];
            for (d, row) in out.iter_mut().enumerate() {
                row[j] = basis.values[d].iter().zip(c).map(|(n, c)| n * c).sum::<f64>();
            }
        }
        out
    }

    /// The joint state of a two-coordinate spline from a basis already evaluated at an instant.
    ///
    /// # Panics
    /// On a spline of another number of coordinates (a programming error: the two-coordinate
    /// consumers would drop the others silently).
    pub fn state_from(&self, basis: &Basis) -> JointState {
        assert_eq!(self.joints(), 2, "a two-coordinate state of a spline of {} coordinates", self.joints());
        let [q, qd, qdd] = self.values::<2>(basis);
        JointState { q, qd, qdd }
    }

    /// The joint state of a two-coordinate spline at global time `t` ([`BSpline::state_from`]).
    pub fn state(&self, t: f64) -> JointState {
        let s = self.span_of(t);
        self.state_from(&self.basis(s, t))
    }

    /// Every coordinate's angle, rate and acceleration from a basis already evaluated at an
    /// instant.
    pub fn shape_from(&self, basis: &Basis) -> ShapeState {
        let sum = |j: usize, d: usize| {
            let c = &self.coefficients[j][basis.first..];
            basis.values[d].iter().zip(c).map(|(n, c)| n * c).sum::<f64>()
        };
        let all = |d: usize| (0..self.joints()).map(|j| sum(j, d)).collect();
        ShapeState { q: all(0), qd: all(1), qdd: all(2) }
    }

    /// Every coordinate's angle, rate and acceleration at global time `t` ([`BSpline::shape_from`]).
    pub fn shape(&self, t: f64) -> ShapeState {
        self.shape_from(&self.basis(self.span_of(t), t))
    }

    /// Every coordinate's angle at global time `t`, rad.
    pub fn angles(&self, t: f64) -> Vec<f64> {
        self.shape(t).q
    }

    /// The same curves fitted on `control_points` control points ([`BSpline::fit`]).
    pub fn refit(&self, control_points: usize, fixed: usize) -> Self {
        Self::fit(self.duration(), control_points, self.degree, fixed, self.joints(), |t| self.angles(t))
    }

    /// The same curve with `knot` inserted (Boehm's algorithm; de Boor ch. XI): one more control
    /// point per joint, each new one `α c_i + (1 − α) c_{i−1}` with
    /// `α = (u − u_i)/(u_{i+p} − u_i)` for the `p` points whose support holds `u`. A knot outside
    /// the open interval `(0, T)` is ignored.
    pub fn with_knot(&self, knot: f64) -> Self {
        let p = self.degree;
        if !(knot > 0.0 && knot < self.duration()) {
            return self.clone();
        }
        // u_k ≤ knot < u_{k+1}
        let k = p + self.span_of(knot);
        let u = &self.knots;
        let coefficients = self.coefficients.iter().map(|c| {
            let mut out = Vec::with_capacity(c.len() + 1);
            out.extend_from_slice(&c[..=k - p]);
            for i in k - p + 1..=k {
                let alpha = (knot - u[i]) / (u[i + p] - u[i]);
                out.push(alpha * c[i] + (1.0 - alpha) * c[i - 1]);
            }
            out.extend_from_slice(&c[k..]);
            out
        });
        let coefficients = coefficients.collect();
        let mut knots = self.knots.clone();
        knots.insert(k + 1, knot);
        Self { degree: p, knots, coefficients }
    }

    /// The least-squares fit of `target(t)` (the `joints` coordinates' angles, rad) on `20` points
    /// per span, with the first and last `fixed` control points of each coordinate held at zero.
    pub fn fit(
        duration: f64,
        control_points: usize,
        degree: usize,
        fixed: usize,
        joints: usize,
        target: impl Fn(f64) -> Vec<f64>,
    ) -> Self {
        let spline = Self::zero(duration, control_points, degree).with_joints(joints);
        let points = 20 * spline.spans();
        let times = (0..=points).map(|k| duration * k as f64 / points as f64);
        spline.least_squares(fixed, times, target)
    }

    /// The least-squares fit of `target(t)` (the `joints` coordinates' angles, rad) on this
    /// spline's knots, uniform or not, at 20 points in every span, with the first and last
    /// `fixed` control points of each coordinate held at zero. `target` is called once per
    /// sample, in increasing time (a target that carries state along the path, as an unwrapped
    /// angle, may rely on it).
    pub fn fit_on_knots(&self, fixed: usize, joints: usize, target: impl Fn(f64) -> Vec<f64>) -> Self {
        let zeros = vec![vec![0.0; self.control_points()]; joints];
        let template = Self { degree: self.degree, knots: self.knots.clone(), coefficients: zeros };
        let times = (0..self.spans())
            .flat_map(|s| {
                let (a, b) = self.span_bounds(s);
                (0..20).map(move |k| a + (b - a) * k as f64 / 20.0)
            })
            .chain(std::iter::once(self.duration()));
        template.least_squares(fixed, times, target)
    }

    /// This spline's knots with the control points fitted to `target` at `times` by least
    /// squares, the first and last `fixed` of each coordinate held at zero (the others' values
    /// are replaced); `target` is called once per time, in their order.
    ///
    /// # Panics
    /// If the normal matrix is not positive definite: the times must put samples in the support
    /// of every free function (both callers sample every span), a programming error otherwise.
    fn least_squares(
        mut self,
        fixed: usize,
        times: impl Iterator<Item = f64>,
        target: impl Fn(f64) -> Vec<f64>,
    ) -> Self {
        let (control_points, degree, joints) = (self.control_points(), self.degree, self.joints());
        let free = control_points.saturating_sub(2 * fixed);
        if free == 0 {
            return self;
        }
        let spline = &self;
        let mut normal = DMatrix::<f64>::zeros(free, free);
        let mut rhs = vec![DVector::<f64>::zeros(free); joints];
        for t in times {
            let basis = spline.basis(spline.span_of(t), t);
            let y = target(t);
            let cols: Vec<(usize, f64)> = (0..=degree)
                .filter_map(|m| {
                    let i = basis.first + m;
                    (i >= fixed && i < control_points - fixed).then(|| (i - fixed, basis.values[0][m]))
                })
                .collect();
            for &(a, na) in &cols {
                for &(b, nb) in &cols {
                    normal[(a, b)] += na * nb;
                }
                for (rhs, y) in rhs.iter_mut().zip(&y) {
                    rhs[a] += na * y;
                }
            }
        }
        // The collocation matrix has full column rank (every free function has support holding
        // sample points), so the normal matrix is positive definite.
        let ch = normal.cholesky().expect("a fit's samples cover the support of every free function");
        for (coefficients, rhs) in self.coefficients.iter_mut().zip(&rhs) {
            coefficients[fixed..fixed + free].copy_from_slice(ch.solve(rhs).as_slice());
        }
        self
    }
}

/// A two-coordinate spline as a schedule ([`BSpline::state_from`] refuses any other).
impl Trajectory for BSpline {
    fn piece_durations(&self) -> Vec<f64> {
        (0..self.spans()).map(|s| self.span_bounds(s)).map(|(a, b)| b - a).collect()
    }

    fn piece_state(&self, piece: usize, s: f64) -> JointState {
        self.state_from(&self.piece_basis(piece, s))
    }
}

impl BSpline {
    /// The basis at local time `s` of span `piece` (clamped to its end).
    fn piece_basis(&self, piece: usize, s: f64) -> Basis {
        let (a, b) = self.span_bounds(piece);
        self.basis(piece, (a + s).min(b))
    }
}

/// A spline of any number of coordinates as a shape trajectory (each knot span a piece), as the
/// general core runs it ([`crate::engines::models`]).
#[derive(Clone, Copy, Debug)]
pub struct SplineShape<'a>(pub &'a BSpline);

impl ShapeTrajectory for SplineShape<'_> {
    fn piece_durations(&self) -> Vec<f64> {
        Trajectory::piece_durations(self.0)
    }
    fn piece_shape(&self, piece: usize, s: f64) -> ShapeState {
        self.0.shape_from(&self.0.piece_basis(piece, s))
    }
    fn acceleration_jumps(&self, _piece: usize) -> Vec<f64> {
        Vec::new()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    fn sample() -> BSpline {
        let mut s = BSpline::zero(1.7, 9, 3);
        s.coefficients = vec![
            vec![0.0, 0.0, 0.4, -0.3, 1.1, 0.2, -0.5, 0.0, 0.0],
            vec![0.0, 0.0, -0.2, 0.9, 0.1, -0.7, 0.3, 0.0, 0.0],
        ];
        s
    }

    #[test]
    fn basis_is_a_partition_of_unity_and_ends_rest() {
        let s = sample();
        for k in 0..=50 {
            let t = 1.7 * k as f64 / 50.0;
            let b = s.basis(s.span_of(t), t);
            assert_relative_eq!(b.values[0].iter().sum::<f64>(), 1.0, epsilon = 1e-14);
            assert_relative_eq!(b.values[1].iter().sum::<f64>(), 0.0, epsilon = 1e-12);
            assert_relative_eq!(b.values[2].iter().sum::<f64>(), 0.0, epsilon = 1e-10);
        }
        for t in [0.0, 1.7] {
            let st = s.state(t);
            for j in 0..2 {
                assert_relative_eq!(st.q[j], 0.0, epsilon = 1e-15);
                assert_relative_eq!(st.qd[j], 0.0, epsilon = 1e-13);
            }
        }
    }

    #[test]
    fn derivatives_match_central_differences() {
        // Step 1e-5 inside a span: truncation ~1e-10·q''', round-off ~1e-16/1e-5: 1e-7 covers it.
        let s = sample();
        let h = 1e-5;
        for t in [0.13, 0.5, 0.91, 1.33] {
            let (a, b, c) = (s.state(t - h), s.state(t), s.state(t + h));
            for j in 0..2 {
                assert_relative_eq!(b.qd[j], (c.q[j] - a.q[j]) / (2.0 * h), epsilon = 1e-7);
                assert_relative_eq!(b.qdd[j], (c.qd[j] - a.qd[j]) / (2.0 * h), epsilon = 1e-6);
            }
        }
    }

    #[test]
    fn an_inserted_knot_leaves_the_curve_as_it_is() {
        let s = sample();
        let finer = s.with_knot(0.61).with_knot(0.61 + 1e-3).with_knot(1.69);
        assert_eq!(finer.control_points(), s.control_points() + 3);
        assert_eq!(finer.spans(), s.spans() + 3);
        for k in 0..=170 {
            let t = 1.7 * k as f64 / 170.0;
            let (a, b) = (s.state(t), finer.state(t));
            for j in 0..2 {
                assert_relative_eq!(a.q[j], b.q[j], epsilon = 1e-13);
                assert_relative_eq!(a.qd[j], b.qd[j], epsilon = 1e-12);
                assert_relative_eq!(a.qdd[j], b.qdd[j], epsilon = 1e-10);
            }
        }
    }

    #[test]
    fn fit_reproduces_a_spline() {
        let s = sample();
        let fit = s.refit(9, 2);
        for j in 0..2 {
            for (a, b) in fit.coefficients[j].iter().zip(&s.coefficients[j]) {
                assert_relative_eq!(a, b, epsilon = 1e-10);
            }
        }
    }
}
