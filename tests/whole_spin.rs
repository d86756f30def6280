//! The whole-manoeuvre optimiser for a cat released with spin (DESIGN.md §9; issue 21 §1):
//! the lifted spinning model's derivatives against central differences, and the min-peak optimum
//! with `L = [0, 0, 0.01]` against the independent reference.

use catflip::model::Cylinder;
use catflip::optimize::whole::sensitivity::{gauss_grid, uniform_grid, Layout};
use catflip::optimize::whole::spin::spin_pass;
use catflip::optimize::whole::{build_start_spinning, flipped, StartKind, WholeSettings};
use catflip::problem::Manoeuvre;
use nalgebra::Vector3;

/// The paper's cat (problems/paper.toml).
const PAPER: Cylinder = Cylinder { mass: 1.0, length: 1.0, radius: 0.1 };
/// Its fall from 10 m at g = 9.8 m/s², s.
const FALL: f64 = 1.428_571_428_571_428_6;

/// The final orientation error's Jacobian and the lifted torque gradients of the spinning model
/// agree with central differences of the same model (step 1e-6 rad along a generic direction of
/// every free control point): the derivatives are exact, attitude dependence included.
#[test]
fn spinning_derivatives_match_central_differences() {
    let spin = Vector3::new(0.02, -0.03, 0.05);
    let settings = WholeSettings { control_points: 16, coarse_control_points: None, ..WholeSettings::default() };
    let start = build_start_spinning(&PAPER, FALL, &Manoeuvre::default(), StartKind::Paper, &settings, &spin)
        .unwrap_or_else(|e| panic!("{e}"));
    let layout = Layout { control_points: settings.control_points, fixed: settings.fixed() };
    let n = layout.variables();
    let direction: Vec<f64> = (0..n).map(|v| ((v as f64 * 1.7).sin() + 0.3) * 0.5).collect();
    for grid in [uniform_grid(&start.spline, 4), gauss_grid(&start.spline, 2)] {
        let at = |k: f64| {
            let step: Vec<f64> = direction.iter().map(|d| k * d).collect();
            spin_pass(&PAPER, &layout.moved(&start.spline, &step), &layout, 8, &flipped(), &spin, &grid)
        };
        let base = at(0.0);
        let (plus, minus) = (at(1e-6), at(-1e-6));
        let extended = base.lift.extend(&direction);
        let predicted = &base.orientation.jacobian * nalgebra::DVector::from_column_slice(&direction);
        for i in 0..3 {
            let fd = (plus.orientation.error[i] - minus.orientation.error[i]) / 2e-6;
            assert!((fd - predicted[i]).abs() <= 1e-6 * (1.0 + fd.abs()), "e[{i}]: {fd} vs {}", predicted[i]);
        }
        let mut worst: f64 = 0.0;
        for (k, s) in base.samples.iter().enumerate() {
            for j in 0..2 {
                let fd = (plus.samples[k].tau[j] - minus.samples[k].tau[j]) / 2e-6;
                let lin: f64 = s.gradient[j].iter().map(|&(v, c)| c * extended[v]).sum();
                worst = worst.max((fd - lin).abs() / (1.0 + fd.abs()));
            }
        }
        assert!(worst <= 1e-6, "torque gradients off by {worst:e} (relative)");
    }
}
