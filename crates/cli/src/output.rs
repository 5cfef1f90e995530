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
use quakejoint_model::run::{PlacedJointResult, RunResult};
use quakejoint_model::service::ServiceResult;
use quakejoint_model::validity::Flags;
use quakejoint_model::Config;
use quakejoint_motion::{LoadedRecord, RecordStats, SpectrumRow};
use quakejoint_solver::Assembly;
use serde_json::json;

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
    out!("  rigid bodies          {:>8}  ({nc} center beams, {ns} support beams, {} bearings)", c.bodies, nc * ns);
    out!("  coordinates           {:>8}  (body coordinates and the deck's u)", c.coordinates);
    out!("  constraint equations  {:>8}", c.constraints);
    out!("  degrees of freedom    {:>8}", c.dof);
    out!("  Jacobian non-zeros    {:>8}  (iteration matrix, {} unknowns)", asm.jacobian_nnz(), asm.dim());
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

/// The residuals of a run as JSON (each in its unit).
/// Every scalar result of a run ([`quakejoint_model::fields::FIELDS`]):
/// counts as whole numbers, what the run did not compute (NaN) as null.
fn fields_json(r: &RunResult) -> serde_json::Value {
    let map = quakejoint_model::fields::FIELDS
        .iter()
        .map(|f| {
            let x = (f.value)(r);
            let value = match (x.is_finite(), f.count) {
                (false, _) => serde_json::Value::Null,
                (true, true) => json!(x as u64),
                (true, false) => json!(x),
            };
            (f.name.to_string(), value)
        })
        .collect();
    serde_json::Value::Object(map)
}

/// The lines of one more joint of `[[joints]]`.
fn placed_joint_lines(j: &PlacedJointResult) {
    out!("joint \"{}\"", j.name);
    out!("  its deck point: Sa {:.5} m/s^2 at t = {:.3} s, Sd {:.6} m, Sv {:.5} m/s", j.sa, j.t_sa, j.sd, j.sv);
    out!("  peak joint force on the deck  {:>12.1} N", j.peak_joint_force);
    if let (Some(lo), Some(hi), Some(dev)) = (j.min_subgap, j.max_subgap, j.max_subgap_deviation) {
        out!(
            "  sub-gaps                      {:>9.2} .. {:.2} mm (deviation from equal {:.2} mm)",
            lo * 1e3,
            hi * 1e3,
            dev * 1e3
        );
    }
    let p = &j.pounding;
    if p.impacts == 0 {
        out!("  pounding                      none (no sub-gap closed)");
    } else {
        out!("  impacts                       {:>12} (beam ends)", p.impacts);
        out!("  peak contact force            {:>12.1} N at t = {:.3} s", p.peak_contact_force, p.peak_contact_time);
        out!("  closed joint on the deck      {:>12.1} N", p.peak_deck_contact_force);
    }
    out!("  validity: {}", j.validity.flags.label());
}

/// A modal bridge's points and base shear, with the joints and without.
fn bridge_lines(r: &RunResult) {
    if r.points.is_empty() {
        return;
    }
    if let Some((check, warnings)) = &r.mode_check {
        let mass =
            check.mass_ratio.map_or("no total_mass_x in the file".to_string(), |m| format!("{:.1} %", m * 100.0));
        let flex: Vec<String> = r
            .points
            .iter()
            .zip(&check.flexibility)
            .filter(|(_, f)| f.is_finite())
            .map(|(p, f)| format!("{} {:.1} %", p.name, f * 100.0))
            .collect();
        out!(
            "the kept modes hold: mass along x {mass}; static flexibility {}",
            if flex.is_empty() {
                "not known (no [static] table in the modes file)".to_string()
            } else {
                flex.join(", ")
            }
        );
        for &(p, q, f) in &check.between {
            if f.is_finite() {
                out!(
                    "  and {:.1} % of the flexibility between {} and {}",
                    f * 100.0,
                    r.points[p].name,
                    r.points[q].name
                );
            }
        }
        for w in warnings {
            eprintln!("warning: {w}");
        }
    }
    if r.exact_linear {
        out!("the bridge's points (along x)");
        for p in &r.points {
            out!("  {:<24} Sd {:>9.5} m  Sa {:>9.4} m/s^2", p.name, p.sd, p.sa);
        }
        if let Some(v) = r.base_shear {
            out!("  base shear (kept modes)    {:>14.1} kN", v / 1e3);
        }
        return;
    }
    out!("the bridge's points (along x)          with the joints         without");
    for p in &r.points {
        out!(
            "  {:<24} Sd {:>9.5} m  Sa {:>9.4} m/s^2   Sd {:>9.5} m  Sa {:>9.4} m/s^2",
            p.name,
            p.sd,
            p.sa,
            p.sd_without,
            p.sa_without
        );
    }
    if let (Some(v), Some(w)) = (r.base_shear, r.base_shear_without) {
        out!("  base shear (kept modes)    {:>14.1} kN {:>27.1} kN", v / 1e3, w / 1e3);
    }
}

