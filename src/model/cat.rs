//! The cat as a model: a front half A and a rear half B, each a solid cylinder of its own mass,
//! length and radius, and the joint between them (DESIGN.md §10).
//!
//! Each half's frame sits at its centre with `z` along its spine, towards the head. The joint
//! sits on the axes at A's rear end `(0, 0, −l_A/2)` and B's front end `(0, 0, +l_B/2)`, and
//! turns B relative to A by the [`Joint`]'s `R_AB(q)`. [`Cat::tree`] is the two-body
//! [`Tree`] the engines reduce; the paper's cat, two equal halves on the universal joint, is
//! [`Cat::from`] a [`Cylinder`]. SI units.
//!
//! ## References
//! - T. R. Kane and M. P. Scher (1969), for the two-body model and the no-twist joint;
//! - the paper, §2 (the spherical joint) and §7 (the worked example's halves).

use nalgebra::{Matrix3, Vector3};
use serde::Serialize;

use crate::model::legs::LEG_STATION;
use crate::model::tree::{Body, Link, Tree};
use crate::model::{Cylinder, Joint};
use crate::numeric::numfmt::echo;

/// Two halves and a joint.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Cat {
    /// The front half A (the base).
    pub front: Cylinder,
    /// The rear half B.
    pub rear: Cylinder,
    /// How B is joined to A.
    pub joint: Joint,
}

impl From<Cylinder> for Cat {
    /// The paper's cat: two equal halves on the universal joint.
    fn from(half: Cylinder) -> Cat {
        Cat::equal(half, Joint::Universal)
    }
}

impl Cat {
    /// Two equal halves on `joint`.
    pub fn equal(half: Cylinder, joint: Joint) -> Cat {
        Cat { front: half, rear: half, joint }
    }

    /// Whether the halves are equal (the paper's `C` is defined only then).
    pub fn has_equal_halves(&self) -> bool {
        self.front == self.rear
    }

    /// The half of the paper's cat, when this is it: equal halves on the universal joint (the
    /// two-cylinder engine's model, [`crate::engines::exact`]).
    pub fn paper(&self) -> Option<&Cylinder> {
        (self.joint == Joint::Universal && self.has_equal_halves()).then_some(&self.front)
    }

    /// The half whose mass, length and radius are the means of the two halves' (the paper's `C`
    /// of this half is only a starting point when the halves differ).
    pub fn mean_half(&self) -> Cylinder {
        self.front.mean(&self.rear)
    }

    /// The model in words: its joint and its halves (`m kg, l m long, r m radius`).
    pub fn describe(&self) -> String {
        let half =
            |c: &Cylinder| format!("{} kg, {} m long, radius {} m", echo(c.mass), echo(c.length), echo(c.radius));
        let halves = if self.has_equal_halves() {
            format!("two equal halves of {}", half(&self.front))
        } else {
            format!("front half {}, rear half {}", half(&self.front), half(&self.rear))
        };
        format!("{} joint, {halves}", self.joint.name())
    }

    /// The straight cat's principal moments of inertia about its centre of mass,
    /// `(transverse, axial)`, kg·m²: each half's own plus the reduced mass at the distance
    /// `(l_A + l_B)/2` between their centres (the parallel-axis theorem).
    pub fn straight_inertia(&self) -> (f64, f64) {
        let (a, b) = (self.front, self.rear);
        let reduced = a.mass * b.mass / (a.mass + b.mass);
        let apart = 0.5 * (a.length + b.length);
        (a.transverse() + b.transverse() + reduced * apart * apart, a.axial() + b.axial())
    }

    /// Number of shape coordinates (the joint's).
    pub fn dof(&self) -> usize {
        self.joint.dof()
    }

    /// The two-body tree: A the base, B hung from A's rear end by the joint at B's front end.
    pub fn tree(&self) -> Tree {
        let link = Link {
            parent: 0,
            joint: self.joint,
            at_parent: Vector3::new(0.0, 0.0, -0.5 * self.front.length),
            at_child: Vector3::new(0.0, 0.0, 0.5 * self.rear.length),
        };
        Tree::two(Body::from(&self.front), link, Body::from(&self.rear))
    }

    /// The cat with a tail: the rod `tail` hung from the rear half's end on `joint`
    /// ([`Cat::tree_with`]).
    pub fn tree_with_tail(&self, tail: &Cylinder, joint: Joint) -> Tree {
        self.tree_with(&Appendages { tail: Some((*tail, joint)), legs: None })
    }

