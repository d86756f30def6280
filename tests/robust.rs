//! The robustness check (`catflip robust`): seeded draws, thread-count independence, and the
//! landing error's meaning.
#![deny(clippy::float_cmp)]

use catflip::engines::resolved::Resolved;
use catflip::problem::Problem;
use catflip::robust::{check, draw, robustness, Engine, Percentiles};

fn problem(extra: &[&str]) -> Problem {
    let mut sets = vec!["robust.trials=40".to_string()];
    sets.extend(extra.iter().map(|s| s.to_string()));
    Problem::from_toml(
        "name = \"paper\"\n[manoeuvre]\ncirculation = \"calibrated\"\nprofile = \"cycloidal\"\n",
        "t.toml",
        &sets,
    )
    .expect("a valid problem")
}

#[test]
fn the_check_is_the_same_at_one_and_two_threads() {
    let p = problem(&[]);
    let r = Resolved::new(&p).expect("calibrates");
    let at = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().expect("a pool");
        pool.install(|| {
            serde_json::to_string(&robustness(&p, &r.schedule, "s").expect("two motors")).expect("serialises")
        })
    };
    let (one, two) = (at(1), at(2));
    assert!(one == two, "the check depends on the thread count");
}

/// The check's JSON, CSV and Markdown of `p`'s own schedule on a pool of `threads` threads.
fn outputs_at(p: &Problem, r: &Resolved, threads: usize) -> (String, String, String) {
    let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().expect("a pool");
    pool.install(|| {
        let report = check(p, &r.schedule, "s").expect("the check");
        (serde_json::to_string(&report).expect("serialises"), report.to_csv(), report.to_markdown())
    })
}

#[test]
fn the_tracked_check_is_byte_identical_at_one_and_two_threads() {
    let p = problem(&[
        "robust.trials=6",
        "robust.engine=both",
        "robust.dt_s=2e-4",
        "robust.landing=true",
        "robust.controller=both",
    ]);
    let r = Resolved::new(&p).expect("calibrates");
    let (one, two) = (outputs_at(&p, &r, 1), outputs_at(&p, &r, 2));
    assert!(one == two, "the tracked check depends on the thread count");
    let report = check(&p, &r.schedule, "s").expect("the check");
    let engines: Vec<Engine> = report.checks.iter().map(|c| c.engine).collect();
    assert_eq!(engines, [Engine::Exact, Engine::Rapier, Engine::RapierFeedback]);
    for tracked in &report.checks[1..] {
        assert!(tracked.trials.iter().all(|t| t.tracked.and_then(|f| f.touchdown).is_some()), "every trial lands");
        // Same draws, same sizes and spins, through every engine and controller.
        for (a, b) in report.checks[0].trials.iter().zip(&tracked.trials) {
            assert!(a.draw == b.draw);
        }
        assert!(tracked.film.as_ref().is_some_and(|f| !f.worst.is_empty() && f.touchdowns.len() == 2));
    }
    // The feedback beats the open loop on these six trials (measured at 200 µs: 95th
    // percentile 2.07° against 9.41°; the spin of σ = 0.005 N·m·s is the open loop's error).
    let (open, closed) = (&report.checks[1], &report.checks[2]);
    assert!(
        closed.landing_error_deg.p95 < 0.25 * open.landing_error_deg.p95,
        "feedback {}° against open loop {}°",
        closed.landing_error_deg.p95,
        open.landing_error_deg.p95
    );
    assert!(closed.within > open.within, "{} against {}", closed.within, open.within);
    let csv = report.to_csv();
    assert!(csv.lines().filter(|l| l.starts_with("rapier-feedback,")).count() == 6, "{csv}");
    let md = report.to_markdown();
    assert!(md.contains("rapier, attitude feedback: the schedule lands within 5° in"), "{md}");
}

#[test]
fn a_replanned_check_is_byte_identical_at_one_and_two_threads() {
    let p = problem(&[
        "robust.trials=4",
        "robust.engine=rapier",
        "robust.dt_s=2e-4",
        "robust.controller=feedback",
        "robust.feedback_replan_hz=20",
    ]);
    let r = Resolved::new(&p).expect("calibrates");
    let (one, two) = (outputs_at(&p, &r, 1), outputs_at(&p, &r, 2));
    assert!(one == two, "the re-planned check depends on the thread count");
    assert!(one.2.contains("re-planned every 0.050 s"), "{}", one.2);
    // The same draws without re-plans land otherwise: the re-plans act.
    let once = problem(&["robust.trials=4", "robust.engine=rapier", "robust.dt_s=2e-4", "robust.controller=feedback"]);
    let without = check(&once, &r.schedule, "s").expect("the check");
    assert!(without.to_csv() != one.1, "re-planning changed nothing");
}

