//! The flip as a picture: the two cylinders in 3D, orthographic projection, as an animated GIF
//! and as a PNG filmstrip.
//!
//! The camera looks at the centre of mass from the cat's left (`−x`), a little above (`+y`, drawn
//! upwards) and ahead (`+z`), so that the head points right and the end faces are ellipses. Each
//! half is drawn as its silhouette (the convex hull of its two projected end circles, filled), its
//! axis, the end circles and generator lines facing the viewer, and, on its belly (local `+y`,
//! the inside of the bend), a red stripe and two legs; A carries the head (ears on its back), B
//! the tail. The head's disc has 1.5 times A's radius, but no more than 15 % of A's length unless
//! that is below A's radius: the paper's slender cat keeps its head, a thick short half (a real
//! cat's front, radius 0.0447 m on 0.2048 m) does not carry a head two thirds its length. Hidden
//! lines are left out; the halves are painted far to near. One scale fits every frame, so sizes
//! compare across frames.

use std::path::{Path, PathBuf};

use nalgebra::Vector3;
use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

use super::gif::RgbFrames;
use super::pose::{cat_poses_spinning, tree_poses, BodyPose, CatPose};
use super::raster::Raster;
use super::style::{bold, create_dir, ensure_fonts, failed, png_written, save_failed, text, GUIDE};
use super::PlotError;
use crate::engines::models::TwoMotorCat;
use crate::engines::shape::ShapeTrajectory;
use crate::model::cat::Appendages;
use crate::model::legs::{legs, Half, Leg, PAW_RADIUS};
use crate::model::tree::Tree;
use crate::problem::Problem;
use crate::schedule::{Phase, Trajectory};

/// Frames in the PNG filmstrip written beside the GIF.
pub const FILMSTRIP_PANELS: usize = 6;
/// GIF size, pixels.
const GIF_SIZE: (u32, u32) = (600, 600);
/// Size of one filmstrip panel, pixels; a title row sits above the panels.
const PANEL_SIZE: (u32, u32) = (340, 380);
const STRIP_TITLE: u32 = 40;
/// Length of one loop of the GIF, s (the manoeuvre in slow motion).
const LOOP_SECONDS: f64 = 6.0;
const CIRCLE_SIDES: usize = 28;
const GENERATORS: usize = 8;

const A_FILL: RGBColor = RGBColor(253, 208, 162);
const A_EDGE: RGBColor = RGBColor(200, 85, 0);
const B_FILL: RGBColor = RGBColor(189, 215, 238);
const B_EDGE: RGBColor = RGBColor(33, 102, 172);
const BELLY: RGBColor = RGBColor(215, 25, 60);
const JOINT: RGBColor = RGBColor(60, 60, 60);

/// Writes the flip as an animated GIF at `path` (`frames` instants evenly spaced over the
/// manoeuvre, 600 × 600, looping) and a PNG filmstrip of [`FILMSTRIP_PANELS`] instants beside
/// it (`<stem>_filmstrip.png`); returns both paths. Both are titled with the problem's name and
/// `name`, the name of `schedule` (the report's, e.g. `exact-refined-calibrated`: a schedule's
/// profile name does not say which circulation it carries).
pub fn flip_animation(
    path: &Path,
    problem: &Problem,
    name: &str,
    schedule: &impl Trajectory,
    frames: usize,
) -> Result<Vec<PathBuf>, PlotError> {
    let bad = |reason: String| PlotError::BadArgument { path: path.to_path_buf(), reason };
    if frames < 2 {
        return Err(bad(format!("an animation needs at least 2 frames, {frames} asked")));
    }
    let total = schedule.total_duration();
    if !(total.is_finite() && total > 0.0) {
        return Err(bad(format!("the schedule lasts {total} s; it must last a positive, finite time")));
    }
    let cat = model_of(problem, path)?;
    let scene = Scene::new(problem, &appendages_of(problem, path)?, name, schedule);
    ensure_fonts()?;
    if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
        create_dir(dir)?;
    }
    let spin = problem.drop.spin();
    let poses = cat_poses_spinning(&cat, &spin, schedule, &spaced(total, frames));
    let extent = poses.iter().map(|p| scene.marks(p)).fold(Extent::EMPTY, |e, m| e.with(&m));

    let delay_ms = (LOOP_SECONDS * 1000.0 / frames as f64).clamp(40.0, 200.0).round() as u32;
    // Frames are drawn in parallel, each into its own buffer, and encoded with one palette.
    let (w, h) = GIF_SIZE;
    let draw = |k: usize| -> Result<Vec<u8>, String> {
        let mut rgb = vec![0u8; 3 * w as usize * h as usize];
        {
            let root = Raster::new(BitMapBackend::with_buffer(&mut rgb, GIF_SIZE)).into_drawing_area();
            scene.draw(&root, &poses[k], &extent, false).and_then(|()| root.present().map_err(failed))?;
        }
        Ok(rgb)
    };
    RgbFrames::new(GIF_SIZE, poses.len(), draw).and_then(|f| f.write(path, delay_ms)).map_err(write_error(path))?;

    let stem = path.file_stem().map_or_else(|| "flip".into(), |s| s.to_string_lossy().into_owned());
    let strip = path.with_file_name(format!("{stem}_filmstrip.png"));
    let panels = cat_poses_spinning(&cat, &spin, schedule, &spaced(total, FILMSTRIP_PANELS));
    let caption = format!("the flip at {} instants", panels.len());
    write_strip(&scene, &strip, &panels, &extent, &caption)?;
    Ok(vec![path.to_path_buf(), strip])
}

