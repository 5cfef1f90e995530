//! `docs/config.md` against the code, so that the reference cannot drift:
//!
//! - every key the config accepts (the defaults serialised, with every
//!   optional key set) and every record and sweep key has a row, and every
//!   row names a key the program accepts;
//! - every documented default equals the program's default;
//! - every key with a range in `quakejoint_model::limits::LIMITS` has the
//!   same unit and range in its row, and a value just outside that range is
//!   refused with a message naming the key.

use std::collections::BTreeMap;

use quakejoint_model::limits::{Bound, LIMITS};
use quakejoint_model::Config;
use quakejoint_motion::RecordSpec;

/// One documented key: unit, default and range cells.
#[derive(Debug)]
struct Row {
    unit: String,
    default: String,
    range: String,
}

fn rows() -> BTreeMap<String, Row> {
    let doc = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/../../docs/config.md")).unwrap();
    let mut out = BTreeMap::new();
    for line in doc.lines() {
        let cells: Vec<&str> = line.split('|').map(str::trim).collect();
        if cells.len() < 6 || !cells[1].starts_with('`') {
            continue;
        }
        let key = cells[1].trim_matches('`').to_string();
        let row = Row { unit: cells[2].to_string(), default: cells[3].to_string(), range: cells[4].to_string() };
        assert!(out.insert(key.clone(), row).is_none(), "{key} documented twice");
    }
    out
}

/// Leaf keys of a TOML table with their values (arrays of tables skipped).
fn flatten(prefix: &str, table: &toml::Table, out: &mut BTreeMap<String, toml::Value>) {
    for (k, v) in table {
        let key = if prefix.is_empty() { k.clone() } else { format!("{prefix}.{k}") };
        match v {
            toml::Value::Table(t) => flatten(&key, t, out),
            toml::Value::Array(a) if a.iter().all(|x| x.is_table()) => {}
            _ => {
                out.insert(key, v.clone());
            }
        }
    }
}

fn table_of(config: &Config) -> toml::Table {
    toml::from_str(&toml::to_string(config).unwrap()).unwrap()
}

/// A config with every optional key set, to list every key.
fn full() -> Config {
    let mut c = Config::default();
    c.joint.center_beam.inertia = Some(1.0);
    c.joint.support_beam.inertia = Some(1.0);
    c.joint.model = Some(quakejoint_model::config::JointKind::Detailed);
    c.joint.link = Some(quakejoint_model::config::LinkConfig {
        stiffness: 1e7,
        friction: 1e5,
        mass: 1e4,
        gap_stiffness: 1e8,
        gap_hertz: Some(1e8),
        damping: Some(0.0),
        v_eps: Some(0.001),
        racking_closing: Some(0.0),
        racking_opening: Some(0.0),
    });
    c.joint.fuse = Some(quakejoint_model::config::FuseConfig {
        kind: quakejoint_model::config::FuseKind::Box,
        break_force: 1e6,
        stroke: Some(0.3),
        beam: None,
        ramp_deg: 0.0,
        mu: 0.15,
        mass: Some(900.0),
    });
    c.bridge.w0 = Some(6.3);
    c.bridge.transverse_period = Some(1.0);
    c.bridge.transverse_damping = Some(0.05);
    c.bridge.far = Some(quakejoint_model::config::FarSegmentConfig {
        mass: Some(1e8),
        period: None,
        period_ratio: Some(1.0),
        damping: Some(0.05),
    });
    c.bridge.modal = Some(quakejoint_model::config::ModalConfig {
        modes: "modes.toml".to_string(),
        joint_point: Some("right end".to_string()),
        joint_point_y: Some("right end".to_string()),
        modes_used: Some(3),
        period_scale: Some(1.0),
        static_correction: Some(false),
        loaded: None,
    });
    c.simulation.duration = Some(1.0);
    c.simulation.h_max = Some(1.0);
    c.simulation.max_wall_time = Some(1.0);
    c.simulation.max_steps = Some(1);
    c
}

/// Whether a documented default such as `` `1e7` `` equals a TOML value.
fn same_default(doc: &str, value: &toml::Value) -> bool {
    let d = doc.trim_matches('`');
    match value {
        toml::Value::Float(x) => d.parse::<f64>().is_ok_and(|y| y == *x),
        toml::Value::Integer(i) => d.parse::<i64>().is_ok_and(|y| y == *i),
        toml::Value::Boolean(b) => d == b.to_string(),
        toml::Value::String(s) => d == format!("\"{s}\""),
        _ => false,
    }
}

