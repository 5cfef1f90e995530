//! The coupled run: the bridge with its joints under records, one
//! observer per joint stepped together ([`simulate_records`]).

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::Instant as Clock;

use quakejoint_motion::Record;
use quakejoint_solver::{
    Assembly, AssemblyOptions, BodyId, ConstraintId, Observer, Radau5, SolverError, StepView, TimeSeries,
};

use super::{
    check_run_length, integrator_options, run_duration, series, window_to, FarSegment, Histories, JointResult,
    ProgressFn, RunOptions, RunResult, Transverse,
};
use crate::config::Config;
use crate::error::ModelError;
use crate::generator::{build_scenario, Bridge, Drive, JointModel};
use crate::pounding::{ContactWatch, Pounding};
use crate::scenario::Scenario;
use crate::validity::Monitor;
use crate::watch::Gaps;
use crate::watch::DENSE_OUTPUT;

/// Runs the coupled model under given records.
pub fn simulate_records(
    config: &Config,
    record_x: &Record,
    record_y: Option<&Record>,
    options: &RunOptions,
) -> Result<RunResult, ModelError> {
    simulate_scenario(&Scenario::new(config.clone())?, record_x, record_y, options)
}

/// Runs the coupled model of a resolved scenario under given records.
pub fn simulate_scenario(
    scenario: &Scenario,
    record_x: &Record,
    record_y: Option<&Record>,
    options: &RunOptions,
) -> Result<RunResult, ModelError> {
    let config = &scenario.config;
    check_run_length(config, record_x)?;
    let gx = series(record_x)?;
    let gy = record_y.map(series).transpose()?;
    let drive = Drive::Earthquake { x: gx.clone(), y: gy.clone() };
    let model = build_scenario(scenario, None, drive, options.bearing_joint)?;
    let duration = run_duration(config, record_x);
    let asm = Arc::new(Assembly::new(&model.system, &AssemblyOptions::default())?);
    let start = Clock::now();
    let cpu = crate::resources::CpuClock::start();
    let mut sim = Radau5::new(asm.clone(), integrator_options(config))?;
    let ground = Ground { x: gx, y: gy, dt: record_x.dt };
    let mut obs = Observers::new(scenario, &model, &asm, &sim, &ground, options)?;
    obs.joints[0].deadline = config.simulation.max_wall_time.map(|s| (start, s));
    if !sim.run(duration, &mut obs)? {
        return Err(match obs.joints[0].deadline {
            Some((_, limit_s)) if obs.joints[0].out_of_time => {
                SolverError::WallClockLimit { limit_s, time: sim.time() }.into()
            }
            _ => ModelError::Interrupted { time: sim.time() },
        });
    }
    let wall = start.elapsed().as_secs_f64();
    let cpu_time_s = cpu.elapsed_s();
    let e = sim.energy();
    let energy_error = e.error_relative_to_input();
    let point_names = std::mem::take(&mut obs.point_names);
    // each joint's friction: its group's, or the system's for one joint
    let friction = match sim.group_friction_energy() {
        [] => vec![e.friction],
        groups => groups.to_vec(),
    };
    let energies = Energies { contact: e.contact, error: energy_error, friction: &friction };
    let (obs, joints) = joint_results(obs.joints, &model, energies);
    let first = &joints[0];
    let mut validity = first.validity.clone();
    for j in &joints[1..] {
        validity.flags = crate::validity::Flags(validity.flags.0 | j.validity.flags.0);
        validity.findings.extend(j.validity.findings.iter().map(|f| format!("{}: {f}", j.name)));
    }
    let w = model.bridge.omega;
    let without = Without { config, modal: scenario.bridge.modal(), record_x, record_y };
    let transverse = transverse_result(&model, &obs, &without);
    let far = model.bridge.far.map(|(_, wf, zeta)| {
        let [sa, sd, f, rel] = obs.far_peaks;
        FarSegment {
            omega: wf,
            sa: sa.value,
            t_sa: sa.time,
            sd: sd.value,
            peak_joint_force: f.value,
            sa_without: without.sdof_sa(record_x, wf, zeta),
            max_relative_displacement: rel.value,
        }
    });
    let points = point_peaks(&obs, &point_names);
    Ok(RunResult {
        omega: w,
        sa: obs.sa.value,
        t_sa: obs.sa.time,
        psa: w * w * obs.sd.value,
        sd: obs.sd.value,
        t_sd: obs.sd.time,
        sv: obs.sv.value,
        t_sv: obs.sv.time,
        peak_joint_force: obs.joint_force.value,
        peak_abutment_force: if obs.abutment_links.is_empty() { f64::NAN } else { obs.abutment_force.value },
        peak_bushing_force: obs.bushing,
        peak_friction_force: obs.friction,
        friction_energy: e.friction,
        damping_energy: e.damping,
        // (the drivers' work: a lagged abutment's, the earthquake's work
        // through it; zero without one)
        earthquake_work: e.base + e.constraints,
        min_subgap: first.min_subgap,
        max_subgap: first.max_subgap,
        max_subgap_deviation: first.max_subgap_deviation,
        pounding: first.pounding,
        transverse,
        far,
        energy_error,
        residuals: sim.constraint_residuals(),
        validity,
        exact_linear: false,
        stats: sim.stats(),
        wall_time_s: wall,
        cpu_time_s,
        duration,
        base_shear: (!obs.points.is_empty()).then_some(obs.base_shear.value),
        points,
        base_shear_without: None,
        mode_check: None,
        histories: obs.histories,
        joints,
    })
}

