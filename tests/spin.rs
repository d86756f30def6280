//! A release with spin (DESIGN.md §9): the exact engine with total angular momentum `L ≠ 0`
//! against closed forms, against the zero-momentum engine, and its own conservation laws.
#![deny(clippy::float_cmp)]

use catflip::engines::evaluate::Evaluation;
use catflip::engines::exact::{body_rate_spinning, flip, flip_spinning, momentum};
use catflip::engines::models::TwoMotorCat;
use catflip::engines::spin::SpinHistory;
use catflip::engines::torque::{joint_torques_spinning, kinematics_spinning};
use catflip::model::Cylinder;
use catflip::problem::Problem;
use catflip::schedule::{paper_circulation, Schedule, Trajectory};
use nalgebra::{UnitQuaternion, Vector3};

mod common;
use common::Held;

fn paper_schedule(p: &Problem) -> Schedule {
    let d = paper_circulation(&p.cat.half(), p.manoeuvre.theta()).expect("C > 0 for the paper's cat");
    Schedule::new(p, d)
}

/// The straight cat's principal inertias about its centre of mass: transverse `2 (I_t + m l²/4)`
/// and axial `2 I_a`.
fn straight_inertia(cat: &Cylinder) -> (f64, f64) {
    (2.0 * cat.end_transverse(), 2.0 * cat.axial())
}

/// The torque-free symmetric top released at the identity with momentum `l` (Goldstein §5.6):
/// `R(t) = exp(t |L|/I₁ [L̂]×) exp(t L_z (1/I₃ − 1/I₁) [ẑ]×)`. Its body momentum `Rᵀ L` turns
/// about `ẑ` at `L_z (1/I₁ − 1/I₃)` while `L` stays fixed in space.
fn symmetric_top(l: &Vector3<f64>, i1: f64, i3: f64, t: f64) -> UnitQuaternion<f64> {
    let precession = UnitQuaternion::from_scaled_axis(l * (t / i1));
    let spin = UnitQuaternion::from_scaled_axis(Vector3::z() * (t * l.z * (1.0 / i3 - 1.0 / i1)));
    precession * spin
}

#[test]
fn a_rigid_straight_cat_tumbles_as_the_torque_free_symmetric_top() {
    let cat = Cylinder::default();
    let (i1, i3) = straight_inertia(&cat);
    for l in [Vector3::new(0.01, 0.0, 0.02), Vector3::new(-0.3, 0.2, 0.004), Vector3::new(0.0, 0.05, -0.01)] {
        let held = Held { q: [0.0, 0.0], duration: 1.5 };
        let f = flip_spinning(&cat, &held, &l, 1e-12);
        let expected = symmetric_top(&l, i1, i3, held.duration);
        let gap = (expected.inverse() * f.orientation).angle();
        assert!(f.converged, "L = {l}: the integration did not converge");
        assert!(gap < 1e-10, "L = {l}: the engine's attitude is {gap:.3e} rad from the closed form");
    }
}

#[test]
fn momentum_along_a_principal_axis_of_the_straight_cat_is_a_steady_spin() {
    let cat = Cylinder::default();
    let (i1, i3) = straight_inertia(&cat);
    let held = Held { q: [0.0, 0.0], duration: 1.2 };
    // About the spine: a pure twist at L_z / I₃.
    let lz = 0.004;
    let f = flip_spinning(&cat, &held, &Vector3::new(0.0, 0.0, lz), 1e-12);
    let twist = lz * held.duration / i3;
    assert!((f.twist - twist).abs() < 1e-10, "twist {} rad, steady spin gives {twist} rad", f.twist);
    assert!(f.swing.abs() < 1e-10, "swing {} rad about the spine", f.swing);
    // About a transverse axis: the spine swings by L_x T / I₁, no twist.
    let lx = 0.2;
    let f = flip_spinning(&cat, &held, &Vector3::new(lx, 0.0, 0.0), 1e-12);
    let swing = lx * held.duration / i1;
    assert!((f.swing - swing).abs() < 1e-10, "swing {} rad, steady spin gives {swing} rad", f.swing);
    assert!(f.twist.abs() < 1e-10, "twist {} rad about a transverse axis", f.twist);
}

