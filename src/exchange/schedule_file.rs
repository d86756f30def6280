//! Schedule files people can load: `NAME.csv` (one row per instant) and its sidecar `NAME.json`
//! ([`Sidecar`]) (DESIGN.md §7).
//!
//! # Columns
//!
//! `t_s, phase, boundary, q1_rad, q2_rad, qd1_rad_s, qd2_rad_s, qdd1_rad_s2, qdd2_rad_s2,
//! tau1_nm, tau2_nm, impulse1_nms, impulse2_nms, qw, qx, qy, qz, twist_deg, swing_deg`:
//! time; the piece (phase) name; the boundary marker (`""`, `end`, `start`: a boundary time is
//! written twice, once with each piece's one-sided values); joint angles, rates and
//! accelerations; the exact motor torques on B about joint 1's and joint 2's axes; the impulse
//! `M(q)Δq̇` of a rate jump on the `start` row where it lands; A's orientation as a unit quaternion
//! in the order (w, x, y, z); its twist and swing. Numbers are written with Rust's shortest
//! round-trip formatting: a reader gets the very `f64`s.
//!
//! # Rows
//!
//! - [`ExportOptions::rate_hz`] `= Some(f)`: the uniform grid `t = k/f` (`k = 0, 1, …`), plus both
//!   rows of every piece boundary and the final instant when they are off the grid (a grid point
//!   within `10⁻⁶/f` of a boundary becomes that boundary);
//! - `None`: [`ExportOptions::steps_per_piece`] equal intervals in every phase (consecutive
//!   pieces of one name), plus the rows of every boundary.
//!
//! A three-phase schedule's phases are cut where the acceleration jumps
//! ([`crate::exchange::cuts`]): the instant is written twice like a phase boundary, so that
//! every piece between `end`/`start` pairs is smooth.
//!
//! # Orientation to the engine's tolerance
//!
//! The orientation columns are not a fixed grid's: [`crate::engines::exact::flip`] first finds the step
//! count `N` per piece at which its Richardson estimate meets `exact.tolerance`; the orientation
//! is then carried from row to row with sixth-order Magnus steps ([`crate::engines::exact::magnus6`]) no
//! longer than `T_piece / N`, so every row is at least as accurate as the engine's final answer
//! (the last row agrees with `flip` to about the tolerance; a test checks it).

use nalgebra::{UnitQuaternion, Vector3};

use crate::engines::exact::{body_rate, flip, magnus6};
use crate::engines::models::TwoMotorCat;
use crate::engines::motors::peaks_and_demand;
use crate::engines::torque::{piece_samples, Peak, TorqueSource};
use crate::exchange::cuts::{acceleration_cuts, CutTrajectory};
use crate::exchange::jumps::{rate_jumps, rate_jumps_by, Jump};
use crate::exchange::links::{num, Links};
use crate::exchange::sidecar::{
    Column, Conventions, ModelInfo, MotorSizing, OrientationInfo, PieceInfo, Sampling, Sidecar, Source, FORMAT,
};
use crate::exchange::ExchangeError;
use crate::model::orientation::{SwingTwist, TwistTracker};
use crate::problem::Problem;
use crate::schedule::{JointState, Phase, Schedule, Trajectory};

/// The columns: name, unit, meaning.
pub const COLUMNS: [(&str, &str, &str); 19] = [
    ("t_s", "s", "time from the start of the schedule"),
    ("phase", "", "the piece (phase) the row belongs to"),
    ("boundary", "", "'' ordinary row; 'end' / 'start': the two one-sided rows of a piece boundary"),
    ("q1_rad", "rad", "joint 1 angle, about A's x"),
    ("q2_rad", "rad", "joint 2 angle, about the cross's y"),
    ("qd1_rad_s", "rad/s", "joint 1 rate"),
    ("qd2_rad_s", "rad/s", "joint 2 rate"),
    ("qdd1_rad_s2", "rad/s²", "joint 1 acceleration"),
    ("qdd2_rad_s2", "rad/s²", "joint 2 acceleration"),
    ("tau1_nm", "N·m", "motor torque on B about joint 1's axis"),
    ("tau2_nm", "N·m", "motor torque on B about joint 2's axis"),
    ("impulse1_nms", "N·m·s", "impulse of a rate jump on joint 1 ('start' rows only, else 0)"),
    ("impulse2_nms", "N·m·s", "impulse of a rate jump on joint 2 ('start' rows only, else 0)"),
    ("qw", "", "A's orientation quaternion, scalar part"),
    ("qx", "", "A's orientation quaternion, x"),
    ("qy", "", "A's orientation quaternion, y"),
    ("qz", "", "A's orientation quaternion, z"),
    ("twist_deg", "deg", "twist of A about its initial +z, continued"),
    ("swing_deg", "deg", "swing of A's spine axis"),
];