/// Writes only the PNG filmstrip of [`flip_animation`] at `path`: [`FILMSTRIP_PANELS`] instants
/// of the flip of `schedule` on the problem's cat (its model, joint and release), one scale for
/// every panel.
pub fn flip_filmstrip(
    path: &Path,
    problem: &Problem,
    name: &str,
    schedule: &impl Trajectory,
) -> Result<PathBuf, PlotError> {
    let total = schedule.total_duration();
    if !(total.is_finite() && total > 0.0) {
        let reason = format!("the schedule lasts {total} s; it must last a positive, finite time");
        return Err(PlotError::BadArgument { path: path.to_path_buf(), reason });
    }
    let cat = model_of(problem, path)?;
    let poses = cat_poses_spinning(&cat, &problem.drop.spin(), schedule, &spaced(total, FILMSTRIP_PANELS));
    let caption = format!("the flip at {} instants", poses.len());
    pose_filmstrip(path, problem, name, schedule, &poses, &caption)
}

/// The PNG filmstrip of a model beyond two motors ([`FILMSTRIP_PANELS`] instants, released
/// without spin): the tree of bodies `tree` (the halves, then the problem's `[cat.tail]` and
/// `[cat.legs]`, [`crate::model::Cat::tree_with`]) along the shape trajectory `shape`, placed by the general core on the tree (`tree_poses`); `timeline` gives
/// the timeline's pieces (the same trajectory as a [`Trajectory`]).
pub fn tree_filmstrip(
    path: &Path,
    problem: &Problem,
    name: &str,
    tree: &Tree,
    shape: &impl ShapeTrajectory,
    timeline: &impl Trajectory,
) -> Result<PathBuf, PlotError> {
    let total = timeline.total_duration();
    if !(total.is_finite() && total > 0.0) {
        let reason = format!("the schedule lasts {total} s; it must last a positive, finite time");
        return Err(PlotError::BadArgument { path: path.to_path_buf(), reason });
    }
    let poses = tree_poses(tree, &appendages_of(problem, path)?, shape, &spaced(total, FILMSTRIP_PANELS));
    let caption = format!("the flip at {} instants", poses.len());
    pose_filmstrip(path, problem, name, timeline, &poses, &caption)
}

/// The problem's tail and legs as the model's, or why a picture of them cannot be drawn.
fn appendages_of(problem: &Problem, path: &Path) -> Result<Appendages, PlotError> {
    problem.cat.appendages().map_err(|e| PlotError::BadArgument { path: path.to_path_buf(), reason: e.to_string() })
}

/// The problem's cat as the engines run it, or why a picture of it cannot be drawn.
pub(super) fn model_of(problem: &Problem, path: &Path) -> Result<TwoMotorCat, PlotError> {
    TwoMotorCat::new(problem.cat.model())
        .map_err(|e| PlotError::BadArgument { path: path.to_path_buf(), reason: e.to_string() })
}

