//! The modal bridge's reference problems, and the configs they share with
//! the tests and the benchmark: the three-span girder bridge of
//! `tests/data/three_span` (its modes exported from OpenSees, and
//! OpenSees' own transient of it) with joints at its ends.

use std::path::{Path, PathBuf};
use std::sync::Arc;

use quakejoint_solver::{
    Assembly, AssemblyOptions, Coord, CoordinateSpring, Excitation, ForceElement, IntegratorOptions, Observer,
    OutputTimes, Radau5, SpringDamper, StateBuffer, StepView, System, TimeFunction, TimeSeries,
};

use super::Outcome;
use crate::generator::lagged_abutment;
use crate::modal::{add_modes, Direction, EndSpec, KeptMode, ModalBridge, ModalParts};
use crate::run::{load_records, simulate_records, RunOptions, RunResult};
use crate::Config;

/// The record of the three-span checks: Loma Prieta, Corralitos 090.
const RECORD: &str = "ground_motions/RSN753_LOMAP_CLS090-hor2.AT2";

/// The folder of the three-span bridge's data.
pub fn three_span_data(root: &Path) -> PathBuf {
    root.join("tests/data/three_span")
}

/// The `[joint]` tables of a shipped config (`configs/<name>`), without
/// its other tables.
pub fn joint_tables(root: &Path, name: &str) -> Result<String, String> {
    let text =
        quakejoint_motion::read_input_text(&root.join("configs").join(name), quakejoint_motion::MAX_CONFIG_BYTES)
            .map_err(|e| format!("{name}: {e}"))?;
    let mut keep = false;
    Ok(text
        .lines()
        .filter(|l| {
            if l.starts_with('[') {
                keep = l.starts_with("[joint") || l.starts_with("[[joint");
            }
            keep
        })
        .map(|l| format!("{l}\n"))
        .collect())
}

/// The joint of `configs/<joint>` at both ends of the three-span bridge
/// (20 modes; "left" at the left end, "right" turned half a turn at the
/// right end) under Corralitos 090 times `scale`, with `extra` TOML
/// (a `[simulation]` table, say) appended.
pub fn two_joints_on_three_span(root: &Path, joint: &str, scale: f64, extra: &str) -> Result<Config, String> {
    let text = format!(
        "{}\n[record]\nfile = \"{}\"\nscale = {scale:e}\n[bridge]\ndamping = 0.05\n\
         [bridge.modal]\nmodes = \"modes.toml\"\nmodes_used = 20\n\
         [[joints]]\nname = \"left\"\ndeck_point = \"left end\"\ndeck_side = \"+x\"\n\
         [[joints]]\nname = \"right\"\ndeck_point = \"right end\"\ndeck_side = \"-x\"\n{extra}",
        joint_tables(root, joint)?,
        root.join(RECORD).display()
    );
    let mut config = Config::from_toml(&text, "two_joints_on_three_span.toml").map_err(|e| e.to_string())?;
    config.load_modes(&three_span_data(root)).map_err(|e| e.to_string())?;
    Ok(config)
}

/// Runs `config` under its record.
pub fn run(root: &Path, config: &Config) -> Result<RunResult, String> {
    let (x, _) = load_records(config, root).map_err(|e| e.to_string())?;
    simulate_records(config, &x.record, None, &RunOptions::default()).map_err(|e| e.to_string())
}

/// The largest |u| of OpenSees' transient at a point of the modes file
/// (`csv` in the three-span data, its column `<point> u [m]`) over the
/// first `samples` samples [m].
fn opensees_peak(root: &Path, csv: &str, point: &str, samples: usize) -> Result<f64, String> {
    let path = three_span_data(root).join(csv);
    let text = quakejoint_motion::read_input_text(&path, quakejoint_motion::MAX_TABLE_BYTES)
        .map_err(|e| format!("{}: {e}", path.display()))?;
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().ok_or("empty CSV")?.split(',').collect();
    let col = header.iter().position(|h| h.starts_with(&format!("{point} u"))).ok_or("no such column")?;
    let mut peak = 0.0f64;
    for l in lines.take(samples) {
        let v: f64 = l.split(',').nth(col).ok_or("short row")?.parse().map_err(|e| format!("{e}"))?;
        peak = peak.max(v.abs());
    }
    Ok(peak)
}

