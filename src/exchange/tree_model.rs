//! The model files of a cat beyond two motors (the spherical joint's third motor, a tail, legs): any
//! tree of cylinders ([`crate::model::tree::Tree`]) as MJCF for MuJoCo and as URDF, each joint
//! as the simulators have it.
//!
//! Every body is named (`A`, `B`, `tail`, `front-legs`, `hind-legs`, [`NamedTree`]) and has its
//! true mass and inertia about its centre of mass (an explicit `<inertial>`; its cylinder is drawn,
//! never collides, and has no mass). Its frame in the MJCF is its body frame: centre of mass, `z`
//! along its axis towards the head (a leg's frame is its half's with the legs standing out, its
//! cylinder along `y`: the geom's `zaxis`). A link hangs child `c` from parent `p` at the joint
//! point, `a` in the parent's frame and `b` in the child's ([`crate::model::tree::Link`]); in the
//! MJCF:
//!
//! - a **universal** joint (`R = Rx(q1) Ry(q2)`) is the two-body file's: a body `cross_c` at the
//!   parent's `a` with hinge `c_1` about `x` through its origin, and the child at the cross's
//!   `−b` with hinge `c_2` about `y` through the child's `b`; motors `tau<k>` (gear 1) on each
//!   hinge, `k` the coordinate's number over the whole tree (its CSV column). The cross's mass and
//!   isotropic moment are those of rapier's tree scene ([`joint_body`]: `f` times the bodies'
//!   mean mass and mean smallest moment; the two-body files' cross,
//!   [`crate::exchange::links::Links`], is a solid sphere of the halves' mean radius: on the
//!   paper's cat 4e-9 against 5e-9 kg·m² at `f = 10⁻⁶`);
//! - a **no-twist** or **spherical** joint is a `ball` joint `c_ball` through the child's `b`,
//!   the child at the parent's `a − b`; three motors `c_bx`, `c_by`, `c_bz` (gear `1 0 0`, …) apply
//!   a couple about the child's own axes. The spherical joint *is* a ball joint with a motor on
//!   every freedom; the no-twist joint has two, and its structure holds the third (the two-body
//!   file's recipe, [`mod@crate::exchange::mjcf`]): a replay gives the ball the joint's whole
//!   couple on the child, motors and structure together, which the schedule file writes in the
//!   child's frame ([`crate::exchange::tree_file`]);
//! - a **hinge** (a leg pair's, a one-motor tail's; `R = Rx(q1)`) is a `hinge` joint `c_1` about
//!   `x` through the child's `b`, the child at the parent's `a − b`; its motor `tau<k>`.
//!
//! The URDF has one link per body and per cross, each non-root link's frame at its joint point
//! with the axes of its body frame (the centre of mass at `−b` in it): two `continuous` joints for
//! a universal joint, one for a hinge, pyBullet's non-standard `spherical` joint for a ball (other
//! URDF tools refuse it, [`mod@crate::exchange::urdf`]). The MJCF's gravity is zero (the falling frame).
//!
//! ## References
//! - MuJoCo, *XML Reference* (body, joint, inertial, motor),
//!   <https://mujoco.readthedocs.io/en/stable/XMLreference.html>;
//! - the URDF XML specification, <http://wiki.ros.org/urdf/XML>.

use std::fmt::Write as _;

use nalgebra::{UnitQuaternion, Vector3};

use crate::engines::rapier::tree_scene::joint_body;
use crate::engines::rapier::RapierError;
use crate::exchange::links::{num, vec3, xml_escape};
use crate::exchange::mjcf::{close_model, geom, inertial, joint, open_model, MjcfOptions};
use crate::exchange::urdf;
use crate::model::tree::Tree;
use crate::model::Joint;
use crate::optimize::whole::{NamedBody, WholeCat};

/// A tree of cylinders with a name for every body: what the model files of a cat beyond two
/// motors are written from.
#[derive(Clone, Debug, PartialEq)]
pub struct NamedTree {
    /// The tree (its bodies are the cylinders').
    pub tree: Tree,
    /// Each body's name, cylinder and its axis, in the tree's order.
    pub bodies: Vec<NamedBody>,
    /// Mass (kg) and isotropic moment (kg·m²) of each universal joint's cross.
    pub cross: (f64, f64),
}

