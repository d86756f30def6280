//! The tracked rapier run behind the robustness check with real motors (issue 21 §2): a
//! controller drives the joints with explicit torques through the actuators.
#![deny(clippy::float_cmp)]

use catflip::engines::exact::flip;
use catflip::engines::models::TwoMotorCat;
use catflip::engines::rapier::{
    lqr_gains, simulate_with, track, AttitudeEstimate, AttitudeSensor, Controller, FeedForwardPd, Feedback,
    FeedbackPlan, FeedbackSettings, JointReading, PdGains, Plan, RapierOptions, TrackOptions, TrackedRun,
};
use catflip::engines::resolved::Resolved;
use catflip::model::motor::{Motor, Motors};
use catflip::model::Cylinder;
use catflip::problem::Problem;
use catflip::schedule::{Schedule, Trajectory};
use nalgebra::Vector3;

fn problem() -> (Problem, Schedule) {
    let p = Problem::from_toml(
        "name = \"paper\"\n[manoeuvre]\ncirculation = \"calibrated\"\nprofile = \"cycloidal\"\n",
        "t.toml",
        &[],
    )
    .expect("a valid problem");
    let r = Resolved::new(&p).expect("calibrates");
    (p, r.schedule)
}

fn options(motors: Motors) -> TrackOptions {
    TrackOptions {
        cross_mass_fraction: 1e-3,
        pgs_iterations: 8,
        motors,
        spin: Vector3::zeros(),
        sensor: AttitudeSensor { latency: 0.01, noise: 0.0, seed: 7 },
        landing: None,
        keep_poses_at: Vec::new(),
    }
}

fn steps(traj: &impl Trajectory, dt: f64) -> usize {
    (traj.total_duration() / dt).ceil() as usize
}

fn run(cat: &Cylinder, nominal: &Cylinder, traj: &Schedule, dt: f64, hz: f64, motors: Motors) -> TrackedRun {
    let plan = Plan::new(nominal, traj, &Vector3::zeros(), 1e-10, steps(traj, dt));
    let mut c = FeedForwardPd::new(&plan, PdGains::servo(nominal, hz, 1.0));
    track(cat, &plan, &mut c, &options(motors)).expect("the run")
}

/// The twist error `|twist| − 180°` of a run, degrees.
fn twist_error(r: &TrackedRun) -> f64 {
    r.twist.abs().to_degrees() - 180.0
}

#[test]
fn exact_feed_forward_on_the_nominal_cat_tracks_the_plan_to_first_order() {
    let (p, s) = problem();
    let cat = p.cat.half();
    let exact = flip(&cat, &s, 1e-10);
    assert!((exact.twist.abs().to_degrees() - 180.0).abs() < 1e-6, "the calibrated schedule turns by π");
    let (coarse, fine) =
        (run(&cat, &cat, &s, 2e-4, 10.0, Motors::ideal()), run(&cat, &cat, &s, 1e-4, 10.0, Motors::ideal()));
    let (ec, ef) = (twist_error(&coarse), twist_error(&fine));
    // Rapier's integrator is first order: the twist error halves with the step (measured:
    // 0.755° → 0.381° → 0.193° at 200, 100, 50 µs), and Richardson removes it.
    let order = (ec / ef).log2();
    assert!((order - 1.0).abs() < 0.05, "observed order {order} ({ec}° at 200 µs, {ef}° at 100 µs)");
    let extrapolated = 2.0 * ef - ec;
    assert!(extrapolated.abs() < 0.02, "Richardson's twist error {extrapolated}°");
    // The servo follows the plan to a hundredth of a degree; rapier's own motors (the
    // verification at the same step) turn the cat no closer to the exact engine.
    assert!(fine.tracking_error.iter().all(|e| e.to_degrees() < 0.03), "{:?}", fine.tracking_error);
    let v = simulate_with(&TwoMotorCat::paper(cat), &s, &p.rapier.with_dt(1e-4), &RapierOptions::default())
        .expect("verification");
    let verification = v.twist.abs().to_degrees() - 180.0;
    assert!(ef.abs() <= verification.abs(), "tracked {ef}°, verification {verification}° at 100 µs");
    assert!(fine.saturated.iter().all(|f| *f <= 0.0), "ideal motors never saturate");
}

