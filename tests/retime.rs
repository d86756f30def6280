//! The certified retiming along a fixed path (`catflip::optimize::retime`): the reduced dynamics
//! `τ = a s̈ + b ṡ²`, closed forms, the certificate, the reconstruction, bad input.

#![deny(clippy::float_cmp)]

mod common;

use approx::assert_relative_eq;
use catflip::engines::calibrate::calibrate;
use catflip::engines::exact::flip;
use catflip::engines::torque::{joint_torques, reduced_mass_matrix};
use catflip::model::Cylinder;
use catflip::optimize::retime::{
    retime, retime_schedule, PathNode, PathPiece, PathProblem, PhasePath, RetimeError, RetimeSettings, RetimeStatus,
    Split,
};
use catflip::problem::Problem;
use catflip::schedule::{paper_circulation, JointState, Schedule, Trajectory};
use proptest::prelude::*;

use common::paper;

fn settings(intervals: usize, split: Split) -> RetimeSettings {
    RetimeSettings { intervals, split, ..RetimeSettings::default() }
}

/// Joint 1 alone, straight line from `q1 = 0` to `q1 = d` over `s ∈ [0, S]`; joint 2 at zero.
#[derive(Clone, Copy)]
struct SingleJoint {
    d: f64,
    length: f64,
}

impl Trajectory for SingleJoint {
    fn piece_durations(&self) -> Vec<f64> {
        vec![self.length]
    }
    fn piece_state(&self, _piece: usize, s: f64) -> JointState {
        JointState { q: [self.d * s / self.length, 0.0], qd: [self.d / self.length, 0.0], qdd: [0.0; 2] }
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 64, ..ProptestConfig::default() })]

    /// `τ(q, q' ṡ, q' s̈ + q'' ṡ²) = a s̈ + b ṡ²` with `a = τ(q, 0, q')`, `b = τ(q, q', q'')`:
    /// Newton–Euler is affine in `q̈` and homogeneous quadratic in `q̇` at zero momentum.
    #[test]
    fn torque_along_a_path_is_a_sdd_plus_b_sd2(t in 0.0..1.0f64, sd in -3.0..3.0f64, sdd in -20.0..20.0f64) {
        let (p, s) = paper();
        let total = s.duration();
        let (phase, local) = s.locate(t * total);
        let st = s.phase_state(phase, local);
        let a = joint_torques(&p.cat.half(), &JointState { q: st.q, qd: [0.0; 2], qdd: st.qd }).tau;
        let b = joint_torques(&p.cat.half(), &st).tau;
        let timed = JointState {
            q: st.q,
            qd: st.qd.map(|v| v * sd),
            qdd: [0, 1].map(|j| st.qd[j] * sdd + st.qdd[j] * sd * sd),
        };
        let tau = joint_torques(&p.cat.half(), &timed).tau;
        for j in 0..2 {
            let scale = 1.0 + a[j].abs() * sdd.abs() + b[j].abs() * sd * sd;
            prop_assert!((tau[j] - (a[j] * sdd + b[j] * sd * sd)).abs() <= 1e-12 * scale,
                "joint {}: τ = {}, a s̈ + b ṡ² = {}", j, tau[j], a[j] * sdd + b[j] * sd * sd);
        }
    }
}

/// Constant `a`, `b = 0`, rest to rest: bang-bang `u = ±A` switching at `S/2`, `A = 4S/T²`,
/// peak `4 a S/T²`; with `N` even the switch is a node and the discrete optimum is exact.
#[test]
fn constant_inertia_is_bang_bang() {
    let (a, length, duration) = (0.37, 2.5, 1.3);
    for n in [2, 10, 64] {
        let node = PathNode { a: [a, 0.0], b: [0.0; 2], tangent: [1.0, 0.0] };
        let problem = PathProblem {
            pieces: vec![PathPiece::uniform(length, vec![node; n + 1])],
            duration,
            settings: settings(n, Split::Kept),
            kept: None,
        };
        let sol = problem.solve().expect("valid");
        assert_eq!(sol.status, RetimeStatus::Solved);
        let expected = 4.0 * a * length / (duration * duration);
        assert_relative_eq!(sol.peak, expected, max_relative = 1e-7);
        assert_relative_eq!(sol.lower_bound, expected, max_relative = 1e-7);
        assert_relative_eq!(sol.durations()[0], duration, max_relative = 1e-12);
        let u = &sol.timings[0].accel;
        let accel = 4.0 * length / (duration * duration);
        assert_relative_eq!(u[0], accel, max_relative = 1e-6);
        assert_relative_eq!(u[n - 1], -accel, max_relative = 1e-6);
    }
}

