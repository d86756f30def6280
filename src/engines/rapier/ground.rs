//! Landing (issue 21 §4): the ground a tracked run falls onto, and what touches it first.
//!
//! Only a scene that asks for it gets any of this ([`super::track::TrackOptions::landing`]);
//! the verification's scenes stay gravity-free and collider-free.
//!
//! # Scene
//!
//! Gravity `g` along world `−y` (the plots' "down"); the cat is released at rest (its centre of
//! mass at `c₀`) and the ground is the plane `y = c₀·ŷ − h`, `h` the drop height, so that the
//! centre of mass would reach it at the fall time `T = √(2h/g)` (DESIGN.md §1). Uniform gravity
//! exerts no torque about the centre of mass, so the rotation is that of the falling frame.
//! Colliders, all of zero density (the bodies' mass properties stay the cylinders'):
//! - each half, a cylinder of its length and radius along its spine;
//! - each leg ([`crate::model::legs`]), a capsule from hip to paw of radius `0.45 r` (the drawn
//!   paw's);
//! - the ground, a half-space **sensor** on a fixed body. A sensor reports overlaps and applies
//!   no force: the run records the first touch and goes on to the end of the schedule, so the
//!   landing error keeps its meaning (attitude at `T`) and no impact dynamics are claimed.
//!
//! The cat's colliders interact with the ground only (collision groups), never with each other.
//!
//! # Touch-down
//!
//! After each step the ground's overlaps are read from rapier's narrow phase. At the first step
//! with one, the part that touches is the overlapping one whose lowest point (its support point
//! along `−ŷ`, computed in closed form: a cylinder's `c + h sgn(d·e) e + r d⊥/|d⊥|`, a capsule's
//! lower end less its radius) lies deepest; the touch-down time is interpolated linearly between
//! that point's heights before and after the step; the impact speed is that point's downward
//! speed (the body's velocity there). **Feet down**: each half's feet direction (its `+y`, the
//! legs' mean) makes an angle with `−ŷ`; the cat lands on its feet when both angles are within
//! the tolerance.

use std::f64::consts::FRAC_PI_2;

use nalgebra::{UnitQuaternion, Vector3};
use rapier3d_f64::geometry::{ColliderBuilder, ColliderHandle, Group, InteractionGroups, InteractionTestMode};
use rapier3d_f64::math::Vector;
use rapier3d_f64::na::Unit;
use rapier3d_f64::prelude::RigidBodyBuilder;
use serde::Serialize;

use super::bodies::{BodyState, Snapshot};
use super::scene::{from_na, CatScene};
use super::RapierError;
use crate::model::legs::{feet_direction, legs, Half, PAW_RADIUS};
use crate::model::Cylinder;

/// The ground below the release.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Landing {
    /// Drop height: the centre of mass at release is this far above the ground, m.
    pub height: f64,
    /// Gravitational acceleration, m/s².
    pub gravity: f64,
    /// The cat lands on its feet when each half's feet point within this angle of straight
    /// down, degrees.
    pub feet_down_deg: f64,
}

/// A part of the cat that can touch the ground.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Part {
    /// The front half's body (A's cylinder).
    FrontBody,
    /// The rear half's body (B's cylinder).
    RearBody,
    /// One of A's legs.
    FrontPaw,
    /// One of B's legs.
    HindPaw,
}

impl Part {
    /// In words.
    pub fn describe(self) -> &'static str {
        match self {
            Part::FrontBody => "the front half's body",
            Part::RearBody => "the rear half's body",
            Part::FrontPaw => "a front paw",
            Part::HindPaw => "a hind paw",
        }
    }
}

/// How the fall ended.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Touchdown {
    /// Touch-down time, s.
    pub time: f64,
    /// The part that touched first.
    pub part: Part,
    /// Downward speed of its lowest point at touch-down, m/s.
    pub impact_speed: f64,
    /// Angle between each half's feet direction and straight down, A then B, degrees.
    pub feet_down_deg: [f64; 2],
    /// Both within the tolerance.
    pub on_its_feet: bool,
    /// A's world orientation at touch-down, serialised as `[w, x, y, z]`.
    #[serde(serialize_with = "super::run::quat_wxyz")]
    pub orientation: UnitQuaternion<f64>,
}

/// One collider of the cat: its part, its body (0 = A, 2 = B) and its shape in that body's frame.
#[derive(Clone, Copy, Debug)]
enum Shape {
    /// Half length, radius.
    Cylinder(f64, f64),
    /// End points, radius.
    Capsule(Vector3<f64>, Vector3<f64>, f64),
}

/// The ground and the cat's colliders in a scene.
pub(super) struct Ground {
    ground: ColliderHandle,
    y: f64,
    parts: Vec<(ColliderHandle, Part, usize, Shape)>,
    feet_down_deg: f64,
}

const DOWN: Vector3<f64> = Vector3::new(0.0, -1.0, 0.0);

