//! The intercept theorem under a slow opening with friction off.
//!
//! A bearing keeps its place on its center beam while staying on its joist,
//! and the joist turns about its pivot to follow the deck's box point, so
//! every sub-gap changes by the same amount: the center beams stay equally
//! spaced, up to the bushings' compliance. A center beam is held in x only
//! through the joists' normals, so its compliance is the bushing's amplified
//! by `1 / sin^2(theta)`: the deviation must stay below the largest bushing
//! force (here from the small inertia forces of a slow opening) over
//! `k sin^2(theta_min)`. Each joist's angle follows `atan(dy / (G0 + u))`,
//! `dy` the box's transverse offset from the pivot.

mod common;

use std::sync::Arc;

use quakejoint_model::config::SupportKind;
use quakejoint_model::generator::{build, Drive};
use quakejoint_model::service::opening;
use quakejoint_solver::{Assembly, AssemblyOptions, Coord, IntegratorOptions, Observer, Radau5, StepView};

struct Check {
    cb_x: Vec<usize>,
    joists: Vec<(usize, f64)>,
    deck: usize,
    gap: f64,
    n: usize,
    worst_gap: f64,
    worst_angle: f64,
    worst_bushing: f64,
    u_range: (f64, f64),
}

impl Observer for Check {
    fn step(&mut self, view: &mut StepView<'_>) -> bool {
        let u = view.q[self.deck];
        self.u_range = (self.u_range.0.min(u), self.u_range.1.max(u));
        let pitch = (self.gap + u) / (self.n + 1) as f64;
        let mut prev = 0.0;
        for &c in &self.cb_x {
            self.worst_gap = self.worst_gap.max((view.q[c] - prev - pitch).abs());
            prev = view.q[c];
        }
        self.worst_gap = self.worst_gap.max((self.gap + u - prev - pitch).abs());
        for &(phi, dy) in &self.joists {
            self.worst_angle = self.worst_angle.max((view.q[phi] - dy.atan2(self.gap + u)).abs());
        }
        let x = view.assembly.force_extremes(view.workspace, view.q, view.v);
        self.worst_bushing = self.worst_bushing.max(x.bushing);
        true
    }
}

#[test]
fn sub_gaps_stay_equal_and_joists_follow_the_deck() {
    let mut config = common::shipped("medium.toml");
    config.joint.friction.mu = 0.0;
    config.service.speed = 0.02;
    config.service.amplitude = 0.1;
    config.service.blend = 1.0;
    config.service.cycles = 1;
    let tri = opening(&config).unwrap();
    let model = build(&config, None, Drive::Service(tri.clone())).unwrap();
    let asm = Arc::new(Assembly::new(&model.system, &AssemblyOptions::default()).unwrap());
    let geo = model.geometry.clone().unwrap();
    let mut check = Check {
        cb_x: model.center_beams.iter().map(|&b| asm.coordinate(b, Coord::X).unwrap()).collect(),
        joists: geo
            .supports
            .iter()
            .zip(&model.supports)
            .filter(|(s, _)| s.kind == SupportKind::Joist)
            .map(|(s, &b)| (asm.coordinate(b, Coord::Phi).unwrap(), s.box_dy))
            .collect(),
        deck: asm.coordinate(model.deck, Coord::X).unwrap(),
        gap: geo.gap,
        n: geo.center_beams,
        worst_gap: 0.0,
        worst_angle: 0.0,
        worst_bushing: 0.0,
        u_range: (0.0, 0.0),
    };
    let mut sim = Radau5::new(asm, IntegratorOptions::default()).unwrap();
    sim.run(tri.period(), &mut check).unwrap();
    assert!(check.u_range.0 < -0.099 && check.u_range.1 > 0.099, "opened and closed: {:?}", check.u_range);
    let sin2_min = geo
        .supports
        .iter()
        .filter(|s| s.kind == SupportKind::Joist)
        .map(|s| s.theta.sin().powi(2))
        .fold(f64::INFINITY, f64::min);
    let compliance = check.worst_bushing / (config.joint.bushing.kx.min(config.joint.bushing.ky) * sin2_min);
    eprintln!(
        "largest deviation from equal spacing {:.2e} m (bushing force {:.2e} N, compliance {:.2e} m), angle {:.2e} rad",
        check.worst_gap, check.worst_bushing, compliance, check.worst_angle
    );
    assert!(check.worst_gap <= compliance, "sub-gaps not equal: {:e} m > {compliance:e} m", check.worst_gap);
    assert!(check.worst_gap < 1e-4, "sub-gaps not equal: {:e} m", check.worst_gap);
    assert!(check.worst_angle < 1e-6, "joist angle off by {:e} rad", check.worst_angle);
}