/// The ground motion a run is driven by: along x, across, and the
/// record's time step (the output interval) \[s\].
struct Ground {
    x: TimeSeries,
    y: Option<TimeSeries>,
    dt: f64,
}

/// Each joint's results from its observer, and the first joint's observer
/// (which also watched the bridge).
fn joint_results(
    observers: Vec<EarthquakeObserver>,
    model: &JointModel,
    energy: Energies<'_>,
) -> (EarthquakeObserver, Vec<JointResult>) {
    let Energies { contact: contact_energy, error: energy_error, friction } = energy;
    let mut results = observers.into_iter().zip(model.joints()).enumerate().map(|(k, (mut obs, jm))| {
        let mut validity = obs.monitor.as_ref().map(|m| m.validity(energy_error)).unwrap_or_default();
        let mut pounding = obs.contacts.as_ref().map_or_else(Pounding::default, |c| c.result);
        if let Some(l) = &obs.link {
            pounding = l.pounding();
            l.validity(&mut validity);
        }
        pounding.contact_energy = contact_energy;
        if let (Some(h), Some(log)) = (&mut obs.histories, obs.contacts.as_mut().and_then(|c| c.log.take())) {
            h.impacts = log;
        }
        let joint = JointResult {
            name: jm.name.clone(),
            sa: obs.sa.value,
            t_sa: obs.sa.time,
            sd: obs.sd.value,
            sv: obs.sv.value,
            peak_joint_force: obs.joint_force.value,
            peak_abutment_force: if obs.abutment_links.is_empty() { f64::NAN } else { obs.abutment_force.value },
            peak_bushing_force: if obs.group.is_some() { obs.own.bushing } else { obs.bushing },
            peak_friction_force: if obs.group.is_some() { obs.own.friction } else { obs.friction },
            // (a joint without bodies of its own, disabled: none)
            friction_energy: friction.get(k).copied().unwrap_or(0.0),
            min_subgap: obs.gaps.as_ref().map(|g| g.min).or(obs.link.as_ref().map(|l| l.cells()[0])),
            max_subgap: obs.gaps.as_ref().map(|g| g.max).or(obs.link.as_ref().map(|l| l.cells()[1])),
            // (a link's cells open alike)
            max_subgap_deviation: obs.gaps.as_ref().map(|g| g.deviation).or(obs.link.as_ref().map(|_| 0.0)),
            pounding,
            validity,
            // (the first joint's stay the run's)
            histories: if k > 0 { obs.histories.take() } else { None },
        };
        (joint, obs)
    });
    let (first, obs) = results.next().expect("a run has a joint");
    let joints = std::iter::once(first).chain(results.map(|(joint, _)| joint)).collect();
    (obs, joints)
}

/// The energies a run's joints share out: the contacts' (the whole
/// system's) \[J\], the balance error [-] and each joint's friction \[J\].
struct Energies<'a> {
    contact: f64,
    error: f64,
    friction: &'a [f64],
}

/// What a run's bridge does without its joints, for the parts of the
/// result computed apart from the coupled run (across, the adjacent
/// segment): the exact linear response over the run's window.
struct Without<'a> {
    config: &'a Config,
    modal: Option<&'a crate::bridge::Modal>,
    record_x: &'a Record,
    record_y: Option<&'a Record>,
}

