//! Smoothing profiles: the shape of the circulation rate `ω(s)` in the twist phase.
//!
//! A profile is a normalised motion `P(u)` on `u ∈ [0, 1]` with `P(0) = 0`, `P(1) = 1`; its rate
//! `V = P'` and acceleration `A = P''` are exact (closed form, no differencing). Scaled to a
//! circulation `D` over a phase of duration `T`:
//!
//! $$ φ(s) = D\,P(s/T), \quad ω(s) = \frac{D}{T} V(s/T), \quad \dot ω(s) = \frac{D}{T^2} A(s/T). $$
//!
//! Every profile is stored as piecewise acceleration: polynomial or sine segments, integrated
//! analytically. The classic peak-acceleration coefficient `C_a = max |A|` gives
//! `a_max = C_a D / T²` (bang-bang 4, trapezoid 4.5, modified trapezoid ≈ 4.888, modified sine
//! ≈ 5.528, 3-4-5 ≈ 5.774, cycloidal 2π, 4-5-6-7 ≈ 7.52).
//!
//! ## References
//! - the paper, §4 and §8 (its cosine, which ends at `2 ω0`);
//! - H. A. Rothbart, *Cam Design Handbook* (2004), ch. 2–3, for the classic cam laws.

use std::f64::consts::PI;

use crate::numeric::roots::golden_max;
use crate::problem::manoeuvre::ProfileKind;

/// One piece of acceleration on `[start, end)` in normalised time, in local time `τ = u − start`.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Shape {
    /// `A(τ) = Σ c_k τ^k`, degree at most 5.
    Poly([f64; 6]),
    /// `A(τ) = amp · sin(freq τ + phase)`.
    Sine { amp: f64, freq: f64, phase: f64 },
}

impl Shape {
    fn scaled(self, s: f64) -> Shape {
        match self {
            Shape::Poly(c) => Shape::Poly(c.map(|x| x * s)),
            Shape::Sine { amp, freq, phase } => Shape::Sine { amp: amp * s, freq, phase },
        }
    }

    /// `(ΔP − v0 τ, ΔV, A)` at local time `τ` from the segment's start.
    fn integrate(&self, tau: f64) -> (f64, f64, f64) {
        match *self {
            Shape::Poly(c) => {
                let (mut p, mut v, mut a) = (0.0, 0.0, 0.0);
                for k in (0..6).rev() {
                    let kf = k as f64;
                    a = a * tau + c[k];
                    v = v * tau + c[k] / (kf + 1.0);
                    p = p * tau + c[k] / ((kf + 1.0) * (kf + 2.0));
                }
                (p * tau * tau, v * tau, a)
            }
            Shape::Sine { amp, freq, phase } => {
                let (s0, c0) = phase.sin_cos();
                let (s, c) = (freq * tau + phase).sin_cos();
                let v = amp / freq * (c0 - c);
                let p = amp / freq * (tau * c0 - (s - s0) / freq);
                (p, v, amp * s)
            }
        }
    }
}

#[derive(Clone, Copy, Debug, PartialEq)]
struct Segment {
    start: f64,
    p0: f64,
    v0: f64,
    shape: Shape,
}

/// A normalised motion law on `[0, 1]`: position, rate and acceleration, exact.
#[derive(Clone, Debug, PartialEq)]
pub struct Profile {
    name: String,
    segments: Vec<Segment>,
}

/// Position, rate and acceleration of a normalised profile at one instant.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ProfilePoint {
    /// `P(u)`.
    pub position: f64,
    /// `V(u) = P'(u)`.
    pub rate: f64,
    /// `A(u) = P''(u)`.
    pub accel: f64,
}