#[test]
fn pd_holds_a_heavier_cat_on_the_plan_that_feed_forward_alone_loses() {
    let (p, s) = problem();
    let heavy = Cylinder { mass: 1.1 * p.cat.mass, ..p.cat.half() };
    let ff = run(&heavy, &p.cat.half(), &s, 2e-4, 0.0, Motors::ideal());
    let soft = run(&heavy, &p.cat.half(), &s, 2e-4, 2.0, Motors::ideal());
    let stiff = run(&heavy, &p.cat.half(), &s, 2e-4, 10.0, Motors::ideal());
    let worst = |r: &TrackedRun| r.tracking_error[0].max(r.tracking_error[1]).to_degrees();
    // Measured at 100 µs (the test runs at 200 µs): feed-forward alone drifts by over a thousand degrees (the 10 % heavier
    // cat gets 10 % too little torque and nothing pulls it back), PD at 2 Hz keeps it within
    // 3.3°, at 10 Hz within 0.42°.
    assert!(worst(&ff) > 100.0, "feed-forward alone: {}°", worst(&ff));
    assert!(worst(&stiff) < 1.0, "PD at 10 Hz: {}°", worst(&stiff));
    assert!(worst(&stiff) < worst(&soft) / 4.0, "10 Hz {}° against 2 Hz {}°", worst(&stiff), worst(&soft));
    assert!(twist_error(&stiff).abs() < 1.0 && twist_error(&ff).abs() > 10.0);
}

#[test]
fn small_torque_limits_saturate_and_cost_landing_accuracy() {
    let (p, s) = problem();
    let free = run(&p.cat.half(), &p.cat.half(), &s, 1e-4, 10.0, Motors::ideal());
    let limit = 0.5 * free.peak_torque[0].max(free.peak_torque[1]);
    let m = Motor { torque: Some(limit), ..Motor::default() };
    let capped = run(&p.cat.half(), &p.cat.half(), &s, 1e-4, 10.0, Motors { joints: [m, m] });
    assert!(capped.saturated.iter().all(|f| *f > 0.0), "{:?}", capped.saturated);
    assert!(capped.peak_torque.iter().all(|t| *t <= limit), "{:?} > {limit}", capped.peak_torque);
    // Measured: 1.50° short of the half turn against 0.38° beyond it without the limit.
    assert!(
        twist_error(&capped).abs() > twist_error(&free).abs() + 0.5,
        "capped {}°, free {}°",
        twist_error(&capped),
        twist_error(&free)
    );
}

/// Feed-forward plus PD that records the attitude estimates it is handed.
struct Recording<'a> {
    inner: FeedForwardPd<'a>,
    seen: Vec<(f64, AttitudeEstimate)>,
}

impl Controller for Recording<'_> {
    fn torques(&mut self, t: f64, joints: &JointReading, attitude: &AttitudeEstimate) -> [f64; 2] {
        self.seen.push((t, *attitude));
        self.inner.torques(t, joints, attitude)
    }
}

fn estimates(latency: f64, noise: f64) -> Vec<(f64, AttitudeEstimate)> {
    let (p, s) = problem();
    let plan = Plan::new(&p.cat.half(), &s, &Vector3::zeros(), 1e-10, steps(&s, 2e-4));
    let mut c =
        Recording { inner: FeedForwardPd::new(&plan, PdGains::servo(&p.cat.half(), 10.0, 1.0)), seen: Vec::new() };
    let mut o = options(Motors::ideal());
    o.sensor = AttitudeSensor { latency, noise, seed: 3 };
    track(&p.cat.half(), &plan, &mut c, &o).expect("the run");
    c.seen
}

