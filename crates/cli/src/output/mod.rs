//! Printing results as tables or JSON.

/// `println!` to stdout that ends the program quietly when the reader has
/// gone away (`quakejoint ... | head`) instead of panicking.
macro_rules! out {
    ($($arg:tt)*) => {{
        use std::io::Write as _;
        if let Err(e) = writeln!(std::io::stdout(), $($arg)*) {
            if e.kind() == std::io::ErrorKind::BrokenPipe {
                std::process::exit(0);
            }
        }
    }};
}

use std::path::Path;

use quakejoint_model::generator::JointModel;
use quakejoint_model::service::ServiceResult;
use quakejoint_model::Config;
use quakejoint_motion::{LoadedRecord, RecordStats, SpectrumRow};
use quakejoint_solver::Assembly;
use serde_json::json;

mod run;
mod sweep;

pub use run::run_result;
pub use sweep::{compare_summary, merge_summary, plan_summary, sweep_check, sweep_summary};

/// `quakejoint model`.
pub fn model_summary(path: &Path, config: &Config, model: &JointModel, asm: &Assembly, json: bool) {
    let c = model.counts;
    let nc = model.center_beams.len();
    let ns = model.supports.len();
    if json {
        let v = json!({
            "config": path.display().to_string(),
            "bodies": c.bodies,
            "center_beams": nc,
            "support_beams": ns,
            "bearings": nc * ns,
            "coordinates": c.coordinates,
            "constraints": c.constraints,
            "dof": c.dof,
            "jacobian_nnz": asm.jacobian_nnz(),
            "unknowns": asm.dim(),
            "block_lu_values": asm.block_structure().nnz(),
            "block_lu_flops": asm.block_structure().flops(),
            "gap": model.geometry.as_ref().map(|g| g.gap),
            "bridge_omega": model.bridge.omega,
            "bridge_period": 2.0 * std::f64::consts::PI / model.bridge.omega,
            "bridge_model": if model.modal.is_some() { "modal" } else { "single-DOF" },
            "modes": model.modal.as_ref().map(|m| m.parts.modes.len()),
            "joints": model.joints().map(|j| json!({
                "name": j.name,
                "center_beams": j.center_beams.len(),
                "support_beams": j.supports.len(),
                "bearings": j.center_beams.len() * j.supports.len(),
                "gap": j.geometry.as_ref().map(|g| g.gap),
                "turned": j.sign < 0.0,
            })).collect::<Vec<_>>(),
            "geometry": model.geometry.as_ref().map(|g| json!({
                "gap": g.gap,
                "pitch": g.pitch,
                "center_beam_width": g.width,
                "center_beam_length": config.joint.center_beam.length,
                "center_x": g.center_x,
                "supports": g.supports.iter().map(|s| json!({
                    "kind": match s.kind { quakejoint_model::config::SupportKind::Guide => "guide", quakejoint_model::config::SupportKind::Joist => "joist" },
                    "y0": s.y0,
                    "angle_deg": s.theta.to_degrees(),
                    "box_dy": s.box_dy,
                })).collect::<Vec<_>>(),
                "bearings": g.center_x.iter().zip(&g.bearing_y).flat_map(|(&x, ys)| ys.iter().map(move |&y| [x, y])).collect::<Vec<_>>(),
            })),
        });
        out!("{v}");
        return;
    }
    out!("model {}", path.display());
    match &model.modal {
        None => out!(
            "  rigid bodies          {:>8}  ({nc} center beams, {ns} support beams, {} bearings)",
            c.bodies,
            nc * ns
        ),
        Some(m) => {
            out!(
                "  rigid bodies          {:>8}  (the joints' below, {} modes and {} joint ends of the bridge)",
                c.bodies,
                m.parts.modes.len(),
                m.parts.ends.len()
            );
            for j in model.joints() {
                let (nc, ns) = (j.center_beams.len(), j.supports.len());
                out!(
                    "    joint \"{}\"{}: {nc} center beams, {ns} support beams, {} bearings{}",
                    j.name,
                    if j.sign < 0.0 { " (turned half a turn)" } else { "" },
                    nc * ns,
                    j.geometry.as_ref().map_or(String::new(), |g| format!(", gap G0 {:.4} m", g.gap))
                );
            }
        }
    }
    out!("  coordinates           {:>8}  (body coordinates and the deck's u)", c.coordinates);
    out!("  constraint equations  {:>8}", c.constraints);
    out!("  degrees of freedom    {:>8}", c.dof);
    out!("  Jacobian non-zeros    {:>8}  (iteration matrix, {} unknowns)", asm.jacobian_nnz(), asm.dim());
    match (&model.modal, &config.bridge.modal) {
        (Some(m), Some(c)) => out!(
            "  bridge                given by its modes: {} modes of {} (longest period {:.4} s)",
            m.parts.modes.len(),
            c.modes,
            2.0 * std::f64::consts::PI / model.bridge.omega
        ),
        _ => {
            if let Some(g) = &model.geometry {
                out!("  gap G0                {:>8.4} m", g.gap);
            }
            out!(
                "  bridge                {:>8.3e} kg, w0 {:.4} rad/s (T {:.4} s), damping {}",
                config.bridge.mass,
                model.bridge.omega,
                2.0 * std::f64::consts::PI / model.bridge.omega,
                config.bridge.damping
            );
        }
    }
}

