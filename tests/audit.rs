//! Tests of the paper audit (`catflip::measure::audit`).
//!
//! Reference values cite their source: "paper §7" for the printed numbers of the worked example
//! (m = 1, l = 1, r = 0.1, θ = π/4, h = 10, g = 9.8), or a hand calculation written out here.

use std::f64::consts::PI;

use approx::{assert_abs_diff_eq, assert_relative_eq};
use catflip::measure::audit::formulas::{
    first_root_theta, k_consistent, k_paper, one_turn_printed_argument, one_turn_residual_consistent,
    one_turn_residual_paper, sin_half_root, whole_cat_moments,
};
use catflip::measure::audit::readings::{ranked, NEAREST};
use catflip::measure::audit::{audit, is_worked_example, Audit, AuditError, ALPHA_ONE_TURN};
use catflip::model::Cylinder;
use catflip::problem::Problem;
use proptest::prelude::*;

fn paper() -> Audit {
    audit(&Problem::default())
}

fn problem(toml: &str) -> Problem {
    match Problem::from_toml(toml, "test", &[]) {
        Ok(p) => p,
        Err(e) => panic!("test problem does not load: {e}"),
    }
}

/// `(published, literal, corrected)` of an entry; panics naming a missing key.
fn cols(a: &Audit, key: &str) -> (Option<f64>, Option<f64>, Option<f64>) {
    let e = a.entry(key).unwrap_or_else(|| panic!("no entry `{key}`"));
    (e.published, e.literal, e.corrected)
}

fn some(x: Option<f64>, what: &str) -> f64 {
    x.unwrap_or_else(|| panic!("{what} is None"))
}

/// Every key the JSON promises, in report order.
const KEYS: [&str; 31] = [
    "fall_time",
    "twist_duration",
    "i_transverse",
    "i_axial",
    "i_yy_transverse_term",
    "i_yy_axial_term",
    "i_yy",
    "i_xx",
    "i_zz",
    "stability_margin",
    "theta_min_stable",
    "length_ratio_min",
    "c_section4",
    "c_code",
    "c_worked_example",
    "c_worked_example_torque",
    "circulation",
    "omega_worked_example",
    "omega0",
    "i_star",
    "tau_twist_worked_example",
    "bend_amplitude",
    "tau_bend",
    "tau_twist",
    "tau_twist_joint_accel",
    "tau_unbend",
    "omega_c_ratio",
    "one_turn_theta",
    "one_turn_theta_paper_equation",
    "turn_no_twist",
    "turn_universal",
];

#[test]
fn default_problem_is_the_worked_example_and_others_are_not() {
    assert!(is_worked_example(&Problem::default()));
    assert!(!is_worked_example(&problem("[cat]\nradius = 0.12\n")));
    assert!(!is_worked_example(&problem("[manoeuvre]\ntheta_deg = 60.0\n")));
    // The phases enter no printed number: still the worked example.
    assert!(is_worked_example(&problem("[manoeuvre]\nphases = [0.25, 0.5, 0.25]\n")));
}

#[test]
fn worked_example_numbers_are_reproduced_by_the_literal_column() {
    // Paper §7, printed values and their printed decimals.
    let printed = [
        ("fall_time", 1.428, 3),
        ("i_transverse", 0.084, 3),
        ("i_axial", 0.005, 3),
        ("i_yy_transverse_term", 0.071841, 6),
        ("i_yy_axial_term", 0.000732, 6),
        ("i_yy", 0.0726, 4),
        ("i_star", 0.3342, 4),
    ];
    let a = paper();
    for (key, value, decimals) in printed {
        let (published, literal, _) = cols(&a, key);
        assert_abs_diff_eq!(some(published, key), value, epsilon = 1e-15);
        let literal = some(literal, key);
        // Agreement to the printed digits: within one unit of the last printed decimal …
        let unit = 10f64.powi(-decimals);
        assert!((literal - value).abs() < unit, "{key}: literal {literal} vs printed {value}");
        // … and the audit says so.
        assert_eq!(a.entry(key).and_then(|e| e.literal_reproduces_published), Some(true), "{key}");
    }
    // Δt = √(20/9.8) = 1.428571…: the paper truncates to 1.428 (rounding would give 1.429).
    let dt = some(cols(&a, "fall_time").1, "fall_time");
    assert!((1.428..1.429).contains(&dt), "Δt = {dt}");
}

