//! A fuse that breaks at a force: a mass striking a wall held by a fuse,
//! the break located in time, and the run continued with the wall freed.
//!
//! A 1000 kg mass moving at 1 m/s meets a wall 10 mm away through a linear
//! contact of 1e7 N/m without damping: `delta = (v0 / w) sin(w t')`,
//! `w = sqrt(k / m) = 100 rad/s`, the force `k delta` peaks at
//! `k v0 / w = 100 kN`. A fuse of 50 kN breaks at `w t' = asin(1/2) = pi/6`,
//! that is at `t = 0.01 + pi / 600 s`, with the mass at
//! `v0 cos(pi / 6)`. From there the wall is a 200 kg body sliding on the
//! ground against 20 kN of friction: the state, the contact's mode and the
//! energy balance carry over, and the balance closes with the wall's
//! friction. A fuse stronger than the peak force never fires, and the run
//! is the same, bit for bit, as one without it.

use std::sync::Arc;

use quakejoint_solver::*;

const M: f64 = 1000.0;
const V0: f64 = 1.0;
const K: f64 = 1.0e7;
const GAP: f64 = 0.01;

fn options() -> IntegratorOptions {
    IntegratorOptions { rtol: 1e-9, atol_translation: 1e-11, atol_velocity: 1e-9, ..IntegratorOptions::default() }
}

/// The mass and the wall's contact (on the ground, or on a freed `wall`
/// body sliding against `friction` \[N\]).
fn system(wall: Option<(f64, f64)>) -> System {
    system_of(wall, 1)
}

/// [`system`] with the wall's contact split into `parts` parallel
/// contacts of `K / parts` each.
fn system_of(wall: Option<(f64, f64)>, parts: usize) -> System {
    let mut sys = System::new();
    let mass = sys.add_body(Body::new("mass", M, 1.0, [0.0; 3]).with_velocity([-V0, 0.0, 0.0]).only(&[Coord::X]));
    // (the wall's body after the mass: the intact system's coordinates first)
    let base = match wall {
        None => BodyId::GROUND,
        Some((m_wall, _)) => sys.add_body(Body::new("wall", m_wall, 1.0, [0.0; 3]).only(&[Coord::X])),
    };
    for _ in 0..parts {
        sys.add_force(ForceElement::Contact(Contact {
            body: mass,
            point: [0.0, 0.0],
            base,
            edge_point: [-GAP, 0.0],
            edge_normal: [1.0, 0.0],
            law: ContactLaw::Linear { stiffness: K / parts as f64, restitution: 1.0 },
            reduced_mass: None,
        }));
    }
    if let Some((_, friction)) = wall {
        sys.add_force(ForceElement::Friction(Friction {
            slider: base,
            point: [0.0, 0.0],
            base: BodyId::GROUND,
            mu: 1.0,
            normal_force: friction,
            surfaces: 1.0,
            v_eps: 1e-4,
            law: FrictionLaw::Linear,
        }));
    }
    sys
}

fn assembly(sys: &System) -> Arc<Assembly> {
    Arc::new(Assembly::new(sys, &AssemblyOptions::default()).unwrap())
}

/// Runs the intact system with a fuse of `threshold` \[N\] on the contact
/// to `t_end`, stopping at the break: the solver and the break event.
fn until_break(threshold: Option<f64>, t_end: f64) -> (Radau5, Option<ContactEvent>) {
    until_break_of(threshold, t_end, 1)
}

/// [`until_break`] with the contact split into `parts`, the fuse held by
/// their summed force.
fn until_break_of(threshold: Option<f64>, t_end: f64, parts: usize) -> (Radau5, Option<ContactEvent>) {
    let mut sim = Radau5::new(assembly(&system_of(None, parts)), options()).unwrap();
    if let Some(f) = threshold {
        sim.set_force_threshold(&(0..parts).collect::<Vec<_>>(), f).unwrap();
    }
    let mut event = None;
    while let Some(view) = sim.advance(t_end).unwrap() {
        event = view.events.iter().copied().find(|e| matches!(e.kind, ContactEventKind::Threshold { .. }));
        if event.is_some() {
            break;
        }
    }
    (sim, event)
}

