//! Reference problems shared by the tests and the benchmarks. Each comes
//! with the closed form or conservation law it is checked against (see the
//! tests of the same name).

use std::sync::Arc;

use crate::model::body::{Body, BodyId, Coord};
use crate::model::constraint::{Constraint, Driver, PointOnLine, Prismatic, Revolute, Weld};
use crate::model::force::{
    AppliedLoad, BodyState, Bushing, CoordinateSpring, CustomElement, CustomForce, Excitation, ForceElement, Friction,
    FrictionLaw, SpringDamper,
};
use crate::model::system::System;
use crate::timefn::{TimeFunction, TimeSeries};

/// Simple pendulum: a point-like body of `mass` \[kg\] on a massless link of
/// `length` \[m\] pivoting at the origin, released from rest at `angle0` \[rad\]
/// from the downward vertical (pi/2 is horizontal), under gravity `g`
/// [m/s^2] in -y.
pub fn pendulum(mass: f64, length: f64, g: f64, angle0: f64) -> (System, BodyId) {
    let mut sys = System::new();
    let (s, c) = angle0.sin_cos();
    // bob at (L sin a, -L cos a); its frame is aligned with the link
    let phi = angle0 - std::f64::consts::FRAC_PI_2;
    let bob = sys.add_body(Body::new("bob", mass, mass * 1e-6, [length * s, -length * c, phi]));
    sys.add_constraint_named(
        "pivot",
        Constraint::Revolute(Revolute {
            body_a: bob,
            point_a: [-length, 0.0],
            body_b: BodyId::GROUND,
            point_b: [0.0, 0.0],
        }),
    );
    sys.set_excitation(Excitation { gravity: [0.0, -g], ..Default::default() });
    (sys, bob)
}

/// Linear single-DOF oscillator: a body of `mass` moving in x only, on a
/// spring and damper to the ground with natural period `period` \[s\] and
/// damping ratio `zeta`, under base acceleration `ground` [m/s^2].
pub fn sdof(mass: f64, period: f64, zeta: f64, ground: TimeSeries) -> (System, BodyId) {
    let w = 2.0 * std::f64::consts::PI / period;
    let mut sys = System::new();
    let body = sys.add_body(Body::new("deck", mass, 1.0, [0.0; 3]).only(&[Coord::X]));
    sys.add_force(ForceElement::CoordinateSpring(CoordinateSpring {
        body,
        coord: Coord::X,
        stiffness: mass * w * w,
        damping: 2.0 * zeta * mass * w,
        rest: 0.0,
    }));
    sys.set_excitation(Excitation { ground_x: Some(ground.into()), ..Default::default() });
    (sys, body)
}

/// Mass on a spring with regularised Coulomb friction against the ground,
/// released from rest at `x0` \[m\] (free vibration).
#[derive(Debug, Clone, Copy)]
pub struct FrictionOscillator {
    /// Mass \[kg\].
    pub mass: f64,
    /// Spring stiffness [N/m].
    pub stiffness: f64,
    /// Coulomb friction force mu N \[N\].
    pub friction_force: f64,
    /// Regularisation velocity [m/s].
    pub v_eps: f64,
    /// Friction law.
    pub law: FrictionLaw,
    /// Initial position \[m\].
    pub x0: f64,
}

impl FrictionOscillator {
    /// The mass as a body restricted to its x coordinate.
    pub fn on_coordinate(&self) -> (System, BodyId) {
        let mut sys = System::new();
        let body = self.add_on_coordinate(&mut sys);
        (sys, body)
    }

    /// [`Self::on_coordinate`] added to `sys` beside what it holds (several
    /// oscillators in one system move independently).
    pub fn add_on_coordinate(&self, sys: &mut System) -> BodyId {
        let body = sys.add_body(Body::new("mass", self.mass, 1.0, [self.x0, 0.0, 0.0]).only(&[Coord::X]));
        self.add_spring_and_friction(sys, body);
        body
    }

    /// The mass as a free planar body held on the x axis by a prismatic
    /// joint to the ground (the friction then acts on a slider, which the
    /// integrator's local friction solve handles).
    pub fn on_prismatic(&self) -> (System, BodyId) {
        let mut sys = System::new();
        let body = sys.add_body(Body::new("slider", self.mass, 0.01, [self.x0, 0.0, 0.0]));
        sys.add_constraint(Constraint::Prismatic(Prismatic {
            slider: body,
            point: [0.0, 0.0],
            base: BodyId::GROUND,
            axis_point: [0.0, 0.0],
            axis_direction: [1.0, 0.0],
        }));
        self.add_spring_and_friction(&mut sys, body);
        (sys, body)
    }

