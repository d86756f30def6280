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
//! **The no-twist joint has no URDF.** URDF's joint types (revolute, continuous, prismatic,
//! fixed, floating, planar) have no ball joint, and two revolute joints make the universal joint,
//! not Kane and Scher's constant-velocity joint. pyBullet reads a non-standard
//! `type="spherical"`, but other URDF tools refuse it, and its torque convention is pyBullet's
//! own; catflip writes no such file it has not replayed. [`urdf`] returns `None` for any joint
//! but the universal one, and the no-twist cat's folder holds its MJCF only (a ball joint,
//! [`mod@crate::exchange::mjcf`]).
//!
//! ## References
//! - the URDF XML specification, <http://wiki.ros.org/urdf/XML> (link, joint, inertial).

use std::fmt::Write as _;

use crate::exchange::links::{num, vec3, xml_escape, Links};

/// The URDF text of the cat `links`, robot name `name`; `None` unless the joint is the universal
/// one (module docs).
pub fn urdf(links: &Links, name: &str) -> Option<String> {
    if !links.has_cross() {
        return None;
    }
    let [a, b] = links.halves;
    let [half_a, half_b] = links.half_lengths();
    let mut s = String::new();
    let _ = writeln!(s, "<?xml version=\"1.0\"?>");
    let _ = writeln!(
        s,
        "<!-- catflip: the two-cylinder cat (README.md, section \"Replay elsewhere\"). SI units; B relative to A is Rx(q1)·Ry(q2). -->"
    );
    let _ = writeln!(s, "<robot name=\"{}\">", xml_escape(name));
    link(&mut s, links, "A", 0, [0.0, 0.0, 0.0], Some((a.length, a.radius)));
    link(&mut s, links, "cross", 1, [0.0, 0.0, 0.0], None);
    link(&mut s, links, "B", 2, [0.0, 0.0, -half_b], Some((b.length, b.radius)));
    joint(&mut s, "joint1", "A", "cross", [0.0, 0.0, -half_a], [1.0, 0.0, 0.0]);
    joint(&mut s, "joint2", "cross", "B", [0.0, 0.0, 0.0], [0.0, 1.0, 0.0]);
    let _ = writeln!(s, "</robot>");
    Some(s)
}

/// One link with its inertial at `com` (link frame) and, for a half, a cylinder visual there.
fn link(s: &mut String, links: &Links, name: &str, index: usize, com: [f64; 3], cylinder: Option<(f64, f64)>) {
    let i = links.inertia[index];
    let _ = writeln!(s, "  <link name=\"{name}\">");
    let _ = writeln!(s, "    <inertial>");
    let _ = writeln!(s, "      <origin xyz=\"{}\" rpy=\"0 0 0\"/>", vec3(com));
    let _ = writeln!(s, "      <mass value=\"{}\"/>", num(links.mass[index]));
    let _ = writeln!(
        s,
        "      <inertia ixx=\"{}\" ixy=\"0\" ixz=\"0\" iyy=\"{}\" iyz=\"0\" izz=\"{}\"/>",
        num(i[0]),
        num(i[1]),
        num(i[2])
    );
    let _ = writeln!(s, "    </inertial>");
    if let Some((length, radius)) = cylinder {
        let _ = writeln!(s, "    <visual>");
        let _ = writeln!(s, "      <origin xyz=\"{}\" rpy=\"0 0 0\"/>", vec3(com));
        let _ =
            writeln!(s, "      <geometry><cylinder radius=\"{}\" length=\"{}\"/></geometry>", num(radius), num(length));
        let _ = writeln!(s, "    </visual>");
    }
    let _ = writeln!(s, "  </link>");
}

/// One continuous joint at `origin` in the parent's frame, turning about `axis`.
fn joint(s: &mut String, name: &str, parent: &str, child: &str, origin: [f64; 3], axis: [f64; 3]) {
    let _ = writeln!(s, "  <joint name=\"{name}\" type=\"continuous\">");
    let _ = writeln!(s, "    <parent link=\"{parent}\"/>");
    let _ = writeln!(s, "    <child link=\"{child}\"/>");
    let _ = writeln!(s, "    <origin xyz=\"{}\" rpy=\"0 0 0\"/>", vec3(origin));
    let _ = writeln!(s, "    <axis xyz=\"{}\"/>", vec3(axis));
    let _ = writeln!(s, "    <dynamics damping=\"0\" friction=\"0\"/>");
    let _ = writeln!(s, "  </joint>");
}