#[test]
fn a_bent_rigid_cat_spins_about_a_principal_axis_of_its_locked_inertia() {
    // Bent and held, the cat is a rigid body with the locked inertia I_lock(q); with L along one
    // of its principal axes it turns steadily about that axis at |L| / I_k.
    let cat = Cylinder::default();
    let q = [0.7, -0.4];
    let cfg = cat.configuration(q);
    let eig = cfg.locked_inertia.symmetric_eigen();
    let held = Held { q, duration: 1.0 };
    for k in 0..3 {
        let axis = eig.eigenvectors.column(k).into_owned();
        let l = axis * 0.05;
        let f = flip_spinning(&cat, &held, &l, 1e-12);
        let expected = UnitQuaternion::from_scaled_axis(axis * (0.05 * held.duration / eig.eigenvalues[k]));
        let gap = (expected.inverse() * f.orientation).angle();
        assert!(gap < 1e-10, "principal axis {k}: {gap:.3e} rad from the steady spin");
    }
}

#[test]
fn a_vanishing_spin_reproduces_the_zero_momentum_engine() {
    // The Runge–Kutta path with L = 1e-15 N·m·s against the Magnus path at L = 0: two different
    // integrators of the same motion (the spin's own effect is ~1e-13 rad).
    let p = Problem::default();
    let s = paper_schedule(&p);
    let magnus = flip(&p.cat.half(), &s, 1e-11);
    let rk = flip_spinning(&p.cat.half(), &s, &Vector3::new(1e-15, -1e-15, 1e-15), 1e-11);
    assert!(rk.converged && magnus.converged);
    let gap = (magnus.orientation.inverse() * rk.orientation).angle();
    assert!(gap < 1e-10, "Runge–Kutta and Magnus differ by {gap:.3e} rad");
    // And L = 0 through the spinning entry point is the Magnus engine itself.
    let zero = flip_spinning(&p.cat.half(), &s, &Vector3::zeros(), 1e-11);
    assert_eq!(zero.steps_per_phase, magnus.steps_per_phase);
    assert!((zero.twist - magnus.twist).abs() <= 0.0, "L = 0 must take the Magnus path");
}

#[test]
fn the_spin_is_conserved_in_the_world_frame_along_the_paper_schedule() {
    let mut p = Problem::default();
    p.drop.angular_momentum = [0.01, 0.02, -0.03];
    let s = paper_schedule(&p);
    let e = Evaluation::of_paper(&p.cat.half(), &s, &p.drop.spin(), &p.actuator.motors(), &p.exact);
    assert!(e.flip.converged);
    assert!(e.momentum_max < 1e-12, "|R H − L| relative {:.3e}", e.momentum_max);
    // Action = reaction holds only when Ω̇ is the true rate of the spinning motion.
    assert!(
        e.peaks.action_reaction_gap < 1e-9 * e.peaks.max,
        "action–reaction gap {:.3e} N·m",
        e.peaks.action_reaction_gap
    );
    // The spin changes the flip: the paper's schedule turns the cat differently.
    let still = flip(&p.cat.half(), &s, p.exact.tolerance);
    assert!((e.flip.twist - still.twist).abs() > 1e-3, "the spin left the twist unchanged");
}

#[test]
fn the_spinning_body_acceleration_is_the_derivative_of_the_body_rate() {
    // Ω̇ of kinematics_spinning against a central difference of Ω(t) = I_lock⁻¹(R(t)ᵀ L − h)
    // along the paper's twist phase, with R(t) from the history.
    let mut p = Problem::default();
    p.drop.angular_momentum = [0.05, -0.02, 0.01];
    let s = paper_schedule(&p);
    let spin = p.drop.spin();
    let (_, history) = SpinHistory::new(&p.cat.half(), &s, &spin, 1e-12);
    let rate = |t: f64| {
        let st = s.piece_state(1, t);
        body_rate_spinning(&p.cat.half(), st.q, st.qd, &history.body_momentum(&p.cat.half(), &s, 1, t))
    };
    for t in [0.05, 0.3, 0.61, 0.8] {
        let st = s.piece_state(1, t);
        let lambda = history.body_momentum(&p.cat.half(), &s, 1, t);
        let k = kinematics_spinning(&p.cat.half(), &st, &lambda);
        let h = 1e-5;
        let fd = (rate(t + h) - rate(t - h)) / (2.0 * h);
        let gap = (k.omega_dot - fd).norm();
        assert!(gap < 1e-6 * k.omega_dot.norm().max(1.0), "t = {t}: Ω̇ {} against {fd}, gap {gap:.3e}", k.omega_dot);
        // |λ| = |L|: the history's attitude is a rotation, and H = λ in A's frame.
        assert!((lambda.norm() - spin.norm()).abs() < 1e-15);
        assert!((momentum(&p.cat.half(), &st, &k.omega) - lambda).norm() < 1e-14);
        let tau = joint_torques_spinning(&p.cat.half(), &st, &lambda);
        let gap = (tau.tau[0] - tau.from_a[0]).abs().max((tau.tau[1] - tau.from_a[1]).abs());
        assert!(gap < 1e-9, "t = {t}: action–reaction gap {gap:.3e} N·m");
    }
}