    fn add_spring_and_friction(&self, sys: &mut System, body: BodyId) {
        sys.add_force(ForceElement::CoordinateSpring(CoordinateSpring {
            body,
            coord: Coord::X,
            stiffness: self.stiffness,
            damping: 0.0,
            rest: 0.0,
        }));
        sys.add_force(ForceElement::Friction(Friction {
            slider: body,
            point: [0.0, 0.0],
            base: BodyId::GROUND,
            mu: 1.0,
            normal_force: self.friction_force,
            surfaces: 1.0,
            v_eps: self.v_eps,
            law: self.law,
        }));
    }
}

/// A frictionless bead (a small body sliding in a prismatic joint) on a rod
/// that a driver turns about the origin at constant angular speed `omega`
/// [rad/s]; the bead starts at radius `r0` at rest relative to the rod.
pub fn bead_on_rod(omega: f64, r0: f64) -> (System, BodyId, BodyId) {
    let mut sys = System::new();
    let rod = sys.add_body(Body::new("rod", 2.0, 0.5, [0.0; 3]).with_velocity([0.0, 0.0, omega]));
    sys.add_constraint_named(
        "hub",
        Constraint::Revolute(Revolute {
            body_a: rod,
            point_a: [0.0, 0.0],
            body_b: BodyId::GROUND,
            point_b: [0.0, 0.0],
        }),
    );
    sys.add_constraint_named(
        "motor",
        Constraint::Driver(Driver {
            body: rod,
            coord: Coord::Phi,
            motion: TimeFunction::Linear { value0: 0.0, rate: omega },
        }),
    );
    let bead = sys.add_body(Body::new("bead", 0.1, 1e-4, [r0, 0.0, 0.0]).with_velocity([0.0, omega * r0, omega]));
    sys.add_constraint_named(
        "slot",
        Constraint::Prismatic(Prismatic {
            slider: bead,
            point: [0.0, 0.0],
            base: rod,
            axis_point: [0.0, 0.0],
            axis_direction: [1.0, 0.0],
        }),
    );
    (sys, rod, bead)
}

/// A chain of `n` rods (1 kg, 1 m) joined end to end by stiff bushings, the
/// first one pinned to the ground, each carrying a slider (prismatic joint
/// along the rod) tied by a spring to the middle of the next rod; released
/// from horizontal under gravity. Frictionless and undamped, so its energy is
/// conserved.
pub fn chain(n: usize, bushing_stiffness: f64) -> System {
    let mut sys = System::new();
    let mut rods = Vec::with_capacity(n);
    for i in 0..n {
        let x = i as f64 + 0.5;
        let rod = sys.add_body(Body::new(format!("rod {i}"), 1.0, 1.0 / 12.0, [x, 0.0, 0.0]));
        let slider = sys.add_body(Body::new(format!("slider {i}"), 0.1, 1e-3, [x + 0.2, 0.0, 0.0]));
        sys.add_constraint(Constraint::Prismatic(Prismatic {
            slider,
            point: [0.0, 0.0],
            base: rod,
            axis_point: [0.0, 0.0],
            axis_direction: [1.0, 0.0],
        }));
        if i == 0 {
            sys.add_constraint(Constraint::Revolute(Revolute {
                body_a: rod,
                point_a: [-0.5, 0.0],
                body_b: BodyId::GROUND,
                point_b: [0.0, 0.0],
            }));
        } else {
            sys.add_force(ForceElement::Bushing(Bushing {
                frame_body: rods[i - 1],
                frame_point: [0.5, 0.0],
                body: rod,
                point: [-0.5, 0.0],
                stiffness: [bushing_stiffness, bushing_stiffness],
                damping: [0.0, 0.0],
                rest: [0.0, 0.0],
            }));
        }
        rods.push(rod);
        if i > 0 {
            // spring from the previous slider to the middle of this rod
            let prev_slider = BodyId(rods[i - 1].0 + 1);
            sys.add_force(ForceElement::SpringDamper(SpringDamper {
                body_a: prev_slider,
                point_a: [0.0, 0.0],
                body_b: rod,
                point_b: [0.0, 0.0],
                stiffness: 50.0,
                damping: 0.0,
                rest_length: 0.8,
            }));
        }
    }
    sys.set_excitation(Excitation { gravity: [0.0, -9.81], ..Default::default() });
    sys
}

/// A linear spring in x to the ground written as a custom force law (its
/// Jacobian comes from finite differences).
#[derive(Debug)]
pub struct CustomSpring {
    /// The body.
    pub body: BodyId,
    /// Stiffness [N/m].
    pub stiffness: f64,
    /// Damping [N s/m].
    pub damping: f64,
}

impl CustomForce for CustomSpring {
    fn bodies(&self) -> (BodyId, BodyId) {
        (self.body, BodyId::GROUND)
    }
    fn force(&self, _t: f64, a: &BodyState, _b: &BodyState) -> ([f64; 3], [f64; 3]) {
        let fx = -self.stiffness * a.pose[0] - self.damping * a.velocity[0];
        let torque = -0.1 * self.stiffness * a.pose[2] * a.pose[0];
        ([fx, 0.0, torque], [0.0; 3])
    }
}

