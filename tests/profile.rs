//! Smoothing profiles: normalisation, exact derivatives, and the classic peak-acceleration
//! coefficients (H. A. Rothbart, *Cam Design Handbook*, 2004, table of cam laws).
#![deny(clippy::float_cmp)]

use std::f64::consts::PI;

use approx::assert_relative_eq;
use catflip::problem::manoeuvre::ProfileKind;
use catflip::schedule::profile::Profile;

/// `C_a = 1 / ∫_0^{1/2} a(s)(1 − 2s) ds` for a unit-amplitude acceleration shape `a` that is
/// odd about `u = 1/2` (integration by parts: `P(1) = ∫_0^1 (1 − s) a(s) ds`), by composite
/// Simpson on 2·10⁵ panels: an independent second derivation of the coefficient.
fn coefficient_by_quadrature(a: impl Fn(f64) -> f64) -> f64 {
    let n = 200_000;
    let h = 0.5 / n as f64;
    let f = |s: f64| a(s) * (1.0 - 2.0 * s);
    let mut sum = f(0.0) + f(0.5);
    for k in 1..n {
        sum += if k % 2 == 1 { 4.0 } else { 2.0 } * f(k as f64 * h);
    }
    1.0 / (sum * h / 3.0)
}

#[test]
fn every_profile_is_normalised_and_starts_at_rest() {
    for kind in ProfileKind::ALL {
        let p = Profile::library(kind);
        assert_relative_eq!(p.at(0.0).position, 0.0, epsilon = 1e-15);
        assert_relative_eq!(p.at(1.0).position, 1.0, epsilon = 1e-13);
        assert!(p.at(0.0).rate.abs() < 1e-13, "{} starts at rate {}", kind.name(), p.at(0.0).rate);
        let rest = kind != ProfileKind::PaperCosine;
        assert_eq!(p.is_rest_to_rest(), rest, "{}", kind.name());
    }
}

#[test]
fn paper_cosine_ends_at_twice_its_mean_rate() {
    // ω(s) = ω0 (1 − cos(π s/T)) with ∫ω = ω0 T: the rate ends at 2 ω0 (paper §4).
    let p = Profile::library(ProfileKind::PaperCosine);
    assert_relative_eq!(p.at(1.0).rate, 2.0, epsilon = 1e-14);
    assert_relative_eq!(p.at(0.3).rate, 1.0 - (0.3 * PI).cos(), epsilon = 1e-14);
}

#[test]
fn derivatives_are_exact() {
    let h = 1e-6;
    for kind in ProfileKind::ALL {
        let p = Profile::library(kind);
        for k in 1..40 {
            let u = k as f64 / 40.0 + 0.003; // off the breakpoints
            let fd_v = (p.at(u + h).position - p.at(u - h).position) / (2.0 * h);
            let fd_a = (p.at(u + h).rate - p.at(u - h).rate) / (2.0 * h);
            assert!((fd_v - p.at(u).rate).abs() < 1e-7, "{} rate at {u}", kind.name());
            assert!(
                (fd_a - p.at(u).accel).abs() < 1e-6 * (1.0 + fd_a.abs()),
                "{} accel at {u}: {} vs {fd_a}",
                kind.name(),
                p.at(u).accel
            );
        }
    }
}

#[test]
fn rates_are_continuous_across_breakpoints() {
    for kind in ProfileKind::ALL {
        let p = Profile::library(kind);
        for b in p.breakpoints().skip(1) {
            let (l, r) = (p.at(b - 1e-12), p.at(b));
            assert!((l.rate - r.rate).abs() < 1e-9, "{} rate jumps at {b}", kind.name());
            assert!((l.position - r.position).abs() < 1e-9, "{} position jumps at {b}", kind.name());
        }
    }
}

#[test]
fn classic_coefficients_match_closed_forms() {
    let c = |k| Profile::library(k).peak_accel_coefficient();
    assert_relative_eq!(c(ProfileKind::BangBang), 4.0, max_relative = 1e-13);
    assert_relative_eq!(c(ProfileKind::Trapezoid), 4.5, max_relative = 1e-13);
    assert_relative_eq!(c(ProfileKind::Cycloidal), 2.0 * PI, max_relative = 1e-13);
    // 3-4-5: P'' = 60u − 180u² + 120u³ peaks at u = 1/2 ± √3/6 with 10/√3.
    assert_relative_eq!(c(ProfileKind::Poly345), 10.0 / 3f64.sqrt(), max_relative = 1e-6);
    // 4-5-6-7: P'' = −840 x (1/4 − x²)² (x = u − 1/2) peaks at x² = 1/20 with 840/(25√20).
    assert_relative_eq!(c(ProfileKind::Poly4567), 840.0 / (25.0 * 20f64.sqrt()), max_relative = 1e-6);
    // The paper's cosine: ω̇ = ω0 π/T sin(π s/T), so C_a = π.
    assert_relative_eq!(c(ProfileKind::PaperCosine), PI, max_relative = 1e-13);
}

#[test]
fn composite_cam_laws_match_their_textbook_definitions() {
    let quarter = |s: f64| (4.0 * PI * s).sin();
    let mod_trap = |s: f64| {
        if s < 0.125 {
            quarter(s)
        } else if s < 0.375 {
            1.0
        } else {
            (4.0 * PI * (s - 0.375)).cos()
        }
    };
    let mod_sine = |s: f64| if s < 0.125 { quarter(s) } else { (4.0 * PI / 3.0 * (s - 0.125)).cos() };
    let s_curve = |s: f64| {
        if s < 0.125 {
            8.0 * s
        } else if s < 0.375 {
            1.0
        } else {
            1.0 - 8.0 * (s - 0.375)
        }
    };
    let c = |k| Profile::library(k).peak_accel_coefficient();
    assert_relative_eq!(c(ProfileKind::ModifiedTrapezoid), coefficient_by_quadrature(mod_trap), max_relative = 1e-9);
    assert_relative_eq!(c(ProfileKind::ModifiedSine), coefficient_by_quadrature(mod_sine), max_relative = 1e-9);
    assert_relative_eq!(c(ProfileKind::SCurve), coefficient_by_quadrature(s_curve), max_relative = 1e-9);
    // Published values (DESIGN.md §3, Rothbart) to their printed precision.
    assert!((c(ProfileKind::ModifiedTrapezoid) - 4.888).abs() < 5e-4);
    assert!((c(ProfileKind::ModifiedSine) - 5.528).abs() < 5e-4);
}

#[test]
fn rate_nodes_profile_is_piecewise_linear_and_normalised() {
    let p = Profile::from_rate_nodes("tri", &[0.0, 2.0, 4.0, 2.0, 0.0]).expect("valid nodes");
    assert_relative_eq!(p.at(1.0).position, 1.0, epsilon = 1e-14);
    // Triangle of height 2 in normalised units (area 1): peak accel 4 — bang-bang.
    assert_relative_eq!(p.peak_accel_coefficient(), 4.0, max_relative = 1e-13);
    assert_relative_eq!(p.at(0.5).rate, 2.0, epsilon = 1e-14);
    assert!(Profile::from_rate_nodes("empty", &[0.0]).is_none());
    assert!(Profile::from_rate_nodes("zero", &[0.0, 0.0, 0.0]).is_none());
}
