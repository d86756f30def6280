//! A tree of rigid bodies joined by joints, and how its bodies move relative to the base.
//!
//! Body 0 is the base (the cat's front half A); every further body `k` hangs from a parent
//! `p < k` by a [`Link`]: a [`Joint`] whose point sits at `a` in the parent's frame and at `b`
//! in the child's. Everything is expressed in the base's frame, relative to the base (its
//! rotation is the world's business, [`crate::engines::reduction`]):
//!
//! $$ R_k = R_p J(q), \quad w_k = w_p + R_p ω_{rel}, \quad
//!    \dot w_k = \dot w_p + w_p × R_p ω_{rel} + R_p \dot ω_{rel}, $$
//! $$ c_k = c_p + R_p a − R_k b, \quad \dot c_k = \dot c_p + w_p × R_p a − w_k × R_k b, $$
//! $$ \ddot c_k = \ddot c_p + \dot w_p × R_p a + w_p × (w_p × R_p a)
//!    − \dot w_k × R_k b − w_k × (w_k × R_k b), $$
//!
//! with `J, ω_rel, ω̇_rel` the joint's ([`Joint`]), `w` the angular velocity relative to the base
//! and dots the derivatives of base-frame components. Positions are then taken from the centre
//! of mass `c̄ = Σ m_k c_k / Σ m_k`: `r_k = c_k − c̄` ([`Tree::motion`]). SI units.
//!
//! ## References
//! - R. Featherstone, *Rigid Body Dynamics Algorithms* (2008), ch. 4 (kinematic trees).

use std::ops::Range;

use nalgebra::{Matrix3, Vector3};

use crate::model::shape::ShapeState;
use crate::model::{Cylinder, Joint};

/// One rigid body: its mass and its inertia about its centre, in its own frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Body {
    /// Mass, kg.
    pub mass: f64,
    /// Inertia about the centre of mass, own frame, kg·m².
    pub inertia: Matrix3<f64>,
}

impl From<&Cylinder> for Body {
    fn from(c: &Cylinder) -> Body {
        Body { mass: c.mass, inertia: c.inertia() }
    }
}

/// A joint hanging a child body from its parent.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Link {
    /// The parent body's index (below the child's).
    pub parent: usize,
    /// The joint.
    pub joint: Joint,
    /// The joint point in the parent's frame, m.
    pub at_parent: Vector3<f64>,
    /// The joint point in the child's frame, m.
    pub at_child: Vector3<f64>,
}

/// A tree of rigid bodies: the base (body 0) and one [`Link`] per further body.
#[derive(Clone, Debug, PartialEq)]
pub struct Tree {
    bodies: Vec<Body>,
    /// `links[i]` hangs body `i + 1`.
    links: Vec<Link>,
}

/// How body `k` moves relative to the base, in the base's frame, positions from the centre of
/// mass ([`Tree::motion`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BodyMotion {
    /// `R_k`: the body's frame in the base's.
    pub rotation: Matrix3<f64>,
    /// `R_k I_k R_kᵀ`, kg·m².
    pub inertia: Matrix3<f64>,
    /// `r_k`, its centre from the centre of mass, m.
    pub position: Vector3<f64>,
    /// `ṙ_k`, m/s.
    pub velocity: Vector3<f64>,
    /// `r̈_k`, m/s².
    pub acceleration: Vector3<f64>,
    /// `w_k`, its angular velocity relative to the base, rad/s.
    pub rate: Vector3<f64>,
    /// `ẇ_k`, rad/s².
    pub rate_dot: Vector3<f64>,
}

/// How one joint moves, in the base's frame, positions from the centre of mass.
#[derive(Clone, Debug, PartialEq)]
pub struct LinkMotion {
    /// The joint point, m.
    pub point: Vector3<f64>,
    /// The motor axes ([`Joint::motor_axes`]).
    pub axes: Vec<Vector3<f64>>,
}

/// The relative motion of a whole tree at one shape.
#[derive(Clone, Debug, PartialEq)]
pub struct TreeMotion {
    /// One per body, the base first.
    pub bodies: Vec<BodyMotion>,
    /// One per link.
    pub links: Vec<LinkMotion>,
}

impl Tree {
    /// A tree of the base alone.
    pub fn new(base: Body) -> Tree {
        Tree { bodies: vec![base], links: Vec::new() }
    }