/// One more joint of `[[joints]]` as JSON.
fn placed_joint_json(j: &PlacedJointResult) -> serde_json::Value {
    json!({
        "name": j.name,
        "sa": j.sa,
        "t_sa": j.t_sa,
        "sd": j.sd,
        "sv": j.sv,
        "peak_joint_force": j.peak_joint_force,
        "min_subgap": j.min_subgap,
        "max_subgap": j.max_subgap,
        "max_subgap_deviation": j.max_subgap_deviation,
        "impacts": j.pounding.impacts,
        "peak_contact_force": j.pounding.peak_contact_force,
        "peak_deck_contact_force": j.pounding.peak_deck_contact_force,
        "max_penetration": j.pounding.max_penetration,
        "validity": j.validity.flags.0,
        "validity_label": j.validity.flags.label(),
        "findings": j.validity.findings,
    })
}

/// Merges the fields of `more` into the object `v`.
fn extend(v: &mut serde_json::Value, more: serde_json::Value) {
    if let (Some(obj), serde_json::Value::Object(more)) = (v.as_object_mut(), more) {
        obj.extend(more);
    }
}

/// `quakejoint simulate`. Quantities not computed (the joint's, without
/// it) are `null` in JSON and left out of the table.
/// With `modal`, the deck's values are those of the joint's point of the
/// modes file.
pub fn run_result(path: &Path, loaded: &LoadedRecord, r: &RunResult, config: &Config, json: bool) {
    let modal = config.bridge.modal.as_ref();
    // the point the deck's values are at: the joint's, or the first of [[joints]]'
    let point =
        modal.and_then(|m| m.joint_point.clone()).or_else(|| config.joints.first().map(|j| j.deck_point.clone()));
    let v = &r.validity;
    let record = &loaded.record;
    if json {
        let mut out = json!({
            "config": path.display().to_string(),
            "record": record.name,
            "record_file": record.source,
            "record_format": loaded.format.name(),
            "record_file_units": record.units.name(),
            "record_scale": record.user_scale,
            "record_pga_g": record.pga() / quakejoint_motion::G,
            "joint": !r.exact_linear,
            "method": if r.exact_linear { "exact linear" } else { "multibody" },
            "validity": v.flags.0,
            "validity_label": v.flags.label(),
            "flags": v.flags.names(),
            "findings": v.findings,
            "peak_contact_place": r.pounding.peak_contact_place.map(|p| json!({"gap": p.gap, "end": p.end})),
            "bridge_model": if modal.is_some() { "modal" } else { "single-DOF" },
            "modes_file": modal.map(|m| m.modes.clone()),
            "joint_point": point,
            "joint_name": config.joints.first().map(|j| j.name.clone()),
            "joints": r.joints.iter().map(placed_joint_json).collect::<Vec<_>>(),
            "points": r.points.iter().map(|p| json!({
                "name": p.name, "sd": p.sd, "t_sd": p.t_sd, "sa": p.sa, "t_sa": p.t_sa,
                "sd_without_joint": p.sd_without, "sa_without_joint": p.sa_without,
            })).collect::<Vec<_>>(),
            "base_shear": r.base_shear,
            "mass_ratio": r.mode_check.as_ref().and_then(|(c, _)| c.mass_ratio),
            "flexibility_captured": r.mode_check.as_ref().map(|(c, _)| c.flexibility.clone()),
            "warnings": r.mode_check.as_ref().map(|(_, w)| w.clone()).unwrap_or_default(),
            "base_shear_without_joint": r.base_shear_without,
        });
        extend(&mut out, fields_json(r));
        out!("{out}");
        return;
    }
    let mode = match (r.exact_linear, r.joints.len()) {
        (true, _) => "bridge alone (exact linear solution)".to_string(),
        (false, 0) => "bridge with joint".to_string(),
        (false, n) => format!("bridge with {} joints", n + 1),
    };
    out!("{} under {}: {mode}", path.display(), record.name);
    out!("  {}", record_line(loaded));
    let period = 2.0 * std::f64::consts::PI / r.omega;
    match modal {
        Some(m) => {
            let kept = m.loaded.as_ref().map_or(0, |b| m.modes_used.unwrap_or(b.modes.len()).min(b.modes.len()));
            out!(
                "  modal bridge: {kept} modes of {} (longest period {period:.4} s), values at its point \"{}\", \
                 {:.2} s simulated",
                m.modes,
                point.unwrap_or_default(),
                r.duration
            );
        }
        None => out!("  w0 {:.4} rad/s, T {period:.4} s, {:.2} s simulated", r.omega, r.duration),
    }
    out!("  Sa   {:>12.5} m/s^2  at t = {:.3} s", r.sa, r.t_sa);
    out!("  PSa  {:>12.5} m/s^2", r.psa);
    out!("  Sd   {:>12.6} m      at t = {:.3} s", r.sd, r.t_sd);
    out!("  Sv   {:>12.5} m/s    at t = {:.3} s", r.sv, r.t_sv);
    if r.exact_linear {
        bridge_lines(r);
        out!("validity: not checked (no joint)");
        return;
    }
    if let Some(f) = &r.far {
        out!(
            "  adjacent segment: T {:.4} s, Sa {:.5} m/s^2 at t = {:.3} s (without the joint {:.5}), Sd {:.6} m; \
             decks apart by up to {:.4} m",
            2.0 * std::f64::consts::PI / f.omega,
            f.sa,
            f.t_sa,
            f.sa_without,
            f.sd,
            f.max_relative_displacement
        );
    }
    if let Some(y) = &r.transverse {
        out!(
            "  across: T_y {:.4} s, Sa_y {:.5} m/s^2 at t = {:.3} s (without the joint {:.5}), Sd_y {:.6} m, joint \
             force across {:.1} N",
            2.0 * std::f64::consts::PI / y.omega,
            y.sa,
            y.t_sa,
            y.sa_without,
            y.sd,
            y.peak_joint_force
        );
    }
    let first = config.joints.first().map_or_else(|| "joint demands".to_string(), |j| format!("joint \"{}\"", j.name));
    out!("{first}");
    out!("  peak joint force on the deck  {:>12.1} N", r.peak_joint_force);
    out!("  peak bushing force            {:>12.1} N", r.peak_bushing_force);
    out!("  peak friction force           {:>12.1} N", r.peak_friction_force);
    out!("  friction energy               {:>12.1} J", r.friction_energy);
    if let (Some(lo), Some(hi), Some(dev)) = (r.min_subgap, r.max_subgap, r.max_subgap_deviation) {
        out!(
            "  sub-gaps                      {:>9.2} .. {:.2} mm (deviation from equal {:.2} mm)",
            lo * 1e3,
            hi * 1e3,
            dev * 1e3
        );
    }
    let p = &r.pounding;
    if p.impacts == 0 {
        out!("  pounding                      none (no sub-gap closed)");
    } else {
        out!("  impacts                       {:>12} (beam ends)", p.impacts);
        out!("  peak contact force            {:>12.1} N at t = {:.3} s", p.peak_contact_force, p.peak_contact_time);
        if let Some(place) = p.peak_contact_place {
            out!("    between {}", place.describe());
        }
        out!(
            "  closed joint on the deck      {:>12.1} N (peak, through the deck's edge beam)",
            p.peak_deck_contact_force
        );
        out!("  contact energy                {:>12.1} J (dissipated by the impacts)", p.contact_energy);
        out!("  deepest penetration           {:>12.3} mm", p.max_penetration * 1e3);
    }
    for j in &r.joints {
        placed_joint_lines(j);
    }
    bridge_lines(r);
    if !r.joints.is_empty() {
        out!("  (bushing and friction peaks, friction and contact energy: all joints together)");
    }
    validity_lines(v);
    out!("quality");
    out!("  energy balance error          {:>12.2e} of the earthquake work", r.energy_error);
    let res = &r.residuals;
    out!(
        "  constraint residuals          {:>12.2e} m, {:.2e} rad (|g|); {:.2e} m/s, {:.2e} rad/s (|G q'|)",
        res.position,
        res.angle,
        res.velocity,
        res.angular_velocity
    );
    let s = &r.stats;
    out!(
        "  steps {} (rejected {}, failed {}), Newton iterations {}, Jacobians {}, factorisations {}, {:.2} s wall, \
         {:.2} s CPU",
        s.steps,
        s.rejected,
        s.failed_attempts,
        s.newton_iterations,
        s.jacobian_evaluations,
        s.factorizations,
        r.wall_time_s,
        r.cpu_time_s
    );
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
    out!("damping,period,sa,psa,sd,sv");
    for r in rows {
        out!("{},{},{:.9e},{:.9e},{:.9e},{:.9e}", r.damping, r.period, r.peaks.sa, r.peaks.psa, r.peaks.sd, r.peaks.sv);
    }
}

