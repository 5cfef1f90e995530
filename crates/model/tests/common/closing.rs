//! The small joint driven shut and open again, for the fuses' hand
//! calculations (`fuse_box.rs`, `fuse_element.rs`).
//!
//! The small joint with 3 center beams (4 cells with a clear sub-gap of
//! [`CLEAR`]) carried on two guides along x by frictionless bearings (no
//! swivel joists, whose skew would hold the beams through the bushings),
//! its beams touching through linear contacts of [`K_END`] at each end.
//! The deck is driven shut and open again, `u(t) = -A/2 (1 - cos(w t))`
//! over [`PERIOD`]. With nothing holding the beams, every cell carries the
//! same force once the joint has closed: the cells' two ends in parallel
//! and the cells in series.

use std::sync::Arc;

use quakejoint_model::generator::{build, Drive, JointModel};
use quakejoint_model::run::fuse::{run_with_fuses, Freed, FuseObserver, FuseResult, FuseWatch};
use quakejoint_model::{Config, ModelError};
use quakejoint_solver::{
    Assembly, AssemblyOptions, Constraint, ContactValue, Coord, Driver, Observer, Radau5, StepView, TimeFunction,
};

/// The closing's period \[s\].
pub const PERIOD: f64 = 40.0;
/// A contact's stiffness at one end of a cell \[N/m\].
pub const K_END: f64 = 1.0e7;
/// The cells' clear width at rest \[m\] (`pitch - center_beam.width`,
/// the defaults).
pub const CLEAR: f64 = 0.04;
/// A center beam's width \[m\] (the default).
pub const WIDTH: f64 = 0.09;
/// The joint's cells.
pub const CELLS: f64 = 4.0;
/// The longest step \[s\]: the deck's force is watched at the steps'
/// ends, and near its turning point the solver takes steps of seconds
/// (the peak then falls between them, 7 % short in `fuse_element.rs`).
const H_MAX: f64 = 0.05;

/// The small joint on frictionless bearings with linear contacts, and
/// `fuse` (a `[joint.fuse]` table's body, or none).
pub fn config(fuse: Option<&str>) -> Config {
    let fuse = fuse.map_or(String::new(), |f| format!("[joint.fuse]\n{f}\n"));
    let text = format!(
        r#"
[joint]
center_beams = 3
[[joint.support_beams]]
kind = "guide"
y = -5.0
[[joint.support_beams]]
kind = "guide"
y = 5.0
[joint.friction]
mu = 0.0
[joint.contact]
law = "linear"
linear_stiffness = {K_END}
{fuse}
[bridge]
mass = 1.0e4
period = 10.0
[simulation]
rtol = 1e-7
h_max = {H_MAX}
"#
    );
    Config::from_toml(&text, "closing.toml").unwrap()
}

/// The joint's model with its deck driven shut by `amplitude` \[m\] and
/// open again.
fn driven(config: &Config, amplitude: f64) -> JointModel {
    let mut model = build(config, None, Drive::None).unwrap();
    let w = 2.0 * std::f64::consts::PI / PERIOD;
    let (a, phase) = (0.5 * amplitude, 0.5 * std::f64::consts::PI);
    let motion = TimeFunction::Harmonic { amplitude: a, omega: w, phase, offset: -a };
    model.system.add_constraint(Constraint::Driver(Driver { body: model.deck, coord: Coord::X, motion }));
    model
}

/// When the deck has closed the joint by `closing` \[m\] \[s\].
pub fn time_of_closing(closing: f64, amplitude: f64) -> f64 {
    let w = 2.0 * std::f64::consts::PI / PERIOD;
    (1.0 - 2.0 * closing / amplitude).acos() / w
}

/// Watches the fuse of a run's one joint, and the force of its last cell's
/// contacts on the deck at every step's end.
struct Watch {
    fuse: Option<FuseWatch>,
    /// The solver's numbers of the contacts at the deck.
    deck: [usize; 2],
    values: Vec<ContactValue>,
    peak_deck_force: f64,
}

impl Observer for Watch {
    fn step(&mut self, view: &mut StepView<'_>) -> bool {
        self.values.resize(view.assembly.contact_count(), ContactValue::default());
        view.assembly.contacts(view.workspace, view.q, view.v, &mut self.values);
        let force: f64 = self.deck.iter().map(|&i| self.values[i]).filter(|c| c.closed).map(|c| c.force).sum();
        self.peak_deck_force = self.peak_deck_force.max(force);
        let Some(f) = &mut self.fuse else { return true };
        let broke = f.step(view.events);
        f.sample(view.assembly, view.workspace, view.q, view.v);
        !broke
    }
}

impl FuseObserver for Watch {
    fn take_break(&mut self) -> Option<usize> {
        self.fuse.as_mut().is_some_and(|f| f.take_pending()).then_some(0)
    }

    fn resumed(&mut self, asm: &Assembly, freed: &[(usize, Freed)]) -> Result<(), ModelError> {
        let fuse = self.fuse.as_mut().unwrap();
        match freed[0].1 {
            Freed::Edge(parts) => fuse.freed(asm.coordinate(parts.edge, Coord::X).unwrap(), parts),
            Freed::Beam { energy, .. } => fuse.released(energy),
        }
        Ok(())
    }
}

/// What a closing run gives: the solver at its end, what the fuse did and
/// the largest force of the joint's last cell on the deck at a step's end
/// \[N\].
pub struct Closed {
    pub sim: Radau5,
    pub fuse: Option<FuseResult>,
    pub peak_deck_force: f64,
}

/// The run of `config`'s joint closed by `amplitude` \[m\] and reopened.
pub fn run(config: &Config, amplitude: f64) -> Closed {
    let model = driven(config, amplitude);
    let asm = Arc::new(Assembly::new(&model.system, &AssemblyOptions::default()).unwrap());
    let options = quakejoint_model::run::integrator_options(config);
    let sim = Radau5::new(asm, options.clone()).unwrap();
    let last = model.first_contact + model.contacts.len() - 2;
    let mut watch =
        Watch { fuse: FuseWatch::new(&model), deck: [last, last + 1], values: Vec::new(), peak_deck_force: 0.0 };
    let (sim, finished) = run_with_fuses(&model, sim, &options, PERIOD, &mut watch).unwrap();
    assert!(finished);
    Closed { sim, fuse: watch.fuse.map(|f| f.result), peak_deck_force: watch.peak_deck_force }
}

/// Asserts that `with`, a run whose fuse never broke, is `without`, the
/// run without one, bit for bit: state, counters and energy balance.
pub fn assert_same_run(with: Closed, without: Closed) {
    assert!(without.fuse.is_none() && !with.fuse.unwrap().broke);
    let (with, without) = (with.sim, without.sim);
    assert_eq!(
        (with.time(), with.positions(), with.velocities(), with.stats()),
        (without.time(), without.positions(), without.velocities(), without.stats())
    );
    assert_eq!(with.energy(), without.energy());
}

/// Asserts that the `strong` fuse broke after the `weak` one in the same
/// closing, within 5 ms of `by_hand` \[s\].
pub fn assert_breaks_later(weak: &FuseResult, strong: &FuseResult, by_hand: f64) {
    assert!(strong.break_time > weak.break_time, "{} s against {} s", strong.break_time, weak.break_time);
    assert!((strong.break_time - by_hand).abs() < 5e-3, "broke at {} s, by hand {by_hand} s", strong.break_time);
}