impl NamedTree {
    /// The tree of `cat`, its universal joints' crosses `fraction` of the mean body
    /// (`rapier.cross_mass_fraction`, as rapier's scene).
    pub fn of(cat: &WholeCat, fraction: f64) -> Result<NamedTree, RapierError> {
        let tree = cat.tree();
        let cross = joint_body(&tree, fraction)?;
        Ok(NamedTree { tree, bodies: cat.named_bodies(), cross })
    }

    /// The name of body `k`.
    pub fn name(&self, k: usize) -> &'static str {
        self.bodies[k].name
    }

    /// Whether link `i`'s joint is a ball in the model files (no-twist, spherical).
    pub fn is_ball(&self, i: usize) -> bool {
        matches!(self.tree.links()[i].joint, Joint::NoTwist | Joint::Spherical)
    }

    /// Link `i`'s motor axes in words ([`Joint::motor_axis_names`] with its own bodies' names).
    pub fn motor_axes(&self, i: usize) -> Vec<String> {
        let l = self.tree.links()[i];
        let (parent, child) = (self.name(l.parent), self.name(i + 1));
        // The names are the two-body cat's (A the parent, B the child, the cross the link's own),
        // replaced in one pass.
        let own = |a: &&str| {
            a.strip_prefix("A's")
                .map(|rest| format!("{parent}'s{rest}"))
                .or_else(|| a.strip_prefix("B's").map(|rest| format!("{child}'s{rest}")))
                .or_else(|| a.strip_prefix("the cross's").map(|rest| format!("cross_{child}'s{rest}")))
                .unwrap_or_else(|| a.to_string())
        };
        l.joint.motor_axis_names().iter().map(own).collect()
    }

    /// The MJCF motors of link `i`: (name, joint, gear).
    pub fn motors(&self, i: usize) -> Vec<(String, String, &'static str)> {
        let child = self.name(i + 1);
        if self.is_ball(i) {
            let joint = format!("{child}_ball");
            ["x", "y", "z"]
                .iter()
                .zip(["1 0 0 0 0 0", "0 1 0 0 0 0", "0 0 1 0 0 0"])
                .map(|(axis, gear)| (format!("{child}_b{axis}"), joint.clone(), gear))
                .collect()
        } else {
            self.tree
                .coordinates(i)
                .zip(1..)
                .map(|(k, h)| (format!("tau{}", k + 1), format!("{child}_{h}"), "1"))
                .collect()
        }
    }
}

/// The MJCF text of `model`, model name `name` (module docs).
pub fn tree_mjcf(model: &NamedTree, name: &str, options: &MjcfOptions) -> String {
    let mut s = String::new();
    let legs = if model.bodies.iter().all(|b| along_z(&b.axis)) {
        ""
    } else {
        " (a leg's cylinder along its frame's y, towards the paw: its frame is its half's with the legs standing out)"
    };
    let comment = format!(
        "a cat of {} bodies (README.md, section \"Replay elsewhere\"). SI units; body frames at the centres of mass, z towards the head{legs}.",
        model.bodies.len()
    );
    open_model(&mut s, &comment, name, model.name(0), options);
    mjcf_body(&mut s, model, 0, 6);
    let motors: Vec<(String, String, &str)> = (0..model.tree.links().len()).flat_map(|i| model.motors(i)).collect();
    let motors: Vec<(&str, &str, &str)> = motors.iter().map(|(m, j, g)| (m.as_str(), j.as_str(), *g)).collect();
    close_model(&mut s, &motors);
    s
}

/// Body `k`'s inertial and cylinder, then its children, at `indent`.
fn mjcf_body(s: &mut String, model: &NamedTree, k: usize, indent: usize) {
    let NamedBody { name, cylinder: c, axis } = model.bodies[k];
    inertial(s, model.tree.bodies()[k].mass, moments(model, k), indent);
    let zaxis = (!along_z(&axis)).then(|| arr(&axis));
    geom(s, name, &format!("{} {}", num(c.radius), num(0.5 * c.length)), zaxis, indent);
    for (i, l) in model.tree.links().iter().enumerate().filter(|(_, l)| l.parent == k) {
        let child = model.name(i + 1);
        let (a, b) = (l.at_parent, l.at_child);
        if l.joint != Joint::Universal {
            let _ = writeln!(s, "{:indent$}<body name=\"{child}\" pos=\"{}\">", "", v(&(a - b)));
            if model.is_ball(i) {
                joint(s, &format!("{child}_ball"), "ball", None, arr(&b), indent + 2);
            } else {
                joint(s, &format!("{child}_1"), "hinge", Some([1.0, 0.0, 0.0]), arr(&b), indent + 2);
            }
            mjcf_body(s, model, i + 1, indent + 2);
            let _ = writeln!(s, "{:indent$}</body>", "");
        } else {
            let (mass, moment) = model.cross;
            let _ = writeln!(s, "{:indent$}<body name=\"cross_{child}\" pos=\"{}\">", "", v(&a));
            let inner = indent + 2;
            joint(s, &format!("{child}_1"), "hinge", Some([1.0, 0.0, 0.0]), [0.0; 3], inner);
            inertial(s, mass, [moment; 3], inner);
            let _ = writeln!(s, "{:inner$}<body name=\"{child}\" pos=\"{}\">", "", v(&-b));
            joint(s, &format!("{child}_2"), "hinge", Some([0.0, 1.0, 0.0]), arr(&b), inner + 2);
            mjcf_body(s, model, i + 1, inner + 2);
            let _ = writeln!(s, "{:inner$}</body>", "");
            let _ = writeln!(s, "{:indent$}</body>", "");
        }
    }
}

