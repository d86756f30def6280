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
//! On the **no-twist joint** (DESIGN.md §10) the same columns come first, with `q1, q2` the
//! rotation vector `(q1, q2, 0)` of B relative to A and `tau1, tau2` (and the impulses) the
//! joint's couple on B about A's `x` and `y`; then what a ball joint's replay needs
//! ([`NO_TWIST_COLUMNS`]): `tauz_nm, impulsez_nms`, the couple's (and impulse's) component about
//! A's `z`, which the joint's structure supplies to hold the relative twist at zero (no motor's;
//! a ball joint must be given it); `rel_qw, rel_qx, rel_qy, rel_qz`, B relative to A as a unit
//! quaternion `R_AB = exp([q1, q2, 0]×)` (from [`Joint::rotation`]), scalar first, `w > 0`; and
//! `rel_wx_rad_s, rel_wy_rad_s, rel_wz_rad_s`, B's angular velocity relative to A in B's frame,
//! `R_ABᵀ ω_rel` (from [`Joint::relative_rate`]). These are MuJoCo's ball-joint `qpos` and `qvel`
//! ([`mod@crate::exchange::mjcf`]). Every torque column is one [`crate::engines::torque::JointTorques`]'s.
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
//! # The measurement it carries
//!
//! A file is written from a measured trajectory ([`Measured`]): the sidecar's flip, jumps and
//! motor sizing are that measurement's, not a second one. The orientation columns are not a
//! fixed grid's: the measurement's [`crate::engines::exact::flip`] found the step count `N` per
//! piece at which its Richardson estimate meets `exact.tolerance`; the orientation is carried
//! from row to row with sixth-order Magnus steps ([`crate::engines::exact::magnus6`]) no longer
//! than `T_piece / N`, so every row is at least as accurate as the engine's final answer (the
//! last row agrees with the flip to about the tolerance; a test checks it).

use nalgebra::{Rotation3, UnitQuaternion, Vector3};

use crate::engines::evaluate::Evaluation;
use crate::engines::exact::{body_rate, magnus6};
use crate::engines::jumps::VelocityJump;
use crate::engines::measured::Measured;
use crate::engines::models::TwoMotorCat;
use crate::engines::torque::{Peak, TorqueSource};
use crate::exchange::cuts::{acceleration_cuts, CutTrajectory};
use crate::exchange::links::{num, Links};
use crate::exchange::sidecar::{
    Column, Conventions, JumpRecord, ModelInfo, MotorSizing, OrientationInfo, PieceInfo, Sampling, Sidecar, Source,
    FORMAT,
};
use crate::exchange::ExchangeError;
use crate::model::orientation::{SwingTwist, TwistTracker};
use crate::model::Joint;
use crate::problem::Problem;
use crate::schedule::{JointState, Phase, Schedule, Trajectory};

/// The columns of a file of the universal joint (the first columns of every file): name, unit,
/// meaning.
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

/// What the no-twist joint's file says differently of the common columns (name, meaning).
const NO_TWIST_MEANINGS: [(&str, &str); 8] = [
    ("q1_rad", "x component of the rotation vector (q1, q2, 0) of B relative to A: R_AB = exp([q1, q2, 0]×)"),
    ("q2_rad", "y component of the rotation vector of B relative to A"),
    ("qd1_rad_s", "rate of q1"),
    ("qd2_rad_s", "rate of q2"),
    ("qdd1_rad_s2", "acceleration of q1"),
    ("qdd2_rad_s2", "acceleration of q2"),
    ("tau1_nm", "motor torque: the joint's couple on B about the joint point, about A's x"),
    ("tau2_nm", "motor torque: the joint's couple on B about the joint point, about A's y"),
];

