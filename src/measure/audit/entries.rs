//! The audit's entries: each quantity's published, literal and corrected values and why they
//! differ. Every explanation is computed for the problem at hand.

use std::f64::consts::PI;

use super::formulas::{
    c_section4, c_worked_example, cosine_peak_torque, first_root_theta, k_consistent, k_paper,
    one_turn_printed_argument, one_turn_residual_consistent, one_turn_residual_paper, paper_end_transverse,
    paper_transverse, sin_half_root, stability_threshold, theta_from_sin_half, whole_cat_moments, y_axis_rank,
};
use super::{reproduces, Entry, Reading, ALPHA_ONE_TURN};
use crate::model::BentMoments;
use crate::problem::manoeuvre::{BendPath, ProfileKind};
use crate::problem::Problem;
use crate::schedule::profile::Profile;
use crate::schedule::{paper_c, paper_circulation, Phase, Schedule};

/// Samples of the twist phase on which the peak joint acceleration is taken.
const TWIST_SAMPLES: usize = 4001;

impl Entry {
    pub(super) fn new(key: &'static str, section: &'static str, unit: &'static str, quantity: &str) -> Entry {
        Entry {
            key,
            section,
            quantity: quantity.to_string(),
            unit,
            published: None,
            published_decimals: None,
            literal: None,
            corrected: None,
            exact: None,
            literal_reproduces_published: None,
            explanation: String::new(),
            readings: Vec::new(),
        }
    }

    /// The printed number, shown when `applies` (the worked example, or a general statement).
    fn printed(mut self, applies: bool, value: f64, decimals: Option<u32>) -> Entry {
        if applies {
            self.published = Some(value);
            self.published_decimals = decimals;
        }
        self
    }

    pub(super) fn values(mut self, literal: Option<f64>, corrected: Option<f64>) -> Entry {
        self.literal = literal.filter(|x| x.is_finite());
        self.corrected = corrected.filter(|x| x.is_finite());
        self
    }

    /// The exact engine's value, computed with the entry (the model question's turns).
    pub(super) fn with_exact(mut self, exact: Option<f64>) -> Entry {
        self.exact = exact.filter(|x| x.is_finite());
        self
    }

    fn reading(mut self, label: &str, value: Option<f64>) -> Entry {
        self.readings.push(Reading { label: label.to_string(), value: value.filter(|x| x.is_finite()) });
        self
    }

    pub(super) fn why(mut self, text: String) -> Entry {
        self.explanation = text;
        self.literal_reproduces_published = match (self.published, self.literal) {
            (Some(p), Some(l)) => Some(reproduces(p, self.published_decimals, l)),
            _ => None,
        };
        self
    }
}

/// A number with five significant digits, for explanations.
fn n(x: f64) -> String {
    if x == 0.0 || !x.is_finite() {
        return format!("{x}");
    }
    let digits = (4 - x.abs().log10().floor() as i32).clamp(0, 12) as usize;
    format!("{x:.digits$}")
}

fn no(x: Option<f64>) -> String {
    x.map_or_else(|| "undefined".to_string(), n)
}

/// `Some(x)` for positive `x`.
fn positive(x: f64) -> Option<f64> {
    (x > 0.0).then_some(x)
}

/// A clause for entries built on `π/C` when the slipped inertia makes the literal `C ≤ 0`.
fn lit_undefined(c: &Ctx) -> String {
    if c.circ_lit.is_none() {
        format!("; the slipped inertia gives C = {} ≤ 0, so the literal π/C is undefined", n(c.c_lit))
    } else {
        String::new()
    }
}

/// Everything the entries share, computed once.
struct Ctx<'a> {
    p: &'a Problem,
    worked: bool,
    theta: f64,
    beta: f64,
    t_fall: f64,
    /// `T1, T2, T3` from the problem's phases, s.
    t: [f64; 3],
    /// The §6.3 code's twist duration `0.6 t_fall`, s.
    t2_code: f64,
    it_lit: f64,
    it: f64,
    ia: f64,
    star_lit: f64,
    star: f64,
    lit: BentMoments,
    cor: BentMoments,
    c_lit: f64,
    c: f64,
    circ_lit: Option<f64>,
    circ: Option<f64>,
    omega0_lit: Option<f64>,
    omega0: Option<f64>,
}