/// The CSV header line (without the newline).
pub fn header() -> String {
    COLUMNS.map(|c| c.0).join(",")
}

/// How to sample a schedule.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ExportOptions {
    /// Rows on the uniform grid `t = k / rate_hz`, Hz; `None` for equal steps per piece.
    pub rate_hz: Option<f64>,
    /// Intervals per phase (consecutive pieces of one name) when `rate_hz` is `None`.
    pub steps_per_piece: usize,
}

impl Default for ExportOptions {
    fn default() -> Self {
        Self { rate_hz: None, steps_per_piece: 400 }
    }
}

/// Most rows a schedule file may have (a guard against a mistyped `--rate`).
pub const MAX_ROWS: usize = 10_000_000;

impl ExportOptions {
    /// Checks the options against a schedule of `duration` seconds.
    pub fn validate(&self, duration: f64) -> Result<(), ExchangeError> {
        if let Some(f) = self.rate_hz {
            if !(f.is_finite() && f > 0.0) {
                return Err(ExchangeError::BadRate { rate_hz: f, reason: "must be a positive number of Hz".into() });
            }
            if duration * f > MAX_ROWS as f64 {
                return Err(ExchangeError::BadRate {
                    rate_hz: f,
                    reason: format!("gives {:.0} rows over {duration} s, more than {MAX_ROWS}", duration * f),
                });
            }
        }
        if self.steps_per_piece == 0 || self.steps_per_piece > MAX_ROWS {
            return Err(ExchangeError::BadSteps(self.steps_per_piece));
        }
        Ok(())
    }
}

/// A schedule file: the CSV text and its sidecar.
#[derive(Clone, Debug, PartialEq)]
pub struct ScheduleFile {
    /// The CSV text.
    pub csv: String,
    /// The sidecar.
    pub sidecar: Sidecar,
}

impl ScheduleFile {
    /// The sidecar as pretty JSON with a final newline.
    pub fn sidecar_json(&self) -> Result<String, ExchangeError> {
        serde_json::to_string_pretty(&self.sidecar).map(|s| s + "\n").map_err(|e| ExchangeError::Json(e.to_string()))
    }
}

/// One of a problem's three-phase schedules as a file named `name` (`name.csv`, `name.json`),
/// its phases cut where the acceleration jumps ([`CutTrajectory`]), so every piece is smooth.
pub fn write_schedule(
    problem: &Problem,
    schedule: &Schedule,
    name: &str,
    options: &ExportOptions,
) -> Result<ScheduleFile, ExchangeError> {
    let refined = CutTrajectory::new(schedule, &acceleration_cuts(schedule));
    let names: Vec<String> =
        (0..refined.piece_durations().len()).map(|k| Phase::ALL[refined.origin(k).min(2)].name().to_string()).collect();
    let description = format!(
        "three phases (bend, twist, unbend) of {:?} s; bend β = {} rad on the {:?} path; twist profile {}, circulation {} rad",
        schedule.durations,
        schedule.bend,
        schedule.path,
        schedule.profile.name(),
        schedule.circulation
    );
    write_trajectory(problem, &refined, &names, name, &description, options)
}

