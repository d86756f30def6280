//! The problem file: what a user asks catflip about (DESIGN.md §8).
//!
//! A problem is TOML, SI units, unknown keys rejected. It holds the cat, the drop, the manoeuvre
//! and the settings of each engine and optimiser; every section and field has a default, kept
//! in one `impl Default`. [`Problem::from_toml`] parses, applies `--set key=value` overrides and
//! validates, so that a problem that loads is one every engine can run.

pub mod error;
pub mod manoeuvre;
mod overrides;
pub mod settings;

use std::path::Path;

use serde::{Deserialize, Serialize};

use crate::model::Cylinder;
use crate::problem::settings::{ExactSettings, OptimizeSettings, RapierSettings};

pub use error::ProblemError;
pub(crate) use error::{bad, not_positive, positive};
pub use manoeuvre::{BendPath, Circulation, Manoeuvre, ProfileKind};

/// The drop: how long the cat has to turn over.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct Drop {
    /// Height the cat falls before landing, m.
    pub height: f64,
    /// Gravitational acceleration, m/s² (positive).
    pub gravity: f64,
}

impl Default for Drop {
    fn default() -> Self {
        Self { height: 10.0, gravity: 9.8 }
    }
}

impl Drop {
    /// Fall time `sqrt(2h/g)`, s.
    pub fn fall_time(&self) -> f64 {
        (2.0 * self.height / self.gravity).sqrt()
    }
}

/// A whole problem file.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct Problem {
    /// Name of the problem; results go to `results/<name>/`.
    pub name: String,
    /// One half of the cat (both halves are identical).
    pub cat: Cylinder,
    /// The drop.
    pub drop: Drop,
    /// The manoeuvre: bend, twist, unbend.
    pub manoeuvre: Manoeuvre,
    /// Settings of the exact engine.
    pub exact: ExactSettings,
    /// Settings of the rapier3d verification.
    pub rapier: RapierSettings,
    /// Settings of the optimisers.
    pub optimize: OptimizeSettings,
}

impl Default for Problem {
    fn default() -> Self {
        Self {
            name: "paper".to_string(),
            cat: Cylinder::default(),
            drop: Drop::default(),
            manoeuvre: Manoeuvre::default(),
            exact: ExactSettings::default(),
            rapier: RapierSettings::default(),
            optimize: OptimizeSettings::default(),
        }
    }
}

impl Problem {
    /// Reads, overrides and validates a problem file.
    pub fn load(path: &Path, overrides: &[String]) -> Result<Self, ProblemError> {
        let text = std::fs::read_to_string(path)
            .map_err(|source| ProblemError::Io { path: path.display().to_string(), source })?;
        Self::from_toml(&text, &path.display().to_string(), overrides)
    }

    /// Parses TOML text, applies `key=value` overrides (values in TOML syntax; a bare word is
    /// taken as a string) and validates.
    pub fn from_toml(text: &str, origin: &str, overrides: &[String]) -> Result<Self, ProblemError> {
        let mut table: toml::Table = text.parse().map_err(|e: toml::de::Error| {
            let line = e.span().map(|s| text[..s.start.min(text.len())].lines().count().max(1));
            ProblemError::Parse {
                origin: line.map_or(origin.to_string(), |l| format!("{origin}, line {l}")),
                message: one_line(e.message()),
            }
        })?;
        for assignment in overrides {
            overrides::apply(&mut table, assignment)?;
        }
        let problem: Problem = table.try_into().map_err(|e: toml::de::Error| ProblemError::Parse {
            origin: origin.to_string(),
            message: one_line(&e.to_string()),
        })?;
        problem.validate()?;
        Ok(problem)
    }

    /// Checks every field a model or engine relies on; names the first bad one.
    pub fn validate(&self) -> Result<(), ProblemError> {
        if self.name.is_empty() || !self.name.chars().all(|c| c.is_ascii_alphanumeric() || c == '-' || c == '_') {
            return Err(bad(
                "name",
                &self.name,
                "must be non-empty and use only letters, digits, '-' and '_' (it names a results folder)",
            ));
        }
        positive("cat.mass", self.cat.mass)?;
        positive("cat.length", self.cat.length)?;
        positive("cat.radius", self.cat.radius)?;
        positive("drop.height", self.drop.height)?;
        positive("drop.gravity", self.drop.gravity)?;
        self.manoeuvre.validate()?;
        self.exact.validate()?;
        self.rapier.validate()?;
        self.optimize.validate()?;
        Ok(())
    }

    /// Warnings about a problem that loads but sits outside the paper's assumptions (§3).
    pub fn warnings(&self) -> Vec<String> {
        let mut out = Vec::new();
        if !self.cat.is_long_enough() {
            out.push(format!(
                "cat.length = {} < √3 · cat.radius = {:.4}: the paper's stability argument (§3) needs L ≥ √3 R",
                self.cat.length,
                3f64.sqrt() * self.cat.radius
            ));
        }
        if self.manoeuvre.theta_deg < 90.0 {
            out.push(format!(
                "manoeuvre.theta_deg = {} < 90: outside the paper's stability range π/2 ≤ θ ≤ π (§3, printed as \"π ≤ θ ≤ π/2\")",
                self.manoeuvre.theta_deg
            ));
        }
        out
    }
}

fn one_line(s: &str) -> String {
    s.split_whitespace().collect::<Vec<_>>().join(" ")
}
