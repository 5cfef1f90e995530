//! The modal bridge's reference problems, and the configs they share with
//! the tests and the benchmark: the three-span girder bridge of
//! `tests/data/three_span` (its modes exported from OpenSees, and
//! OpenSees' own transient of it) with joints at its ends.

use std::path::{Path, PathBuf};

use super::Outcome;
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
    let text = std::fs::read_to_string(root.join("configs").join(name)).map_err(|e| format!("{name}: {e}"))?;
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
/// (`opensees_corralitos090.csv`, its column `<point> u [m]`) over the
/// first `samples` samples [m].
fn opensees_peak(root: &Path, point: &str, samples: usize) -> Result<f64, String> {
    let path = three_span_data(root).join("opensees_corralitos090.csv");
    let text = std::fs::read_to_string(&path).map_err(|e| format!("{}: {e}", path.display()))?;
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
    Ok(Outcome { computed: r.sd, reference: opensees_peak(root, "right end", x.record.acceleration.len())? })
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
    let right = reversed.joints.first().ok_or("no second joint")?;
    Ok(Outcome { computed: forward.peak_joint_force, reference: right.peak_joint_force })
}