impl Without<'_> {
    /// `record` over the run's window (the run's duration under `record_x`).
    fn window(&self, record: &Record) -> Record {
        window_to(record, run_duration(self.config, self.record_x))
    }

    /// Sa of a single-DOF oscillator of circular frequency `w` [rad/s] and
    /// damping ratio `zeta` [-] under `record` over the run's window.
    fn sdof_sa(&self, record: &Record, w: f64, zeta: f64) -> f64 {
        let period = 2.0 * std::f64::consts::PI / w;
        let window = self.window(record);
        quakejoint_motion::peaks(&window.acceleration, window.dt, period, zeta, Default::default()).sa
    }

    /// Sa across of a modal bridge's point `py` under `[record_y]` (0
    /// without it).
    fn modal_sa_across(&self, py: usize) -> f64 {
        let (Some(r), Some(modal)) = (self.record_y, self.modal) else { return 0.0 };
        let alone = modal.superposition(&self.window(r), 1);
        alone.points[py].a_abs.iter().fold(0.0f64, |m, a| m.max(a.abs()))
    }
}

/// The deck's response across the bridge: the single-DOF deck's
/// transverse oscillator, or a modal bridge's first joint's deck end if it
/// moves across.
fn transverse_result(model: &JointModel, obs: &EarthquakeObserver, without: &Without<'_>) -> Option<Transverse> {
    let [sa, sd, sv, f] = obs.across;
    let (omega, sa_without) = if let Some((wy, zeta)) = model.bridge.transverse {
        (wy, without.record_y.map_or(0.0, |r| without.sdof_sa(r, wy, zeta)))
    } else {
        let m = model.modal.as_ref()?;
        let (py, _) = m.parts.ends[m.end].across?;
        (f64::NAN, without.modal_sa_across(py))
    };
    Some(Transverse {
        omega,
        sa: sa.value,
        t_sa: sa.time,
        sd: sd.value,
        sv: sv.value,
        peak_joint_force: f.value,
        sa_without,
    })
}

/// A modal bridge's points' peaks with the joints (those without are
/// filled in by [`crate::runspec::RunSpec::run`]).
fn point_peaks(obs: &EarthquakeObserver, names: &[String]) -> Vec<crate::modal::PointPeaks> {
    names
        .iter()
        .zip(&obs.points)
        .map(|(name, [d, a])| crate::modal::PointPeaks {
            name: name.clone(),
            sd: d.value,
            t_sd: d.time,
            sa: a.value,
            t_sa: a.time,
            sd_without: f64::NAN,
            sa_without: f64::NAN,
        })
        .collect()
}

/// The observers of every joint of a run, stepped together; the first
/// reports progress and watches the wall-clock limit.
struct Observers {
    joints: Vec<EarthquakeObserver>,
    progress: Option<ProgressFn>,
    cancel: Option<Arc<AtomicBool>>,
    /// A modal bridge's points, whose peaks the first joint's observer
    /// watches.
    point_names: Vec<String>,
}

impl Observers {
    /// One observer per joint of `model`, each sampled at the start.
    fn new(
        scenario: &Scenario,
        model: &JointModel,
        asm: &Assembly,
        sim: &Radau5,
        ground: &Ground,
        options: &RunOptions,
    ) -> Result<Self, ModelError> {
        let places = &scenario.places;
        let mut joints = Vec::with_capacity(places.len());
        let point_names: Vec<String> =
            scenario.bridge.modal().map(|m| m.file.points.iter().map(|p| p.name.clone()).collect()).unwrap_or_default();
        for (k, (jm, place)) in model.joints().zip(places).enumerate() {
            let mut obs = EarthquakeObserver::new(jm, asm, ground.x.clone(), ground.dt, options.histories)?;
            obs.monitor = Monitor::new(jm, asm, &place.config)?;
            obs.ground_y = ground.y.clone();
            if places.len() > 1 && k < asm.group_count() {
                obs.group = Some(k);
                obs.group_extremes = vec![Default::default(); asm.group_count()];
            }
            if k == 0 {
                obs.points = vec![[Peak::default(); 2]; point_names.len()];
                if let Some(h) = &mut obs.histories {
                    h.points_u = vec![Vec::new(); point_names.len()];
                    h.points_a_abs = vec![Vec::new(); point_names.len()];
                }
            }
            obs.sample(0.0, sim.positions(), sim.velocities(), sim.multipliers(), asm, &mut asm.workspace());
            joints.push(obs);
        }
        Ok(Observers { joints, progress: options.progress.clone(), cancel: options.cancel.clone(), point_names })
    }
}

impl Observer for Observers {
    fn step(&mut self, view: &mut StepView<'_>) -> bool {
        if self.cancel.as_ref().is_some_and(|c| c.load(Ordering::Relaxed)) {
            return false;
        }
        if let Some(p) = &self.progress {
            let first = &mut self.joints[0];
            if view.t >= first.last_report + 0.1 {
                first.last_report = view.t;
                p(view.t);
            }
        }
        let mut go_on = true;
        for j in &mut self.joints {
            go_on &= j.step(view);
        }
        go_on
    }
}

