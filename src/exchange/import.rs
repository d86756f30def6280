//! Bring your own schedule: a CSV of joint angles read into a [`Trajectory`] the engines run.
//!
//! # The file
//!
//! A header row names the columns (case-insensitive, in any order, other columns ignored; a
//! quantity named by two columns, or a `phase` column given twice, is refused: which to read
//! would be a guess):
//!
//! | quantity | accepted names | unit |
//! |---|---|---|
//! | time | `t_s`, `t`, `time_s`, `time` | s |
//! | joint angles | `q1_rad`, `q1`; `q2_rad`, `q2` | rad |
//! | rates (optional) | `qd1_rad_s`, `qd1`; `qd2_rad_s`, `qd2` | rad/s |
//! | accelerations (optional, need the rates) | `qdd1_rad_s2`, `qdd1`; `qdd2_rad_s2`, `qdd2` | rad/s² |
//! | piece names (optional) | `phase` | |
//!
//! Lines starting with `#` are comments. Times must increase strictly, except that one time may
//! be written twice in a row: that splits the file into **pieces** there (the first row ends a
//! piece with its one-sided values, the second starts the next), which is how rates may jump
//! (catflip's own files mark such pairs `end`/`start` in their `boundary` column). Phases are
//! optional: a file without duplicated times is one piece. The first row's time is the start
//! (`t = 0` of the trajectory); times far from zero lose their resolution in double precision
//! ([`TimeRounding`]), so a file is refused when that rounding reaches
//! [`TIME_ROUNDING_REFUSED`] of the rows' mean spacing. Conventions are the README's ("Replay elsewhere": `R_AB = Rx(q1) · Ry(q2)`).
//!
//! # Interpolation
//!
//! Each piece is interpolated on its own ([`crate::exchange::interp`]): quintic Hermite when
//! `q̇` and `q̈` are given (error `O(h⁶)` in `q`, `O(h⁴)` in `q̈`), cubic Hermite with `q̇` alone
//! (`O(h⁴)`, `q̈` `O(h²)` and discontinuous at the rows), else the not-a-knot cubic spline
//! (`O(h⁴)`; at least four rows per piece). A Hermite piece needs two rows.
//!
//! A rate jump between pieces is reported when the two one-sided rates differ by more than
//! round-off; for the spline, whose rates at a piece's ends are interpolated, not given, also by
//! more than [`JUMP_SAFETY`] times their estimated error ([`ImportedPiece::end_rate_error`]).
//!
//! Every defect is an [`ImportError`] naming the file, the line and the column; nothing panics.

use std::borrow::Cow;
use std::path::Path;

use serde::Serialize;

use crate::exchange::interp::Piecewise;
use crate::exchange::table::{error_message, record_line};
use crate::numeric::numfmt::sig;
use crate::problem::error::one_line;
use crate::schedule::{JointState, Trajectory};

