//! `catflip bench`: run time against error for every engine, and numerical stress tests.
//!
//! - **Exact engine**: the sixth-order Magnus integration of the paper's schedule with 2…2048
//!   steps per phase; error = angle of `R_n⁻¹ R_ref` against 8192 steps per phase. Also the
//!   adaptive [`crate::engines::exact::flip`] at tolerances 1e-4…1e-12 with its actual error.
//! - **rapier3d-f64**: the same schedule (with a rest-to-rest profile, so that no impulse
//!   enters) at time steps 1/60…1/8000 s; error = twist and swing against the exact engine,
//!   and the observed order of convergence between successive steps.
//! - **Stress tests**: problems at the edges of the model (near-folded and near-straight cats,
//!   thin and fat cylinders, extreme masses, many turns, a fast fall, the cone near its gimbal
//!   margin): whether the exact engine converges, its error estimate, the momentum residual,
//!   the action–reaction gap of the torques and the steps it needed.
//!
//! Times are medians of repeated wall-clock measurements on this machine: for the record, not
//! for pass/fail (criterion benches in `benches/` are the controlled measurement).

use std::fmt;
use std::time::Instant;

use serde::Serialize;

use crate::engines::circulation::{CirculationError, Resolved};
use crate::engines::evaluate::Evaluation;
use crate::engines::exact::{flip, integrate};
use crate::engines::rapier::RapierError;
use crate::problem::settings::ExactSettings;
use crate::problem::{Problem, ProfileKind};
use crate::schedule::Schedule;

/// Why the benchmark could not run.
#[derive(Debug, thiserror::Error)]
pub enum BenchError {
    /// The rapier engine failed.
    #[error(transparent)]
    Rapier(#[from] RapierError),
    /// The base problem could not be written as TOML for the stress cases' overrides.
    #[error("cannot write the bench problem as TOML for the stress cases")]
    Toml(#[from] toml::ser::Error),
}

/// How a benchmark point was computed.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Method {
    /// The exact engine's sixth-order Magnus integration with a fixed number of steps.
    ExactMagnus6,
    /// The exact engine's adaptive integration to a tolerance.
    ExactAdaptive,
    /// rapier3d-f64 at a time step.
    Rapier,
}

impl fmt::Display for Method {
    /// The name in files and tables: `exact-magnus6`, `exact-adaptive`, `rapier`.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Method::ExactMagnus6 => "exact-magnus6",
            Method::ExactAdaptive => "exact-adaptive",
            Method::Rapier => "rapier",
        })
    }
}

/// One measurement of an engine.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct EnginePoint {
    /// How it was computed.
    pub engine: Method,
    /// The resolution: steps per phase, tolerance (rad) or time step (s).
    pub setting: f64,
    /// Median wall-clock time, s.
    pub time_s: f64,
    /// Error of the final orientation (exact) or twist (rapier) against the reference, rad.
    pub error_rad: f64,
    /// Swing error against the reference, rad.
    pub swing_error_rad: f64,
    /// Relative error of the peak torque against the exact engine (rapier only).
    pub peak_torque_rel_error: Option<f64>,
    /// Observed order of convergence from the previous point (log error ratio / log step ratio).
    pub observed_order: Option<f64>,
}

/// One stress case.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct StressCase {
    /// What is stressed.
    pub case: String,
    /// The overrides that make it.
    pub overrides: Vec<String>,
    /// Whether the adaptive integration met its tolerance.
    pub converged: bool,
    /// Its error estimate, rad.
    pub error_estimate_rad: f64,
    /// Steps per phase it needed.
    pub steps_per_phase: usize,
    /// Twist, degrees.
    pub twist_deg: f64,
    /// Largest momentum along the motion relative to `I*·max|q̇|`.
    pub momentum_max: f64,
    /// Largest action–reaction gap of the torques relative to the peak torque.
    pub action_reaction_rel: f64,
    /// Peak torque, N·m.
    pub peak_torque_nm: f64,
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
            error_estimate_rad: f64::NAN,
            steps_per_phase: 0,
            twist_deg: f64::NAN,
            momentum_max: f64::NAN,
            action_reaction_rel: f64::NAN,
            peak_torque_nm: f64::NAN,
            refused: Some(error),
        }
    }
}

/// The whole benchmark.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct BenchReport {
    /// Engine measurements.
    pub points: Vec<EnginePoint>,
    /// Stress cases.
    pub stress: Vec<StressCase>,
}

fn median_time(repeats: usize, mut f: impl FnMut()) -> f64 {
    let mut t: Vec<f64> = (0..repeats.max(1))
        .map(|_| {
            let s = Instant::now();
            f();
            s.elapsed().as_secs_f64()
        })
        .collect();
    t.sort_by(f64::total_cmp);
    t[t.len() / 2]
}

fn with_orders(mut points: Vec<EnginePoint>) -> Vec<EnginePoint> {
    for i in 1..points.len() {
        let (a, b) = (&points[i - 1], &points[i]);
        let ratio = (a.setting / b.setting).abs().ln();
        if a.error_rad > 0.0 && b.error_rad > 0.0 && ratio != 0.0 {
            let order = (a.error_rad / b.error_rad).ln() / ratio;
            points[i].observed_order = Some(order.abs());
        }
    }
    points
}