    /// Two bodies: `child` hung from the base by `joint` (`link.parent` is taken as 0).
    pub fn two(base: Body, link: Link, child: Body) -> Tree {
        Tree { bodies: vec![base, child], links: vec![Link { parent: 0, ..link }] }
    }

    /// The tree with `body` hung from body `link.parent`; `None` if there is no such body.
    pub fn attach(mut self, link: Link, body: Body) -> Option<Tree> {
        (link.parent < self.bodies.len()).then(|| {
            self.bodies.push(body);
            self.links.push(link);
            self
        })
    }

    /// The bodies, the base first.
    pub fn bodies(&self) -> &[Body] {
        &self.bodies
    }

    /// The links; `links()[i]` hangs body `i + 1`.
    pub fn links(&self) -> &[Link] {
        &self.links
    }

    /// Number of shape coordinates, `Σ dof`.
    pub fn dof(&self) -> usize {
        self.links.iter().map(|l| l.joint.dof()).sum()
    }

    /// Total mass, kg.
    pub fn mass(&self) -> f64 {
        self.bodies.iter().map(|b| b.mass).sum()
    }

    /// The shape coordinates of link `i`.
    pub fn coordinates(&self, i: usize) -> Range<usize> {
        let start: usize = self.links[..i].iter().map(|l| l.joint.dof()).sum();
        start..start + self.links[i].joint.dof()
    }

    /// The bodies of the subtree hanging from link `i`: body `i + 1` and its descendants.
    pub fn subtree(&self, i: usize) -> Vec<bool> {
        let mut inside = vec![false; self.bodies.len()];
        inside[i + 1] = true;
        for (j, l) in self.links.iter().enumerate().skip(i + 1) {
            inside[j + 1] = inside[l.parent];
        }
        inside
    }

    /// Every body's and joint's motion relative to the base at `shape` ([`Tree::dof`]
    /// coordinates), positions from the centre of mass (the module's equations).
    pub fn motion(&self, shape: &ShapeState) -> TreeMotion {
        let base = self.bodies[0];
        let still = BodyMotion {
            rotation: Matrix3::identity(),
            inertia: base.inertia,
            position: Vector3::zeros(),
            velocity: Vector3::zeros(),
            acceleration: Vector3::zeros(),
            rate: Vector3::zeros(),
            rate_dot: Vector3::zeros(),
        };
        let mut bodies = Vec::with_capacity(self.bodies.len());
        bodies.push(still);
        let mut links = Vec::with_capacity(self.links.len());
        for (i, l) in self.links.iter().enumerate() {
            let p = bodies[l.parent];
            let (q, qd, qdd) = shape.slice(self.coordinates(i));
            let rotation = p.rotation * l.joint.rotation(q);
            let w_rel = p.rotation * l.joint.relative_rate(q, qd);
            let rate = p.rate + w_rel;
            let rate_dot = p.rate_dot + p.rate.cross(&w_rel) + p.rotation * l.joint.relative_accel(q, qd, qdd);
            let (a, b) = (p.rotation * l.at_parent, rotation * l.at_child);
            let point = p.position + a;
            let inertia = rotation * self.bodies[i + 1].inertia * rotation.transpose();
            bodies.push(BodyMotion {
                rotation,
                inertia,
                position: point - b,
                velocity: p.velocity + p.rate.cross(&a) - rate.cross(&b),
                acceleration: p.acceleration + p.rate_dot.cross(&a) + p.rate.cross(&p.rate.cross(&a))
                    - rate_dot.cross(&b)
                    - rate.cross(&rate.cross(&b)),
                rate,
                rate_dot,
            });
            links.push(LinkMotion { point, axes: l.joint.motor_axes(q).into_iter().map(|x| p.rotation * x).collect() });
        }
        let total = self.mass();
        let mean = |f: fn(&BodyMotion) -> Vector3<f64>| {
            bodies.iter().zip(&self.bodies).map(|(m, b)| f(m) * b.mass).sum::<Vector3<f64>>() / total
        };
        let (c, cd, cdd) = (mean(|m| m.position), mean(|m| m.velocity), mean(|m| m.acceleration));
        for m in &mut bodies {
            m.position -= c;
            m.velocity -= cd;
            m.acceleration -= cdd;
        }
        for l in &mut links {
            l.point -= c;
        }
        TreeMotion { bodies, links }
    }
}
