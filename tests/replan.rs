//! The feedback's re-plan (issue 21 §3, "warm re-plan"): the attitude error's exact dynamics
//! relative to the plan, their linearisation about a motion off the plan, and the re-planned
//! regulator.
#![deny(clippy::float_cmp)]

use catflip::engines::exact::body_rate_spinning;
use catflip::engines::rapier::feedback::{error_rate, linearise, PlanPoint, State};
use catflip::engines::rapier::{FeedbackPlan, FeedbackSettings, Plan, Regulator};
use catflip::engines::resolved::Resolved;
use catflip::model::Cylinder;
use catflip::problem::Problem;
use catflip::schedule::Trajectory;
use nalgebra::{UnitQuaternion, Vector3};
use proptest::prelude::*;

fn cat() -> Cylinder {
    Cylinder { mass: 1.0, length: 1.0, radius: 0.1 }
}

/// A plan point of `cat` at joints `q`, `qd`, attitude `r`, released with `spin`.
fn point(q: [f64; 2], qd: [f64; 2], r: UnitQuaternion<f64>, spin: &Vector3<f64>) -> PlanPoint {
    let omega = body_rate_spinning(&cat(), q, qd, &(r.inverse() * spin));
    PlanPoint { q, qd, attitude: r, omega }
}

fn state(e: [f64; 3], dq: [f64; 2], dqd: [f64; 2], d: [f64; 3]) -> State {
    State::from_column_slice(&[e[0], e[1], e[2], dq[0], dq[1], dqd[0], dqd[1], d[0], d[1], d[2]])
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    /// The node's Jacobians (the attitude's in closed form, the spin's exact) against central
    /// differences of the exact error rate, and its affine term reproduces `f(x̄)`.
    #[test]
    fn the_linearisation_matches_central_differences_off_the_plan(
        q in prop::array::uniform2(-1.2f64..1.2),
        qd in prop::array::uniform2(-4.0f64..4.0),
        axis in prop::array::uniform3(-2.0f64..2.0),
        spin in prop::array::uniform3(-0.02f64..0.02),
        e in prop::array::uniform3(-0.3f64..0.3),
        dq in prop::array::uniform2(-0.3f64..0.3),
        dqd in prop::array::uniform2(-1.0f64..1.0),
        d in prop::array::uniform3(-0.01f64..0.01),
    ) {
        let spin = Vector3::from(spin);
        let p = point(q, qd, UnitQuaternion::from_scaled_axis(Vector3::from(axis)), &spin);
        let xbar = state(e, dq, dqd, d);
        let (node, f) = linearise(&cat(), &p, &spin, &xbar);
        let rate = |x: &State| error_rate(&cat(), &p, &spin, x);
        prop_assert!((rate(&xbar) - f).amax() <= 1e-15 * (1.0 + f.amax()), "f(x̄) {f} against {}", rate(&xbar));
        prop_assert!((node.rate(&xbar) - f).amax() <= 1e-12 * (1.0 + f.amax()), "the affine term");
        let h = 1e-5;
        for (col, block) in (0..10).map(|c| (c, c)) {
            let mut plus = xbar;
            let mut minus = xbar;
            plus[col] += h;
            minus[col] -= h;
            let fd = (rate(&plus) - rate(&minus)) / (2.0 * h);
            let model = match block {
                0..=2 => node.a.column(col).into_owned(),
                3 | 4 => node.bq.column(col - 3).into_owned(),
                5 | 6 => node.bqd.column(col - 5).into_owned(),
                _ => node.g.column(col - 7).into_owned(),
            };
            let scale = 1.0 + fd.amax();
            prop_assert!((model - fd).amax() <= 2e-6 * scale, "column {col}: {model} against {fd}");
        }
    }
}

/// The error rate is the derivative of `e = log(R*ᵀ R)` when `R*` and `R` turn at their body
/// rates `Ω*` and `Ω` (a second derivation of `f`, through rotations only).
#[test]
fn the_error_rate_is_the_derivative_of_the_attitude_error() {
    let spin = Vector3::new(0.004, -0.003, 0.008);
    let r0 = UnitQuaternion::from_scaled_axis(Vector3::new(0.3, -1.1, 0.7));
    let p = point([0.6, -0.4], [1.5, 2.0], r0, &spin);
    for (e, dq, dqd, d) in [
        ([0.0; 3], [0.0; 2], [0.0; 2], [0.0; 3]),
        ([0.05, -0.2, 0.1], [0.1, -0.2], [0.5, -0.3], [0.002, 0.001, -0.004]),
        ([0.4, 0.3, -0.5], [-0.2, 0.25], [-1.0, 0.8], [-0.005, 0.003, 0.006]),
    ] {
        let x = state(e, dq, dqd, d);
        let ev = Vector3::from(e);
        let r = r0 * UnitQuaternion::from_scaled_axis(ev);
        let q = [p.q[0] + dq[0], p.q[1] + dq[1]];
        let qd = [p.qd[0] + dqd[0], p.qd[1] + dqd[1]];
        let omega = body_rate_spinning(&cat(), q, qd, &(r.inverse() * (spin + Vector3::from(d))));
        let error = |h: f64| {
            let planned = r0 * UnitQuaternion::from_scaled_axis(p.omega * h);
            let actual = r * UnitQuaternion::from_scaled_axis(omega * h);
            (planned.inverse() * actual).scaled_axis()
        };
        let h = 1e-6;
        let fd = (error(h) - error(-h)) / (2.0 * h);
        let f = error_rate(&cat(), &p, &spin, &x);
        assert!((f - fd).amax() < 1e-8, "e = {e:?}: f = {f}, finite differences {fd}");
    }
}

