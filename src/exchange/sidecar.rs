//! The JSON sidecar `NAME.json` of a schedule CSV `NAME.csv`: what a replay needs to know and
//! must not guess (units, conventions, the model, the source problem, the jumps).
//!
//! Every field is plain data; [`Sidecar`] round-trips through serde, so a script reads it with
//! any JSON parser (`json.load`) and Rust code with `serde_json::from_str::<Sidecar>`.

use serde::{Deserialize, Serialize};

use crate::engines::jumps::VelocityJump;
use crate::engines::motors::MotorDemand;
use crate::engines::torque::Peak;
use crate::exchange::links::Links;
use crate::model::Joint;

/// The sidecar's format tag.
pub const FORMAT: &str = "catflip-schedule/1";

/// The whole sidecar.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Sidecar {
    /// [`FORMAT`].
    pub format: String,
    /// The CSV file this describes (same folder).
    pub csv: String,
    /// Where the schedule came from.
    pub source: Source,
    /// The cat and the model files beside the CSV.
    pub model: ModelInfo,
    /// Frames, units and sign conventions.
    pub conventions: Conventions,
    /// The CSV's columns in order.
    pub columns: Vec<Column>,
    /// How the rows are spaced.
    pub sampling: Sampling,
    /// The smooth pieces (phases), in order.
    pub pieces: Vec<PieceInfo>,
    /// Joint-rate jumps at piece boundaries, with their impulses; empty when the rates are
    /// continuous.
    pub jumps: Vec<JumpRecord>,
    /// How the orientation columns were computed, and how accurate they are.
    pub orientation: OrientationInfo,
    /// How to interpolate between rows.
    pub interpolation: String,
    /// What the schedule asks of its motors, measured by the exact engine.
    pub motors: MotorSizing,
}

/// A joint-rate jump as the sidecar records it ([`VelocityJump`], with the units in the names as
/// every field of the sidecar has them).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct JumpRecord {
    /// Time of the jump from the trajectory's start, s.
    pub time_s: f64,
    /// Index of the piece that ends there (the next one starts there).
    pub after_piece: usize,
    /// Rates just before, rad/s.
    pub rates_before_rad_s: [f64; 2],
    /// Rates just after, rad/s.
    pub rates_after_rad_s: [f64; 2],
    /// The motors' impulse on joints 1 and 2 (on the universal joint the generalised impulse
    /// `M(q) Δq̇`), N·m·s.
    pub impulse_nms: [f64; 2],
}

impl From<&VelocityJump> for JumpRecord {
    fn from(j: &VelocityJump) -> JumpRecord {
        JumpRecord {
            time_s: j.time,
            after_piece: j.after_piece,
            rates_before_rad_s: j.rates_before,
            rates_after_rad_s: j.rates_after,
            impulse_nms: j.impulse,
        }
    }
}

/// The motor-sizing figures of a schedule (DESIGN.md §9), from the exact engine's torques on the
/// trajectory's own samples ([`crate::engines::motors`]), against the problem's `[actuator]`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct MotorSizing {
    /// Peak `|τ_j|` of joints 1 and 2 over the whole schedule, N·m, and when.
    pub peak_torque_nm: [Peak; 2],
    /// Peak speed and power per joint, and each limit's worst usage (none with ideal motors).
    #[serde(flatten)]
    pub demand: MotorDemand,
    /// Whether every limit of `[actuator]` holds (true with ideal motors).
    pub within_motors: bool,
    /// The verdict in words.
    pub verdict: String,
}

/// Where a schedule came from.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Source {
    /// The schedule's name.
    pub schedule: String,
    /// The problem's name.
    pub problem: String,
    /// What the schedule is (profile, path, circulation, phase durations), in words.
    pub description: String,
    /// The whole problem file the schedule was made from (the TOML's content as JSON).
    pub problem_file: serde_json::Value,
}

