//! Values that load but lie far from any cat's or robot's: most likely the wrong unit (degrees
//! for radians, millimetres for metres, radians in a degrees field). [`super::limits`] refuses
//! what the engines cannot compute; these ranges are narrower and only warn, naming the field
//! and the unit it expects, because a number from them is computed exactly but answers another
//! question than the user's.

use super::{Circulation, Drop, Problem, WARN_SPIN_TURNS};
use crate::numeric::numfmt::{echo, num};

/// Drop heights a cat or a robot is dropped from, m: a few centimetres to a tall building.
pub const PLAUSIBLE_HEIGHT_M: (f64, f64) = (0.05, 500.0);
/// Gravitational accelerations, m/s²: below the Moon's 1.62, above Jupiter's 24.8.
const GRAVITY_M_S2: (f64, f64) = (1.0, 30.0);
/// Lengths of a half, m.
const LENGTH_M: (f64, f64) = (0.01, 10.0);
/// Masses of a half, kg.
const MASS_KG: (f64, f64) = (0.01, 500.0);
/// The sizes of an appendage (a tail, a pair of legs) relative to the cat's body (both halves end
/// to end; their mass together) outside which a length or a mass is warned of: a tail as long as
/// the body is a long one (a gecko's, a tailed robot's) and legs are shorter than a half, while a
/// gecko's tail weighs grams against its body's tens, so the lower ends are far below any.
const APPENDAGE_TO_BODY: (f64, f64) = (1e-3, 3.0);
/// Turns of the bend direction beyond which a given circulation is warned about (the paper's
/// `π/C` is half a turn on its cat; a light tail on a heavy body needs a few).
const CIRCULATION_TURNS: f64 = 10.0;
/// `manoeuvre.theta_deg` at or below this (π and a little) reads as radians.
const THETA_AS_RADIANS: f64 = 3.2;

/// `field = value unit` outside `(lo, hi)`, as a warning that guesses the unit.
fn outside(field: &str, value: f64, unit: &str, (lo, hi): (f64, f64), small: &str, large: &str) -> Option<String> {
    let guess = if value < lo {
        small
    } else if value > hi {
        large
    } else {
        return None;
    };
    Some(format!(
        "{field} = {} {unit} is outside the {}–{} {unit} any cat or robot meets: is it in {guess}? (the field is in {unit})",
        echo(value),
        echo(lo),
        echo(hi)
    ))
}

/// The problem's values that are probably in the wrong unit, as warnings.
pub(crate) fn warnings(p: &Problem) -> Vec<String> {
    let mut out = Vec::new();
    out.extend(outside("drop.height", p.drop.height, "m", PLAUSIBLE_HEIGHT_M, "km", "mm or cm"));
    out.extend(outside("drop.gravity", p.drop.gravity, "m/s²", GRAVITY_M_S2, "g units or km/s²", "cm/s²"));
    let cat = &p.cat;
    let halves = [
        ("cat", Some(cat.half())),
        ("cat.front", cat.front.map(|_| cat.front())),
        ("cat.rear", cat.rear.map(|_| cat.rear())),
    ];
    for (section, half) in halves {
        let Some(half) = half else { continue };
        out.extend(outside(&format!("{section}.length"), half.length, "m", LENGTH_M, "km", "mm or cm"));
        out.extend(outside(&format!("{section}.mass"), half.mass, "kg", MASS_KG, "tonnes", "g"));
    }
    let body = cat.model();
    // Each appendage section with the length and the mass it sets itself (a pair of legs of its
    // own may leave them to [cat.legs], which is checked itself).
    let mut appendages: Vec<(&str, Option<f64>, Option<f64>)> = Vec::new();
    appendages.extend(cat.tail.map(|t| ("cat.tail", Some(t.length), Some(t.mass))));
    appendages.extend(cat.legs.map(|l| ("cat.legs", l.length, l.mass)));
    for (field, own) in cat.legs.iter().flat_map(|l| l.own_pairs()) {
        appendages.push((field, own.length, own.mass));
    }
    // An appendage's length and mass against the body's: the cat's own scale, not any cat's.
    for (section, length, mass) in appendages {
        let sizes = [
            ("length", length, body.front.length + body.rear.length, ("long", "short"), "m", ("mm or cm", "km")),
            ("mass", mass, body.front.mass + body.rear.mass, ("heavy", "light"), "kg", ("g", "tonnes")),
        ];
        for (field, value, whole, (more, less), unit, (small_unit, large_unit)) in sizes {
            let Some(value) = value else { continue };
            let ratio = value / whole;
            let (word, guess) = if ratio > APPENDAGE_TO_BODY.1 {
                (more, small_unit)
            } else if ratio < APPENDAGE_TO_BODY.0 {
                (less, large_unit)
            } else {
                continue;
            };
            out.push(format!(
                "{section}.{field} = {} {unit} is {} times the cat's body (both halves, {} {unit}): too {word} for an appendage; is it in {guess}? (the field is in {unit})",
                echo(value),
                num(ratio),
                echo(whole)
            ));
        }
    }
    if let Circulation::Angle(d) = p.manoeuvre.circulation {
        let turns = d.abs() / std::f64::consts::TAU;
        if turns > CIRCULATION_TURNS {
            out.push(format!(
                "manoeuvre.circulation = {} rad turns the bend direction {} times: is it in degrees? (the field is in radians; the paper's π/C is 3.22 rad, results/paper/optimize.md)",
                echo(d),
                num(turns)
            ));
        }
    }
    if p.manoeuvre.theta_deg <= THETA_AS_RADIANS {
        out.push(format!(
            "manoeuvre.theta_deg = {} folds the halves to {}° apart: is it in radians? (the field is in degrees; 180 is straight)",
            echo(p.manoeuvre.theta_deg),
            echo(p.manoeuvre.theta_deg)
        ));
    }
    // A one-σ draw of the robustness check's release spin, on every axis.
    let sigma = p.robust.spin_sigma_nms;
    let turns = Drop { angular_momentum: [sigma; 3], ..p.drop }.spin_turns(&cat.model());
    if turns > WARN_SPIN_TURNS {
        out.push(format!(
            "robust.spin_sigma_nms = {} turns the straight cat {} turns during the fall at one σ: a cat released by hand turns a fraction of a turn (is it in N·m·s, kg·m²/s?)",
            echo(sigma),
            num(turns)
        ));
    }
    out
}