fn paper_plan() -> (Problem, Plan, FeedbackPlan) {
    let p = Problem::from_toml(
        "name = \"paper\"\n[manoeuvre]\ncirculation = \"calibrated\"\nprofile = \"cycloidal\"\n",
        "t.toml",
        &[],
    )
    .expect("a valid problem");
    let s = Resolved::new(&p).expect("calibrates").schedule;
    let plan = Plan::new(&p.cat.half(), &s, &Vector3::zeros(), 1e-10, (s.total_duration() / 2e-4).ceil() as usize);
    let settings = FeedbackSettings {
        rate_hz: 1000.0,
        replan_hz: 50.0,
        attitude: 1f64.to_radians(),
        joint: 10f64.to_radians(),
        accel: 20.0,
        spin_prior: 0.001,
        sensor_noise: 0.0,
    };
    let fb = FeedbackPlan::new(&p.cat.half(), &s, &Vector3::zeros(), 1e-10, &plan, settings);
    (p, plan, fb)
}

/// With nothing deviated, the roll-out is the plan, the linearisation about it the plan's and the
/// re-solved gains the plan's, to the bit; no offsets.
#[test]
fn a_replan_from_the_plan_reproduces_the_plans_gains() {
    let (_, _, fb) = paper_plan();
    let n = fb.gains.len();
    for from in [1, n / 2, n - 3] {
        let mut r = Regulator::of(&fb);
        r.replan(&fb.linearisation, &fb.settings, from, &State::zeros());
        assert!(r.nodes == fb.linearisation.nodes, "from node {from}: the nodes moved");
        for i in 0..n {
            assert!(
                r.gains[i] == fb.gains[i],
                "from node {from}: gain {i} moved by {}",
                (r.gains[i] - fb.gains[i]).amax()
            );
            assert!(r.offsets[i].amax() <= 0.0, "from node {from}: offset {i} = {}", r.offsets[i]);
        }
    }
}

/// From a state off the plan, the re-plan's input moves (it sees the motion the old policy
/// leads to), its nodes before the re-plan stay as they were, and it keeps a step that lowers the
/// cost of its roll-out below the policy in force's. Re-plans repeated from the same state are the
/// iterations of iterative LQR: they never raise the cost they expect (beyond round-off: the
/// kept policy's input and the line search's are the same affine map, rounded differently), and
/// they converge, to a policy no step improves.
#[test]
fn a_replan_off_the_plan_lowers_the_cost_it_expects() {
    let (_, _, fb) = paper_plan();
    let n = fb.gains.len();
    let from = n / 3;
    let x = state([0.02, -0.03, 0.08], [0.05, -0.04], [0.1, 0.0], [0.003, -0.002, 0.008]);
    let mut r = Regulator::of(&fb);
    let before = r.input(from, &x);
    r.replan(&fb.linearisation, &fb.settings, from, &x);
    assert!(r.nodes[..from] == fb.linearisation.nodes[..from], "the past nodes are kept for the filter");
    assert!(r.gains[..from] == fb.gains[..from], "the past gains are kept");
    assert!(r.last_step > 0.0, "the first re-plan found no better step");
    assert!(
        r.expected_cost < r.cost_before,
        "the re-plan expects {} against the policy in force's {}",
        r.expected_cost,
        r.cost_before
    );
    let change = (r.input(from, &x) - before).norm();
    assert!(change > 1e-3, "the re-plan changed the input by {change} rad/s²");
    let mut costs = vec![r.expected_cost];
    for _ in 0..8 {
        r.replan(&fb.linearisation, &fb.settings, from, &x);
        costs.push(r.expected_cost);
    }
    let round_off = 1e-12;
    assert!(costs.windows(2).all(|w| w[1] <= w[0] * (1.0 + round_off)), "expected costs {costs:?}");
    let (first, last) = (costs[0], costs[costs.len() - 1]);
    assert!(last < first * (1.0 - 1e-4), "the iterations after the first gained nothing: {costs:?}");
    let tail = (costs[costs.len() - 2] - last).abs();
    assert!(tail <= round_off * last, "not converged after 9 re-plans: {costs:?}");
}