#[test]
fn worked_example_omega_and_torque_are_not_reproduced_by_any_literal_reading() {
    // Paper §7 prints ω ≈ 2.2514 rad/s and τ ≈ 1.655 N·m.
    let a = paper();
    let omega = a.entry("omega_worked_example").unwrap_or_else(|| panic!("no omega entry"));
    assert_abs_diff_eq!(some(omega.published, "ω"), 2.2514, epsilon = 1e-15);
    assert_eq!(omega.literal_reproduces_published, Some(false));
    // Hand: π/(Δt (1 − (0.005/I_yy) sin²(π/8))) with I_yy = 1.01/12 cos²(π/8) + 0.005 sin²(π/8).
    let (s2, c2) = ((2.0 - 2f64.sqrt()) / 4.0, (2.0 + 2f64.sqrt()) / 4.0);
    let iyy = 1.01 / 12.0 * c2 + 0.005 * s2;
    let dt = (20.0f64 / 9.8).sqrt();
    assert_relative_eq!(some(omega.literal, "ω literal"), PI / (dt * (1.0 - 0.005 / iyy * s2)), max_relative = 1e-12);
    assert!(omega.readings.len() >= 3);
    for r in &omega.readings {
        let v = some(r.value, &r.label);
        assert!((v - 2.2514).abs() > 0.5e-4, "reading `{}` = {v} would reproduce 2.2514", r.label);
    }
    let tau = a.entry("tau_twist_worked_example").unwrap_or_else(|| panic!("no τ entry"));
    assert_abs_diff_eq!(some(tau.published, "τ"), 1.655, epsilon = 1e-15);
    assert_eq!(tau.literal_reproduces_published, Some(false));
    // τ = ω (π/Δt) I* is reproduced only from the *printed* ω, Δt and I*: 2.2514 · π/1.428 · 0.3342.
    let from_printed = 2.2514 * PI / 1.428 * 0.3342;
    assert_abs_diff_eq!(from_printed, 1.655, epsilon = 0.5e-3);
    assert!(tau.readings.iter().any(|r| r.value.is_some_and(|v| (v - from_printed).abs() < 1e-12)));
}

#[test]
fn corrected_values_match_hand_calculations() {
    let a = paper();
    let corr = |k: &str| some(cols(&a, k).2, k);
    // Solid cylinder, m = 1, l = 1, r = 0.1: (3·0.01 + 1)/12 and, through an end, (3·0.01 + 4)/12.
    assert_relative_eq!(corr("i_transverse"), 1.03 / 12.0, max_relative = 1e-14);
    assert_relative_eq!(corr("i_star"), 4.03 / 12.0, max_relative = 1e-14);
    let (s, s2, c2) = ((2.0 - 2f64.sqrt()).sqrt() / 2.0, (2.0 - 2f64.sqrt()) / 4.0, (2.0 + 2f64.sqrt()) / 4.0);
    let iyy = 1.03 / 12.0 * c2 + 0.005 * s2;
    assert_relative_eq!(corr("i_yy"), iyy, max_relative = 1e-14);
    let c = 1.0 - 0.005 * s / iyy;
    assert_relative_eq!(corr("c_code"), c, max_relative = 1e-14);
    let fall = (20.0f64 / 9.8).sqrt();
    let (t1, t2) = (0.2 * fall, 0.6 * fall);
    let omega0 = PI / (c * t2);
    assert_relative_eq!(corr("omega0"), omega0, max_relative = 1e-13);
    assert_relative_eq!(corr("circulation"), PI / c, max_relative = 1e-13);
    let i_star = 4.03 / 12.0;
    assert_relative_eq!(corr("tau_twist"), i_star * omega0 * PI / t2, max_relative = 1e-13);
    // β = π − π/4 = 3π/4, amplitude β/2 = 3π/8.
    assert_relative_eq!(corr("tau_bend"), i_star * 3.0 * PI / 8.0 * PI * PI / (t1 * t1), max_relative = 1e-13);
    assert_relative_eq!(corr("tau_unbend"), corr("tau_bend"), max_relative = 1e-13);
    assert_relative_eq!(corr("bend_amplitude"), 3.0 * PI / 8.0, max_relative = 1e-14);
    // Literal §8 bound π² I*/T1² with I* = 4.01/12 and §8's amplitude π − θ/2 = 7π/8.
    assert_relative_eq!(some(cols(&a, "tau_bend").1, "τ1"), PI * PI * 4.01 / 12.0 / (t1 * t1), max_relative = 1e-13);
    assert_relative_eq!(some(cols(&a, "bend_amplitude").1, "A"), 7.0 * PI / 8.0, max_relative = 1e-14);
    // §9: |ω_c|/ω0 = 1/(α + 1) printed, 1 − α right.
    assert_relative_eq!(some(cols(&a, "omega_c_ratio").1, "ratio"), 2.0 / 3.0, max_relative = 1e-15);
    assert_relative_eq!(corr("omega_c_ratio"), 0.5, max_relative = 1e-15);
}

