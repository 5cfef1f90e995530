//! The service case: the deck is driven kinematically, opening and closing
//! the joint at constant speed (a triangle wave of opening `u(t)` with
//! rounded reversals), and the joint's reaction on the deck is recorded
//! against `u` (a hysteresis loop). The friction work per cycle is compared
//! with a hand calculation: each bearing slides along its support beam by the
//! change of its distance from the pivot, `l_ik(u) = i/(Nc + 1) * sqrt((G0 +
//! u)^2 + dy_k^2)` for a joist (`dy_k = G0 tan theta_k`) and `i (G0 + u)/(Nc +
//! 1)` for a guide, so one cycle (u from 0 to +A, to -A, back to 0) costs
//! `sum_ik mu n_s F_N * 2 |l_ik(A) - l_ik(-A)|`.
//!
//! That is the limit of rigid bushings. With compliant bushings each center
//! beam lags its intercept position while its bearings slide (held in x
//! only by the small x component of the joists' normal forces), the lag
//! flips at every reversal, and the bearings stick while it flips: each
//! reversal costs a sliding distance that does not depend on the amplitude.
//! [`compliance_deficit`] computes that loss in closed form (quasi-static,
//! linear in the bushing compliance): for each center beam and sliding
//! direction `s`, the bearing forces are `-s F` along each support line and
//! a normal reaction; the bushing deflections follow from the bushings'
//! stiffness, and the beam's displacement `dq = (dx, dy, dphi)` from its
//! equilibrium, a 3 x 3 linear system. The lag of bearing j along its line
//! is `e_j(s)`; a reversal costs `F |e_j(+1) - e_j(-1)|` per bearing, summed
//! at both reversals `u = +A` and `u = -A`. It is an upper estimate: the
//! beams' inertia at the rounded reversals carries them part of the way
//! (docs/model.md, "The service case").

use std::sync::Arc;
use std::time::Instant;

use quakejoint_solver::{
    Assembly, AssemblyOptions, Coord, Observer, OutputTimes, Radau5, SmoothTriangle, StateBuffer, Stats, StepView,
};

use crate::config::{Config, SupportKind};
use crate::error::ModelError;
use crate::generator::{build, Drive};
use crate::geometry::Geometry;
use crate::pounding::ContactWatch;
use crate::run::{integrator_options, DENSE_OUTPUT};
use crate::validity::{Monitor, Validity};
use crate::watch::Gaps;

/// Results of a service run (SI units).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct ServiceResult {
    /// Period of one opening-closing cycle \[s\].
    pub period: f64,
    /// Number of cycles run.
    pub cycles: u32,
    /// Energy dissipated by friction during the last cycle \[J\].
    pub friction_work_per_cycle: f64,
    /// Work done by the deck on the joint during the last cycle, the area of
    /// the hysteresis loop `-closed integral F_joint du` \[J\].
    pub loop_work_per_cycle: f64,
    /// The hand calculation of the friction work per cycle, rigid bushings \[J\].
    pub hand_calculation: f64,
    /// The expected loss of friction work per cycle from the bushings'
    /// compliance, closed form ([`compliance_deficit`]) \[J\]; None when a
    /// center beam's position is not fixed by its bearings.
    pub compliance_deficit: Option<f64>,
    /// What the comparison with the hand calculation means, when it needs
    /// saying (the deficit is large, or the simulation lies outside what it
    /// explains).
    pub warnings: Vec<String>,
    /// x, y and angle of each center beam at the output times, from their
    /// reference positions, `[beam][time]` [m, m, rad].
    pub center_beams: [Vec<Vec<f64>>; 3],
    /// Energy dissipated by the bushings' dampers during the last cycle \[J\]
    /// (with the friction work, what the loop area should equal).
    pub damping_work_per_cycle: f64,
    /// Energy dissipated by impacts between beams during the last cycle \[J\]
    /// (0 unless a sub-gap closes).
    pub contact_work_per_cycle: f64,
    /// Smallest and largest clear sub-gap over the run, at either end of
    /// the center beams \[m\].
    pub min_subgap: f64,
    /// Largest clear sub-gap \[m\].
    pub max_subgap: f64,
    /// Whether the run stayed inside what the model can stand behind
    /// (collision, bearing off its support, joist pulled out, energy
    /// balance), as for an earthquake run.
    pub validity: Validity,
    /// Largest force of the joint on the deck \[N\].
    pub peak_joint_force: f64,
    /// Output times \[s\].
    pub t: Vec<f64>,
    /// Deck opening at the output times \[m\].
    pub u: Vec<f64>,
    /// Force of the joint on the deck (x) at the output times \[N\].
    pub joint_force: Vec<f64>,
    /// Energy-balance error relative to the work put in [-].
    pub energy_error: f64,
    /// Largest constraint residuals, by kind and unit.
    pub residuals: quakejoint_solver::ConstraintResiduals,
    /// Solver counters.
    pub stats: Stats,
    /// Wall-clock time \[s\].
    pub wall_time_s: f64,
}

