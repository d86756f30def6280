//! Landing (issue 21 §4): a tracked rapier run that falls onto the ground `drop.height` below
//! the release, against the free-fall kinematics of the lowest point.
#![deny(clippy::float_cmp)]

use catflip::engines::rapier::{
    track, AttitudeSensor, FeedForwardPd, Landing, Part, PdGains, Plan, TrackOptions, TrackedRun,
};
use catflip::model::legs::{legs, Half, PAW_RADIUS};
use catflip::model::motor::Motors;
use catflip::model::Cylinder;

use nalgebra::Vector3;

mod common;
use common::Held;

const HEIGHT: f64 = 10.0;
const G: f64 = 9.8;
const DT: f64 = 1e-4;

fn fall(cat: &Cylinder, spin: Vector3<f64>) -> TrackedRun {
    let duration = (2.0 * HEIGHT / G).sqrt();
    let traj = Held { q: [0.0, 0.0], duration };
    let plan = Plan::new(cat, &traj, &spin, 1e-10, (duration / DT).ceil() as usize);
    let mut controller = FeedForwardPd::new(&plan, PdGains::servo(cat, 10.0, 1.0));
    let options = TrackOptions {
        cross_mass_fraction: 1e-3,
        pgs_iterations: 8,
        motors: Motors::ideal(),
        spin,
        sensor: AttitudeSensor { latency: 0.0, noise: 0.0, seed: 1 },
        landing: Some(Landing { height: HEIGHT, gravity: G, feet_down_deg: 20.0 }),
        keep_poses_at: Vec::new(),
    };
    track(cat, &plan, &mut controller, &options).expect("the run")
}

/// Time for the centre of mass to fall `HEIGHT − depth`: when a point `depth` below it (held
/// there, the cat not turning) reaches the ground.
fn touch_time(depth: f64) -> f64 {
    (2.0 * (HEIGHT - depth) / G).sqrt()
}

#[test]
fn a_straight_cat_released_on_its_back_lands_on_its_back() {
    let cat = Cylinder::default();
    let run = fall(&cat, Vector3::zeros());
    let td = run.touchdown.expect("touches down");
    assert!(matches!(td.part, Part::FrontBody | Part::RearBody), "{td:?}");
    assert!(!td.on_its_feet);
    assert!(td.feet_down_deg.iter().all(|a| (a - 180.0).abs() < 1e-6), "{:?}", td.feet_down_deg);
    // Its back, the cylinders' top generator, is r below the axis (the centre of mass's line).
    // Rapier's symplectic Euler (velocity first) puts the centre `g t h/2` below the parabola,
    // so the cat touches about `h/2` early: within one step of the free-fall time.
    let expected = touch_time(cat.radius);
    assert!((td.time - expected).abs() < DT, "touch-down at {} s, free fall says {expected} s", td.time);
    assert!((td.impact_speed / (G * expected) - 1.0).abs() < 1e-3, "impact {} m/s", td.impact_speed);
}

#[test]
fn a_straight_cat_that_rolls_half_a_turn_lands_on_its_feet() {
    let cat = Cylinder::default();
    // The paws' lowest point below the axis when the belly faces down: hip height 0.87 r, the
    // leg's reach 0.9 (l/2) along (0.2, 1, 0)/|·|, the paw's radius.
    let leg = legs(&cat, Half::A)[1];
    let depth = leg.paw.y + PAW_RADIUS * cat.radius;
    let t_touch = touch_time(depth);
    // A spin about the spine that turns the straight cat by π at that instant: ω = π/t about z,
    // L = (2 · m r²/2) ω (the straight cat is a symmetric top; A's +z is the world's).
    let spin = Vector3::new(0.0, 0.0, 2.0 * cat.axial() * std::f64::consts::PI / t_touch);
    let run = fall(&cat, spin);
    let td = run.touchdown.expect("touches down");
    assert!(matches!(td.part, Part::FrontPaw | Part::HindPaw), "{td:?}");
    assert!(td.on_its_feet, "{td:?}");
    assert!(td.feet_down_deg.iter().all(|a| *a < 1.0), "{:?}", td.feet_down_deg);
    assert!((td.time - t_touch).abs() < DT, "touch-down at {} s, free fall says {t_touch} s", td.time);
}