/// Joint 1 alone from straight: a one-degree-of-freedom motion `τ = M(q) q̈ + ½ M'(q) q̇²`, whose
/// energy obeys `dE/dq = τ`. With `|τ| ≤ t` rest to rest the fastest motion has
/// `E(q) = t min(q, D − q)` (bang-bang in torque), so `T = ∫ √(M/(2E)) dq` and the least peak
/// is `t* = C²/T²`, `C = ∫_0^D √(M(q)/(2 min(q, D − q))) dq` (by `q = w²` from each end,
/// `C = ∫_0^{√(D/2)} (√(2M(w²)) + √(2M(D − w²))) dw`, Simpson's rule).
#[test]
fn single_joint_matches_its_one_dimensional_optimum() {
    let p = Problem::default();
    let cat: Cylinder = p.cat.half();
    let (d, duration): (f64, f64) = (2.0, 0.6);
    let m = |q: f64| reduced_mass_matrix(&cat, [q, 0.0])[(0, 0)];
    let half = (0.5 * d).sqrt();
    let k = 2000;
    let f = |w: f64| (2.0 * m(w * w)).sqrt() + (2.0 * m(d - w * w)).sqrt();
    let h = half / k as f64;
    let c: f64 = (0..=k)
        .map(|i| {
            let weight = if i == 0 || i == k {
                1.0
            } else if i % 2 == 1 {
                4.0
            } else {
                2.0
            };
            weight * f(i as f64 * h)
        })
        .sum::<f64>()
        * h
        / 3.0;
    let expected = c * c / (duration * duration);
    let path = SingleJoint { d, length: 1.0 };
    let mut errors = Vec::new();
    for n in [100, 200, 400] {
        let r = retime(&cat, &path, duration, settings(n, Split::Kept)).expect("valid");
        assert_eq!(r.solution.status, RetimeStatus::Solved);
        let m = r.remeasure(&cat, 8 * n, 1e-10).expect("solved");
        // joint 2 carries nothing: the motion is planar about joint 1's axis
        assert!(m.peaks.per_piece[0][1].value < 1e-9 * expected, "τ2 = {}", m.peaks.per_piece[0][1].value);
        // the exact peak of any timing of the duration is at least the continuous optimum
        assert!(m.peaks.max >= expected * (1.0 - 1e-9), "exact {} < optimum {expected}", m.peaks.max);
        errors.push((m.peaks.max - expected) / expected);
    }
    // measured: 8.2e-3, 4.1e-3, 2.1e-3: first order in 1/N (u is constant on an interval, so the
    // torque cannot stay at the bound across it, and the optimum holds it there)
    assert!(errors[2] < 2.5e-3, "relative excess at N = 400: {errors:?}");
    assert!(errors[2] < 0.6 * errors[1] && errors[1] < 0.6 * errors[0], "no convergence: {errors:?}");
}