#[test]
fn every_key_is_documented_with_its_default() {
    let rows = rows();
    let mut defaults = BTreeMap::new();
    flatten("", &table_of(&Config::default()), &mut defaults);
    let mut all = BTreeMap::new();
    flatten("", &table_of(&full()), &mut all);
    let mut by_period = full();
    (by_period.bridge.w0, by_period.bridge.period) = (None, Some(1.0));
    if let Some(f) = &mut by_period.bridge.far {
        (f.period, f.period_ratio) = (Some(1.0), None);
    }
    by_period.bridge.transverse_period = None;
    // (a fuse element: its beam, in place of a box's stroke)
    by_period.joint.fuse = Some(quakejoint_model::config::FuseConfig {
        kind: quakejoint_model::config::FuseKind::Element,
        break_force: 1e6,
        stroke: None,
        beam: Some(2),
        ramp_deg: 0.0,
        mu: 0.15,
        mass: None,
    });
    flatten("", &table_of(&by_period), &mut all);
    let mut problems = Vec::new();
    for (key, value) in &defaults {
        match rows.get(key) {
            None => problems.push(format!("{key}: not documented")),
            Some(r) if !same_default(&r.default, value) => {
                problems.push(format!("{key}: documented default {} but the program's is {value}", r.default))
            }
            _ => {}
        }
    }
    for key in all.keys().filter(|k| !defaults.contains_key(*k)) {
        if !rows.contains_key(key) {
            problems.push(format!("{key}: an optional key that is not documented"));
        }
    }
    // records: every field of a record spec, for [record]
    let mut spec = RecordSpec::new("x.txt");
    (spec.units, spec.dt, spec.column, spec.target_pga_g, spec.name) =
        (Some(quakejoint_motion::Units::G), Some(0.01), Some(2), Some(0.3), Some("x".into()));
    (spec.channel, spec.azimuth, spec.allow_vertical) = (Some(2), Some(90.0), true);
    let spec: toml::Table = toml::from_str(&toml::to_string(&spec).unwrap()).unwrap();
    let record_keys: Vec<String> = spec.keys().map(|k| format!("record.{k}")).collect();
    for key in &record_keys {
        if !rows.contains_key(key) {
            problems.push(format!("{key}: not documented"));
        }
    }
    let support_keys = ["kind", "y", "angle_deg"].map(|k| format!("joint.support_beams[k].{k}"));
    // [[joints]]: every field of an entry, its own [joints.joint] as one row
    let placed = quakejoint_model::config::PlacedJointConfig {
        name: "a".into(),
        deck_point: "p".into(),
        deck_point_y: Some("q".into()),
        deck_side: quakejoint_model::config::DeckSide::PlusX,
        abutment_point: Some("r".into()),
        abutment_lag: Some(0.1),
        joint: Some(Default::default()),
    };
    let placed: toml::Table = toml::from_str(&toml::to_string(&placed).unwrap()).unwrap();
    let joints_keys: Vec<String> = placed.keys().map(|k| format!("joints[k].{k}")).collect();
    let mut sweep_keys: Vec<String> = quakejoint_sweep::plan::SWEEP_KEYS.iter().map(|k| format!("sweep.{k}")).collect();
    sweep_keys.extend(quakejoint_sweep::plan::SUITE_KEYS.iter().map(|k| format!("sweep.suite.{k}")));
    sweep_keys.extend(quakejoint_sweep::plan::STRIPES_KEYS.iter().map(|k| format!("sweep.stripes.{k}")));
    sweep_keys.extend(quakejoint_sweep::fragility::FRAGILITY_KEYS.iter().map(|k| format!("sweep.fragility.{k}")));
    for key in support_keys.iter().chain(&sweep_keys).chain(&joints_keys) {
        if !rows.contains_key(key) {
            problems.push(format!("{key}: not documented"));
        }
    }
    // and nothing documented that the program does not accept
    for key in rows.keys() {
        let known = all.contains_key(key)
            || record_keys.contains(key)
            || support_keys.contains(key)
            || sweep_keys.contains(key)
            || joints_keys.contains(key);
        if !known {
            problems.push(format!("{key}: documented but not a key of the config"));
        }
    }
    assert!(problems.is_empty(), "docs/config.md disagrees with the code:\n{}", problems.join("\n"));
}