impl Profile {
    /// The library profile of the given kind.
    pub fn library(kind: ProfileKind) -> Profile {
        use Shape::{Poly, Sine};
        let poly0 = |c: f64| Poly([c, 0.0, 0.0, 0.0, 0.0, 0.0]);
        let quarter = |amp: f64, phase: f64| Sine { amp, freq: 4.0 * PI, phase };
        let pieces: Vec<(f64, Shape)> = match kind {
            ProfileKind::PaperCosine => vec![(0.0, Sine { amp: PI, freq: PI, phase: 0.0 })],
            ProfileKind::Cycloidal => vec![(0.0, Sine { amp: 2.0 * PI, freq: 2.0 * PI, phase: 0.0 })],
            ProfileKind::BangBang => vec![(0.0, poly0(1.0)), (0.5, poly0(-1.0))],
            ProfileKind::Trapezoid => vec![(0.0, poly0(1.0)), (1.0 / 3.0, poly0(0.0)), (2.0 / 3.0, poly0(-1.0))],
            ProfileKind::ModifiedTrapezoid => vec![
                (0.0, quarter(1.0, 0.0)),
                (0.125, poly0(1.0)),
                (0.375, quarter(1.0, PI / 2.0)),
                (0.5, quarter(-1.0, 0.0)),
                (0.625, poly0(-1.0)),
                (0.875, quarter(-1.0, PI / 2.0)),
            ],
            ProfileKind::ModifiedSine => vec![
                (0.0, quarter(1.0, 0.0)),
                (0.125, Sine { amp: 1.0, freq: 4.0 * PI / 3.0, phase: PI / 2.0 }),
                (0.875, quarter(-1.0, PI / 2.0)),
            ],
            ProfileKind::Poly345 => vec![(0.0, Poly([0.0, 60.0, -180.0, 120.0, 0.0, 0.0]))],
            ProfileKind::Poly4567 => vec![(0.0, Poly([0.0, 0.0, 420.0, -1680.0, 2100.0, -840.0]))],
            ProfileKind::SCurve => vec![
                (0.0, Poly([0.0, 8.0, 0.0, 0.0, 0.0, 0.0])),
                (0.125, poly0(1.0)),
                (0.375, Poly([1.0, -8.0, 0.0, 0.0, 0.0, 0.0])),
                (0.5, Poly([0.0, -8.0, 0.0, 0.0, 0.0, 0.0])),
                (0.625, poly0(-1.0)),
                (0.875, Poly([-1.0, 8.0, 0.0, 0.0, 0.0, 0.0])),
            ],
        };
        Profile::from_pieces(kind.name(), 0.0, pieces)
    }

    /// The harmonic motion `P(u) = (1 − cos πu)/2`: the paper's bend and unbend timing
    /// (rest to rest, peak-acceleration coefficient π²/2).
    pub fn harmonic() -> Profile {
        Profile::from_pieces(
            "harmonic",
            0.0,
            vec![(0.0, Shape::Sine { amp: 0.5 * PI * PI, freq: PI, phase: PI / 2.0 })],
        )
    }

    /// A profile whose rate is linear between equally spaced nodes: `rates[k]` at
    /// `u = k/(n−1)`, in any units; it is normalised to unit circulation (trapezoid rule).
    /// Returns `None` when fewer than two nodes or a zero circulation are given.
    pub fn from_rate_nodes(name: &str, rates: &[f64]) -> Option<Profile> {
        let n = rates.len();
        if n < 2 {
            return None;
        }
        let h = 1.0 / (n - 1) as f64;
        let pieces = rates
            .windows(2)
            .enumerate()
            .map(|(k, w)| (k as f64 * h, Shape::Poly([(w[1] - w[0]) / h, 0.0, 0.0, 0.0, 0.0, 0.0])))
            .collect();
        let area: f64 = rates.windows(2).map(|w| 0.5 * h * (w[0] + w[1])).sum();
        if area == 0.0 || !area.is_finite() {
            return None;
        }
        Some(Profile::from_pieces(name, rates[0], pieces))
    }

    /// Builds the segments' starting values and scales the whole to `P(1) = 1`.
    fn from_pieces(name: &str, v_start: f64, pieces: Vec<(f64, Shape)>) -> Profile {
        let mut segments = Vec::with_capacity(pieces.len());
        let (mut p0, mut v0) = (0.0, v_start);
        let ends: Vec<f64> = pieces.iter().skip(1).map(|(s, _)| *s).chain(std::iter::once(1.0)).collect();
        for ((start, shape), end) in pieces.into_iter().zip(ends) {
            segments.push(Segment { start, p0, v0, shape });
            let tau = end - start;
            let (dp, dv, _) = shape.integrate(tau);
            p0 += v0 * tau + dp;
            v0 += dv;
        }
        let mut profile = Profile { name: name.to_string(), segments };
        if p0 != 0.0 {
            profile.rescale(1.0 / p0);
        }
        profile
    }

