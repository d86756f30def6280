//! The peak-torque table and the optimisers against the exact engine (`catflip run`'s output is checked end to end in `tests/results_fresh.rs`).
#![deny(clippy::float_cmp)]

use std::f64::consts::PI;

use approx::assert_relative_eq;
use catflip::engines::resolved::Resolved;
use catflip::optimize::optimize;
use catflip::problem::manoeuvre::ProfileKind;
use catflip::problem::Problem;
use catflip::report::compare::compare;

fn small() -> Problem {
    let mut p = Problem::default();
    p.optimize.nodes = 61;
    p
}

#[test]
fn table_has_every_profile_and_the_paper_model_peaks() {
    let p = Problem::default();
    let t = compare(&Resolved::new(&p).expect("resolves"), &[]);
    assert_eq!(t.rows.len(), ProfileKind::ALL.len());
    let t2 = 0.6 * p.drop.fall_time();
    for r in &t.rows {
        // Model peak I*·C_a·D/T² (paper §8 with the correct I*).
        let (model, coefficient, circulation) = (
            r.model_peak_nm.expect("a profile's row"),
            r.accel_coefficient.expect("a profile's row"),
            r.circulation_rad.expect("a profile's row"),
        );
        assert_relative_eq!(
            model,
            p.cat.half().end_transverse() * coefficient * circulation / (t2 * t2),
            max_relative = 1e-12
        );
        // Path invariance: twist and swing do not depend on the profile.
        assert_relative_eq!(r.twist_deg, t.rows[0].twist_deg, epsilon = 1e-7);
        assert_relative_eq!(r.swing_deg, t.rows[0].swing_deg, epsilon = 1e-7);
        let jumps = if r.profile == "paper-cosine" { 1 } else { 0 };
        assert_eq!(r.velocity_jumps, jumps, "{}", r.profile);
        // The exact peak is far above the paper's model: centripetal terms dominate.
        assert!(r.exact_peak_nm.max > model, "{}", r.profile);
    }
    let csv = t.to_csv();
    assert_eq!(csv.lines().count(), 1 + t.rows.len());
}

#[test]
fn qp_matches_its_closed_form_and_refinement_beats_every_library_profile() {
    let p = small();
    let resolved = Resolved::new(&p).expect("resolves");
    let r = optimize(&resolved).expect("runs");
    assert!(r.qp.status.is_solved(), "{:?}", r.qp.status);
    // N = 61 is odd: the discrete optimum is the bang-bang value 4 D I*/T² (qp module docs).
    assert_relative_eq!(
        r.qp.peak_torque.expect("solved"),
        r.qp_closed_form_nm.unwrap_or(f64::NAN),
        max_relative = 1e-7
    );
    let t2 = 0.6 * p.drop.fall_time();
    assert_relative_eq!(
        r.qp.peak_torque.expect("solved"),
        4.0 * r.circulation.radians * p.cat.half().end_transverse() / (t2 * t2),
        max_relative = 1e-7
    );
    let refined = r.refined_optimum.as_ref().expect("refinement ran");
    let peak = refined.measured.exact.phase_peaks().phase_max(catflip::schedule::Phase::Twist);
    let table = compare(&resolved, &[]);
    for row in &table.rows {
        let lib = row.exact_peak_nm.twist[0].max(row.exact_peak_nm.twist[1]);
        assert!(peak < lib, "refined {peak} ≥ {} ({lib})", row.profile);
    }
    // The refinement changes the timing only: the flip is unchanged, and with the calibrated
    // circulation it is π.
    let e = &refined.measured.exact;
    assert_relative_eq!(e.twist_deg(), table.rows[0].twist_deg, epsilon = 1e-7);
    assert_relative_eq!(
        refined.calibrated.expect("calibration converged").twist.abs(),
        PI,
        epsilon = 1e-6f64.to_radians()
    );
    assert!(e.jumps.is_empty(), "{:?}", e.jumps);
    // Retiming bend and unbend too lowers the whole manoeuvre's peak below the twist-only
    // refinement's (which the harmonic bend dominates), keeps every phase rest to rest, and
    // leaves the flip alone (same joint path).
    let whole = r.all_phases.as_ref().expect("the all-phases refinement ran");
    let w = &whole.optimum.measured.exact;
    assert!(w.peak() < e.peak(), "{} vs {}", w.peak(), e.peak());
    assert!(w.jumps.is_empty(), "{:?}", w.jumps);
    assert_relative_eq!(w.twist_deg(), table.rows[0].twist_deg, epsilon = 1e-7);
    assert_relative_eq!(w.swing_deg(), table.rows[0].swing_deg, epsilon = 1e-7);
    assert_relative_eq!(
        whole.optimum.calibrated.expect("calibration converged").twist.abs(),
        PI,
        epsilon = 1e-6f64.to_radians()
    );
}