/// Writes a PNG filmstrip of `poses` (one panel each, e.g. from a rapier run rather than the
/// exact engine) at `path`, titled with the problem's name, `name` and `caption`; one scale fits
/// every panel. The problem gives the cat's sizes and `schedule` the timeline's phases.
pub fn pose_filmstrip(
    path: &Path,
    problem: &Problem,
    name: &str,
    schedule: &impl Trajectory,
    poses: &[CatPose],
    caption: &str,
) -> Result<PathBuf, PlotError> {
    if poses.is_empty() {
        return Err(PlotError::BadArgument { path: path.to_path_buf(), reason: "a filmstrip needs a pose".into() });
    }
    let scene = Scene::new(problem, &appendages_of(problem, path)?, name, schedule);
    ensure_fonts()?;
    if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
        create_dir(dir)?;
    }
    let extent = poses.iter().map(|p| scene.marks(p)).fold(Extent::EMPTY, |e, m| e.with(&m));
    write_strip(&scene, path, poses, &extent, caption)?;
    Ok(path.to_path_buf())
}

fn write_strip(
    scene: &Scene,
    strip: &Path,
    panels: &[CatPose],
    extent: &Extent,
    caption: &str,
) -> Result<(), PlotError> {
    let size = (PANEL_SIZE.0 * panels.len() as u32, PANEL_SIZE.1 + STRIP_TITLE);
    {
        let root = Raster::new(BitMapBackend::new(strip, size)).into_drawing_area();
        scene
            .draw_filmstrip(&root, panels, extent, caption)
            .and_then(|()| root.present().map_err(save_failed))
            .map_err(write_error(strip))?;
    }
    png_written(strip).map_err(write_error(strip))
}

/// Turns a backend's message into a [`PlotError::Write`] naming `path`.
fn write_error(path: &Path) -> impl Fn(String) -> PlotError + '_ {
    move |message| PlotError::Write { path: path.to_path_buf(), message }
}

/// `n ≥ 2` instants from 0 to `total`, both ends included.
fn spaced(total: f64, n: usize) -> Vec<f64> {
    (0..n).map(|k| total * k as f64 / (n - 1) as f64).collect()
}

/// An orthographic camera: `toward` points from the scene to the viewer.
struct Camera {
    right: Vector3<f64>,
    up: Vector3<f64>,
    toward: Vector3<f64>,
}

impl Camera {
    fn new() -> Self {
        let toward = Vector3::new(-1.0, 0.55, 0.35).normalize();
        let up = (Vector3::y() - toward * toward.y).normalize();
        Self { right: up.cross(&toward), up, toward }
    }
    fn project(&self, p: &Vector3<f64>) -> (f64, f64) {
        (p.dot(&self.right), p.dot(&self.up))
    }
    fn depth(&self, p: &Vector3<f64>) -> f64 {
        p.dot(&self.toward)
    }
    fn faces(&self, normal: &Vector3<f64>) -> bool {
        normal.dot(&self.toward) > 0.0
    }
}

/// Something to paint, in projected world units (m); widths in pixels of a 600-pixel frame.
#[derive(Clone, Debug)]
enum Mark {
    Fill { points: Vec<(f64, f64)>, fill: RGBColor, edge: RGBColor },
    Line { points: Vec<(f64, f64)>, colour: RGBColor, width: f64 },
    Disc { centre: (f64, f64), radius: f64, fill: RGBColor, edge: RGBColor },
}

/// A mark with its painting order: by group depth (far first), then layer.
#[derive(Clone, Debug)]
struct Layered {
    depth: f64,
    layer: u8,
    mark: Mark,
}

/// Layers within one half: hidden legs, silhouette, outline, features, head.
const BEHIND: u8 = 0;
const HULL: u8 = 1;
const OUTLINE: u8 = 2;
const FEATURE: u8 = 3;
const HEAD: u8 = 4;

/// What stays the same from frame to frame.
struct Scene {
    camera: Camera,
    /// Half-length and radius of A and of B, m.
    sizes: [(f64, f64); 2],
    /// The legs of A and of B, each in its half's body frame.
    legs: [[Leg; 2]; 2],
    /// Half-length and radius of the problem's `[cat.tail]`, m, drawn where a pose has one.
    tail: Option<(f64, f64)>,
    /// Half-length and radius of the problem's `[cat.legs]`, the front pair's and the rear
    /// pair's, m: drawn as rods (in place of the drawn legs) where a pose has them.
    leg_rods: Option<[(f64, f64); 2]>,
    title: String,
    /// The timeline's segments: the three phases, or the whole manoeuvre in one.
    segments: Vec<(&'static str, f64)>,
}

/// The projected bounding box of every frame, m.
#[derive(Clone, Copy, Debug)]
struct Extent {
    lo: (f64, f64),
    hi: (f64, f64),
}

impl Extent {
    const EMPTY: Extent = Extent { lo: (f64::INFINITY, f64::INFINITY), hi: (f64::NEG_INFINITY, f64::NEG_INFINITY) };

