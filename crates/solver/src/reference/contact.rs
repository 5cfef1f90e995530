//! Reference problems with contact ([`crate::Contact`]), shared by the
//! tests and the benchmarks: two bodies meeting head on, an oscillator
//! pounding against a rigid stop, and a row of bodies struck at one end (a
//! Newton's cradle of center beams). The closed forms and the second method
//! they are checked against are in `crates/solver/tests/contact_*.rs`.

use crate::model::body::{Body, BodyId, Coord};
use crate::model::force::{Contact, ContactLaw, CoordinateSpring, Excitation, ForceElement};
use crate::model::system::System;
use crate::timefn::TimeSeries;

/// Half the width of the bodies of these problems \[m\]: their faces are
/// this far from their centres.
pub const HALF_WIDTH: f64 = 0.05;

/// The contact of body `a`'s right face (x = +HALF_WIDTH) against body
/// `b`'s left face (x = -HALF_WIDTH, outward normal -x).
fn faces(a: BodyId, b: BodyId, law: ContactLaw) -> ForceElement {
    ForceElement::Contact(Contact {
        body: a,
        point: [HALF_WIDTH, 0.0],
        base: b,
        edge_point: [-HALF_WIDTH, 0.0],
        edge_normal: [-1.0, 0.0],
        law,
        reduced_mass: None,
    })
}

/// Two bodies moving along x only, `a` left of `b`, their facing sides
/// `gap` apart at t = 0, meeting through one contact.
#[derive(Debug, Clone, Copy)]
pub struct HeadOn {
    /// Mass of `a` \[kg\].
    pub mass_a: f64,
    /// Mass of `b` \[kg\].
    pub mass_b: f64,
    /// Velocity of `a` [m/s] (toward `b` when above `speed_b`).
    pub speed_a: f64,
    /// Velocity of `b` [m/s].
    pub speed_b: f64,
    /// Clear distance between the faces at t = 0 \[m\].
    pub gap: f64,
    /// The contact law.
    pub law: ContactLaw,
}

impl HeadOn {
    /// The system and the two bodies `(a, b)`.
    pub fn system(&self) -> (System, BodyId, BodyId) {
        let mut sys = System::new();
        let a = sys.add_body(Body::new("a", self.mass_a, 1.0, [0.0; 3]).only(&[Coord::X]).with_velocity([
            self.speed_a,
            0.0,
            0.0,
        ]));
        let xb = 2.0 * HALF_WIDTH + self.gap;
        let b = sys.add_body(Body::new("b", self.mass_b, 1.0, [xb, 0.0, 0.0]).only(&[Coord::X]).with_velocity([
            self.speed_b,
            0.0,
            0.0,
        ]));
        sys.add_force_named("a on b", faces(a, b, self.law));
        (sys, a, b)
    }

    /// Reduced mass `m_a m_b / (m_a + m_b)` \[kg\].
    pub fn reduced_mass(&self) -> f64 {
        self.mass_a * self.mass_b / (self.mass_a + self.mass_b)
    }

    /// Approach speed at contact [m/s].
    pub fn approach_speed(&self) -> f64 {
        self.speed_a - self.speed_b
    }
}

/// A single-DOF oscillator (a body moving along x on a spring and damper
/// to the ground) whose right face meets a rigid stop `gap` away when it
/// moves in +x: a deck pounding against an abutment.
#[derive(Debug, Clone, Copy)]
pub struct PoundingOscillator {
    /// Mass \[kg\].
    pub mass: f64,
    /// Natural period \[s\].
    pub period: f64,
    /// Damping ratio [-].
    pub damping: f64,
    /// Clear distance to the stop at rest \[m\].
    pub gap: f64,
    /// The contact law.
    pub law: ContactLaw,
}

impl PoundingOscillator {
    /// The system under base acceleration `ground` [m/s^2], and the body.
    pub fn system(&self, ground: TimeSeries) -> (System, BodyId) {
        let w = 2.0 * std::f64::consts::PI / self.period;
        let mut sys = System::new();
        let body = sys.add_body(Body::new("deck", self.mass, 1.0, [0.0; 3]).only(&[Coord::X]));
        sys.add_force(ForceElement::CoordinateSpring(CoordinateSpring {
            body,
            coord: Coord::X,
            stiffness: self.mass * w * w,
            damping: 2.0 * self.damping * self.mass * w,
            rest: 0.0,
        }));
        sys.add_force_named(
            "stop",
            ForceElement::Contact(Contact {
                body,
                point: [0.0, 0.0],
                base: BodyId::GROUND,
                edge_point: [self.gap, 0.0],
                edge_normal: [-1.0, 0.0],
                law: self.law,
                reduced_mass: None,
            }),
        );
        sys.set_excitation(Excitation { ground_x: Some(ground.into()), ..Default::default() });
        (sys, body)
    }
}

/// A row of equal bodies along x, `gap` apart, the first moving at `speed`
/// toward the others at rest: a stack of center beams struck at one end.
#[derive(Debug, Clone, Copy)]
pub struct Cradle {
    /// Number of bodies.
    pub bodies: usize,
    /// Mass of each \[kg\].
    pub mass: f64,
    /// Clear distance between neighbours at t = 0 \[m\].
    pub gap: f64,
    /// Speed of the first body [m/s].
    pub speed: f64,
    /// The contact law between neighbours.
    pub law: ContactLaw,
}

impl Cradle {
    /// The system and its bodies, left to right.
    pub fn system(&self) -> (System, Vec<BodyId>) {
        let mut sys = System::new();
        let pitch = 2.0 * HALF_WIDTH + self.gap;
        let ids: Vec<BodyId> = (0..self.bodies)
            .map(|i| {
                let v = if i == 0 { self.speed } else { 0.0 };
                sys.add_body(
                    Body::new(format!("beam {i}"), self.mass, 1.0, [i as f64 * pitch, 0.0, 0.0])
                        .only(&[Coord::X])
                        .with_velocity([v, 0.0, 0.0]),
                )
            })
            .collect();
        for pair in ids.windows(2) {
            sys.add_force(faces(pair[0], pair[1], self.law));
        }
        (sys, ids)
    }
}
