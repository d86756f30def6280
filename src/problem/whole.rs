//! Settings of the whole-manoeuvre optimisation (`[optimize.whole]` in a problem file), with
//! their defaults in one place; the optimiser is [`crate::optimize::whole`].

use serde::{Deserialize, Serialize};

use super::error::{bad, positive, ProblemError};

/// What the optimisation minimises.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Objective {
    /// The peak motor torque `max_t max_j |τ_j(t)|`, N·m.
    Peak,
    /// The effort `∫ τ·τ dt`, N²·m²·s.
    Energy,
    /// The least fall time within the motors' limits (`[actuator]`), s: the least drop height
    /// `g T²/2`. The path is optimised for its shape; its duration is the result.
    MinTime,
}

impl Objective {
    /// The kebab-case name used in problem files.
    pub fn name(self) -> &'static str {
        match self {
            Objective::Peak => "peak",
            Objective::Energy => "energy",
            Objective::MinTime => "min-time",
        }
    }
}

/// A start of the optimisation: a library schedule fitted to the spline. None of them
/// presupposes the answer's shape; each is the problem's manoeuvre (its bend, phases, profile)
/// with the circulation calibrated so that the exact engine turns it by π.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum StartKind {
    /// The paper's joint-circle schedule.
    Paper,
    /// Its mirror image `q2 → −q2`, which twists the other way.
    PaperMirrored,
    /// The cone path (constant bend) with the cycloidal profile.
    Cone,
    /// Its mirror image.
    ConeMirrored,
}

impl StartKind {
    /// The kebab-case name used in problem files.
    pub fn name(self) -> &'static str {
        match self {
            StartKind::Paper => "paper",
            StartKind::PaperMirrored => "paper-mirrored",
            StartKind::Cone => "cone",
            StartKind::ConeMirrored => "cone-mirrored",
        }
    }
}

/// The method of the least-peak stage.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Method {
    /// The interior point beyond two motors, where it is 5 to 11 times faster and ends lower, or
    /// converged where the trust region stops at its budget; the trust region on two, where it is
    /// within 2 s and the interior point's refinement can cycle (unequal halves; README, "More
    /// motors").
    #[default]
    Auto,
    /// Successive convexification in a trust region, Clarabel's subproblems.
    TrustRegion,
    /// The primal-dual interior-point method with the torques' exact curvature, wherever it
    /// applies (ideal motors, no spin, no bend limit); the trust-region loop elsewhere.
    InteriorPoint,
}

impl Method {
    /// The kebab-case name used in problem files.
    pub fn name(self) -> &'static str {
        match self {
            Method::Auto => "auto",
            Method::TrustRegion => "trust-region",
            Method::InteriorPoint => "interior-point",
        }
    }

    /// Whether the least peak of a cat of `motors` motors is the interior-point method's (where
    /// it applies).
    pub fn interior_point(self, motors: usize) -> bool {
        match self {
            Method::Auto => motors > 2,
            Method::TrustRegion => false,
            Method::InteriorPoint => true,
        }
    }
}

/// Settings of the whole-manoeuvre optimisation.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct WholeSettings {
    /// What to minimise.
    pub objective: Objective,
    /// The method of the least-peak stage (the energy's stages and every stage with motor
    /// limits, spin or a bend limit are the trust-region loop's).
    pub method: Method,
    /// Smallest angle allowed between the halves (180 = straight), degrees; none when absent.
    pub min_angle_deg: Option<f64>,
    /// Bound on `|q1|` and `|q2|`, degrees, imposed on the control points (so on the whole
    /// curve, by the convex-hull property); none when absent. Beyond two motors (the library's
    /// [`crate::optimize::whole::WholeCat::Spherical`] and [`crate::optimize::whole::WholeCat::Appended`])
    /// it bounds every coordinate alike: the spherical joint's twist and a tail's angles too
    /// (nothing keeps a tail from passing through the rear half), and the legs' swing where it is
    /// below their own 90° fold (the smaller of the two limits holds).
    pub joint_limit_deg: Option<f64>,
    /// Control points per joint, ends included.
    pub control_points: usize,
    /// Control points of a first, coarse energy solve whose optimum starts the fine one (a coarse
    /// spline has fewer poor local optima); none to start on the fine spline directly.
    pub coarse_control_points: Option<usize>,
    /// Whether the joint accelerations (and so the torques) also vanish at both ends.
    pub zero_end_acceleration: bool,
    /// Torque (and bend) samples per knot span for the peak objective.
    pub samples_per_span: usize,
    /// Rounds of knot refinement where a torque switches, after the solve on the uniform knots
    /// (objectives `peak` and `min-time`): each round splits every span across which a torque
    /// swings by more than half the peak, and its neighbours, into four, and solves again from
    /// the same curve; 0 solves on the uniform knots alone.
    pub switch_refinements: usize,
    /// Magnus steps per knot span in the optimisation loop (the final flip is re-measured by
    /// [`crate::engines::exact::flip`] to the requested tolerance).
    pub steps_per_span: usize,
    /// Most iterations per start (all stages together).
    pub max_iterations: usize,
    /// The starts, in order; the best feasible result is kept. The default pair covers both twist
    /// directions and both bend paths (the paper's twists by −π, the mirrored cone by +π).
    pub starts: Vec<StartKind>,
    /// With the peak objective, first minimise the energy from each start (a smooth problem),
    /// then the peak from there: the trust region's peak stage; the interior-point method's
    /// (`method`) starts without it (after the coarse solve, where there is one).
    pub homotopy: bool,
    /// Stop when the predicted decrease of the merit function is below this fraction of the
    /// objective (times the trust radius in radians, up to one, for a step the radius cut short);
    /// the interior-point method stops when its optimality error, in units of the start's peak,
    /// is below it.
    pub optimality: f64,
    /// Initial trust radius on the control points, degrees.
    pub trust_radius_deg: f64,
    /// Weight of the orientation error `|e|₁` in the merit function, per radian, relative to the
    /// current objective.
    pub penalty: f64,
}

