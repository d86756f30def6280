//! The cat as an MJCF model, for MuJoCo.
//!
//! MJCF lets a body's frame sit anywhere relative to its joints, so every body frame here is the
//! body frame of the README's "Replay elsewhere". On the **universal joint** (links A, cross, B):
//!
//! - body `A` (centre of mass, `z` towards the head) with a `freejoint` (the floating base; its
//!   `qpos` is the position and the unit quaternion `(w, x, y, z)` of A in the world);
//! - body `cross` at A's `(0, 0, −l_A/2)`, with hinge `joint1` about `x` through its origin;
//! - body `B` at the cross's `(0, 0, −l_B/2)` (B's centre of mass at `q = 0`), with hinge `joint2`
//!   about `y` through B's `(0, 0, +l_B/2)`, the joint point. So `R_AB = Rx(q1) · Ry(q2)` and
//!   `qpos[7:9] = (q1, q2)`, `qvel[6:8] = (q̇1, q̇2)`. Two `motor` actuators (`tau1`, `tau2`,
//!   gear 1) apply the joint torques in N·m, the CSV's `tau` columns.
//!
//! On the **no-twist joint** (Kane and Scher's, DESIGN.md §10, `R_AB = exp([q1, q2, 0]×)`) MuJoCo
//! has no joint of its own, so the file builds the nearest one it has, a `ball` joint, and the
//! replay holds its relative twist at zero:
//!
//! - body `A` with its `freejoint` as above, and body `B` at A's `(0, 0, −l_A/2 − l_B/2)` (B's
//!   centre of mass at `q = 0`; no cross), with the `ball` joint `joint` through B's
//!   `(0, 0, +l_B/2)`, the joint point. MuJoCo's ball `qpos[7:11]` is the unit quaternion
//!   `(w, x, y, z)` of B relative to A, and `qvel[6:9]` B's angular velocity relative to A in B's
//!   frame: the CSV's `rel_qw … rel_qz` and `rel_wx_rad_s … rel_wz_rad_s` columns;
//! - three `motor` actuators `tau_bx`, `tau_by`, `tau_bz` on the ball (gear `1 0 0`, `0 1 0`,
//!   `0 0 1`: a couple about B's own `x`, `y`, `z`, N·m). The CSV gives the joint's whole couple on
//!   B in A's frame: the two motor torques `tau1_nm, tau2_nm` about A's `x` and `y` and the
//!   constraint's `tauz_nm` about A's `z`; a replay turns it into B's frame,
//!   `τ_B = R_ABᵀ (τ1, τ2, τz)`, and sets the three controls to it;
//! - why the constraint's torque is fed forward: a ball joint has three rotational freedoms and
//!   the no-twist joint two; what keeps the relative twist at zero is the couple's part about
//!   A's `z`, which in DESIGN.md §10's split (the motors about A's `x` and `y`) the joint's
//!   structure supplies, and on the exact motion it is `tauz_nm`. That part is not workless: the
//!   relative rate has a component about A's `z` wherever the bend direction turns (on Kane and
//!   Scher's optimum it exchanges up to 0.28 W against the two motors' 1.7 W, netting zero over
//!   the fall; the joint's workless direction is the bisector of the two spines).
//!   With all three components given, the ball follows the no-twist motion exactly up to the
//!   integration error, and the replay's stiff PD on the relative rotation (towards `rel_q…`, at
//!   the rate `rel_w…`) holds the drift, twist included. MuJoCo's equality constraints cannot lock
//!   one rotational freedom of a ball, and a no-twist joint made of hinges would need a coupling
//!   of their angles that MJCF does not express; a PD alone on the twist would leave a lag of
//!   `τz / k`.
//!
//! Every body has an explicit `<inertial>` ([`Links`]; `inertiafromgeom="false"`, so the
//! cylinder geoms are for viewing only: they have no mass and collide with nothing). The joints
//! have no damping, armature, friction or limits, and the motors no control limits.
//!
//! **Gravity** is zero by default: in the frame falling with the centre of mass, gravity exerts
//! no torque about it, so the rotation is exactly that of the weightless cat; a
//! simulation with `g` gives the same rotation and a centre of mass on the ballistic parabola.
//! [`MjcfOptions::gravity`] writes `g` along `−z` instead.
//!
//! ## References
//! - MuJoCo documentation, *XML Reference* (body, inertial, joint, freejoint, motor),
//!   <https://mujoco.readthedocs.io/en/stable/XMLreference.html>; *Computation*, "Joint
//!   coordinates" (a ball joint's `qpos` is a unit quaternion, its `qvel` the angular velocity in
//!   the child's local frame), <https://mujoco.readthedocs.io/en/stable/computation/index.html>.
//!   `python/examples/03_mujoco_replay_files.py` checks both readings on the exported model.
//! - T. R. Kane and M. P. Scher, *A dynamical explanation of the falling cat phenomenon*,
//!   Int. J. Solids Structures 5 (1969) 663–670 (the no-twist joint).

use std::fmt::Write as _;

use crate::exchange::links::{num, vec3, xml_escape, Links};
use crate::model::Joint;

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