    fn with(self, marks: &[Layered]) -> Extent {
        let mut e = self;
        let mut add = |(x, y): (f64, f64), r: f64| {
            e.lo = (e.lo.0.min(x - r), e.lo.1.min(y - r));
            e.hi = (e.hi.0.max(x + r), e.hi.1.max(y + r));
        };
        for m in marks {
            match &m.mark {
                Mark::Fill { points, .. } | Mark::Line { points, .. } => points.iter().for_each(|&p| add(p, 0.0)),
                Mark::Disc { centre, radius, .. } => add(*centre, *radius),
            }
        }
        e
    }
}

/// Maps projected world coordinates into a pixel rectangle, one scale for both axes.
struct Fit {
    scale: f64,
    centre: (f64, f64),
    origin: (f64, f64),
}

impl Fit {
    fn new(extent: &Extent, (x0, y0, x1, y1): (f64, f64, f64, f64)) -> Fit {
        let w = (extent.hi.0 - extent.lo.0).max(1e-9);
        let h = (extent.hi.1 - extent.lo.1).max(1e-9);
        let scale = 0.94 * ((x1 - x0) / w).min((y1 - y0) / h);
        let centre = (0.5 * (extent.lo.0 + extent.hi.0), 0.5 * (extent.lo.1 + extent.hi.1));
        Fit { scale, centre, origin: (0.5 * (x0 + x1), 0.5 * (y0 + y1)) }
    }
    fn px(&self, (x, y): (f64, f64)) -> (i32, i32) {
        let px = self.origin.0 + (x - self.centre.0) * self.scale;
        let py = self.origin.1 - (y - self.centre.1) * self.scale;
        (px.round() as i32, py.round() as i32)
    }
}

/// Where things go in one frame, from the bottom up: two caption lines, the phase bar, the
/// ground line, and the cat above it; pixels.
struct Layout {
    /// Pixels per pixel of a 600-pixel frame.
    u: f64,
    w: f64,
    /// Caption and small text sizes.
    caption: f64,
    small: f64,
    /// Centres of the two caption lines.
    captions: [f64; 2],
    /// Top and height of the phase bar.
    bar: (f64, f64),
    ground: f64,
    /// The cat's rectangle `(x0, y0, x1, y1)`.
    cat: (f64, f64, f64, f64),
}

impl Layout {
    fn new(w: f64, h: f64, compact: bool) -> Layout {
        let u = w.min(h) / 600.0;
        let caption = (20.0 * u).max(13.0);
        let small = (13.0 * u).max(11.0);
        let line = 1.35 * caption;
        let second = h - 0.85 * line;
        let first = second - line;
        let bar_h = (18.0 * u).max(small + 3.0);
        let bar_y = first - 0.75 * line - bar_h;
        let ground = bar_y - (14.0 * u).max(8.0);
        let top = if compact { 8.0 * u } else { 78.0 * u };
        Layout {
            u,
            w,
            caption,
            small,
            captions: [first, second],
            bar: (bar_y, bar_h),
            ground,
            cat: (12.0 * u, top, w - 12.0 * u, ground - 8.0 * u),
        }
    }
}

/// The unit in which the head and ears are drawn on a half of half-length `h` and radius `r`:
/// the head's disc has radius `1.5 u` (module docs).
fn head_unit(h: f64, r: f64) -> f64 {
    r.min(0.2 * h).max(r / 1.5)
}

/// The timeline's segments of a trajectory: its three phases, or one for the whole manoeuvre.
fn segments(t: &impl Trajectory) -> Vec<(&'static str, f64)> {
    let d = t.piece_durations();
    if d.len() == Phase::ALL.len() {
        Phase::ALL.iter().zip(d).map(|(p, di)| (p.name(), di)).collect()
    } else {
        vec![("whole manoeuvre", t.total_duration())]
    }
}

impl Scene {
    /// The scene of `problem`'s cat with its `appendages` ([`crate::problem::cat::CatSection::appendages`]).
    fn new(problem: &Problem, appendages: &Appendages, name: &str, schedule: &impl Trajectory) -> Scene {
        let (front, rear) = (problem.cat.front(), problem.cat.rear());
        Scene {
            camera: Camera::new(),
            sizes: [(0.5 * front.length, front.radius), (0.5 * rear.length, rear.radius)],
            legs: [legs(&front, Half::A), legs(&rear, Half::B)],
            tail: appendages.tail.map(|(t, _)| (0.5 * t.length, t.radius)),
            leg_rods: appendages.legs.map(|pairs| pairs.map(|p| (0.5 * p.length, p.radius))),
            title: format!("catflip: problem \u{201c}{}\u{201d}, {name}", problem.name),
            segments: segments(schedule),
        }
    }

