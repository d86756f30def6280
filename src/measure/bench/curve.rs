//! One work-precision curve: a sweep of a resolution setting, each point timed and its error
//! measured, or a status saying why it has none.
//!
//! A curve is made by [`Curve::sweep`] from a closure `run(setting) → Result<Outcome, String>`
//! that does the whole computation at one setting and measures its error against a reference
//! computed once, outside the closure. The closure is first run once for its outcome, then
//! repeated for timing ([`Timing::measure`]: up to `k` runs within a time budget, best and
//! median kept). So adding a curve for a new engine or optimiser is one function that returns
//! `Curve::sweep(name, setting, error, settings, run)`. When measuring the error costs more
//! than a small part of the run (a re-measurement by the exact engine), [`Curve::sweep_with`]
//! takes the solve and the measurement apart and times only the solve.

use std::time::Instant;

use serde::Serialize;

/// Wall-clock time of repeated runs of one computation, s.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Timing {
    /// Number of runs timed.
    pub repeats: usize,
    /// The fastest run, s.
    pub best_s: f64,
    /// The median run, s.
    pub median_s: f64,
}

/// Most runs timed per point.
pub const MAX_REPEATS: usize = 7;

/// Time budget per point beyond its first timed run, s: slow points are timed fewer times.
pub const BUDGET_S: f64 = 0.25;

impl Timing {
    /// Times `f`: at least once, at most [`MAX_REPEATS`] times, and no more once [`BUDGET_S`]
    /// has been spent.
    pub fn measure(mut f: impl FnMut()) -> Timing {
        let mut times = Vec::new();
        let start = Instant::now();
        while times.is_empty() || (times.len() < MAX_REPEATS && start.elapsed().as_secs_f64() < BUDGET_S) {
            let s = Instant::now();
            f();
            times.push(s.elapsed().as_secs_f64());
        }
        times.sort_by(f64::total_cmp);
        Timing { repeats: times.len(), best_s: times[0], median_s: times[times.len() / 2] }
    }
}

/// What one run at one setting produced.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Outcome {
    /// The error against the curve's reference, in the curve's error unit (finite, ≥ 0).
    pub error: f64,
    /// A second measure beside it, when the curve has one (e.g. the swing error, the gap to
    /// the continuous optimum).
    pub secondary: Option<f64>,
}

impl Outcome {
    /// An outcome with only an error.
    pub fn error(error: f64) -> Outcome {
        Outcome { error, secondary: None }
    }
}

/// One point of a curve.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct BenchPoint {
    /// The setting (steps, tolerance, time step, nodes…).
    pub setting: f64,
    /// Its timing; `None` when the run failed.
    pub timing: Option<Timing>,
    /// Its outcome; `None` when the run failed.
    pub outcome: Option<Outcome>,
    /// Why the run has no outcome (a refusal, a solver status), when it has none.
    pub failed: Option<String>,
}

/// A sentence for the report on what a curve's error means and against which reference (the
/// reference's value when it is computed), printed under the curve's table.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct CurveNote {
    /// The curve's name.
    pub curve: String,
    /// The sentence (Markdown).
    pub note: String,
}

/// A work-precision curve.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Curve {
    /// Its name in files and tables (`exact-magnus6`, `qp`, …).
    pub name: String,
    /// What the setting is, with its unit.
    pub setting: String,
    /// What the error measures, with its unit.
    pub error: String,
    /// What the secondary measure is, when there is one.
    pub secondary: Option<String>,
    /// Whether the error is an angle in rad (such curves enter the time-to-reach table).
    pub error_is_angle: bool,
    /// The points, in the order of the settings.
    pub points: Vec<BenchPoint>,
}

impl Curve {
    /// Runs `run` at every setting: once for its outcome, then [`Timing::measure`]d. An `Err`
    /// (a refusal or solver status, one line) or a non-finite error makes a failed point.
    pub fn sweep(
        name: &str,
        setting: &str,
        error: &str,
        settings: &[f64],
        run: impl FnMut(f64) -> Result<Outcome, String>,
    ) -> Curve {
        Curve::sweep_with(name, setting, error, settings, run, |_, o| Ok(*o))
    }

