//! A slider-crank with a friction bearing on its slider, driven by a motor,
//! built from scratch through the public API (`model.rs`) and checked
//! against an independent solution: the closed-form kinematics (slider
//! position and rod angle from the crank angle), a fourth-order Runge-Kutta
//! integration of the one-degree-of-freedom equation of motion written
//! apart from the solver (crank angle and speed at every output time, the
//! dead centres, the energy the bearing dissipates), and the energy
//! balance (motor work = kinetic energy + bearing friction + motor losses).
//! The solver's state comes from its dense output every 10 ms; the slider's
//! velocity reversals are located as roots on it. `tests/slider_crank.rs`
//! asserts the agreement.
//!
//! `cargo run --release -p quakejoint-solver --example slider_crank`

mod model;

use std::error::Error;
use std::f64::consts::PI;

use model::SliderCrank;

fn main() -> Result<(), Box<dyn Error>> {
    let mech = SliderCrank::default();
    let (t_end, out_dt) = (2.0, 0.01);
    let run = mech.simulate(SliderCrank::options(), t_end, out_dt)?;
    let reference = mech.runge_kutta(t_end, 1e-5, out_dt);

    println!("   t [s]   crank [rad]   RK4 [rad]    speed [rad/s]   RK4 [rad/s]   slider x [m]  closed form [m]");
    let (mut d_theta, mut d_omega, mut d_x, mut d_beta) = (0.0f64, 0.0f64, 0.0f64, 0.0f64);
    for (k, (s, &(theta, omega))) in run.samples.iter().zip(&reference.samples).enumerate() {
        d_theta = d_theta.max((s.theta - theta).abs());
        d_omega = d_omega.max((s.omega - omega).abs());
        d_x = d_x.max((s.x - mech.slider_x(s.theta)).abs());
        d_beta = d_beta.max((s.beta - mech.rod_angle(s.theta)).abs());
        if (k + 1) % 20 == 0 {
            println!(
                "{:8.3} {:13.8} {:13.8} {:14.8} {:14.8} {:14.9} {:14.9}",
                s.t,
                s.theta,
                theta,
                s.omega,
                omega,
                s.x,
                mech.slider_x(s.theta)
            );
        }
    }
    println!("largest difference to the RK4 solution: crank angle {d_theta:.1e} rad, speed {d_omega:.1e} rad/s");
    println!("largest difference to the closed-form kinematics: slider {d_x:.1e} m, rod angle {d_beta:.1e} rad");

    let d_centre =
        run.reversals.iter().zip(&reference.dead_centres).map(|((t, _), t_ref)| (t - t_ref).abs()).fold(0.0, f64::max);
    let off_centre =
        run.reversals.iter().map(|(_, theta)| (theta / PI - (theta / PI).round()).abs() * PI).fold(0.0, f64::max);
    println!(
        "slider reversals: {} located (RK4 dead centres: {}), times within {d_centre:.1e} s, crank angle within \
         {off_centre:.1e} rad of k pi",
        run.reversals.len(),
        reference.dead_centres.len()
    );

    let e = &run.energy;
    let last = run.samples.last().ok_or("no samples")?;
    let work = mech.torque * (last.theta - mech.theta0);
    let kinetic = mech.kinetic_energy(last.theta, last.omega);
    println!("energy [J]: motor work {:.6} (T0 x angle turned: {work:.6})", e.applied);
    println!("            bearing friction {:.6} (RK4: {:.6})", e.friction, reference.friction_work);
    println!("            motor losses {:.6} (RK4: {:.6})", e.damping, reference.motor_loss);
    println!("            kinetic {:.6} (J(theta) omega^2 / 2: {kinetic:.6})", e.kinetic);
    println!("            balance error {:.1e} of the energy scale", e.relative_error());
    println!(
        "solver: {} steps, {} rejected, {} Newton iterations",
        run.stats.steps, run.stats.rejected, run.stats.newton_iterations
    );
    Ok(())
}
