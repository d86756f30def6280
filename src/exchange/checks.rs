//! What can be checked of an imported schedule before its numbers are believed: against the
//! problem it is evaluated with, and against itself.
//!
//! Refused ([`ImportError`], nothing reported):
//! - a duration more than [`ABSURD_DURATION_FACTOR`] times longer or shorter than the fall
//!   `t_fall = √(2h/g)` (the times cannot be seconds; the engines' numbers would overflow);
//! - (when the file is read, [`crate::exchange::import`]) a non-finite field, an angle beyond
//!   [`crate::exchange::import::MAX_ANGLE_RAD`], a rate or an acceleration beyond the limits of
//!   [`crate::exchange::import::FASTEST_TURN_SHARE`], angles that jump at a repeated time, times so
//!   far from zero that their rounding in double precision reaches
//!   [`crate::exchange::import::TIME_ROUNDING_REFUSED`] of the rows' mean spacing
//!   ([`crate::exchange::import::TimeRounding`]: near 1e15 s rows 1 ms apart run together).
//!
//! Warned (the report is made, with the warning beside it):
//! - times that do not start at 0: the schedule starts at its first row, so every time is shifted
//!   (by how much is said, with the file's last time and where it falls after the shift);
//! - times whose rounding reaches [`TIME_ROUNDING_WARNED`] of the rows' mean spacing (a clock's
//!   epoch, not the fall's start: near 1e9 s the rows move by 1e-7 s);
//! - a duration that is not the fall's (within [`DURATION_TOLERANCE`] relative), said as
//!   milliseconds when it is a thousand times the fall;
//! - a joint angle beyond π rad (the halves would fold through each other): degrees, most likely;
//! - ends that are not straight (`|q| >` [`POSITION_JUMP_TOLERANCE`]) and at rest (the rates
//!   within [`crate::engines::JUMP_TOLERANCE`] of zero relative to `max(1 rad/s, |q̇|)`, and the
//!   spline's end-rate uncertainty): the cat is released and lands straight and at rest, so
//!   starting or stopping otherwise takes an impulse `M(q) q̇` (stated) that no torque column
//!   shows;
//! - rates that contradict the angles: over each row interval `h`, the trapezoid rule with its
//!   end correction, `Δq ≈ h (q̇_i + q̇_{i+1})/2 − h² (q̈_{i+1} − q̈_i)/12` (the correction when
//!   `q̈` is given; error `O(h⁵)`, else `O(h³)`), and likewise `Δq̇ ≈ h (q̈_i + q̈_{i+1})/2`; the
//!   residuals summed over the file larger than [`CONSISTENCY_FRACTION`] of `Σ|Δq|`;
//! - rows too far apart for the interpolation: the peak torque recomputed with every other row
//!   dropped, `|P_h − P_2h| / (2^p − 1)` (`p` the order of the scheme's `q̈`: 4 quintic Hermite,
//!   2 otherwise) larger than [`SAMPLING_TOLERANCE`] of the peak;
//! - a phase boundary written once (the `phase` column changing within a piece, or an
//!   interval whose rate change contradicts the accelerations as a jump inside it would):
//!   catflip writes each boundary's time twice;
//! - piece boundaries whose rate jump cannot be judged (spline pieces of fewer than seven rows);
//! - the problem's cat outside the paper's stability argument (`l < √3 r`). The problem's
//!   manoeuvre is not used, so nothing is said of it.

use crate::engines::models::TwoMotorCat;
use crate::engines::torque::{piece_samples, PeakTorques};
use crate::engines::JUMP_TOLERANCE;
use crate::exchange::import::{
    ImportError, ImportedSchedule, Interpolation, Row, TimeRounding, POSITION_JUMP_TOLERANCE, TIME_ROUNDING_WARNED,
};
use crate::numeric::numfmt::sig;
use crate::problem::Problem;
use crate::schedule::Trajectory;

