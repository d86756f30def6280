//! Support shared by the integration tests and the benches: the paper's problem and schedule,
//! built once here instead of in every file (`mod common;` in a test, `#[path =
//! "../tests/common/mod.rs"] mod common;` in a bench).
//!
//! Each test binary uses only some of these, hence `dead_code` allowed.

#![allow(dead_code)]

use catflip::engines::measured::{Measured, Rig};
use catflip::engines::resolved::Resolved;
use catflip::problem::Problem;
use catflip::schedule::variant::ScheduleName;
use catflip::schedule::{paper_circulation, JointState, Schedule, Trajectory};

/// The paper's problem (every field at its default) and its schedule with the paper's
/// circulation `π/C` (DESIGN.md §3).
pub fn paper() -> (Problem, Schedule) {
    let problem = Problem::default();
    let circulation =
        paper_circulation(&problem.cat.half(), problem.manoeuvre.theta()).expect("C > 0 for the paper's cat");
    let schedule = Schedule::new(&problem, circulation);
    (problem, schedule)
}

/// The paper's problem resolved (its schedule and circulation), as every command starts.
pub fn paper_resolved() -> Resolved {
    Resolved::new(&Problem::default()).unwrap_or_else(|e| panic!("the paper's problem resolves: {e}"))
}

/// `schedule` measured on `problem`'s cat, release and motors, named `problem` (as `catflip run`
/// names the problem's own schedule), as every command measures it.
pub fn measured<T: Trajectory + Clone>(problem: &Problem, schedule: &T) -> Measured<T> {
    let rig = Rig::new(problem).unwrap_or_else(|e| panic!("a two-motor cat: {e}"));
    rig.measure(ScheduleName::Problem, schedule.clone())
}

/// A cat held at joint angles `q` for `duration` s: a rigid body (`q = 0`: held straight).
pub struct Held {
    pub q: [f64; 2],
    pub duration: f64,
}

impl Trajectory for Held {
    fn piece_durations(&self) -> Vec<f64> {
        vec![self.duration]
    }

    fn piece_state(&self, _piece: usize, _s: f64) -> JointState {
        JointState { q: self.q, ..JointState::default() }
    }
}

/// The paper's schedule as catflip exports it at 1 kHz (each phase boundary's time written twice,
/// one row per side), the CSV's text.
pub fn paper_csv() -> String {
    use catflip::exchange::{write_schedule, ExportOptions};
    let (p, s) = paper();
    write_schedule(&p, &measured(&p, &s), &ExportOptions { rate_hz: Some(1000.0), ..Default::default() })
        .expect("writes")
        .csv
}

/// Runs the `catflip` binary with `args`: its exit code (-1 when killed by a signal), stdout and
/// stderr.
pub fn catflip(args: &[&str]) -> (i32, String, String) {
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_catflip")).args(args).output().expect("the binary runs");
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&out.stdout).into(),
        String::from_utf8_lossy(&out.stderr).into(),
    )
}

/// Whether a whole optimum's `reason` says that the stage which gave its number stopped at its
/// iteration budget (the status `upper-bound`): the last refinement where the torques switch
/// decides when one was kept ("that stage stopped at its … iterations" against a stage that
/// stopped on its own test), else the spherical joint's lifted stage ("… % below it: a flip
/// below the universal joint's optimum").
pub fn last_stage_at_budget(reason: &str) -> bool {
    match reason.rfind("refined to ") {
        Some(at) => {
            let clause = &reason[at..];
            clause[..clause.find("; ").unwrap_or(clause.len())].contains("stopped at its")
        }
        None => reason.contains("% below it: a flip below"),
    }
}