#[test]
fn c_forms_relate_as_derived() {
    // §4 with a per-half I_cc doubles 1 − C of the code; §7's ω line squares sin(θ/2).
    let a = paper();
    let lit = |k: &str| some(cols(&a, k).1, k);
    assert_relative_eq!(1.0 - lit("c_section4"), 2.0 * (1.0 - lit("c_code")), max_relative = 1e-13);
    let s = (PI / 8.0).sin();
    assert_relative_eq!(1.0 - lit("c_worked_example"), (1.0 - lit("c_code")) * s, max_relative = 1e-13);
    assert_relative_eq!(lit("c_worked_example_torque"), lit("c_code"), max_relative = 1e-15);
}

#[test]
fn paper_cosine_peak_rate_of_change_is_omega0_pi_over_t2() {
    // ω(s) = ω0(1 − cos(πs/T2)) ⇒ dω/ds = ω0 (π/T2) sin(πs/T2), peak ω0 π/T2: check on the
    // profile library's exact acceleration, a second derivation of the §8 bound.
    let a = paper();
    let d = some(cols(&a, "circulation").2, "circulation");
    let fall = (20.0f64 / 9.8).sqrt();
    let t2 = 0.6 * fall;
    let profile = catflip::schedule::profile::Profile::library(catflip::problem::ProfileKind::PaperCosine);
    let peak = (0..=1000).map(|k| profile.at(k as f64 / 1000.0).accel.abs()).fold(0.0, f64::max) * d / (t2 * t2);
    let omega0 = some(cols(&a, "omega0").2, "ω0");
    assert_relative_eq!(peak, omega0 * PI / t2, max_relative = 1e-12);
    assert_relative_eq!(some(cols(&a, "tau_twist").2, "τ2"), 4.03 / 12.0 * peak, max_relative = 1e-12);
}

#[test]
fn joint_acceleration_estimate_lies_between_its_hand_bounds() {
    // On q = β(cos φ, sin φ): |q̈_i| ≤ β √(φ̈² + φ̇⁴) ≤ β √((ω0π/T2)² + (2ω0)⁴); at the end of the
    // twist φ̈ = 0, φ̇ = 2ω0 and the larger joint has |q̈_i| ≥ β (2ω0)²/√2.
    let a = paper();
    let (beta, i_star) = (3.0 * PI / 4.0, 4.03 / 12.0);
    let omega0 = some(cols(&a, "omega0").2, "ω0");
    let t2 = 0.6 * (20.0f64 / 9.8).sqrt();
    let est = some(cols(&a, "tau_twist_joint_accel").2, "joint estimate") / i_star;
    let upper = beta * ((omega0 * PI / t2).powi(2) + (2.0 * omega0).powi(4)).sqrt();
    let lower = beta * (2.0 * omega0).powi(2) / 2f64.sqrt();
    assert!(lower <= est * (1.0 + 1e-9) && est <= upper * (1.0 + 1e-9), "{lower} ≤ {est} ≤ {upper}");
}

#[test]
fn whole_cat_moments_match_the_locked_inertia_of_the_model() {
    // A second derivation: the model's locked inertia at q = (β, 0) is the whole cat's tensor about
    // its centre of mass; its eigenvalues are twice the per-half moments xx, yy, zz.
    for (cat, theta_deg) in [
        (Cylinder::default(), 45.0),
        (Cylinder { mass: 1.7, length: 0.6, radius: 0.15 }, 120.0),
        (Cylinder { mass: 0.4, length: 0.3, radius: 0.25 }, 80.0),
    ] {
        let theta = f64::to_radians(theta_deg);
        let locked = cat.configuration([PI - theta, 0.0]).locked_inertia;
        let mut eig: Vec<f64> = locked.symmetric_eigenvalues().iter().copied().collect();
        eig.sort_by(f64::total_cmp);
        let b = whole_cat_moments(cat.transverse(), cat.axial(), cat.mass, cat.length, theta);
        let mut ours = vec![2.0 * b.xx, 2.0 * b.yy, 2.0 * b.zz];
        ours.sort_by(f64::total_cmp);
        for (e, o) in eig.iter().zip(&ours) {
            assert_relative_eq!(*e, *o, max_relative = 1e-12);
        }
    }
}