/// Longest interval between two checks of the sub-gaps and the validity
/// limits \[s\]: 5 ms, the time step of most records; a beam closing a sub-gap
/// at 1 m/s moves 5 mm in it.
pub const CHECK_INTERVAL: f64 = 0.005;

/// The tolerance to which the first crossing of a validity limit is
/// located in time \[s\].
pub const CROSSING_TOLERANCE: f64 = 1e-6;

/// A running maximum of |x| with its time.
#[derive(Debug, Clone, Copy, Default)]
struct Peak {
    value: f64,
    time: f64,
}

impl Peak {
    fn update(&mut self, x: f64, t: f64) {
        if x.abs() > self.value {
            self.value = x.abs();
            self.time = t;
        }
    }
}

/// Evaluates the reported quantities at the output times.
struct EarthquakeObserver {
    deck: usize,
    /// The deck's y coordinate, when it moves across.
    deck_y: Option<usize>,
    /// The adjacent segment's deck: its x coordinate and body.
    far: Option<(usize, BodyId)>,
    abutment_links: Vec<ConstraintId>,
    /// The support beams, one per link of `abutment_links`.
    supports: Vec<BodyId>,
    /// The joint's force on its abutment side (its links and the
    /// abutment's edge-beam contacts).
    abutment_force: Peak,
    deck_body: BodyId,
    boxes: Vec<ConstraintId>,
    bridge: Bridge,
    /// The modes, when the bridge is given by them.
    modal: Option<crate::modal::ModalDeck>,
    /// Scratch: the modes' accelerations at a sample, and the forces the
    /// joints' ends pass to them.
    modal_acc: Vec<f64>,
    modal_forces: Vec<(usize, f64)>,
    ground: TimeSeries,
    /// +1, or -1 for a joint turned half a turn: its own x is the bridge's -x.
    sign: f64,
    /// The ground's acceleration across, if a record acts across.
    ground_y: Option<TimeSeries>,
    dt: f64,
    /// The output times: the record's samples after the first.
    outputs: quakejoint_solver::OutputTimes,
    sa: Peak,
    sd: Peak,
    sv: Peak,
    joint_force: Peak,
    /// Across the bridge: Sa, Sd, Sv and the joint's force.
    across: [Peak; 4],
    /// A modal bridge's points (displacement and absolute acceleration) and
    /// base shear, watched by the first joint's observer only.
    points: Vec<[Peak; 2]>,
    base_shear: Peak,
    /// The adjacent segment: Sa, Sd, the joint's force on it and the decks'
    /// relative displacement.
    far_peaks: [Peak; 4],
    bushing: f64,
    friction: f64,
    /// Its own group of bodies when a run has several joints (its peak
    /// forces and friction energy apart from the others'), with scratch
    /// for every group's peak forces, and its own peaks.
    group: Option<usize>,
    group_extremes: Vec<quakejoint_solver::ForceExtremes>,
    /// Scratch: every group's friction power at a sample \[W\].
    group_powers: Vec<f64>,
    own: quakejoint_solver::ForceExtremes,
    gaps: Option<Gaps>,
    contacts: Option<ContactWatch>,
    /// The link element, its node's and abutment's x coordinates, and what
    /// is watched of it.
    link: Option<LinkObserver>,
    /// Scratch: contact force per sub-gap at a sample.
    gap_forces: Vec<f64>,
    histories: Option<Histories>,
    /// Interval of the sub-gap and validity checks between output times
    /// [s]: the record's time step divided into pieces of at most
    /// [`CHECK_INTERVAL`] (a coarse record must not hide a collision).
    check_dt: f64,
    checks: quakejoint_solver::OutputTimes,
    /// Each validity limit's excess at the last step's end \[m\]
    /// ([`Monitor::excesses`]; NaN before the first step).
    excess: [f64; crate::validity::LIMITS],
    /// The run's start and wall-clock limit [s], checked as output samples
    /// are written too (a long free vibration is many samples per step).
    deadline: Option<(Clock, f64)>,
    out_of_time: bool,
    monitor: Option<Monitor>,
    last_report: f64,
    /// Scratch: the state at an output time or a check.
    state: quakejoint_solver::StateBuffer,
}

