//! The named stress cases: problems at the edges of the model (near-folded and near-straight
//! cats, thin and fat cylinders, extreme masses, many turns, a fast fall, the cone near its
//! gimbal margin): whether the exact engine converges, its error estimate, the momentum
//! residual, the action–reaction gap of the torques and the steps it needed. The seeded random
//! problems spanning decades are in [`super::random`].

use serde::Serialize;

use crate::engines::circulation::CirculationError;
use crate::engines::evaluate::Evaluation;
use crate::engines::resolved::Resolved;
use crate::measure::bench::BenchError;
use crate::problem::Problem;

/// One stress case.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct StressCase {
    /// What is stressed.
    pub case: String,
    /// The overrides that make it.
    pub overrides: Vec<String>,
    /// Whether the adaptive integration met its tolerance.
    pub converged: bool,
    /// Its error estimate, rad (this and the numbers below are absent when refused).
    pub error_estimate_rad: Option<f64>,
    /// Steps per phase it needed.
    pub steps_per_phase: Option<usize>,
    /// Twist, degrees.
    pub twist_deg: Option<f64>,
    /// Largest momentum along the motion relative to `I*·max|q̇|`.
    pub momentum_max: Option<f64>,
    /// Largest action–reaction gap of the torques relative to the peak torque.
    pub action_reaction_rel: Option<f64>,
    /// Peak torque, N·m.
    pub peak_torque_nm: Option<f64>,
    /// A load error, when the case is refused (as it should be for invalid input).
    pub refused: Option<String>,
}

impl StressCase {
    /// A case the model refuses, with the error it gives.
    fn refused(case: &str, overrides: Vec<String>, error: String) -> StressCase {
        StressCase {
            case: case.to_string(),
            overrides,
            converged: false,
            error_estimate_rad: None,
            steps_per_phase: None,
            twist_deg: None,
            momentum_max: None,
            action_reaction_rel: None,
            peak_torque_nm: None,
            refused: Some(error),
        }
    }
}

/// The stress cases, each a set of overrides on `base`.
pub fn stress(base: &Problem) -> Result<Vec<StressCase>, BenchError> {
    let cases: [(&str, &[&str]); 11] = [
        ("nearly folded (θ = 2°)", &["manoeuvre.theta_deg=2"]),
        ("nearly straight (θ = 179°)", &["manoeuvre.theta_deg=179"]),
        ("thin cylinders (r = 1e-4 m)", &["cat.radius=1e-4"]),
        ("fat cylinders (r = l)", &["cat.radius=1.0"]),
        ("light cat (m = 1e-6 kg)", &["cat.mass=1e-6"]),
        ("heavy cat (m = 1e6 kg)", &["cat.mass=1e6"]),
        ("many turns (circulation 60 rad)", &["manoeuvre.circulation=60.0"]),
        ("fast fall (h = 1 cm)", &["drop.height=0.01"]),
        (
            "cone at the gimbal margin (θ = 95.1°)",
            &["manoeuvre.bend_path=\"cone\"", "manoeuvre.theta_deg=95.1", "manoeuvre.profile=\"cycloidal\""],
        ),
        ("cone inside the gimbal margin (θ = 92°)", &["manoeuvre.bend_path=\"cone\"", "manoeuvre.theta_deg=92"]),
        ("short twist phase (phases 0.45/0.1/0.45)", &["manoeuvre.phases=[0.45, 0.1, 0.45]"]),
    ];
    let text = toml::to_string(base)?;
    Ok(cases
        .iter()
        .map(|(case, o)| {
            let overrides: Vec<String> = o.iter().map(|s| s.to_string()).collect();
            match Problem::from_toml(&text, "stress", &overrides) {
                Err(e) => StressCase::refused(case, overrides, e.to_string()),
                Ok(p) => stress_case(case, overrides.clone(), &p)
                    .unwrap_or_else(|e| StressCase::refused(case, overrides, e.to_string())),
            }
        })
        .collect())
}

fn stress_case(case: &str, overrides: Vec<String>, p: &Problem) -> Result<StressCase, CirculationError> {
    let r = Resolved::new(p)?;
    let e = Evaluation::of_paper(&p.cat.half(), &r.schedule, &p.drop.spin(), &p.actuator.motors(), &p.exact);
    Ok(StressCase {
        case: case.to_string(),
        overrides,
        converged: e.flip.converged,
        error_estimate_rad: finite(e.flip.error_estimate),
        steps_per_phase: Some(e.flip.steps_per_phase),
        twist_deg: finite(e.twist_deg()),
        momentum_max: finite(e.momentum_max),
        action_reaction_rel: finite(e.peaks.action_reaction_gap / e.peaks.max.max(f64::MIN_POSITIVE)),
        peak_torque_nm: finite(e.peaks.max),
        refused: None,
    })
}

/// `x` when it is finite: a number the engine could not give is shown as `—`, never as NaN.
fn finite(x: f64) -> Option<f64> {
    x.is_finite().then_some(x)
}