/// Why a schedule file could not be read.
#[derive(Debug, thiserror::Error, PartialEq)]
pub enum ImportError {
    /// The problem asks for what this computation does not model (the problem's message).
    #[error("{0}")]
    Problem(String),
    /// The file could not be read.
    #[error("cannot read schedule file {path}: {message}")]
    Io {
        /// The path.
        path: String,
        /// What the OS said.
        message: String,
    },
    /// The text is not well-formed CSV (e.g. a row with too few fields).
    #[error("{path}: line {line}: {message}")]
    Csv {
        /// The file.
        path: String,
        /// The line (1 = the header).
        line: u64,
        /// The CSV parser's message.
        message: String,
    },
    /// A required column is absent.
    #[error("{path}: line 1: no column `{column}` (accepted names: {accepted}); the header has: {header}")]
    MissingColumn {
        /// The file.
        path: String,
        /// The canonical name.
        column: String,
        /// The names accepted for it.
        accepted: String,
        /// The header found.
        header: String,
    },
    /// Two columns name one quantity (`q1_rad` twice, or `t` beside `t_s`): which to read is a
    /// guess.
    #[error("{path}: line 1: columns {first} and {second} (`{a}`, `{b}`) both give {what}: keep one")]
    RepeatedColumn {
        /// The file.
        path: String,
        /// The columns, counted from 1.
        first: usize,
        /// The second.
        second: usize,
        /// Their names as the header spells them.
        a: String,
        /// The second's.
        b: String,
        /// The quantity, in words.
        what: &'static str,
    },
    /// One joint has a rate or acceleration column and the other not, or accelerations come
    /// without rates.
    #[error("{path}: line 1: column `{present}` needs column `{missing}`")]
    IncompleteColumns {
        /// The file.
        path: String,
        /// The column found.
        present: String,
        /// The column missing.
        missing: String,
    },
    /// A field is not a number.
    #[error("{path}: line {line}, column {column} (`{name}`): `{value}` is not a number")]
    NotANumber {
        /// The file.
        path: String,
        /// The line.
        line: u64,
        /// The column, 1-based.
        column: usize,
        /// The column's name.
        name: String,
        /// The field.
        value: String,
    },
    /// A field is NaN or infinite.
    #[error("{path}: line {line}, column {column} (`{name}`): {value} is not finite")]
    NotFinite {
        /// The file.
        path: String,
        /// The line.
        line: u64,
        /// The column, 1-based.
        column: usize,
        /// The column's name.
        name: String,
        /// The value.
        value: f64,
    },
    /// Time goes backwards, or repeats more than twice.
    #[error("{path}: line {line}, column {column} (`{name}`): t = {value} s after t = {previous} s: times must increase (a time may be written twice in a row, to split pieces, but not more)")]
    TimeNotIncreasing {
        /// The file.
        path: String,
        /// The line.
        line: u64,
        /// The time column, 1-based.
        column: usize,
        /// Its name.
        name: String,
        /// The previous row's time, s.
        previous: f64,
        /// This row's, s.
        value: f64,
    },
    /// A piece has fewer rows than its interpolation needs.
    #[error("{path}: lines {first_line}–{last_line}: a piece of {rows} row(s); {scheme} needs at least {needed}")]
    TooFewRows {
        /// The file.
        path: String,
        /// The piece's first line.
        first_line: u64,
        /// Its last line.
        last_line: u64,
        /// Rows in it.
        rows: usize,
        /// Rows needed.
        needed: usize,
        /// The scheme.
        scheme: Interpolation,
    },
    /// A joint angle too large to be an angle in radians.
    #[error("{path}: line {line}, column {column} (`{name}`): {value:e} rad is not a joint angle (more than {limit:e} rad, {} turns); angles must be in radians", sig(*turns, 3))]
    AbsurdAngle {
        /// The file.
        path: String,
        /// The line.
        line: u64,
        /// The column, 1-based.
        column: usize,
        /// The column's name.
        name: String,
        /// The value.
        value: f64,
        /// The largest accepted magnitude, rad ([`MAX_ANGLE_RAD`]).
        limit: f64,
        /// The value in turns.
        turns: f64,
    },
    /// A rate or an acceleration too large to be a joint's ([`FASTEST_TURN_SHARE`]): the engines
    /// cannot use it.
    #[error("{path}: line {line}, column {column} (`{name}`): {value:e} {unit} is not a joint {quantity}: more than {} {unit} ({}), too large for the engines; {quantity}s must be in {unit}", sig(*limit, 2), fastest_turn(*duration_s, *power), unit = derivative(*power).1, quantity = derivative(*power).0)]
    AbsurdRate {
        /// The file.
        path: String,
        /// The line.
        line: u64,
        /// The column, 1-based.
        column: usize,
        /// The column's name.
        name: String,
        /// The value, rad/s or rad/s².
        value: f64,
        /// The largest accepted magnitude, rad/s or rad/s².
        limit: f64,
        /// The schedule's duration (its last time less its first), s.
        duration_s: f64,
        /// The time derivative: 1 for a rate (rad/s), 2 for an acceleration (rad/s²).
        power: u8,
    },
    /// A time written twice (a piece split) with different angles: the joints would have to jump.
    #[error("{path}: lines {lines:?}: t = {time} s is written twice with `{name}` = {before} then {after} rad: a joint cannot jump (a repeated time splits pieces where the rates may jump, not the angles); write the same angles on both rows")]
    PositionJump {
        /// The file.
        path: String,
        /// The two lines.
        lines: [u64; 2],
        /// The time, s (the file's clock).
        time: f64,
        /// The angle column's name.
        name: String,
        /// The angle on the first row, rad.
        before: f64,
        /// The angle on the second row, rad.
        after: f64,
    },
    /// The schedule's duration is so far from the fall's that its times cannot be seconds.
    #[error("{path}: column `{name}`: the schedule lasts {duration_s:e} s against a fall of {fall_s} s (drop.height = {height} m, drop.gravity = {gravity} m/s²): {factor:.1e} times too {direction}; times must be in seconds")]
    AbsurdDuration {
        /// The file.
        path: String,
        /// The time column's name.
        name: String,
        /// The schedule's duration, s.
        duration_s: f64,
        /// The fall time, s.
        fall_s: f64,
        /// The problem's drop height, m.
        height: f64,
        /// The problem's gravity, m/s².
        gravity: f64,
        /// How many times too long or short.
        factor: f64,
        /// `long` or `short`.
        direction: String,
    },
    /// The times are so large against the rows' spacing that double precision cannot keep the
    /// rows apart (times near 1e15 s are held to 0.125 s).
    #[error("{path}: {what}, so the rows run together; write the times from the start of the fall (t = 0)")]
    TimesUnresolved {
        /// The file.
        path: String,
        /// The column, the times' size and rounding against the spacing ([`TimeRounding::describe`]).
        what: String,
    },
    /// The exact engine could not compute a number the report needs (it came out NaN or
    /// infinite): nothing is reported rather than a wrong number.
    #[error("{path}: the exact engine could not compute {quantity} for this schedule (it is not finite): the file's angles, rates or times are too large or too small to evaluate")]
    NotComputable {
        /// The file.
        path: String,
        /// What could not be computed.
        quantity: String,
    },
    /// The spline's linear system was singular (times too unevenly spaced).
    #[error("{path}: lines {first_line}–{last_line}: the not-a-knot spline's system is singular (times too unevenly spaced); give the rates q̇ too")]
    SplineFailed {
        /// The file.
        path: String,
        /// The piece's first line.
        first_line: u64,
        /// Its last line.
        last_line: u64,
    },
}