/// The columns the no-twist joint's file adds after [`COLUMNS`] (module docs).
pub const NO_TWIST_COLUMNS: [(&str, &str, &str); 9] = [
    (
        "tauz_nm",
        "N·m",
        "the joint's couple on B about A's z: the no-twist constraint's, no motor's; a ball joint must be given it",
    ),
    ("impulsez_nms", "N·m·s", "the impulsive couple of a rate jump about A's z ('start' rows only, else 0)"),
    ("rel_qw", "", "B's orientation relative to A, exp([q1, q2, 0]×), scalar part (MuJoCo's ball qpos)"),
    ("rel_qx", "", "B's orientation relative to A, x"),
    ("rel_qy", "", "B's orientation relative to A, y"),
    ("rel_qz", "", "B's orientation relative to A, z (0: no relative twist)"),
    ("rel_wx_rad_s", "rad/s", "B's angular velocity relative to A, B's frame, x (MuJoCo's ball qvel)"),
    ("rel_wy_rad_s", "rad/s", "B's angular velocity relative to A, B's frame, y"),
    ("rel_wz_rad_s", "rad/s", "B's angular velocity relative to A, B's frame, z"),
];

/// The columns of a file of the cat on `joint` (the universal or no-twist joint): name, unit,
/// meaning.
pub fn columns(joint: Joint) -> Vec<(&'static str, &'static str, &'static str)> {
    if joint == Joint::Universal {
        return COLUMNS.to_vec();
    }
    let meaning = |(name, unit, text): (&'static str, &'static str, &'static str)| {
        let own = NO_TWIST_MEANINGS.iter().find(|(n, _)| *n == name).map_or(text, |(_, m)| *m);
        (name, unit, own)
    };
    COLUMNS.into_iter().map(meaning).chain(NO_TWIST_COLUMNS).collect()
}