    /// The cat's tree with its appendages: the halves (bodies 0 and 1), then
    /// - a tail: the rod hung from the rear half's end (`(0, 0, −l_B/2)` in B's frame) by its own
    ///   front end (`(0, 0, +l_T/2)` in its frame) on its joint, straight behind the cat at zero;
    /// - legs: on each half one rod for its pair of legs (the pair's mass, on the belly's midline),
    ///   hung by its top end from the hip `(0, r, ±s l/2)` (the belly's surface at the legs'
    ///   station `s` = [`LEG_STATION`], `+` on A, `−` on B) on a [`Joint::Hinge`] about the half's
    ///   `x`: at zero the legs stand out along the belly's `+y` (the rod's axis is its own `y`,
    ///   its frame the half's at zero), and `q` swings them towards the head (`q > 0`) or the
    ///   tail, at most [`LEG_FOLD_LIMIT_DEG`] either way (parallel to the spine; the rods do not
    ///   collide, so a long leg folded towards the nearer end passes it), front legs first;
    ///
    /// the coordinates in that order after the cat's.
    pub fn tree_with(&self, appendages: &Appendages) -> Tree {
        let mut tree = self.tree();
        if let Some((tail, joint)) = appendages.tail {
            let link = Link {
                parent: 1,
                joint,
                at_parent: Vector3::new(0.0, 0.0, -0.5 * self.rear.length),
                at_child: Vector3::new(0.0, 0.0, 0.5 * tail.length),
            };
            tree = tree.attach(link, Body::from(&tail)).expect("a cat's tree has its rear half as body 1");
        }
        if let Some([front_legs, rear_legs]) = appendages.legs {
            for (parent, half, side, leg) in [(0, &self.front, 1.0, front_legs), (1, &self.rear, -1.0, rear_legs)] {
                let link = Link {
                    parent,
                    joint: Joint::Hinge,
                    at_parent: Vector3::new(0.0, half.radius, side * LEG_STATION * 0.5 * half.length),
                    at_child: Vector3::new(0.0, -0.5 * leg.length, 0.0),
                };
                let (transverse, axial) = (leg.transverse(), leg.axial());
                let body = Body {
                    mass: leg.mass,
                    inertia: Matrix3::from_diagonal(&Vector3::new(transverse, axial, transverse)),
                };
                tree = tree.attach(link, body).expect("a cat's tree has both halves");
            }
        }
        tree
    }
}

/// How far the legs swing from standing out along the belly, either way, degrees: parallel to the
/// spine.
pub const LEG_FOLD_LIMIT_DEG: f64 = 90.0;

/// What hangs from the cat beyond its halves (DESIGN.md §10, [`Cat::tree_with`]).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize)]
pub struct Appendages {
    /// A rod hung from the rear half's end, and its joint (two motors, or one on a
    /// [`Joint::Hinge`]).
    pub tail: Option<(Cylinder, Joint)>,
    /// Each half's pair of legs as one rod (the pair's mass), each on a hinge at its hips: the
    /// front half's pair, then the rear half's.
    pub legs: Option<[Cylinder; 2]>,
}

impl Appendages {
    /// Whether there is nothing beyond the halves.
    pub fn is_empty(&self) -> bool {
        self.tail.is_none() && self.legs.is_none()
    }

    /// The appendages' shape coordinates (and motors), after the cat's: one per
    /// [`Appendages::limits`] entry.
    pub fn dof(&self) -> usize {
        self.limits().len()
    }

    /// Each appendage coordinate's limit, rad (none for the tail's), in the tree's order: the
    /// tail's joint's coordinates, then one per pair of legs.
    pub fn limits(&self) -> Vec<Option<f64>> {
        let tail = self.tail.map_or(0, |(_, j)| j.dof());
        let legs = if self.legs.is_some() { 2 } else { 0 };
        std::iter::repeat_n(None, tail)
            .chain(std::iter::repeat_n(Some(LEG_FOLD_LIMIT_DEG.to_radians()), legs))
            .collect()
    }

    /// The appendages in words (`, with a tail of … on a … joint, with legs of …`).
    pub fn describe(&self) -> String {
        let mut out = String::new();
        if let Some((tail, joint)) = self.tail {
            out += &format!(
                ", with a tail of {} kg, {} m long, radius {} m on a {joint} joint",
                echo(tail.mass),
                echo(tail.length),
                echo(tail.radius)
            );
        }
        let rod = |leg: Cylinder| {
            format!("{} kg a pair, {} m long, radius {} m", echo(leg.mass), echo(leg.length), echo(leg.radius))
        };
        match self.legs {
            Some([front, rear]) if front == rear => {
                out += &format!(", with legs of {} on hinges at the hips", rod(front))
            }
            Some([front, rear]) => {
                out +=
                    &format!(", with front legs of {} and hind legs of {} on hinges at the hips", rod(front), rod(rear))
            }
            None => {}
        }
        out
    }
}