/// The problem's refusal, in its words.
impl From<crate::problem::ProblemError> for ImportError {
    fn from(e: crate::problem::ProblemError) -> Self {
        ImportError::Problem(e.to_string())
    }
}

impl From<crate::engines::models::ModelError> for ImportError {
    /// A cat model that cannot run a two-coordinate schedule (the spherical joint).
    fn from(e: crate::engines::models::ModelError) -> Self {
        ImportError::Problem(e.to_string())
    }
}

/// The interpolation scheme of an imported schedule.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Interpolation {
    /// Quintic Hermite through `q`, `q̇`, `q̈`.
    QuinticHermite,
    /// Cubic Hermite through `q`, `q̇`.
    CubicHermite,
    /// Not-a-knot cubic spline through `q`.
    NotAKnotSpline,
}

impl Interpolation {
    /// Rows a piece needs.
    pub fn min_rows(self) -> usize {
        match self {
            Interpolation::NotAKnotSpline => 4,
            _ => 2,
        }
    }
}

impl std::fmt::Display for Interpolation {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Interpolation::QuinticHermite => "quintic Hermite (q, q̇, q̈)",
            Interpolation::CubicHermite => "cubic Hermite (q, q̇)",
            Interpolation::NotAKnotSpline => "the not-a-knot cubic spline (q)",
        })
    }
}

/// One smooth piece of an imported schedule.
#[derive(Clone, Debug, PartialEq)]
pub struct ImportedPiece {
    /// Its name: the `phase` column of its first row, else `piece-K`.
    pub name: String,
    /// Its start on the file's clock, s.
    pub file_start: f64,
    /// Lines of the file it came from (first, last).
    pub lines: (u64, u64),
    /// Estimated error of the interpolated rates `|δq̇|` (both joints) at the piece's start and
    /// end, rad/s: zero when the file gives the rates; for the spline, `|q̇_h − q̇_2h|/7` from a
    /// second spline through every other row (the rates are `O(h³)`), infinite when the piece has
    /// too few rows for that second spline (fewer than seven).
    pub end_rate_error: [f64; 2],
    /// The file's rows of this piece, in order.
    pub rows: Vec<Row>,
    joints: [Piecewise; 2],
}

/// One data row of a schedule file, as written (angles rad, rates rad/s, accelerations rad/s²).
#[derive(Clone, Debug, PartialEq)]
pub struct Row {
    /// The line it is on.
    pub line: u64,
    /// Its time on the file's clock, s.
    pub t: f64,
    /// `q1`, `q2`.
    pub q: [f64; 2],
    /// `q̇1`, `q̇2`, when the file gives them.
    pub qd: Option<[f64; 2]>,
    /// `q̈1`, `q̈2`, when the file gives them.
    pub qdd: Option<[f64; 2]>,
    /// The `phase` column, if any.
    pub phase: Option<String>,
}

/// The names of the columns read, as the header spells them (lower-cased).
#[derive(Clone, Debug, PartialEq)]
pub struct Columns {
    /// Time.
    pub time: String,
    /// Joint angles.
    pub angles: [String; 2],
    /// Joint rates, when given.
    pub rates: Option<[String; 2]>,
    /// Joint accelerations, when given.
    pub accels: Option<[String; 2]>,
}