/// How many times longer or shorter than the fall a schedule may be before it is refused.
pub const ABSURD_DURATION_FACTOR: f64 = 1e6;
/// Relative difference of the schedule's duration and the fall's above which it is warned.
pub const DURATION_TOLERANCE: f64 = 1e-6;
/// Fraction of the angles' total motion the rates' residual may reach before it is warned.
pub const CONSISTENCY_FRACTION: f64 = 0.1;
/// An interval's rate residual, as a share of `h max|q̈|`, above which it reads as an
/// acceleration jump inside the interval (a phase boundary written once, [`check`]).
pub const JUMP_SHARE: f64 = 0.01;
/// How many times its neighbours' residuals an interval's must exceed to read as a jump.
pub const JUMP_ISOLATION: f64 = 100.0;
/// How many times its neighbours' changes of acceleration an interval's must exceed to read as a
/// jump (a jerk-limited profile's kink changes it as they do).
pub const ACCEL_ISOLATION: f64 = 10.0;
/// Estimated relative error of the peak torque from the rows' spacing above which it is warned.
pub const SAMPLING_TOLERANCE: f64 = 1e-3;

/// The refusals and warnings of `schedule` evaluated with `problem` (module docs); the warnings
/// in the user's words, naming the line or the column.
pub fn check(problem: &Problem, model: &TwoMotorCat, schedule: &ImportedSchedule) -> Result<Vec<String>, ImportError> {
    let mut warnings = Vec::new();
    made_for(problem, schedule, &mut warnings);
    start(schedule, &mut warnings);
    duration(problem, schedule, &mut warnings)?;
    time_rounding(schedule, &mut warnings);
    degrees(schedule, &mut warnings);
    ends(model, schedule, &mut warnings);
    consistency(schedule, &mut warnings);
    unrepeated_boundaries(schedule, &mut warnings);
    warnings.extend(problem.short_halves());
    Ok(warnings)
}

/// A file catflip wrote carries its sidecar (`NAME.json` beside `NAME.csv`) with the problem it
/// was made for: a cat, or a release's spin, other than this problem's is said (the file is still
/// evaluated on this cat and release, as asked). A file without a readable sidecar is taken as it
/// is.
fn made_for(problem: &Problem, s: &ImportedSchedule, warnings: &mut Vec<String>) {
    use crate::numeric::numfmt::echo;
    let path = std::path::Path::new(&s.path).with_extension("json");
    let Ok(text) = std::fs::read_to_string(&path) else { return };
    let Ok(sidecar) = serde_json::from_str::<crate::exchange::sidecar::Sidecar>(&text) else { return };
    let source = &sidecar.source;
    let Ok(cat) = serde_json::from_value::<crate::problem::CatSection>(source.problem_file["cat"].clone()) else {
        return;
    };
    let (theirs, ours) = (cat.model(), problem.cat.model());
    if theirs != ours {
        warnings.push(format!(
            "its sidecar {} says it was made for problem \"{}\", whose cat ({}) is not this problem's ({}): the twist and torques here are this cat's, not the ones it was planned for",
            path.display(),
            source.problem,
            theirs.describe(),
            ours.describe()
        ));
    }
    // The release it was planned for: a plan for zero momentum released with spin turns the
    // cat otherwise (a QA run's landed at −132.5°, unsaid).
    let spin = |v: &serde_json::Value| -> Option<[f64; 3]> {
        match v.get("drop").and_then(|d| d.get("angular_momentum")) {
            None => Some([0.0; 3]),
            Some(l) => serde_json::from_value(l.clone()).ok(),
        }
    };
    let Some(planned) = spin(&source.problem_file) else { return };
    let here = problem.drop.angular_momentum;
    // To 1e-12 of the larger spin: a sidecar carries the numbers its problem file gave.
    let gap = (0..3).map(|i| (planned[i] - here[i]).abs()).fold(0.0, f64::max);
    let size = (0..3).map(|i| planned[i].abs().max(here[i].abs())).fold(0.0, f64::max);
    if gap > 1e-12 * size {
        let shown = |l: [f64; 3]| format!("[{}, {}, {}]", echo(l[0]), echo(l[1]), echo(l[2]));
        warnings.push(format!(
            "its sidecar {} says it was planned for a release with drop.angular_momentum = {} N·m·s, this problem's is {}: the twist here is this release's, not the one it was planned for",
            path.display(),
            shown(planned),
            shown(here)
        ));
    }
}