/// `quakejoint sweep`.
///
/// `next` continues an interrupted sweep; `retry` runs its failed jobs again.
pub fn sweep_summary(
    s: &quakejoint_sweep::Summary,
    next: Option<&crate::continuation::Next>,
    retry: Option<&crate::continuation::Next>,
    json: bool,
) {
    // a bridge given by its modes sweeps period scales, not periods
    let axis = if s.modal { "period_scale" } else { "period" };
    let at = |z: f64, t: f64| if s.modal { format!("period scale {t}") } else { format!("damping {z} / T {t:.4} s") };
    if json {
        let failures: Vec<_> = s
            .failed
            .iter()
            .map(|(case, record, z, t, msg)| json!({"case": case, "record": record, "damping": z, axis: t, "message": msg}))
            .collect();
        let v = json!({
            "output": s.output.display().to_string(),
            "journal": s.journal.display().to_string(),
            "jobs": s.jobs,
            "resumed": s.resumed,
            "retried": s.retried,
            "ran": s.ran,
            "not_run": s.not_run,
            "complete": s.not_run == 0,
            "interrupted": s.interrupted,
            "failed": s.failed.len(),
            "failures": failures,
            "flagged": s.flagged.len(),
            "flag_counts": flag_counts(&s.flagged),
            "flagged_jobs": s.flagged.iter().map(|(case, record, z, t, bits, findings)| json!({
                "case": case, "record": record, "damping": z, axis: t,
                "validity": bits, "flags": Flags(*bits).names(), "findings": findings,
            })).collect::<Vec<_>>(),
            "pounded": s.pounded,
            "peak_contact_force": s.peak_contact.as_ref().map(|p| p.0),
            "notices": s.notices,
            "continue_command": next.map(|n| &n.command),
            "retry_command": retry.map(|n| &n.command),
            "wall_time_s": s.wall_time_s,
            "peak_memory_mb": s.peak_memory_mb,
        });
        out!("{v}");
        return;
    }
    let mut state = if s.interrupted {
        "interrupted"
    } else if s.ran == 0 && s.not_run == 0 {
        "already complete"
    } else {
        "complete"
    }
    .to_string();
    if !s.interrupted && !s.failed.is_empty() {
        // never just "complete" while jobs wait to be retried
        state += &format!(", but {} of its jobs failed", s.failed.len());
    }
    let retried = if s.retried > 0 { format!(", {} failed jobs retried", s.retried) } else { String::new() };
    out!(
        "sweep {state}: {} of {} jobs done ({} from the journal{retried}, {} run now) in {:.1} s -> {}",
        s.jobs - s.not_run,
        s.jobs,
        s.resumed,
        s.ran,
        s.wall_time_s,
        s.output.display()
    );
    if let Some((f, case, record, z, t)) = &s.peak_contact {
        out!(
            "pounding: the beams of {} job(s) struck each other; the largest contact force, {:.1} kN, in {case} / \
             {record} / {}",
            s.pounded,
            f / 1e3,
            at(*z, *t)
        );
    }
    if let Some(mb) = s.peak_memory_mb {
        out!("peak memory: {mb:.0} MB");
    }
    if !s.failed.is_empty() {
        out!("{} jobs failed:", s.failed.len());
        for (case, record, z, t, msg) in &s.failed {
            out!("  {case} / {record} / {}: {msg}", at(*z, *t));
        }
        if let Some(retry) = retry {
            out!(
                "after fixing the cause (raising simulation.max_wall_time or max_steps, say), run the {} failed jobs \
                 again (`--retry-failed`; the finished ones are kept) with:\n{retry}",
                s.failed.len()
            );
        }
    }
    if !s.flagged.is_empty() {
        let counts: Vec<String> = flag_counts(&s.flagged).iter().map(|(n, c)| format!("{n} {c}")).collect();
        out!(
            "{} jobs FLAGGED ({}): they finished outside what the model can stand behind:",
            s.flagged.len(),
            counts.join(", ")
        );
        const SHOWN: usize = 10;
        for (case, record, z, t, _, findings) in s.flagged.iter().take(SHOWN) {
            out!("  {case} / {record} / {}: {findings}", at(*z, *t));
        }
        if s.flagged.len() > SHOWN {
            out!("  ... and {} more (all in the output's /spectrum/with_joint/findings)", s.flagged.len() - SHOWN);
        }
    }
}

