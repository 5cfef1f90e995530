//! `quakejoint calibrate`: the link element of a config's joint, its fit
//! and damping table, and its exports (docs/link.md).

use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

use anyhow::{Context, Result};
use quakejoint_model::calibrate::{calibrate, elastoplastic, export, Calibration, CalibrationOptions};
use quakejoint_model::runspec::{Overrides, RecordOverride, RunSpec};
use serde_json::json;

use crate::args::CalibrateArgs;
use crate::commands::read_config;

/// Runs `quakejoint calibrate`.
pub fn calibrate_cmd(a: CalibrateArgs) -> Result<ExitCode> {
    let (config, _) = read_config(&a.config)?;
    if a.record.is_empty() && a.read.any() {
        return Err(crate::commands::InputError(
            "--format, --units, --dt, --column, --channel, --azimuth, --allow-vertical, --scale and --target-pga-g \
             describe the files of --record; without --record, set them in the config's [record]"
                .into(),
        )
        .into());
    }
    // each --record: relative to the current directory, replacing the
    // config's whole [record] (none: the config's own)
    let overrides: Vec<Overrides> = if a.record.is_empty() {
        vec![Overrides::default()]
    } else {
        a.record
            .iter()
            .map(|path| {
                let file = std::path::absolute(path).unwrap_or_else(|_| path.clone());
                Overrides { record: Some(RecordOverride::File(a.read.spec(&file))), ..Overrides::default() }
            })
            .collect()
    };
    let specs = overrides.iter().map(|o| RunSpec::new(config.clone(), o)).collect::<Result<Vec<_>, _>>()?;
    let spec = &specs[0];
    let config = spec.config();
    let mut options = CalibrationOptions::default();
    if let Some(x) = a.amplitudes {
        options.amplitudes = x;
    }
    if let Some(s) = a.speed {
        options.speed = s;
    }
    if let Some(f) = a.contact_force {
        options.contact_force = Some(f);
    }
    // (each option named as typed: `--contact-force 0: ...`), before a
    // record is read or a loop runs
    options.check(|k| format!("--{}", k.replace('_', "-")))?;
    if !a.no_earthquake {
        for spec in &specs {
            let (record, _) = spec.records(&quakejoint_model::config::base_dir(&a.config))?;
            // (which channel of a file of several was read, a record not
            // starting at rest, ...: as simulate says)
            crate::commands::print_warnings(&[&record]);
            options.records.push(quakejoint_model::run::run_window(config, &record.record));
        }
    }
    let dir = a.output_dir.clone().unwrap_or_else(|| default_dir(&a.config));
    let mut inputs = config.input_files(&quakejoint_model::config::base_dir(&a.config));
    inputs.push(a.config.clone());
    inputs.extend(a.record.iter().cloned());
    check_outputs(&dir, &inputs)?;
    let c = calibrate(&spec.scenario, &options)?;
    let written = write_exports(&c, &dir, &a.config.display().to_string())?;
    for w in &c.warnings {
        eprintln!("warning: {w}");
    }
    if a.print.json {
        println!("{}", serde_json::to_string_pretty(&json_of(&c, &written))?);
    } else {
        print!("{}", table(&c, &a.config, &written));
    }
    // (a calibration resting on what the model flags says so in its exit code)
    Ok(if c.warnings.is_empty() { ExitCode::SUCCESS } else { ExitCode::from(crate::commands::FLAGGED) })
}

fn default_dir(config: &Path) -> PathBuf {
    let stem = config.file_stem().map_or_else(|| "config".into(), |s| s.to_string_lossy().into_owned());
    quakejoint_model::config::base_dir(config).join(format!("{stem}_link"))
}

/// The files the calibration writes in its folder.
const OUTPUTS: [&str; 5] = ["link.toml", "link.tcl", "link_opensees.py", "link_sap2000.txt", "loops.csv"];