    /// Like [`Curve::sweep`], but the error is measured apart from the computation that is
    /// timed: `solve(setting)` is run once, `measure(setting, &result)` turns its result into an
    /// outcome (e.g. a re-measurement by the exact engine, which is not the method's cost), and
    /// only `solve` is [`Timing::measure`]d. An `Err` from either makes a failed point, as does
    /// a non-finite or negative error; a non-finite secondary measure is dropped (`—`).
    pub fn sweep_with<T>(
        name: &str,
        setting: &str,
        error: &str,
        settings: &[f64],
        mut solve: impl FnMut(f64) -> Result<T, String>,
        mut measure: impl FnMut(f64, &T) -> Result<Outcome, String>,
    ) -> Curve {
        let failed = |x: f64, why: String| BenchPoint { setting: x, timing: None, outcome: None, failed: Some(why) };
        let points = settings
            .iter()
            .map(|&x| match solve(x).and_then(|r| measure(x, &r)) {
                Ok(o) if o.error.is_finite() && o.error >= 0.0 => {
                    let timing = Timing::measure(|| {
                        let _ = std::hint::black_box(solve(x));
                    });
                    let outcome = Outcome { secondary: o.secondary.filter(|v| v.is_finite()), ..o };
                    BenchPoint { setting: x, timing: Some(timing), outcome: Some(outcome), failed: None }
                }
                Ok(_) => failed(x, "the error is not a finite, non-negative number".to_string()),
                Err(why) => failed(x, why),
            })
            .collect();
        Curve {
            name: name.to_string(),
            setting: setting.to_string(),
            error: error.to_string(),
            secondary: None,
            error_is_angle: false,
            points,
        }
    }

    /// The same curve with its error marked as an angle in rad.
    pub fn angle(mut self) -> Curve {
        self.error_is_angle = true;
        self
    }

    /// The same curve with a name for its secondary measure.
    pub fn with_secondary(mut self, what: &str) -> Curve {
        self.secondary = Some(what.to_string());
        self
    }

    /// The least best-of-k time of a point whose error is at most `target`; `None` when no
    /// point reaches it.
    pub fn time_to_reach(&self, target: f64) -> Option<f64> {
        self.points
            .iter()
            .filter_map(|p| match (p.timing, p.outcome) {
                (Some(t), Some(o)) if o.error <= target => Some(t.best_s),
                _ => None,
            })
            .min_by(f64::total_cmp)
    }

    /// The observed order between neighbouring points, `ln(e_i/e_{i+1}) / |ln(x_i/x_{i+1})|`, for
    /// each point after the first: the points run from coarse to fine, so the order is positive
    /// where the error fell and negative where it grew (a step at which rapier's error rose is
    /// no convergence); `None` where an error is zero or missing.
    pub fn observed_orders(&self) -> Vec<Option<f64>> {
        let mut out = vec![None];
        for w in self.points.windows(2) {
            let order = match (w[0].outcome, w[1].outcome) {
                (Some(a), Some(b))
                    if a.error > 0.0 && b.error > 0.0 && (w[0].setting / w[1].setting).ln().abs() > 0.0 =>
                {
                    Some((a.error / b.error).ln() / (w[0].setting / w[1].setting).ln().abs())
                }
                _ => None,
            };
            out.push(order);
        }
        out.truncate(self.points.len());
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn curve(settings: &[f64], errors: &[f64]) -> Curve {
        let points = settings
            .iter()
            .zip(errors)
            .map(|(&setting, &e)| BenchPoint { setting, timing: None, outcome: Some(Outcome::error(e)), failed: None })
            .collect();
        Curve {
            name: "c".into(),
            setting: "s".into(),
            error: "e".into(),
            secondary: None,
            error_is_angle: false,
            points,
        }
    }

    /// Coarse to fine, a falling error has a positive order whether the setting is a step
    /// (falling) or a count (rising), and a rising one a negative order (the committed bench
    /// showed rapier's error growing from 7.4e-2 to 2.0e-1 at half the step as order 1.44).
    #[test]
    fn an_error_that_grows_on_refinement_has_a_negative_order() {
        let orders = |c: Curve| {
            c.observed_orders().into_iter().map(|o| o.map(|x| (x * 100.0).round() / 100.0)).collect::<Vec<_>>()
        };
        assert_eq!(orders(curve(&[1e-2, 5e-3, 2.5e-3], &[4e-2, 1e-2, 4e-2])), [None, Some(2.0), Some(-2.0)]);
        assert_eq!(orders(curve(&[10.0, 20.0, 40.0], &[4e-2, 2e-2, 4e-2])), [None, Some(1.0), Some(-1.0)]);
    }
}