/// The largest joint angle accepted, rad: a joint turned further (more than 159 turns, or 17
/// if the column holds degrees) is not a joint angle, and the engines' numbers would be
/// meaningless.
pub const MAX_ANGLE_RAD: f64 = 1e3;

/// The shortest time, as a share of a schedule's duration `T`, in which a joint may turn by
/// [`MAX_ANGLE_RAD`]: a rate beyond `MAX_ANGLE_RAD / (share · T)` or an acceleration beyond
/// `MAX_ANGLE_RAD / (share · T)²` is no joint's (on a fall of 1.43 s, 7·10⁸ rad/s and
/// 5·10¹⁴ rad/s²), and the engines' numbers would overflow. The limits scale with the file's own
/// times, so a file in the wrong time unit is refused for its duration, not here.
pub const FASTEST_TURN_SHARE: f64 = 1e-6;

/// The name and unit of the angles' `power`-th time derivative (1 or 2).
fn derivative(power: u8) -> (&'static str, &'static str) {
    if power == 1 {
        ("rate", "rad/s")
    } else {
        ("acceleration", "rad/s²")
    }
}

/// The limit's basis in words: `1000 rad in 1.4e-6 s, a millionth of the schedule's 1.4 s`
/// (per that time squared for an acceleration, `power` 2).
fn fastest_turn(duration_s: f64, power: u8) -> String {
    let tau = FASTEST_TURN_SHARE * duration_s;
    let per = if power == 1 { format!("in {} s", sig(tau, 2)) } else { format!("per ({} s)²", sig(tau, 2)) };
    format!("{} rad {per}, a millionth of the schedule's {} s", sig(MAX_ANGLE_RAD, 3), sig(duration_s, 6))
}

/// The largest difference of the angles on the two rows of a repeated time, rad: below any
/// joint's resolution, above the round-off of a file written to seven digits or more.
pub const POSITION_JUMP_TOLERANCE: f64 = 1e-6;

/// The share of the rows' mean spacing that the times' rounding may reach before the file is
/// refused ([`TimeRounding`]): beyond it the rows' spacing is wrong by 0.1 % and more, and the
/// interpolated accelerations with it.
pub const TIME_ROUNDING_REFUSED: f64 = 1e-3;
/// The share above which the times' rounding is warned.
pub const TIME_ROUNDING_WARNED: f64 = 1e-6;

/// How finely a file's times are held: a time `t` is stored in double precision to within
/// `|t| ε/2`, so times far from zero (a clock's epoch, not the fall's start) move the rows by that
/// much, and near 1e15 s rows 0.7 ms apart run together.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TimeRounding {
    /// The largest `|t|` of the file, s.
    pub largest: f64,
    /// Its rounding, `|t| ε/2`, s.
    pub rounding: f64,
    /// The rows' mean spacing, s.
    pub spacing: f64,
}

impl TimeRounding {
    /// The rounding of a file's times; `None` for fewer than two rows or no time between them.
    pub fn of(times: &[f64]) -> Option<TimeRounding> {
        let (first, last) = (times.first()?, times.last()?);
        let largest = times.iter().map(|t| t.abs()).fold(0.0, f64::max);
        let spacing = (last - first) / (times.len() - 1) as f64;
        (spacing > 0.0).then_some(TimeRounding { largest, rounding: largest * f64::EPSILON / 2.0, spacing })
    }

    /// The rounding as a share of the spacing.
    pub fn share(&self) -> f64 {
        self.rounding / self.spacing
    }

    /// In words, for the time column `name`: ``column `t_s`: times near 1e15 s are held in
    /// double precision only to ±0.11 s, 156 times the rows' mean spacing of 0.000714 s``.
    pub fn describe(&self, name: &str) -> String {
        use crate::numeric::numfmt::sig;
        let share = self.share();
        let share =
            if share >= 1.0 { format!("{} times", sig(share, 3)) } else { format!("{} % of", sig(100.0 * share, 2)) };
        format!(
            "column `{name}`: times near {} s are held in double precision only to ±{} s, {share} the rows' mean spacing of {} s",
            sig(self.largest, 6),
            sig(self.rounding, 2),
            sig(self.spacing, 3)
        )
    }
}

/// How many times the estimated rate error a difference of rates must exceed to be a jump.
pub const JUMP_SAFETY: f64 = 10.0;