#[test]
fn without_spread_every_trial_is_the_nominal_cat() {
    let p = problem(&["robust.mass_pct=0", "robust.radius_pct=0", "robust.spin_sigma_nms=0"]);
    let r = Resolved::new(&p).expect("calibrates");
    let c = robustness(&p, &r.schedule, "s").expect("two motors");
    for t in &c.trials {
        assert!((t.landing_error_deg - c.nominal.landing_error_deg).abs() <= 0.0, "trial {}", t.draw.trial);
    }
    // The calibrated cycloidal schedule turns by exactly 180° and keeps its swing (1.27°,
    // README): the landing error is the swing, the twist error zero.
    assert!(c.nominal.twist_error_deg.abs() < 1e-6, "twist error {}", c.nominal.twist_error_deg);
    assert!((c.nominal.landing_error_deg - c.nominal.swing_deg).abs() < 1e-6);
    assert!(c.within >= 1.0 - f64::EPSILON, "every trial lands within 5°");
}

#[test]
fn the_spin_spreads_the_landing_and_the_worst_trials_are_the_largest_errors() {
    let p = problem(&["robust.spin_sigma_nms=0.005"]);
    let r = Resolved::new(&p).expect("calibrates");
    let c = robustness(&p, &r.schedule, "s").expect("two motors");
    let largest = c.trials.iter().map(|t| t.landing_error_deg).fold(0.0, f64::max);
    assert!((c.worst[0].landing_error_deg - largest).abs() <= 0.0);
    assert!(c.worst.windows(2).all(|w| w[0].landing_error_deg >= w[1].landing_error_deg));
    assert!(c.landing_error_deg.p95 > c.nominal.landing_error_deg, "a spin of σ = 0.005 N·m·s must move the landing");
    assert!((c.landing_error_deg.max - largest).abs() <= 0.0);
    // The landing error bounds the swing exactly: the target turns about z, so `R_*⁻¹ R` tilts
    // the spine as `R` does, and a rotation moves no unit vector by more than its angle. The
    // twist part is bounded only up to the composition of the two small rotations (1 %).
    for t in &c.trials {
        assert!(t.landing_error_deg + 1e-9 >= t.swing_deg, "{t:?}");
        assert!(t.landing_error_deg + 1e-9 >= t.twist_error_deg.abs() * 0.99, "{t:?}");
    }
    assert!(c.verdict.contains("40 trials"), "{}", c.verdict);
}

#[test]
fn draws_follow_their_distributions_and_repeat_with_the_seed() {
    let p = problem(&["robust.spin_sigma_nms=0.01", "robust.mass_pct=20"]);
    let s = p.robust;
    let n = 4000;
    let draws: Vec<_> = (0..n).map(|k| draw(&p, &s, k)).collect();
    assert!(draws.iter().all(|d| (d.mass - 1.0).abs() <= 0.2 && (d.length - 1.0).abs() <= 0.0));
    for axis in 0..3 {
        let var = draws.iter().map(|d| d.angular_momentum_nms[axis].powi(2)).sum::<f64>() / n as f64;
        // The sample standard deviation of 4000 normals is within 5 % of σ with overwhelming odds.
        assert!((var.sqrt() / 0.01 - 1.0).abs() < 0.05, "axis {axis}: σ = {}", var.sqrt());
    }
    assert!(draw(&p, &s, 17) == draws[17], "a trial's draw depends on its index and the seed only");
}

#[test]
fn percentiles_are_nearest_rank() {
    let v: Vec<f64> = (1..=100).map(f64::from).collect();
    let p = Percentiles::of(&v);
    assert!((p.p50 - 50.0).abs() <= 0.0 && (p.p95 - 95.0).abs() <= 0.0 && (p.max - 100.0).abs() <= 0.0);
    let one = Percentiles::of(&[3.0]);
    assert!((one.p50 - 3.0).abs() <= 0.0 && (one.p99 - 3.0).abs() <= 0.0);
}

