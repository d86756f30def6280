//! The three-phase schedule: paths, derivatives, boundaries, jumps (DESIGN.md §3).
#![deny(clippy::float_cmp)]

use approx::assert_relative_eq;
use catflip::engines::models::TwoMotorCat;
use catflip::model::joint_rotation;
use catflip::problem::manoeuvre::{BendPath, ProfileKind};
use catflip::problem::Problem;
use catflip::schedule::{Phase, Schedule};
use nalgebra::Vector3;

fn schedule(theta: f64, path: BendPath, profile: ProfileKind, d: f64) -> Schedule {
    let mut p = Problem::default();
    p.manoeuvre.theta_deg = theta;
    p.manoeuvre.bend_path = path;
    p.manoeuvre.profile = profile;
    Schedule::new(&p, d)
}

#[test]
fn cone_keeps_the_angle_between_the_halves() {
    for theta in [150.0, 120.0, 60.0, 45.0, 20.0] {
        let s = schedule(theta, BendPath::Cone, ProfileKind::Cycloidal, 7.0);
        let beta = (180.0f64 - theta).to_radians();
        for k in 0..=50 {
            let st = s.phase_state(Phase::Twist, s.durations[1] * k as f64 / 50.0);
            let axis = joint_rotation(st.q) * Vector3::z();
            assert_relative_eq!(axis.z.acos(), beta, epsilon = 1e-12);
        }
    }
}

#[test]
fn joint_circle_does_not_keep_the_angle() {
    // The paper's (β cos φ, β sin φ) path: at φ = 45° with β = 135° the halves are nearly square.
    let s = schedule(45.0, BendPath::JointCircle, ProfileKind::Cycloidal, 1.0);
    let st = s.path_state(std::f64::consts::FRAC_PI_4, 0.0, 0.0);
    let angle = (joint_rotation(st.q) * Vector3::z()).z.acos().to_degrees();
    assert!((angle - 135.0).abs() > 40.0, "angle {angle}°");
}

#[test]
fn path_derivatives_match_finite_differences() {
    let h = 1e-6;
    for (theta, path) in [(45.0, BendPath::JointCircle), (45.0, BendPath::Cone), (120.0, BendPath::Cone)] {
        let s = schedule(theta, path, ProfileKind::Poly345, 5.0);
        for t in [0.05, 0.3, 0.5, 0.77, 1.0, 1.2, 1.35] {
            let (a, b, c) = (s.state(t - h), s.state(t), s.state(t + h));
            for j in 0..2 {
                assert!(
                    ((c.q[j] - a.q[j]) / (2.0 * h) - b.qd[j]).abs() < 1e-6 * (1.0 + b.qd[j].abs()),
                    "{path:?} q̇{j} at {t}"
                );
                assert!(
                    ((c.qd[j] - a.qd[j]) / (2.0 * h) - b.qdd[j]).abs() < 1e-5 * (1.0 + b.qdd[j].abs()),
                    "{path:?} q̈{j} at {t}"
                );
            }
        }
    }
}

#[test]
fn joint_angles_are_continuous_and_the_cat_ends_straight() {
    for path in [BendPath::JointCircle, BendPath::Cone] {
        let s = schedule(60.0, path, ProfileKind::PaperCosine, 3.3);
        for (a, b) in [(Phase::Bend, Phase::Twist), (Phase::Twist, Phase::Unbend)] {
            let end = s.phase_state(a, s.durations[a.index()]).q;
            let start = s.phase_state(b, 0.0).q;
            assert_relative_eq!(end[0], start[0], epsilon = 1e-12);
            assert_relative_eq!(end[1], start[1], epsilon = 1e-12);
        }
        // Straight is the configuration R_AB = I: q1 may end at a multiple of 2π (the cone's
        // short way, see `nearest_straight`).
        let last = s.phase_state(Phase::Unbend, s.durations[2]);
        assert!((joint_rotation(last.q) - nalgebra::Matrix3::identity()).norm() < 1e-12, "{path:?} ends at {last:?}");
        assert!(last.qd.iter().all(|v| v.abs() < 1e-12), "{path:?} ends at {last:?}");
    }
}

#[test]
fn only_the_paper_cosine_jumps() {
    for kind in ProfileKind::ALL {
        let s = schedule(45.0, BendPath::JointCircle, kind, 3.0);
        let jumps = TwoMotorCat::paper(Problem::default().cat.half()).velocity_jumps(&s, |_| 0.0);
        if kind == ProfileKind::PaperCosine {
            assert_eq!(jumps.len(), 1);
            // Joint circle: |q̇| = β φ̇ and φ̇ ends at 2 D / T2 (paper §4: ω ends at 2 ω0).
            let j = jumps[0];
            let size = j.rates_before[0].hypot(j.rates_before[1]);
            assert_relative_eq!(size, s.bend * 2.0 * 3.0 / s.durations[1], max_relative = 1e-12);
            assert_relative_eq!(j.time, s.durations[0] + s.durations[1], epsilon = 1e-15);
        } else {
            assert!(jumps.is_empty(), "{} jumps: {jumps:?}", kind.name());
        }
    }
}

#[test]
fn phases_split_the_fall_time() {
    let p = Problem::default();
    let s = Schedule::new(&p, 1.0);
    // Fall time sqrt(2h/g) = sqrt(20/9.8) (paper §7: ≈ 1.428 s).
    assert_relative_eq!(s.duration(), (20.0f64 / 9.8).sqrt(), max_relative = 1e-15);
    assert_relative_eq!(s.durations[1], 0.6 * s.duration(), max_relative = 1e-15);
}

#[test]
fn round_off_of_a_fast_phase_is_not_a_jump() {
    // With a 1e-7 bend phase the rates reach ~β π/T1 ≈ 3e7 rad/s; sin(π) round-off there must
    // not be reported as a velocity jump (the tolerance is relative to the rates).
    let mut p = Problem::default();
    p.manoeuvre.phases = [1e-7, 0.5, 0.5 - 1e-7];
    p.manoeuvre.profile = ProfileKind::Cycloidal;
    let s = Schedule::new(&p, 3.0);
    let jumps = TwoMotorCat::paper(p.cat.half()).velocity_jumps(&s, |_| 0.0);
    assert!(jumps.is_empty(), "{jumps:?}");
}

#[test]
fn harmonic_bend_and_unbend_are_the_papers_cosines() {
    // DESIGN §3: q1 = β/2 (1 − cos(π t/T1)) in the bend; q = q_e (1 + cos(π u/T3))/2 in the unbend.
    let s = schedule(45.0, BendPath::JointCircle, ProfileKind::Cycloidal, 3.0);
    let (t1, t3) = (s.durations[0], s.durations[2]);
    let qe = s.phase_state(Phase::Twist, s.durations[1]).q;
    for k in 0..=10 {
        let f = k as f64 / 10.0;
        let b = s.phase_state(Phase::Bend, f * t1);
        assert_relative_eq!(b.q[0], 0.5 * s.bend * (1.0 - (std::f64::consts::PI * f).cos()), epsilon = 1e-14);
        let w = std::f64::consts::PI / t1;
        assert_relative_eq!(b.qdd[0], 0.5 * s.bend * w * w * (std::f64::consts::PI * f).cos(), epsilon = 1e-10);
        let u = s.phase_state(Phase::Unbend, f * t3);
        for (q, e) in u.q.iter().zip(qe) {
            assert_relative_eq!(*q, e * 0.5 * (1.0 + (std::f64::consts::PI * f).cos()), epsilon = 1e-14);
        }
    }
}