/// Exact engine: Magnus steps and adaptive tolerances on `schedule`.
pub fn exact_points(problem: &Problem, schedule: &Schedule) -> Vec<EnginePoint> {
    let cat = &problem.cat;
    let (reference, ref_angles) = integrate(cat, schedule, 8192, |_| {});
    let fixed: Vec<EnginePoint> = (1..=11)
        .map(|k| {
            let n = 1usize << k;
            let (r, a) = integrate(cat, schedule, n, |_| {});
            let time_s = median_time(7, || {
                std::hint::black_box(integrate(cat, schedule, n, |_| {}));
            });
            EnginePoint {
                engine: Method::ExactMagnus6,
                setting: 1.0 / n as f64,
                time_s,
                error_rad: (r.inverse() * reference).angle(),
                swing_error_rad: (a.swing - ref_angles.swing).abs(),
                peak_torque_rel_error: None,
                observed_order: None,
            }
        })
        .collect();
    let adaptive = [1e-4, 1e-6, 1e-8, 1e-10, 1e-12].iter().map(|&tol| {
        let f = flip(cat, schedule, tol);
        let time_s = median_time(7, || {
            std::hint::black_box(flip(cat, schedule, tol));
        });
        EnginePoint {
            engine: Method::ExactAdaptive,
            setting: tol,
            time_s,
            error_rad: (f.orientation.inverse() * reference).angle(),
            swing_error_rad: (f.swing - ref_angles.swing).abs(),
            peak_torque_rel_error: None,
            observed_order: None,
        }
    });
    let mut out = with_orders(fixed);
    out.extend(adaptive);
    out
}

/// rapier3d: a time-step sweep on `schedule` against the exact engine (at 1e-12 rad).
pub fn rapier_points(problem: &Problem, schedule: &Schedule, dts: &[f64]) -> Result<Vec<EnginePoint>, RapierError> {
    let cat = &problem.cat;
    let exact = Evaluation::new(cat, schedule, &ExactSettings { tolerance: 1e-12, ..problem.exact });
    let mut points = Vec::new();
    for &dt in dts {
        let settings = problem.rapier.with_dt(dt);
        let start = Instant::now();
        let run = crate::engines::rapier::simulate(cat, schedule, &settings)?;
        let time_s = start.elapsed().as_secs_f64();
        points.push(EnginePoint {
            engine: Method::Rapier,
            setting: run.dt,
            time_s,
            error_rad: (run.twist - exact.flip.twist).abs(),
            swing_error_rad: (run.swing - exact.flip.swing).abs(),
            peak_torque_rel_error: Some((run.peak_torque.max - exact.peaks.max) / exact.peaks.max),
            observed_order: None,
        });
    }
    Ok(with_orders(points))
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
    let e = Evaluation::new(&p.cat, &r.schedule, &p.exact);
    Ok(StressCase {
        case: case.to_string(),
        overrides,
        converged: e.flip.converged,
        error_estimate_rad: e.flip.error_estimate,
        steps_per_phase: e.flip.steps_per_phase,
        twist_deg: e.twist_deg(),
        momentum_max: e.momentum_max,
        action_reaction_rel: e.action_reaction_gap / e.peaks.max.max(f64::MIN_POSITIVE),
        peak_torque_nm: e.peaks.max,
        refused: None,
    })
}

/// The full benchmark on a resolved problem (its schedule, with a cycloidal profile for rapier).
pub fn bench(r: &Resolved, dts: &[f64]) -> Result<BenchReport, BenchError> {
    let mut points = exact_points(&r.problem, &r.schedule);
    let smooth = r.with_library(ProfileKind::Cycloidal);
    points.extend(rapier_points(&r.problem, &smooth, dts)?);
    Ok(BenchReport { points, stress: stress(&r.problem)? })
}

impl BenchReport {
    /// Markdown tables.
    pub fn to_markdown(&self) -> String {
        use std::fmt::Write;
        let mut s = String::from("## Run time against error\n\n| engine | setting | median time | error rad | swing error rad | peak torque rel. error | observed order |\n|---|---:|---:|---:|---:|---:|---:|\n");
        for p in &self.points {
            let _ = writeln!(
                s,
                "| {} | {:.3e} | {:.3e} s | {:.2e} | {:.2e} | {} | {} |",
                p.engine,
                p.setting,
                p.time_s,
                p.error_rad,
                p.swing_error_rad,
                p.peak_torque_rel_error.map_or("—".into(), |e| format!("{:+.3}%", 100.0 * e)),
                p.observed_order.map_or("—".into(), |o| format!("{o:.2}"))
            );
        }
        s.push_str("\nSettings: steps per phase as 1/n for `exact-magnus6`, tolerance in rad for `exact-adaptive`, time step in s for `rapier` (cycloidal profile, no impulses).\n\n## Stress tests of the exact engine\n\n| case | converged | error estimate rad | steps/phase | twist ° | momentum (rel.) | action–reaction (rel.) | peak torque N·m | refused with |\n|---|---|---:|---:|---:|---:|---:|---:|---|\n");
        for c in &self.stress {
            let _ = writeln!(
                s,
                "| {} | {} | {:.1e} | {} | {:.4} | {:.1e} | {:.1e} | {:.4e} | {} |",
                c.case,
                c.converged,
                c.error_estimate_rad,
                c.steps_per_phase,
                c.twist_deg,
                c.momentum_max,
                c.action_reaction_rel,
                c.peak_torque_nm,
                c.refused.as_deref().unwrap_or("")
            );
        }
        s
    }

    /// Tidy CSV of the engine points.
    pub fn to_csv(&self) -> String {
        let header =
            ["engine", "setting", "time_s", "error_rad", "swing_error_rad", "peak_torque_rel_error", "observed_order"];
        let records = self.points.iter().map(|p| {
            [
                p.engine.to_string(),
                format!("{:e}", p.setting),
                format!("{:e}", p.time_s),
                format!("{:e}", p.error_rad),
                format!("{:e}", p.swing_error_rad),
                p.peak_torque_rel_error.map_or(String::new(), |e| format!("{e:e}")),
                p.observed_order.map_or(String::new(), |o| format!("{o:.4}")),
            ]
        });
        crate::exchange::table::csv_table(&header, records)
    }
}