/// The CSV header line of a file of the cat on `joint` (without the newline).
pub fn header(joint: Joint) -> String {
    columns(joint).iter().map(|c| c.0).collect::<Vec<_>>().join(",")
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

/// Fewest rows a schedule file at `rate_hz` should give the shortest phase; fewer are warned of
/// ([`ExportOptions::coarse`]).
pub const MIN_ROWS_PER_PHASE: f64 = 10.0;

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

    /// A warning when `rate_hz` gives the shortest phase of `problem`'s fall fewer than
    /// [`MIN_ROWS_PER_PHASE`] rows: the files would keep little more than its boundaries.
    pub fn coarse(&self, problem: &Problem) -> Option<String> {
        let shortest =
            problem.drop.fall_time() * problem.manoeuvre.phases.iter().copied().fold(f64::INFINITY, f64::min);
        self.rate_hz.filter(|r| r * shortest < MIN_ROWS_PER_PHASE).map(|r| {
            format!(
                "--rate {r} Hz gives {:.2} rows in the shortest phase ({shortest:.3} s): the schedule files keep little more than its boundaries (at least {} Hz gives {MIN_ROWS_PER_PHASE} rows)",
                r * shortest,
                (MIN_ROWS_PER_PHASE / shortest).ceil()
            )
        })
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

/// One of a problem's three-phase schedules, measured, as a file named by its name (`NAME.csv`,
/// `NAME.json`), its phases cut where the acceleration jumps ([`CutTrajectory`]), so every piece
/// is smooth.
pub fn write_schedule(
    problem: &Problem,
    measured: &Measured<Schedule>,
    options: &ExportOptions,
) -> Result<ScheduleFile, ExchangeError> {
    let schedule = &measured.trajectory;
    let refined = CutTrajectory::new(schedule, &acceleration_cuts(schedule));
    let pieces = refined.piece_durations().len();
    let names: Vec<String> = (0..pieces).map(|k| Phase::ALL[refined.origin(k).min(2)].name().to_string()).collect();
    let origins: Vec<usize> = (0..pieces).map(|k| refined.origin(k)).collect();
    let description = format!(
        "three phases (bend, twist, unbend) of {:?} s; bend β = {} rad on the {:?} path; twist profile {}, circulation {} rad",
        schedule.durations,
        schedule.bend,
        schedule.path,
        schedule.profile.name(),
        schedule.circulation
    );
    let file = FileTrajectory { traj: &refined, origins: &origins, measured: &measured.exact };
    write_file(problem, &file, &names, &measured.name.to_string(), &description, options)
}

/// Any measured trajectory as a file named by its name; `piece_names` name its pieces (missing
/// names are `piece-K`), `description` says what it is. Its pieces are the file's.
pub fn write_trajectory<T: Trajectory>(
    problem: &Problem,
    measured: &Measured<T>,
    piece_names: &[String],
    description: &str,
    options: &ExportOptions,
) -> Result<ScheduleFile, ExchangeError> {
    let origins: Vec<usize> = (0..measured.trajectory.piece_durations().len()).collect();
    let file = FileTrajectory { traj: &measured.trajectory, origins: &origins, measured: &measured.exact };
    write_file(problem, &file, piece_names, &measured.name.to_string(), description, options)
}

/// The whole-manoeuvre optimum, measured, as its schedule file (`whole-optimum.csv` + sidecar):
/// one piece name for every span, so the rows spread over the whole fall (the spans' joins,
/// where only the jerk jumps, still get their boundary rows).
pub fn write_whole_optimum<T: Trajectory>(
    problem: &Problem,
    measured: &Measured<T>,
    options: &ExportOptions,
) -> Result<ScheduleFile, ExchangeError> {
    let pieces = vec!["whole".to_string(); measured.trajectory.piece_durations().len()];
    let description = "the whole-manoeuvre optimum: both joints as clamped cubic B-splines over the whole fall";
    write_trajectory(problem, measured, &pieces, description, options)
}

/// The rows' trajectory of a file (a measured trajectory, or its pieces cut further), each of
/// its pieces `k` inside the measured piece `origins[k]`, and the measurement.
struct FileTrajectory<'a, T: Trajectory> {
    traj: &'a T,
    origins: &'a [usize],
    measured: &'a Evaluation,
}

fn write_file<T: Trajectory>(
    problem: &Problem,
    file: &FileTrajectory<T>,
    piece_names: &[String],
    name: &str,
    description: &str,
    options: &ExportOptions,
) -> Result<ScheduleFile, ExchangeError> {
    // The orientation and torque columns and the sidecar's figures are the zero-momentum flip's.
    problem.require_no_spin("a schedule file (its orientation and torque columns)")?;
    problem.require_two_motor_joint("a schedule file (its columns and URDF/MJCF model)")?;
    // The paper's cat through the two-cylinder engine, any other through the general core.
    let model = TwoMotorCat::new(problem.cat.model())?;
    let paper = model.cat().paper().copied();
    let (traj, e) = (file.traj, file.measured);
    let durations = traj.piece_durations();
    options.validate(durations.iter().sum())?;
    let piece_name = |k: usize| piece_names.get(k).cloned().unwrap_or_else(|| format!("piece-{}", k + 1));
    let labels: Vec<String> = (0..durations.len()).map(piece_name).collect();
    let plan = plan_rows(&durations, &labels, options);
    // Steps no longer than the measured pieces' own Magnus steps (a cut piece is shorter).
    let mut measured_durations = vec![0.0; file.origins.last().map_or(0, |o| o + 1)];
    for (k, d) in durations.iter().enumerate() {
        measured_durations[file.origins[k]] += d;
    }
    let h_max: Vec<f64> =
        file.origins.iter().map(|&o| measured_durations[o] / e.flip.steps_per_phase.max(1) as f64).collect();
    let max_step = h_max.iter().copied().fold(0.0, f64::max);
    let rate = |piece: usize, s: f64| {
        let st = traj.piece_state(piece, s);
        paper.map_or_else(|| model.body_rate(&st), |cat| body_rate(&cat, st.q, st.qd))
    };
    let attitude = orientations(rate, &plan, &h_max);
    // The measured jumps, at the file's piece boundaries: after the last file piece of each
    // measured piece.
    let last_piece_of = |o: usize| file.origins.iter().rposition(|&x| x == o).unwrap_or(o);
    let jumps: Vec<VelocityJump> =
        e.jumps.iter().map(|j| VelocityJump { after_piece: last_piece_of(j.after_piece), ..*j }).collect();
    let source = TorqueSource::of(&model);
    let joint = problem.cat.joint;
    let columns = columns(joint);
    let mut w = csv::Writer::from_writer(Vec::new());
    w.write_record(columns.iter().map(|c| c.0)).map_err(csv_error)?;
    for (row, (q, angles)) in plan.iter().zip(&attitude) {
        let st = traj.piece_state(row.piece, row.local);
        let torques = source.at(traj, row.piece, row.local, &st);
        let tau = torques.tau;
        let jump = match row.marker {
            Marker::Start => jumps.iter().find(|j| j.after_piece + 1 == row.piece),
            _ => None,
        };
        let impulse = jump.map_or([0.0; 2], |j| j.impulse);
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
        if joint != Joint::Universal {
            let impulse_z = jump.map_or(0.0, |j| {
                let dq = [j.rates_after[0] - j.rates_before[0], j.rates_after[1] - j.rates_before[1]];
                model.jump_impulse_couple(st.q, dq).couple.z
            });
            record.extend(ball_columns(joint, &st, torques.couple.z, impulse_z).map(num));
        }
        w.write_record(&record).map_err(csv_error)?;
    }
    let csv = csv_text(w)?;
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
        conventions: Conventions::new(joint),
        columns: columns.iter().map(|c| Column { name: c.0.into(), unit: c.1.into(), meaning: c.2.into() }).collect(),
        sampling: Sampling {
            kind: if options.rate_hz.is_some() { "uniform" } else { "per-piece" }.into(),
            rate_hz: options.rate_hz,
            steps_per_piece: options.rate_hz.is_none().then_some(options.steps_per_piece),
            rows: plan.len(),
            duration_s: durations.iter().sum(),
        },
        pieces: piece_infos(&plan, piece_name),
        jumps: jumps.iter().map(JumpRecord::from).collect(),
        orientation: OrientationInfo {
            engine: "exact".into(),
            tolerance_rad: problem.exact.tolerance,
            max_step_s: max_step,
            error_estimate_rad: e.flip.error_estimate,
            converged: e.flip.converged,
            final_twist_deg: e.flip.twist.to_degrees(),
            final_swing_deg: e.flip.swing.to_degrees(),
        },
        interpolation: interpolation_advice(&jumps),
        motors: motor_sizing(e),
    };
    Ok(ScheduleFile { csv, sidecar })
}