/// The model, as [`Links`] describes it.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ModelInfo {
    /// Mass of each half (of the front half A when `rear` is given), kg.
    pub mass_kg: f64,
    /// Length of each half (of A when `rear` is given), m.
    pub length_m: f64,
    /// Radius of each half (of A when `rear` is given), m.
    pub radius_m: f64,
    /// Each half's (A's when `rear` is given) moments about its centre of mass `(I_x, I_y, I_z)`:
    /// `m(3r² + l²)/12` twice, then `m r²/2`, kg·m².
    pub half_inertia_kg_m2: [f64; 3],
    /// The rear half B when the halves differ (absent for equal halves).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub rear: Option<HalfInfo>,
    /// The joint point in A's body frame, m.
    pub joint_point_in_a_m: [f64; 3],
    /// The joint point in B's body frame, m.
    pub joint_point_in_b_m: [f64; 3],
    /// The joint: axes and the rotation of B relative to A.
    pub joint: String,
    /// Mass of the cross of the universal joint in the model files, kg (absent on the no-twist
    /// joint, which has no cross).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub cross_mass_kg: Option<f64>,
    /// Its moments, kg·m².
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub cross_inertia_kg_m2: Option<[f64; 3]>,
    /// Why the cross has a mass.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub cross_note: Option<String>,
    /// The URDF model file, relative to the CSV (on the no-twist joint pyBullet's non-standard
    /// spherical joint, `model_note` says so).
    pub urdf: String,
    /// The MJCF model file, relative to the CSV.
    pub mjcf: String,
    /// How the model files build this joint, when they need saying (the no-twist joint's ball).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub model_note: Option<String>,
}

/// One half of a cat whose halves differ.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct HalfInfo {
    /// Mass, kg.
    pub mass_kg: f64,
    /// Length, m.
    pub length_m: f64,
    /// Radius, m.
    pub radius_m: f64,
    /// Moments about its centre of mass `(I_x, I_y, I_z)`, kg·m².
    pub inertia_kg_m2: [f64; 3],
}

impl ModelInfo {
    /// The description of `links`, with the model files' names.
    pub fn new(links: &Links, urdf: &str, mjcf: &str) -> ModelInfo {
        let [front, rear] = links.halves;
        let [half_a, half_b] = links.half_lengths();
        let cross = links.has_cross();
        ModelInfo {
            mass_kg: front.mass,
            length_m: front.length,
            radius_m: front.radius,
            half_inertia_kg_m2: links.inertia[0],
            rear: (front != rear).then(|| HalfInfo {
                mass_kg: rear.mass,
                length_m: rear.length,
                radius_m: rear.radius,
                inertia_kg_m2: links.inertia[2],
            }),
            joint_point_in_a_m: [0.0, 0.0, -half_a],
            joint_point_in_b_m: [0.0, 0.0, half_b],
            joint: if cross {
                "universal: joint 1 turns about A's x, joint 2 about the cross's y (Rx(q1)·ŷ in A's frame); B relative to A is R_AB = Rx(q1)·Ry(q2); q = 0 is the straight cat"
            } else {
                "no-twist (Kane and Scher's constant-velocity joint): (q1, q2, 0) is the rotation vector of B relative to A, R_AB = exp([q1, q2, 0]×); the halves bend by |q| and never twist relative to each other; the motors act about A's x and y; q = 0 is the straight cat"
            }
            .into(),
            cross_mass_kg: cross.then_some(links.mass[1]),
            cross_inertia_kg_m2: cross.then_some(links.inertia[1]),
            cross_note: cross.then(|| "the cross is massless in the model; simulators need a body between two revolute joints, so the model files give it rapier.cross_mass_fraction times a half's mass and the inertia (2/5)·m_c·r² of a solid sphere of the cat's radius, as the rapier scene does; the tau columns are the massless cross's, so a simulator's inverse dynamics of the model files differ from them by a relative amount of the order of that fraction".into()),
            urdf: urdf.into(),
            mjcf: mjcf.into(),
            model_note: (!cross).then(|| "MuJoCo has no no-twist joint and URDF no ball joint: the MJCF joins B to A by a ball joint (qpos = rel_qw..rel_qz, qvel = rel_wx..rel_wz in B's frame) with three motors tau_bx, tau_by, tau_bz about B's own axes, and the URDF by pyBullet's non-standard 'spherical' joint (joint position rel_qx, rel_qy, rel_qz, rel_qw; velocity in B's frame; TORQUE_CONTROL couples about B's axes). A replay sets the couple to R_AB^T (tau1, tau2, tauz), the joint's whole couple turned into B's frame (tauz is the couple that holds the relative twist at zero, no motor's), plus a stiff PD on the relative rotation".into()),
        }
    }
}

/// Frames, units and signs.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Conventions {
    /// Units of every quantity.
    pub units: String,
    /// The frames.
    pub frames: String,
    /// The quaternion columns.
    pub quaternion: String,
    /// Twist and swing.
    pub twist_swing: String,
    /// The torque and impulse columns.
    pub torque: String,
    /// The boundary column.
    pub boundary: String,
}