    fn rescale(&mut self, s: f64) {
        for seg in &mut self.segments {
            seg.p0 *= s;
            seg.v0 *= s;
            seg.shape = seg.shape.scaled(s);
        }
    }

    /// The profile's name (the problem-file spelling for library profiles).
    pub fn name(&self) -> &str {
        &self.name
    }

    /// Position, rate and acceleration at normalised time `u` (clamped to `[0, 1]`).
    pub fn at(&self, u: f64) -> ProfilePoint {
        let u = u.clamp(0.0, 1.0);
        self.on_segment(self.segments.partition_point(|s| s.start <= u).saturating_sub(1), u)
    }

    /// [`Profile::at`] with the earlier segment's formula at a breakpoint: the left limit, where
    /// the acceleration may jump.
    pub fn at_before(&self, u: f64) -> ProfilePoint {
        let u = u.clamp(0.0, 1.0);
        self.on_segment(self.segments.partition_point(|s| s.start < u).saturating_sub(1), u)
    }

    /// The breakpoints strictly inside `(0, 1)`, where the acceleration may jump.
    pub fn inner_breakpoints(&self) -> impl Iterator<Item = f64> + '_ {
        self.breakpoints().filter(|&u| u > 0.0 && u < 1.0)
    }

    /// Segment `idx`'s formula at `u`.
    fn on_segment(&self, idx: usize, u: f64) -> ProfilePoint {
        let seg = &self.segments[idx];
        let tau = u - seg.start;
        let (dp, dv, a) = seg.shape.integrate(tau);
        ProfilePoint { position: seg.p0 + seg.v0 * tau + dp, rate: seg.v0 + dv, accel: a }
    }

    /// Normalised time at which each segment starts (where the acceleration may jump).
    pub fn breakpoints(&self) -> impl Iterator<Item = f64> + '_ {
        self.segments.iter().map(|s| s.start)
    }

    /// Whether the rate is zero at both ends (to round-off).
    pub fn is_rest_to_rest(&self) -> bool {
        self.at(0.0).rate.abs() < 1e-12 && self.at(1.0).rate.abs() < 1e-12
    }

    /// The peak-acceleration coefficient `max |A(u)|`: each segment sampled on a fine grid, the
    /// best sample refined by golden-section search, and each sine crest checked exactly.
    pub fn peak_accel_coefficient(&self) -> f64 {
        const PER_SEGMENT: usize = 64;
        let mut peak: f64 = 0.0;
        let ends: Vec<f64> = self.segments.iter().skip(1).map(|s| s.start).chain(std::iter::once(1.0)).collect();
        for (seg, end) in self.segments.iter().zip(ends) {
            let len = end - seg.start;
            let acc = |tau: f64| seg.shape.integrate(tau).2.abs();
            let best = (0..=PER_SEGMENT)
                .map(|i| len * i as f64 / PER_SEGMENT as f64)
                .fold((0.0, 0.0), |b: (f64, f64), tau| if acc(tau) > b.1 { (tau, acc(tau)) } else { b });
            let h = len / PER_SEGMENT as f64;
            let (_, refined) = golden_max(acc, (best.0 - h).max(0.0), (best.0 + h).min(len), 80);
            peak = peak.max(best.1).max(refined);
            if let Shape::Sine { amp, freq, phase } = seg.shape {
                // A sine segment may crest between samples: at freq·τ + phase = π/2 + nπ.
                let n = ((phase - PI / 2.0) / PI).ceil();
                let crest = (n * PI + PI / 2.0 - phase) / freq;
                if crest <= end - seg.start {
                    peak = peak.max(amp.abs());
                }
            }
        }
        peak
    }
}