/// How many flagged jobs carry each flag.
fn flag_counts(flagged: &[(String, String, f64, f64, u32, String)]) -> serde_json::Map<String, serde_json::Value> {
    Flags::ALL
        .iter()
        .map(|(f, name)| (name.to_string(), flagged.iter().filter(|j| Flags(j.4).contains(*f)).count()))
        .filter(|(_, n)| *n > 0)
        .map(|(name, n)| (name, json!(n)))
        .collect()
}

/// `quakejoint merge`.
///
/// `retry`, in a job of `scripts/slurm_array.sh`: the resubmission that runs
/// the failed jobs again.
pub fn merge_summary(s: &quakejoint_sweep::MergeSummary, retry: Option<&str>, json: bool) {
    if json {
        let v = json!({
            "output": s.output.display().to_string(),
            "jobs": s.jobs,
            "finished": s.finished,
            "failed": s.failed,
            "flagged": s.flagged,
            "missing": s.missing,
            "complete": s.missing == 0,
            "notices": s.notices,
            "failed_jobs": s.failed_jobs,
            "flagged_jobs": s.flagged_jobs,
        });
        out!("{v}");
        return;
    }
    let state = if s.missing == 0 { "complete" } else { "PARTIAL" };
    const SHOWN: usize = 10;
    let list = |title: String, jobs: &[String]| {
        if !jobs.is_empty() {
            out!("{title}");
            for j in jobs.iter().take(SHOWN) {
                out!("  {j}");
            }
            if jobs.len() > SHOWN {
                out!("  ... and {} more", jobs.len() - SHOWN);
            }
        }
    };
    match retry {
        Some(command) => {
            list(format!("{} jobs failed:", s.failed), &s.failed_jobs);
            out!(
                "after fixing the cause, run them again (on the login node, in the directory slurm_array.sh was run \
                 from: it resubmits their shards) with:\n  {command}"
            );
        }
        None => list(
            format!(
                "{} jobs failed (after fixing the cause, `--retry-failed` on their shards runs them again):",
                s.failed
            ),
            &s.failed_jobs,
        ),
    }
    list(format!("{} jobs FLAGGED (outside what the model can stand behind):", s.flagged), &s.flagged_jobs);
    out!(
        "merged {} of {} jobs ({} failed, {} flagged), {state} -> {}",
        s.finished,
        s.jobs,
        s.failed,
        s.flagged,
        s.output.display()
    );
}