#[test]
fn stability_threshold_is_where_i_zz_meets_i_yy() {
    // Hand: cos θ* = (m l²/8)/(I_t − I_a + m l²/8) = 0.125/(1.03/12 − 0.005 + 0.125).
    let a = paper();
    let star = some(cols(&a, "theta_min_stable").2, "θ*");
    let hand = (0.125f64 / (1.03 / 12.0 - 0.005 + 0.125)).acos().to_degrees();
    assert_relative_eq!(star, hand, max_relative = 1e-13);
    let cat = Cylinder::default();
    let b = whole_cat_moments(cat.transverse(), cat.axial(), 1.0, 1.0, star.to_radians());
    assert_abs_diff_eq!(b.zz - b.yy, 0.0, epsilon = 1e-15);
    // The printed range π/2 ≤ θ ≤ π is §3's own model; the worked example's 45° is outside both,
    // where y is the intermediate axis.
    assert_relative_eq!(some(cols(&a, "theta_min_stable").1, "literal"), 90.0, max_relative = 1e-14);
    assert!(some(cols(&a, "stability_margin").1, "lit") < 0.0);
    assert!(some(cols(&a, "stability_margin").2, "cor") < 0.0);
}

#[test]
fn one_turn_roots_satisfy_their_equations_and_closed_forms() {
    let a = paper();
    let cat = Cylinder::default();
    let (it, ia, al) = (cat.transverse(), cat.axial(), ALPHA_ONE_TURN);
    // The right condition C(θ) = α.
    let th = some(first_root_theta(|t| one_turn_residual_consistent(it, ia, al, t)), "root");
    assert!(one_turn_residual_consistent(it, ia, al, th).abs() <= 1e-12);
    let closed = 2.0 * some(sin_half_root(it, ia, k_consistent(al)), "closed form").asin();
    assert_relative_eq!(th, closed, max_relative = 1e-12);
    assert_relative_eq!(some(cols(&a, "one_turn_theta").2, "θ"), th.to_degrees(), max_relative = 1e-12);
    // §9's equation as printed, with its corrected closed form (−√ root).
    let thp = some(first_root_theta(|t| one_turn_residual_paper(it, ia, al, t)), "paper root");
    assert!(one_turn_residual_paper(it, ia, al, thp).abs() <= 1e-12);
    let closed_p = 2.0 * some(sin_half_root(it, ia, k_paper(al)), "paper closed form").asin();
    assert_relative_eq!(thp, closed_p, max_relative = 1e-12);
    // The printed closed form is the other root: arcsin argument below −1 for the paper's cat
    // (slipped inertia 1.01/12), so the literal column is None.
    let printed = some(one_turn_printed_argument(1.01 / 12.0, 0.005, al), "printed argument");
    assert!(printed < -1.0, "printed argument {printed}");
    assert!(cols(&a, "one_turn_theta").1.is_none());
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(200))]

    #[test]
    fn one_turn_root_and_closed_forms_agree_for_any_cat(
        mass in 0.1f64..10.0,
        length in 0.05f64..2.0,
        radius in 0.01f64..1.0,
        alpha in 0.05f64..0.95,
    ) {
        let cat = Cylinder { mass, length, radius };
        let (it, ia) = (cat.transverse(), cat.axial());
        for (k, residual) in [
            (k_paper(alpha), &(|t: f64| one_turn_residual_paper(it, ia, alpha, t)) as &dyn Fn(f64) -> f64),
            (k_consistent(alpha), &(|t: f64| one_turn_residual_consistent(it, ia, alpha, t)) as &dyn Fn(f64) -> f64),
        ] {
            let th = first_root_theta(residual);
            prop_assert!(th.is_some(), "a root exists for k > 1");
            let th = th.unwrap_or(f64::NAN);
            prop_assert!(residual(th).abs() <= 1e-12, "residual {}", residual(th));
            let x = sin_half_root(it, ia, k);
            prop_assert!(x.is_some());
            let closed = 2.0 * x.unwrap_or(f64::NAN).asin();
            prop_assert!((th - closed).abs() <= 1e-10 * th.max(1.0), "{} vs {}", th, closed);
        }
        // The printed form's argument is the quadratic's other root, never in [−1, 1] (I_y ≠ I_z).
        if (it - ia).abs() > 1e-9 * it {
            if let Some(p) = one_turn_printed_argument(it, ia, alpha) {
                prop_assert!(p.abs() > 1.0, "printed argument {}", p);
            }
        }
    }
}