#[test]
fn a_spin_too_large_to_be_a_flip_is_refused_and_a_large_one_warned_about() {
    let err = Problem::from_toml("[drop]\nangular_momentum = [1e3, 0, 0]\n", "t.toml", &[])
        .expect_err("a thousand N·m·s spins the cat thousands of turns");
    let msg = err.to_string();
    assert!(msg.contains("drop.angular_momentum") && msg.contains("turns"), "{msg}");
    let err = Problem::from_toml("[drop]\nangular_momentum = [0, nan, 0]\n", "t.toml", &[]).expect_err("NaN");
    // Counted from 0, as manoeuvre.phases[i] and the sweep's axis[i] are: [0, nan, 0] is element 1.
    assert!(err.to_string().contains("drop.angular_momentum[1]"), "{err}");
    // 1 N·m·s about the spine of the paper's cat: dozens of turns in the fall, warned about.
    let p = Problem::from_toml("[drop]\nangular_momentum = [0, 0, 0.3]\n", "t.toml", &[]).expect("loads");
    assert!(p.warnings().iter().any(|w| w.contains("drop.angular_momentum")), "{:?}", p.warnings());
    let p = Problem::from_toml("[drop]\nangular_momentum = [0.01, 0, 0]\n", "t.toml", &[]).expect("loads");
    assert!(!p.warnings().iter().any(|w| w.contains("drop.angular_momentum")));
}

#[test]
fn computations_that_assume_no_spin_refuse_one() {
    let p = Problem::from_toml("[drop]\nangular_momentum = [0, 0, 0.01]\n", "t.toml", &[]).expect("loads");
    let err = p.require_no_spin("optimize --whole").expect_err("a spin");
    let msg = err.to_string();
    assert!(msg.contains("drop.angular_momentum") && msg.contains("optimize --whole"), "{msg}");
    assert!(Problem::default().require_no_spin("optimize --whole").is_ok());
}

#[test]
fn rapier_started_with_the_spin_verifies_the_spinning_flip() {
    // rapier knows nothing of the exact engine's spin formula: it starts the multibody with the
    // rigid rotation that gives it momentum L and integrates Newton's laws. Its dt → 0 estimate
    // must agree with the exact engine's spinning flip (the spin moves the twist by ~3° here).
    use catflip::engines::rapier::{verify_with, RapierOptions, Reference, Status};
    let mut p = Problem::default();
    p.drop.angular_momentum = [0.01, 0.02, -0.03];
    let s = paper_schedule(&p);
    let e = Evaluation::of_paper(&p.cat.half(), &s, &p.drop.spin(), &p.actuator.motors(), &p.exact);
    let reference = Reference { twist: e.flip.twist, swing: e.flip.swing, peak_torque: e.peaks.max };
    let cat = TwoMotorCat::paper(p.cat.half());
    let v = verify_with(&cat, &s, &p.rapier, &reference, &RapierOptions::for_problem(&p)).expect("a valid scene");
    assert_eq!(v.status, Status::Verified, "{}\n{}", v.verdict, v.to_text());
    // Without the spin, rapier lands elsewhere: the same reference is then not verified.
    let still = RapierOptions::within(p.actuator.motors());
    let v = verify_with(&cat, &s, &p.rapier, &reference, &still).expect("a valid scene");
    assert_eq!(v.status, Status::NotVerified, "{}", v.verdict);
}

/// Twist and swing (degrees) of the paper's schedule released with spin `L`, from an independent
/// derivation (`tests/reference/spin.py`, `spinrun.py`: written without the Rust source; SciPy's
/// DOP853 at rtol = atol = 1e-13 on a unit quaternion, restarted at each phase; converged to
/// ~1e-11°, `tests/reference/README.md`).
const REFERENCE_FLIPS: [([f64; 3], f64, f64); 8] = [
    ([0.0, 0.0, 0.0], -174.067345148963, 0.590135829642),
    ([0.01, 0.0, 0.0], -173.979191910851, 2.390839840611),
    ([0.0, 0.01, 0.0], -174.045798158710, 4.830650438362),
    ([0.0, 0.0, 0.01], -158.106453297382, 0.580134342112),
    ([0.05, 0.0, 0.0], -173.854927901643, 12.135735533106),
    ([0.0, 0.05, 0.0], -173.718443169551, 21.819300165255),
    ([0.0, 0.0, 0.05], -94.262929899460, 0.540829792210),
    ([0.01, 0.02, -0.03], -221.609078960094, 10.037103031316),
];