/// The first row's time is the schedule's start (`t = 0`): any other is said, with the shift.
fn start(s: &ImportedSchedule, warnings: &mut Vec<String>) {
    use crate::numeric::numfmt::{echo, num, signed};
    let (Some(first), Some(last)) = (s.all_rows().next(), s.all_rows().last()) else { return };
    if first.t != 0.0 {
        warnings.push(format!(
            "line {}, column `{}`: the times start at {} s, not 0: the schedule starts at its first row, so every time is shifted by {} s (the last, {} s on line {}, is {} s from the start); write the times from the start of the fall (t = 0)",
            first.line,
            s.columns.time,
            echo(first.t),
            signed(-first.t),
            echo(last.t),
            last.line,
            num(last.t - first.t)
        ));
    }
}

fn duration(problem: &Problem, s: &ImportedSchedule, warnings: &mut Vec<String>) -> Result<(), ImportError> {
    let fall = problem.drop.fall_time();
    let d = s.total_duration();
    let ratio = d / fall;
    let name = &s.columns.time;
    if !(1.0 / ABSURD_DURATION_FACTOR..=ABSURD_DURATION_FACTOR).contains(&ratio) {
        let long = ratio > 1.0;
        return Err(ImportError::AbsurdDuration {
            path: s.path.clone(),
            name: name.clone(),
            duration_s: d,
            fall_s: fall,
            height: problem.drop.height,
            gravity: problem.drop.gravity,
            factor: if long { ratio } else { 1.0 / ratio },
            direction: if long { "long" } else { "short" }.into(),
        });
    }
    let last = s.all_rows().last().map_or(0, |r| r.line);
    if (ratio - 1e3).abs() < 0.05e3 {
        warnings.push(format!(
            "column `{name}`: the schedule lasts {d} s against a fall of {fall:.6} s (drop.height = {} m, drop.gravity = {} m/s²): the times look like milliseconds; they must be in seconds",
            problem.drop.height, problem.drop.gravity
        ));
    } else if (ratio - 1.0).abs() > DURATION_TOLERANCE {
        let gap = d - fall;
        let when = if gap < 0.0 { "before" } else { "after" };
        warnings.push(format!(
            "line {last}: the schedule ends at {d:.6} s, {:.3} ms {when} the cat lands (fall {fall:.6} s from drop.height = {} m, drop.gravity = {} m/s²)",
            1e3 * gap.abs(),
            problem.drop.height,
            problem.drop.gravity
        ));
    }
    Ok(())
}

/// Times far from zero are rounded by more than [`TIME_ROUNDING_WARNED`] of the rows' spacing
/// (more than [`crate::exchange::import::TIME_ROUNDING_REFUSED`] was refused on reading).
fn time_rounding(s: &ImportedSchedule, warnings: &mut Vec<String>) {
    let times: Vec<f64> = s.all_rows().map(|r| r.t).collect();
    if let Some(r) = TimeRounding::of(&times).filter(|r| r.share() > TIME_ROUNDING_WARNED) {
        warnings.push(format!(
            "{}, which moves the rows and the accelerations interpolated between them; write the times from the start of the fall (t = 0)",
            r.describe(&s.columns.time)
        ));
    }
}

fn degrees(s: &ImportedSchedule, warnings: &mut Vec<String>) {
    for j in 0..2 {
        let worst = s.all_rows().max_by(|a, b| a.q[j].abs().total_cmp(&b.q[j].abs()));
        if let Some(r) = worst.filter(|r| r.q[j].abs() > std::f64::consts::PI) {
            warnings.push(format!(
                "line {}, column `{}`: {} rad ({:.0}°) bends the joint beyond 180°, folding the halves through each other: the column looks like degrees; angles must be in radians",
                r.line,
                s.columns.angles[j],
                r.q[j],
                r.q[j].to_degrees()
            ));
        }
    }
}