#[test]
fn json_carries_every_key_with_its_three_columns() {
    let mut a = paper();
    assert_eq!(a.set_exact("tau_twist", 5.25), Ok(()));
    assert_eq!(a.set_exact("tau_nonsense", 1.0), Err(AuditError::UnknownKey("tau_nonsense".to_string())));
    let json = match serde_json::to_value(&a) {
        Ok(v) => v,
        Err(e) => panic!("audit does not serialise: {e}"),
    };
    let entries = json["entries"].as_object().unwrap_or_else(|| panic!("entries is not a map: {json}"));
    for key in KEYS {
        let e = entries.get(key).unwrap_or_else(|| panic!("JSON lacks `{key}`"));
        for field in ["published", "literal", "corrected", "exact", "section", "unit", "explanation"] {
            assert!(e.get(field).is_some(), "`{key}` lacks `{field}`");
        }
        assert_eq!(e["key"], key);
        assert!(!e["explanation"].as_str().unwrap_or("").is_empty(), "`{key}` has no explanation");
    }
    assert_eq!(entries.len(), a.entries.len());
    assert_eq!(json["entries"]["i_star"]["published"].as_f64(), Some(0.3342));
    assert_eq!(json["entries"]["tau_twist"]["exact"].as_f64(), Some(5.25));
    assert!(json["entries"]["tau_bend"]["exact"].is_null());
    assert_eq!(json["worked_example"], true);
    assert!(json["warnings"].as_array().is_some_and(|w| !w.is_empty()), "θ = 45° must warn (§3)");
}

#[test]
fn other_problems_show_only_general_published_values_and_no_nan() {
    // θ = 180°: a straight cat, C = 1 − I_z/I_z = 0, so π/C and everything built on it is undefined.
    for toml in ["[cat]\nradius = 0.2\n[manoeuvre]\ntheta_deg = 120.0\n", "[manoeuvre]\ntheta_deg = 180.0\n"] {
        let a = audit(&problem(toml));
        assert!(!a.worked_example);
        for key in ["fall_time", "i_transverse", "i_yy", "omega_worked_example", "i_star", "tau_twist_worked_example"] {
            assert!(cols(&a, key).0.is_none(), "{key} must not be published for {toml:?}");
        }
        assert!(cols(&a, "length_ratio_min").0.is_some());
        let text = match serde_json::to_string(&a) {
            Ok(t) => t,
            Err(e) => panic!("audit does not serialise: {e}"),
        };
        assert!(!text.contains("NaN") && !text.contains(" inf") && !text.contains("-inf"), "{text}");
    }
    let straight = audit(&problem("[manoeuvre]\ntheta_deg = 180.0\n"));
    assert!(cols(&straight, "circulation").2.is_none());
    assert!(cols(&straight, "omega0").2.is_none());
    assert!(cols(&straight, "tau_twist").2.is_none());
}

#[test]
fn markdown_lists_every_entry_warning_and_note() {
    let a = paper();
    let md = a.to_markdown();
    for e in &a.entries {
        assert!(md.contains(&format!("`{}`", e.key)), "markdown lacks {}", e.key);
    }
    assert!(md.contains("| key | § | quantity |"));
    assert!(md.contains("< 90"), "the §3 warning is missing");
    assert!(md.contains("cloud"));
    // Printed values keep their printed decimals.
    assert!(md.contains("| 0.071841 |") && md.contains("| 1.428 |"));
}

