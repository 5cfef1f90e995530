//! The service case: the deck is driven kinematically, opening and closing
//! the joint at constant speed (a triangle wave of opening `u(t)` with
//! rounded reversals), and the joint's reaction on the deck is recorded
//! against `u` (a hysteresis loop). The friction work per cycle is compared
//! with a hand calculation: each bearing slides along its support beam by the
//! change of its distance from the pivot, `l_ik(u) = i/(Nc + 1) * sqrt((G0 +
//! u)^2 + dy_k^2)` for a joist (`dy_k = G0 tan theta_k`) and `i (G0 + u)/(Nc +
//! 1)` for a guide, so one cycle (u from 0 to +A, to -A, back to 0) costs
//! `sum_ik mu n_s F_N * 2 |l_ik(A) - l_ik(-A)|`.

use std::sync::Arc;
use std::time::Instant;

use quakejoint_solver::{Assembly, AssemblyOptions, Coord, Observer, Radau5, SmoothTriangle, Stats, StepView};

use crate::config::{Config, SupportKind};
use crate::error::ModelError;
use crate::generator::{build, Drive};
use crate::geometry::Geometry;
use crate::run::integrator_options;

/// Results of a service run (SI units).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct ServiceResult {
    /// Period of one opening-closing cycle [s].
    pub period: f64,
    /// Number of cycles run.
    pub cycles: u32,
    /// Energy dissipated by friction during the last cycle [J].
    pub friction_work_per_cycle: f64,
    /// Work done by the deck on the joint during the last cycle, the area of
    /// the hysteresis loop `-closed integral F_joint du` [J].
    pub loop_work_per_cycle: f64,
    /// The hand calculation of the friction work per cycle [J].
    pub hand_calculation: f64,
    /// Largest force of the joint on the deck [N].
    pub peak_joint_force: f64,
    /// Output times [s].
    pub t: Vec<f64>,
    /// Deck opening at the output times [m].
    pub u: Vec<f64>,
    /// Force of the joint on the deck (x) at the output times [N].
    pub joint_force: Vec<f64>,
    /// Energy-balance error relative to the work put in [-].
    pub energy_error: f64,
    /// Largest |g| [m or rad].
    pub max_position_residual: f64,
    /// Largest |G q' + g_t| [m/s or rad/s].
    pub max_velocity_residual: f64,
    /// Solver counters.
    pub stats: Stats,
    /// Wall-clock time [s].
    pub wall_time_s: f64,
}

/// The opening history of the service case.
pub fn opening(config: &Config) -> Result<SmoothTriangle, ModelError> {
    let s = &config.service;
    Ok(SmoothTriangle::new(s.amplitude, s.speed, s.blend)?)
}

/// Friction work per cycle by hand (see the module documentation) [J].
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

struct LoopObserver {
    deck: usize,
    deck_body: quakejoint_solver::BodyId,
    boxes: Vec<quakejoint_solver::ConstraintId>,
    dt: f64,
    next: u64,
    t: Vec<f64>,
    u: Vec<f64>,
    f: Vec<f64>,
    q: Vec<f64>,
    v: Vec<f64>,
    l: Vec<f64>,
}

impl Observer for LoopObserver {
    fn step(&mut self, view: &mut StepView<'_>) -> bool {
        loop {
            let tj = (self.next + 1) as f64 * self.dt;
            if tj > view.t + 1e-9 * self.dt {
                break;
            }
            self.next += 1;
            view.interpolate(tj, &mut self.q, &mut self.v, &mut self.l);
            let fj = view.assembly.reaction_sum(view.workspace, tj, &self.q, &self.l, &self.boxes, self.deck_body)[0];
            self.t.push(tj);
            self.u.push(self.q[self.deck]);
            self.f.push(fj);
        }
        true
    }
}

/// Runs the service case of `config`.
pub fn service(config: &Config) -> Result<ServiceResult, ModelError> {
    let tri = opening(config)?;
    let period = tri.period();
    let cycles = config.service.cycles;
    let model = build(config, None, Drive::Service(tri))?;
    if model.joist_boxes.is_empty() && model.geometry.is_none() {
        return Err(ModelError::Invalid {
            field: "joint.enabled".to_string(),
            value: "false".to_string(),
            reason: "the service case needs the joint".to_string(),
        });
    }
    let asm = Arc::new(Assembly::new(&model.system, &AssemblyOptions::default())?);
    let deck = asm.coordinate(model.deck, Coord::X).ok_or_else(|| ModelError::Geometry("deck has no x".into()))?;
    let (n, m) = (asm.coordinates(), asm.equations());
    let mut obs = LoopObserver {
        deck,
        deck_body: model.deck,
        boxes: model.joist_boxes.clone(),
        dt: period / 1000.0,
        next: 0,
        t: Vec::new(),
        u: Vec::new(),
        f: Vec::new(),
        q: vec![0.0; n],
        v: vec![0.0; n],
        l: vec![0.0; m],
    };
    let start = Instant::now();
    let mut sim = Radau5::new(asm, integrator_options(config))?;
    let t_end = cycles as f64 * period;
    sim.run(t_end - period, &mut obs)?;
    let before = sim.energy().friction;
    let first_sample = obs.t.len();
    sim.run(t_end, &mut obs)?;
    let e = sim.energy();
    // hysteresis loop area over the last cycle (trapezoid over the samples)
    let mut loop_work = 0.0;
    let k0 = first_sample.saturating_sub(1);
    for k in k0..obs.t.len().saturating_sub(1) {
        loop_work -= 0.5 * (obs.f[k] + obs.f[k + 1]) * (obs.u[k + 1] - obs.u[k]);
    }
    let (g, gv) = sim.max_constraint_residuals();
    Ok(ServiceResult {
        period,
        cycles,
        friction_work_per_cycle: e.friction - before,
        loop_work_per_cycle: loop_work,
        hand_calculation: hand_friction_work_per_cycle(config)?,
        peak_joint_force: obs.f.iter().fold(0.0, |m, x| m.max(x.abs())),
        t: obs.t,
        u: obs.u,
        joint_force: obs.f,
        energy_error: e.error_relative_to_input(),
        max_position_residual: g,
        max_velocity_residual: gv,
        stats: sim.stats(),
        wall_time_s: start.elapsed().as_secs_f64(),
    })
}