/// Any trajectory as a file named `name`; `piece_names` name its pieces (missing names are
/// `piece-K`), `description` says what it is.
pub fn write_trajectory(
    problem: &Problem,
    traj: &impl Trajectory,
    piece_names: &[String],
    name: &str,
    description: &str,
    options: &ExportOptions,
) -> Result<ScheduleFile, ExchangeError> {
    // The orientation and torque columns and the sidecar's figures are the zero-momentum flip's.
    problem.require_no_spin("a schedule file (its orientation and torque columns)")?;
    problem.require_universal_joint("a schedule file (its URDF/MJCF model)")?;
    // The paper's cat through the two-cylinder engine, any other through the general core.
    let model = TwoMotorCat::new(problem.cat.model())?;
    let paper = model.cat().paper().copied();
    let durations = traj.piece_durations();
    options.validate(durations.iter().sum())?;
    let piece_name = |k: usize| piece_names.get(k).cloned().unwrap_or_else(|| format!("piece-{}", k + 1));
    let labels: Vec<String> = (0..durations.len()).map(piece_name).collect();
    let plan = plan_rows(&durations, &labels, options);
    let tolerance = problem.exact.tolerance;
    let engine = paper.map_or_else(|| model.flip(traj, tolerance), |cat| flip(&cat, traj, tolerance));
    let max_step = durations.iter().fold(0.0, |m: f64, &d| m.max(d)) / engine.steps_per_phase.max(1) as f64;
    let rate = |st: &JointState| paper.map_or_else(|| model.body_rate(st), |cat| body_rate(&cat, st.q, st.qd));
    let attitude = orientations(rate, traj, &plan, &durations, engine.steps_per_phase);
    let jumps = match &paper {
        Some(cat) => rate_jumps(cat, traj),
        None => rate_jumps_by(|q, dq| model.motor_impulse(q, dq), traj, |_| 0.0),
    };
    let source = TorqueSource::of(&model);
    let mut w = csv::Writer::from_writer(Vec::new());
    w.write_record(COLUMNS.map(|c| c.0)).map_err(csv_error)?;
    let mut pieces: Vec<PieceInfo> = Vec::new();
    for (i, (row, (q, angles))) in plan.iter().zip(&attitude).enumerate() {
        let st = traj.piece_state(row.piece, row.local);
        let tau = source.at(traj, row.piece, row.local, &st).tau;
        let impulse = match row.marker {
            Marker::Start => jumps.iter().find(|j| j.after_piece + 1 == row.piece).map(|j| j.impulse_nms),
            _ => None,
        }
        .unwrap_or([0.0; 2]);
        let numbers = [
            st.q[0],
            st.q[1],
            st.qd[0],
            st.qd[1],
            st.qdd[0],
            st.qdd[1],
            tau[0],
            tau[1],
            impulse[0],
            impulse[1],
            q.w,
            q.i,
            q.j,
            q.k,
            angles.twist.to_degrees(),
            angles.swing.to_degrees(),
        ];
        let mut record = vec![num(row.time), piece_name(row.piece), row.marker.text().to_string()];
        record.extend(numbers.map(num));
        w.write_record(&record).map_err(csv_error)?;
        let same_piece = pieces.len() == row.piece + 1;
        match pieces.last_mut() {
            Some(p) if same_piece => {
                p.last_row = i;
                p.end_s = row.time;
            }
            _ => pieces.push(PieceInfo {
                name: piece_name(row.piece),
                start_s: row.time,
                end_s: row.time,
                first_row: i,
                last_row: i,
            }),
        }
    }
    let bytes = w.into_inner().map_err(|e| ExchangeError::Csv(e.to_string()))?;
    let csv = String::from_utf8(bytes).map_err(|e| ExchangeError::Csv(e.to_string()))?;
    let links = Links::new(model.cat(), problem.rapier.cross_mass_fraction);
    let sidecar = Sidecar {
        format: FORMAT.into(),
        csv: format!("{name}.csv"),
        source: Source {
            schedule: name.into(),
            problem: problem.name.clone(),
            description: description.into(),
            problem_file: serde_json::to_value(problem).map_err(|e| ExchangeError::Json(e.to_string()))?,
        },
        model: ModelInfo::new(&links, super::URDF_FILE, super::MJCF_FILE),
        conventions: Conventions::default(),
        columns: COLUMNS.iter().map(|c| Column { name: c.0.into(), unit: c.1.into(), meaning: c.2.into() }).collect(),
        sampling: Sampling {
            kind: if options.rate_hz.is_some() { "uniform" } else { "per-piece" }.into(),
            rate_hz: options.rate_hz,
            steps_per_piece: options.rate_hz.is_none().then_some(options.steps_per_piece),
            rows: plan.len(),
            duration_s: durations.iter().sum(),
        },
        pieces,
        jumps: jumps.clone(),
        orientation: OrientationInfo {
            engine: "exact".into(),
            tolerance_rad: problem.exact.tolerance,
            max_step_s: max_step,
            error_estimate_rad: engine.error_estimate,
            converged: engine.converged,
            final_twist_deg: engine.twist.to_degrees(),
            final_swing_deg: engine.swing.to_degrees(),
        },
        interpolation: interpolation_advice(&jumps),
        motors: motor_sizing(problem, &source, traj),
    };
    Ok(ScheduleFile { csv, sidecar })
}

/// The motor-sizing figures of `traj` on `problem`'s cat and `[actuator]`, sampled as the
/// reports sample peaks.
fn motor_sizing(problem: &Problem, source: &TorqueSource, traj: &impl Trajectory) -> MotorSizing {
    let samples = piece_samples(traj, problem.exact.torque_samples);
    let (peaks, demand) = peaks_and_demand(source, traj, &samples, &problem.actuator.motors());
    let largest = |j: usize| {
        peaks
            .per_piece
            .iter()
            .map(|p| p[j])
            .fold(Peak { value: 0.0, time: 0.0 }, |a, b| if b.value > a.value { b } else { a })
    };
    MotorSizing {
        peak_torque_nm: [largest(0), largest(1)],
        within_motors: demand.within(),
        verdict: demand.verdict(),
        demand,
    }
}

fn csv_error(e: csv::Error) -> ExchangeError {
    ExchangeError::Csv(e.to_string())
}

