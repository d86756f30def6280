//! `catflip bench`'s optimiser curves and tables (`catflip::measure::bench`): the retiming and the
//! whole-manoeuvre optimiser converge along their sweeps, and no table, CSV or JSON prints a NaN.
//! No timing is asserted (timing belongs in `benches/`).

#![deny(clippy::float_cmp)]

mod common;

use catflip::measure::bench::curve::{Curve, Outcome, Timing};
use catflip::measure::bench::random::run_many;
use catflip::measure::bench::{optimizers, stress, BenchReport};

use common::paper_resolved;

/// Every point's outcome, in the sweep's order; fails on a point without one.
fn outcomes(c: &Curve) -> Vec<Outcome> {
    c.points
        .iter()
        .map(|p| p.outcome.unwrap_or_else(|| panic!("{} at {}: {:?}", c.name, p.setting, p.failed)))
        .collect()
}

#[test]
fn retiming_gap_to_the_converged_bound_falls_at_first_order() {
    let r = paper_resolved();
    let (curve, note) = optimizers::retime_curve(&r.problem.cat.half(), &r.schedule, &[25, 400], [400, 800]);
    let o = outcomes(&curve);
    println!("retime: {o:?}\n{}", note.note);
    assert!(note.note.contains("P_∞"), "the note gives the converged bound: {}", note.note);
    for x in &o {
        assert!(x.error.is_finite() && x.error > 0.0, "{x:?}");
        let gap = x.secondary.expect("a duality gap");
        assert!(gap.abs() < 1e-5, "certified duality gap {gap:e} (relative), expected below 1e-5");
    }
    // First order in 1/N: 16× the grid, ~16× less gap (the bound alone: 2.0 % at 25, 0.12 % at 400).
    assert!(o[1].error < o[0].error / 8.0, "gap {:e} at N = 400 against {:e} at N = 25", o[1].error, o[0].error);
}

#[test]
fn whole_optimiser_converges_to_a_flip_and_its_peak_falls_with_the_spline() {
    let r = paper_resolved();
    let (curve, note) = optimizers::whole_curve(&r.problem, &[20, 60], 90);
    let o = outcomes(&curve);
    println!("whole: {o:?}\n{}", note.note);
    assert!(note.note.contains("0.3159"), "the note cites IPOPT's optimum: {}", note.note);
    for x in &o {
        let violation = x.secondary.expect("a constraint violation");
        assert!(violation < 1e-9, "the landed orientation is {violation:e} rad from R_z(π), expected below 1e-9");
        assert!(x.error.is_finite(), "{x:?}");
    }
    // 0.379 N·m at 20 points, 0.325 at 60, 0.320 at 90: the gap to the finer run shrinks.
    assert!(o[1].error < o[0].error / 2.0, "gap {:e} at 60 points against {:e} at 20", o[1].error, o[0].error);
}

#[test]
fn refused_cases_and_missing_numbers_print_no_nan() {
    let r = paper_resolved();
    let p = &r.problem;
    let stress = stress::stress(p).unwrap_or_else(|e| panic!("{e}"));
    let refused: Vec<_> = stress.iter().filter(|c| c.refused.is_some()).collect();
    assert!(!refused.is_empty(), "the named cases include refusals (θ = 179°, the cone at 92°)");
    assert!(refused.iter().all(|c| c.twist_deg.is_none() && c.peak_torque_nm.is_none()));
    let base = toml::to_string(p).unwrap_or_else(|e| panic!("{e}"));
    let (results, tally) = run_many(&base, 11, 8);
    // A curve whose every kind of point is present: measured, with a non-finite secondary
    // (dropped), with a non-finite error (failed) and refused.
    let odd = Curve::sweep("odd", "setting", "error", &[1.0, 2.0, 3.0, 4.0], |x| match x as u8 {
        1 => Ok(Outcome::error(0.5)),
        2 => Ok(Outcome { error: 0.25, secondary: Some(f64::NAN) }),
        3 => Ok(Outcome::error(f64::NAN)),
        _ => Err("refused".to_string()),
    });
    assert!(odd.points[1].outcome.is_some_and(|o| o.secondary.is_none()), "a NaN secondary is dropped");
    assert!(odd.points[2].outcome.is_none(), "a NaN error fails the point");
    let report = BenchReport {
        machine: "test".into(),
        curves: vec![odd, optimizers::qp_curve(&p.cat.half(), &r.schedule, &[10, 20])],
        notes: Vec::new(),
        evaluation: Timing::measure(|| {}),
        stress,
        random: tally,
        random_notable: results,
    };
    let md = report.to_markdown();
    let json = serde_json::to_string(&report).unwrap_or_else(|e| panic!("{e}"));
    for (what, text) in [("bench.md", &md), ("bench.csv", &report.to_csv()), ("bench.json", &json)] {
        let words = text.split(|c: char| !c.is_alphanumeric());
        let bad: Vec<&str> = words.filter(|w| ["NaN", "nan", "inf"].contains(w)).collect();
        assert!(bad.is_empty(), "{what} prints {bad:?}:\n{text}");
    }
    let row = md.lines().find(|l| l.starts_with("| nearly straight")).expect("the θ = 179° row");
    assert!(row.contains("| — | — |"), "a refused case shows —: {row}");
}