/// The pieces of a file of rows `plan`, piece `k` named `name(k)`.
pub(crate) fn piece_infos(plan: &[Row], name: impl Fn(usize) -> String) -> Vec<PieceInfo> {
    let mut pieces: Vec<PieceInfo> = Vec::new();
    for (i, row) in plan.iter().enumerate() {
        let same_piece = pieces.len() == row.piece + 1;
        match pieces.last_mut() {
            Some(p) if same_piece => {
                p.last_row = i;
                p.end_s = row.time;
            }
            _ => pieces.push(PieceInfo {
                name: name(row.piece),
                start_s: row.time,
                end_s: row.time,
                first_row: i,
                last_row: i,
            }),
        }
    }
    pieces
}

/// The no-twist joint's [`NO_TWIST_COLUMNS`] at `st`: the couple's and the jump impulse's
/// components about A's `z`, B's orientation relative to A as a quaternion `(w, x, y, z)` with
/// `w ≥ 0`, and B's angular velocity relative to A in B's frame.
fn ball_columns(joint: Joint, st: &JointState, tau_z: f64, impulse_z: f64) -> [f64; 9] {
    let [w, x, y, z, wx, wy, wz] = relative_motion(joint, &st.q, &st.qd);
    [tau_z, impulse_z, w, x, y, z, wx, wy, wz]
}