impl EarthquakeObserver {
    fn new(
        model: &JointModel,
        asm: &Assembly,
        ground: TimeSeries,
        dt: f64,
        histories: bool,
    ) -> Result<Self, ModelError> {
        let deck = asm
            .coordinate(model.deck, quakejoint_solver::Coord::X)
            .ok_or_else(|| ModelError::Geometry("the deck has no x coordinate".into()))?;
        let gaps = Gaps::new(model, asm)?;
        let mut contacts = ContactWatch::new(model, asm.contact_count());
        if let (true, Some(c)) = (histories, &mut contacts) {
            c.log = Some(Vec::new());
        }
        // (a link's cells open alike: one series stands for them all)
        let n_gaps = model.geometry.as_ref().map_or(usize::from(model.link.is_some()), |g| g.center_beams + 1);
        let histories = histories.then(|| Histories {
            center_beam_dx: vec![Vec::new(); model.center_beams.len()],
            subgaps: vec![Vec::new(); n_gaps],
            subgaps_wide: vec![Vec::new(); n_gaps],
            contact_force: vec![Vec::new(); if contacts.is_some() { n_gaps } else { 0 }],
            ..Histories::default()
        });
        let check_dt = dt / (dt / CHECK_INTERVAL).ceil().max(1.0);
        let grid = |dt: f64| {
            quakejoint_solver::OutputTimes::uniform(0.0, dt).map_err(|e| ModelError::Invalid {
                field: "record.dt".into(),
                value: dt.to_string(),
                reason: e.to_string(),
            })
        };
        Ok(Self {
            deck,
            deck_y: asm.coordinate(model.deck, quakejoint_solver::Coord::Y),
            far: model.far_deck.and_then(|b| asm.coordinate(b, quakejoint_solver::Coord::X).map(|c| (c, b))),
            abutment_links: model.abutment_links.clone(),
            supports: model.supports.clone(),
            abutment_force: Peak::default(),
            deck_body: model.deck,
            boxes: model.joist_boxes.clone(),
            bridge: model.bridge,
            modal: model.modal.clone(),
            modal_acc: Vec::new(),
            modal_forces: Vec::new(),
            ground,
            sign: model.sign,
            ground_y: None,
            dt,
            outputs: grid(dt)?,
            sa: Peak::default(),
            sd: Peak::default(),
            sv: Peak::default(),
            joint_force: Peak::default(),
            across: [Peak::default(); 4],
            points: Vec::new(),
            base_shear: Peak::default(),
            far_peaks: [Peak::default(); 4],
            bushing: 0.0,
            friction: 0.0,
            group: None,
            group_extremes: Vec::new(),
            group_powers: Vec::new(),
            own: Default::default(),
            gaps,
            contacts,
            link: LinkObserver::new(model, asm),
            gap_forces: vec![0.0; n_gaps],
            histories,
            check_dt,
            checks: grid(check_dt)?,
            excess: [f64::NAN; crate::validity::LIMITS],
            deadline: None,
            out_of_time: false,
            monitor: None,
            last_report: 0.0,
            state: quakejoint_solver::StateBuffer::new(asm),
        })
    }

    /// The sub-gaps and the validity limits at time `t` (positions `q`).
    fn check(&mut self, t: f64, q: &[f64]) {
        if let Some(g) = &mut self.gaps {
            g.check(t, q, q[self.deck], self.monitor.as_mut());
        }
    }

    /// The times within the step at which a validity limit is first crossed,
    /// located on the dense output to [`CROSSING_TOLERANCE`] (the samples
    /// of the sub-gaps and the limits find the worst excess, but an excess
    /// between two samples, or where it began, only the root finding sees).
    fn locate_crossings(&mut self, view: &StepView<'_>) {
        let (Some(gaps), Some(monitor)) = (&mut self.gaps, &mut self.monitor) else { return };
        let deck = self.deck;
        let excess = |gaps: &mut Gaps, monitor: &Monitor, q: &[f64]| {
            gaps.fill(q, q[deck]);
            monitor.excesses(q, q[deck], &gaps.smallest, &gaps.largest)
        };
        // the step's end against the last one's: a limit crossed within
        // the step is located there (one crossing per step and limit; one
        // that goes and comes back within a step is the samples' to see)
        let end = excess(gaps, monitor, view.q);
        for (limit, &(now, _)) in end.iter().enumerate() {
            let before = std::mem::replace(&mut self.excess[limit], now);
            // (NaN: the first step, whose start the dense output gives)
            if before > 0.0 || now <= 0.0 {
                continue;
            }
            let root = view
                .locate_root(CROSSING_TOLERANCE, &mut self.state, |s| excess(gaps, monitor, &s.q)[limit].0)
                .expect(DENSE_OUTPUT);
            // (none: the dense output at the step's start, which differs from
            // the last end state by its projection, is beyond already)
            let t = root.map_or(view.t_prev, |r| r.t);
            let (e, place) = excess(gaps, monitor, &self.state.q)[limit];
            monitor.crossed(limit, t, e, place);
        }
    }