/// The spline's rate error at both ends of a piece, estimated from a spline on every other knot.
fn spline_end_rate_error(knots: &[f64], q: [&[f64]; 2], fine: [&Piecewise; 2]) -> [f64; 2] {
    let n = knots.len();
    let mut idx: Vec<usize> = (0..n).step_by(2).collect();
    if idx.last() != Some(&(n - 1)) {
        idx.push(n - 1);
    }
    let coarse_knots: Vec<f64> = idx.iter().map(|&i| knots[i]).collect();
    let coarse: Option<Vec<Piecewise>> = q
        .iter()
        .map(|qj| Piecewise::not_a_knot(&coarse_knots, &idx.iter().map(|&i| qj[i]).collect::<Vec<_>>()))
        .collect();
    match coarse {
        Some(c) if n >= 7 => [knots[0], knots[n - 1]].map(|t| {
            let d: Vec<f64> = (0..2).map(|j| (fine[j].eval(t).rate - c[j].eval(t).rate) / 7.0).collect();
            d[0].hypot(d[1])
        }),
        _ => [f64::INFINITY; 2],
    }
}

/// A schedule read from a CSV file: a [`Trajectory`] with one piece per smooth stretch.
#[derive(Clone, Debug, PartialEq)]
pub struct ImportedSchedule {
    /// The file it came from.
    pub path: String,
    /// The interpolation scheme.
    pub interpolation: Interpolation,
    /// Data rows read.
    pub rows: usize,
    /// The pieces, in order.
    pub pieces: Vec<ImportedPiece>,
    /// The columns read.
    pub columns: Columns,
}

impl Trajectory for ImportedSchedule {
    fn piece_durations(&self) -> Vec<f64> {
        self.pieces
            .iter()
            .map(|p| {
                let k = p.joints[0].knots();
                k[k.len() - 1] - k[0]
            })
            .collect()
    }

    fn piece_state(&self, piece: usize, s: f64) -> JointState {
        let p = &self.pieces[piece.min(self.pieces.len() - 1)];
        let d = p.joints.each_ref().map(|j| j.eval(s));
        JointState { q: [d[0].value, d[1].value], qd: [d[0].rate, d[1].rate], qdd: [d[0].accel, d[1].accel] }
    }

    /// Every inner row: the interpolant is a polynomial between rows only (cubic Hermite's `q̈`
    /// jumps there; the other schemes' higher derivatives do), so the exact engine steps row
    /// interval by row interval and the peak torque is sampled at every row, from both sides.
    fn acceleration_jumps(&self, piece: usize) -> Vec<f64> {
        let k = self.pieces[piece.min(self.pieces.len() - 1)].joints[0].knots();
        k[1..k.len() - 1].to_vec()
    }

    fn piece_state_before(&self, piece: usize, s: f64) -> JointState {
        let p = &self.pieces[piece.min(self.pieces.len() - 1)];
        let d = p.joints.each_ref().map(|j| j.eval_before(s));
        JointState { q: [d[0].value, d[1].value], qd: [d[0].rate, d[1].rate], qdd: [d[0].accel, d[1].accel] }
    }

    /// [`JUMP_SAFETY`] times the two sides' [`ImportedPiece::end_rate_error`] (zero where the
    /// file gives the rates; infinite where a piece is too short to estimate them).
    fn boundary_rate_uncertainty(&self, k: usize) -> f64 {
        match (self.pieces.get(k), self.pieces.get(k + 1)) {
            (Some(a), Some(b)) => JUMP_SAFETY * (a.end_rate_error[1] + b.end_rate_error[0]),
            _ => 0.0,
        }
    }
}

/// Reads a schedule CSV file.
pub fn read_schedule(path: &Path) -> Result<ImportedSchedule, ImportError> {
    let name = path.display().to_string();
    let text =
        std::fs::read_to_string(path).map_err(|e| ImportError::Io { path: name.clone(), message: e.to_string() })?;
    parse_schedule(&text, &name)
}

const TIME: [&str; 4] = ["t_s", "t", "time_s", "time"];
const ANGLES: [[&str; 2]; 2] = [["q1_rad", "q1"], ["q2_rad", "q2"]];
const RATES: [[&str; 2]; 2] = [["qd1_rad_s", "qd1"], ["qd2_rad_s", "qd2"]];
const ACCELS: [[&str; 2]; 2] = [["qdd1_rad_s2", "qdd1"], ["qdd2_rad_s2", "qdd2"]];