/// The dual objective bounds the primal from below, within the reported gap, and the exact
/// torques of the reconstruction at the grid nodes are the program's.
#[test]
fn certificate_and_reconstruction_agree() {
    let (p, s) = paper();
    for split in [Split::Kept, Split::Free] {
        let r = retime(&p.cat.half(), &s, s.duration(), settings(50, split)).expect("valid");
        let sol = &r.solution;
        assert!(sol.status.is_solved(), "{}", sol.status);
        assert!(sol.lower_bound <= sol.peak, "bound {} above peak {}", sol.lower_bound, sol.peak);
        assert_relative_eq!(sol.peak - sol.lower_bound, sol.gap, epsilon = 1e-15);
        // Clarabel's tolerances (1e-8 on the normalised program) when fully solved; at reduced
        // accuracy (measured: free split, N = 60, 6.9e-4 N·m) the gap is what it reports
        if sol.status == RetimeStatus::Solved {
            assert!(sol.gap <= 1e-6 * sol.peak, "{split:?}: gap {}", sol.gap);
        }
        assert!(sol.discrete_peak <= sol.peak * (1.0 + 1e-6));
        assert_relative_eq!(sol.durations().iter().sum::<f64>(), s.duration(), max_relative = 1e-9);
        let traj = r.trajectory.as_ref().expect("solved");
        for (piece, t) in sol.timings.iter().enumerate() {
            for k in (0..t.accel.len()).step_by(7) {
                // just after node k: s̈ = u_k, ṡ² = x_k
                let time = t.times[k] + 1e-9 * (t.times[k + 1] - t.times[k]);
                let tau = joint_torques(&p.cat.half(), &traj.piece_state(piece, time)).tau;
                let path = s.piece_state(piece, t.grid[k]);
                let a = joint_torques(&p.cat.half(), &JointState { q: path.q, qd: [0.0; 2], qdd: path.qd }).tau;
                let b = joint_torques(&p.cat.half(), &path).tau;
                for j in 0..2 {
                    let promised = a[j] * t.accel[k] + b[j] * t.speed_squared[k];
                    assert!(
                        (tau[j] - promised).abs() <= 1e-6 * sol.peak,
                        "piece {piece} node {k} joint {j}: {} vs {promised}",
                        tau[j]
                    );
                }
            }
        }
    }
}

/// Retiming changes no twist or swing (a geometric phase), and the exact peak of the
/// reconstruction approaches the certified bound as the grid is refined.
#[test]
fn flip_is_unchanged_and_the_gap_shrinks() {
    let (p, s) = paper();
    let original = flip(&p.cat.half(), &s, 1e-12);
    let mut gaps = Vec::new();
    for n in [50, 100, 200] {
        let r = retime(&p.cat.half(), &s, s.duration(), settings(n, Split::Kept)).expect("valid");
        let m = r.remeasure(&p.cat.half(), 16 * n, 1e-12).expect("solved");
        for (what, a, b) in [("twist", m.flip.twist, original.twist), ("swing", m.flip.swing, original.swing)] {
            assert!((a - b).abs().to_degrees() <= 1e-7, "N = {n}: {what} {}° vs {}°", a.to_degrees(), b.to_degrees());
        }
        assert!(m.peaks.max >= r.solution.lower_bound, "exact {} below the bound", m.peaks.max);
        gaps.push(m.gap_to_bound);
    }
    assert!(gaps[2] < 0.5 * gaps[1] && gaps[1] < 0.5 * gaps[0], "exact − bound: {gaps:?}");
}

/// The paper's schedule: the convex retiming matches or beats the sequential LP's whole-manoeuvre
/// exact peak, 9.8022 N·m with the paper's circulation (results/paper/optimize.md) and 14.837 N·m
/// with the calibrated one (results/paper/verification.md), with the phases' durations kept, and
/// beats both further with the split free (measured at N = 200: 7.26 and 7.57 N·m).
#[test]
fn paper_schedule_beats_the_sequential_lp() {
    let (p, s) = paper();
    let calibrated = s.with_circulation(calibrate(&p.cat.half(), &s, 1e-10).circulation);
    for (path, lp) in [(&s, 9.8022), (&calibrated, 14.837)] {
        for (split, below) in [(Split::Kept, lp), (Split::Free, 7.8)] {
            let r = retime(&p.cat.half(), path, path.duration(), settings(200, split)).expect("valid");
            let m = r.remeasure(&p.cat.half(), 3200, 1e-10).expect("solved");
            assert!(m.peaks.max < below, "{split:?}: exact peak {} N·m, LP {lp} N·m", m.peaks.max);
        }
    }
}

