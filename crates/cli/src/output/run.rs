//! The results of one run (`quakejoint simulate`): table or JSON.

use std::path::Path;

use quakejoint_model::run::{JointResult, RunResult};
use quakejoint_model::Config;
use quakejoint_motion::LoadedRecord;
use serde_json::json;

use super::{extend, record_line, validity_lines};

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

/// What a joint's config changes about how it is modelled: its link
/// element, its abutment's lag.
fn joint_model_lines(config: &Config, name: &str) {
    let placed = config.joints.iter().find(|p| p.name == name);
    let joint = placed.and_then(|p| p.joint.as_ref()).unwrap_or(&config.joint);
    if joint.is_link() {
        out!(
            "  modelled as its link element (joint.model = \"link\", docs/link.md): its cells open alike but for \
             their racking ({:.1} mm closing, {:.1} mm opening); its impacts are its racked cell's closures, not \
             the beams' bounces",
            joint.link.as_ref().map_or(0.0, |l| l.racking()[0] * 1e3),
            joint.link.as_ref().map_or(0.0, |l| l.racking()[1] * 1e3)
        );
    }
    if let Some(lag) = placed.and_then(|p| p.abutment_lag).filter(|&l| l > 0.0) {
        out!("  its abutment reached {lag} s after the bridge's other supports (abutment_lag: wave passage)");
    }
}

/// A modal bridge's points and base shear, with the joints and without.
fn bridge_lines(config: &Config, r: &RunResult) {
    if r.points.is_empty() {
        return;
    }
    let corrected = config.bridge.modal.as_ref().is_some_and(|m| m.corrected());
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
        if corrected {
            out!(
                "  the static correction adds the modes left out at the joints' points (bridge.modal.static_correction): \
                 they have all of the full model's static flexibility"
            );
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

/// One joint of a run as JSON, every joint alike: its scalars
/// ([`JointResult::scalars`]; NaN as null, counts whole), validity and
/// findings.
fn joint_json(j: &JointResult) -> serde_json::Value {
    let mut map = serde_json::Map::new();
    map.insert("name".into(), json!(j.name));
    for (name, value, _) in j.scalars() {
        let v = match (value.is_finite(), name == "impacts") {
            (false, _) => serde_json::Value::Null,
            (true, true) => json!(value as u64),
            (true, false) => json!(value),
        };
        map.insert(name.into(), v);
    }
    map.insert("validity".into(), json!(j.validity.flags.0));
    map.insert("validity_label".into(), json!(j.validity.flags.label()));
    map.insert("findings".into(), json!(j.validity.findings));
    serde_json::Value::Object(map)
}

/// One point of a modal bridge as JSON: its name and peaks
/// ([`quakejoint_model::modal::PointPeaks::scalars`], NaN as null).
fn point_json(p: &quakejoint_model::modal::PointPeaks) -> serde_json::Value {
    let mut map = serde_json::Map::new();
    map.insert("name".into(), json!(p.name));
    for (name, value, _) in p.scalars() {
        map.insert(name.into(), json!(value));
    }
    serde_json::Value::Object(map)
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
        run_json(path, loaded, r, config, point);
        return;
    }
    let mode = match (r.exact_linear, r.joints.len()) {
        (true, _) => "bridge alone (exact linear solution)".to_string(),
        (false, 1) => "bridge with joint".to_string(),
        (false, n) => format!("bridge with {n} joints"),
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
        bridge_lines(config, r);
        out!("validity: not checked (no joint)");
        return;
    }
    side_lines(r);
    let several = r.joints.len() > 1;
    for j in &r.joints {
        joint_lines(config, j, several);
    }
    bridge_lines(config, r);
    if several {
        system_lines(r);
    }
    validity_lines(v);
    quality_lines(r);
}

/// `quakejoint simulate --json`: one JSON object.
fn run_json(path: &Path, loaded: &LoadedRecord, r: &RunResult, config: &Config, point: Option<String>) {
    let modal = config.bridge.modal.as_ref();
    let v = &r.validity;
    let record = &loaded.record;
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
        "joints": r.joints.iter().map(joint_json).collect::<Vec<_>>(),
        "points": r.points.iter().map(point_json).collect::<Vec<_>>(),
        "base_shear": r.base_shear,
        "mass_ratio": r.mode_check.as_ref().and_then(|(c, _)| c.mass_ratio),
        "flexibility_captured": r.mode_check.as_ref().map(|(c, _)| c.flexibility.clone()),
        "warnings": r.mode_check.as_ref().map(|(_, w)| w.clone()).unwrap_or_default(),
        "base_shear_without_joint": r.base_shear_without,
    });
    extend(&mut out, fields_json(r));
    out!("{out}");
}

/// The adjacent segment's and the deck's across the bridge, when the run
/// has them.
fn side_lines(r: &RunResult) {
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
            "  across: {}, Sa_y {:.5} m/s^2 at t = {:.3} s (without the joint {:.5}), Sd_y {:.6} m, joint \
             force across {:.1} N",
            // (a modal bridge has no one period across: its point's modes)
            if y.omega.is_finite() {
                format!("T_y {:.4} s", 2.0 * std::f64::consts::PI / y.omega)
            } else {
                "the deck point across".to_string()
            },
            y.sa,
            y.t_sa,
            y.sa_without,
            y.sd,
            y.peak_joint_force
        );
    }
}