/// Merges the fields of `more` into the object `v`.
fn extend(v: &mut serde_json::Value, more: serde_json::Value) {
    if let (Some(obj), serde_json::Value::Object(more)) = (v.as_object_mut(), more) {
        obj.extend(more);
    }
}

/// The record as read, in one line: the file, its format and units, the
/// scale and the PGA, so that a unit or scale slip shows.
pub fn record_line(loaded: &LoadedRecord) -> String {
    let record = &loaded.record;
    format!(
        "record {} ({}, numbers in {}, scale {}): PGA {:.4} g, dt {} s, {:.2} s",
        record.source,
        loaded.format.name(),
        record.units.name(),
        quakejoint_motion::number(record.user_scale),
        record.pga() / quakejoint_motion::G,
        record.dt,
        record.duration()
    )
}

/// The validity of a run in the table: ok, or the flags and findings.
fn validity_lines(v: &quakejoint_model::validity::Validity) {
    if v.flags.is_ok() {
        out!("validity: ok (no collision, bearings on their supports, energy balance closed)");
    } else if !v.flags.is_flagged() {
        out!("validity: not checked");
        for f in &v.findings {
            out!("  {f}");
        }
    } else {
        out!("VALIDITY: {} (the model cannot stand behind these numbers)", v.flags.label());
        for f in &v.findings {
            out!("  {f}");
        }
    }
}

/// `quakejoint service`.
pub fn service_result(path: &Path, r: &ServiceResult, json: bool) {
    let deficit = r.compliance_deficit;
    if json {
        let mut v = json!({
            "config": path.display().to_string(),
            "period": r.period,
            "cycles": r.cycles,
            "friction_work_per_cycle": r.friction_work_per_cycle,
            "loop_work_per_cycle": r.loop_work_per_cycle,
            "hand_calculation": r.hand_calculation,
            "compliance_deficit": deficit,
            "damping_work_per_cycle": r.damping_work_per_cycle,
            "contact_work_per_cycle": r.contact_work_per_cycle,
            "min_subgap": r.min_subgap,
            "max_subgap": r.max_subgap,
            "validity": r.validity.flags.0,
            "validity_label": r.validity.flags.label(),
            "flags": r.validity.flags.names(),
            "findings": r.validity.findings,
            "warnings": r.warnings,
            "peak_joint_force": r.peak_joint_force,
            "energy_error": r.energy_error,
            "steps": r.stats.steps,
            "wall_time_s": r.wall_time_s,
        });
        let res = &r.residuals;
        extend(
            &mut v,
            json!({
                "max_position_residual": res.position,
                "max_angle_residual": res.angle,
                "max_velocity_residual": res.velocity,
                "max_angular_velocity_residual": res.angular_velocity,
            }),
        );
        out!("{v}");
        return;
    }
    let against = if r.hand_calculation > 0.0 {
        format!("{:+.1} % against the hand calculation", 100.0 * (r.friction_work_per_cycle / r.hand_calculation - 1.0))
    } else {
        "no friction in the hand calculation".to_string()
    };
    out!("{}: service case, {} cycles of {:.3} s", path.display(), r.cycles, r.period);
    out!("  friction work per cycle      {:>12.1} J (last cycle; {against})", r.friction_work_per_cycle);
    out!(
        "  hand calculation             {:>12.1} J (sum of mu n_s F_N x sliding distance, rigid bushings)",
        r.hand_calculation
    );
    match deficit {
        Some(d) => out!(
            "  bushing compliance deficit   {:>12.1} J (closed form: friction work expected between {:.1} and {:.1} J)",
            d,
            r.hand_calculation - d,
            r.hand_calculation
        ),
        None => out!("  bushing compliance           not computable (a center beam is not held by its bearings)"),
    }
    out!("  hysteresis loop area         {:>12.1} J (work of the deck on the joint)", r.loop_work_per_cycle);
    out!("  damper work per cycle        {:>12.1} J (bushing dampers)", r.damping_work_per_cycle);
    out!(
        "  impact work per cycle        {:>12.1} J (pounding; friction, dampers and impacts: what the loop area equals)",
        r.contact_work_per_cycle
    );
    out!("  peak joint force on the deck {:>12.1} N", r.peak_joint_force);
    out!("  sub-gaps                     {:>9.2} .. {:.2} mm", r.min_subgap * 1e3, r.max_subgap * 1e3);
    validity_lines(&r.validity);
    let res = &r.residuals;
    out!(
        "  energy balance error {:.2e}, constraint residuals {:.1e} m, {:.1e} rad, {} steps, {:.2} s wall",
        r.energy_error,
        res.position.max(res.velocity),
        res.angle.max(res.angular_velocity),
        r.stats.steps,
        r.wall_time_s
    );
}