/// Parses a schedule CSV text; `origin` names it in errors.
pub fn parse_schedule(text: &str, origin: &str) -> Result<ImportedSchedule, ImportError> {
    let path = origin.to_string();
    // Every line end as `\n` (a file's `\r\n` or lone `\r`): the reader ends a comment at `\n`
    // only, so a comment in a file of `\r` line ends would swallow the rows after it.
    let text: Cow<str> =
        if text.contains('\r') { text.replace("\r\n", "\n").replace('\r', "\n").into() } else { text.into() };
    let mut reader = csv::ReaderBuilder::new().trim(csv::Trim::All).comment(Some(b'#')).from_reader(text.as_bytes());
    let line_of = |p: &csv::Position| record_line(text.as_bytes(), p, Some(b'#'));
    let csv_err = |e: csv::Error| ImportError::Csv {
        path: path.clone(),
        line: e.position().map_or(1, line_of),
        message: error_message(&e),
    };
    let header: Vec<String> = reader.headers().map_err(csv_err)?.iter().map(|h| h.to_lowercase()).collect();
    let find = |names: &[&str]| names.iter().find_map(|n| header.iter().position(|h| h == n));
    // Each quantity from one column: a second that names it too would be read or ignored silently.
    let quantities: [(&[&str], &'static str); 8] = [
        (&TIME, "the time"),
        (&ANGLES[0], "joint 1's angle"),
        (&ANGLES[1], "joint 2's angle"),
        (&RATES[0], "joint 1's rate"),
        (&RATES[1], "joint 2's rate"),
        (&ACCELS[0], "joint 1's acceleration"),
        (&ACCELS[1], "joint 2's acceleration"),
        (&["phase"], "the phase"),
    ];
    for (names, what) in quantities {
        let at: Vec<usize> = (0..header.len()).filter(|&c| names.contains(&header[c].as_str())).collect();
        if let [first, second, ..] = at[..] {
            return Err(ImportError::RepeatedColumn {
                path: path.clone(),
                first: first + 1,
                second: second + 1,
                a: one_line(&header[first]),
                b: one_line(&header[second]),
                what,
            });
        }
    }
    let require = |names: &[&str]| {
        find(names).ok_or_else(|| ImportError::MissingColumn {
            path: path.clone(),
            column: names[0].into(),
            accepted: names.join(", "),
            header: header.join(","),
        })
    };
    let t_col = require(&TIME)?;
    let q_cols = [require(&ANGLES[0])?, require(&ANGLES[1])?];
    let pair = |names: [[&str; 2]; 2]| -> Result<Option<[usize; 2]>, ImportError> {
        match (find(&names[0]), find(&names[1])) {
            (Some(a), Some(b)) => Ok(Some([a, b])),
            (None, None) => Ok(None),
            (Some(_), None) => Err(incomplete(&path, names[0][0], names[1][0])),
            (None, Some(_)) => Err(incomplete(&path, names[1][0], names[0][0])),
        }
    };
    let qd_cols = pair(RATES)?;
    let qdd_cols = pair(ACCELS)?;
    if qdd_cols.is_some() && qd_cols.is_none() {
        return Err(incomplete(&path, ACCELS[0][0], RATES[0][0]));
    }
    let interpolation = match (qd_cols, qdd_cols) {
        (Some(_), Some(_)) => Interpolation::QuinticHermite,
        (Some(_), None) => Interpolation::CubicHermite,
        _ => Interpolation::NotAKnotSpline,
    };
    let names = |cols: [usize; 2]| cols.map(|c| header[c].clone());
    let columns = Columns {
        time: header[t_col].clone(),
        angles: names(q_cols),
        rates: qd_cols.map(names),
        accels: qdd_cols.map(names),
    };
    let phase_col = header.iter().position(|h| h == "phase");
    let mut samples = Vec::new();
    for record in reader.records() {
        let record = record.map_err(csv_err)?;
        let line = record.position().map_or(0, line_of);
        let number = |col: usize| -> Result<f64, ImportError> {
            let field = record.get(col).unwrap_or("");
            let value: f64 = field.parse().map_err(|_| ImportError::NotANumber {
                path: path.clone(),
                line,
                column: col + 1,
                name: one_line(&header[col]),
                value: one_line(field),
            })?;
            if value.is_finite() {
                Ok(value)
            } else {
                Err(ImportError::NotFinite {
                    path: path.clone(),
                    line,
                    column: col + 1,
                    name: header[col].clone(),
                    value,
                })
            }
        };
        let angle = |col: usize| -> Result<f64, ImportError> {
            let value = number(col)?;
            if value.abs() <= MAX_ANGLE_RAD {
                Ok(value)
            } else {
                Err(ImportError::AbsurdAngle {
                    path: path.clone(),
                    line,
                    column: col + 1,
                    name: header[col].clone(),
                    value,
                    limit: MAX_ANGLE_RAD,
                    turns: value.abs() / std::f64::consts::TAU,
                })
            }
        };
        let both = |cols: Option<[usize; 2]>| -> Result<Option<[f64; 2]>, ImportError> {
            cols.map(|[a, b]| Ok([number(a)?, number(b)?])).transpose()
        };
        samples.push(Row {
            line,
            t: number(t_col)?,
            q: [angle(q_cols[0])?, angle(q_cols[1])?],
            qd: both(qd_cols)?,
            qdd: both(qdd_cols)?,
            phase: phase_col.and_then(|c| record.get(c)).filter(|s| !s.is_empty()).map(str::to_string),
        });
    }
    let times: Vec<f64> = samples.iter().map(|r| r.t).collect();
    if let Some(r) = TimeRounding::of(&times).filter(|r| r.share() > TIME_ROUNDING_REFUSED) {
        return Err(ImportError::TimesUnresolved { path, what: r.describe(&header[t_col]) });
    }
    let groups = split_pieces(&samples, &path, t_col, &header[t_col])?;
    check_continuity(&groups, &path, &columns)?;
    check_magnitudes(&samples, &path, &header, qd_cols, qdd_cols)?;
    let pieces = groups
        .iter()
        .enumerate()
        .map(|(k, g)| build_piece(g, k, interpolation, &path))
        .collect::<Result<Vec<_>, _>>()?;
    if pieces.is_empty() {
        return Err(ImportError::TooFewRows {
            path,
            first_line: 2,
            last_line: 2,
            rows: 0,
            needed: interpolation.min_rows(),
            scheme: interpolation,
        });
    }
    Ok(ImportedSchedule { path, interpolation, rows: samples.len(), pieces, columns })
}

fn incomplete(path: &str, present: &str, missing: &str) -> ImportError {
    ImportError::IncompleteColumns { path: path.into(), present: present.into(), missing: missing.into() }
}

/// Splits the rows at duplicated times; checks that time increases otherwise.
fn split_pieces<'a>(samples: &'a [Row], path: &str, t_col: usize, t_name: &str) -> Result<Vec<&'a [Row]>, ImportError> {
    let mut groups = Vec::new();
    let mut start = 0;
    for i in 1..samples.len() {
        let (prev, this) = (samples[i - 1].t, samples[i].t);
        let backwards = this < prev;
        let duplicate = this <= prev;
        let repeated = duplicate && i == start + 1 && start > 0;
        if backwards || repeated {
            return Err(ImportError::TimeNotIncreasing {
                path: path.into(),
                line: samples[i].line,
                column: t_col + 1,
                name: t_name.into(),
                previous: prev,
                value: this,
            });
        }
        if duplicate {
            groups.push(&samples[start..i]);
            start = i;
        }
    }
    if start < samples.len() {
        groups.push(&samples[start..]);
    }
    Ok(groups)
}

