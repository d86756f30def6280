//! Exploration (temporary).
use catflip::manoeuvre::{BendPath, ProfileKind};
use catflip::problem::Problem;
use catflip::profile::Profile;
use catflip::rapier::{simulate_with, RunOptions};
use catflip::schedule::{paper_circulation, Schedule};
use catflip::settings::RapierSettings;

fn paper() -> (Problem, Schedule) {
    let p = Problem::default();
    let c = paper_circulation(&p.cat, p.manoeuvre.theta()).unwrap();
    let s = Schedule::new(&p, c);
    (p, s)
}

#[test]
#[ignore]
fn explore() {
    let (p, paper) = paper();
    let cyc = paper.with_profile(Profile::library(ProfileKind::Cycloidal));
    let _ = BendPath::Cone;
    for (name, s) in [("paper", &paper), ("cycloidal", &cyc)] {
        let ex = catflip::exact::flip(&p.cat, s, 1e-10);
        let pk = catflip::torque::peak_torques(&p.cat, s, 400);
        println!("{name}: exact twist {:.6} deg swing {:.6} deg peaks {:?} max {:.4}", ex.twist.to_degrees(), ex.swing.to_degrees(),
            pk.per_piece.iter().map(|x| [x[0].value, x[1].value]).collect::<Vec<_>>(), pk.max);
        for alpha in [0.3, 1.0, 3.0] {
          for shift in [true, false] {
            for pgs in [2usize, 8] {
            for dt in [1.0 / 60.0, 1e-2, 1e-3, 1e-4] {
                let st = RapierSettings { dt, ..Default::default() };
                let o = RunOptions { bandwidth_per_step: alpha, shift_target: shift, pgs_iterations: pgs, ..Default::default() };
                let t0 = std::time::Instant::now();
                let r = simulate_with(&p.cat, s, &st, &o).unwrap();
                println!("  a={alpha} shift={shift} pgs={pgs} dt={dt:.5}: twist {:+.5} swing {:.5} dtwist {:+.2e} track {:.2e},{:.2e} H {:.2e} ({:.2e}) peaks b{:.3?} t{:.3?} u{:.3?} max {:.4} [{:.1} ms]",
                    r.twist.to_degrees(), r.swing.to_degrees(), (r.twist - ex.twist).to_degrees(), r.tracking_error[0], r.tracking_error[1],
                    r.momentum.max_abs, r.momentum.max_rel, r.peak_torque.bend, r.peak_torque.twist, r.peak_torque.unbend, r.peak_torque.max,
                    t0.elapsed().as_secs_f64() * 1e3);
            }}}
        }
    }
}

#[test]
#[ignore]
fn explore_h() {
    use catflip::rapier::*;
    let (p, paper) = paper();
    let s = paper.with_profile(Profile::library(ProfileKind::Cycloidal));
    for (dt, subs) in [(1e-3, 1usize), (1e-4, 1)] {
        let n = (s.duration() / dt).ceil() as usize;
        let dt = s.duration() / n as f64;
        let g = MotorGains::new(1.0 / dt, 1.0);
        let mut sc = CatScene::new(&p.cat, 1e-6, dt, 8, Some(g), [0.0, 0.0]).unwrap();
        let m = *sc.masses();
        let mut prev = sc.snapshot().unwrap();
        let _ = subs;
        for k in 1..=n {
            let t = k as f64 * dt;
            let st = s.state(t);
            sc.set_targets([st.q[0] - dt * st.qd[0], st.q[1] - dt * st.qd[1]], st.qd).unwrap();
            sc.step();
            let snap = sc.snapshot().unwrap();
            let mut vbar = [0.0; NDOFS];
            for i in 0..NDOFS { vbar[i] = 0.5 * (prev.velocities[i] + snap.velocities[i]); }
            if k % (n / 20) == 0 {
                let hraw = angular_momentum(&m, &snap.bodies(&m));
                let hmid = angular_momentum(&m, &prev.bodies_with(&m, &vbar));
                println!("dt {dt:.1e} t {:.3} Hraw {:+.4} {:+.4} {:+.4}  Hmid(t-dt) {:+.4} {:+.4} {:+.4}  q {:+.4} {:+.4} qrot {:?}", t,
                 hraw.x, hraw.y, hraw.z, hmid.x, hmid.y, hmid.z, snap.q[0], snap.q[1], snap.q_from_rotations());
            }
            prev = snap;
        }
    }
}

#[test]
#[ignore]
fn explore_sub() {
    let (p, paper) = paper();
    let cyc = paper.with_profile(Profile::library(ProfileKind::Cycloidal));
    for (name, s) in [("paper", &paper), ("cycloidal", &cyc)] {
        let ex = catflip::exact::flip(&p.cat, s, 1e-10);
        println!("{name}: exact twist {:.6} swing {:.6}", ex.twist.to_degrees(), ex.swing.to_degrees());
        for alpha in [1.0, 3.0] {
            for subs in [1usize, 4, 16] {
            for dt in [1.0 / 60.0, 1e-2, 1e-3, 1e-4] {
                let st = RapierSettings { dt, ..Default::default() };
                let o = RunOptions { bandwidth_per_step: alpha, substeps: subs, ..Default::default() };
                let t0 = std::time::Instant::now();
                let r = simulate_with(&p.cat, s, &st, &o).unwrap();
                println!("  a={alpha} N={subs} dt={dt:.5}: twist {:+.5} swing {:.5} dtwist {:+.2e} track {:.2e},{:.2e} H {:.2e} ({:.2e}) peaks b{:.3?} t{:.3?} u{:.3?} max {:.4} [{:.1} ms]",
                    r.twist.to_degrees(), r.swing.to_degrees(), (r.twist - ex.twist).to_degrees(), r.tracking_error[0], r.tracking_error[1],
                    r.momentum.max_abs, r.momentum.max_rel, r.peak_torque.bend, r.peak_torque.twist, r.peak_torque.unbend, r.peak_torque.max,
                    t0.elapsed().as_secs_f64() * 1e3);
            }}
        }
    }
}