    /// The checks between the output times up to the step's end (none when
    /// the record's time step is already at most [`CHECK_INTERVAL`]), on the
    /// dense output.
    fn check_between(&mut self, view: &mut StepView<'_>) {
        if self.gaps.is_none() || self.check_dt >= self.dt {
            return;
        }
        while let Some(tk) = self.checks.next_in(view) {
            let mut state = std::mem::take(&mut self.state);
            view.sample(&tk, &mut state).expect(DENSE_OUTPUT);
            self.check(tk.t(), &state.q);
            self.state = state;
        }
    }

    /// Quantities at one output time.
    fn sample(
        &mut self,
        t: f64,
        q: &[f64],
        v: &[f64],
        lam: &[f64],
        asm: &Assembly,
        ws: &mut quakejoint_solver::Workspace,
    ) {
        let (u, ud) = (q[self.deck], v[self.deck]);
        // the joint holds the deck through the joist boxes and, once closed,
        // pushes it through the deck's edge beam
        let pushed = match &mut self.contacts {
            Some(c) => c.at(asm, ws, q, v, Some(&mut self.gap_forces)),
            None => 0.0,
        };
        let reaction = asm.reaction_sum(ws, t, q, lam, &self.boxes, self.deck_body);
        let mut fj = reaction[0] + pushed;
        if !self.abutment_links.is_empty() {
            // the links' reactions on the support beams, turned round, and
            // the abutment's edge-beam contacts
            let held: f64 = self
                .abutment_links
                .iter()
                .zip(&self.supports)
                .map(|(&c, &b)| asm.reaction_sum(ws, t, q, lam, &[c], b)[0])
                .sum();
            let pushed_abutment = self.contacts.as_ref().map_or(0.0, |w| w.far_push());
            self.abutment_force.update(pushed_abutment - held, t);
        }
        if let Some(l) = &mut self.link {
            fj = l.update(t, q, v, asm, ws);
        }
        let b = self.bridge;
        // a modal deck end's absolute acceleration across, in the joint's y
        let (a_abs, modal_ay) = match self.modal.is_some() {
            true => self.modal_sample(Instant { t, q, v, lam }, asm, ws),
            false => ((-b.stiffness() * u - b.damper() * ud + fj) / b.mass, None),
        };
        if let (Some((c, body)), Some((mass, w, zeta))) = (self.far, b.far) {
            let (uf, vf) = (q[c], v[c]);
            let pushed_far = self.contacts.as_ref().map_or(0.0, |w| w.far_push());
            let ff = asm.reaction_sum(ws, t, q, lam, &self.abutment_links, body)[0] + pushed_far;
            let a = (-mass * w * w * uf - 2.0 * zeta * mass * w * vf + ff) / mass;
            for (peak, x) in self.far_peaks.iter_mut().zip([a, uf, ff, u - uf]) {
                peak.update(x, t);
            }
        }
        // across: the joist boxes alone hold the deck (contacts push along x)
        let across = match (self.deck_y, b.transverse, modal_ay) {
            (Some(c), _, Some(a)) => Some((q[c], v[c], a)),
            (Some(c), Some((w, zeta)), None) => {
                let (uy, vy, fy) = (q[c], v[c], reaction[1]);
                Some((uy, vy, (-b.mass * w * w * uy - 2.0 * zeta * b.mass * w * vy + fy) / b.mass))
            }
            _ => None,
        };
        let across = across.map(|(uy, vy, a)| {
            for (peak, x) in self.across.iter_mut().zip([a, uy, vy, reaction[1]]) {
                peak.update(x, t);
            }
            (uy, a, reaction[1])
        });
        self.sa.update(a_abs, t);
        self.sd.update(u, t);
        self.sv.update(ud, t);
        self.joint_force.update(fj, t);
        self.check(t, q);
        if self.gaps.is_some() || self.link.is_some() {
            self.force_peaks(asm, ws, q, v);
        }
        if self.histories.is_some() {
            let at = Instant { t, q, v, lam };
            self.record(at, [u, ud, a_abs, fj], across, asm, ws);
        }
    }