/// The three-span bridge without joints, 20 modes through the multibody
/// solver: the right deck end's Sd against OpenSees' transient.
pub fn three_span_against_opensees(root: &Path) -> Result<Outcome, String> {
    let mut config = two_joints_on_three_span(root, "small.toml", 1.0, "")?;
    config.joints.truncate(1);
    config.joints[0].deck_point = "right end".into();
    config.joint.enabled = false;
    let (x, _) = load_records(&config, root).map_err(|e| e.to_string())?;
    let r = simulate_records(&config, &x.record, None, &RunOptions::default()).map_err(|e| e.to_string())?;
    Ok(Outcome {
        computed: r.sd,
        reference: opensees_peak(root, "opensees_corralitos090.csv", "right end", x.record.acceleration.len())?,
    })
}

/// The small joint on a bridge of one mode against the same joint on the
/// single-DOF deck of the same mass, period and damping: Sa.
pub fn one_mode_equals_single_dof(root: &Path) -> Result<Outcome, String> {
    let (mass, period, damping) = (2.0e6f64, 1.0, 0.05);
    let dir = std::env::temp_dir().join(format!("qj-verify-one-mode-{}", std::process::id()));
    std::fs::create_dir_all(&dir).map_err(|e| e.to_string())?;
    let modes = dir.join("one_mode.toml");
    std::fs::write(
        &modes,
        format!(
            "format = \"quakejoint-modes-1\"\n[[point]]\nname = \"deck end\"\ndirection = \"x\"\n\
             [[mode]]\nperiod = {period}\ndamping = {damping}\nparticipation_x = {:e}\nshape = [{:e}]\n",
            mass.sqrt(),
            1.0 / mass.sqrt()
        ),
    )
    .map_err(|e| e.to_string())?;
    let base = format!(
        "{}\n[record]\nfile = \"{}\"\nscale = 0.15\n[bridge]\nmass = {mass:e}\nperiod = {period}\ndamping = {damping}\n",
        joint_tables(root, "small.toml")?,
        root.join(RECORD).display()
    );
    let sdof = Config::from_toml(&base, "single_dof.toml").map_err(|e| e.to_string())?;
    let modal_text = format!("{base}[bridge.modal]\nmodes = \"{}\"\njoint_point = \"deck end\"\n", modes.display());
    let mut modal = Config::from_toml(&modal_text, "one_mode.toml").map_err(|e| e.to_string())?;
    modal.load_modes(&dir).map_err(|e| e.to_string())?;
    Ok(Outcome { computed: run(root, &modal)?.sa, reference: run(root, &sdof)?.sa })
}

/// The small joint at both ends of the three-span bridge: the left joint's
/// peak force under the record against the right joint's under the record
/// reversed (the bridge mirrored about midspan).
pub fn mirrored_joints(root: &Path) -> Result<Outcome, String> {
    let extra = "[simulation]\nduration = 8.0\n";
    let forward = run(root, &two_joints_on_three_span(root, "small.toml", 0.6, extra)?)?;
    let reversed = run(root, &two_joints_on_three_span(root, "small.toml", -0.6, extra)?)?;
    let (Some(left), Some(right)) = (forward.joints.first(), reversed.joints.get(1)) else {
        return Err("not two joints".to_string());
    };
    Ok(Outcome { computed: left.peak_joint_force, reference: right.peak_joint_force })
}

