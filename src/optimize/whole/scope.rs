//! What the whole optimiser plans and what it refuses, before anything runs: a release with spin
//! takes neither motor limits nor the least fall time ([`spin_supported`]), and a cat of more than
//! two motors (the spherical joint, a tail, legs) takes no spin and no motor limits but one torque limit
//! on every motor ([`beyond_two_motors`]). Each refusal names the problem file's field.

use nalgebra::Vector3;

use super::cat::WholeCat;
use super::settings::{Objective, WholeError, WholeSettings};
use crate::model::motor::{motors_beyond, Motor, Motors, MotorsBeyond};

/// Refuses what the optimiser does not plan with spin: motor limits and the least fall time.
/// The least fall time slows a path (`q(t/k)`), which with spin changes the flip itself, and the
/// limits' feasibility stage is that least fall time; at a fixed fall the limits would need the
/// spinning torques' rows, which are not built.
pub fn spin_supported(settings: &WholeSettings, motors: &Motors, spin: &Vector3<f64>) -> Result<(), WholeError> {
    if spin.norm_squared() == 0.0 {
        return Ok(());
    }
    let value = format!("[{}, {}, {}]", spin.x, spin.y, spin.z);
    if settings.objective == Objective::MinTime {
        return Err(WholeError::BadFieldValue {
            field: "drop.angular_momentum",
            value,
            reason: "optimize.whole.objective = \"min-time\" assumes a release without spin (slowing a path changes a spinning cat's flip): use \"peak\" or \"energy\", or set drop.angular_momentum to [0, 0, 0]".into(),
        });
    }
    if !motors.is_ideal() {
        return Err(WholeError::BadFieldValue {
            field: "drop.angular_momentum",
            value,
            reason: "the whole optimiser does not take [actuator] limits (torque_limit_nm, speed_limit_rad_s, stall_torque_nm, free_speed_rad_s, power_limit_w) with a release with spin: remove them, or set drop.angular_momentum to [0, 0, 0]".into(),
        });
    }
    Ok(())
}

/// Refuses what the optimiser does not plan for a cat of more than two motors (the spherical joint,
/// [`WholeCat::Spherical`]; a tail, [`WholeCat::Appended`]): a release with spin (the spinning model
/// is built for two coordinates), and motor limits other than one torque limit on every motor
/// ([`motors_beyond`]), which it plans with the objective `peak` or `min-time` only (the
/// energy's limit rows are built for two motors).
pub fn beyond_two_motors(
    cat: &WholeCat,
    objective: Objective,
    motors: &Motors,
    spin: &Vector3<f64>,
) -> Result<(), WholeError> {
    if cat.joints() == 2 {
        return Ok(());
    }
    let refuse = |field: &'static str, value: String, what: &str| {
        Err(WholeError::BadFieldValue {
            field,
            value,
            reason: format!("the whole optimiser plans a cat of {} motors {what}", cat.joints()),
        })
    };
    if spin.norm_squared() > 0.0 {
        let value = format!("[{}, {}, {}]", spin.x, spin.y, spin.z);
        return refuse("drop.angular_momentum", value, "for a release without spin only: set it to [0, 0, 0]");
    }
    match motors_beyond(motors) {
        MotorsBeyond::Other => {
            let (field, value, fix) = if motors.joints.iter().all(Motor::torque_only) {
                let t = motors.joints.map(|m| m.torque.map_or("none".to_string(), crate::numeric::numfmt::echo));
                (
                    "actuator.torque_limit_nm",
                    format!("[{}, {}]", t[0], t[1]),
                    "give every motor the same torque limit (one number)",
                )
            } else {
                ("actuator", "limits".to_string(), "remove the speed, envelope and power limits")
            };
            refuse(
                field,
                value,
                &format!("with ideal motors or one torque limit on every motor (actuator.torque_limit_nm alone, one number or a pair of equal numbers): {fix}"),
            )
        }
        MotorsBeyond::TorqueLimit(_) if objective == Objective::Energy => refuse(
            "optimize.whole.objective",
            "\"energy\"".into(),
            "within a torque limit for the objective \"peak\" or \"min-time\" only: use one of them, or remove actuator.torque_limit_nm",
        ),
        _ => Ok(()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::{Cat, Cylinder, Joint};

    /// Unequal torque limits are named as what they are (a QA run was told to remove speed,
    /// envelope and power limits it never gave); other limits keep that advice.
    #[test]
    fn a_refused_limit_names_what_was_given() {
        let cat = WholeCat::spherical(Cat::equal(Cylinder::default(), Joint::Spherical)).expect("three motors");
        let torque = |t: f64| Motor { torque: Some(t), ..Motor::default() };
        let unequal = Motors { joints: [torque(0.5), torque(0.1)] };
        let e = beyond_two_motors(&cat, Objective::Peak, &unequal, &Vector3::zeros()).expect_err("refused").to_string();
        assert!(e.contains("actuator.torque_limit_nm") && e.contains("the same torque limit"), "{e}");
        assert!(!e.contains("speed"), "{e}");
        let speed = Motors { joints: [Motor { speed: Some(6.0), ..torque(0.5) }, torque(0.5)] };
        let e = beyond_two_motors(&cat, Objective::Peak, &speed, &Vector3::zeros()).expect_err("refused").to_string();
        assert!(e.contains("remove the speed, envelope and power limits"), "{e}");
        let equal = Motors { joints: [torque(0.5), torque(0.5)] };
        assert!(beyond_two_motors(&cat, Objective::Peak, &equal, &Vector3::zeros()).is_ok());
    }
}
