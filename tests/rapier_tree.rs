//! Rapier's scene of a tree of bodies (issue 22: the cats beyond two motors): on a two-body cat it
//! runs as the two-body scene does, and it refuses what it does not run, naming it.

use catflip::engines::models::{flip_on, TwoMotorCat};
use catflip::engines::rapier::tree_run::{simulate_tree, verify_tree};
use catflip::engines::rapier::{simulate_with, RapierError, RapierOptions, Reference, Status};
use catflip::engines::reduction;
use catflip::model::motor::{Motor, Motors};
use catflip::model::{Cat, Cylinder, Joint};
use catflip::optimize::whole::spline::SplineShape;
use catflip::optimize::whole::BSpline;
use catflip::problem::settings::{RapierSettings, TimeStep};
use nalgebra::Vector3;

mod common;

const HALF: Cylinder = Cylinder { mass: 1.0, length: 1.0, radius: 0.1 };

/// A smooth two-coordinate path over 1.2 s that bends, circulates and unbends (a cubic B-spline,
/// rest to rest), in either joint's coordinates.
fn circulation() -> BSpline {
    let mut s = BSpline::zero(1.2, 12, 3);
    s.coefficients = vec![
        vec![0.0, 0.0, 0.3, 0.8, 0.9, 0.2, -0.6, -0.9, -0.5, 0.1, 0.0, 0.0],
        vec![0.0, 0.0, 0.1, -0.4, 0.5, 0.9, 0.6, -0.2, -0.7, -0.2, 0.0, 0.0],
    ];
    s
}

/// The tree scene, built from the general core's tree of the two halves, against the two-body
/// scene ([`simulate_with`]) on the same smooth path at the same step: the same bodies, joints
/// and motors built another way. They differ only in the tiny joint body's inertia (5e-9 against
/// 4e-9 kg·m², `rapier.cross_mass_fraction` = 1e-6), which changes how far rapier's eight
/// Gauss–Seidel sweeps get with the motor rows: the peaks agree to 1.6e-6 of the peak (measured),
/// the twist to 1e-4°, far below rapier's own error at this step (1.8° at 0.6 ms,
/// `examples/more_motors.rs`).
#[test]
fn the_tree_scene_runs_a_two_body_cat_as_the_two_body_scene_does() {
    let path = circulation();
    let settings = RapierSettings { dt: TimeStep::Fixed(6e-4), ..RapierSettings::default() };
    for joint in [Joint::Universal, Joint::NoTwist] {
        let cat = Cat::equal(HALF, joint);
        let two =
            simulate_with(&TwoMotorCat::new(cat).expect("two motors"), &path, &settings, &RapierOptions::default())
                .unwrap_or_else(|e| panic!("{joint}: {e}"));
        let tree = simulate_tree(&cat.tree(), &path, &settings, &RapierOptions::default())
            .unwrap_or_else(|e| panic!("{joint}: {e}"));
        assert_eq!((tree.steps, tree.dt), (two.steps, two.dt), "{joint}");
        let (dtwist, dswing) = ((tree.twist - two.twist).abs(), (tree.swing - two.swing).abs());
        assert!(dtwist.to_degrees() < 1e-4 && dswing.to_degrees() < 1e-4, "{joint}: {dtwist} {dswing} rad apart");
        assert!(tree.twist.abs().to_degrees() > 10.0, "{joint}: the path turns the cat ({} rad)", tree.twist);
        let peaks = two.peak_torque.max;
        for (j, p) in tree.peak_torque.iter().enumerate() {
            let other = two.peak_torque.per_piece.iter().map(|x| x[j]).fold(0.0, f64::max);
            assert!((p - other).abs() <= 1e-5 * peaks, "{joint} motor {}: {p} against {other} N·m", j + 1);
        }
        let drift = (tree.momentum.max_abs - two.momentum.max_abs).abs();
        assert!(
            drift <= 1e-3 * two.momentum.max_abs,
            "{joint}: drift {} against {}",
            tree.momentum.max_abs,
            two.momentum.max_abs
        );
        assert!(tree.tracking_error.iter().all(|e| *e < 1e-5), "{joint}: tracking {:?} rad", tree.tracking_error);
    }
}

