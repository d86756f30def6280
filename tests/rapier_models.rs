//! Rapier on cats other than the paper's (issue 22): unequal halves on the universal joint and
//! Kane and Scher's no-twist joint (a ball joint) are built, joined where the model joins them and
//! verified against the general exact engine; what the scene does not build is refused, naming
//! the joint.
#![deny(clippy::float_cmp)]

use std::path::Path;

use approx::assert_relative_eq;
use nalgebra::Vector3;

use catflip::engines::models::TwoMotorCat;
use catflip::engines::rapier::{
    simulate_with, verify, CatScene, MassModel, RapierError, RapierOptions, Reference, Status,
};
use catflip::engines::resolved::Resolved;
use catflip::model::motor::{Motor, Motors};
use catflip::model::{joint_rotation, Cat, Cylinder, Joint};
use catflip::problem::Problem;

/// The front and rear halves of `problems/unequal-halves.toml`.
const FRONT: Cylinder = Cylinder { mass: 0.8, length: 0.8, radius: 0.1 };
const REAR: Cylinder = Cylinder { mass: 1.2, length: 1.0, radius: 0.1 };

fn unequal() -> Cat {
    Cat { front: FRONT, rear: REAR, joint: Joint::Universal }
}

fn resolved(file: &str) -> Resolved {
    let problem = Problem::load(&Path::new("problems").join(file), &[]).unwrap_or_else(|e| panic!("{file}: {e}"));
    Resolved::new(&problem).unwrap_or_else(|e| panic!("{file}: {e}"))
}

/// Each half keeps its own mass and inertia; the cross is the tiny body between the revolutes.
#[test]
fn each_half_keeps_its_own_mass_and_inertia() {
    let m = MassModel::new(&unequal(), 1e-6);
    assert_relative_eq!(m.mass[0], FRONT.mass, epsilon = 0.0);
    assert_relative_eq!(m.mass[2], REAR.mass, epsilon = 0.0);
    assert_relative_eq!(m.mass[1], 1e-6 * 1.0, max_relative = 1e-15);
    assert_relative_eq!(m.inertia[0][0], FRONT.transverse(), epsilon = 0.0);
    assert_relative_eq!(m.inertia[2][0], REAR.transverse(), epsilon = 0.0);
    assert_relative_eq!(m.inertia[2][2], REAR.axial(), epsilon = 0.0);
    assert_relative_eq!(m.half_lengths[0], 0.4, epsilon = 0.0);
    assert_relative_eq!(m.half_lengths[1], 0.5, epsilon = 0.0);
}

/// DESIGN.md §10: the joint sits at A's `(0, 0, −l_A/2)` and B's `(0, 0, +l_B/2)`, and B turns
/// relative to A by `Rx(q1) Ry(q2)`; rapier's joint coordinates read back the same angles.
#[test]
fn unequal_halves_are_joined_where_the_model_joins_them() {
    let q = [0.3, -0.5];
    let scene = CatScene::new(&unequal(), 1e-6, 1e-3, 8, None, q).unwrap_or_else(|e| panic!("{e}"));
    let s = scene.snapshot().unwrap_or_else(|e| panic!("{e}"));
    let rel = (s.rotations[0].inverse() * s.rotations[2]).to_rotation_matrix().into_inner();
    assert_relative_eq!(rel, joint_rotation(q), epsilon = 1e-12);
    let joint_in_a = s.positions[0] + s.rotations[0] * Vector3::new(0.0, 0.0, -0.5 * FRONT.length);
    let joint_in_b = s.positions[2] + s.rotations[2] * Vector3::new(0.0, 0.0, 0.5 * REAR.length);
    assert_relative_eq!(joint_in_a, joint_in_b, epsilon = 1e-12);
    assert_relative_eq!(s.joint_point(scene.masses()), joint_in_a, epsilon = 1e-12);
    for (read, set) in s.q.iter().zip(q) {
        assert_relative_eq!(*read, set, epsilon = 1e-12);
    }
}

/// The library schedule of `problems/unequal-halves.toml` (calibrated circulation) is verified in
/// rapier against the general exact engine; the same schedule's numbers on the paper's cat of the
/// mean half (1 kg, 0.9 m) are not what rapier's unequal cat does, so the scene is the model's.
#[test]
fn a_library_schedule_on_unequal_halves_is_verified_against_the_general_core() {
    let r = resolved("unequal-halves.toml");
    assert!(r.model().cat().paper().is_none());
    let e = r.evaluate(&r.schedule);
    let reference = Reference { twist: e.flip.twist, swing: e.flip.swing, peak_torque: e.peaks.max };
    let v = verify(r.model(), &r.schedule, &r.problem.rapier, &reference).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(v.status, Status::Verified, "{}\n{}", v.verdict, v.to_text());

    let mean = TwoMotorCat::paper(r.model().cat().mean_half());
    let m = mean.flip(&r.schedule, 1e-10);
    let wrong = Reference { twist: m.twist, swing: m.swing, peak_torque: e.peaks.max };
    // 1.7° apart, more than twice the verification's twist tolerance.
    let apart = (m.twist - e.flip.twist).abs().to_degrees();
    assert!(apart > 2.0 * r.problem.rapier.twist_tolerance_deg, "the mean cat turns {apart}° from the model");
    let v = verify(r.model(), &r.schedule, &r.problem.rapier, &wrong).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(v.status, Status::NotVerified, "{}", v.verdict);
}