/// The opening history of the service case.
pub fn opening(config: &Config) -> Result<SmoothTriangle, ModelError> {
    let s = &config.service;
    Ok(SmoothTriangle::new(s.amplitude, s.speed, s.blend)?)
}

/// Friction work per cycle by hand (see the module documentation) \[J\].
pub fn hand_friction_work_per_cycle(config: &Config) -> Result<f64, ModelError> {
    let geo = Geometry::new(config)?;
    let f = &config.joint.friction;
    let force = f.mu * f.surfaces * f.normal_force;
    let a = config.service.amplitude;
    let n1 = (geo.center_beams + 1) as f64;
    let mut distance = 0.0;
    for s in &geo.supports {
        for i in 1..=geo.center_beams {
            let l = |u: f64| match s.kind {
                SupportKind::Joist => i as f64 / n1 * ((geo.gap + u).powi(2) + s.box_dy.powi(2)).sqrt(),
                SupportKind::Guide => i as f64 * (geo.gap + u) / n1,
            };
            distance += 2.0 * (l(a) - l(-a)).abs();
        }
    }
    Ok(force * distance)
}

/// Solves the 3 x 3 system `m x = b` by Gaussian elimination with partial
/// pivoting; None if `m` is singular to working precision.
fn solve3(mut m: [[f64; 3]; 3], mut b: [f64; 3]) -> Option<[f64; 3]> {
    let scale = m.iter().flatten().fold(0.0f64, |a, x| a.max(x.abs()));
    for c in 0..3 {
        let p = (c..3).max_by(|&i, &j| m[i][c].abs().total_cmp(&m[j][c].abs()))?;
        // NaN fails the test too
        if m[p][c].abs().partial_cmp(&(1e-12 * scale)) != Some(std::cmp::Ordering::Greater) {
            return None;
        }
        m.swap(c, p);
        b.swap(c, p);
        let pivot = m[c];
        for r in c + 1..3 {
            let f = m[r][c] / pivot[c];
            for (x, &y) in m[r][c..].iter_mut().zip(&pivot[c..]) {
                *x -= f * y;
            }
            b[r] -= f * b[c];
        }
    }
    let mut x = [0.0; 3];
    for r in (0..3).rev() {
        let sum: f64 = (r + 1..3).map(|k| m[r][k] * x[k]).sum();
        x[r] = (b[r] - sum) / m[r][r];
    }
    Some(x)
}

