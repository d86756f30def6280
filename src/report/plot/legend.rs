//! Which curves of a chart a reader can see: a legend entry must not promise a curve that is
//! drawn under others.
//!
//! Series are painted in order, so series `i` is hidden when every one of its points lies on
//! the curves painted after it. "On" is measured in axis-normalised units
//! (`(x − x₀)/(x₁ − x₀)`, `(y − y₀)/(y₁ − y₀)`, on the mapped — for log axes log10 — values):
//! a point is covered when it lies within [`COINCIDENT`] of a later series' polyline (a
//! single-point run counts as a dot). On the 1000 × 600 figures, whose plot areas are about
//! 560–660 × 470 pixels, that is 2.5–3 pixels: the 2-pixel line on top and its anti-aliasing,
//! so at most a pixel of the curve underneath peeks out.
//!
//! A hidden series keeps its legend entry, with the note "under a" naming one later series that
//! covers it alone, or "under a, b" naming those that cover it together (in painting order;
//! "under a, 2; b, 10" when the names hold commas of their own, [`Label::note_pieces`]).

/// Distance, as a fraction of each axis span, within which a point lies on a curve.
pub(crate) const COINCIDENT: f64 = 5e-3;

/// One series' runs of mapped points, as [`super::chart`] draws them.
pub(crate) type Runs = [Vec<(f64, f64)>];

/// A legend entry: the series' name, and for a hidden series what it is drawn under.
#[derive(Clone, Debug, PartialEq, Eq)]
pub(crate) struct Label {
    /// The series' name.
    pub name: String,
    /// The later series that cover it (empty when it is seen).
    pub under: Vec<String>,
}

impl Label {
    /// The note's pieces, `["under a,", "b"]`: each covering series' name, the first after
    /// "under", each but the last followed by the separator's mark, a comma, or a semicolon when
    /// a name has a comma of its own (`under poly-345, 10; s-curve, 10`).
    pub fn note_pieces(&self) -> Vec<String> {
        let mark = if self.under.iter().any(|n| n.contains(',')) { ";" } else { "," };
        let last = self.under.len().saturating_sub(1);
        self.under
            .iter()
            .enumerate()
            .map(|(k, n)| format!("{}{n}{}", if k == 0 { "under " } else { "" }, if k < last { mark } else { "" }))
            .collect()
    }

    /// The note on one line, `Some("under a, b")`, when the series is hidden.
    pub fn note(&self) -> Option<String> {
        (!self.under.is_empty()).then(|| self.note_pieces().join(" "))
    }
}

/// The legend entry of each series ([`Label`]).
pub(crate) fn legend_labels(names: &[&str], runs: &[&Runs], x: (f64, f64), y: (f64, f64)) -> Vec<Label> {
    let (wx, wy) = ((x.1 - x.0).abs().max(f64::MIN_POSITIVE), (y.1 - y.0).abs().max(f64::MIN_POSITIVE));
    let norm = |(px, py): (f64, f64)| ((px - x.0) / wx, (py - y.0) / wy);
    let curves: Vec<Curve> = runs.iter().map(|r| Curve::new(r, norm)).collect();
    names
        .iter()
        .enumerate()
        .map(|(i, name)| {
            let points: Vec<(f64, f64)> =
                runs.get(i).into_iter().flat_map(|r| r.iter()).flatten().map(|&p| norm(p)).collect();
            let under = cover(&points, &curves[i + 1..]).map_or_else(Vec::new, |js| {
                js.iter().filter_map(|&j| names.get(i + 1 + j).map(|n| (*n).to_string())).collect()
            });
            Label { name: (*name).to_string(), under }
        })
        .collect()
}

/// Indices into `later` of curves that together cover every one of `points` (one alone if
/// one does), or `None` when a point is uncovered or there are no points.
fn cover(points: &[(f64, f64)], later: &[Curve]) -> Option<Vec<usize>> {
    if points.is_empty() {
        return None;
    }
    if let Some(j) = later.iter().position(|c| points.iter().all(|&p| c.near(p, COINCIDENT))) {
        return Some(vec![j]);
    }
    let mut used = Vec::new();
    for &p in points {
        let j = later.iter().position(|c| c.near(p, COINCIDENT))?;
        if !used.contains(&j) {
            used.push(j);
        }
    }
    used.sort_unstable();
    Some(used)
}

/// A series as normalised segments (a lone point is a segment of length zero).
struct Curve {
    segments: Vec<((f64, f64), (f64, f64))>,
    /// Whether both ends' x never decrease along the list, so a binary search finds the
    /// segments near a given x.
    monotone: bool,
}