impl Default for WholeSettings {
    fn default() -> Self {
        Self {
            objective: Objective::Peak,
            method: Method::Auto,
            min_angle_deg: None,
            joint_limit_deg: None,
            control_points: 120,
            coarse_control_points: Some(10),
            zero_end_acceleration: false,
            samples_per_span: 4,
            switch_refinements: 1,
            steps_per_span: 8,
            max_iterations: 200,
            starts: vec![StartKind::Paper, StartKind::ConeMirrored],
            homotopy: true,
            optimality: 1e-7,
            trust_radius_deg: 10.0,
            penalty: 1e4,
        }
    }
}

impl WholeSettings {
    /// The spline's degree: cubic (module docs of [`super`] argue the choice).
    pub const DEGREE: usize = 3;

    /// The most control points per joint, of the setting and of a refined spline.
    pub const MAX_CONTROL_POINTS: usize = 400;

    /// Control points held at zero at each end of each joint.
    pub fn fixed(&self) -> usize {
        if self.zero_end_acceleration {
            3
        } else {
            2
        }
    }

    /// Checks every field; names the first one that is wrong.
    pub fn validate(&self) -> Result<(), ProblemError> {
        if let Some(a) = self.min_angle_deg {
            if !(a.is_finite() && (0.0..180.0).contains(&a)) {
                return Err(bad("optimize.whole.min_angle_deg", a, "must lie in [0, 180)"));
            }
        }
        if let Some(l) = self.joint_limit_deg {
            positive("optimize.whole.joint_limit_deg", l)?;
        }
        let least = 2 * self.fixed() + 2;
        if self.control_points < least.max(Self::DEGREE + 2) || self.control_points > Self::MAX_CONTROL_POINTS {
            return Err(bad(
                "optimize.whole.control_points",
                self.control_points,
                &format!(
                    "must lie in [{least}, {}] (at least two free control points per joint)",
                    Self::MAX_CONTROL_POINTS
                ),
            ));
        }
        if let Some(n) = self.coarse_control_points {
            if n < least.max(Self::DEGREE + 2) || n > self.control_points {
                return Err(bad(
                    "optimize.whole.coarse_control_points",
                    n,
                    &format!("must lie in [{least}, optimize.whole.control_points = {}]", self.control_points),
                ));
            }
        }
        if !(2..=64).contains(&self.samples_per_span) {
            return Err(bad("optimize.whole.samples_per_span", self.samples_per_span, "must lie in [2, 64]"));
        }
        if self.switch_refinements > 4 {
            return Err(bad("optimize.whole.switch_refinements", self.switch_refinements, "must lie in [0, 4]"));
        }
        if !(1..=1024).contains(&self.steps_per_span) {
            return Err(bad("optimize.whole.steps_per_span", self.steps_per_span, "must lie in [1, 1024]"));
        }
        if self.max_iterations == 0 {
            return Err(bad("optimize.whole.max_iterations", 0, "must be at least 1"));
        }
        if self.starts.is_empty() {
            return Err(bad("optimize.whole.starts", "[]", "name at least one start"));
        }
        positive("optimize.whole.optimality", self.optimality)?;
        if self.optimality > MAX_OPTIMALITY {
            return Err(bad(
                "optimize.whole.optimality",
                crate::numeric::numfmt::echo(self.optimality),
                &format!(
                    "must be at most {MAX_OPTIMALITY:.0e}: a stage would end while its model still predicts a decrease of that share of the objective, far from an optimum (the default is {:.0e})",
                    WholeSettings::default().optimality
                ),
            ));
        }
        positive("optimize.whole.trust_radius_deg", self.trust_radius_deg)?;
        positive("optimize.whole.penalty", self.penalty)
    }
}

/// The largest `optimize.whole.optimality`: the predicted decrease, relative to the objective,
/// below which a stage ends (with 1, the paper's problem ended "converged" at twice its optimum).
pub const MAX_OPTIMALITY: f64 = 1e-3;

/// The message of a `min-time` objective without motor limits (shared with the problem file's
/// validation).
pub const MIN_TIME_NEEDS_LIMITS: &str =
    "needs motor limits: give at least one of [actuator]'s torque_limit_nm, speed_limit_rad_s, stall_torque_nm with free_speed_rad_s, power_limit_w (with ideal motors any fall is long enough)";
