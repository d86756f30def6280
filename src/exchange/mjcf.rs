//! The cat as an MJCF model, for MuJoCo.
//!
//! MJCF lets a body's frame sit anywhere relative to its joints, so every body frame here is the
//! body frame of the README's "Replay elsewhere" (links A, cross, B):
//!
//! - body `A` (centre of mass, `z` towards the head) with a `freejoint` (the floating base; its
//!   `qpos` is the position and the unit quaternion `(w, x, y, z)` of A in the world);
//! - body `cross` at A's `(0, 0, −l_A/2)`, with hinge `joint1` about `x` through its origin;
//! - body `B` at the cross's `(0, 0, −l_B/2)` (B's centre of mass at `q = 0`), with hinge `joint2`
//!   about `y` through B's `(0, 0, +l_B/2)`, the joint point. So `R_AB = Rx(q1) · Ry(q2)` and
//!   `qpos[7:9] = (q1, q2)`, `qvel[6:8] = (q̇1, q̇2)`.
//!
//! Every body has an explicit `<inertial>` ([`Links`]; `inertiafromgeom="false"`, so the
//! cylinder geoms are for viewing only: they have no mass and collide with nothing). The joints
//! have no damping, armature, friction or limits. Two `motor` actuators (`tau1`, `tau2`, gear
//! 1, unlimited) apply joint torques in N·m, the CSV's `tau` columns.
//!
//! **Gravity** is zero by default: in the frame falling with the centre of mass, gravity exerts
//! no torque about it, so the rotation is exactly that of the weightless cat; a
//! simulation with `g` gives the same rotation and a centre of mass on the ballistic parabola.
//! [`MjcfOptions::gravity`] writes `g` along `−z` instead.
//!
//! ## References
//! - MuJoCo documentation, *XML Reference* (body, inertial, joint, freejoint, motor),
//!   <https://mujoco.readthedocs.io/en/stable/XMLreference.html>.

use std::fmt::Write as _;

use crate::exchange::links::{num, vec3, xml_escape, Links};

/// Choices in the MJCF file.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MjcfOptions {
    /// Gravitational acceleration along the world's `−z`, m/s²; zero simulates the falling frame.
    pub gravity: f64,
    /// MuJoCo's time step, s (with the RK4 integrator).
    pub timestep: f64,
}

impl Default for MjcfOptions {
    fn default() -> Self {
        Self { gravity: 0.0, timestep: 1e-4 }
    }
}

/// The MJCF text of the cat `links`, model name `name`.
pub fn mjcf(links: &Links, name: &str, options: &MjcfOptions) -> String {
    let [half_a, half_b] = links.half_lengths();
    let size = |i: usize| format!("{} {}", num(links.halves[i].radius), num(links.half_lengths()[i]));
    let mut s = String::new();
    let _ = writeln!(
        s,
        "<!-- catflip: the two-cylinder cat (README.md, section \"Replay elsewhere\"). SI units; B relative to A is Rx(q1)·Ry(q2). -->"
    );
    let _ = writeln!(s, "<mujoco model=\"{}\">", xml_escape(name));
    let _ = writeln!(s, "  <compiler angle=\"radian\" inertiafromgeom=\"false\" autolimits=\"true\"/>");
    let _ = writeln!(
        s,
        "  <option gravity=\"0 0 {}\" timestep=\"{}\" integrator=\"RK4\"/>",
        // `+ 0.0` turns −0 into 0.
        num(-options.gravity + 0.0),
        num(options.timestep)
    );
    let _ = writeln!(s, "  <worldbody>");
    let _ = writeln!(s, "    <body name=\"A\" pos=\"0 0 0\">");
    let _ = writeln!(s, "      <freejoint name=\"base\"/>");
    inertial(&mut s, links, 0, 6);
    geom(&mut s, "A", &size(0), 6);
    let _ = writeln!(s, "      <body name=\"cross\" pos=\"{}\">", vec3([0.0, 0.0, -half_a]));
    hinge(&mut s, "joint1", [1.0, 0.0, 0.0], [0.0, 0.0, 0.0], 8);
    inertial(&mut s, links, 1, 8);
    let _ = writeln!(s, "        <body name=\"B\" pos=\"{}\">", vec3([0.0, 0.0, -half_b]));
    hinge(&mut s, "joint2", [0.0, 1.0, 0.0], [0.0, 0.0, half_b], 10);
    inertial(&mut s, links, 2, 10);
    geom(&mut s, "B", &size(1), 10);
    let _ = writeln!(s, "        </body>");
    let _ = writeln!(s, "      </body>");
    let _ = writeln!(s, "    </body>");
    let _ = writeln!(s, "  </worldbody>");
    let _ = writeln!(s, "  <actuator>");
    let _ = writeln!(s, "    <motor name=\"tau1\" joint=\"joint1\" gear=\"1\"/>");
    let _ = writeln!(s, "    <motor name=\"tau2\" joint=\"joint2\" gear=\"1\"/>");
    let _ = writeln!(s, "  </actuator>");
    let _ = writeln!(s, "</mujoco>");
    s
}

fn inertial(s: &mut String, links: &Links, index: usize, indent: usize) {
    let _ = writeln!(
        s,
        "{:indent$}<inertial pos=\"0 0 0\" mass=\"{}\" diaginertia=\"{}\"/>",
        "",
        num(links.mass[index]),
        vec3(links.inertia[index])
    );
}

fn geom(s: &mut String, name: &str, size: &str, indent: usize) {
    let _ = writeln!(
        s,
        "{:indent$}<geom name=\"{name}\" type=\"cylinder\" size=\"{size}\" mass=\"0\" contype=\"0\" conaffinity=\"0\"/>",
        ""
    );
}

fn hinge(s: &mut String, name: &str, axis: [f64; 3], pos: [f64; 3], indent: usize) {
    let _ = writeln!(
        s,
        "{:indent$}<joint name=\"{name}\" type=\"hinge\" axis=\"{}\" pos=\"{}\" damping=\"0\" armature=\"0\" frictionloss=\"0\"/>",
        "",
        vec3(axis),
        vec3(pos)
    );
}