/// Whether a row's state is straight (`q ≈ 0`) and at rest (`q̇ ≈ 0`, within `rate_uncertainty`).
fn ends(model: &TwoMotorCat, s: &ImportedSchedule, warnings: &mut Vec<String>) {
    let durations = s.piece_durations();
    let (Some(first), Some(last)) = (s.pieces.first(), s.pieces.last()) else { return };
    let n = durations.len() - 1;
    let ends = [
        ("starts", "is released", first.rows.first(), s.piece_state(0, 0.0), first.end_rate_error[0]),
        ("ends", "lands", last.rows.last(), s.piece_state(n, durations[n]), last.end_rate_error[1]),
    ];
    for (verb, event, row, state, rate_error) in ends {
        let line = row.map_or(0, |r: &Row| r.line);
        let q = state.q;
        if q[0].hypot(q[1]) > POSITION_JUMP_TOLERANCE {
            warnings.push(format!(
                "line {line}: the schedule {verb} bent (q = [{:.6}, {:.6}] rad): the cat {event} straight (q = 0)",
                q[0], q[1]
            ));
        }
        let speed = state.qd[0].hypot(state.qd[1]);
        let uncertainty = crate::exchange::import::JUMP_SAFETY * rate_error;
        if !uncertainty.is_finite() {
            warnings.push(format!(
                "line {line}: whether the schedule {verb} at rest could not be checked: its piece has too few rows (fewer than 7) to estimate the spline's rate there; give q̇ or more rows"
            ));
        } else if speed > (JUMP_TOLERANCE * speed.max(1.0)).max(uncertainty) {
            // The impulse from rest: the paper's cat's M(q) q̇, any other model's motor impulse.
            let m = model.jump_impulse(q, state.qd);
            warnings.push(format!(
                "line {line}: the schedule {verb} moving (q̇ = [{:.6}, {:.6}] rad/s): the cat {event} at rest, so this takes an impulse [{:.6}, {:.6}] N·m·s at that instant, which no torque here includes",
                state.qd[0], state.qd[1], m[0], m[1]
            ));
        }
    }
}

/// Rates against the angles' differences, and accelerations against the rates'.
fn consistency(s: &ImportedSchedule, warnings: &mut Vec<String>) {
    let Some(rates) = &s.columns.rates else { return };
    for j in 0..2 {
        // Σ|Δq|, Σ|h·mean q̇|, Σ|residual|, worst (residual, lines); and the same one level up.
        let mut q = Residuals::default();
        let mut qd = Residuals::default();
        for p in &s.pieces {
            for w in p.rows.windows(2) {
                let (a, b) = (&w[0], &w[1]);
                let h = b.t - a.t;
                let (Some(va), Some(vb)) = (a.qd, b.qd) else { continue };
                let correction = match AccelStep::of(a, b, j) {
                    Some(step) => {
                        qd.add(step.change, step.integral, step.lines);
                        h * h * step.accel_change / 12.0
                    }
                    None => 0.0,
                };
                q.add(b.q[j] - a.q[j], 0.5 * h * (va[j] + vb[j]) - correction, [a.line, b.line]);
            }
        }
        if let Some(lines) = q.inconsistent() {
            warnings.push(format!(
                "column `{}` contradicts `{}`: integrated, the rates move joint {} by {:.6} rad in all, the angles by {:.6} rad (worst between lines {} and {}); rates must be dq/dt in rad/s",
                rates[j],
                s.columns.angles[j],
                j + 1,
                q.integrated,
                q.moved,
                lines[0],
                lines[1]
            ));
        }
        if let (Some(lines), Some(accels)) = (qd.inconsistent(), &s.columns.accels) {
            warnings.push(format!(
                "column `{}` contradicts `{}`: integrated, the accelerations change joint {}'s rate by {:.6} rad/s in all, the rates by {:.6} rad/s (worst between lines {} and {}); accelerations must be d²q/dt² in rad/s²",
                accels[j],
                rates[j],
                j + 1,
                qd.integrated,
                qd.moved,
                lines[0],
                lines[1]
            ));
        }
    }
}