/// Springs from the left and right deck ends of the three-span bridge to
/// the ground [N/m]: a stuck joint's order of stiffness, about the deck
/// end's own (1 / F_LL = 1.7e8 N/m), unequal so that the deck is stretched
/// between its ends (OpenSees' `transient.py --end-springs 2e8 5e7`).
pub const END_SPRINGS: [f64; 2] = [2e8, 5e7];

/// A spring from the left deck end to an abutment the ground motion
/// reaches later: its stiffness [N/m] and the lag \[s\] (OpenSees'
/// `transient.py --lagged-spring 2e8 0.2`: a wave crossing the 140 m bridge
/// at 700 m/s).
pub const LAGGED_SPRING: (f64, f64) = (2e8, 0.2);

/// A spring along x from a deck end of the three-span bridge to its
/// abutment.
#[derive(Debug, Clone, Copy)]
pub struct EndSpring {
    /// The deck end: 0 left, 1 right.
    pub end: usize,
    /// Stiffness \[N/m\].
    pub stiffness: f64,
    /// How much later the ground motion reaches the abutment \[s\].
    pub lag: f64,
}

/// [`END_SPRINGS`] as [`EndSpring`]s.
pub fn end_springs() -> [EndSpring; 2] {
    [0, 1].map(|end| EndSpring { end, stiffness: END_SPRINGS[end], lag: 0.0 })
}

/// Corralitos 090 as OpenSees had it: the ground acceleration, the AT2's
/// samples (in m/s^2) then zero.
pub fn corralitos(root: &Path) -> Result<TimeSeries, String> {
    let spec = quakejoint_motion::RecordSpec::new(root.join(RECORD));
    let record = quakejoint_motion::load_record(&spec, root).map_err(|e| e.to_string())?.record;
    TimeSeries::uniform(0.0, record.dt, record.acceleration).map_err(|e| e.to_string())
}

/// Every point's displacement along x relative to the ground, sampled.
struct Sampler {
    parts: Arc<ModalParts>,
    asm: Arc<Assembly>,
    times: OutputTimes,
    ground: TimeFunction,
    state: StateBuffer,
    u: Vec<Vec<f64>>,
}

impl Observer for Sampler {
    fn step(&mut self, view: &mut StepView<'_>) -> bool {
        // (displacements only: the modes' accelerations are not needed)
        let zeros = vec![0.0; self.parts.modes.len()];
        while let Some(t) = self.times.next_in(view) {
            if view.sample(&t, &mut self.state).is_err() {
                return false;
            }
            let ag = self.ground.value(self.state.t);
            for (p, u) in self.u.iter_mut().enumerate() {
                u.push(self.parts.point(&self.asm, p, &self.state.q, &self.state.v, &zeros, ag)[0]);
            }
        }
        true
    }
}

