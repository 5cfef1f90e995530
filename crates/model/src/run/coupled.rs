//! The coupled run: the bridge with its joints under records, one
//! observer per joint stepped together ([`simulate_records`]).

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::Instant as Clock;

use quakejoint_motion::Record;
use quakejoint_solver::{Assembly, AssemblyOptions, Observer, Radau5, SolverError, StepView, TimeSeries};

use super::observer::{EarthquakeObserver, Peak};
use super::{
    check_run_length, integrator_options, run_duration, series, window_to, FarSegment, JointResult, ProgressFn,
    RunOptions, RunResult, Transverse,
};
use crate::config::Config;
use crate::error::ModelError;
use crate::generator::{build_scenario, Drive, JointModel};
use crate::pounding::Pounding;
use crate::scenario::Scenario;
use crate::validity::Monitor;

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
    let mut solver_options = integrator_options(config);
    // (a link's stick-slip converges only in short steps; docs/link.md)
    crate::link::tighten(&mut solver_options, &scenario.places);
    let sim = Radau5::new(asm.clone(), solver_options.clone())?;
    let ground = Ground { x: gx, y: gy, dt: record_x.dt };
    let mut obs = Observers::new(scenario, &model, &asm, &sim, &ground, options)?;
    obs.joints[0].deadline = config.simulation.max_wall_time.map(|s| (start, s));
    let (sim, finished) = crate::run::fuse::run_with_fuses(&model, sim, &solver_options, duration, &mut obs)?;
    if !finished {
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
    // each joint's friction: its group's, or the system's for one joint;
    // a broken fuse's freed beam's, in a group after the joints'
    let n_joints = obs.joints.len();
    let groups = sim.group_friction_energy();
    let fuses: Vec<f64> = (0..n_joints).map(|k| groups.get(n_joints + k).copied().unwrap_or(0.0)).collect();
    let bearings = e.friction - fuses.iter().sum::<f64>();
    let friction = if n_joints > 1 { groups[..n_joints].to_vec() } else { vec![bearings] };
    // (a fuse element's contacts' energy as its beam left is its own)
    let released: f64 = obs.joints.iter().filter_map(|j| j.fuse.as_ref()).map(|f| f.result.energy).sum();
    let energies = Energies { contact: e.contact - released, error: energy_error, friction: &friction, fuses: &fuses };
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
        friction_energy: bearings,
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
    let Energies { contact: contact_energy, error: energy_error, friction, fuses } = energy;
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
            // (a box's friction is its group's; an element's energy, its own)
            fuse: obs
                .fuse
                .as_ref()
                .map(|f| crate::run::fuse::FuseResult { energy: f.result.energy + fuses[k], ..f.result }),
        };
        (joint, obs)
    });
    let (first, obs) = results.next().expect("a run has a joint");
    let joints = std::iter::once(first).chain(results.map(|(joint, _)| joint)).collect();
    (obs, joints)
}

/// The energies a run's joints share out: the contacts' (the whole
/// system's) \[J\], the balance error [-], each joint's friction and each
/// joint's fuse's \[J\].
struct Energies<'a> {
    contact: f64,
    error: f64,
    friction: &'a [f64],
    fuses: &'a [f64],
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
                obs.joint_groups = places.len();
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

impl crate::run::fuse::FuseObserver for Observers {
    fn take_break(&mut self) -> Option<usize> {
        // (a run stopped by its user or its clock stops, broken or not)
        if self.joints[0].out_of_time || self.cancel.as_ref().is_some_and(|c| c.load(Ordering::Relaxed)) {
            return None;
        }
        self.joints.iter_mut().position(|j| j.fuse.as_mut().is_some_and(|f| f.take_pending()))
    }

    fn resumed(&mut self, asm: &Assembly, freed: &[(usize, crate::run::fuse::Freed)]) -> Result<(), ModelError> {
        for (k, j) in self.joints.iter_mut().enumerate() {
            j.resumed(asm, freed.iter().find(|(b, _)| *b == k).map(|(_, f)| *f))?;
        }
        Ok(())
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