/// `quakejoint plan`.
pub fn plan_summary(
    path: &Path,
    plan: &quakejoint_sweep::Plan,
    shards: &[quakejoint_sweep::plan::Estimate],
    threads: usize,
    sbatch: bool,
    json: bool,
) {
    let worst = shards.iter().fold((0.0f64, 0.0f64), |(s, m), e| (s.max(e.seconds), m.max(e.memory_mb)));
    // cluster requests: twice the estimate, rounded up, at least 256 MB and
    // 10 minutes (nodes slower than the reference machine, shared caches)
    let mem_mb = ((2.0 * worst.1 / 64.0).ceil() * 64.0).max(256.0) as u64;
    let minutes = ((3.0 * worst.0 / threads as f64 / 60.0).ceil() + 10.0) as u64;
    let time = format!("{}:{:02}:00", minutes / 60, minutes % 60);
    if sbatch {
        out!("--cpus-per-task={threads} --mem={mem_mb}M --time={time}");
        return;
    }
    let [nc, nr, nz, nt] = plan.dims();
    // a bridge given by its modes sweeps period scales, not periods
    let (axis, one, many) = if plan.modal.is_some() {
        ("period_scales", "period scale", "period scales")
    } else {
        ("periods", "period", "periods")
    };
    if json {
        let v = json!({
            "config": path.display().to_string(),
            "jobs": plan.job_count(),
            "cases": nc, "records": nr, "dampings": nz, axis: nt,
            "threads_per_shard": threads,
            "shards": shards.iter().enumerate().map(|(k, e)| json!({
                "shard": format!("{}/{}", k + 1, shards.len()),
                "jobs": e.jobs,
                "cpu_seconds": e.seconds,
                "memory_mb": e.memory_mb,
            })).collect::<Vec<_>>(),
            "sbatch": {"cpus_per_task": threads, "mem_mb": mem_mb, "time": time},
        });
        out!("{v}");
        return;
    }
    let total: f64 = shards.iter().map(|e| e.seconds).sum();
    let count = |n: usize, one: &str, many: &str| format!("{n} {}", if n == 1 { one } else { many });
    out!(
        "plan {}: {} ({} x {} x {} x {}), about {} of CPU time on the reference machine",
        path.display(),
        count(plan.job_count(), "job", "jobs"),
        count(nc, "case", "cases"),
        count(nr, "record", "records"),
        count(nz, "damping ratio", "damping ratios"),
        count(nt, one, many),
        quakejoint_sweep::progress::format_duration(total)
    );
    for (k, e) in shards.iter().enumerate() {
        out!(
            "  shard {:>3}/{}: {:>5} jobs, {:>8} on {threads} thread(s), {:.0} MB peak",
            k + 1,
            shards.len(),
            e.jobs,
            quakejoint_sweep::progress::format_duration(e.seconds / threads as f64),
            e.memory_mb
        );
    }
    out!("sbatch resources per shard: --cpus-per-task={threads} --mem={mem_mb}M --time={time}");
}