/// The three-span bridge with the `kept` modes (and the static correction
/// if `corrected`) and `springs` from its deck ends to their abutments,
/// under `ground` along x for `duration` \[s\]: each point's displacement
/// relative to the ground every `dt` from `dt` on \[m\].
pub fn end_springs_run(
    bridge: &ModalBridge,
    kept: &[KeptMode],
    corrected: bool,
    ground: &TimeSeries,
    springs: &[EndSpring],
    (duration, dt): (f64, f64),
) -> Result<Vec<Vec<f64>>, String> {
    let ends = ["left end", "right end"]
        .iter()
        .map(|name| {
            let point = bridge.point(name, Direction::X, "point").map_err(|e| e.to_string())?;
            Ok(EndSpec { name: name.to_string(), point, point_y: None, sign: 1.0 })
        })
        .collect::<Result<Vec<_>, String>>()?;
    let points: Vec<usize> = ends.iter().map(|e| e.point).collect();
    let correction = match corrected {
        true => Some(bridge.static_correction(kept, &points, 1.0, "modes.toml").map_err(|e| e.to_string())?),
        false => None,
    };
    let mut sys = System::new();
    let parts = Arc::new(add_modes(&mut sys, kept, correction.as_ref(), &ends));
    for s in springs {
        let body = parts.ends[s.end].body;
        let element = if s.lag == 0.0 {
            ForceElement::CoordinateSpring(CoordinateSpring {
                body,
                coord: Coord::X,
                stiffness: s.stiffness,
                damping: 0.0,
                rest: 0.0,
            })
        } else {
            // (a spring 1 m long along x: it stays along x)
            let abutment = lagged_abutment(&mut sys, ground, s.lag, "").map_err(|e| e.to_string())?;
            ForceElement::SpringDamper(SpringDamper {
                body_a: abutment,
                point_a: [-1.0, 0.0],
                body_b: body,
                point_b: [0.0, 0.0],
                stiffness: s.stiffness,
                damping: 0.0,
                rest_length: 1.0,
            })
        };
        sys.add_force(element);
    }
    let ground = TimeFunction::Series(Arc::new(ground.clone()));
    sys.set_excitation(Excitation { ground_x: Some(ground.clone()), ..Default::default() });
    let asm = Arc::new(Assembly::new(&sys, &AssemblyOptions::default()).map_err(|e| e.to_string())?);
    let mut sim = Radau5::new(asm.clone(), IntegratorOptions::default()).map_err(|e| e.to_string())?;
    let mut obs = Sampler {
        parts,
        state: StateBuffer::new(&asm),
        asm,
        times: OutputTimes::uniform(0.0, dt).map_err(|e| e.to_string())?,
        ground,
        u: vec![Vec::new(); bridge.points.len()],
    };
    sim.run(duration, &mut obs).map_err(|e| e.to_string())?;
    Ok(obs.u)
}

/// The three-span bridge with springs at its deck ends, 3 modes and the
/// static correction, under the first 15 s of Corralitos 090: the left
/// deck end's peak displacement against OpenSees' transient of the full
/// model with the same springs.
pub fn static_correction_against_opensees(root: &Path) -> Result<Outcome, String> {
    let bridge = ModalBridge::read(&three_span_data(root).join("modes.toml")).map_err(|e| e.to_string())?;
    let ground = corralitos(root)?;
    let dt = ground.times()[1];
    let duration = 15.0;
    let kept = bridge.kept(Some(3), 1.0, 0.05);
    let u = end_springs_run(&bridge, &kept, true, &ground, &end_springs(), (duration, dt))?;
    let samples = (duration / dt).round() as usize + 1;
    let computed = u[0].iter().fold(0.0f64, |m, x| m.max(x.abs()));
    let csv = "opensees_corralitos090_end_springs.csv";
    Ok(Outcome { computed, reference: opensees_peak(root, csv, "left end", samples)? })
}

/// The three-span bridge with [`LAGGED_SPRING`] from its left deck end to
/// an abutment the ground motion reaches 0.2 s late, all 124 modes, under
/// the first 15 s of Corralitos 090: the left deck end's peak displacement
/// against OpenSees' transient of the full model with the same spring and
/// the abutment node's displacement imposed.
pub fn wave_passage_against_opensees(root: &Path) -> Result<Outcome, String> {
    let bridge = ModalBridge::read(&three_span_data(root).join("modes.toml")).map_err(|e| e.to_string())?;
    let ground = corralitos(root)?;
    let dt = ground.times()[1];
    let duration = 15.0;
    let kept = bridge.kept(None, 1.0, 0.05);
    let (stiffness, lag) = LAGGED_SPRING;
    let u = end_springs_run(&bridge, &kept, false, &ground, &[EndSpring { end: 0, stiffness, lag }], (duration, dt))?;
    let samples = (duration / dt).round() as usize + 1;
    let computed = u[0].iter().fold(0.0f64, |m, x| m.max(x.abs()));
    let csv = "opensees_corralitos090_lagged_spring.csv";
    Ok(Outcome { computed, reference: opensees_peak(root, csv, "left end", samples)? })
}