#[test]
fn bad_robust_settings_name_their_field() {
    for (set, field) in [
        ("robust.trials=0", "robust.trials"),
        ("robust.mass_pct=95", "robust.mass_pct"),
        ("robust.spin_sigma_nms=-1", "robust.spin_sigma_nms"),
        ("robust.tolerance_deg=0", "robust.tolerance_deg"),
        ("robust.dt_s=0", "robust.dt_s"),
        ("robust.dt_s=0.5", "robust.dt_s"),
        ("robust.servo_hz=-1", "robust.servo_hz"),
        ("robust.servo_damping=-0.1", "robust.servo_damping"),
        ("robust.gain_pct=95", "robust.gain_pct"),
        ("robust.attitude_latency_s=-0.01", "robust.attitude_latency_s"),
        ("robust.attitude_noise_deg=200", "robust.attitude_noise_deg"),
        ("robust.feet_down_deg=0", "robust.feet_down_deg"),
        ("robust.engine=mujoco", "engine"),
        ("robust.controller=pid", "controller"),
        ("robust.feedback_hz=0", "robust.feedback_hz"),
        ("robust.feedback_hz=20000", "robust.feedback_hz"),
        ("robust.feedback_attitude_deg=0", "robust.feedback_attitude_deg"),
        ("robust.feedback_joint_deg=100", "robust.feedback_joint_deg"),
        ("robust.feedback_accel=0", "robust.feedback_accel"),
        ("robust.feedback_spin_prior_nms=-1", "robust.feedback_spin_prior_nms"),
        ("robust.feedback_replan_hz=-1", "robust.feedback_replan_hz"),
        ("robust.feedback_replan_hz=nan", "robust.feedback_replan_hz"),
        ("robust.feedback_replan_hz=inf", "robust.feedback_replan_hz"),
        ("robust.feedback_replan_hz=2000", "robust.feedback_replan_hz"),
        ("robust.controller=feedback", "robust.controller"),
    ] {
        let err = Problem::from_toml("", "t.toml", &[set.to_string()]).expect_err(set);
        assert!(err.to_string().contains(field), "{set}: {err}");
    }
}

fn unequal(extra: &[&str]) -> Problem {
    let mut sets = vec!["robust.trials=40".to_string()];
    sets.extend(extra.iter().map(|s| s.to_string()));
    let text = std::fs::read_to_string("problems/unequal-halves.toml").expect("the preset");
    Problem::from_toml(&text, "unequal-halves.toml", &sets).expect("a valid problem")
}

/// On unequal halves each half is scaled by the same drawn factors, so the halves keep their
/// ratios, and the nominal draw is the problem's own cat.
#[test]
fn a_draw_scales_both_unequal_halves_alike() {
    let p = unequal(&[]);
    let nominal = catflip::robust::drawn_cat(&p, &catflip::robust::nominal_draw(&p));
    assert_eq!(nominal, p.cat.model(), "the nominal draw is the problem's cat");
    let d = draw(&p, &p.robust, 7);
    let cat = catflip::robust::drawn_cat(&p, &d);
    let (f, r) = (p.cat.front(), p.cat.rear());
    for (drawn, own) in [(cat.front, f), (cat.rear, r)] {
        assert!((drawn.mass / own.mass - d.mass / p.cat.mass).abs() < 1e-14, "{drawn:?}");
        assert!((drawn.length / own.length - d.length / p.cat.length).abs() < 1e-14, "{drawn:?}");
        assert!((drawn.radius / own.radius - d.radius / p.cat.radius).abs() < 1e-14, "{drawn:?}");
    }
    assert_eq!(cat.joint, p.cat.joint);
}

/// The exact engine's check on unequal halves (general core) and on Kane and Scher's joint: the
/// calibrated schedule lands the nominal cat exactly (its twist error below 1e-6°, as the
/// calibration's flip), the check is the same at one and two threads, and spreading the sizes
/// spreads the landing.
#[test]
fn the_exact_check_runs_on_other_cats() {
    for extra in [&[][..], &["cat.joint=\"no-twist\""][..]] {
        let p = unequal(extra);
        let r = Resolved::new(&p).expect("calibrates");
        let at = |threads: usize| {
            let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().expect("a pool");
            pool.install(|| robustness(&p, &r.schedule, "s").expect("two motors"))
        };
        let (one, two) = (at(1), at(2));
        assert_eq!(serde_json::to_string(&one).ok(), serde_json::to_string(&two).ok(), "{extra:?}: thread count");
        assert!(
            one.nominal.twist_error_deg.abs() < 1e-6,
            "{extra:?}: nominal twist error {}",
            one.nominal.twist_error_deg
        );
        let flip = r.model().flip(&r.schedule, p.exact.tolerance);
        assert!((one.nominal.swing_deg - flip.swing.to_degrees()).abs() < 1e-9, "{extra:?}: nominal swing");
        assert!(
            one.landing_error_deg.max > one.nominal.landing_error_deg + 0.1,
            "{extra:?}: the draws spread the landing"
        );
    }
}