/// Body `k`'s principal moments (its inertia is diagonal in its frame: a cylinder's).
fn moments(model: &NamedTree, k: usize) -> [f64; 3] {
    arr(&model.tree.bodies()[k].inertia.diagonal())
}

/// The components, `−0` written as `0`.
pub(crate) fn arr(x: &Vector3<f64>) -> [f64; 3] {
    [x.x + 0.0, x.y + 0.0, x.z + 0.0]
}

/// Whether a body's cylinder lies along its frame's `z` (the halves, a tail): its files then say
/// nothing of the axis (MJCF's and URDF's default).
fn along_z(axis: &Vector3<f64>) -> bool {
    (axis - Vector3::z()).norm() < 1e-12
}

/// URDF's `rpy` (fixed-axis roll, pitch, yaw) that turns a cylinder along `z` onto `axis`.
fn rpy(axis: &Vector3<f64>) -> [f64; 3] {
    let turn = UnitQuaternion::rotation_between(&Vector3::z(), axis).unwrap_or_else(UnitQuaternion::identity);
    let (roll, pitch, yaw) = turn.euler_angles();
    arr(&Vector3::new(roll, pitch, yaw))
}

fn v(x: &Vector3<f64>) -> String {
    vec3(arr(x))
}

/// The URDF text of `model`, robot name `name` (module docs).
pub fn tree_urdf(model: &NamedTree, name: &str) -> String {
    let mut s = String::new();
    let _ = writeln!(s, "<?xml version=\"1.0\"?>");
    let _ = writeln!(
        s,
        "<!-- catflip: a cat of {} bodies (README.md, section \"Replay elsewhere\"). SI units; each joint's link frame at its joint point; ball joints are pyBullet's non-standard spherical joint. -->",
        model.bodies.len()
    );
    let _ = writeln!(s, "<robot name=\"{}\">", xml_escape(name));
    let links = model.tree.links();
    // Where each body's link frame sits in its body frame: the root's at its centre, the others'
    // at their joint point.
    let origin = |k: usize| if k == 0 { Vector3::zeros() } else { links[k - 1].at_child };
    for (k, b) in model.bodies.iter().enumerate() {
        let com = arr(&-origin(k));
        let visual = Some((b.cylinder.length, b.cylinder.radius, (!along_z(&b.axis)).then(|| rpy(&b.axis))));
        urdf::link(&mut s, b.name, model.tree.bodies()[k].mass, moments(model, k), com, visual);
    }
    for (i, l) in links.iter().enumerate() {
        let (parent, child) = (model.name(l.parent), model.name(i + 1));
        let at = arr(&(l.at_parent - origin(l.parent)));
        if model.is_ball(i) {
            urdf::joint(&mut s, &format!("{child}_ball"), parent, child, at, None);
        } else if l.joint == Joint::Hinge {
            urdf::joint(&mut s, &format!("{child}_1"), parent, child, at, Some([1.0, 0.0, 0.0]));
        } else {
            let cross = format!("cross_{child}");
            let (mass, moment) = model.cross;
            urdf::link(&mut s, &cross, mass, [moment; 3], [0.0; 3], None);
            urdf::joint(&mut s, &format!("{child}_1"), parent, &cross, at, Some([1.0, 0.0, 0.0]));
            urdf::joint(&mut s, &format!("{child}_2"), &cross, child, [0.0; 3], Some([0.0, 1.0, 0.0]));
        }
    }
    let _ = writeln!(s, "</robot>");
    s
}