    /// Every mark of one pose, in painting order.
    fn marks(&self, pose: &CatPose) -> Vec<Layered> {
        let cam = &self.camera;
        let [(h, r), (h_b, _)] = self.sizes;
        let mut out = Vec::new();
        match (self.leg_rods, &pose.legs) {
            // The model's legs (rods of their own): drawn as the halves are, in their halves' colours.
            (Some([front_size, hind_size]), Some([front, hind])) => {
                self.cylinder(&pose.a, self.sizes[0], A_FILL, A_EDGE, Some(&[]), &mut out);
                self.cylinder(&pose.b, self.sizes[1], B_FILL, B_EDGE, Some(&[]), &mut out);
                self.cylinder(front, front_size, A_FILL, A_EDGE, None, &mut out);
                self.cylinder(hind, hind_size, B_FILL, B_EDGE, None, &mut out);
            }
            _ => {
                self.cylinder(&pose.a, self.sizes[0], A_FILL, A_EDGE, Some(&self.legs[0]), &mut out);
                self.cylinder(&pose.b, self.sizes[1], B_FILL, B_EDGE, Some(&self.legs[1]), &mut out);
            }
        }
        let (da, db) = (cam.depth(&pose.a.centre), cam.depth(&pose.b.centre));
        // The head on A's front end, ears on its back (−y, away from the belly), drawn in units
        // of `u`: the half's radius, or less on a thick short half (module docs).
        let u = head_unit(h, r);
        let head = Vector3::new(0.0, 0.0, h + 1.3 * u);
        for s in [-1.0, 1.0] {
            let ear = [(0.35, -1.0), (1.45, -0.3), (1.55, -2.9)]
                .map(|(x, y)| pose.a.point(head + Vector3::new(s * x * u, y * u, 0.0)));
            let points = ear.iter().map(|p| cam.project(p)).collect();
            out.push(Layered { depth: da, layer: HEAD, mark: Mark::Fill { points, fill: A_EDGE, edge: A_EDGE } });
        }
        let centre = cam.project(&pose.a.point(head));
        out.push(Layered {
            depth: da,
            layer: HEAD,
            mark: Mark::Disc { centre, radius: 1.5 * u, fill: A_FILL, edge: A_EDGE },
        });
        match (self.tail, &pose.tail) {
            // A real tail (a rod of the model): drawn as the halves are, without legs.
            (Some(size), Some(tail)) => self.cylinder(tail, size, B_FILL, B_EDGE, None, &mut out),
            // Otherwise a drawn one from B's rear end, curling up to its back.
            _ => {
                let tail = (0..=12).map(|k| {
                    let s = 0.7 * h_b * k as f64 / 12.0;
                    cam.project(&pose.b.point(Vector3::new(0.0, -1.2 * s * s / h_b, -h_b - s)))
                });
                out.push(Layered {
                    depth: db,
                    layer: FEATURE,
                    mark: Mark::Line { points: tail.collect(), colour: B_EDGE, width: 4.0 },
                });
            }
        }
        // The joint, painted with the nearer half.
        let joint = cam.project(&pose.a.point(Vector3::new(0.0, 0.0, -h)));
        out.push(Layered {
            depth: da.max(db),
            layer: HEAD,
            mark: Mark::Disc { centre: joint, radius: 0.7 * r, fill: JOINT, edge: JOINT },
        });
        out.sort_by(|x, y| x.depth.total_cmp(&y.depth).then(x.layer.cmp(&y.layer)));
        out
    }