/// The loss of friction work per cycle that the bushings' compliance causes
/// against the rigid-bushing hand calculation, in closed form (see the
/// module documentation) \[J\]; None when a center beam is not held by its
/// bearings (a singular 3 x 3 system, or a bushing without stiffness).
pub fn compliance_deficit(config: &Config) -> Result<Option<f64>, ModelError> {
    let geo = Geometry::new(config)?;
    let j = &config.joint;
    let f = j.friction.mu * j.friction.surfaces * j.friction.normal_force;
    let (kx, ky) = (j.bushing.kx, j.bushing.ky);
    if f == 0.0 {
        return Ok(Some(0.0));
    }
    if !(kx > 0.0 && ky > 0.0) {
        return Ok(None);
    }
    let a = config.service.amplitude;
    let mut loss = 0.0;
    for u in [a, -a] {
        // tangent of each support line at opening u
        let tangents: Vec<[f64; 2]> = geo
            .supports
            .iter()
            .map(|s| match s.kind {
                SupportKind::Joist => {
                    let l = (geo.gap + u).hypot(s.box_dy);
                    [(geo.gap + u) / l, s.box_dy / l]
                }
                SupportKind::Guide => [1.0, 0.0],
            })
            .collect();
        for ys in &geo.bearing_y {
            // per bearing: d = a1 * (-s F) + a2 * (-(g_n . dq)), with
            // [a1 a2] = [t^T K; n^T]^-1; beam equilibrium sum G K d = 0
            let mut m = [[0.0; 3]; 3];
            let mut rhs = [0.0; 3];
            let mut parts = Vec::with_capacity(ys.len());
            for (&y, t) in ys.iter().zip(&tangents) {
                let n = [-t[1], t[0]];
                let (p, q) = (kx * t[0], ky * t[1]); // t^T K
                let det = p * n[1] - q * n[0];
                let a1 = [n[1] / det, -n[0] / det];
                let a2 = [-q / det, p / det];
                let g_of = |v: [f64; 2]| [v[0], v[1], -y * v[0]];
                let gk = |d: [f64; 2]| g_of([kx * d[0], ky * d[1]]);
                let (gn, ga1, ga2) = (g_of(n), gk(a1), gk(a2));
                for r in 0..3 {
                    rhs[r] += ga1[r];
                    for c in 0..3 {
                        m[r][c] += ga2[r] * gn[c];
                    }
                }
                parts.push((t, y, a1, a2, gn));
            }
            // dq for s = +1 (the lag flips sign with s, it is linear in F)
            let Some(dq) = solve3(m, [-f * rhs[0], -f * rhs[1], -f * rhs[2]]) else { return Ok(None) };
            for (t, y, a1, a2, gn) in parts {
                let gn_dq = gn[0] * dq[0] + gn[1] * dq[1] + gn[2] * dq[2];
                let d = [-f * a1[0] - gn_dq * a2[0], -f * a1[1] - gn_dq * a2[1]];
                let moved = [dq[0] - y * dq[2], dq[1]];
                let lag = t[0] * (d[0] + moved[0]) + t[1] * (d[1] + moved[1]);
                // e(+1) - e(-1) = 2 lag
                loss += f * 2.0 * lag.abs();
            }
        }
    }
    Ok(Some(loss))
}

/// Deviation of the friction work from the hand calculation beyond which it
/// is reported, as a fraction of the hand calculation [-].
pub const SERVICE_TOLERANCE: f64 = 0.05;

/// Warnings on the comparison of the simulated friction work with the hand
/// calculation and the closed-form compliance deficit.
fn service_warnings(config: &Config, work: f64, hand: f64, deficit: Option<f64>) -> Vec<String> {
    let mut out = Vec::new();
    let b = &config.joint.bushing;
    let rel = |x: f64| 100.0 * x / hand;
    match deficit {
        None => out.push(
            "the expected effect of the bushings' compliance cannot be computed (a center beam is not held by its \
             bearings, or a bushing has no stiffness): the hand calculation is a rigid-bushing estimate only"
                .to_string(),
        ),
        Some(d) if d > SERVICE_TOLERANCE * hand => out.push(format!(
            "the hand calculation assumes rigid bushings; with these (kx = {:e}, ky = {:e} N/m) the center beams lag \
             their intercept positions and the bearings stick at each reversal, which costs up to {:.1} % of the \
             friction work (closed form); stiffer bushings (e.g. 1e9 N/m) bring the two together",
            b.kx,
            b.ky,
            rel(d)
        )),
        _ => {}
    }
    if hand > 0.0 {
        let low = hand - deficit.unwrap_or(0.0) - SERVICE_TOLERANCE * hand;
        let high = hand * (1.0 + SERVICE_TOLERANCE);
        if work < low || work > high {
            out.push(format!(
                "the friction work per cycle differs from the hand calculation by {:+.1} %, outside what the \
                 bushings' compliance explains ({:+.1} to 0 %, +/- {} %): look at the hysteresis loop and the center \
                 beams' drift in the output",
                rel(work - hand),
                -rel(deficit.unwrap_or(0.0)),
                100.0 * SERVICE_TOLERANCE
            ));
        }
    }
    out
}

/// Largest difference between the loop area and the work dissipated in
/// the same cycle (friction, dampers and impacts), as a fraction of the
/// latter [-].
pub const LOOP_TOLERANCE: f64 = 0.05;