impl Ground {
    /// Adds gravity, the ground and the cat's colliders to `scene` (at its current poses).
    pub fn add(scene: &mut CatScene, cat: &Cylinder, landing: &Landing) -> Result<Ground, RapierError> {
        let snap = scene.snapshot()?;
        let masses = *scene.masses();
        let centre = (0..3).map(|i| masses.mass[i] * snap.positions[i]).sum::<Vector3<f64>>() / masses.total();
        let y = centre.y - landing.height;
        let world = &mut scene.world;
        world.gravity = from_na(&(landing.gravity * DOWN));
        let cat_groups = InteractionGroups::new(Group::GROUP_1, Group::GROUP_2, InteractionTestMode::And);
        let ground_groups = InteractionGroups::new(Group::GROUP_2, Group::GROUP_1, InteractionTestMode::And);
        let fixed = world.bodies.insert(RigidBodyBuilder::fixed().translation(Vector::new(0.0, y, 0.0)).build());
        let plane = ColliderBuilder::halfspace(Unit::new_unchecked(Vector::Y))
            .sensor(true)
            .collision_groups(ground_groups)
            .build();
        let ground = world.colliders.insert_with_parent(plane, fixed, &mut world.bodies);
        let (h, r) = (0.5 * cat.length, cat.radius);
        let mut shapes = vec![(Part::FrontBody, 0, Shape::Cylinder(h, r)), (Part::RearBody, 2, Shape::Cylinder(h, r))];
        for (half, part, body) in [(Half::A, Part::FrontPaw, 0), (Half::B, Part::HindPaw, 2)] {
            for leg in legs(cat, half) {
                shapes.push((part, body, Shape::Capsule(leg.hip, leg.paw, PAW_RADIUS * r)));
            }
        }
        let mut parts = Vec::with_capacity(shapes.len());
        for (part, body, shape) in shapes {
            let builder = match shape {
                // rapier's cylinder is along its local y; the spine is z.
                Shape::Cylinder(h, r) => ColliderBuilder::cylinder(h, r).rotation(Vector::new(FRAC_PI_2, 0.0, 0.0)),
                Shape::Capsule(a, b, rho) => ColliderBuilder::capsule_from_endpoints(from_na(&a), from_na(&b), rho),
            };
            let collider = builder.density(0.0).collision_groups(cat_groups).build();
            let handle = world.colliders.insert_with_parent(collider, scene.bodies[body], &mut world.bodies);
            parts.push((handle, part, body, shape));
        }
        Ok(Ground { ground, y, parts, feet_down_deg: landing.feet_down_deg })
    }

    /// The lowest point of a part at `bodies`' poses, world frame.
    fn lowest(&self, bodies: &[BodyState; 3], body: usize, shape: Shape) -> Vector3<f64> {
        let b = &bodies[body];
        match shape {
            Shape::Cylinder(h, r) => {
                let e = b.rotation * Vector3::z();
                let along = DOWN.dot(&e);
                let across = DOWN - along * e;
                let radial = across.try_normalize(1e-12).unwrap_or_else(Vector3::zeros);
                b.position + h * along.signum() * e + r * radial
            }
            Shape::Capsule(a, c, rho) => {
                let (a, c) = (b.position + b.rotation * a, b.position + b.rotation * c);
                (if a.y <= c.y { a } else { c }) + rho * DOWN
            }
        }
    }

    /// The touch-down, if the step from `before` to `after` (ending at `t`, of length `dt`)
    /// made the first overlap with the ground.
    pub fn touchdown(
        &self,
        scene: &CatScene,
        before: &[BodyState; 3],
        after: &Snapshot,
        t: f64,
        dt: f64,
    ) -> Option<Touchdown> {
        let np = &scene.world.narrow_phase;
        let touching: Vec<_> = np.intersection_pairs_with(self.ground).filter(|p| p.2).map(|p| [p.0, p.1]).collect();
        if touching.is_empty() {
            return None;
        }
        let now = after.bodies(scene.masses());
        let (_, part, body, shape) = *self
            .parts
            .iter()
            .filter(|p| touching.iter().any(|pair| pair.contains(&p.0)))
            .min_by(|x, y| self.lowest(&now, x.2, x.3).y.total_cmp(&self.lowest(&now, y.2, y.3).y))?;
        let (y0, point) = (self.lowest(before, body, shape).y, self.lowest(&now, body, shape));
        let fraction = if y0 > point.y { ((y0 - self.y) / (y0 - point.y)).clamp(0.0, 1.0) } else { 1.0 };
        let b = &now[body];
        let speed = b.linvel + b.angvel.cross(&(point - b.position));
        let angle = |r: &UnitQuaternion<f64>| (r * feet_direction()).angle(&DOWN).to_degrees();
        let feet_down_deg = [angle(&after.rotations[0]), angle(&after.rotations[2])];
        Some(Touchdown {
            time: t - dt * (1.0 - fraction),
            part,
            impact_speed: -speed.dot(&Vector3::y()),
            feet_down_deg,
            on_its_feet: feet_down_deg.iter().all(|a| *a <= self.feet_down_deg),
            orientation: after.rotations[0],
        })
    }
}
