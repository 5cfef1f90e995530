//! The slider-crank example (`examples/slider_crank`) against its
//! independent solution: a slider-crank with a friction bearing on its
//! slider and a motor on its crank, built through the public API, run with
//! the dense output (every 10 ms) and the slider's velocity reversals
//! located as roots; compared with
//!
//! - the closed-form kinematics: the slider's position and the rod's angle
//!   from the crank angle (to the constraint tolerance);
//! - a fourth-order Runge-Kutta integration of the one-degree-of-freedom
//!   equation of motion (Lagrange's, with the same friction law), written
//!   apart from the solver: the crank angle and speed at every output time,
//!   the dead centres (`theta = k pi`, where the slider reverses) and the
//!   energy the bearing and the motor's losses dissipate;
//! - the energy balance: the motor's work `T0 (theta - theta0)` equals the
//!   kinetic energy `J(theta) omega^2 / 2` plus both dissipations.

#[path = "../examples/slider_crank/model.rs"]
mod model;

use std::f64::consts::PI;

use model::SliderCrank;

#[test]
fn the_slider_crank_matches_its_kinematics_a_second_integration_and_its_energy() {
    let mech = SliderCrank::default();
    let (t_end, out_dt) = (2.0, 0.01);
    let run = mech.simulate(SliderCrank::options(), t_end, out_dt).unwrap();
    let reference = mech.runge_kutta(t_end, 1e-5, out_dt);
    let fine = mech.runge_kutta(t_end, 5e-6, out_dt);
    assert_eq!(run.samples.len(), 200);
    assert_eq!(reference.samples.len(), 200);

    // the second method's own error, from halving its step
    let rk_error = reference.samples.iter().zip(&fine.samples).map(|(a, b)| (a.0 - b.0).abs()).fold(0.0, f64::max);
    let (mut d_theta, mut d_omega, mut d_x, mut d_beta) = (0.0f64, 0.0f64, 0.0f64, 0.0f64);
    for (k, (s, &(theta, omega))) in run.samples.iter().zip(&fine.samples).enumerate() {
        assert!((s.t - (k + 1) as f64 * out_dt).abs() < 1e-12);
        d_theta = d_theta.max((s.theta - theta).abs());
        d_omega = d_omega.max((s.omega - omega).abs());
        d_x = d_x.max((s.x - mech.slider_x(s.theta)).abs());
        d_beta = d_beta.max((s.beta - mech.rod_angle(s.theta)).abs());
    }
    let turned = run.samples.last().unwrap().theta - mech.theta0;
    eprintln!(
        "crank angle within {d_theta:.2e} rad of RK4 (its own error {rk_error:.1e}) over {turned:.1} rad, speed within \
         {d_omega:.2e} rad/s; kinematics: slider {d_x:.1e} m, rod {d_beta:.1e} rad; {:?}",
        run.stats
    );
    assert!(turned > 10.0 * PI, "the crank turns several times: {turned} rad");
    // (measured: 6.3e-6 rad and 2.7e-5 rad/s at tolerances 1e-9, whose
    // error control allows 1e-9 of the 33 rad turned per step; the second
    // method is 200 times closer)
    assert!(rk_error < 1e-7, "the second method's own error {rk_error:e} rad");
    assert!(d_theta < 3e-5, "crank angle {d_theta:e} rad");
    assert!(d_omega < 1e-4, "crank speed {d_omega:e} rad/s");
    // the dense output between steps holds the joints to 1.4e-8 m and 3.5e-8 rad
    assert!(d_x < 1e-7 && d_beta < 2e-7, "kinematics {d_x:e} m, {d_beta:e} rad");

    // the slider reverses at the dead centres
    assert_eq!(run.reversals.len(), fine.dead_centres.len());
    assert!(run.reversals.len() >= 10);
    let mut d_centre = 0.0f64;
    let mut off_centre = 0.0f64;
    for ((t, theta), t_ref) in run.reversals.iter().zip(&fine.dead_centres) {
        d_centre = d_centre.max((t - t_ref).abs());
        off_centre = off_centre.max((theta - (theta / PI).round() * PI).abs());
    }
    eprintln!(
        "{} reversals within {d_centre:.2e} s of RK4's dead centres, {off_centre:.1e} rad off k pi",
        run.reversals.len()
    );
    // (measured: 2.2e-7 s, 4.2e-9 rad)
    assert!(d_centre < 1e-6, "reversals {d_centre:e} s off the dead centres");
    assert!(off_centre < 1e-7, "the slider reverses {off_centre:e} rad off a dead centre");

    // energies
    let e = &run.energy;
    let last = run.samples.last().unwrap();
    let work = mech.torque * turned;
    let kinetic = mech.kinetic_energy(last.theta, last.omega);
    let rel = |a: f64, b: f64| (a - b).abs() / b.abs();
    let (last_theta, last_omega) = *fine.samples.last().unwrap();
    let rk_balance = rel(
        mech.torque * (last_theta - mech.theta0),
        mech.kinetic_energy(last_theta, last_omega) + fine.friction_work + fine.motor_loss,
    );
    eprintln!(
        "relative differences: motor work {:.1e}, bearing friction {:.1e}, motor losses {:.1e}, kinetic energy \
         {:.1e}; the second method's balance {rk_balance:.1e}, the solver's {:.1e}",
        rel(e.applied, work),
        rel(e.friction, fine.friction_work),
        rel(e.damping, fine.motor_loss),
        rel(e.kinetic, kinetic),
        e.relative_error()
    );
    // (measured: 0, 1.1e-6, 4.2e-7, 5e-12)
    assert!(rel(e.applied, work) < 1e-9, "motor work {} J against {work} J", e.applied);
    assert!(rel(e.friction, fine.friction_work) < 5e-6, "bearing friction {} J", e.friction);
    assert!(rel(e.damping, fine.motor_loss) < 2e-6, "motor losses {} J", e.damping);
    assert!(rel(e.kinetic, kinetic) < 1e-9, "kinetic energy {} J against {kinetic} J", e.kinetic);
    assert!(rk_balance < 1e-8, "the second method's own balance {rk_balance:e}");
    assert!(e.relative_error() < 1e-7, "the solver's balance {:e}", e.relative_error());
}