    /// One body: silhouette, axis, visible outline, and for a half (`half`: its drawn legs) the
    /// belly stripe and those legs (none for a half whose legs are rods of their own); a rod of
    /// the model (a tail, a pair of legs: `half` none) has neither.
    fn cylinder(
        &self,
        body: &BodyPose,
        (h, r): (f64, f64),
        fill: RGBColor,
        edge: RGBColor,
        half: Option<&[Leg]>,
        out: &mut Vec<Layered>,
    ) {
        let legs = half.unwrap_or_default();
        let cam = &self.camera;
        let depth = cam.depth(&body.centre);
        let push = |out: &mut Vec<Layered>, layer, mark| out.push(Layered { depth, layer, mark });
        let line = |a: Vector3<f64>, b: Vector3<f64>| vec![cam.project(&body.point(a)), cam.project(&body.point(b))];
        let radial = |k: usize, of: usize| {
            let (s, c) = (std::f64::consts::TAU * k as f64 / of as f64).sin_cos();
            Vector3::new(c, s, 0.0)
        };
        let ring: Vec<Vector3<f64>> = (0..CIRCLE_SIDES).map(|k| r * radial(k, CIRCLE_SIDES)).collect();
        let rim: Vec<(f64, f64)> = [-h, h]
            .iter()
            .flat_map(|&z| ring.iter().map(move |p| p + Vector3::new(0.0, 0.0, z)))
            .map(|p| cam.project(&body.point(p)))
            .collect();
        push(out, HULL, Mark::Fill { points: convex_hull(rim), fill, edge });
        push(
            out,
            OUTLINE,
            Mark::Line {
                points: line(Vector3::new(0.0, 0.0, -h), Vector3::new(0.0, 0.0, h)),
                colour: edge,
                width: 1.0,
            },
        );
        for k in 0..GENERATORS {
            let n = radial(k, GENERATORS);
            if cam.faces(&(body.rotation * n)) {
                push(
                    out,
                    OUTLINE,
                    Mark::Line {
                        points: line(r * n - h * Vector3::z(), r * n + h * Vector3::z()),
                        colour: edge,
                        width: 1.0,
                    },
                );
            }
        }
        for z in [-h, h] {
            let cap_faces = cam.faces(&(body.rotation * Vector3::z() * z.signum()));
            for k in 0..CIRCLE_SIDES {
                let mid = radial(2 * k + 1, 2 * CIRCLE_SIDES);
                if cap_faces || cam.faces(&(body.rotation * mid)) {
                    let at = Vector3::new(0.0, 0.0, z);
                    let points = line(ring[k] + at, ring[(k + 1) % CIRCLE_SIDES] + at);
                    push(out, OUTLINE, Mark::Line { points, colour: edge, width: 1.5 });
                }
            }
        }
        let belly = body.rotation * Vector3::y();
        if cam.faces(&belly) && half.is_some() {
            push(
                out,
                FEATURE,
                Mark::Line {
                    points: line(Vector3::new(0.0, r, -h), Vector3::new(0.0, r, h)),
                    colour: BELLY,
                    width: 5.0,
                },
            );
        }
        let layer = if cam.faces(&belly) { FEATURE } else { BEHIND };
        for leg in legs {
            push(out, layer, Mark::Line { points: line(leg.hip, leg.paw), colour: edge, width: 5.0 });
            let centre = cam.project(&body.point(leg.paw));
            push(out, layer, Mark::Disc { centre, radius: PAW_RADIUS * r, fill: edge, edge });
        }
    }

    /// One frame in `area`; `compact` leaves out the title and key (filmstrip panels).
    fn draw<DB: DrawingBackend>(
        &self,
        area: &DrawingArea<DB, Shift>,
        pose: &CatPose,
        extent: &Extent,
        compact: bool,
    ) -> Result<(), String> {
        area.fill(&WHITE).map_err(failed)?;
        let (w, h) = area.dim_in_pixel();
        let lay = Layout::new(f64::from(w), f64::from(h), compact);
        if !compact {
            self.header(area, &lay)?;
        }
        // The ground the cat falls towards: world −y, drawn downwards.
        let u = lay.u;
        let ground = lay.ground as i32;
        let line = vec![((16.0 * u) as i32, ground), ((lay.w - 16.0 * u) as i32, ground)];
        area.draw(&PathElement::new(line, GUIDE.stroke_width(1))).map_err(failed)?;
        let label = text(lay.small).color(&GUIDE).pos(Pos::new(HPos::Right, VPos::Bottom));
        area.draw(&Text::new("down ↓", ((lay.w - 18.0 * u) as i32, ground - 3), label)).map_err(failed)?;

        let fit = Fit::new(extent, lay.cat);
        let stroke = |width: f64| (width * u).round().max(1.0) as u32;
        let px = |p: &[(f64, f64)]| p.iter().map(|&q| fit.px(q)).collect::<Vec<_>>();
        for item in self.marks(pose) {
            match item.mark {
                Mark::Fill { points, fill, edge } => {
                    let mut outline = px(&points);
                    area.draw(&Polygon::new(outline.clone(), fill.filled())).map_err(failed)?;
                    outline.extend(outline.first().copied());
                    area.draw(&PathElement::new(outline, edge.stroke_width(stroke(2.0)))).map_err(failed)?;
                }
                Mark::Line { points, colour, width } => {
                    area.draw(&PathElement::new(px(&points), colour.stroke_width(stroke(width)))).map_err(failed)?;
                }
                Mark::Disc { centre, radius, fill, edge } => {
                    let r = ((radius * fit.scale).round() as i32).max(2);
                    area.draw(&Circle::new(fit.px(centre), r, fill.filled())).map_err(failed)?;
                    area.draw(&Circle::new(fit.px(centre), r, edge.stroke_width(stroke(2.0)))).map_err(failed)?;
                }
            }
        }
        self.timeline(area, pose, &lay)?;
        let captions = [
            format!("t = {:.3} s   phase: {}", pose.time, pose.phase.map_or("whole manoeuvre", |p| p.name())),
            format!("twist {:+.1}°   swing {:.1}°", pose.twist.to_degrees(), pose.swing.to_degrees()),
        ];
        for (line, y) in captions.into_iter().zip(lay.captions) {
            let style = text(lay.caption).pos(Pos::new(HPos::Center, VPos::Center));
            area.draw(&Text::new(line, ((lay.w / 2.0) as i32, y as i32), style)).map_err(failed)?;
        }
        Ok(())
    }