/// Warnings on the hysteresis loop itself: over a closed cycle of a steady
/// state the deck's work on the joint (the loop area) equals the work
/// dissipated by friction, dampers and impacts, whatever the compliance; if not,
/// the cycle is not a steady quasi-static loop (reversals so abrupt that the
/// beams are still swinging, or too few cycles), and the loop says little.
fn loop_warnings(config: &Config, loop_work: f64, dissipated: f64) -> Vec<String> {
    let s = &config.service;
    let mut out = Vec::new();
    if loop_work < 0.0 {
        out.push(format!(
            "the hysteresis loop has a negative area ({loop_work:.1} J): the joint gave work back to the deck over \
              the cycle, which a dissipative joint in a steady cycle cannot; the reversals are too abrupt for a \
              quasi-static service loop (service.speed = {} m/s, service.blend = {} s: the deck's acceleration at a \
              reversal is {:.3} m/s^2); lower the speed or lengthen the blend",
            s.speed,
            s.blend,
            2.0 * s.speed / s.blend
        ));
    } else if (loop_work - dissipated).abs() > LOOP_TOLERANCE * dissipated.abs().max(1e-9) {
        out.push(format!(
            "the loop area ({loop_work:.1} J) differs from the work dissipated in the same cycle ({dissipated:.1} J \
             by friction, dampers and impacts) by more than {} %: the last cycle is not a steady quasi-static loop (raise \
              service.cycles, lower service.speed or lengthen service.blend)",
            100.0 * LOOP_TOLERANCE
        ));
    }
    out
}

struct LoopObserver {
    deck: usize,
    gaps: Gaps,
    monitor: Option<Monitor>,
    contacts: Option<ContactWatch>,
    /// x, y, phi coordinates of each center beam and their reference values.
    beams: Vec<[(usize, f64); 3]>,
    center_beams: [Vec<Vec<f64>>; 3],
    deck_body: quakejoint_solver::BodyId,
    boxes: Vec<quakejoint_solver::ConstraintId>,
    /// The output times, every thousandth of the cycle.
    outputs: OutputTimes,
    t: Vec<f64>,
    u: Vec<f64>,
    f: Vec<f64>,
    /// Scratch: the state at an output time.
    state: StateBuffer,
}

impl Observer for LoopObserver {
    fn step(&mut self, view: &mut StepView<'_>) -> bool {
        if let Some(c) = &mut self.contacts {
            c.step(view, self.monitor.as_mut());
        }
        while let Some(out) = self.outputs.next_in(view) {
            let tj = out.t();
            let s = &mut self.state;
            view.sample(&out, s).expect(DENSE_OUTPUT);
            // the joist boxes, and the deck's edge beam once the joint is closed
            let pushed = match &mut self.contacts {
                Some(c) => c.at(view.assembly, view.workspace, &s.q, &s.v, None),
                None => 0.0,
            };
            let fj = view.assembly.reaction_sum(view.workspace, tj, &s.q, &s.lambda, &self.boxes, self.deck_body)[0]
                + pushed;
            self.gaps.check(tj, &s.q, s.q[self.deck], self.monitor.as_mut());
            self.t.push(tj);
            self.u.push(s.q[self.deck]);
            self.f.push(fj);
            for (i, coords) in self.beams.iter().enumerate() {
                for (c, &(index, reference)) in coords.iter().enumerate() {
                    self.center_beams[c][i].push(s.q[index] - reference);
                }
            }
        }
        true
    }
}