/// A ball joint's reading of `joint` at coordinates `q`, rates `qd`: the child's orientation
/// relative to its parent as a unit quaternion `(w, x, y, z)` with `w ≥ 0`, then the child's
/// angular velocity relative to its parent in the child's frame (MuJoCo's ball `qpos`, `qvel`).
pub(crate) fn relative_motion(joint: Joint, q: &[f64], qd: &[f64]) -> [f64; 7] {
    let r = joint.rotation(q);
    let rel = UnitQuaternion::from_rotation_matrix(&Rotation3::from_matrix_unchecked(r));
    let rel = if rel.w < 0.0 { UnitQuaternion::new_unchecked(-rel.into_inner()) } else { rel };
    let w = r.transpose() * joint.relative_rate(q, qd);
    [rel.w, rel.i, rel.j, rel.k, w.x, w.y, w.z]
}

/// The motor-sizing figures of a measured trajectory: each joint's peak with when, and what the
/// trajectory asks of the motors.
fn motor_sizing(e: &Evaluation) -> MotorSizing {
    let largest = |j: usize| {
        e.peaks.per_piece.iter().map(|p| p[j]).fold(Peak { value: 0.0, time: 0.0 }, |a, b| {
            if b.value > a.value {
                b
            } else {
                a
            }
        })
    };
    MotorSizing {
        peak_torque_nm: [largest(0), largest(1)],
        within_motors: e.motors.within(),
        verdict: e.motors.verdict(),
        demand: e.motors.clone(),
    }
}

/// The text a CSV writer wrote.
pub(crate) fn csv_text(w: csv::Writer<Vec<u8>>) -> Result<String, ExchangeError> {
    let bytes = w.into_inner().map_err(|e| ExchangeError::Csv(e.to_string()))?;
    String::from_utf8(bytes).map_err(|e| ExchangeError::Csv(e.to_string()))
}

pub(crate) fn csv_error(e: csv::Error) -> ExchangeError {
    ExchangeError::Csv(e.to_string())
}

fn interpolation_advice(jumps: &[VelocityJump]) -> String {
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
pub(crate) enum Marker {
    /// An ordinary row.
    Plain,
    /// The last row of a piece followed by another at the same time.
    End,
    /// The first row of a piece that follows another.
    Start,
}

impl Marker {
    pub(crate) fn text(self) -> &'static str {
        match self {
            Marker::Plain => "",
            Marker::End => "end",
            Marker::Start => "start",
        }
    }
}

/// Where a row is: piece, local time in it, global time, marker.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Row {
    pub(crate) piece: usize,
    pub(crate) local: f64,
    pub(crate) time: f64,
    pub(crate) marker: Marker,
}

/// The rows of the file: each piece from its start to its end, boundary times twice. The grid
/// is `t = k / rate` or, per phase (consecutive pieces with the same label), `steps` equal
/// intervals of the phase; grid points within `10⁻⁶` of a grid step of a boundary are dropped.
pub(crate) fn plan_rows(durations: &[f64], labels: &[String], options: &ExportOptions) -> Vec<Row> {
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

/// A's orientation at every row: Magnus steps no longer than `h_max[piece]` from row to row,
/// `body_rate(piece, s)` A's angular velocity (A's frame) at local time `s` of `piece`.
pub(crate) fn orientations(
    body_rate: impl Fn(usize, f64) -> Vector3<f64>,
    rows: &[Row],
    h_max: &[f64],
) -> Vec<(UnitQuaternion<f64>, SwingTwist)> {
    let c = 15f64.sqrt() / 10.0;
    let mut r = UnitQuaternion::identity();
    let mut tracker = TwistTracker::default();
    let mut angles = tracker.update(&r);
    let mut out = Vec::with_capacity(rows.len());
    let mut prev: Option<Row> = None;
    for row in rows {
        if let Some(p) = prev.filter(|p| p.piece == row.piece) {
            let h_max = h_max[row.piece];
            let span = row.local - p.local;
            let n = ((span / h_max) * (1.0 - 1e-12)).ceil().max(1.0) as usize;
            let h = span / n as f64;
            let rate = |s: f64| body_rate(row.piece, s);
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