impl Curve {
    fn new(runs: &Runs, norm: impl Fn((f64, f64)) -> (f64, f64)) -> Curve {
        let mut segments = Vec::new();
        for run in runs {
            let pts: Vec<(f64, f64)> = run.iter().map(|&p| norm(p)).collect();
            match pts.as_slice() {
                [] => {}
                [only] => segments.push((*only, *only)),
                _ => segments.extend(pts.windows(2).map(|w| (w[0], w[1]))),
            }
        }
        let lo = |s: &((f64, f64), (f64, f64))| s.0 .0.min(s.1 .0);
        let hi = |s: &((f64, f64), (f64, f64))| s.0 .0.max(s.1 .0);
        let monotone = segments.windows(2).all(|w| lo(&w[0]) <= lo(&w[1]) && hi(&w[0]) <= hi(&w[1]));
        Curve { segments, monotone }
    }

    /// Whether `p` lies within `tol` of the curve.
    fn near(&self, p: (f64, f64), tol: f64) -> bool {
        let (from, to) = if self.monotone {
            let from = self.segments.partition_point(|s| s.0 .0.max(s.1 .0) < p.0 - tol);
            let to = self.segments.partition_point(|s| s.0 .0.min(s.1 .0) <= p.0 + tol);
            (from, to.max(from))
        } else {
            (0, self.segments.len())
        };
        self.segments[from..to].iter().any(|&(a, b)| distance(p, a, b) <= tol)
    }
}

/// Distance from `p` to the segment `a`–`b` (to `a` when they coincide).
pub(super) fn distance(p: (f64, f64), a: (f64, f64), b: (f64, f64)) -> f64 {
    let (dx, dy) = (b.0 - a.0, b.1 - a.1);
    let len2 = dx * dx + dy * dy;
    let t = if len2 > 0.0 { (((p.0 - a.0) * dx + (p.1 - a.1) * dy) / len2).clamp(0.0, 1.0) } else { 0.0 };
    (p.0 - a.0 - t * dx).hypot(p.1 - a.1 - t * dy)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn line(f: impl Fn(f64) -> f64, n: usize) -> Vec<Vec<(f64, f64)>> {
        vec![(0..=n).map(|k| k as f64 / n as f64).map(|x| (x, f(x))).collect()]
    }

    fn notes(names: &[&str], runs: &[&Runs]) -> Vec<Option<String>> {
        legend_labels(names, runs, (0.0, 1.0), (0.0, 1.0)).into_iter().map(|l| l.note()).collect()
    }

    #[test]
    fn a_curve_under_a_later_one_is_marked() {
        let a = line(|x| x * x, 100);
        let b = line(|x| 1.0 - x, 100);
        let a_again = line(|x| x * x, 37); // other sampling, same curve
        assert_eq!(notes(&["a", "b", "a2"], &[&a, &b, &a_again]), [Some("under a2".to_string()), None, None]);
    }

    #[test]
    fn a_curve_on_top_or_apart_is_not_marked() {
        let a = line(|x| x, 50);
        let b = line(|x| x, 50);
        let c = line(|x| x + 0.02, 50); // two hundredths of the span apart: four times the tolerance
                                        // a lies under b; b is painted after a, and c is apart from both.
        assert_eq!(notes(&["a", "b", "c"], &[&a, &b, &c]), [Some("under b".to_string()), None, None]);
    }

    #[test]
    fn a_curve_covered_piecewise_names_every_cover() {
        // b covers a on [0, ½], c on [½, 1]; d covers a alone and is preferred.
        let a = line(|x| x, 40);
        let b: Vec<Vec<(f64, f64)>> = vec![vec![(0.0, 0.0), (0.5, 0.5), (0.5, 0.9)]];
        let c: Vec<Vec<(f64, f64)>> = vec![vec![(0.5, 0.1), (0.5, 0.5), (1.0, 1.0)]];
        assert_eq!(notes(&["a", "b", "c"], &[&a, &b, &c])[0].as_deref(), Some("under b, c"));
        assert_eq!(notes(&["a", "b", "c", "d"], &[&a, &b, &c, &a])[0].as_deref(), Some("under d"));
        // Partly covered is visible.
        let half: Vec<Vec<(f64, f64)>> = vec![vec![(0.0, 0.0), (0.5, 0.5)]];
        assert_eq!(notes(&["a", "half"], &[&a, &half])[0], None);
        // Names with commas of their own (a sweep's "poly-345, 10") are told apart by semicolons.
        assert_eq!(notes(&["a, 2", "b, 10", "c, 10"], &[&a, &b, &c])[0].as_deref(), Some("under b, 10; c, 10"));
    }
}