    /// Title and colour key.
    fn header<DB: DrawingBackend>(&self, area: &DrawingArea<DB, Shift>, lay: &Layout) -> Result<(), String> {
        let u = lay.u;
        // A long schedule name shrinks the title to the frame's width rather than cropping it.
        let size = lay.caption * 1.1;
        let width = f64::from(area.estimate_text_size(&self.title, &bold(size)).map_err(failed)?.0);
        let room = lay.w - 24.0 * u;
        let title = bold(if width > room { size * room / width } else { size }).pos(Pos::new(HPos::Center, VPos::Top));
        area.draw(&Text::new(self.title.clone(), ((lay.w / 2.0) as i32, (12.0 * u) as i32), title)).map_err(failed)?;
        let key = [("A: front half", A_EDGE), ("B: rear half", B_EDGE), ("red stripe, legs: belly", BELLY)];
        let mut x = 20.0 * u;
        for (label, c) in key {
            let style = text(lay.small * 1.1).color(&c);
            area.draw(&Text::new(label, (x as i32, (48.0 * u) as i32), style.clone())).map_err(failed)?;
            x += f64::from(area.estimate_text_size(label, &style).map_err(failed)?.0) + 24.0 * u;
        }
        Ok(())
    }

    /// The three phases as a bar, with the current instant marked.
    fn timeline<DB: DrawingBackend>(
        &self,
        area: &DrawingArea<DB, Shift>,
        pose: &CatPose,
        lay: &Layout,
    ) -> Result<(), String> {
        let (u, y, bar) = (lay.u, lay.bar.0, lay.bar.1);
        let (x0, x1) = (24.0 * u, lay.w - 24.0 * u);
        let total: f64 = self.segments.iter().map(|s| s.1).sum();
        let at = |t: f64| x0 + (x1 - x0) * t / total;
        let shades = [RGBColor(228, 228, 228), RGBColor(205, 205, 205), RGBColor(228, 228, 228)];
        let mut start = 0.0;
        for (&(label, duration), shade) in self.segments.iter().zip(shades) {
            let end = start + duration;
            let rect = [(at(start) as i32, y as i32), (at(end) as i32, (y + bar) as i32)];
            area.draw(&Rectangle::new(rect, shade.filled())).map_err(failed)?;
            let style = text(lay.small).color(&JOINT).pos(Pos::new(HPos::Center, VPos::Center));
            let centre = (at(0.5 * (start + end)) as i32, (y + 0.5 * bar) as i32);
            area.draw(&Text::new(label, centre, style)).map_err(failed)?;
            start = end;
        }
        let x = at(pose.time) as i32;
        let marker = vec![(x, (y - 4.0 * u) as i32), (x, (y + bar + 4.0 * u) as i32)];
        area.draw(&PathElement::new(marker, BELLY.stroke_width((3.0 * u).max(2.0) as u32))).map_err(failed)
    }

