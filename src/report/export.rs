//! Schedules exported for robots and other simulators (DESIGN.md §7).
//!
//! One CSV row per instant: time `t` (s), joint angles `q1, q2` (rad), rates (rad/s),
//! accelerations (rad/s²), the exact motor torques `tau1, tau2` (N·m, on B about joint 1's and
//! joint 2's axes), and A's orientation in the falling frame as a unit quaternion
//! `qw, qx, qy, qz` with its twist and swing (degrees). Rows at a phase boundary are written
//! twice, once with each phase's one-sided values, so a replay can reproduce a rate jump.

use crate::engines::exact::history;
use crate::engines::torque::joint_torques;
use crate::model::Cylinder;
use crate::schedule::{Phase, Schedule};

/// The CSV header.
pub const HEADER: &str = "t,phase,q1,q2,qd1,qd2,qdd1,qdd2,tau1,tau2,qw,qx,qy,qz,twist_deg,swing_deg";

/// The schedule as CSV with `steps` intervals per phase (orientation from the exact engine on the
/// same grid).
pub fn schedule_csv(cat: &Cylinder, schedule: &Schedule, steps: usize) -> String {
    let steps = steps.max(1);
    let orientations = history(cat, schedule, steps);
    let mut out = String::with_capacity(200 * (3 * steps + 3));
    out.push_str(HEADER);
    out.push('\n');
    for phase in Phase::ALL {
        let dur = schedule.durations[phase.index()];
        let t0 = schedule.phase_start(phase);
        for k in 0..=steps {
            let s = dur * k as f64 / steps as f64;
            let st = schedule.phase_state(phase, s);
            let tau = joint_torques(cat, &st).tau;
            let o = &orientations[phase.index() * steps + k];
            let q = o.orientation;
            out.push_str(&format!(
                "{:.9},{},{:.12},{:.12},{:.12},{:.12},{:.12},{:.12},{:.9},{:.9},{:.12},{:.12},{:.12},{:.12},{:.9},{:.9}\n",
                t0 + s,
                phase.name(),
                st.q[0],
                st.q[1],
                st.qd[0],
                st.qd[1],
                st.qdd[0],
                st.qdd[1],
                tau[0],
                tau[1],
                q.w,
                q.i,
                q.j,
                q.k,
                o.angles.twist.to_degrees(),
                o.angles.swing.to_degrees()
            ));
        }
    }
    out
}