/// One joint's demands, every joint alike: its own peaks, energy, cells,
/// pounding and (in a run of several joints) its deck point and validity.
fn joint_lines(config: &Config, j: &JointResult, several: bool) {
    match config.joints.is_empty() {
        true => out!("joint demands"),
        false => out!("joint \"{}\"", j.name),
    }
    joint_model_lines(config, &j.name);
    if several {
        out!("  its deck point: Sa {:.5} m/s^2 at t = {:.3} s, Sd {:.6} m, Sv {:.5} m/s", j.sa, j.t_sa, j.sd, j.sv);
    }
    out!("  peak joint force on the deck  {:>12.1} N", j.peak_joint_force);
    if j.peak_abutment_force.is_finite() {
        out!("  peak force on its abutment    {:>12.1} N", j.peak_abutment_force);
    }
    out!("  peak bushing force            {:>12.1} N", j.peak_bushing_force);
    out!("  peak friction force           {:>12.1} N", j.peak_friction_force);
    out!("  friction energy               {:>12.1} J", j.friction_energy);
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
        if let Some(place) = p.peak_contact_place {
            let released = j.fuse.and_then(|f| f.released());
            out!("    between {}", place.describe_after(released, p.peak_contact_time));
        }
        out!(
            "  closed joint on the deck      {:>12.1} N (peak, through the deck's edge beam)",
            p.peak_deck_contact_force
        );
        if !several {
            out!("  contact energy                {:>12.1} J (dissipated by the impacts)", p.contact_energy);
        }
        out!("  deepest penetration           {:>12.3} mm", p.max_penetration * 1e3);
    }
    fuse_lines(config, j);
    if several {
        out!("  validity: {}", j.validity.flags.label());
    }
}

/// A joint's seismic fuse: whether and when it broke, the edge beam's
/// travel against the stroke, where it rests, its friction energy.
fn fuse_lines(config: &Config, j: &JointResult) {
    let placed = config.joints.iter().find(|p| p.name == j.name);
    let joint = placed.and_then(|p| p.joint.as_ref()).unwrap_or(&config.joint);
    let (Some(fuse), Some(f)) = (&joint.fuse, &j.fuse) else { return };
    let break_kn = fuse.break_force / 1e3;
    let Some(stroke) = fuse.stroke.filter(|_| fuse.kind == quakejoint_model::config::FuseKind::Box) else {
        return element_lines(fuse, f);
    };
    if !f.broke {
        out!("  seismic fuse (box)            held (never reached its break force of {break_kn:.1} kN)");
        return;
    }
    out!("  seismic fuse (box)            BROKE at t = {:.3} s at {:.1} kN", f.break_time, f.break_force / 1e3);
    let exhausted = if f.stroke_exhausted {
        " STROKE EXHAUSTED: the joint pushed the abutment again through the box's stop"
    } else {
        ""
    };
    out!(
        "    edge beam travel            {:>12.1} mm of its {:.1} mm stroke{exhausted}",
        f.stroke_used * 1e3,
        stroke * 1e3
    );
    // (held on its ramp by friction alone, the regularised friction lets
    // the beam creep back: docs/model.md, "Seismic fuse")
    let held = fuse.ramp_deg > 0.0 && fuse.ramp_deg.to_radians().tan() < fuse.mu;
    // (back on its seat it is pressed a few micrometres into it: 0.0, not -0.0)
    let offset_mm = if f.residual_offset.abs() < 5e-5 { 0.0 } else { f.residual_offset * 1e3 };
    out!(
        "    residual offset             {offset_mm:>12.1} mm (the joint must be reset by this much{})",
        if held { "; at least: held by friction on its ramp, the model lets it creep back" } else { "" }
    );
    out!("    fuse friction energy        {:>12.1} J", f.energy);
}

/// A fuse element's lines: whether its beam left the plane, when and at
/// what force.
fn element_lines(fuse: &quakejoint_model::config::FuseConfig, f: &quakejoint_model::run::fuse::FuseResult) {
    let beam = fuse.beam.unwrap_or(0);
    if !f.broke {
        out!(
            "  seismic fuse (element)        held (beam {beam} never reached its release force of {:.1} kN)",
            fuse.break_force / 1e3
        );
        return;
    }
    out!(
        "  seismic fuse (element)        RELEASED: beam {beam} left the plane at t = {:.3} s at {:.1} kN; its two cells \
         acted as one (the beam must be put back)",
        f.break_time,
        f.break_force / 1e3
    );
    out!("    energy its contacts held    {:>12.1} J", f.energy);
}

/// The whole system's peaks and energies, in a run of several joints.
fn system_lines(r: &RunResult) {
    out!("the whole system (all joints)");
    out!("  peak bushing force            {:>12.1} N", r.peak_bushing_force);
    out!("  peak friction force           {:>12.1} N", r.peak_friction_force);
    out!("  friction energy               {:>12.1} J", r.friction_energy);
    out!("  contact energy                {:>12.1} J (dissipated by the impacts)", r.pounding.contact_energy);
}

/// The run's quality: energy balance, constraint residuals, solver
/// counters and time.
fn quality_lines(r: &RunResult) {
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