/// Refuses, before the calibration runs, an output folder that is a file
/// and an output that would overwrite one of the `inputs` (the config, its
/// records, its modes file).
fn check_outputs(dir: &Path, inputs: &[PathBuf]) -> Result<()> {
    if dir.exists() && !dir.is_dir() {
        return Err(crate::commands::InputError(format!(
            "--output-dir {}: it is a file, not a folder; the calibration writes {} there",
            dir.display(),
            OUTPUTS.join(", ")
        ))
        .into());
    }
    for name in OUTPUTS {
        let path = dir.join(name);
        if let Some(input) = inputs.iter().find(|i| quakejoint_io::files::same_file(&path, i)) {
            return Err(crate::commands::InputError(format!(
                "{}: the calibration would overwrite its input {} there; choose another --output-dir",
                path.display(),
                input.display()
            ))
            .into());
        }
    }
    Ok(())
}

/// Writes the exports and the loops; returns the paths written.
fn write_exports(c: &Calibration, dir: &Path, source: &str) -> Result<Vec<PathBuf>> {
    std::fs::create_dir_all(dir).with_context(|| format!("creating {}", dir.display()))?;
    let texts = [
        export::toml(c, source),
        export::opensees_tcl(c, source),
        export::opensees_py(c, source),
        export::sap2000(c, source),
        loops_csv(c),
    ];
    let mut written = Vec::new();
    for (name, text) in OUTPUTS.into_iter().zip(texts) {
        let path = dir.join(name);
        std::fs::write(&path, text).with_context(|| format!("writing {}", path.display()))?;
        written.push(path);
    }
    Ok(written)
}

/// Every loop: amplitude, time, opening, the detailed joint's force and
/// the link's (its elastic-perfectly-plastic law), on the deck.
fn loops_csv(c: &Calibration) -> String {
    let mut out = String::from("amplitude [m],t [s],u [m],detailed force [N],link force [N]\n");
    for l in &c.loops {
        let link = elastoplastic(&l.u, c.link.stiffness, c.link.friction);
        for (((t, u), f), g) in l.t.iter().zip(&l.u).zip(&l.force).zip(&link) {
            let _ = writeln!(out, "{},{t},{u},{f},{g}", l.amplitude);
        }
    }
    out
}

/// A length in millimetres, "closed" for NaN (the racking of a record
/// under which a cell closed).
fn shown_mm(x: f64) -> String {
    if x.is_nan() {
        "closed".to_string()
    } else {
        format!("{:.1}", x * 1e3)
    }
}