#[test]
fn a_rate_limit_below_the_mean_rate_is_infeasible() {
    let (p, s) = paper();
    // ṡ ≤ 0.9 cannot cover the path (its mean rate is 1) in the original duration
    let r =
        retime(&p.cat.half(), &s, s.duration(), RetimeSettings { rate_limit: Some(0.9), ..settings(40, Split::Free) })
            .expect("valid input");
    assert_eq!(r.solution.status, RetimeStatus::Infeasible);
    assert!(r.solution.status.to_string().contains("infeasible"));
    assert!(r.trajectory.is_none() && r.solution.peak.is_nan());
}

#[test]
fn bad_input_names_the_field() {
    let (p, s) = paper();
    let field = |e: RetimeError| match e {
        RetimeError::BadInput { field, .. } => field,
        other => panic!("unexpected {other}"),
    };
    for t in [0.0, -1.0, f64::NAN, f64::INFINITY] {
        let e = retime(&p.cat.half(), &s, t, RetimeSettings::default()).expect_err("rejected");
        assert_eq!(field(e), "duration", "T = {t}");
    }
    let e = retime(&p.cat.half(), &s, 1.0, settings(1, Split::Kept)).expect_err("rejected");
    assert_eq!(field(e), "intervals");
    let e = retime(&p.cat.half(), &s, 1.0, RetimeSettings { rate_limit: Some(f64::NAN), ..RetimeSettings::default() })
        .expect_err("rejected");
    assert_eq!(field(e), "rate_limit");
    let node = PathNode { a: [1.0, 0.0], b: [f64::NAN, 0.0], tangent: [1.0, 0.0] };
    let problem = PathProblem {
        pieces: vec![PathPiece::uniform(1.0, vec![node; 5])],
        duration: 1.0,
        settings: RetimeSettings::default(),
        kept: None,
    };
    match problem.solve() {
        Err(RetimeError::NonFinitePath { piece: 0, what: "b", .. }) => {}
        other => panic!("expected a non-finite path error, got {other:?}"),
    }
}

/// The single joint's line cut into two pieces that join straight: the joint rates are
/// continuous across the cut (no rest), and with the split free the two-piece retiming is the
/// one-piece one (the same grid: the cut falls on a node of the one-piece grid).
#[test]
fn a_straight_join_keeps_the_rates_continuous() {
    #[derive(Clone, Copy)]
    struct Halves(SingleJoint);
    impl Trajectory for Halves {
        fn piece_durations(&self) -> Vec<f64> {
            vec![0.5 * self.0.length; 2]
        }
        fn piece_state(&self, piece: usize, s: f64) -> JointState {
            self.0.piece_state(0, s + 0.5 * self.0.length * piece as f64)
        }
    }
    let cat = Problem::default().cat.half();
    let line = SingleJoint { d: 2.0, length: 1.0 };
    let whole = retime(&cat, &line, 0.6, settings(200, Split::Free)).expect("valid");
    let cut = retime(&cat, &Halves(line), 0.6, settings(100, Split::Free)).expect("valid");
    assert_eq!(cut.solution.status, RetimeStatus::Solved);
    assert_relative_eq!(cut.solution.peak, whole.solution.peak, max_relative = 1e-6);
    let traj = cut.trajectory.as_ref().expect("solved");
    let d = traj.piece_durations();
    let before = traj.piece_state(0, d[0]).qd[0];
    let after = traj.piece_state(1, 0.0).qd[0];
    assert!(before > 1.0, "the joint moves through the cut: {before} rad/s");
    assert_relative_eq!(before, after, max_relative = 1e-6);
}