#[test]
fn the_controller_sees_the_attitude_late_and_noisy() {
    let prompt = estimates(0.0, 0.0);
    let late = estimates(0.01, 0.0);
    let noisy = estimates(0.0, 0.01);
    let dt = late[1].0 - late[0].0;
    let delay = (0.01 / dt).round() as usize; // whole steps
    for (k, (t, e)) in late.iter().enumerate() {
        let expected = (t - 0.01).max(0.0);
        assert!((e.measured_at - expected).abs() <= 0.5 * dt + 1e-12, "measured at {} for t = {t}", e.measured_at);
        let then = prompt[k.saturating_sub(delay)].1.orientation;
        assert!(e.orientation.angle_to(&then) < 1e-12, "step {k}: the estimate is the attitude 10 ms before");
    }
    // The noise is a rotation exp(σ n), n three standard normals: its angle σ|n| has mean
    // square 3σ²; over 7000 steps the sample is within 5 % of it with overwhelming odds.
    let ms = noisy.iter().zip(&prompt).map(|(a, b)| a.1.orientation.angle_to(&b.1.orientation).powi(2)).sum::<f64>()
        / noisy.len() as f64;
    assert!((ms.sqrt() / (0.01 * 3f64.sqrt()) - 1.0).abs() < 0.05, "rms angle {}", ms.sqrt());
}

fn feedback_settings(noise: f64) -> FeedbackSettings {
    FeedbackSettings {
        rate_hz: 1000.0,
        replan_hz: 0.0,
        attitude: 1f64.to_radians(),
        joint: 10f64.to_radians(),
        accel: 20.0,
        spin_prior: 0.01,
        sensor_noise: noise,
    }
}

/// Open loop and feedback on `cat` released with `spin`, the sensor 10 ms late with `noise`:
/// `(open loop, feedback, the feedback's largest correction in degrees)`.
fn open_and_closed(cat: &Cylinder, spin: Vector3<f64>, noise: f64, dt: f64) -> (TrackedRun, TrackedRun, f64) {
    let (p, s) = problem();
    let plan = Plan::new(&p.cat.half(), &s, &Vector3::zeros(), 1e-10, steps(&s, dt));
    let fb = FeedbackPlan::new(&p.cat.half(), &s, &Vector3::zeros(), 1e-10, &plan, feedback_settings(noise));
    let servo = PdGains::servo(&p.cat.half(), 10.0, 1.0);
    let mut o = options(Motors::ideal());
    o.spin = spin;
    o.sensor.noise = noise;
    let open = track(cat, &plan, &mut FeedForwardPd::new(&plan, servo), &o).expect("open loop");
    let mut c = Feedback::new(&plan, &fb, servo, &p.cat.half());
    let closed = track(cat, &plan, &mut c, &o).expect("feedback");
    let correction = c.log().largest_correction.map(f64::to_degrees);
    (open, closed, correction[0].max(correction[1]))
}

#[test]
fn feedback_on_the_nominal_cat_lands_as_the_plan_does() {
    let (p, _) = problem();
    let (open, closed, correction) = open_and_closed(&p.cat.half(), Vector3::zeros(), 0.0, 2e-4);
    // Nothing to correct but rapier's own first-order bias (0.76° of twist at 200 µs, the
    // test above, a momentum leak the filter takes for spin): the feedback bends the joints by
    // a few degrees (measured 2.67°) and lands closer to the half turn than the open loop
    // (measured 0.83° against 1.14°).
    let target = nalgebra::UnitQuaternion::from_axis_angle(&Vector3::z_axis(), std::f64::consts::PI);
    let landing = |r: &TrackedRun| r.orientation.angle_to(&target).to_degrees();
    assert!(correction < 5.0, "correction {correction}°");
    assert!(
        twist_error(&closed).abs() <= twist_error(&open).abs(),
        "{} against {}",
        twist_error(&closed),
        twist_error(&open)
    );
    assert!(landing(&closed) < landing(&open), "{}° against {}°", landing(&closed), landing(&open));
    assert!(landing(&closed) < 1.0, "{}° from the half turn", landing(&closed));
}

#[test]
fn feedback_undoes_a_spinning_release_that_the_open_loop_cannot() {
    let (p, _) = problem();
    let light = Cylinder { mass: 0.92 * p.cat.mass, ..p.cat.half() };
    let spin = Vector3::new(0.004, -0.003, 0.008);
    let (open, closed, correction) = open_and_closed(&light, spin, 0.5f64.to_radians(), 2e-4);
    // The spin about the spine alone turns the straight cat at L_z/(m r²) ≈ 0.87 rad/s: the
    // open loop lands tens of degrees off; the feedback, from a sensor 10 ms late with 0.5° of
    // noise, within 2°.
    assert!(twist_error(&open).abs() > 10.0, "open loop {}°", twist_error(&open));
    assert!(twist_error(&closed).abs() < 2.0, "feedback {}°", twist_error(&closed));
    assert!(correction > 1.0 && correction <= 30.0, "correction {correction}°");
}

