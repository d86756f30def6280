//! Knot refinement where a torque switches.
//!
//! A peak-torque (or least-fall-time) optimum is bang-bang-like: each torque rides its bound and
//! switches across it within one knot span, where the spline's piecewise-linear `q̈` can only ramp.
//! On uniform knots that ramp limits the optimum's accuracy (the peak converges as `h²`: 0.3183,
//! 0.3168, 0.3162 N·m at 120, 200, 300 control points on the paper's cat), and the ramp's
//! coupling into the other joint's torque is the dip or spike between saturated arcs. A span
//! *switches* when a torque swings by more than [`SWITCH_FRACTION`] of the peak across it (its
//! samples, both ends included); it and its two neighbours (the switch may move by a span when
//! solved again) are split into [`PARTS`] equal spans by knot insertion
//! ([`BSpline::with_knot`]), which leaves the curve as it is, so the refined solve starts from the
//! optimum it refines, with a trust radius ([`TRUST_SHARE`]) and an optimality ([`OPTIMALITY`])
//! fit for a start at an optimum, for at most [`BUDGET`] iterations. The refined result is kept
//! when it is lower than what it refines and flips within the limits (also when it stopped at
//! its budget: then its status is `upper-bound`, [`super::WholeStatus::UpperBound`], and the
//! start's reason says so).

use super::cat::WholeCat;
use super::spline::BSpline;
use super::torques::ExactTorques;
use crate::schedule::Trajectory;

/// The swing of a torque across one span, as a fraction of the peak, that marks a switch.
pub const SWITCH_FRACTION: f64 = 0.5;

/// Spans each refined span is split into.
pub const PARTS: usize = 4;

/// The refined solve's first trust radius as a share of `trust_radius_deg`: it starts at an
/// optimum, where the setting's radius was rejected twice or three times before (ratios −3.6 and
/// −0.64 for the peak, −12 and −3.5 for the least fall time within a speed limit, on the paper's
/// cat) and a radius of `1/64` of it was accepted at once.
pub const TRUST_SHARE: f64 = 1.0 / 64.0;

/// The refined solve's optimality, at least: from an optimum on the coarser knots the least fall
/// time within a speed limit crawled by `10⁻⁶` relative per step for 30 steps (ratios near 0.5)
/// below it, at the paper's cat.
pub const OPTIMALITY: f64 = 1e-6;

/// Most iterations of a refined solve. From the optimum on the coarser knots it converges in 10–25
/// on the paper's cat; on others (a bend limit, a small cat) it crawls on (ratios near 0.4 at a
/// fixed radius, `10⁻⁵` relative per step), and the iterations past this bought `< 10⁻⁴`.
pub const BUDGET: usize = 25;

/// Most iterations of a refined solve by the interior-point method (`optimize.whole.method`),
/// whose stage ends converged rather than crawling: from the coarser optimum the tailed cat's
/// refined in 19, the legged cat's in 13, the spherical joint's in 66 (in 25 it had wandered
/// above the optimum it refines and was not kept; converged, 0.308286 N·m against 0.312451).
pub const INTERIOR_BUDGET: usize = 100;

/// The budget of a refined solve: the interior point's ([`INTERIOR_BUDGET`]) where its method
/// plans the stage, the trust region's ([`BUDGET`]) elsewhere.
pub fn budget(interior_point: bool) -> usize {
    if interior_point {
        INTERIOR_BUDGET
    } else {
        BUDGET
    }
}

/// Torque samples per span of the switch search, ends included.
const SAMPLES: usize = 8;

/// The spans across which a torque switches (module docs), in order.
pub fn switching_spans(cat: &WholeCat, spline: &BSpline) -> Vec<usize> {
    switching_spans_from(&cat.exact_torques(None), spline)
}

/// [`switching_spans`] with the torques of `source` (a release with spin).
pub fn switching_spans_from(source: &ExactTorques, spline: &BSpline) -> Vec<usize> {
    let durations = spline.piece_durations();
    let torques: Vec<Vec<Vec<f64>>> = durations
        .iter()
        .enumerate()
        .map(|(span, &d)| {
            (0..=SAMPLES)
                .map(|k| {
                    let s = d * k as f64 / SAMPLES as f64;
                    source.at(spline, span, s)
                })
                .collect()
        })
        .collect();
    let peak = torques.iter().flatten().flatten().map(|t| t.abs()).fold(0.0, f64::max);
    (0..durations.len())
        .filter(|&span| {
            (0..spline.joints()).any(|j| {
                let (lo, hi) = torques[span]
                    .iter()
                    .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), t| (lo.min(t[j]), hi.max(t[j])));
                hi - lo > SWITCH_FRACTION * peak
            })
        })
        .collect()
}

/// `spline` with every span in `spans` and its neighbours split into [`PARTS`] (module docs).
pub fn refined(spline: &BSpline, spans: &[usize]) -> BSpline {
    let last = spline.spans() - 1;
    let mut split: Vec<usize> = spans.iter().flat_map(|&s| [s.saturating_sub(1), s, (s + 1).min(last)]).collect();
    split.sort_unstable();
    split.dedup();
    let knots: Vec<f64> = split
        .iter()
        .flat_map(|&s| {
            let (a, b) = spline.span_bounds(s);
            (1..PARTS).map(move |k| a + (b - a) * k as f64 / PARTS as f64)
        })
        .collect();
    knots.into_iter().fold(spline.clone(), |s, u| s.with_knot(u))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_refined_span_and_its_neighbours_are_split_into_parts() {
        let s = BSpline::zero(1.0, 13, 3);
        let r = refined(&s, &[0, 5]);
        // spans 0, 1 and 4, 5, 6 split into four: 5 × 3 knots more.
        assert_eq!(r.spans(), s.spans() + 5 * (PARTS - 1));
        assert_eq!(r.control_points(), s.control_points() + 5 * (PARTS - 1));
        let widths = r.piece_durations();
        assert!((widths[0] - 0.025).abs() < 1e-15 && (widths[8] - 0.1).abs() < 1e-15, "{widths:?}");
    }
}
