//! Rapier's scene of a tree of bodies (issue 22: the cats beyond two motors): on a two-body cat it
//! runs as the two-body scene does, and it refuses what it does not run, naming it.

use catflip::engines::models::{flip_on, TwoMotorCat};
use catflip::engines::rapier::tree_run::{simulate_tree, verify_tree};
use catflip::engines::rapier::tree_scene::TreeScene;
use catflip::engines::rapier::{simulate_with, MotorGains, RapierError, RapierOptions, Reference, Status};
use catflip::engines::reduction;
use catflip::model::cat::Appendages;
use catflip::model::motor::{Motor, Motors};
use catflip::model::tree::Tree;
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
/// Gauss–Seidel sweeps get with the motor rows. Measured: the peaks agree to 1.6e-6 of the peak,
/// the twist and swing to 1e-5° (held to 1e-4°, far below rapier's own error at this step, 1.8°
/// at 0.6 ms, `examples/more_motors.rs`), the momentum drift to 1.4e-6 of itself (held to 1e-5),
/// and the joints track their plan to 1.4e-6 rad (held to 1e-5: the servo shrinks an error
/// twentyfold per step).
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
        assert_eq!(tree.steps, two.steps, "{joint}");
        assert!((tree.dt - two.dt).abs() <= 1e-15 * two.dt, "{joint}: {} against {} s", tree.dt, two.dt);
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
            drift <= 1e-5 * two.momentum.max_abs,
            "{joint}: drift {} against {}",
            tree.momentum.max_abs,
            two.momentum.max_abs
        );
        assert!(tree.tracking_error.iter().all(|e| *e < 1e-5), "{joint}: tracking {:?} rad", tree.tracking_error);
    }
}

/// What the tree scene does not run is refused with the reason: a torque limit on the spherical
/// joint (its motors are not its ball's axes), limits other than one torque limit, spin, a path of
/// the wrong size, a schedule whose phases join with a jump (the paper's own), and a step too
/// coarse to measure torques (fewer than ten steps in the trajectory).
#[test]
fn the_tree_scene_refuses_what_it_does_not_run() {
    let tree = Cat::equal(HALF, Joint::Spherical).tree();
    let settings = RapierSettings { dt: TimeStep::Fixed(1e-3), ..RapierSettings::default() };
    let spline = circulation().with_joints(3);
    let three = SplineShape(&spline);
    let limit = Motor { torque: Some(1.0), ..Motor::default() };
    let limited = RapierOptions::within(Motors { joints: [limit; 2] });
    let spinning = RapierOptions { spin: Vector3::new(0.0, 0.0, 0.1), ..RapierOptions::default() };
    let (_, paper) = common::paper();
    let cases: Vec<(Result<_, RapierError>, &str)> = vec![
        (simulate_tree(&tree, &three, &settings, &limited), "the spherical joint's motors are not its ball's axes"),
        (
            simulate_tree(
                &tree,
                &three,
                &settings,
                &RapierOptions::within(Motors { joints: [Motor { speed: Some(5.0), ..limit }; 2] }),
            ),
            "one torque limit on every motor only",
        ),
        (simulate_tree(&tree, &three, &settings, &spinning), "without spin"),
        (
            simulate_tree(&tree, &circulation(), &settings, &RapierOptions::default()),
            "has 3 joint coordinates; the trajectory has 2",
        ),
        (
            simulate_tree(&Cat::equal(HALF, Joint::Universal).tree(), &paper, &settings, &RapierOptions::default()),
            "smooth trajectories only",
        ),
        (
            simulate_tree(
                &tree,
                &three,
                &RapierSettings { dt: TimeStep::Fixed(0.5), ..settings },
                &RapierOptions::default(),
            ),
            "leaves only 2.4 steps",
        ),
    ];
    for (result, expected) in cases {
        let message = result.err().map(|e| e.to_string()).unwrap_or_default();
        assert!(message.contains(expected), "{message:?} does not say {expected:?}");
    }
}

/// The appendages' coordinates of `path` from its third on: smooth swings of `amplitude` rad.
fn swing_appendages(path: &mut BSpline, amplitude: f64) {
    for (k, c) in path.coefficients.iter_mut().enumerate().skip(2) {
        let phase = k as f64;
        for (i, x) in c.iter_mut().enumerate().take(10).skip(2) {
            *x = amplitude * (0.7 * i as f64 + phase).sin();
        }
    }
}

/// The cat with legs (a hinge at each pair's hips) and, when given, a tail on `tail`.
fn legged(tail: Option<Joint>) -> Tree {
    let appendages = Appendages { tail: tail.map(|j| (TAIL, j)), legs: Some([LEG; 2]) };
    Cat::equal(HALF, Joint::NoTwist).tree_with(&appendages)
}