/// DESIGN.md §10: the no-twist joint turns B by `exp([q1, q2, 0]×)` about the joint point at A's
/// `(0, 0, −l_A/2)` and B's `(0, 0, +l_B/2)`; the scene reads the same coordinates back.
#[test]
fn the_no_twist_joint_is_a_ball_joint_where_the_model_puts_it() {
    let cat = Cat { joint: Joint::NoTwist, ..unequal() };
    let q = [0.3, -0.5];
    let scene = CatScene::new(&cat, 1e-6, 1e-3, 8, None, q).unwrap_or_else(|e| panic!("{e}"));
    let s = scene.snapshot().unwrap_or_else(|e| panic!("{e}"));
    let rel = (s.rotations[0].inverse() * s.rotations[2]).to_rotation_matrix().into_inner();
    assert_relative_eq!(rel, Joint::NoTwist.rotation(&q), epsilon = 1e-12);
    let joint_in_a = s.positions[0] + s.rotations[0] * Vector3::new(0.0, 0.0, -0.5 * FRONT.length);
    let joint_in_b = s.positions[2] + s.rotations[2] * Vector3::new(0.0, 0.0, 0.5 * REAR.length);
    assert_relative_eq!(joint_in_a, joint_in_b, epsilon = 1e-12);
    for (read, set) in s.q.iter().zip(q) {
        assert_relative_eq!(*read, set, epsilon = 1e-12);
    }
}

/// Kane and Scher's cat (`problems/kane-scher.toml`, the paper's π/C) is verified in rapier's ball
/// joint against the general exact engine; the paper's universal joint on the same halves and
/// schedule turns the cat 5.9° less, and that reference is not what rapier's no-twist cat does.
#[test]
fn kane_and_schers_cat_is_verified_on_the_ball_joint() {
    let r = resolved("kane-scher.toml");
    assert_eq!(r.model().cat().joint, Joint::NoTwist);
    let e = r.evaluate(&r.schedule);
    let reference = Reference { twist: e.flip.twist, swing: e.flip.swing, peak_torque: e.peaks.max };
    let v = verify(r.model(), &r.schedule, &r.problem.rapier, &reference).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(v.status, Status::Verified, "{}\n{}", v.verdict, v.to_text());
    let tracking = v.tracking_error_rad.unwrap_or([f64::NAN; 2]);
    assert!(tracking.iter().all(|t| *t < 1e-4), "tracking error {tracking:?} rad");

    let universal = TwoMotorCat::paper(r.model().cat().front);
    let u = universal.flip(&r.schedule, 1e-10);
    let apart = (u.twist - e.flip.twist).abs().to_degrees();
    assert!(apart > 2.0 * r.problem.rapier.twist_tolerance_deg, "the universal joint turns {apart}° from the model");
    let wrong = Reference { twist: u.twist, swing: u.swing, peak_torque: e.peaks.max };
    let v = verify(r.model(), &r.schedule, &r.problem.rapier, &wrong).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(v.status, Status::NotVerified, "{}", v.verdict);
}

/// Motor limits on the ball joint are refused (it drives the relative rotation, not the two motor
/// axes), and the spherical joint's third motor is not built: each refused, naming the joint.
#[test]
fn what_the_ball_joint_cannot_do_is_refused() {
    let r = resolved("kane-scher.toml");
    let limited = Motor { torque: Some(1.0), ..Motor::default() };
    let opts = RapierOptions::within(Motors { joints: [limited, limited] });
    let e = simulate_with(r.model(), &r.schedule, &r.problem.rapier, &opts).map(|_| ()).unwrap_err();
    assert!(matches!(e, RapierError::LimitsOnJoint(Joint::NoTwist)), "{e}");
    let cat = Cat { joint: Joint::Spherical, ..unequal() };
    let e = CatScene::new(&cat, 1e-6, 1e-3, 8, None, [0.0; 2]).err().unwrap_or_else(|| panic!("built"));
    assert!(matches!(e, RapierError::UnsupportedJoint(Joint::Spherical)), "{e}");
    assert!(e.to_string().starts_with("cat.joint = \"spherical\""), "{e}");
}