/// Every force element and constraint type in one system, for the Jacobian
/// checks: anisotropic bushings with offsets and rest deflection, both
/// friction laws, a spring-damper, coordinate springs, an applied load, a
/// custom force, revolute joints to the ground and between bodies, a
/// prismatic joint, a point-on-line with a body restricted to x, a weld and
/// a driver.
pub fn element_zoo() -> System {
    let mut sys = System::new();
    let a = sys.add_body(Body::new("a", 3.0, 0.4, [0.3, 0.2, 0.3]));
    let b = sys.add_body(Body::new("b", 2.0, 0.3, [1.1, -0.4, -0.2]));
    let c = sys.add_body(Body::new("c", 1.5, 0.2, [0.7, 0.9, 0.5]));
    let d = sys.add_body(Body::new("d", 5.0, 1.0, [2.0, 0.1, 0.0]).only(&[Coord::X]));
    let e = sys.add_body(Body::new("e", 1.0, 0.1, [-0.5, 0.5, 0.1]));
    let f = sys.add_body(Body::new("f", 0.7, 0.05, [-1.0, -0.8, 0.0]));
    let g = sys.add_body(Body::new("g", 0.9, 0.07, [1.6, 1.3, 0.25]));
    sys.add_force(ForceElement::Bushing(Bushing {
        frame_body: a,
        frame_point: [0.2, -0.1],
        body: b,
        point: [-0.3, 0.15],
        stiffness: [2.0e3, 5.0e2],
        damping: [3.0, 7.0],
        rest: [0.01, -0.02],
    }));
    sys.add_force(ForceElement::Bushing(Bushing {
        frame_body: c,
        frame_point: [0.0, 0.3],
        body: BodyId::GROUND,
        point: [0.5, 1.0],
        stiffness: [1.0e3, 1.0e3],
        damping: [2.0, 2.0],
        rest: [0.0, 0.0],
    }));
    for (slider, base, law) in
        [(b, c, FrictionLaw::Linear), (c, a, FrictionLaw::Smooth), (e, BodyId::GROUND, FrictionLaw::Linear)]
    {
        sys.add_force(ForceElement::Friction(Friction {
            slider,
            point: [0.05, -0.02],
            base,
            mu: 0.3,
            normal_force: 10.0,
            surfaces: 2.0,
            v_eps: 0.1,
            law,
        }));
    }
    sys.add_force(ForceElement::SpringDamper(SpringDamper {
        body_a: a,
        point_a: [0.1, 0.1],
        body_b: c,
        point_b: [-0.1, 0.2],
        stiffness: 300.0,
        damping: 4.0,
        rest_length: 0.3,
    }));
    sys.add_force(ForceElement::CoordinateSpring(CoordinateSpring {
        body: d,
        coord: Coord::X,
        stiffness: 50.0,
        damping: 1.0,
        rest: 2.0,
    }));
    sys.add_force(ForceElement::AppliedLoad(AppliedLoad {
        body: b,
        point: [0.2, 0.1],
        fx: TimeFunction::Harmonic { amplitude: 3.0, omega: 2.0, phase: 0.1, offset: 1.0 },
        fy: TimeFunction::Constant(-2.0),
        torque: TimeFunction::Constant(0.5),
    }));
    sys.add_force(ForceElement::Custom(CustomElement(Arc::new(CustomSpring {
        body: e,
        stiffness: 20.0,
        damping: 0.5,
    }))));
    sys.add_constraint(Constraint::Revolute(Revolute {
        body_a: a,
        point_a: [-0.3, 0.0],
        body_b: BodyId::GROUND,
        point_b: [0.0, 0.2],
    }));
    sys.add_constraint(Constraint::Revolute(Revolute {
        body_a: f,
        point_a: [0.2, 0.1],
        body_b: e,
        point_b: [-0.3, -0.4],
    }));
    sys.add_constraint(Constraint::Prismatic(Prismatic {
        slider: b,
        point: [0.1, 0.0],
        base: a,
        axis_point: [0.4, -0.2],
        axis_direction: [0.8, -0.3],
    }));
    sys.add_constraint(Constraint::PointOnLine(PointOnLine {
        body: d,
        point: [-0.5, 0.4],
        line_body: c,
        line_point: [0.3, -0.1],
        line_direction: [0.6, -0.9],
    }));
    sys.add_constraint(Constraint::Weld(Weld { body_a: g, point_a: [0.1, 0.2], body_b: c, point_b: [0.0, 0.0] }));
    sys.add_constraint(Constraint::Driver(Driver {
        body: e,
        coord: Coord::Phi,
        motion: TimeFunction::Harmonic { amplitude: 0.2, omega: 3.0, phase: 0.0, offset: 0.1 },
    }));
    sys
}

pub mod andrews;
pub mod closed_form;
pub mod contact;