const TAIL: Cylinder = Cylinder { mass: 0.2, length: 1.0, radius: 0.02 };
const LEG: Cylinder = Cylinder { mass: 0.2, length: 0.45, radius: 0.03 };

/// A cat with a tail on each joint (universal, no-twist, spherical, hinge: four, four, five and
/// three motors), and with legs (four motors; six with a tail too), along a smooth path that moves
/// every coordinate, verified in rapier against the general core: its flip (the adaptive engine on
/// the tree, 1e-12 rad) and its peak torque (its Newton–Euler, sampled at 6001 instants), within
/// the default tolerances (0.5°, 2 %).
#[test]
fn a_tail_on_every_joint_and_legs_are_verified_against_the_general_core() {
    let cat = Cat::equal(HALF, Joint::NoTwist);
    let tails =
        Joint::ALL.into_iter().chain([Joint::Hinge]).map(|joint| (joint.to_string(), cat.tree_with_tail(&TAIL, joint)));
    let legs = [("legs".to_string(), legged(None)), ("legs and a tail".to_string(), legged(Some(Joint::Universal)))];
    for (joint, tree) in tails.chain(legs) {
        let mut path = circulation().with_joints(tree.dof());
        // The tail's coordinates (a swing and, on the spherical joint, a twist), the legs'.
        swing_appendages(&mut path, 0.5);
        let flip = flip_on(&tree, &SplineShape(&path), &Vector3::zeros(), 1e-12);
        let peak = (0..=6000)
            .map(|k| path.shape(1.2 * k as f64 / 6000.0))
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

/// The bodies' velocities the tree scene maps from rapier's generalized velocities (on which
/// every momentum and torque it measures rests) are the bodies' own motion: on a cat with a tail
/// on the spherical joint (a ball for the halves too: the no-twist joint), moving along a smooth
/// path, each body's mapped velocity and angular velocity match the finite differences of its
/// poses over each step. Rapier's step is `x_k = x_{k−1} ⊕ h v_k` and the mapping is at `x_k`, so
/// they differ by `O(h)`: measured 2.1e-4 of the largest speed at `h` = 0.1 ms and half that at
/// 0.05 ms. A wrong mapping (a rate in the wrong frame, a missing body) would not shrink with `h`.
#[test]
fn mapped_velocities_are_the_bodies_motion() {
    let coarse = velocity_mismatch(1e-4);
    let fine = velocity_mismatch(5e-5);
    assert!(coarse <= 3e-4, "mapped velocities {coarse} of the largest speed off the poses' differences");
    let order = (coarse / fine).log2();
    assert!((0.9..=1.1).contains(&order), "the mismatch shrinks as h^{order}, not as h: {coarse} then {fine}");
}

/// The largest mismatch between mapped velocities and the poses' differences over 0.4 s at step
/// `h`, relative to the largest speed (m/s or rad/s) of any body.
fn velocity_mismatch(h: f64) -> f64 {
    let cat = Cat::equal(HALF, Joint::NoTwist);
    let tail = Cylinder { mass: 0.2, length: 1.0, radius: 0.02 };
    let tree = cat.tree_with_tail(&tail, Joint::Spherical);
    let mut path = circulation().with_joints(tree.dof());
    for (k, c) in path.coefficients.iter_mut().enumerate().skip(2) {
        for (i, x) in c.iter_mut().enumerate().take(10).skip(2) {
            *x = 0.6 * (0.9 * i as f64 + k as f64).cos();
        }
    }
    let gains = MotorGains::new(20.0 / h, 1.0);
    let start = path.shape_from(&path.basis(0, 0.0));
    let mut scene = TreeScene::new(&tree, 1e-6, h, 8, gains, &start.q).unwrap_or_else(|e| panic!("{e}"));
    scene.start_at_zero_momentum(&start.q, &start.qd).unwrap_or_else(|e| panic!("{e}"));
    let mut before = scene.snapshot().unwrap_or_else(|e| panic!("{e}"));
    let (mut worst, mut fastest) = (0.0f64, 0.0f64);
    for k in 1..=(0.4 / h).round() as usize {
        let t = k as f64 * h;
        scene.aim(&path.shape(t)).unwrap_or_else(|e| panic!("{e}"));
        scene.step();
        let now = scene.snapshot().unwrap_or_else(|e| panic!("{e}"));
        for (a, b) in before.bodies.iter().zip(&now.bodies) {
            let linear = (b.position - a.position) / h;
            let angular = (b.rotation * a.rotation.inverse()).scaled_axis() / h;
            worst = worst.max((linear - b.linvel).norm()).max((angular - b.angvel).norm());
            fastest = fastest.max(b.linvel.norm()).max(b.angvel.norm());
        }
        before = now;
    }
    assert!(fastest > 1.0, "the bodies move ({fastest})");
    worst / fastest
}

/// With one torque limit on every motor the tree scene bounds the universal and no-twist joints'
/// motors by it, as the two-body scene bounds its own: on the smooth circulation path, a limit a
/// fifth above the plan's peak never binds (the run is the unbounded one, bit for bit), and one a
/// fifth below it saturates the motors, which the run and rapier's verdict say.
#[test]
fn the_tree_scene_bounds_its_motors_by_one_torque_limit() {
    let path = circulation();
    let settings = RapierSettings { dt: TimeStep::Fixed(6e-4), ..RapierSettings::default() };
    let within =
        |limit: f64| RapierOptions::within(Motors { joints: [Motor { torque: Some(limit), ..Motor::default() }; 2] });
    for joint in [Joint::Universal, Joint::NoTwist] {
        let tree = Cat::equal(HALF, joint).tree();
        let peak = (0..=4000)
            .map(|k| path.shape(1.2 * k as f64 / 4000.0))
            .flat_map(|shape| {
                reduction::joint_torques(&tree, &shape, &Vector3::zeros()).into_iter().flat_map(|l| l.tau)
            })
            .fold(0.0, |m: f64, t| m.max(t.abs()));
        let free = simulate_tree(&tree, &path, &settings, &RapierOptions::default()).unwrap_or_else(|e| panic!("{e}"));
        let loose = simulate_tree(&tree, &path, &settings, &within(1.2 * peak)).unwrap_or_else(|e| panic!("{e}"));
        assert!(loose.saturation.is_empty(), "{joint}: {:?}", loose.saturation);
        assert_eq!((loose.twist, loose.swing), (free.twist, free.swing), "{joint}: a bound that never binds");
        let tight = simulate_tree(&tree, &path, &settings, &within(0.8 * peak)).unwrap_or_else(|e| panic!("{e}"));
        assert!(!tight.saturation.is_empty(), "{joint}: no motor saturated below the peak {peak} N·m");
        assert!(
            tight.saturation.iter().all(|s| s.fraction > 0.0 && s.shortfall_nm > 0.0),
            "{joint}: {:?}",
            tight.saturation
        );
        let reference = Reference {
            twist: flip_on(&tree, &path, &Vector3::zeros(), 1e-11).twist,
            swing: flip_on(&tree, &path, &Vector3::zeros(), 1e-11).swing,
            peak_torque: peak,
        };
        let verdict =
            verify_tree(&tree, &path, &settings, &reference, &within(0.8 * peak)).unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(verdict.status, Status::NotVerified, "{joint}: {}", verdict.verdict);
        assert!(verdict.verdict.to_string().contains("saturated"), "{joint}: {}", verdict.verdict);
    }
}

/// The legs' hinges are bounded as the joints' motors are: on the cat held straight while its
/// legs swing fast (the halves' motors only hold them straight), a limit between the halves'
/// peak and the legs' saturates the legs' hinges alone, and the run departs from the unbounded
/// one (the bound acts in rapier, not only in the count).
#[test]
fn the_legs_hinges_are_bounded_by_the_limit() {
    let tree = legged(None);
    let mut path = circulation().with_joints(tree.dof());
    path.coefficients[..2].iter_mut().flatten().for_each(|c| *c = 0.0);
    swing_appendages(&mut path, 1.2);
    let settings = RapierSettings { dt: TimeStep::Fixed(6e-4), ..RapierSettings::default() };
    let mut peaks = vec![0.0f64; tree.dof()];
    for k in 0..=4000 {
        let shape = path.shape(1.2 * k as f64 / 4000.0);
        let tau: Vec<f64> =
            reduction::joint_torques(&tree, &shape, &Vector3::zeros()).into_iter().flat_map(|l| l.tau).collect();
        for (p, t) in peaks.iter_mut().zip(tau) {
            *p = p.max(t.abs());
        }
    }
    let (halves, legs) = (peaks[0].max(peaks[1]), peaks[2].min(peaks[3]));
    assert!(legs > 1.25 * halves, "the legs need the most: peaks {peaks:?}");
    let bound = 0.5 * (halves + legs);
    let options = RapierOptions::within(Motors { joints: [Motor { torque: Some(bound), ..Motor::default() }; 2] });
    let run = simulate_tree(&tree, &SplineShape(&path), &settings, &options).unwrap_or_else(|e| panic!("{e}"));
    let saturated: Vec<usize> = run.saturation.iter().map(|s| s.joint).collect();
    assert_eq!(saturated, [3, 4], "peaks {peaks:?}, bound {bound}");
    let free = simulate_tree(&tree, &SplineShape(&path), &settings, &RapierOptions::default())
        .unwrap_or_else(|e| panic!("{e}"));
    assert!(free.saturation.is_empty());
    assert!(
        (run.twist - free.twist).abs() + (run.swing - free.swing).abs() > 1e-6,
        "{} {} against {} {}",
        run.twist,
        run.swing,
        free.twist,
        free.swing
    );
}