/// A value just outside the range, on the lower side if it has one.
fn outside(b: &Bound) -> f64 {
    if b.min.is_finite() {
        if b.min_inclusive {
            b.min - (b.min.abs() * 1e-6).max(1e-300)
        } else {
            b.min
        }
    } else if b.max_inclusive {
        b.max * (1.0 + 1e-6)
    } else {
        b.max
    }
}

#[test]
fn every_range_is_documented_and_enforced() {
    let rows = rows();
    let mut problems = Vec::new();
    for (key, unit, bound) in LIMITS {
        let Some(row) = rows.get(*key) else {
            problems.push(format!("{key}: not documented"));
            continue;
        };
        if row.unit != *unit {
            problems.push(format!("{key}: documented unit `{}` but the program's is `{unit}`", row.unit));
        }
        if row.range != bound.describe() {
            problems.push(format!(
                "{key}: documented range `{}` but the program's is `{}`",
                row.range,
                bound.describe()
            ));
        }
        // a value just outside, on both sides, is refused
        let is_int =
            matches!(*key, "joint.center_beams" | "joint.fuse.beam" | "simulation.max_steps" | "service.cycles");
        let values = if is_int {
            vec![bound.min - 1.0, bound.max + 1.0]
        } else {
            vec![outside(bound), if bound.max_inclusive { bound.max * (1.0 + 1e-6) } else { bound.max }]
        };
        for v in values {
            let (section, field) = key.rsplit_once('.').unwrap();
            let text = if let Some(sb) = section.strip_suffix("[k]") {
                let table = sb;
                let mut entry = "kind = \"joist\"\ny = 0.0\nangle_deg = 10.0\n".to_string();
                entry = entry
                    .lines()
                    .filter(|l| !l.starts_with(&format!("{field} ")))
                    .map(|l| format!("{l}\n"))
                    .collect::<String>();
                format!("[[{table}]]\n{entry}{field} = {v:e}\n")
            } else {
                let value = if is_int { format!("{}", v.floor() as i64) } else { format!("{v:e}") };
                if is_int && (v.floor() as i64) < 0 {
                    continue; // not representable in the key's unsigned type: refused by the parser
                }
                // (a modal bridge's table needs its modes file named)
                let required = if section == "bridge.modal" { "modes = \"m.toml\"\njoint_point = \"a\"\n" } else { "" };
                if section == "joint.link" {
                    // (the link's required keys, and the joint made its link)
                    let others: String = [("stiffness", 1e7), ("friction", 1e5), ("mass", 1e4), ("gap_stiffness", 1e8)]
                        .iter()
                        .filter(|(k, _)| *k != field)
                        .map(|(k, x)| format!("{k} = {x:e}\n"))
                        .collect();
                    format!("[joint]\nmodel = \"link\"\n[joint.link]\n{others}{field} = {value}\n")
                } else if *key == "joint.fuse.beam" {
                    format!("[joint.fuse]\nkind = \"element\"\nbreak_force = 1e6\nbeam = {value}\n")
                } else if section == "joint.fuse" {
                    // (the fuse's required keys)
                    let others: String = [("break_force", "1e6"), ("stroke", "0.3")]
                        .iter()
                        .filter(|(k, _)| *k != field)
                        .map(|(k, x)| format!("{k} = {x}\n"))
                        .collect();
                    format!("[joint.fuse]\nkind = \"box\"\n{others}{field} = {value}\n")
                } else {
                    format!("[{section}]\n{required}{field} = {value}\n")
                }
            };
            match Config::from_toml(&text, "test.toml") {
                Ok(_) => problems.push(format!("{key} = {v:e} is accepted, outside {}", bound.describe())),
                Err(e) => {
                    let shown = key.replace("[k]", "[0]");
                    if !e.to_string().contains(&shown) && !e.to_string().contains(field) {
                        problems.push(format!("{key} = {v:e}: the message does not name the key: {e}"));
                    }
                }
            }
        }
    }
    assert!(problems.is_empty(), "ranges:\n{}", problems.join("\n"));
}