/// A rest-to-rest move over `S` in `T` needs `|s̈| ≥ 4S/T²` somewhere (bang-bang is the least
/// peak acceleration): an acceleration limit just below is infeasible, just above it changes
/// nothing for constant `a`.
#[test]
fn an_acceleration_limit_below_bang_bang_is_infeasible() {
    let (a, length, duration) = (0.37, 2.5, 1.3);
    let node = PathNode { a: [a, 0.0], b: [0.0; 2], tangent: [1.0, 0.0] };
    let least = 4.0 * length / (duration * duration);
    for (factor, feasible) in [(0.95, false), (1.05, true)] {
        let problem = PathProblem {
            pieces: vec![PathPiece::uniform(length, vec![node; 33])],
            duration,
            settings: RetimeSettings { accel_limit: Some(factor * least), ..settings(32, Split::Kept) },
            kept: None,
        };
        let sol = problem.solve().expect("valid");
        if feasible {
            assert_eq!(sol.status, RetimeStatus::Solved);
            assert_relative_eq!(sol.peak, a * least, max_relative = 1e-7);
        } else {
            assert_eq!(sol.status, RetimeStatus::Infeasible, "limit {factor} × 4S/T²");
        }
    }
}

#[test]
fn the_schedule_retiming_is_well_posed_whatever_the_solver_tolerance() {
    // Timed by its own local time, the paper's path starts its twist with q' ∝ s², the optimal
    // ṡ is singular there and the split-free program so badly scaled that Clarabel's bounds at
    // tolerances 1e-8 and 1e-10 differed by 5.5e-6 (relative: 7.2460922 and 7.2460525 N·m), and
    // by 2e-3 as its equilibration changed, each "solved" with a duality gap near 1e-8.
    // Parametrised by the phases' progress variables (retime_schedule), both agree to the
    // tolerance.
    let p = Problem::default();
    let s = Schedule::new(&p, paper_circulation(&p.cat.half(), p.manoeuvre.theta()).expect("C > 0"));
    for split in [Split::Kept, Split::Free] {
        let bound = |tolerance: f64| {
            let mut settings = settings(200, split);
            settings.solver.tolerance = tolerance;
            let r = retime_schedule(&p.cat.half(), &s, settings).expect("valid");
            assert!(r.solution.status.is_solved(), "{split:?} at {tolerance:e}: {}", r.solution.status);
            r.solution.lower_bound
        };
        let (coarse, fine) = (bound(1e-8), bound(1e-10));
        assert_relative_eq!(coarse, fine, max_relative = 1e-6);
    }
}

#[test]
fn the_phase_path_is_the_schedules_path() {
    // The paper's schedule, and a cone path bent by 100° whose twist ends at q1 ≈ 4.54 rad, so
    // that it straightens towards (2π, 0), not (0, 0): the progress-variable path must follow the
    // schedule's own path (the same flip, a geometric phase) and end where it ends.
    use catflip::problem::manoeuvre::BendPath;
    use catflip::schedule::Phase;
    let paper = Problem::default();
    let mut cone = Problem::default();
    cone.manoeuvre.theta_deg = 80.0;
    cone.manoeuvre.bend_path = BendPath::Cone;
    for (p, circulation) in
        [(&paper, paper_circulation(&paper.cat.half(), paper.manoeuvre.theta()).expect("C > 0")), (&cone, 3.0)]
    {
        let s = Schedule::new(p, circulation);
        let path = PhasePath { schedule: s.clone() };
        let (a, b) = (flip(&p.cat.half(), &s, 1e-11), flip(&p.cat.half(), &path, 1e-11));
        assert!((a.orientation.inverse() * b.orientation).angle() < 1e-10, "{a:?} vs {b:?}");
        let lengths = path.piece_durations();
        for (k, phase) in Phase::ALL.into_iter().enumerate() {
            let end = path.piece_state(k, lengths[k]).q;
            let want = s.phase_state(phase, s.durations[k]).q;
            assert!((end[0] - want[0]).hypot(end[1] - want[1]) < 1e-12, "{phase:?} ends at {end:?}, not {want:?}");
        }
    }
}