/// The MJCF text of the cat `links`, model name `name`: the universal joint's hinges, or the ball
/// joint of the no-twist joint (module docs). The spherical joint is that same ball.
pub fn mjcf(links: &Links, name: &str, options: &MjcfOptions) -> String {
    let [half_a, half_b] = links.half_lengths();
    let size = |i: usize| format!("{} {}", num(links.halves[i].radius), num(links.half_lengths()[i]));
    let relation = match links.joint {
        Joint::Universal => "B relative to A is Rx(q1)·Ry(q2)",
        Joint::NoTwist | Joint::Spherical => {
            "B relative to A is exp([q1, q2, 0]×), a ball joint whose relative twist the replay holds at zero"
        }
        Joint::Hinge => unreachable!("the halves are never joined by a hinge (Links::new panics on one)"),
    };
    let mut s = String::new();
    let comment = format!("the two-cylinder cat (README.md, section \"Replay elsewhere\"). SI units; {relation}.");
    open_model(&mut s, &comment, name, "A", options);
    inertial(&mut s, links.mass[0], links.inertia[0], 6);
    geom(&mut s, "A", &size(0), None, 6);
    let motors: &[(&str, &str, &str)] = if links.has_cross() {
        let _ = writeln!(s, "      <body name=\"cross\" pos=\"{}\">", vec3([0.0, 0.0, -half_a]));
        joint(&mut s, "joint1", "hinge", Some([1.0, 0.0, 0.0]), [0.0, 0.0, 0.0], 8);
        inertial(&mut s, links.mass[1], links.inertia[1], 8);
        let _ = writeln!(s, "        <body name=\"B\" pos=\"{}\">", vec3([0.0, 0.0, -half_b]));
        joint(&mut s, "joint2", "hinge", Some([0.0, 1.0, 0.0]), [0.0, 0.0, half_b], 10);
        inertial(&mut s, links.mass[2], links.inertia[2], 10);
        geom(&mut s, "B", &size(1), None, 10);
        let _ = writeln!(s, "        </body>");
        let _ = writeln!(s, "      </body>");
        &[("tau1", "joint1", "1"), ("tau2", "joint2", "1")]
    } else {
        let _ = writeln!(s, "      <body name=\"B\" pos=\"{}\">", vec3([0.0, 0.0, -(half_a + half_b)]));
        joint(&mut s, "joint", "ball", None, [0.0, 0.0, half_b], 8);
        inertial(&mut s, links.mass[2], links.inertia[2], 8);
        geom(&mut s, "B", &size(1), None, 8);
        let _ = writeln!(s, "      </body>");
        &[("tau_bx", "joint", "1 0 0 0 0 0"), ("tau_by", "joint", "0 1 0 0 0 0"), ("tau_bz", "joint", "0 0 1 0 0 0")]
    };
    close_model(&mut s, motors);
    s
}

/// The file's head: the comment, `<mujoco>` named `model`, its compiler and option, the world
/// and the root body `root` with its free joint, left open (at indent 6 within it).
pub(crate) fn open_model(s: &mut String, comment: &str, model: &str, root: &str, options: &MjcfOptions) {
    let _ = writeln!(s, "<!-- catflip: {comment} -->");
    let _ = writeln!(s, "<mujoco model=\"{}\">", xml_escape(model));
    let _ = writeln!(s, "  <compiler angle=\"radian\" inertiafromgeom=\"false\" autolimits=\"true\"/>");
    let _ = writeln!(
        s,
        "  <option gravity=\"0 0 {}\" timestep=\"{}\" integrator=\"RK4\"/>",
        // `+ 0.0` turns −0 into 0.
        num(-options.gravity + 0.0),
        num(options.timestep)
    );
    let _ = writeln!(s, "  <worldbody>");
    let _ = writeln!(s, "    <body name=\"{root}\" pos=\"0 0 0\">");
    let _ = writeln!(s, "      <freejoint name=\"base\"/>");
}

/// The file's tail: closes the root body and the world, then the `motors` (name, joint, gear).
pub(crate) fn close_model(s: &mut String, motors: &[(&str, &str, &str)]) {
    let _ = writeln!(s, "    </body>");
    let _ = writeln!(s, "  </worldbody>");
    let _ = writeln!(s, "  <actuator>");
    for (name, joint, gear) in motors {
        let _ = writeln!(s, "    <motor name=\"{name}\" joint=\"{joint}\" gear=\"{gear}\"/>");
    }
    let _ = writeln!(s, "  </actuator>");
    let _ = writeln!(s, "</mujoco>");
}

/// An `<inertial>` of `mass` and principal `moments` at the body frame's origin.
pub(crate) fn inertial(s: &mut String, mass: f64, moments: [f64; 3], indent: usize) {
    let _ =
        writeln!(s, "{:indent$}<inertial pos=\"0 0 0\" mass=\"{}\" diaginertia=\"{}\"/>", "", num(mass), vec3(moments));
}

/// A massless cylinder to look at, `size` MJCF's `"radius half-length"`, along `axis` of its
/// body's frame when given (MJCF's `zaxis`; MuJoCo's default is `z`).
pub(crate) fn geom(s: &mut String, name: &str, size: &str, axis: Option<[f64; 3]>, indent: usize) {
    let zaxis = axis.map(|a| format!(" zaxis=\"{}\"", vec3(a))).unwrap_or_default();
    let _ = writeln!(
        s,
        "{:indent$}<geom name=\"{name}\" type=\"cylinder\" size=\"{size}\"{zaxis} mass=\"0\" contype=\"0\" conaffinity=\"0\"/>",
        ""
    );
}

/// A joint of MJCF `kind` (`hinge` with its `axis`, or `ball`) through `pos` in its body's frame.
pub(crate) fn joint(s: &mut String, name: &str, kind: &str, axis: Option<[f64; 3]>, pos: [f64; 3], indent: usize) {
    let axis = axis.map(|a| format!(" axis=\"{}\"", vec3(a))).unwrap_or_default();
    let _ = writeln!(
        s,
        "{:indent$}<joint name=\"{name}\" type=\"{kind}\"{axis} pos=\"{}\" damping=\"0\" armature=\"0\" frictionloss=\"0\"/>",
        "",
        vec3(pos)
    );
}
