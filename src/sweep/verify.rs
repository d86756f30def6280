//! The `rapier` rows of a case: every `ok` exact row's measured trajectory verified by rapier
//! against the exact engine's twist, swing and peak torque ([`Measured::verify`], DESIGN.md §6).
//!
//! The step is refined by halving until rapier's own Richardson error estimate meets the
//! problem's `[rapier]` tolerances or the next run would overrun `rapier.step_budget` (all runs'
//! steps together). The wall-clock budget `rapier.time_budget_s` is ignored here (set to none):
//! with a budget in steps alone the verdict and every number are the same on any machine, under
//! any load and whatever the thread count.
//!
//! The row carries the finest run's raw twist, swing and peak torque (per phase for a three-phase
//! schedule) in the usual columns, the extrapolated ones and the steps in `rapier_*` columns, and
//! the verdict's text in `rapier_verdict`. A verification that ran is `ok` whatever its verdict
//! (the verdict is its result); one with no run to show is `failed` (it has no numbers) with the
//! verdict as reason and in `rapier_verdict`, and counts as `inconclusive` among the verdicts,
//! as in `catflip run`; an exact row without a result gives a `skipped` rapier row.

use crate::engines::measured::{Measured, Rig};
use crate::engines::rapier::{Quantity, RapierError, Verification};
use crate::engines::Engine;
use crate::problem::settings::RapierSettings;
use crate::problem::Problem;
use crate::schedule::Trajectory;

use super::row::{ExactRow, Labels, Numbers, RapierNumbers, Row, Status, Subject};

/// The problem's rapier settings without a wall-clock budget (module docs).
pub fn rapier_settings(problem: &Problem) -> RapierSettings {
    RapierSettings { time_budget_s: None, ..problem.rapier }
}

/// The rapier row of one exact row, verified on the case's `rig` without a wall-clock budget.
pub(crate) fn rapier_row(rig: &Rig, exact: &ExactRow) -> Row {
    let schedule = exact.row.schedule;
    let Some(subject) = &exact.subject else {
        let reason = format!("no exact result to verify (the exact row is {})", exact.row.status.name());
        return Row::without(schedule, Engine::Rapier, Status::Skipped, &reason, Labels::default());
    };
    let rig = Rig { rapier: RapierSettings { time_budget_s: None, ..rig.rapier }, ..rig.clone() };
    let result = match subject {
        Subject::Schedule(m) => verified(&rig, m),
        Subject::Retimed(m) => verified(&rig, m),
        Subject::Whole(m) => verified(&rig, m),
    };
    let v = match result {
        Ok(v) => v,
        Err(e) => {
            let reason = format!("rapier could not run: {e}");
            return Row::without(schedule, Engine::Rapier, Status::Failed, &reason, Labels::default());
        }
    };
    let verdict = v.verdict.to_string();
    let labels = Labels { rapier_verdict: super::spec::one_line(&verdict), ..Labels::default() };
    let Some(finest) = &v.finest else {
        return Row::without(schedule, Engine::Rapier, Status::Failed, &verdict, labels);
    };
    let value = |q| v.quantity(q).and_then(|c| c.value);
    let mut numbers =
        Numbers::flip(exact.row.numbers.and_then(|n| n.circulation_rad), finest.twist, finest.swing, None);
    numbers.peaks = finest.peak_torque.phase_peaks();
    numbers.peak_nm = Some(finest.peak_torque.max);
    numbers.rapier = Some(RapierNumbers {
        twist_extrapolated_deg: value(Quantity::Twist),
        swing_extrapolated_deg: value(Quantity::Swing),
        peak_extrapolated_nm: value(Quantity::PeakTorque),
        steps: v.steps_taken,
        finest_dt_s: finest.dt,
    });
    Row::with(schedule, Engine::Rapier, numbers, labels)
}

/// `m` verified in rapier on `rig`: its verification.
fn verified<T: Trajectory + Clone>(rig: &Rig, m: &Measured<T>) -> Result<Verification, RapierError> {
    let mut m = m.clone();
    m.verify(rig)?;
    m.verification().cloned().ok_or_else(|| RapierError::NoResult("not verified".into()))
}