#[test]
fn a_fuse_breaks_where_the_contact_force_reaches_its_threshold() {
    let (intact, event) = until_break(Some(5.0e4), 0.05);
    let event = event.expect("the fuse breaks");
    let w = (K / M).sqrt();
    let t_break = GAP / V0 + (0.5f64).asin() / w;
    assert!((event.time - t_break).abs() < 1e-8, "break at {} s, closed form {t_break} s", event.time);
    let ContactEventKind::Threshold { force } = event.kind else { unreachable!() };
    assert!((force / 5.0e4 - 1.0).abs() < 1e-5, "break force {force} N");
    let v_break = -V0 * (std::f64::consts::PI / 6.0).cos();
    assert!((intact.velocities()[0] / v_break - 1.0).abs() < 1e-6, "{} m/s", intact.velocities()[0]);

    // the wall freed: 200 kg against 20 kN of friction
    let freed = assembly(&system(Some((200.0, 2.0e4))));
    let mut sim = Radau5::resume(freed, options(), &intact).unwrap();
    let state = |s: &Radau5| (s.time(), s.positions()[0], s.velocities()[0]);
    assert_eq!(state(&sim), state(&intact));
    let e0 = *intact.energy();
    assert!(sim.run(0.2, &mut NoObserver).unwrap());
    let e = sim.energy();
    // the wall slid and stopped; the mass left it
    let (x_wall, v_wall) = (sim.positions()[1], sim.velocities()[1]);
    assert!(x_wall < -1e-3 && v_wall.abs() < 1e-3, "wall at {x_wall} m, {v_wall} m/s");
    assert!(e.friction > 0.0 && e0.friction == 0.0);
    // the wall's friction dissipates 20 kN times its slide (its speed
    // stays above v_eps but for the last micrometres)
    assert!((e.friction / (2.0e4 * -x_wall) - 1.0).abs() < 1e-3, "{} J over {x_wall} m", e.friction);
    let scale = 0.5 * M * V0 * V0;
    assert!(e.error().abs() < 1e-6 * scale, "energy balance error {} J", e.error());
}

#[test]
fn a_fuse_that_is_never_reached_changes_nothing() {
    let (with, event) = until_break(Some(2.0e5), 0.05);
    let (without, _) = until_break(None, 0.05);
    assert!(event.is_none());
    assert_eq!(
        (with.time(), with.positions(), with.velocities()),
        (without.time(), without.positions(), without.velocities())
    );
    assert_eq!(with.stats(), without.stats());
}

#[test]
fn a_fuse_held_by_two_contacts_breaks_on_their_sum() {
    // the wall's contact as two of K/2 each: the same motion, the same
    // break, reported on the first of the two
    let (_, one) = until_break(Some(5.0e4), 0.05);
    let (_, two) = until_break_of(Some(5.0e4), 0.05, 2);
    let (one, two) = (one.unwrap(), two.unwrap());
    assert!((one.time - two.time).abs() < 1e-9, "{} against {} s", one.time, two.time);
    assert_eq!(two.contact, 0);
    let ContactEventKind::Threshold { force } = two.kind else { unreachable!() };
    assert!((force / 5.0e4 - 1.0).abs() < 1e-5, "break force {force} N");
}

/// A wall that leaves the plane at the fuse's force (a fuse element): its
/// contact opens, the elastic energy `F^2 / (2 k)` it held (125 J at 50 kN
/// on 1e7 N/m) is booked as lost with it, the mass goes on at its speed at
/// the break, and the run resumes in a system whose contact, its number
/// kept, can no longer close; the energy balance closes.
#[test]
fn a_released_contact_books_the_energy_it_held_and_the_run_goes_on() {
    let (mut intact, event) = until_break(Some(5.0e4), 0.05);
    assert!(event.is_some());
    let v_break = intact.velocities()[0];
    let held = intact.release_contacts(&[0]).unwrap();
    let by_hand = 5.0e4 * 5.0e4 / (2.0 * K);
    assert!((held / by_hand - 1.0).abs() < 1e-4, "{held} J, by hand {by_hand} J");
    assert!(intact.release_contacts(&[1]).is_err(), "the system has one contact");
    // (the contact's edge 1 km away: it never closes)
    let mut sys = System::new();
    let mass = sys.add_body(Body::new("mass", M, 1.0, [0.0; 3]).only(&[Coord::X]));
    sys.add_force(ForceElement::Contact(Contact {
        body: mass,
        point: [0.0, 0.0],
        base: BodyId::GROUND,
        edge_point: [-1.0e3, 0.0],
        edge_normal: [1.0, 0.0],
        law: ContactLaw::Linear { stiffness: K, restitution: 1.0 },
        reduced_mass: None,
    }));
    let mut sim = Radau5::resume(assembly(&sys), options(), &intact).unwrap();
    assert!(sim.run(0.05, &mut NoObserver).unwrap());
    assert_eq!(sim.velocities()[0], v_break, "the mass flies on");
    let e = sim.energy();
    assert!((e.contact - held).abs() < 1e-12 * held, "booked {} J", e.contact);
    let scale = 0.5 * M * V0 * V0;
    assert!(e.error().abs() < 1e-6 * scale, "energy balance error {} J", e.error());
}