fn interpolation_advice(jumps: &[Jump]) -> String {
    let mut s = String::from(
        "Within a piece, interpolate q with q̇ and q̈ by quintic Hermite (what `catflip simulate --schedule` does: error O(h⁶) in q, O(h⁴) in q̈); a cubic spline through q alone is O(h⁴). Never interpolate across a piece boundary: split the file at its 'end'/'start' row pairs (each pair has the same t) and fit each piece on its own.",
    );
    if !jumps.is_empty() {
        s.push_str(" The rates jump at a boundary listed under 'jumps': that is an impulse (N·m·s), delivered at that instant, not a torque.");
    }
    s
}

/// The boundary marker of a row.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Marker {
    /// An ordinary row.
    Plain,
    /// The last row of a piece followed by another at the same time.
    End,
    /// The first row of a piece that follows another.
    Start,
}

impl Marker {
    fn text(self) -> &'static str {
        match self {
            Marker::Plain => "",
            Marker::End => "end",
            Marker::Start => "start",
        }
    }
}

/// Where a row is: piece, local time in it, global time, marker.
#[derive(Clone, Copy, Debug)]
struct Row {
    piece: usize,
    local: f64,
    time: f64,
    marker: Marker,
}

/// The rows of the file: each piece from its start to its end, boundary times twice. The grid
/// is `t = k / rate` or, per phase (consecutive pieces with the same label), `steps` equal
/// intervals of the phase; grid points within `10⁻⁶` of a grid step of a boundary are dropped.
fn plan_rows(durations: &[f64], labels: &[String], options: &ExportOptions) -> Vec<Row> {
    let n = durations.len();
    let starts: Vec<f64> = durations.iter().scan(0.0, |t, &d| Some(std::mem::replace(t, *t + d))).collect();
    let same = |a: usize, b: usize| labels.get(a).is_some() && labels.get(a) == labels.get(b);
    let mut rows = Vec::new();
    for (piece, &d) in durations.iter().enumerate() {
        let (start, end) = (starts[piece], starts[piece] + d);
        let (origin, step) = match options.rate_hz {
            Some(f) => (0.0, 1.0 / f),
            None => {
                let first = (0..=piece).rev().take_while(|&k| k == piece || same(k, piece)).last().unwrap_or(piece);
                let last = (piece..n).take_while(|&k| k == piece || same(k, piece)).last().unwrap_or(piece);
                let span = starts[last] + durations[last] - starts[first];
                (starts[first], span / options.steps_per_piece as f64)
            }
        };
        let first = if piece == 0 { Marker::Plain } else { Marker::Start };
        let last = if piece + 1 == n { Marker::Plain } else { Marker::End };
        rows.push(Row { piece, local: 0.0, time: start, marker: first });
        if step > 0.0 {
            let eps = 1e-6;
            let mut k = ((start - origin) / step + eps).floor() as usize + 1;
            while origin + (k as f64) * step < end - eps * step {
                let t = origin + k as f64 * step;
                rows.push(Row { piece, local: t - start, time: t, marker: Marker::Plain });
                k += 1;
            }
        }
        rows.push(Row { piece, local: d, time: end, marker: last });
    }
    rows
}

/// A's orientation at every row: Magnus steps no longer than `T_piece / steps` from row to row.
fn orientations(
    body_rate: impl Fn(&JointState) -> Vector3<f64>,
    traj: &impl Trajectory,
    rows: &[Row],
    durations: &[f64],
    steps: usize,
) -> Vec<(UnitQuaternion<f64>, SwingTwist)> {
    let c = 15f64.sqrt() / 10.0;
    let mut r = UnitQuaternion::identity();
    let mut tracker = TwistTracker::default();
    let mut angles = tracker.update(&r);
    let mut out = Vec::with_capacity(rows.len());
    let mut prev: Option<Row> = None;
    for row in rows {
        if let Some(p) = prev.filter(|p| p.piece == row.piece) {
            let h_max = durations[row.piece] / steps.max(1) as f64;
            let span = row.local - p.local;
            let n = ((span / h_max) * (1.0 - 1e-12)).ceil().max(1.0) as usize;
            let h = span / n as f64;
            let rate = |s: f64| body_rate(&traj.piece_state(row.piece, s));
            for k in 0..n {
                let s = p.local + k as f64 * h;
                let sigma = magnus6(h, rate(s + (0.5 - c) * h), rate(s + 0.5 * h), rate(s + (0.5 + c) * h));
                r = UnitQuaternion::new_normalize(*(r * UnitQuaternion::from_scaled_axis(sigma)).quaternion());
                angles = tracker.update(&r);
            }
        }
        out.push((r, angles));
        prev = Some(*row);
    }
    out
}
