//! The cat as a URDF robot, for pyBullet, ROS tools, Drake, Pinocchio …
//!
//! Links `A` (the root: a simulator that loads it without a fixed base makes it floating),
//! `cross` and `B`; joints `joint1` (`A` → `cross`) and `joint2` (`cross` → `B`), both
//! `continuous` (URDF's revolute joint without limits) with zero damping and friction. URDF puts a child link's frame at its
//! joint, so:
//!
//! - `A`'s frame is A's body frame (centre of mass, `z` towards the head);
//! - `joint1` sits at `(0, 0, −l_A/2)` in `A` with axis `(1, 0, 0)`; the cross's frame is there,
//!   turned by `Rx(q1)`;
//! - `joint2` sits at the cross's origin with axis `(0, 1, 0)`; `B`'s frame is at the joint
//!   point, turned by `Ry(q2)` from the cross, so with axes of B's body frame and B's centre of
//!   mass at `(0, 0, −l_B/2)` in it (its `<inertial>` origin).
//!
//! Every link has an `<inertial>` with its true mass and inertia ([`Links`]); A and B carry a
//! cylinder `<visual>` (its own radius `r` and length `l`, at the centre of mass), and no link has a
//! `<collision>`: the scene needs no contacts. Tools that compute inertia from collision
//! shapes by default (pyBullet) must be told to use the file's (`URDF_USE_INERTIA_FROM_FILE`).
//!
//! **The no-twist joint** is written for pyBullet only. URDF's joint types (revolute,
//! continuous, prismatic, fixed, floating, planar) have no ball joint, and two revolute joints
//! make the universal joint, not Kane and Scher's constant-velocity joint. pyBullet reads a
//! non-standard `type="spherical"` (other URDF tools refuse it): links `A` and `B` only, joint
//! `joint` at `(0, 0, −l_A/2)` in `A` with `B`'s frame there (B's centre of mass at
//! `(0, 0, −l_B/2)`), the same layout as the MJCF's ball ([`mod@crate::exchange::mjcf`]).
//! pyBullet's conventions for it, measured on this file (pyBullet 3.2.7): the joint's position is
//! B's rotation relative to A as `(x, y, z, w)`, its velocity B's angular velocity relative to A in
//! B's frame, and a `TORQUE_CONTROL` force of `setJointMotorControlMultiDof` a couple about B's own
//! axes (from rest, the work it does equals the change of kinetic energy to 8.5e-6 relative with
//! B's axes and is 62 % off with A's: `python/examples/04_pybullet_replay_files.py` checks it). Like the MJCF's ball it has three rotational freedoms where the joint has two: a replay
//! gives it the joint's whole couple, `(tau1, tau2, tauz)` turned into B's frame, with `tauz` the
//! couple that holds the relative twist at zero (README, "Replay elsewhere").
//!
//! ## References
//! - the URDF XML specification, <http://wiki.ros.org/urdf/XML> (link, joint, inertial).

use std::fmt::Write as _;

use crate::exchange::links::{num, vec3, xml_escape, Links};

/// The URDF text of the cat `links`, robot name `name`: two continuous joints and the cross on
/// the universal joint, pyBullet's `spherical` joint on the no-twist one (module docs).
pub fn urdf(links: &Links, name: &str) -> String {
    let [a, b] = links.halves;
    let [half_a, half_b] = links.half_lengths();
    let mut s = String::new();
    let _ = writeln!(s, "<?xml version=\"1.0\"?>");
    let relative = if links.has_cross() {
        "Rx(q1)·Ry(q2)"
    } else {
        "exp([q1, q2, 0]×), pyBullet's non-standard spherical joint whose relative twist the replay holds at zero"
    };
    let _ = writeln!(
        s,
        "<!-- catflip: the two-cylinder cat (README.md, section \"Replay elsewhere\"). SI units; B relative to A is {relative}. -->"
    );
    let _ = writeln!(s, "<robot name=\"{}\">", xml_escape(name));
    link(&mut s, "A", links.mass[0], links.inertia[0], [0.0, 0.0, 0.0], Some((a.length, a.radius, None)));
    if links.has_cross() {
        link(&mut s, "cross", links.mass[1], links.inertia[1], [0.0, 0.0, 0.0], None);
        link(&mut s, "B", links.mass[2], links.inertia[2], [0.0, 0.0, -half_b], Some((b.length, b.radius, None)));
        joint(&mut s, "joint1", "A", "cross", [0.0, 0.0, -half_a], Some([1.0, 0.0, 0.0]));
        joint(&mut s, "joint2", "cross", "B", [0.0, 0.0, 0.0], Some([0.0, 1.0, 0.0]));
    } else {
        link(&mut s, "B", links.mass[2], links.inertia[2], [0.0, 0.0, -half_b], Some((b.length, b.radius, None)));
        joint(&mut s, "joint", "A", "B", [0.0, 0.0, -half_a], None);
    }
    let _ = writeln!(s, "</robot>");
    s
}

/// One link of `mass` and principal `moments` with its inertial at `com` (link frame) and, for a
/// body, a cylinder visual `(length, radius, rpy)` there (URDF's cylinder lies along `z`, turned
/// by `rpy` when given).
pub(crate) fn link(
    s: &mut String,
    name: &str,
    mass: f64,
    i: [f64; 3],
    com: [f64; 3],
    cylinder: Option<(f64, f64, Option<[f64; 3]>)>,
) {
    let _ = writeln!(s, "  <link name=\"{name}\">");
    let _ = writeln!(s, "    <inertial>");
    let _ = writeln!(s, "      <origin xyz=\"{}\" rpy=\"0 0 0\"/>", vec3(com));
    let _ = writeln!(s, "      <mass value=\"{}\"/>", num(mass));
    let _ = writeln!(
        s,
        "      <inertia ixx=\"{}\" ixy=\"0\" ixz=\"0\" iyy=\"{}\" iyz=\"0\" izz=\"{}\"/>",
        num(i[0]),
        num(i[1]),
        num(i[2])
    );
    let _ = writeln!(s, "    </inertial>");
    if let Some((length, radius, rpy)) = cylinder {
        let _ = writeln!(s, "    <visual>");
        let rpy = rpy.map_or_else(|| "0 0 0".to_string(), vec3);
        let _ = writeln!(s, "      <origin xyz=\"{}\" rpy=\"{rpy}\"/>", vec3(com));
        let _ =
            writeln!(s, "      <geometry><cylinder radius=\"{}\" length=\"{}\"/></geometry>", num(radius), num(length));
        let _ = writeln!(s, "    </visual>");
    }
    let _ = writeln!(s, "  </link>");
}

/// One joint at `origin` in the parent's frame: continuous about `axis`, or pyBullet's
/// `spherical` without one.
pub(crate) fn joint(s: &mut String, name: &str, parent: &str, child: &str, origin: [f64; 3], axis: Option<[f64; 3]>) {
    let kind = if axis.is_some() { "continuous" } else { "spherical" };
    let _ = writeln!(s, "  <joint name=\"{name}\" type=\"{kind}\">");
    let _ = writeln!(s, "    <parent link=\"{parent}\"/>");
    let _ = writeln!(s, "    <child link=\"{child}\"/>");
    let _ = writeln!(s, "    <origin xyz=\"{}\" rpy=\"0 0 0\"/>", vec3(origin));
    if let Some(axis) = axis {
        let _ = writeln!(s, "    <axis xyz=\"{}\"/>", vec3(axis));
    }
    let _ = writeln!(s, "    <dynamics damping=\"0\" friction=\"0\"/>");
    let _ = writeln!(s, "  </joint>");
}
