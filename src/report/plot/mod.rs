//! Plots and the animation of the flip (DESIGN.md §7): what a report shows a reader.
//!
//! Every static figure is written twice with the same stem, as PNG (raster, for Markdown
//! viewers) and as SVG (vector, text kept as text), into a folder the caller names:
//!
//! | stem | what is drawn | axes |
//! |---|---|---|
//! | `profiles` | circulation rate `ω(s) = D/T₂ · V(s/T₂)` over the twist phase, one curve per schedule | s (s), rad/s |
//! | `torques_joint1`, `torques_joint2` | motor torques `τ₁`, `τ₂` (Newton–Euler, [`crate::engines::torque`]) over the whole manoeuvre, phases marked | s, N·m |
//! | `flip` | twist (continued) and swing of the front half A ([`crate::engines::exact::history`]), ±180° target dashed | s, degrees |
//! | `error_vs_time` | run time against error, one series per engine, log–log | error, s |
//!
//! [`flip_animation`] draws the cat itself as an animated GIF, and a PNG filmstrip of six
//! instants beside it for viewers that show no GIF.
//!
//! Conventions are the crate's (DESIGN.md §1): world frame = A's body frame at `t = 0`, spine
//! along `+z` towards the head, B relative to A `R_AB(q) = Rx(q1)·Ry(q2)`. The cat bends towards
//! its local `+y` (the inside of the V), so `+y` is its belly: it starts belly up (world `+y` is
//! drawn upwards) and lands belly down after a twist of ±π. Twist is signed, right-handed about
//! `+z`. Angles are shown in degrees, everything else in SI units.
//!
//! Text needs no system font: the embedded DejaVu Sans ([`dejavu`]) is registered with
//! plotters' `ab_glyph` renderer once, under the family name every style here uses.
//! PNGs and GIFs are drawn on a raster backend (`raster.rs`) that replaces plotters' bitmap
//! stroking of thick lines (mitred joins that spike where a dense curve turns back) and its glyph
//! placement (pen truncated, side bearings dropped), so a PNG shows what its SVG twin shows.
//! A legend notes a curve drawn under later ones ("under …", `legend.rs`).
//!
//! ## References
//! - the paper, §4 and §8 (its profile and torque figures);
//! - T. R. Kane and M. P. Scher (1969), fig. 1–3, for the two-cylinder picture of the cat.

mod animation;
mod chart;
mod curves;
mod gif;
mod legend;
mod pose;
mod raster;
mod style;

use std::path::PathBuf;

pub use animation::{flip_animation, flip_filmstrip, pose_filmstrip, tree_filmstrip, FILMSTRIP_PANELS};
pub use chart::{line_plot, Band, LinePlot, RefLine, Scale};
pub use curves::{
    error_vs_time_plot, flip_plot, plot_profiles, profiles_plot, torques_plot, trajectory_torques_plot, TORQUE_SAMPLES,
};
pub use pose::{cat_poses, cat_poses_spinning, BodyPose, CatPose};
pub(crate) use style::{bold, failed, text, write_png_svg, Figure};
pub use style::{PNG_SIZE, SVG_SIZE};

/// Why a figure could not be written.
#[derive(Debug, thiserror::Error)]
pub enum PlotError {
    /// There is nothing to draw: no series, or no finite (for log axes: positive) point.
    #[error("nothing to plot in {path}: {reason}")]
    NoData {
        /// The file that would have been written (without extension for a PNG + SVG pair).
        path: PathBuf,
        /// What is missing.
        reason: String,
    },
    /// An argument cannot be drawn (too few frames, a schedule of zero duration, …).
    #[error("cannot draw {path}: {reason}")]
    BadArgument {
        /// The file that would have been written.
        path: PathBuf,
        /// Which argument and why.
        reason: String,
    },
    /// The output folder could not be created.
    #[error("cannot create the output folder {path}")]
    CreateDir {
        /// The folder.
        path: PathBuf,
        /// What the OS said.
        source: std::io::Error,
    },
    /// Drawing or encoding failed (an I/O error, a font or encoder error).
    #[error("cannot write {path}: {message}")]
    Write {
        /// The file being written.
        path: PathBuf,
        /// The backend's message.
        message: String,
    },
    /// The embedded font was rejected by the font renderer.
    #[error("cannot register the embedded DejaVu Sans font with plotters: {0}")]
    Font(String),
}

impl PlotError {
    /// The same error with its path passed through `at`: a file written in a scratch folder is
    /// named as the user will find it ([`crate::report::results_dir::Staging::shown`]).
    pub fn shown_as(self, at: impl Fn(PathBuf) -> PathBuf) -> PlotError {
        match self {
            PlotError::NoData { path, reason } => PlotError::NoData { path: at(path), reason },
            PlotError::BadArgument { path, reason } => PlotError::BadArgument { path: at(path), reason },
            PlotError::CreateDir { path, source } => PlotError::CreateDir { path: at(path), source },
            PlotError::Write { path, message } => PlotError::Write { path: at(path), message },
            other @ PlotError::Font(_) => other,
        }
    }
}

/// One named curve: `(x, y)` points in the plot's units, drawn in the given order.
#[derive(Clone, Debug, PartialEq)]
pub struct Series {
    /// Legend entry.
    pub name: String,
    /// The points; non-finite ones are skipped (and break the line there).
    pub points: Vec<(f64, f64)>,
    /// Its place in the palette (colour, and dashed on the palette's second pass), so that one
    /// thing keeps one look across plots; none: its position among the series.
    pub slot: Option<usize>,
}

impl Series {
    /// A series from a name and its points.
    pub fn new(name: impl Into<String>, points: Vec<(f64, f64)>) -> Self {
        Self { name: name.into(), points, slot: None }
    }

    /// The series drawn in the palette's place `slot` ([`Series::slot`]).
    pub fn in_slot(self, slot: usize) -> Self {
        Self { slot: Some(slot), ..self }
    }
}

impl From<(String, Vec<(f64, f64)>)> for Series {
    fn from((name, points): (String, Vec<(f64, f64)>)) -> Self {
        Self::new(name, points)
    }
}