#[test]
fn the_spinning_paper_schedule_matches_an_independent_derivation() {
    let mut p = Problem::default();
    let s = paper_schedule(&p);
    for (l, twist, swing) in REFERENCE_FLIPS {
        p.drop.angular_momentum = l;
        let f = flip_spinning(&p.cat.half(), &s, &p.drop.spin(), p.exact.tolerance);
        let (dt, ds) = (f.twist.to_degrees() - twist, f.swing.to_degrees() - swing);
        assert!(f.converged, "L = {l:?}: not converged");
        // Target of issue 21: the engine within 1e-6° of the independent values.
        assert!(dt.abs() < 1e-6 && ds.abs() < 1e-6, "L = {l:?}: twist off by {dt:.2e}°, swing by {ds:.2e}°");
    }
}

/// Per-phase peak motor torques (N·m, `[bend, twist, unbend]` × joint) of the paper's schedule
/// released with spin, from the same independent derivation (Newton–Euler on B checked against
/// A's side, an Euler–Lagrange derivation and finite differences, to ≤ 6e-9 relative).
const REFERENCE_PEAKS: [([f64; 3], [[f64; 2]; 3]); 3] = [
    ([0.0, 0.0, 0.01], [[21.3099630469, 0.4451653388], [66.4664065103, 45.8473766963], [19.3956214623, 3.1605446529]]),
    ([0.05, 0.0, 0.0], [[21.3061479351, 0.0], [66.5006506810, 45.8243448128], [19.3913496803, 3.1597305570]]),
    (
        [0.01, 0.02, -0.03],
        [[21.3060090929, 1.3355475216], [66.3604996213, 45.9186617643], [19.3923337035, 3.1600739299]],
    ),
];

#[test]
fn the_spinning_torques_match_an_independent_derivation() {
    let mut p = Problem::default();
    let s = paper_schedule(&p);
    for (l, peaks) in REFERENCE_PEAKS {
        p.drop.angular_momentum = l;
        let e = Evaluation::of_paper(&p.cat.half(), &s, &p.drop.spin(), &p.actuator.motors(), &p.exact);
        let pp = e.phase_peaks();
        let got = [pp.bend, pp.twist, pp.unbend];
        for (phase, (g, r)) in got.iter().zip(peaks).enumerate() {
            for j in 0..2 {
                // 1e-6 relative to the phase's larger peak (a joint at rest has none).
                let gap = (g[j] - r[j]).abs() / r[0].max(r[1]);
                assert!(gap < 1e-6, "L = {l:?}, phase {phase}, joint {}: {} N·m against {} N·m", j + 1, g[j], r[j]);
            }
        }
    }
}

#[test]
fn an_imported_schedule_is_measured_with_the_spin() {
    // The paper's schedule as exported by `catflip run` (results/paper/schedules/problem.csv),
    // read back with a spin: the same flip and peaks as the built-in schedule with that spin.
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("results/paper/schedules/problem.csv");
    let imported = catflip::exchange::read_schedule(&path).expect("the committed export reads back");
    let mut p = Problem::default();
    p.drop.angular_momentum = [0.0, 0.0, 0.01];
    let report = catflip::report::import::evaluate(&p, &imported).expect("evaluates");
    let e = Evaluation::of_paper(&p.cat.half(), &paper_schedule(&p), &p.drop.spin(), &p.actuator.motors(), &p.exact);
    let gap = (report.figures.twist_deg - e.twist_deg()).abs();
    assert!(gap < 1e-6, "imported twist {}° against {}°", report.figures.twist_deg, e.twist_deg());
    assert!((report.peak_torque_nm.max - e.peaks.max).abs() < 1e-6 * e.peaks.max);
    assert!(report.figures.momentum_max < 1e-12, "momentum check {:.3e}", report.figures.momentum_max);
    assert!(!report.warnings.iter().any(|w| w.contains("too far apart")), "{:?}", report.warnings);
}
