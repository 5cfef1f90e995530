//! Analytic Jacobians against finite differences.
//!
//! Every force law and constraint provides its derivatives analytically; a
//! sign or lever-arm slip in one of them would still let a simulation run,
//! only slower or wrongly converged. Here the stiffness `K = -dF/dq`
//! (constraint Hessian included), damping `D = -dF/dv` and constraint
//! gradient `G = dg/dq` of a system containing every element and constraint
//! type are compared with central differences of the residual, computed with
//! Curtis-Powell-Reid colouring (serially and on the rayon pool), at random
//! states: sliding friction, sticking friction (the linear regime of the
//! regularised law) and random multipliers.

use quakejoint_solver::fd::{jacobian_with, Colouring};
use quakejoint_solver::reference::element_zoo;
use quakejoint_solver::{
    Assembly, AssemblyOptions, Body, BodyId, Contact, ContactLaw, Coord, ForceElement, HertzDamping, System,
};

fn lcg(seed: &mut u64) -> f64 {
    *seed = seed.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
    ((*seed >> 11) as f64 / (1u64 << 53) as f64) - 0.5
}

fn compare(name: &str, analytic: &[f64], fd: &[f64]) {
    let scale = analytic.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    assert!(scale > 0.0, "{name}: empty");
    let mut worst = 0.0f64;
    for (i, (a, f)) in analytic.iter().zip(fd).enumerate() {
        let err = (a - f).abs();
        worst = worst.max(err / scale);
        // entry-wise relative check for entries that matter
        if a.abs() > 1e-3 * scale {
            assert!(err <= 1e-6 * a.abs().max(1e-2 * scale), "{name}[{i}]: analytic {a}, finite difference {f}");
        }
    }
    assert!(worst <= 1e-6, "{name}: max relative difference {worst:e}");
}

fn check_state(asm: &Assembly, seed: u64, vscale: f64) {
    let mut s = seed;
    let (q0, _) = asm.initial_state();
    let q: Vec<f64> = q0.iter().map(|x| x + 0.3 * lcg(&mut s)).collect();
    let v: Vec<f64> = (0..q.len()).map(|_| vscale * 2.0 * lcg(&mut s)).collect();
    let lam: Vec<f64> = (0..asm.equations()).map(|_| 50.0 * lcg(&mut s)).collect();
    let t = 0.37;
    let mut ws = asm.workspace();
    let mut an = asm.jacobian_values();
    asm.jacobian(&mut ws, t, &q, &v, &lam, &mut an);
    for parallel in [false, true] {
        let col = Colouring::new(asm);
        assert!(col.colours() < asm.coordinates(), "colouring should group columns");
        let mut fd = asm.jacobian_values();
        jacobian_with(asm, &col, (t, &q, &v, &lam), &mut fd, parallel, None);
        compare("K", an.stiffness(), fd.stiffness());
        compare("D", an.damping(), fd.damping());
        compare("G", &an.g, &fd.g);
    }
}

#[test]
fn analytic_jacobian_matches_coloured_finite_differences_when_sliding() {
    let asm = Assembly::new(&element_zoo(), &AssemblyOptions::default()).unwrap();
    for seed in 1..6 {
        check_state(&asm, seed, 1.0);
    }
}

#[test]
fn analytic_jacobian_matches_coloured_finite_differences_when_sticking() {
    let asm = Assembly::new(&element_zoo(), &AssemblyOptions::default()).unwrap();
    for seed in 10..14 {
        check_state(&asm, seed, 1e-3);
    }
}

#[test]
fn dense_and_coloured_finite_differences_agree() {
    let asm = Assembly::new(&element_zoo(), &AssemblyOptions::default()).unwrap();
    let (q, v) = asm.initial_state();
    let lam = vec![1.0; asm.equations()];
    let mut a = asm.jacobian_values();
    let mut b = asm.jacobian_values();
    jacobian_with(&asm, &Colouring::new(&asm), (0.0, &q, &v, &lam), &mut a, false, None);
    jacobian_with(&asm, &Colouring::dense(&asm), (0.0, &q, &v, &lam), &mut b, false, None);
    compare("K", a.stiffness(), b.stiffness());
    compare("G", &a.g, &b.g);
}

/// Contacts of both laws between two free bodies (a point against a turned
/// edge), of a free body against the ground, and of a body restricted to x
/// against a free one: every contact closed, at states where the points
/// penetrate or not (the law is used as written for both signs inside a
/// closed contact).
fn contact_zoo(only: usize) -> System {
    let mut sys = System::new();
    let a = sys.add_body(Body::new("a", 3.0, 0.4, [0.3, 0.2, 0.3]));
    let b = sys.add_body(Body::new("b", 2.0, 0.3, [0.6, -0.1, -0.2]));
    let d = sys.add_body(Body::new("d", 5.0, 1.0, [1.0, 0.1, 0.0]).only(&[Coord::X]));
    let hertz = |damping| ContactLaw::Hertz { stiffness: 3e6, restitution: 0.6, damping };
    let contacts = [
        (a, [0.2, 0.1], b, [-0.1, 0.05], [-0.8, 0.6], ContactLaw::Linear { stiffness: 2e5, restitution: 0.7 }),
        (b, [0.1, -0.2], a, [0.1, 0.0], [0.6, 0.8], hertz(HertzDamping::YeLiZhu)),
        (a, [-0.1, 0.3], BodyId::GROUND, [0.1, 0.2], [0.0, -1.0], hertz(HertzDamping::LankaraniNikravesh)),
        (d, [-0.2, 0.1], b, [0.3, 0.1], [1.0, 0.0], ContactLaw::Linear { stiffness: 1e5, restitution: 0.5 }),
    ];
    for (body, point, base, edge_point, edge_normal, law) in contacts.into_iter().skip(only).take(1) {
        sys.add_force(ForceElement::Contact(Contact {
            body,
            point,
            base,
            edge_point,
            edge_normal,
            law,
            reduced_mass: None,
        }));
    }
    sys
}

#[test]
fn closed_contacts_match_finite_differences() {
    for (only, seed) in (0..4).flat_map(|k| (20..24).map(move |s| (k, s))) {
        eprintln!("contact {only}, seed {seed}");
        let asm = Assembly::new(&contact_zoo(only), &AssemblyOptions::default()).unwrap();
        let mut s = seed;
        let (q0, _) = asm.initial_state();
        let q: Vec<f64> = q0.iter().map(|x| x + 0.1 * lcg(&mut s)).collect();
        let v: Vec<f64> = (0..q.len()).map(|_| 2.0 * lcg(&mut s)).collect();
        let mut ws = asm.workspace();
        for i in 0..asm.contact_count() {
            ws.set_contact(i, true, 0.2 + 0.1 * i as f64);
        }
        let mut an = asm.jacobian_values();
        asm.jacobian(&mut ws, 0.0, &q, &v, &[], &mut an);
        let mut fd = asm.jacobian_values();
        jacobian_with(&asm, &Colouring::new(&asm), (0.0, &q, &v, &[]), &mut fd, false, Some(&ws));
        compare("K", an.stiffness(), fd.stiffness());
        compare("D", an.damping(), fd.damping());
    }
}