/// `quakejoint compare`.
pub fn compare_summary(a: &Path, b: &Path, diffs: &[String], json: bool) {
    if json {
        out!(
            "{}",
            json!({"a": a.display().to_string(), "b": b.display().to_string(), "identical": diffs.is_empty(), "differences": diffs})
        );
        return;
    }
    if diffs.is_empty() {
        out!(
            "{} and {}: identical results (wall times, creation times and shard labels aside)",
            a.display(),
            b.display()
        );
    } else {
        out!("{} and {} differ:", a.display(), b.display());
        for d in diffs {
            out!("  {d}");
        }
    }
}

/// `quakejoint sweep --check`.
pub fn sweep_check(c: &quakejoint_sweep::runner::Check, retry: bool, json: bool) {
    if json {
        out!(
            "{}",
            json!({
                "output": c.output.display().to_string(),
                "jobs": c.jobs,
                "done": c.done,
                "failed": c.failed,
                "flagged": c.flagged,
                "journal": c.journal,
                "cpu_seconds": c.cpu_seconds,
                "notices": c.notices,
                "output_problem": c.output_problem,
            })
        );
        return;
    }
    for n in c.notices.iter().chain(&c.output_problem) {
        eprintln!("warning: {n}");
    }
    let what = if !c.journal {
        "would start".to_string()
    } else if c.done == c.jobs && c.failed > 0 && retry {
        format!("would run its {} failed jobs again", c.failed)
    } else if c.done == c.jobs && c.failed > 0 {
        format!("is complete, but {} of its jobs failed, which `--retry-failed` runs again", c.failed)
    } else if c.done == c.jobs {
        "is complete".to_string()
    } else {
        format!("would continue: {} of {} jobs done", c.done, c.jobs)
    };
    let fine = if c.output_problem.is_none() {
        "config, records and output are fine"
    } else {
        "config and records are fine, the output is not (above)"
    };
    out!(
        "check {}: {fine}; the sweep {what} ({} jobs, {} failed and {} flagged so far, about {} of CPU time to go)",
        c.output.display(),
        c.jobs,
        c.failed,
        c.flagged,
        quakejoint_sweep::progress::format_duration(c.cpu_seconds)
    );
}