    /// The filmstrip: a title row, then one compact frame per pose side by side.
    fn draw_filmstrip<DB: DrawingBackend>(
        &self,
        root: &DrawingArea<DB, Shift>,
        poses: &[CatPose],
        extent: &Extent,
        caption: &str,
    ) -> Result<(), String> {
        root.fill(&WHITE).map_err(failed)?;
        let (head, body) = root.split_vertically(STRIP_TITLE);
        let title = format!("{}: {caption} (A front: orange, B rear: blue, belly: red)", self.title);
        let (w, _) = head.dim_in_pixel();
        // A title wider than the strip (few panels) shrinks to fit rather than being cropped.
        let width = f64::from(head.estimate_text_size(&title, &bold(20.0)).map_err(failed)?.0);
        let room = f64::from(w) - 16.0;
        let size = if width > room { 20.0 * room / width } else { 20.0 };
        head.draw(&Text::new(title, (w as i32 / 2, 20), bold(size).pos(Pos::new(HPos::Center, VPos::Center))))
            .map_err(failed)?;
        for (panel, pose) in body.split_evenly((1, poses.len().max(1))).iter().zip(poses) {
            self.draw(panel, pose, extent, true)?;
            let (pw, ph) = panel.dim_in_pixel();
            let frame = vec![(0, 0), (pw as i32 - 1, 0), (pw as i32 - 1, ph as i32 - 1), (0, ph as i32 - 1), (0, 0)];
            panel.draw(&PathElement::new(frame, RGBColor(200, 200, 200).stroke_width(1))).map_err(failed)?;
        }
        Ok(())
    }
}

/// Convex hull of 2D points (Andrew's monotone chain), counter-clockwise.
fn convex_hull(mut points: Vec<(f64, f64)>) -> Vec<(f64, f64)> {
    points.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.total_cmp(&b.1)));
    if points.len() < 3 {
        return points;
    }
    let cross = |o: (f64, f64), a: (f64, f64), b: (f64, f64)| (a.0 - o.0) * (b.1 - o.1) - (a.1 - o.1) * (b.0 - o.0);
    let mut hull: Vec<(f64, f64)> = Vec::with_capacity(points.len() + 1);
    for pass in [points.clone(), points.into_iter().rev().collect()] {
        let floor = hull.len();
        for p in pass {
            while hull.len() >= floor + 2 && cross(hull[hull.len() - 2], hull[hull.len() - 1], p) <= 0.0 {
                hull.pop();
            }
            hull.push(p);
        }
        hull.pop();
    }
    hull
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::schedule::Schedule;

    #[test]
    fn hull_of_a_square_with_an_inner_point() {
        let pts = vec![(0.0, 0.0), (1.0, 0.0), (0.5, 0.5), (1.0, 1.0), (0.0, 1.0)];
        assert_eq!(convex_hull(pts), vec![(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)]);
    }

    #[test]
    fn the_title_names_the_schedule_shown() {
        // The report animates `exact-refined-all-phases` with the calibrated circulation: its
        // profile is still named `exact-refined-all-phases`, the schedule is not.
        let problem = Problem::default();
        let schedule = Schedule::new(&problem, 4.0);
        let scene = Scene::new(&problem, &Appendages::default(), "exact-refined-all-phases-calibrated", &schedule);
        assert_eq!(scene.title, "catflip: problem \u{201c}paper\u{201d}, exact-refined-all-phases-calibrated");
        assert!(!scene.title.contains(schedule.profile.name()) || schedule.profile.name().is_empty());
    }

    #[test]
    fn head_is_the_paper_cats_and_bounded_on_a_thick_half() {
        // The paper's halves (1 m by 0.1 m): the unit is the radius itself, as drawn before the bound.
        assert_eq!(head_unit(0.5, 0.1).to_bits(), 0.1f64.to_bits());
        // The real cat's front (0.2048 m by 0.0447 m): 15 % of its length is below its radius,
        // so the head's radius is the half's own.
        assert!((1.5 * head_unit(0.1024, 0.0447) - 0.0447).abs() < 1e-15);
        // Between the two (0.5 m by 0.06 m): 15 % of the length, 0.075 m.
        assert!((1.5 * head_unit(0.25, 0.06) - 0.075).abs() < 1e-15);
    }

    #[test]
    fn camera_is_right_handed_with_head_to_the_right() {
        let c = Camera::new();
        assert!((c.right.cross(&c.up) - c.toward).norm() < 1e-12);
        assert!(c.project(&Vector3::z()).0 > 0.0, "the head (+z) should point right");
        assert!(c.project(&Vector3::y()).1 > 0.0, "world +y should be drawn upwards");
    }
}