/// Rates and accelerations within [`FASTEST_TURN_SHARE`]'s limits of the file's duration; the
/// first row beyond them (and its first column) is refused.
fn check_magnitudes(
    samples: &[Row],
    path: &str,
    header: &[String],
    rates: Option<[usize; 2]>,
    accels: Option<[usize; 2]>,
) -> Result<(), ImportError> {
    let (Some(first), Some(last)) = (samples.first(), samples.last()) else { return Ok(()) };
    let duration = last.t - first.t;
    // The times increase (checked before), so only a file of one time has no duration.
    if duration <= 0.0 {
        return Ok(());
    }
    let tau = FASTEST_TURN_SHARE * duration;
    // The limit of the angles' `power`-th time derivative.
    let limit = |power: u8| MAX_ANGLE_RAD / tau.powi(i32::from(power));
    for row in samples {
        // The row's rates and accelerations as (column, value, power), in the file's column order.
        let mut fields: Vec<(usize, f64, u8)> = Vec::with_capacity(4);
        for (cols, values, power) in [(rates, row.qd, 1), (accels, row.qdd, 2)] {
            if let (Some(c), Some(v)) = (cols, values) {
                fields.extend([(c[0], v[0], power), (c[1], v[1], power)]);
            }
        }
        fields.sort_by_key(|f| f.0);
        if let Some(&(col, value, power)) = fields.iter().find(|f| f.1.abs() > limit(f.2)) {
            return Err(ImportError::AbsurdRate {
                path: path.into(),
                line: row.line,
                column: col + 1,
                name: header[col].clone(),
                value,
                limit: limit(power),
                duration_s: duration,
                power,
            });
        }
    }
    Ok(())
}