    /// The peak bushing and friction forces: the whole system's and, in a
    /// run of several joints, this joint's group's (every bushing and
    /// bearing is some joint's, so the system's are the groups' largest).
    fn force_peaks(&mut self, asm: &Assembly, ws: &mut quakejoint_solver::Workspace, q: &[f64], v: &[f64]) {
        let x = match self.group {
            None => asm.force_extremes(ws, q, v),
            Some(g) => {
                self.group_extremes.iter_mut().for_each(|x| *x = Default::default());
                asm.force_extremes_by_group(ws, q, v, &mut self.group_extremes);
                let own = self.group_extremes[g];
                self.own.bushing = self.own.bushing.max(own.bushing);
                self.own.friction = self.own.friction.max(own.friction);
                self.group_extremes.iter().fold(Default::default(), |m: quakejoint_solver::ForceExtremes, x| {
                    quakejoint_solver::ForceExtremes {
                        bushing: m.bushing.max(x.bushing),
                        friction: m.friction.max(x.friction),
                    }
                })
            }
        };
        self.bushing = self.bushing.max(x.bushing);
        self.friction = self.friction.max(x.friction);
    }

    /// A modal deck end's absolute acceleration along and across (in the
    /// joint's own x and y) at `at`, and the points' and base shear's
    /// peaks when this observer watches them.
    fn modal_sample(
        &mut self,
        at: Instant<'_>,
        asm: &Assembly,
        ws: &mut quakejoint_solver::Workspace,
    ) -> (f64, Option<f64>) {
        let Instant { t, q, v, lam } = at;
        let m = self.modal.as_ref().expect("called for a modal deck");
        let ag = [self.ground.value(t), self.ground_y.as_ref().map_or(0.0, |g| g.value(t))];
        let mut acc = std::mem::take(&mut self.modal_acc);
        let at = crate::modal::Instant { t, q, v, lam, ag };
        m.parts.accelerations(asm, ws, at, &mut self.modal_forces, &mut acc);
        let end = &m.parts.ends[m.end];
        // (in the joint's own x and y)
        let a = end.sign * m.parts.point(asm, end.point, q, v, &acc, ag[0])[2];
        let ay = end.across.map(|(py, _)| end.sign * m.parts.point(asm, py, q, v, &acc, ag[1])[2]);
        for (p, peaks) in self.points.iter_mut().enumerate() {
            let [up, _, ap] = m.parts.point(asm, p, q, v, &acc, ag[0]);
            peaks[0].update(up, t);
            peaks[1].update(ap, t);
            if let Some(h) = &mut self.histories {
                h.points_u[p].push(up);
                h.points_a_abs[p].push(ap);
            }
        }
        if !self.points.is_empty() {
            self.base_shear.update(m.parts.base_shear(asm, q, v), t);
        }
        self.modal_acc = acc;
        (a, ay)
    }

    /// Appends one output time to the histories: the deck's `[u, v, a_abs,
    /// joint force]`, across `(uy, a_abs_y, force_y)` if the deck moves
    /// across, the friction power and the joint's cells.
    fn record(
        &mut self,
        at: Instant<'_>,
        deck: [f64; 4],
        across: Option<(f64, f64, f64)>,
        asm: &Assembly,
        ws: &mut quakejoint_solver::Workspace,
    ) {
        let Instant { t, q, v, lam } = at;
        let Some(h) = &mut self.histories else { return };
        let [u, ud, a_abs, fj] = deck;
        h.t.push(t);
        // (in the joint's own x, as its deck point's motion)
        h.ag.push(self.sign * self.ground.value(t));
        h.u.push(u);
        h.v.push(ud);
        h.a_abs.push(a_abs);
        h.joint_force.push(fj);
        if let Some((uy, a, fy)) = across {
            h.uy.push(uy);
            h.a_abs_y.push(a);
            h.joint_force_y.push(fy);
        }
        // (its own group's, in a run of several joints; else the system's)
        let friction_power = match self.group {
            Some(g) => {
                let mut powers = std::mem::take(&mut self.group_powers);
                powers.clear();
                powers.resize(asm.group_count(), 0.0);
                asm.friction_powers_by_group(ws, t, q, v, &mut powers);
                let own = powers[g];
                self.group_powers = powers;
                own
            }
            None => asm.powers(ws, t, q, v, lam).friction,
        };
        h.friction_power.push(friction_power);
        if let Some(g) = &self.gaps {
            for (i, &c) in g.beams.iter().enumerate() {
                h.center_beam_dx[i].push(q[c] - g.geometry.center_x[i]);
            }
            for (series, &gap) in h.subgaps.iter_mut().zip(&g.smallest) {
                series.push(gap);
            }
            for (series, &gap) in h.subgaps_wide.iter_mut().zip(&g.largest) {
                series.push(gap);
            }
            for (series, &f) in h.contact_force.iter_mut().zip(&self.gap_forces) {
                series.push(f);
            }
        }
        if let Some(l) = &self.link {
            let cell = l.cell();
            for series in h.subgaps.iter_mut().chain(h.subgaps_wide.iter_mut()) {
                series.push(cell);
            }
        }
    }
}

