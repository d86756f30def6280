//! Peak joint torques per phase: the one shape in which every engine reports them.
//!
//! `max_t |τ_i(t)|` over each phase (bend, twist, unbend) for joint 1 (about A's `x`) and
//! joint 2 (about the cross's `y`), in N·m, and the largest of the six. The exact engine fills
//! it from [`crate::engines::torque::peak_torques`] (Newton–Euler on the zero-momentum motion,
//! each peak refined by golden-section search); rapier from the torques it infers from motion.

use serde::Serialize;

use crate::engines::torque::PeakTorques;
use crate::schedule::Phase;

/// Peak torque per phase and joint, N·m.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize)]
pub struct PhasePeaks {
    /// Bend phase, joints 1 and 2.
    pub bend: [f64; 2],
    /// Twist phase, joints 1 and 2.
    pub twist: [f64; 2],
    /// Unbend phase, joints 1 and 2.
    pub unbend: [f64; 2],
    /// The largest.
    pub max: f64,
}

impl PhasePeaks {
    /// The CSV header of [`PhasePeaks::csv`].
    pub const CSV_HEADER: &'static str =
        "bend_tau1_nm,bend_tau2_nm,twist_tau1_nm,twist_tau2_nm,unbend_tau1_nm,unbend_tau2_nm,max_nm";

    /// The seven values as CSV fields, N·m.
    pub fn csv(&self) -> String {
        self.fields().join(",")
    }

    /// The seven values, formatted, in the order of [`PhasePeaks::CSV_HEADER`], N·m.
    pub fn fields(&self) -> [String; 7] {
        let v = [self.bend[0], self.bend[1], self.twist[0], self.twist[1], self.unbend[0], self.unbend[1], self.max];
        v.map(|x| format!("{x:.9}"))
    }

    /// From per-phase peaks of a three-phase schedule (NaN for a phase it lacks).
    pub fn from_peaks(p: &PeakTorques) -> PhasePeaks {
        let get = |ph: Phase| p.per_piece.get(ph.index()).map_or([f64::NAN; 2], |x| [x[0].value, x[1].value]);
        PhasePeaks { bend: get(Phase::Bend), twist: get(Phase::Twist), unbend: get(Phase::Unbend), max: p.max }
    }

    /// The peaks of one phase, joints 1 and 2.
    pub fn phase(&self, phase: Phase) -> [f64; 2] {
        match phase {
            Phase::Bend => self.bend,
            Phase::Twist => self.twist,
            Phase::Unbend => self.unbend,
        }
    }

    /// The larger joint's peak in one phase, N·m.
    pub fn phase_max(&self, phase: Phase) -> f64 {
        let [a, b] = self.phase(phase);
        a.max(b)
    }

    /// Takes a torque sample `tau` (N·m, joints 1 and 2) in `phase` into the peaks.
    pub fn add(&mut self, phase: Phase, tau: [f64; 2]) {
        let slot = match phase {
            Phase::Bend => &mut self.bend,
            Phase::Twist => &mut self.twist,
            Phase::Unbend => &mut self.unbend,
        };
        for (s, t) in slot.iter_mut().zip(tau) {
            *s = s.max(t.abs());
            self.max = self.max.max(t.abs());
        }
    }
}