#[test]
fn exact_column_holds_the_exact_engine_numbers() {
    // The exact engine's peaks of the paper's schedule, and the calibrated circulation, go into
    // the audit's `exact` column; each is checked against a direct call of the engine.
    let p = catflip::problem::Problem::default();
    let resolve = || catflip::engines::resolved::Resolved::new(&p).expect("the paper's schedule resolves");
    let a = catflip::measure::audit::audit_with_exact(&resolve()).expect("every key is the audit's own");
    let r = catflip::report::simulate::simulate(&resolve(), catflip::engines::Engine::Exact).expect("runs");
    let exact = |k: &str| a.entry(k).and_then(|e| e.exact).unwrap_or(f64::NAN);
    let pk = r.peak_torque_nm;
    assert!((exact("tau_bend") - pk.bend[0].max(pk.bend[1])).abs() < 1e-12);
    assert!((exact("tau_twist") - pk.twist[0].max(pk.twist[1])).abs() < 1e-12);
    assert!((exact("tau_unbend") - pk.unbend[0].max(pk.unbend[1])).abs() < 1e-12);
    // The calibrated circulation turns the cat by π (to the engine's tolerance).
    let s = catflip::schedule::Schedule::new(&p, exact("circulation"));
    let f = catflip::engines::exact::flip(&p.cat.half(), &s, 1e-11);
    assert!((f.twist.abs() - std::f64::consts::PI).abs() < 1e-8, "twist {}", f.twist);
}

#[test]
fn a_reading_of_the_papers_ingredients_gives_its_omega_within_0_05_percent() {
    // Paper §7 prints ω ≈ 2.2514 rad/s and τ ≈ 1.655 N·m; the search tries the grid of
    // catflip::measure::audit::readings over the worked example.
    let a = paper();
    let search = a.omega_readings.as_ref().unwrap_or_else(|| panic!("the worked example has no reading search"));
    assert_eq!(search.tried, ranked(&Problem::default()).len());
    assert!(search.tried > 500, "only {} readings tried", search.tried);
    assert_eq!(search.nearest.len(), NEAREST);
    let best = &search.nearest[0];
    assert!(
        best.omega_relative_error.abs() < 5e-4,
        "nearest ω {} is {:+.4}% off",
        best.omega,
        100.0 * best.omega_relative_error
    );
    assert_relative_eq!(best.omega / 2.2514 - 1.0, best.omega_relative_error, max_relative = 1e-12);
    // Ranked: nearest first, and nothing left out is nearer than the last one kept.
    let errors: Vec<f64> = search.nearest.iter().map(|r| r.omega_relative_error.abs()).collect();
    assert!(errors.windows(2).all(|w| w[0] <= w[1]), "not sorted: {errors:?}");
    let all = ranked(&Problem::default());
    assert!(all.iter().skip(NEAREST).all(|r| r.omega_relative_error.abs() >= errors[NEAREST - 1]));
    // Hand: the printed I_y'y' = 0.084 for I_yy, C = 1 − (0.005/0.084) sin(π/8), Δt = 1.428 s.
    let c = 1.0 - 0.005 / 0.084 * (PI / 8.0).sin();
    assert_relative_eq!(best.omega, PI / (1.428 * c), max_relative = 1e-12);
    // Its τ = I* ω π/Δt with the printed I* = 0.3342 is §7's 1.655 to the printed digits.
    assert_relative_eq!(best.tau, 0.3342 * PI / (1.428 * c) * PI / 1.428, max_relative = 1e-12);
    assert_abs_diff_eq!(best.tau, 1.655, epsilon = 0.5e-3);
    // The audit's Markdown and JSON carry it; the ω entry names it.
    let md = a.to_markdown();
    assert!(md.contains("## Readings of §7's ω") && md.contains(&best.words), "Markdown lacks the search");
    let json = serde_json::to_value(&a).unwrap_or_else(|e| panic!("audit does not serialise: {e}"));
    assert_eq!(json["omega_readings"]["nearest"].as_array().map(Vec::len), Some(NEAREST));
    assert_eq!(json["omega_readings"]["nearest"][0]["choices"]["moment"], "transverse");
    let omega = a.entry("omega_worked_example").unwrap_or_else(|| panic!("no omega entry"));
    assert!(omega.explanation.contains("omega_readings"), "{}", omega.explanation);
    // Other problems have no printed ω to search for.
    assert!(audit(&problem("[manoeuvre]\ntheta_deg = 120.0\n")).omega_readings.is_none());
}