impl<'a> Ctx<'a> {
    fn new(p: &'a Problem, worked: bool) -> Ctx<'a> {
        let cat = &p.cat.half();
        let theta = p.manoeuvre.theta();
        let t_fall = p.drop.fall_time();
        let t = p.manoeuvre.phases.map(|f| f * t_fall);
        let t2_code = 0.6 * t_fall;
        let (it_lit, it, ia) = (paper_transverse(cat), cat.transverse(), cat.axial());
        let c_lit = paper_c(it_lit, ia, theta);
        let c = paper_c(it, ia, theta);
        let circ_lit = positive(c_lit).map(|c| PI / c);
        let circ = paper_circulation(cat, theta).ok();
        Ctx {
            p,
            worked,
            theta,
            beta: p.manoeuvre.bend(),
            t_fall,
            t,
            t2_code,
            it_lit,
            it,
            ia,
            star_lit: paper_end_transverse(cat),
            star: cat.end_transverse(),
            lit: BentMoments::new(it_lit, ia, theta),
            cor: BentMoments::new(it, ia, theta),
            c_lit,
            c,
            circ_lit,
            circ,
            omega0_lit: circ_lit.map(|d| d / t2_code),
            omega0: circ.map(|d| d / t[1]),
        }
    }

    fn theta_deg(&self) -> f64 {
        self.p.manoeuvre.theta_deg
    }
}

/// All entries for a problem, in report order.
pub(super) fn build(p: &Problem, worked: bool) -> Vec<Entry> {
    let c = Ctx::new(p, worked);
    let mut v = inertia(&c);
    v.extend(stability(&c));
    v.extend(c_forms(&c));
    v.extend(super::models::entries(p));
    v.extend(rates(&c));
    v.extend(torques(&c));
    v.extend(one_turn(&c));
    v
}

fn inertia(c: &Ctx) -> Vec<Entry> {
    let w = c.worked;
    let (s2, c2) = ((0.5 * c.theta).sin().powi(2), (0.5 * c.theta).cos().powi(2));
    let reproduced = |what: &str| {
        if w {
            format!("literal reproduces {what}; ")
        } else {
            String::new()
        }
    };
    vec![
        Entry::new("fall_time", "§7", "s", "fall time Δt = √(2h/g)")
            .printed(w, 1.428, Some(3))
            .values(Some(c.t_fall), Some(c.t_fall))
            .why(if w {
                format!("agrees: √(2h/g) = {}…, truncated (not rounded) to 1.428", n(c.t_fall))
            } else {
                "agrees".to_string()
            }),
        Entry::new("twist_duration", "§6.3", "s", "twist phase T2 (the code's dt = step_3 − step_2)")
            .values(Some(c.t2_code), Some(c.t[1]))
            .why(if (c.p.manoeuvre.phases[1] - 0.6).abs() < 1e-12 {
                format!(
                    "agrees; the code hard-codes t_max = √(2·10/9.8) and the split at 2/10 and 8/10 of it; §7's ω and τ use the whole fall Δt = {} s instead",
                    n(c.t_fall)
                )
            } else {
                format!("the code's split is fixed at 0.6 of the fall; this problem twists for {} of it", c.p.manoeuvre.phases[1])
            }),
        Entry::new("i_transverse", "§7", "kg·m²", "transverse moment of a half about its centre, I_x'x' = I_y'y'")
            .printed(w, 0.084, Some(3))
            .values(Some(c.it_lit), Some(c.it))
            .why(format!(
                "{}§6.3's code and §7 use m(r² + l²)/12, dropping the 3 on r² (§2 eq. (2) and §5 print the solid cylinder's m(3r² + l²)/12); corrected is {:.2}% larger",
                reproduced("0.084"),
                100.0 * (c.it / c.it_lit - 1.0)
            )),
        Entry::new("i_axial", "§7", "kg·m²", "axial moment of a half, I_z'z' = m r²/2")
            .printed(w, 0.005, Some(3))
            .values(Some(c.ia), Some(c.ia))
            .why("agrees".to_string()),
        Entry::new("i_yy_transverse_term", "§7", "kg·m²", "first term of §7's I_yy, I_y'y' cos²(θ/2)")
            .printed(w, 0.071841, Some(6))
            .values(Some(c.it_lit * c2), Some(c.it * c2))
            .why(format!("{}differs by the transverse-inertia slip only (see i_transverse)", reproduced("0.071841"))),
        Entry::new("i_yy_axial_term", "§7", "kg·m²", "second term of §7's I_yy, I_z'z' sin²(θ/2)")
            .printed(w, 0.000732, Some(6))
            .values(Some(c.ia * s2), Some(c.ia * s2))
            .why("agrees".to_string()),
        Entry::new("i_yy", "§7", "kg·m²", "I_yy of one half about the cat's centre of mass (§2 eq. (1)–(2))")
            .printed(w, 0.0726, Some(4))
            .values(Some(c.lit.yy), Some(c.cor.yy))
            .why(format!(
                "{}differs by the inertia slip only: y runs through both halves' centres, so no parallel-axis term enters; the whole cat's is 2 I_yy (Claim 1), while eq. (1)–(2) give one half's momentum",
                reproduced("0.0726")
            )),
    ]
}

fn stability(c: &Ctx) -> Vec<Entry> {
    let cat = &c.p.cat.half();
    let whole = whole_cat_moments(c.it, c.ia, cat.mass, cat.length, c.theta);
    let shift = whole.xx - c.it;
    let parallel = format!(
        "about the cat's centre each half's centre sits (l/2) sin(θ/2) off along y, adding m l² sin²(θ/2)/4 = {}; plus the inertia slip",
        n(shift)
    );
    let lit_min = stability_threshold(c.it_lit, c.ia, 0.0).map(f64::to_degrees);
    let cor_min = stability_threshold(c.it, c.ia, cat.mass * cat.length.powi(2) / 4.0).map(f64::to_degrees);
    let from = match cor_min {
        Some(m) => format!("with the parallel-axis terms the whole cat's y axis is least from θ = {}°", n(m)),
        None => "the threshold needs I_x'x' > I_z'z'".to_string(),
    };
    let where_this = match cor_min {
        Some(m) if c.theta_deg() >= m => format!("this problem's θ = {}° is inside", c.theta_deg()),
        Some(_) => format!("this problem's θ = {}° is outside", c.theta_deg()),
        None => "this cat has I_x'x' ≤ I_z'z' (L < √3 R), outside §3's argument".to_string(),
    };
    let ratio = cat.length / cat.radius;
    vec![
        Entry::new("i_xx", "§3", "kg·m²", "I_xx of one half about the cat's centre of mass")
            .values(Some(c.lit.xx), Some(whole.xx))
            .why(format!("§3 takes I_xx = I_x'x', about the half's own centre; {parallel}")),
        Entry::new("i_zz", "§3", "kg·m²", "I_zz of one half about the cat's centre of mass")
            .values(Some(c.lit.zz), Some(whole.zz))
            .why(format!("§3 takes I_zz = I_y'y' sin²(θ/2) + I_z'z' cos²(θ/2); {parallel}")),
        Entry::new("stability_margin", "§3", "kg·m²", "I_zz − I_yy of one half (≥ 0: y is the least principal axis)")
            .values(Some(c.lit.zz - c.lit.yy), Some(whole.zz - whole.yy))
            .why(format!(
                "at θ = {}°, y is the {} axis in §3's model (no parallel-axis terms, slipped inertia) and the {} axis of the whole cat; §3's text writes \"so I_yy > I_xx\" right after deriving I_yy < I_xx",
                c.theta_deg(),
                y_axis_rank(&c.lit),
                y_axis_rank(&whole)
            )),
        Entry::new("theta_min_stable", "§3", "deg", "smallest θ for which y is the least principal axis (I_yy ≤ I_zz)")
            .printed(true, 90.0, None)
            .values(lit_min, cor_min)
            .why(format!(
                "the printed range \"π ≤ θ ≤ π/2\" is empty: it means π/2 ≤ θ ≤ π, where sin(θ/2) ≥ cos(θ/2) (printed \"≤\", true only below π/2); {from}; {where_this}"
            )),
        Entry::new("length_ratio_min", "§3", "1", "least L/R for I_x'x' ≥ I_z'z' (§3's \"sufficiently large length\")")
            .printed(true, 3f64.sqrt(), None)
            .values(Some(3f64.sqrt()), Some(3f64.sqrt()))
            .reading("needed with §6.3/§7's slipped I_x'x' = m(r² + l²)/12", Some(5f64.sqrt()))
            .reading("this cat's L/R", Some(ratio))
            .why(format!(
                "agrees; the printed chain writes ¼MR² + ½MR² for ½MR² and ½M(L/√3)² for ¼M(L/√3)², two slips that cancel; with the code's slipped inertia it would be L ≥ √5 R; this cat: L/R = {}",
                n(ratio)
            )),
    ]
}

fn c_forms(c: &Ctx) -> Vec<Entry> {
    let c4 = c_section4(c.it_lit, c.ia, c.theta);
    let ratio = c.c_lit / c.c - 1.0;
    let slip = if ratio.is_finite() {
        format!("differs from corrected by the inertia slip only ({:+.3}%)", 100.0 * ratio)
    } else {
        "differs from corrected by the inertia slip only".to_string()
    };
    vec![
        Entry::new("c_section4", "§4", "1", "C = 1 − 2 (I_zz/I_cc) sin(θ/2)")
            .values(Some(c4), Some(c.c))
            .why(format!(
                "I_cc is never defined; read as the code's per-half ic = I_yy (literal), the 2 doubles the counter-rotation (1 − C = {} against the code's {}); with I_cc the whole cat's 2 I_yy, as §5's L_C = I_yy ω_c needs, it is the code's form (corrected)",
                n(1.0 - c4),
                n(1.0 - c.c_lit)
            )),
        Entry::new("c_code", "§6.3", "1", "the code's c = 1 − 2·iz/(2·ic)·sin(θ/2) = 1 − I_z'z' sin(θ/2)/I_yy")
            .values(Some(c.c_lit), Some(c.c))
            .why(format!("the form DESIGN.md adopts; {slip}")),
        Entry::new("c_worked_example", "§7", "1", "C in §7's ω line, 1 − (I_z'z'/I_yy) sin²(θ/2)")
            .values(Some(c_worked_example(c.it_lit, c.ia, c.theta)), Some(c.c))
            .why("§7's ω line squares sin(θ/2), unlike the code and §7's own τ line; corrected: the code's form with the correct inertia".to_string()),
        Entry::new("c_worked_example_torque", "§7", "1", "C in §7's τ line, 1 − (I_z'z'/I_yy) sin(θ/2)")
            .values(Some(c.c_lit), Some(c.c))
            .why(format!("sin(θ/2) unsquared here: the code's C, inconsistent with the ω line above it; {slip}")),
        Entry::new("circulation", "§4", "rad", "circulation ∫ω ds = π/C (the code's C)")
            .values(c.circ_lit, c.circ)
            .why(match c.circ {
                Some(_) => format!(
                    "differs by the inertia slip in C only; circulation = \"calibrated\" instead finds the circulation that turns the cat by exactly π on the exact engine{}",
                    lit_undefined(c)
                ),
                None => format!("C = {} ≤ 0: π/C is no circulation for this cat", n(c.c)),
            }),
    ]
}

fn rates(c: &Ctx) -> Vec<Entry> {
    let w = c.worked;
    let c_we = c_worked_example(c.it_lit, c.ia, c.theta);
    let omega_lit = positive(c_we).map(|k| PI / (c.t_fall * k));
    let omega_sin = positive(c.c_lit).map(|k| PI / (c.t_fall * k));
    // The C that the printed ω would need with the printed formula's π/(Δt C).
    let implied = PI / (c.t_fall * 2.2514);
    let omega = Entry::new(
        "omega_worked_example",
        "§7",
        "rad/s",
        "§7's rate ω = π/(Δt C), C with sin²(θ/2), over the whole fall",
    )
    .printed(w, 2.2514, Some(4))
    .values(omega_lit, c.omega0)
    .reading("printed formula π/(Δt (1 − (I_z'z'/I_yy) sin²(θ/2)))", omega_lit)
    .reading("sin(θ/2) unsquared (§7's τ line, the code's C), whole Δt", omega_sin)
    .reading(
        "§4's C (factor 2, per-half I_cc), whole Δt",
        positive(c_section4(c.it_lit, c.ia, c.theta)).map(|k| PI / (c.t_fall * k)),
    )
    .reading("the code's π/(T2 C), slipped inertia", c.omega0_lit);
    let right = format!(
        "right: the code's C with the correct inertia over the twist phase T2 = {} s, not the whole fall: ω0 = π/(C T2) = {}",
        n(c.t[1]),
        no(c.omega0)
    );
    let omega = omega.why(if w {
        format!(
            "no literal reading reproduces 2.2514 to its 4 decimals: the printed formula gives {}, sin(θ/2) unsquared {} (see readings); the C it implies, π/(Δt · 2.2514) = {}, matches none of the printed forms ({}, {}, {}); {}; {right}",
            no(omega_lit),
            no(omega_sin),
            n(implied),
            n(c_we),
            n(c.c_lit),
            n(c_section4(c.it_lit, c.ia, c.theta)),
            nearest_reading(c.p)
        )
    } else {
        format!("§7's formula squares sin(θ/2), which the code does not, and spreads the turn over the whole fall; {right}")
    });
    let split = if (c.t2_code - c.t[1]).abs() > 1e-12 * c.t[1] { " and the phase split" } else { "" };
    vec![
        omega,
        Entry::new("omega0", "§6.3", "rad/s", "ω0 = π/(T2 C) as the code computes it (omega_0 = π/(dt·c))")
            .values(c.omega0_lit, c.omega0)
            .why(format!(
                "the code's ω0 with dt = step_3 − step_2 the twist duration (the listing writes `cloud` for `c`); differs by the inertia slip{split}; ω0 is the mean of ω(s) = ω0(1 − cos(πs/T2)), which ends at 2ω0, not at rest{}",
                lit_undefined(c)
            )),
        Entry::new("i_star", "§7", "kg·m²", "I*: a half's moment about a transverse axis through its end")
            .printed(w, 0.3342, Some(4))
            .values(Some(c.star_lit), Some(c.star))
            .why(format!(
                "{}parallel axis I_x'x' + m(l/2)²; §7 writes \"I_x'x' + md\" and \"m h²/4\" (h is the drop height) for m d² = m l²/4, and inherits the r² slip",
                if w { "literal reproduces 0.3342; " } else { "" }
            )),
    ]
}

/// The nearest reading of §7's ω from the paper's ingredients ([`super::readings`]), in words.
fn nearest_reading(p: &Problem) -> String {
    match super::readings::search(p).and_then(|s| s.nearest.first().cloned().map(|r| (s.tried, r))) {
        Some((tried, r)) => format!(
            "of {tried} readings of the paper's own ingredients the nearest (omega_readings) gives {} ({:+.4}%): {}",
            n(r.omega),
            100.0 * r.omega_relative_error,
            r.words
        ),
        None => "no reading of the paper's ingredients gives a rate".to_string(),
    }
}

fn torques(c: &Ctx) -> Vec<Entry> {
    let w = c.worked;
    let [t1, t2, t3] = c.t;
    let amp = 0.5 * c.beta;
    let tau2_lit = c.omega0_lit.map(|o| c.star_lit * o * PI / c.t2_code);
    let tau2 = c.omega0.map(|o| c.star * o * PI / t2);
    let tau_we_lit = positive(c.c_lit).map(|k| PI * PI * c.star_lit / (c.t_fall.powi(2) * k));
    let c_we = c_worked_example(c.it_lit, c.ia, c.theta);
    let from_omega = positive(c_we).map(|k| PI / (c.t_fall * k) * PI / c.t_fall * c.star_lit);
    let from_printed = 2.2514 * PI / 1.428 * 0.3342;
    let mut we = Entry::new("tau_twist_worked_example", "§7", "N·m", "§7's peak twist torque ω (π/Δt) I*")
        .printed(w, 1.655, Some(3))
        .values(tau_we_lit, tau2)
        .reading("ω (π/Δt) I* with the literal ω (sin²)", from_omega)
        .reading("printed final form π² I*/(Δt² (1 − (I_z'z'/I_yy) sin(θ/2)))", tau_we_lit);
    if w {
        we = we.reading("printed ω = 2.2514 × π/1.428 × printed I* = 0.3342", Some(from_printed));
    }
    let tail = format!(
        "both use the whole fall where the twist lasts T2 = {}·Δt, which enters squared; corrected: §8's bound I* ω0 π/T2 with correct I*, C and T2 (tau_twist); the exact inverse dynamics is the reference",
        n(c.p.manoeuvre.phases[1])
    );
    let we = we.why(if w {
        format!(
            "the printed expressions disagree (sin² in ω, sin here): {} and {}; 1.655 follows from the printed ω = 2.2514 × π/1.428 × 0.3342 = {}{}; unit printed \"N\" for N·m; {tail}",
            no(from_omega),
            no(tau_we_lit),
            n(from_printed),
            super::readings::search(c.p)
                .and_then(|s| s.nearest.into_iter().next())
                .map_or_else(String::new, |r| format!(", and from the nearest ω reading (omega_readings): I* ω π/T = {}", n(r.tau)))
        )
    } else {
        format!("the printed expressions disagree (sin² in ω, sin here): {} and {}; {tail}", no(from_omega), no(tau_we_lit))
    });
    let joint = twist_joint_accel_peak(c).map(|a| c.star * a);
    let one_link = "still a one-link estimate: the exact inverse dynamics (exact engine) is the reference";
    let dropped = |t: f64| {
        format!(
            "A(1 − cos(πt/T)) peaks at A π²/T²: §8's π² I*/T² drops A = β/2 = {} rad (×{}) and uses the slipped I*; {one_link}",
            n(amp),
            n(cosine_peak_torque(c.star, amp, t) / cosine_peak_torque(c.star_lit, 1.0, t))
        )
    };
    vec![
        we,
        Entry::new("bend_amplitude", "§8", "rad", "amplitude A of θ1(t) = A(1 − cos(πt/T1)) and of θ3")
            .values(Some(PI - 0.5 * c.theta), Some(amp))
            .why(format!(
                "§8 prints (π − θ0/2) for (π − θ0)/2: θ1 runs from 0 to 2A, which must be the bend β = π − θ0 = {} rad; §6.4's code has (π − θ)/2",
                n(c.beta)
            )),
        Entry::new("tau_bend", "§8", "N·m", "peak bend torque, §8's bound max τ1 = π² I*/T1²")
            .values(Some(cosine_peak_torque(c.star_lit, 1.0, t1)), Some(cosine_peak_torque(c.star, amp, t1)))
            .why(dropped(t1)),
        Entry::new("tau_twist", "§8", "N·m", "peak twist torque, §8's bound max τ2 = I* ω0 π/T2")
            .values(tau2_lit, tau2)
            .why(format!(
                "ω0(1 − cos(πs/T2)) peaks at dω/ds = ω0 π/T2 (s = T2/2): the bound is right for I* dω/ds and differs by the inertia slips{}; but ω is no joint acceleration: the joint circle accelerates the joints by β φ̈ and β φ̇² (tau_twist_joint_accel); {one_link}{}",
                if (c.t2_code - t2).abs() > 1e-12 * t2 { " and the phase split" } else { "" },
                lit_undefined(c)
            )),
        Entry::new("tau_twist_joint_accel", "§8", "N·m", "I* × peak joint acceleration of the paper's twist (joint circle, paper cosine, π/C)")
            .values(None, joint)
            .why(format!(
                "q = β(cos φ, sin φ) accelerates a joint by up to β √(φ̈² + φ̇⁴): the bend amplitude and the centripetal φ̇² (φ̇ reaches 2ω0) that §8 ignores, {}× the §8 bound; sampled at {TWIST_SAMPLES} points; {one_link}",
                no(joint.zip(tau2).map(|(a, b)| a / b))
            )),
        Entry::new("tau_unbend", "§8", "N·m", "peak unbend torque, §8's bound max τ3 = π² I*/T3²")
            .values(Some(cosine_peak_torque(c.star_lit, 1.0, t3)), Some(cosine_peak_torque(c.star, amp, t3)))
            .why(format!("{}; each joint starts the unbend from its end-of-twist value, at most β, so β/2 bounds its amplitude", dropped(t3))),
    ]
}

/// Peak `max_i |q̈_i|` over the paper's twist phase: joint circle, paper cosine, circulation `π/C`.
fn twist_joint_accel_peak(c: &Ctx) -> Option<f64> {
    let schedule = Schedule {
        durations: c.t,
        bend: c.beta,
        path: BendPath::JointCircle,
        profile: Profile::library(ProfileKind::PaperCosine),
        circulation: c.circ?,
        bend_profile: Profile::harmonic(),
        unbend_profile: Profile::harmonic(),
    };
    let t2 = c.t[1];
    let peak = (0..TWIST_SAMPLES)
        .map(|k| schedule.phase_state(Phase::Twist, t2 * k as f64 / (TWIST_SAMPLES - 1) as f64).qdd)
        .fold(0.0f64, |m, a| m.max(a[0].abs()).max(a[1].abs()));
    Some(peak)
}

fn one_turn(c: &Ctx) -> Vec<Entry> {
    let a = ALPHA_ONE_TURN;
    let deg = |x: Option<f64>| x.map(f64::to_degrees);
    let printed_arg = one_turn_printed_argument(c.it_lit, c.ia, a);
    let printed = printed_arg.and_then(theta_from_sin_half);
    let root = deg(first_root_theta(|th| one_turn_residual_consistent(c.it, c.ia, a, th)));
    let closed = deg(sin_half_root(c.it, c.ia, k_consistent(a)).and_then(theta_from_sin_half));
    let paper_lit = deg(first_root_theta(|th| one_turn_residual_paper(c.it_lit, c.ia, a, th)));
    let paper_cor = deg(first_root_theta(|th| one_turn_residual_paper(c.it, c.ia, a, th)));
    let paper_closed_lit = deg(sin_half_root(c.it_lit, c.ia, k_paper(a)).and_then(theta_from_sin_half));
    let paper_closed = deg(sin_half_root(c.it, c.ia, k_paper(a)).and_then(theta_from_sin_half));
    let gap = root.zip(closed).map(|(r, k)| (r - k).abs());
    vec![
        Entry::new("omega_c_ratio", "§9", "1", "|ω_c|/ω0 needed for the one-turn twist (α = 1/2)")
            .values(Some(1.0 / (a + 1.0)), Some(1.0 - a))
            .why("§9's own dφ/dt = ω_c + ω0 and dφ/dt = α ω0 give ω_c/ω0 = α − 1 = −1/2 (it opposes ω0, as §5's minus sign says and §9's ω_c drops); 1/(α + 1) does not follow: it would need ω0 = ω_c + dφ/dt with dφ/dt = α ω_c".to_string()),
        Entry::new("one_turn_theta", "§9", "deg", "one-turn θ: a circulation of 2π turns the cat by π (α = 1/2, printed \"θ = 1/2\")")
            .values(printed, root)
            .reading("printed arcsin argument (slipped inertia)", printed_arg)
            .reading("closed form of C(θ) = α: x = I_y'y'/(I_z'z'/(2(1 − α)) + √(…)), θ = 2 arcsin x", closed)
            .reading("root of §9's equation as printed (one_turn_theta_paper_equation), correct inertia", paper_cor)
            .why(format!(
                "the printed closed form takes the wrong root of its quadratic: arcsin of {} (the other root lies outside [−1, 1] for every cat with I_y'y' ≠ I_z'z'); right: C(θ) = α with the code's C and correct inertia, I_z'z' sin(θ/2)/I_yy = 1 − α, solved by bracketing: θ = {}° (the closed form {}); a root in (0°, 180°) exists for every cat since the residual changes sign; whether this θ really turns the cat by π is for the exact engine",
                no(printed_arg),
                no(root),
                gap.map_or_else(
                    || "is undefined".to_string(),
                    |g| if g == 0.0 { "agrees to the last bit".to_string() } else { format!("agrees within {g:.1e}°") }
                )
            )),
        Entry::new("one_turn_theta_paper_equation", "§9", "deg", "root of §9's equation as printed, 1 = (α + 1)(2 I_z'z'/I_yy) sin(θ/2), α = 1/2")
            .values(paper_lit, paper_cor)
            .reading("closed form (−√ root), slipped inertia", paper_closed_lit)
            .reading("closed form (−√ root), correct inertia", paper_closed)
            .why("with x = sin(θ/2): (I_y'y' − I_z'z') x² + 2(α + 1) I_z'z' x − I_y'y' = 0, root x = [−(α + 1) I_z'z' + √((α + 1)² I_z'z'² + I_y'y'(I_y'y' − I_z'z'))]/(I_y'y' − I_z'z'); the printed form has +√ over (I_z'z' − I_y'y'), the other root (its denominator is consistent); the equation is not the one-turn condition: its 2 with a per-half I_yy doubles ω_c and 1/(α + 1) stands for 1 − α (one_turn_theta)".to_string()),
    ]
}
