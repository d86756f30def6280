//! The plots and the animation of `catflip run`, drawn into the results folder's `plots/`.

use std::path::{Path, PathBuf};

use crate::engines::resolved::Resolved;
use crate::measure::whole::WholeReport;
use crate::problem::ProfileKind;
use crate::report::export::Shown;
use crate::report::plot::PlotError;
use crate::schedule::variant::{Origin, Variant, VariantCirculation, WHOLE};
use crate::schedule::{Schedule, Trajectory};

/// The library profiles shown in the plots beside the optimised ones.
const SHOWN: [ProfileKind; 4] =
    [ProfileKind::PaperCosine, ProfileKind::Cycloidal, ProfileKind::BangBang, ProfileKind::Trapezoid];

/// Magnus steps over the fall behind a flip plot.
const FLIP_STEPS: usize = 768;

/// Frames of the animation.
const FRAMES: usize = 72;

/// The profiles, the torques of the shown schedules and of the optimum, and the flips of the
/// problem's schedule and of the optimum; returns the files written.
pub(super) fn plots(
    r: &Resolved,
    plots: &Path,
    verified: &[Shown],
    whole: &WholeReport,
) -> Result<Vec<PathBuf>, PlotError> {
    let problem = &r.problem;
    let mut written = Vec::new();
    let shown: Vec<(String, Schedule)> = verified
        .iter()
        .filter_map(|v| v.measured.name.variant().map(|x| (x, v)))
        .filter(|(x, _)| x.circulation == VariantCirculation::Problem)
        .filter(|(x, _)| match x.origin {
            Origin::Library(k) => SHOWN.contains(&k),
            _ => true,
        })
        .map(|(x, v)| (x.to_string(), v.measured.trajectory.clone()))
        .collect();
    written.extend(crate::report::plot::profiles_plot(plots, problem, &shown)?);
    let mut curves: Vec<(String, &dyn Trajectory)> =
        shown.iter().map(|(n, s)| (n.clone(), s as &dyn Trajectory)).collect();
    if let Some(spline) = whole.spline() {
        curves.push((WHOLE.to_string(), spline));
    }
    written.extend(crate::report::plot::torques_plot(plots, problem, &curves)?);
    if let Some(spline) = whole.spline() {
        written.extend(crate::report::plot::trajectory_torques_plot(
            plots,
            problem,
            "torques_whole_optimum",
            WHOLE,
            spline,
        )?);
        written.extend(crate::report::plot::flip_plot(&plots.join(WHOLE), problem, WHOLE, spline, FLIP_STEPS)?);
    }
    let own = Variant::new(Origin::Library(problem.manoeuvre.profile)).to_string();
    written.extend(crate::report::plot::flip_plot(plots, problem, &own, &r.schedule, FLIP_STEPS)?);
    Ok(written)
}

/// The animation of the schedule to replay when the whole optimum does not exist: the most
/// refined calibrated schedule, else the problem's (the run animates the optimum beside its
/// verification).
pub(super) fn fallback_animation(r: &Resolved, plots: &Path, verified: &[Shown]) -> Result<Vec<PathBuf>, PlotError> {
    let own = Variant::new(Origin::Library(r.problem.manoeuvre.profile)).to_string();
    let (name, schedule) = verified
        .iter()
        .find(|v| v.measured.name.variant().is_some_and(|x| x.is_calibrated()))
        .map_or((own, &r.schedule), |v| (v.name(), &v.measured.trajectory));
    animation_of(r, plots, &name, schedule)
}

/// The animation of `traj`, named `name`, as `plots/flip.gif` and its filmstrip.
pub(super) fn animation_of(
    r: &Resolved,
    plots: &Path,
    name: &str,
    traj: &impl Trajectory,
) -> Result<Vec<PathBuf>, PlotError> {
    crate::report::plot::flip_animation(&plots.join("flip.gif"), &r.problem, name, traj, FRAMES)
}