#[test]
fn the_gains_stay_bounded_as_the_cat_straightens() {
    let (p, s) = problem();
    let plan = Plan::new(&p.cat.half(), &s, &Vector3::zeros(), 1e-10, steps(&s, 2e-4));
    let settings = feedback_settings(0.0);
    let fb = FeedbackPlan::new(&p.cat.half(), &s, &Vector3::zeros(), 1e-10, &plan, settings);
    assert!(fb.gains.iter().all(|k| k.iter().all(|x| x.is_finite())));
    let n = fb.gains.len();
    let attitude_gain = |k: usize| fb.gains[k].columns(0, 3).amax();
    // The last gain is that of one step from the end: the regulator cannot turn the straight
    // cat, and the input weight keeps the gain within a few times the mid-fall one.
    let middle = attitude_gain(n / 2);
    assert!(attitude_gain(n - 1) < 10.0 * middle, "end {} against middle {middle}", attitude_gain(n - 1));
    // The sweep from a later node gives that node's gains: a re-solve from the current time.
    let late = lqr_gains(&fb.linearisation, &settings, n / 2);
    assert!((late[0] - fb.gains[n / 2]).amax() <= 1e-9 * middle);
}

/// Feedback without and with re-plans at 20 Hz on `cat` released with `spin`, the sensor 10 ms
/// late with 0.5° of noise, the filter's spin prior 0.001 N·m·s (the check's default).
fn without_and_with_replans(cat: &Cylinder, spin: Vector3<f64>, dt: f64) -> [(TrackedRun, usize); 2] {
    let (p, s) = problem();
    let plan = Plan::new(&p.cat.half(), &s, &Vector3::zeros(), 1e-10, steps(&s, dt));
    let noise = 0.5f64.to_radians();
    let settings = FeedbackSettings { spin_prior: 0.001, ..feedback_settings(noise) };
    let fb = FeedbackPlan::new(&p.cat.half(), &s, &Vector3::zeros(), 1e-10, &plan, settings);
    let servo = PdGains::servo(&p.cat.half(), 10.0, 1.0);
    let mut o = options(Motors::ideal());
    o.spin = spin;
    o.sensor.noise = noise;
    [0.0, 20.0].map(|hz| {
        let fb = FeedbackPlan { settings: FeedbackSettings { replan_hz: hz, ..settings }, ..fb.clone() };
        let mut c = Feedback::new(&plan, &fb, servo, &p.cat.half());
        let run = track(cat, &plan, &mut c, &o).expect("feedback");
        (run, c.log().replans)
    })
}

#[test]
fn a_replan_lands_a_large_spin_that_the_linear_model_mishandles() {
    let (p, _) = problem();
    let light = Cylinder { mass: 0.93 * p.cat.mass, ..p.cat.half() };
    // About 2σ of the check's spins about the spine and a transverse axis: the gains solved
    // once along the plan leave the cat 9.13° from the half turn (twist 6.92°, swing 5.95°; its
    // joint corrections reach 8.4°, where the linearisation along the plan no longer predicts
    // the attitude); re-planned at 20 Hz about the motion it then expects, 0.32° (measured at
    // 200 µs).
    let [(once, none), (replanned, replans)] =
        without_and_with_replans(&light, Vector3::new(-0.0009, -0.0089, -0.0102), 2e-4);
    assert_eq!(none, 0, "no re-plan at 0 Hz");
    // 1.43 s of fall at 20 Hz: a re-plan every 50 ms after the release.
    assert!((25..=29).contains(&replans), "{replans} re-plans");
    let target = nalgebra::UnitQuaternion::from_axis_angle(&Vector3::z_axis(), std::f64::consts::PI);
    let landing = |r: &TrackedRun| r.orientation.angle_to(&target).to_degrees();
    assert!(landing(&once) > 5.0, "gains along the plan: {}°", landing(&once));
    assert!(landing(&replanned) < 1.0, "re-planned: {}°", landing(&replanned));
}
