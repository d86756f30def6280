//! Shape coordinates: the joint angles of every joint of a model at one instant.
//!
//! A model with joints of `n₁, n₂, …` coordinates ([`crate::model::Joint::dof`]) has the shape
//! `q = (q_joint1, q_joint2, …)`, `n = Σ nᵢ` numbers (rad), with rates `q̇` (rad/s) and
//! accelerations `q̈` (rad/s²). Their trajectories are
//! [`crate::engines::shape::ShapeTrajectory`]s.

/// Shape coordinates, rates and accelerations at one instant.
#[derive(Clone, Debug, PartialEq, Default)]
pub struct ShapeState {
    /// `q`, rad.
    pub q: Vec<f64>,
    /// `q̇`, rad/s.
    pub qd: Vec<f64>,
    /// `q̈`, rad/s².
    pub qdd: Vec<f64>,
}

impl ShapeState {
    /// Number of coordinates.
    pub fn len(&self) -> usize {
        self.q.len()
    }

    /// Whether there are none.
    pub fn is_empty(&self) -> bool {
        self.q.is_empty()
    }

    /// The coordinates `range` of this state (one joint's).
    pub fn slice(&self, range: std::ops::Range<usize>) -> (&[f64], &[f64], &[f64]) {
        (&self.q[range.clone()], &self.qd[range.clone()], &self.qdd[range])
    }

    /// The same state with its rates and accelerations scaled by `k` (`k = 0`: held still).
    pub fn with_rates_scaled(&self, k: f64) -> ShapeState {
        ShapeState {
            q: self.q.clone(),
            qd: self.qd.iter().map(|v| v * k).collect(),
            qdd: self.qdd.iter().map(|v| v * k * k).collect(),
        }
    }
}