/// `quakejoint record`.
pub fn record_stats(loaded: &LoadedRecord, s: &RecordStats, json: bool) {
    let (record, warnings) = (&loaded.record, &loaded.warnings);
    if json {
        let v = json!({
            "file": record.source,
            "name": record.name,
            "format": loaded.format.name(),
            "file_units": record.units.name(),
            "file_pga": record.file_pga,
            "user_scale": record.user_scale,
            "dt": s.dt,
            "samples": s.samples,
            "duration": s.duration,
            "pga": s.pga, "t_pga": s.t_pga,
            "pgv": s.pgv, "t_pgv": s.t_pgv,
            "pgd": s.pgd, "t_pgd": s.t_pgd,
            "arias": s.arias,
            "d5_95": s.d5_95, "t5": s.t5, "t95": s.t95,
            "scale": record.scale,
            "channel": loaded.channel,
            "warnings": warnings,
            "units": {
                "dt": "s", "duration": "s", "pga": "m/s^2", "t_pga": "s", "pgv": "m/s", "t_pgv": "s",
                "pgd": "m", "t_pgd": "s", "arias": "m/s", "d5_95": "s", "t5": "s", "t95": "s",
                "file_pga": record.units.name(), "scale": "m/s^2 per file unit", "user_scale": "1",
            },
        });
        out!("{v}");
        return;
    }
    let g = quakejoint_motion::G;
    out!("record {} ({})", record.name, record.source);
    if loaded.format == quakejoint_motion::Format::At2 {
        // the event and station line
        for h in record.header.iter().skip(1).take(1) {
            out!("  {}", h.trim());
        }
    }
    out!(
        "  read as           {} file, numbers in {} (PGA in the file {:.5} {}), scale {}",
        loaded.format.name(),
        record.units.name(),
        record.file_pga,
        record.units.name(),
        quakejoint_motion::number(record.user_scale)
    );
    if let Some(c) = &loaded.channel {
        out!("  channel           {}", c.describe());
    }
    out!("  dt                {:>12.5} s", s.dt);
    out!("  samples           {:>12}", s.samples);
    out!("  duration          {:>12.3} s (first to last sample: (samples - 1) dt)", s.duration);
    out!("  PGA               {:>12.5} m/s^2 ({:.4} g) at t = {:.3} s", s.pga, s.pga / g, s.t_pga);
    out!("  PGV               {:>12.5} m/s at t = {:.3} s", s.pgv, s.t_pgv);
    out!("  PGD               {:>12.5} m at t = {:.3} s (raw integration, no baseline correction)", s.pgd, s.t_pgd);
    out!("  Arias intensity   {:>12.5} m/s", s.arias);
    out!("  D5-95             {:>12.3} s (from {:.3} s to {:.3} s)", s.d5_95, s.t5, s.t95);
}

/// `quakejoint spectrum`: CSV (default) or JSON.
pub fn spectrum_rows(rows: &[SpectrumRow], json: bool) {
    if json {
        let v: Vec<_> = rows
            .iter()
            .map(|r| {
                json!({
                    "damping": r.damping, "period": r.period,
                    "sa": r.peaks.sa, "psa": r.peaks.psa, "sd": r.peaks.sd, "sv": r.peaks.sv,
                    "psv": r.peaks.psv, "t_sa": r.peaks.t_sa, "t_sd": r.peaks.t_sd, "t_sv": r.peaks.t_sv,
                })
            })
            .collect();
        out!("{}", serde_json::Value::Array(v));
        return;
    }
    out!("damping [1],period [s],sa [m/s^2],psa [m/s^2],sd [m],sv [m/s]");
    for r in rows {
        // every digit (the shortest text that reads back as the same number)
        out!("{},{},{:e},{:e},{:e},{:e}", r.damping, r.period, r.peaks.sa, r.peaks.psa, r.peaks.sd, r.peaks.sv);
    }
}