fn table(c: &Calibration, config: &Path, written: &[PathBuf]) -> String {
    let l = &c.link;
    let mut s = String::new();
    let _ = writeln!(s, "{}: the link element of its [joint] (docs/link.md)", config.display());
    let _ = writeln!(s, "  spring (stuck joint)       {:>12.4e} N/m", l.stiffness);
    let _ = writeln!(
        s,
        "  slider (friction)          {:>12.4e} N    (hand calculation {:.4e} N)",
        l.friction, c.hand_friction
    );
    let _ = writeln!(
        s,
        "  moving mass                {:>12.4e} kg   (sliding as a whole {:.4e} kg)",
        l.mass, c.kinetic_mass
    );
    let _ = writeln!(s, "  damper (with the spring)   {:>12.4e} N s/m", l.damping.unwrap_or(0.0));
    let _ = writeln!(s, "  closing movement (gap)     {:>12.4e} m    ({} cells)", c.gap, c.cells);
    let _ = writeln!(
        s,
        "  closed-joint stiffness     {:>12.4e} N/m  (secant at {:.3e} N: {})",
        l.gap_stiffness, c.secant_force, c.secant_from
    );
    let _ = writeln!(
        s,
        "  racking                    {:>5.1} / {:.1} mm (narrowest cell behind the average closing / widest ahead of it \
         opening: {})",
        l.racking()[0] * 1e3,
        l.racking()[1] * 1e3,
        c.racking_from
    );
    let _ = writeln!(s, "  first cell closes at       {:>12.4e} m    (the beams strike)", c.first_closure());
    let _ = writeln!(s, "  opening capacity           {:>12.4e} m    (the widest cell)", c.capacity);
    let _ = writeln!(
        s,
        "  fit: RMS force error {:.4e} N ({:.2} % of the slider force) over {} loops at {} m/s",
        c.fit_rms,
        100.0 * c.fit_rms / l.friction,
        c.loops.len(),
        c.options.speed
    );
    if !c.dynamic.is_empty() {
        let _ = writeln!(
            s,
            "under the calibration suite: the link's peak force on the deck and friction energy against the detailed \
             joint's, the mass each record alone calls for, and the detailed joint's racking (closing / opening)"
        );
        let _ = writeln!(
            s,
            "  {:<32} {:>11} {:>11} {:>7} {:>11} {:>11} {:>7} {:>11} {:>15}",
            "record", "peak [N]", "detailed", "error", "E_f [J]", "detailed", "error", "own m [kg]", "racking [mm]"
        );
        for d in &c.dynamic {
            let _ = writeln!(
                s,
                "  {:<32} {:>11.4e} {:>11.4e} {:>+6.1}% {:>11.4e} {:>11.4e} {:>+6.1}% {:>11.4e} {:>15}",
                d.record,
                d.peak_link,
                d.peak_detailed,
                100.0 * (d.peak_link / d.peak_detailed - 1.0),
                d.friction_link,
                d.friction_detailed,
                100.0 * (d.friction_link / d.friction_detailed - 1.0),
                d.own_mass,
                format!("{} / {:.1}", shown_mm(d.racking[0]), d.racking[1] * 1e3)
            );
        }
    }
    let _ = writeln!(s, "equivalent viscous damping ratio E_D / (4 pi E_S) against the amplitude");
    let _ = writeln!(
        s,
        "  {:>10} {:>12} {:>12} {:>12} {:>10} {:>12}",
        "amplitude", "E_D [J]", "link E_D", "peak F [N]", "joint", "on bridge"
    );
    for p in &c.loops {
        let bridge = p.damping_bridge.map_or_else(|| "-".to_string(), |x| format!("{:.3e}", x));
        // (the amplitude as written: 0.002, not 0.0020)
        let _ = writeln!(
            s,
            "  {:>10} {:>12.4e} {:>12.4e} {:>12.4e} {:>10.3} {:>12}",
            format!("{} m", p.amplitude),
            p.energy,
            p.link_energy,
            p.peak_force,
            p.damping_joint,
            bridge
        );
    }
    if !c.warnings.is_empty() {
        let _ = writeln!(s, "WARNINGS (the calibration cannot stand behind all of it):");
        for w in &c.warnings {
            let _ = writeln!(s, "  {w}");
        }
    }
    let _ = writeln!(s, "written:");
    for w in written {
        let _ = writeln!(s, "  {}", w.display());
    }
    s
}

fn json_of(c: &Calibration, written: &[PathBuf]) -> serde_json::Value {
    // (the numbers from the one list of them, Calibration::scalars, as
    // Python's; NaN is null)
    let numbers = |pairs: &[(&str, f64, &str)]| -> serde_json::Map<String, serde_json::Value> {
        pairs.iter().map(|(k, v, _)| (k.to_string(), json!(v))).collect()
    };
    let mut out = numbers(&c.scalars());
    let suite = c
        .dynamic
        .iter()
        .map(|d| {
            let mut e = numbers(&d.scalars());
            e.insert("record".into(), json!(d.record));
            serde_json::Value::Object(e)
        })
        .collect::<Vec<_>>();
    out.insert("suite".into(), json!(suite));
    out.insert("gap_hertz".into(), json!(c.link.gap_hertz));
    out.insert("warnings".into(), json!(c.warnings));
    out.insert("cells".into(), json!(c.cells));
    let loops = c.loops.iter().map(|p| serde_json::Value::Object(numbers(&p.scalars()))).collect::<Vec<_>>();
    out.insert("loops".into(), json!(loops));
    out.insert("written".into(), json!(written.iter().map(|p| p.display().to_string()).collect::<Vec<_>>()));
    serde_json::Value::Object(out)
}