/// The angles on the two rows of a repeated time must agree ([`POSITION_JUMP_TOLERANCE`]): a
/// piece split is where the rates may jump, never the angles.
fn check_continuity(groups: &[&[Row]], path: &str, columns: &Columns) -> Result<(), ImportError> {
    for w in groups.windows(2) {
        let (Some(end), Some(start)) = (w[0].last(), w[1].first()) else { continue };
        for j in 0..2 {
            if (start.q[j] - end.q[j]).abs() > POSITION_JUMP_TOLERANCE {
                return Err(ImportError::PositionJump {
                    path: path.into(),
                    lines: [end.line, start.line],
                    time: start.t,
                    name: columns.angles[j].clone(),
                    before: end.q[j],
                    after: start.q[j],
                });
            }
        }
    }
    Ok(())
}

fn build_piece(rows: &[Row], k: usize, scheme: Interpolation, path: &str) -> Result<ImportedPiece, ImportError> {
    let lines = (rows.first().map_or(2, |r| r.line), rows.last().map_or(2, |r| r.line));
    if rows.len() < scheme.min_rows() {
        return Err(ImportError::TooFewRows {
            path: path.into(),
            first_line: lines.0,
            last_line: lines.1,
            rows: rows.len(),
            needed: scheme.min_rows(),
            scheme,
        });
    }
    let t0 = rows[0].t;
    let knots: Vec<f64> = rows.iter().map(|r| r.t - t0).collect();
    let q = |joint: usize| rows.iter().map(|r| r.q[joint]).collect::<Vec<f64>>();
    let qd = |joint: usize| rows.iter().map(|r| r.qd.map_or(0.0, |v| v[joint])).collect::<Vec<f64>>();
    let qdd = |joint: usize| rows.iter().map(|r| r.qdd.map_or(0.0, |v| v[joint])).collect::<Vec<f64>>();
    let joint = |j: usize| match scheme {
        Interpolation::QuinticHermite => Some(Piecewise::quintic_hermite(&knots, &q(j), &qd(j), &qdd(j))),
        Interpolation::CubicHermite => Some(Piecewise::cubic_hermite(&knots, &q(j), &qd(j))),
        Interpolation::NotAKnotSpline => Piecewise::not_a_knot(&knots, &q(j)),
    };
    let failed = || ImportError::SplineFailed { path: path.into(), first_line: lines.0, last_line: lines.1 };
    let joints = [joint(0).ok_or_else(failed)?, joint(1).ok_or_else(failed)?];
    let end_rate_error = match scheme {
        Interpolation::NotAKnotSpline => spline_end_rate_error(&knots, [&q(0), &q(1)], [&joints[0], &joints[1]]),
        _ => [0.0; 2],
    };
    Ok(ImportedPiece {
        name: rows[0].phase.clone().unwrap_or_else(|| format!("piece-{}", k + 1)),
        file_start: t0,
        lines,
        end_rate_error,
        rows: rows.to_vec(),
        joints,
    })
}

impl ImportedSchedule {
    /// The same file with every other row of each piece dropped (a piece's first and last rows
    /// kept), for an a-posteriori estimate of the interpolation's error; `None` when no piece has
    /// rows to spare (every piece would stay as it is).
    pub fn every_other_row(&self) -> Option<ImportedSchedule> {
        let mut halved_any = false;
        let mut pieces = Vec::with_capacity(self.pieces.len());
        for (k, p) in self.pieces.iter().enumerate() {
            let n = p.rows.len();
            let mut keep: Vec<Row> = p.rows.iter().step_by(2).cloned().collect();
            if n % 2 == 0 {
                keep.push(p.rows[n - 1].clone());
            }
            if keep.len() >= self.interpolation.min_rows() && keep.len() < n {
                if let Ok(piece) = build_piece(&keep, k, self.interpolation, &self.path) {
                    halved_any = true;
                    pieces.push(ImportedPiece { name: p.name.clone(), ..piece });
                    continue;
                }
            }
            pieces.push(p.clone());
        }
        halved_any.then(|| ImportedSchedule { pieces, ..self.clone() })
    }

    /// All rows, in order.
    pub fn all_rows(&self) -> impl Iterator<Item = &Row> {
        self.pieces.iter().flat_map(|p| p.rows.iter())
    }
}