/// Phase boundaries written once: catflip writes each boundary's time twice, one row per side,
/// and the import splits its pieces there, where the accelerations jump. A file that keeps one of
/// the two rows (a careless de-duplication of the times) joins two phases in one piece, and the
/// interpolation carries the jump into the rows' intervals (a QA run's peak torque rose by 37 %,
/// silently). Said when the `phase` column changes within a piece, or, with accelerations given,
/// when one interval's rate change contradicts them by more than [`JUMP_SHARE`] of the largest
/// change an interval of its width sees, that residual more than [`JUMP_ISOLATION`] times its two
/// neighbours' and its change of acceleration more than [`ACCEL_ISOLATION`] times theirs.
fn unrepeated_boundaries(s: &ImportedSchedule, warnings: &mut Vec<String>) {
    let advice = "catflip writes each phase boundary's time twice, one row per side, and the import splits the file there, where the accelerations may jump: keep both rows, or the interpolation carries any such jump into the rows around it";
    for p in &s.pieces {
        for w in p.rows.windows(2) {
            if let (Some(a), Some(b)) = (&w[0].phase, &w[1].phase) {
                if a != b {
                    warnings.push(format!(
                        "lines {} and {}: the phase changes from \"{a}\" to \"{b}\" at different times (t = {} and {} s), not at one time written twice; {advice}",
                        w[0].line, w[1].line, w[0].t, w[1].t
                    ));
                    return;
                }
            }
        }
    }
    let Some(accels) = &s.columns.accels else { return };
    for j in 0..2 {
        let largest =
            s.pieces.iter().flat_map(|p| &p.rows).filter_map(|r| r.qdd.map(|a| a[j].abs())).fold(0.0, f64::max);
        for p in &s.pieces {
            let steps: Vec<AccelStep> = p.rows.windows(2).filter_map(|w| AccelStep::of(&w[0], &w[1], j)).collect();
            // An interval with a neighbour on each side, isolated in both its residual and its
            // change of acceleration: a jerk-limited profile's kink (continuous q̈, a jump in the
            // jerk) leaves a residual of J h²/8 but changes q̈ as its neighbours do.
            for w in steps.windows(3) {
                let [before, step, after] = [&w[0], &w[1], &w[2]];
                let r = step.residual();
                let isolated = r > JUMP_ISOLATION * before.residual().max(after.residual())
                    && step.accel_change.abs()
                        > ACCEL_ISOLATION * before.accel_change.abs().max(after.accel_change.abs());
                if r > JUMP_SHARE * step.h * largest && isolated {
                    warnings.push(format!(
                        "lines {} and {}: column `{}` jumps within one interval (by {} rad/s², the rates changing by {} rad/s less or more than the accelerations say), as at a phase boundary written once; {advice}",
                        step.lines[0],
                        step.lines[1],
                        accels[j],
                        sig(step.accel_change, 6),
                        sig(r, 3)
                    ));
                    return;
                }
            }
        }
    }
}

/// One row interval's rates and accelerations for joint `j` (both given at both ends): the
/// change of rate, its trapezoid integral of the accelerations, the change of acceleration.
struct AccelStep {
    h: f64,
    lines: [u64; 2],
    change: f64,
    integral: f64,
    accel_change: f64,
}

impl AccelStep {
    fn of(a: &Row, b: &Row, j: usize) -> Option<AccelStep> {
        let (va, vb, aa, ab) = (a.qd?, b.qd?, a.qdd?, b.qdd?);
        let h = b.t - a.t;
        Some(AccelStep {
            h,
            lines: [a.line, b.line],
            change: vb[j] - va[j],
            integral: 0.5 * h * (aa[j] + ab[j]),
            accel_change: ab[j] - aa[j],
        })
    }

