//! A release with spin on the other cat models (DESIGN.md §9, §10): the general core's spinning
//! flip and torques against closed forms, against the two-cylinder engine on the paper's cat, and
//! its own conservation laws.
//!
//! - a rigid straight cat of unequal halves tumbles as the torque-free symmetric top;
//! - on the paper's cat the general core with spin is the two-cylinder engine's spinning flip
//!   and torques (two implementations of §9);
//! - the spin is conserved in the world frame and action = reaction on every model;
//! - a spinning release of unequal halves calibrates to a turn of π.
#![deny(clippy::float_cmp)]

use std::path::Path;

use catflip::engines::exact;
use catflip::engines::models::TwoMotorCat;
use catflip::engines::resolved::Resolved;
use catflip::engines::spin::SpinHistory;
use catflip::engines::torque::TorqueSource;
use catflip::model::{Cat, Cylinder, Joint};
use catflip::problem::Problem;
use catflip::schedule::Trajectory;
use nalgebra::{UnitQuaternion, Vector3};

mod common;
use common::Held;

fn unequal(joint: Joint) -> Cat {
    let front = Cylinder { mass: 0.8, length: 0.8, radius: 0.09 };
    let rear = Cylinder { mass: 1.2, length: 1.0, radius: 0.11 };
    Cat { front, rear, joint }
}

fn load(name: &str, overrides: &[&str]) -> Problem {
    let overrides: Vec<String> = overrides.iter().map(|s| s.to_string()).collect();
    Problem::load(Path::new(&format!("problems/{name}.toml")), &overrides).expect("the preset loads")
}

#[test]
fn a_rigid_straight_cat_of_unequal_halves_tumbles_as_the_symmetric_top() {
    for joint in [Joint::Universal, Joint::NoTwist] {
        let cat = unequal(joint);
        let model = TwoMotorCat::new(cat).expect("two coordinates");
        // The straight cat about its centre of mass (Goldstein §5.6's top): the halves' own
        // inertias plus the reduced mass at the distance between their centres.
        let (a, b) = (cat.front, cat.rear);
        let apart = 0.5 * (a.length + b.length);
        let i1 = a.transverse() + b.transverse() + a.mass * b.mass / (a.mass + b.mass) * apart * apart;
        let i3 = a.axial() + b.axial();
        for l in [Vector3::new(0.01, 0.0, 0.02), Vector3::new(-0.3, 0.2, 0.004)] {
            let held = Held { q: [0.0, 0.0], duration: 1.3 };
            let f = model.flip_released(&held, &l, 1e-12);
            let t = held.duration;
            let precession = UnitQuaternion::from_scaled_axis(l * (t / i1));
            let spin = UnitQuaternion::from_scaled_axis(Vector3::z() * (t * l.z * (1.0 / i3 - 1.0 / i1)));
            let gap = ((precession * spin).inverse() * f.orientation).angle();
            assert!(f.converged, "{joint:?}, L = {l}: not converged");
            assert!(gap < 1e-10, "{joint:?}, L = {l}: {gap:.3e} rad from the closed form");
        }
    }
}

#[test]
fn on_the_papers_cat_the_general_core_with_spin_is_the_two_cylinder_engine() {
    let (p, schedule) = common::paper();
    let half = p.cat.half();
    let general = TwoMotorCat::new(Cat::equal(half, Joint::Universal)).expect("two coordinates");
    let l = Vector3::new(0.01, 0.02, -0.03);
    let (f, history) = general.flip_spinning(&schedule, &l, 1e-11);
    let reference = exact::flip_spinning(&half, &schedule, &l, 1e-11);
    let gap = (reference.orientation.inverse() * f.orientation).angle();
    assert!(f.converged && reference.converged);
    assert!(gap < 1e-10, "the general core is {gap:.3e} rad from the two-cylinder engine");
    // The torques along the motion, each engine at its own orientation history.
    let (_, paper_history) = SpinHistory::new(&half, &schedule, &l, 1e-11);
    let (ours, theirs) =
        (TorqueSource::model_spinning(&general, &history), TorqueSource::spinning(&half, &paper_history));
    for (piece, duration) in schedule.piece_durations().into_iter().enumerate() {
        for k in 0..=20 {
            let s = duration * k as f64 / 20.0;
            let st = schedule.piece_state(piece, s);
            let (a, b) = (ours.at(&schedule, piece, s, &st), theirs.at(&schedule, piece, s, &st));
            for j in 0..2 {
                assert!(
                    (a.tau[j] - b.tau[j]).abs() < 1e-8 * (1.0 + b.tau[j].abs()),
                    "piece {piece}, s = {s}: τ{} {} vs {}",
                    j + 1,
                    a.tau[j],
                    b.tau[j]
                );
            }
        }
    }
}

#[test]
fn every_spinning_model_conserves_its_momentum_and_action_equals_reaction() {
    for (name, joint) in [("kane-scher", "no-twist"), ("unequal-halves", "universal"), ("unequal-halves", "no-twist")] {
        let p = load(name, &[&format!("cat.joint=\"{joint}\""), "drop.angular_momentum=[0.01, -0.02, 0.03]"]);
        let r = Resolved::new(&p).expect("resolves");
        let e = r.evaluate(&r.schedule);
        assert!(e.flip.converged, "{name}, {joint}");
        assert!(e.momentum_max < 1e-12, "{name}, {joint}: |R H − L| relative {:e}", e.momentum_max);
        // Action = reaction holds only when Ω̇ is the true rate of the spinning motion.
        assert!(
            e.peaks.action_reaction_gap < 1e-9 * e.peaks.max,
            "{name}, {joint}: gap {:e}",
            e.peaks.action_reaction_gap
        );
        // The spin changes the flip.
        let still = load(name, &[&format!("cat.joint=\"{joint}\"")]);
        let still = Resolved::new(&still).expect("resolves");
        let e0 = still.evaluate(&r.schedule);
        assert!((e.flip.twist - e0.flip.twist).abs() > 1e-3, "{name}, {joint}: the spin left the twist unchanged");
    }
}

#[test]
fn a_spinning_release_of_unequal_halves_calibrates_to_a_turn_of_pi() {
    let p = load("unequal-halves", &["drop.angular_momentum=[0, 0, 0.01]"]);
    let r = Resolved::new(&p).expect("the calibration converges");
    let cal = r.circulation.calibration.expect("a calibrated circulation");
    assert!(cal.status.is_converged(), "{:?}", cal.status);
    let e = r.evaluate(&r.schedule);
    assert!((e.twist_deg().abs() - 180.0).abs() < 1e-6, "twist {}°", e.twist_deg());
    // Not the circulation of the release without spin.
    let still = Resolved::new(&load("unequal-halves", &[])).expect("converges");
    assert!((r.schedule.circulation - still.schedule.circulation).abs() > 1e-3);
}