#[test]
fn rapier_trials_are_refused_on_other_cats_naming_the_engine() {
    let p = unequal(&["robust.engine=\"both\""]);
    let r = Resolved::new(&p).expect("calibrates");
    let e = check(&p, &r.schedule, "s")
        .err()
        .map(|e| format!("{e}: {}", std::error::Error::source(&e).map_or(String::new(), |s| s.to_string())));
    let message = e.expect("refused");
    assert!(message.contains("robust.engine"), "{message}");
}

#[test]
fn the_histogram_holds_every_trial_and_spreads_errors_over_decades_on_a_log_axis() {
    use catflip::report::plot::Scale;
    // The least and the largest landing error of a check's trials, degrees.
    let range = |c: &catflip::robust::Robustness| {
        c.trials
            .iter()
            .fold((f64::INFINITY, 0.0f64), |(a, b), t| (a.min(t.landing_error_deg), b.max(t.landing_error_deg)))
    };
    // Counts of the step outline: every bin's height once (each bin is two points at one height).
    let counted = |plot: &catflip::report::plot::LinePlot| -> Vec<f64> {
        plot.series.iter().map(|s| s.points[1..s.points.len() - 1].iter().step_by(2).map(|p| p.1).sum()).collect()
    };
    // Without spin, the mass draws alone move the landing by less than a decade (on this
    // calibrated cat not at all: 1.2718° for every trial): equal bins from 0 on a linear axis.
    let p = problem(&["robust.spin_sigma_nms=0"]);
    let r = Resolved::new(&p).expect("calibrates");
    let c = robustness(&p, &r.schedule, "s").expect("two motors");
    let report = catflip::robust::RobustReport { checks: vec![c.clone()], command: String::new() };
    let within = report.histogram_plot();
    let (least, most) = range(&c);
    assert!(most <= 10.0 * least, "{least}–{most}°");
    assert_eq!(within.scale, Scale::Linear);
    assert!(within.y_label.starts_with("trials per ") && within.y_label.ends_with("° bin"), "{}", within.y_label);
    assert_eq!(counted(&within), vec![40.0]);
    // With a spin of σ = 0.05 N·m·s the errors run from tenths of a degree to tens: bins equal in
    // log error on a log axis, and still every trial counted once.
    let p = problem(&["robust.spin_sigma_nms=0.05"]);
    let c = robustness(&p, &r.schedule, "s").expect("two motors");
    let (least, most) = range(&c);
    assert!(most > 10.0 * least, "the spin should spread the landing over a decade: {least}–{most}°");
    let report = catflip::robust::RobustReport { checks: vec![c], command: String::new() };
    let spread = report.histogram_plot();
    assert_eq!(spread.scale, Scale::LogX);
    assert!(spread.y_label.contains("equal in log error"), "{}", spread.y_label);
    assert_eq!(counted(&spread), vec![40.0]);
    let edges: Vec<f64> = spread.series[0].points.iter().map(|p| p.0).collect();
    assert!(edges[0] > 0.0 && edges[0] <= least && edges.windows(2).all(|w| w[1] >= w[0]), "{edges:?}");
    // The distribution of the same trials is drawn on the log axis too.
    assert_eq!(report.distribution_plot().scale, Scale::LogX);
}

/// An overdamped servo is stiffer than its `servo_hz` says: its fast mode decays at
/// ω_n (ζ + √(ζ² − 1)), 9.9 ω_n at ζ = 5, and the warning before a tracked run counts it and names
/// `robust.servo_damping` (a review's ζ = 5 diverged at the default step with a warning and an
/// error that named only the step and the frequency); at ζ = 1 the default step draws none.
#[test]
fn an_overdamped_servo_is_warned_of_by_its_damping() {
    let warned = |damping: &str| {
        let p = problem(&["robust.engine=\"rapier\"", &format!("robust.servo_damping={damping}")]);
        p.warnings().into_iter().filter(|w| w.contains("rad per step")).collect::<Vec<_>>()
    };
    let w = warned("5.0");
    assert_eq!(w.len(), 1, "{w:?}");
    assert!(
        w[0].starts_with("robust.servo_hz = 10 with robust.servo_damping = 5 (its fast mode 9.9× ω_n)"),
        "{}",
        w[0]
    );
    assert!(w[0].ends_with("bring robust.servo_damping down towards 1"), "{}", w[0]);
    assert!(warned("1.0").is_empty(), "the default damping at the default step is stable");
}