    /// How far the rates' change departs from the accelerations' trapezoid, rad/s.
    fn residual(&self) -> f64 {
        (self.change - self.integral).abs()
    }
}

/// Sums of a difference column against its integrated derivative.
#[derive(Default)]
struct Residuals {
    moved: f64,
    integrated: f64,
    residual: f64,
    worst: (f64, [u64; 2]),
}

impl Residuals {
    fn add(&mut self, difference: f64, integral: f64, lines: [u64; 2]) {
        let r = (difference - integral).abs();
        self.moved += difference.abs();
        self.integrated += integral.abs();
        self.residual += r;
        if r > self.worst.0 {
            self.worst = (r, lines);
        }
    }

    /// The worst lines when the residual exceeds [`CONSISTENCY_FRACTION`] of the motion (and
    /// round-off).
    fn inconsistent(&self) -> Option<[u64; 2]> {
        let floor = 1e-12 * self.moved.max(self.integrated).max(1.0);
        (self.residual > CONSISTENCY_FRACTION * self.moved && self.residual > floor).then_some(self.worst.1)
    }
}

/// Samples per piece for the peak torque: by the schedule's own time scale
/// ([`piece_samples`], `torque_samples` at least); the rows are sampled too, as
/// [`Trajectory::acceleration_jumps`].
pub fn peak_samples(schedule: &ImportedSchedule, torque_samples: usize) -> Vec<usize> {
    piece_samples(schedule, torque_samples)
}

/// The estimated relative error of the peak torques `peaks` (per piece and joint, as
/// [`crate::engines::torque::peak_torques_from`] gives them on `s`) from the rows' spacing (module docs), as a warning
/// naming the worst piece's lines when it exceeds [`SAMPLING_TOLERANCE`] (pieces and joints whose
/// peak is below [`SAMPLING_TOLERANCE`] of the largest are not judged); also when no piece has
/// rows to spare.
pub fn sampling(
    s: &ImportedSchedule,
    peaks: &[[f64; 2]],
    peaks_of: impl Fn(&ImportedSchedule) -> PeakTorques,
) -> Option<String> {
    let Some(coarse) = s.every_other_row() else {
        return Some(
            "whether the rows are close enough for the interpolation could not be checked: no piece has rows to spare for a coarser copy"
                .into(),
        );
    };
    // The coarser copy's peaks are measured as the file's are (`peaks_of`: the same model, with
    // the release spin, if any).
    let coarse_peaks = peaks_of(&coarse);
    let divisor = match s.interpolation {
        Interpolation::QuinticHermite => 15.0,
        _ => 3.0,
    };
    let max = peaks.iter().flatten().copied().fold(0.0, f64::max);
    // (estimated relative error, piece, joint, fine, coarse) of the worst piece and joint.
    let mut worst = (0.0, 0, 0, 0.0, 0.0);
    for (k, (fine, rough)) in peaks.iter().zip(&coarse_peaks.per_piece).enumerate() {
        for j in 0..2 {
            let (a, b) = (fine[j], rough[j].value);
            if a > SAMPLING_TOLERANCE * max {
                let error = (a - b).abs() / divisor / a;
                if error > worst.0 {
                    worst = (error, k, j, a, b);
                }
            }
        }
    }
    let (error, k, j, a, b) = worst;
    let piece = &s.pieces[k];
    let rows_per_s = (piece.rows.len() - 1) as f64 / (piece.rows[piece.rows.len() - 1].t - piece.rows[0].t);
    (error > SAMPLING_TOLERANCE).then(|| {
        format!(
            "lines {}–{}: the rows ({rows_per_s:.0} per second) are too far apart for {}: with every other row dropped joint {}'s peak torque there moves from {a:.6} to {b:.6} N·m, an estimated error of {:.2} %; write the rows closer together{}",
            piece.lines.0,
            piece.lines.1,
            s.interpolation,
            j + 1,
            100.0 * error,
            if s.interpolation == Interpolation::QuinticHermite { "" } else { ", or give q̇ and q̈" }
        )
    })
}