/// What the tree scene does not run is refused with the reason: motor limits, spin, a path of
/// the wrong size, and a schedule whose phases join with a jump (the paper's own).
#[test]
fn the_tree_scene_refuses_what_it_does_not_run() {
    let tree = Cat::equal(HALF, Joint::Spherical).tree();
    let settings = RapierSettings { dt: TimeStep::Fixed(1e-3), ..RapierSettings::default() };
    let three = circulation().with_joints(3);
    let limit = Motor { torque: Some(1.0), ..Motor::default() };
    let limited = RapierOptions::within(Motors { joints: [limit; 2] });
    let spinning = RapierOptions { spin: Vector3::new(0.0, 0.0, 0.1), ..RapierOptions::default() };
    let (_, paper) = common::paper();
    let cases: Vec<(Result<_, RapierError>, &str)> = vec![
        (simulate_tree(&tree, &three, &settings, &limited), "ideal motors only"),
        (simulate_tree(&tree, &three, &settings, &spinning), "without spin"),
        (
            simulate_tree(&tree, &circulation(), &settings, &RapierOptions::default()),
            "has 3 joint coordinates; the trajectory has 2",
        ),
        (
            simulate_tree(&Cat::equal(HALF, Joint::Universal).tree(), &paper, &settings, &RapierOptions::default()),
            "join smoothly",
        ),
    ];
    for (result, expected) in cases {
        let message = result.err().map(|e| e.to_string()).unwrap_or_default();
        assert!(message.contains(expected), "{message:?} does not say {expected:?}");
    }
}

/// A cat with a tail on each joint (universal, no-twist, spherical: four, four and five motors)
/// along a smooth path that moves every coordinate, verified in rapier against the general core:
/// its flip (the adaptive engine on the three-body tree, 1e-12 rad) and its peak torque (its
/// Newton–Euler, sampled at 6001 instants), within the default tolerances (0.5°, 2 %).
#[test]
fn a_tail_on_every_joint_is_verified_against_the_general_core() {
    let cat = Cat::equal(HALF, Joint::NoTwist);
    let tail = Cylinder { mass: 0.2, length: 1.0, radius: 0.02 };
    for joint in Joint::ALL {
        let tree = cat.tree_with_tail(&tail, joint);
        let mut path = circulation().with_joints(tree.dof());
        for (k, c) in path.coefficients.iter_mut().enumerate().skip(2) {
            // The tail's coordinates: a swing and, on the spherical joint, a twist.
            let phase = k as f64;
            for (i, x) in c.iter_mut().enumerate().take(10).skip(2) {
                *x = 0.5 * (0.7 * i as f64 + phase).sin();
            }
        }
        let flip = flip_on(&tree, &SplineShape(&path), &Vector3::zeros(), 1e-12);
        let peak = (0..=6000)
            .map(|k| path.shape_from(&path.basis(path.span_of(1.2 * k as f64 / 6000.0), 1.2 * k as f64 / 6000.0)))
            .flat_map(|shape| {
                reduction::joint_torques(&tree, &shape, &Vector3::zeros()).into_iter().flat_map(|l| l.tau)
            })
            .fold(0.0, |m: f64, t| m.max(t.abs()));
        let reference = Reference { twist: flip.twist, swing: flip.swing, peak_torque: peak };
        let v =
            verify_tree(&tree, &SplineShape(&path), &RapierSettings::default(), &reference, &RapierOptions::default())
                .unwrap_or_else(|e| panic!("{joint}: {e}"));
        assert_eq!(v.status, Status::Verified, "tail on the {joint} joint: {}", v.verdict);
        assert!(flip.twist.abs().to_degrees() > 10.0, "{joint}: the path turns the cat ({} rad)", flip.twist);
    }
}