impl Conventions {
    /// The conventions of a file of the cat on `joint` (the universal or no-twist joint).
    pub fn new(joint: Joint) -> Self {
        let universal = joint == Joint::Universal;
        Conventions {
            units: "SI: time s, angles rad, rates rad/s, accelerations rad/s², torques N·m, impulses N·m·s; twist and swing in degrees; each column's name ends with its unit".into(),
            frames: "each half's body frame is at its centre of mass, z along its axis towards the head; the world frame is the frame falling with the cat's centre of mass, aligned with A's body frame at t = 0".into(),
            quaternion: if universal {
                "qw, qx, qy, qz: A's orientation in the world frame as a unit quaternion, scalar first (w, x, y, z), the map from A's body frame to the world"
            } else {
                "qw, qx, qy, qz: A's orientation in the world frame as a unit quaternion, scalar first (w, x, y, z), the map from A's body frame to the world; rel_qw, rel_qx, rel_qy, rel_qz: B's orientation relative to A, R_AB = exp([q1, q2, 0]×), scalar first (MuJoCo's ball-joint qpos); rel_wx_rad_s, rel_wy_rad_s, rel_wz_rad_s: B's angular velocity relative to A in B's frame (MuJoCo's ball-joint qvel)"
            }
            .into(),
            twist_swing: "A's orientation split as R = R_swing·R_twist: twist_deg about A's initial +z (right-handed, signed, continued past ±180°), swing_deg the angle between A's initial and current z".into(),
            torque: if universal {
                "tau1_nm, tau2_nm: the motor torques the joint applies to B about joint 1's and joint 2's axes (exact inverse dynamics of the zero-momentum motion); impulse1_nms, impulse2_nms: the generalised impulse M(q)·Δq̇ of a rate jump, on the row where the jump lands ('start'), zero elsewhere"
            } else {
                "tau1_nm, tau2_nm, tauz_nm: the couple the joint applies to B about the joint point, in A's frame (exact inverse dynamics of the zero-momentum motion); tau1 and tau2, about A's x and y, are the motor torques; tauz, about A's z, is the no-twist constraint's couple (no motor's) that a ball joint must be given too; impulse1_nms, impulse2_nms, impulsez_nms: the same of the impulsive couple of a rate jump, on the row where the jump lands ('start'), zero elsewhere"
            }
            .into(),
            boundary: "'' for an ordinary row; at a boundary between two pieces the time is written twice: 'end' carries the ending piece's one-sided values, 'start' the next piece's; drop one of them (or split the file there) before fitting a spline".into(),
        }
    }
}

/// One CSV column.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Column {
    /// Its name in the header.
    pub name: String,
    /// Its unit (`""` for text).
    pub unit: String,
    /// What it holds.
    pub meaning: String,
}

/// How the rows are spaced.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Sampling {
    /// `uniform` (rows at `t = k / rate_hz`, plus the boundary rows and the final instant) or
    /// `per-piece` (`steps_per_piece` equal intervals in every piece).
    pub kind: String,
    /// The rate of a uniform grid, Hz.
    pub rate_hz: Option<f64>,
    /// Intervals per piece of a per-piece grid.
    pub steps_per_piece: Option<usize>,
    /// Data rows (the header not counted).
    pub rows: usize,
    /// Duration of the schedule, s.
    pub duration_s: f64,
}

/// One smooth piece of the schedule.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct PieceInfo {
    /// Its name (the `phase` column).
    pub name: String,
    /// Start time, s.
    pub start_s: f64,
    /// End time, s.
    pub end_s: f64,
    /// Index of its first data row (0 = the row after the header).
    pub first_row: usize,
    /// Index of its last data row.
    pub last_row: usize,
}

/// How the orientation columns were computed.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct OrientationInfo {
    /// The engine (`exact`: the momentum map integrated by the sixth-order Magnus method).
    pub engine: String,
    /// The tolerance asked of the engine, rad.
    pub tolerance_rad: f64,
    /// Largest Magnus step used, s (sub-steps between rows are never longer).
    pub max_step_s: f64,
    /// The engine's error estimate of the final orientation, rad.
    pub error_estimate_rad: f64,
    /// Whether the engine met the tolerance; when false the orientation columns are less
    /// accurate than `tolerance_rad`.
    pub converged: bool,
    /// The engine's final twist, degrees (the last row's `twist_deg` agrees to the tolerance).
    pub final_twist_deg: f64,
    /// The engine's final swing, degrees.
    pub final_swing_deg: f64,
}