/// The state at one output time.
#[derive(Clone, Copy)]
struct Instant<'a> {
    t: f64,
    q: &'a [f64],
    v: &'a [f64],
    lam: &'a [f64],
}

impl Observer for EarthquakeObserver {
    fn step(&mut self, view: &mut StepView<'_>) -> bool {
        self.locate_crossings(view);
        self.check_between(view);
        if let Some(c) = &mut self.contacts {
            c.step(view, self.monitor.as_mut());
        }
        // the record's samples: the step's end state at the samples it ends
        // on (every one while the record lasts), the dense output between
        while let Some(tj) = self.outputs.next_in(view) {
            if let Some((start, limit)) = self.deadline {
                if (tj.index() + 1).is_multiple_of(1024) && start.elapsed().as_secs_f64() > limit {
                    self.out_of_time = true;
                    return false;
                }
            }
            let mut state = std::mem::take(&mut self.state);
            view.sample(&tj, &mut state).expect(DENSE_OUTPUT);
            self.sample(state.t, &state.q, &state.v, &state.lambda, view.assembly, view.workspace);
            self.state = state;
        }
        true
    }
}

/// A link element's watch in a run: its parts, coordinates and extremes.
struct LinkObserver {
    parts: crate::link::LinkParts,
    /// Scratch: the contacts' states.
    contacts: Vec<quakejoint_solver::ContactValue>,
    deck: usize,
    slider: usize,
    abutment: Option<usize>,
    watch: crate::link::LinkWatch,
    /// The opening at the last update \[m\].
    u: f64,
}

impl LinkObserver {
    fn new(model: &JointModel, asm: &Assembly) -> Option<Self> {
        let parts = model.link.clone()?;
        let deck = asm.coordinate(parts.deck, quakejoint_solver::Coord::X)?;
        let slider = asm.coordinate(parts.slider, quakejoint_solver::Coord::X)?;
        let abutment = asm.coordinate(parts.abutment, quakejoint_solver::Coord::X);
        Some(Self {
            parts,
            contacts: Vec::new(),
            deck,
            slider,
            abutment,
            watch: crate::link::LinkWatch::default(),
            u: 0.0,
        })
    }

    /// Watches the state `(q, v)` at `t`; returns the link's force on the
    /// deck (its spring's and damper's and, closed, its gap's) \[N\].
    fn update(&mut self, t: f64, q: &[f64], v: &[f64], asm: &Assembly, ws: &mut quakejoint_solver::Workspace) -> f64 {
        let u = q[self.deck] - self.abutment.map_or(0.0, |c| q[c]);
        self.u = u;
        let gap = match self.parts.contact {
            Some(i) => {
                self.contacts.resize(asm.contact_count(), Default::default());
                asm.contacts(ws, q, v, &mut self.contacts);
                let c = &self.contacts[i];
                if c.closed {
                    c.force
                } else {
                    0.0
                }
            }
            None => 0.0,
        };
        self.watch.update(&self.parts, t, u, gap);
        let p = &self.parts;
        p.stiffness * (q[self.slider] - q[self.deck]) + p.damping * (v[self.slider] - v[self.deck]) + gap
    }

    fn cells(&self) -> [f64; 2] {
        self.watch.cells(&self.parts)
    }

    /// The cells' clear width at the last update \[m\].
    fn cell(&self) -> f64 {
        self.parts.clear + self.u / self.parts.cells as f64
    }

    /// The closures as pounding: the closed joint's force on the deck.
    fn pounding(&self) -> Pounding {
        let w = &self.watch;
        Pounding {
            impacts: w.closures,
            peak_contact_force: w.peak_gap_force,
            peak_contact_time: w.peak_gap_time,
            peak_deck_contact_force: w.peak_gap_force,
            max_penetration: w.max_overlap / self.parts.cells as f64,
            // (a link's closure is no one beam's impact)
            max_impact_speed: f64::NAN,
            ..Pounding::default()
        }
    }

    /// A cell beyond its capacity, flagged as the detailed joint's.
    fn validity(&self, v: &mut crate::validity::Validity) {
        if let Some(t) = self.watch.beyond_capacity_at {
            v.flags |= crate::validity::Flags::CAPACITY_EXCEEDED;
            v.findings.push(format!(
                "capacity_exceeded: the link's cells (opening alike) opened to {:.1} mm, beyond the capacity of \
                 {:.0} mm (joint.capacity.max_subgap; first at t = {t:.3} s)",
                self.cells()[1] * 1e3,
                self.parts.max_subgap * 1e3
            ));
        }
    }
}