/// Runs the service case of a scenario (its `[service]` with a front
/// end's overrides: [`crate::runspec::Overrides`]).
pub fn service(scenario: &crate::scenario::Scenario) -> Result<ServiceResult, ModelError> {
    let config = &scenario.config;
    let tri = opening(config)?;
    let period = tri.period();
    let cycles = config.service.cycles;
    // the deck's motion is prescribed: its own spring and damper do not act
    // on the joint, and without the damper the energy balance's damping
    // term is the joint's dampers alone
    let mut driven = config.clone();
    driven.bridge.damping = 0.0;
    // the service case opens the joint along the bridge only, against the
    // abutment: the deck does not move across
    (driven.bridge.transverse_period, driven.bridge.transverse_damping) = (None, None);
    // and against the abutment: an adjacent segment would be pushed away
    driven.bridge.far = None;
    let closing = config.joint.cells() as f64 * config.joint.clear_subgap();
    if config.joint.fuse.is_some() && config.joint.enabled && tri.amplitude >= closing {
        return Err(ModelError::Invalid {
            field: "service.amplitude".to_string(),
            value: quakejoint_motion::number(tri.amplitude),
            reason: format!(
                "closes the whole joint (its closing movement is {} m): with [joint.fuse] that would break the fuse, \
                 which the service case does not model; lower the amplitude",
                quakejoint_motion::number(closing)
            ),
        });
    }
    let model = build(&driven, None, Drive::Service(tri))?;
    if model.joist_boxes.is_empty() && model.geometry.is_none() {
        return Err(ModelError::Invalid {
            field: "joint.enabled".to_string(),
            value: "false".to_string(),
            reason: "the service case needs the joint".to_string(),
        });
    }
    let asm = Arc::new(Assembly::new(&model.system, &AssemblyOptions::default())?);
    let deck = asm.coordinate(model.deck, Coord::X).ok_or_else(|| ModelError::Geometry("deck has no x".into()))?;
    let geo = model.geometry.as_ref().ok_or_else(|| ModelError::Geometry("the service case needs the joint".into()))?;
    let coord =
        |b, c| asm.coordinate(b, c).ok_or_else(|| ModelError::Geometry("a center beam lacks a coordinate".into()));
    let beams = model
        .center_beams
        .iter()
        .zip(&geo.center_x)
        .map(|(&b, &x)| Ok([(coord(b, Coord::X)?, x), (coord(b, Coord::Y)?, 0.0), (coord(b, Coord::Phi)?, 0.0)]))
        .collect::<Result<Vec<_>, ModelError>>()?;
    let nb = beams.len();
    let gaps =
        Gaps::new(&model, &asm)?.ok_or_else(|| ModelError::Geometry("the service case needs the joint".into()))?;
    let monitor = Monitor::new(&model, &asm, config)?;
    let mut obs = LoopObserver {
        deck,
        gaps,
        monitor,
        contacts: ContactWatch::new(&model, model.contacts.len()),
        beams,
        center_beams: [vec![Vec::new(); nb], vec![Vec::new(); nb], vec![Vec::new(); nb]],
        deck_body: model.deck,
        boxes: model.joist_boxes.clone(),
        outputs: OutputTimes::uniform(0.0, period / 1000.0).map_err(|e| ModelError::Invalid {
            field: "service".into(),
            value: period.to_string(),
            reason: e.to_string(),
        })?,
        t: Vec::new(),
        u: Vec::new(),
        f: Vec::new(),
        state: StateBuffer::new(&asm),
    };
    let start = Instant::now();
    let mut sim = Radau5::new(asm, integrator_options(config))?;
    let t_end = cycles as f64 * period;
    sim.run(t_end - period, &mut obs)?;
    let before = *sim.energy();
    let first_sample = obs.t.len();
    sim.run(t_end, &mut obs)?;
    let e = sim.energy();
    // hysteresis loop area over the last cycle (trapezoid over the samples)
    let mut loop_work = 0.0;
    let k0 = first_sample.saturating_sub(1);
    for k in k0..obs.t.len().saturating_sub(1) {
        loop_work -= 0.5 * (obs.f[k] + obs.f[k + 1]) * (obs.u[k + 1] - obs.u[k]);
    }
    let work = e.friction - before.friction;
    let damping_work = e.damping - before.damping;
    let contact_work = e.contact - before.contact;
    let hand = hand_friction_work_per_cycle(config)?;
    let deficit = compliance_deficit(config)?;
    let energy_error = e.error_relative_to_input();
    let validity = match &obs.monitor {
        Some(m) => m.validity(energy_error),
        None => Validity::not_checked("no joint"),
    };
    let mut warnings = service_warnings(config, work, hand, deficit);
    warnings.extend(loop_warnings(config, loop_work, work + damping_work + contact_work));
    Ok(ServiceResult {
        period,
        cycles,
        friction_work_per_cycle: work,
        loop_work_per_cycle: loop_work,
        hand_calculation: hand,
        compliance_deficit: deficit,
        warnings,
        damping_work_per_cycle: damping_work,
        contact_work_per_cycle: contact_work,
        min_subgap: obs.gaps.min,
        max_subgap: obs.gaps.max,
        validity,
        center_beams: obs.center_beams,
        peak_joint_force: obs.f.iter().fold(0.0, |m, x| m.max(x.abs())),
        t: obs.t,
        u: obs.u,
        joint_force: obs.f,
        energy_error,
        residuals: sim.constraint_residuals(),
        stats: sim.stats(),
        wall_time_s: start.elapsed().as_secs_f64(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The loop's own energy balance: a loop whose area matches what was
    /// dissipated passes, one that does not or runs backwards is warned
    /// about.
    #[test]
    fn a_loop_that_is_not_steady_or_runs_backwards_is_warned_about() {
        let config = Config::default();
        assert!(loop_warnings(&config, 1000.0, 1010.0).is_empty());
        let w = loop_warnings(&config, 1000.0, 1100.0);
        assert!(w.len() == 1 && w[0].contains("not a steady quasi-static loop"), "{w:?}");
        let w = loop_warnings(&config, -5.0, 10.0);
        assert!(w.len() == 1 && w[0].contains("negative area"), "{w:?}");
    }
}
