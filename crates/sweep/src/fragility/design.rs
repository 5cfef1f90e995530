//! Choosing a joint: the sweep's cases are the candidate joints, each
//! limit state may carry a target annual frequency (`target` in its
//! `[[sweep.fragility.limit_states]]` table), and every candidate is
//! checked against every target at the upper end of its annual frequency's
//! bootstrap interval. The recommendation is the candidate with the fewest
//! gaps (cells) that meets every target, with its margin (docs/design.md).
//!
//! The check is made from the fitted curves alone, so a changed target
//! needs no job run again; the same sweep sharded and merged gives the
//! same curves, hence the same table.

use quakejoint_model::config::FuseKind;
use quakejoint_model::Config;

use super::{CurveRow, StoredFragility};

/// A candidate joint: a case of the sweep.
#[derive(Debug, Clone, PartialEq)]
pub struct Candidate {
    /// The case's name.
    pub name: String,
    /// Its gaps (cells, `Nc + 1`; the most of its joints when it has
    /// several).
    pub cells: usize,
    /// Its fuse in words (`"none"` without one).
    pub fuse: String,
}

impl Candidate {
    /// The candidate of a case named `name` with the config `config`.
    pub fn of(name: &str, config: &Config) -> Self {
        let joints = std::iter::once(&config.joint).chain(config.joints.iter().filter_map(|j| j.joint.as_ref()));
        let cells = joints.clone().map(|j| j.cells()).max().unwrap_or(0);
        let fuses: Vec<String> = joints
            .filter_map(|j| j.fuse.as_ref())
            .map(|f| match (f.kind, f.stroke, f.beam) {
                (FuseKind::Box, Some(stroke), _) => {
                    let ramp = if f.ramp_deg > 0.0 { format!(", ramp {} deg", f.ramp_deg) } else { String::new() };
                    format!("box {} kN, stroke {stroke} m{ramp}", f.break_force / 1e3)
                }
                (_, _, Some(beam)) => format!("element {} kN, beam {beam}", f.break_force / 1e3),
                _ => format!("{:?} {} kN", f.kind, f.break_force / 1e3),
            })
            .collect();
        let fuse = if fuses.is_empty() { "none".to_string() } else { fuses.join("; ") };
        Self { name: name.to_string(), cells, fuse }
    }
}

/// The candidates of a sweep file: its cases' names and full configs
/// (TOML, as `/spectrum/case_config` stores them).
pub fn candidates_of(names: &[String], configs: &[String]) -> Vec<Candidate> {
    names
        .iter()
        .zip(configs)
        .map(|(name, text)| match toml::from_str::<Config>(text) {
            Ok(config) => Candidate::of(name, &config),
            Err(_) => Candidate { name: name.clone(), cells: usize::MAX, fuse: "unknown (config unreadable)".into() },
        })
        .collect()
}

/// One candidate against one target.
#[derive(Debug, Clone, PartialEq)]
pub struct Check {
    /// The annual frequency \[1/year\] (0: no run reports the limit state,
    /// a fuse's for a joint without one; NaN: not determined).
    pub frequency: f64,
    /// The value checked: the upper end of its bootstrap interval (the
    /// frequency itself without a bootstrap) \[1/year\].
    pub upper: f64,
    /// Whether `upper` is at most the target.
    pub pass: bool,
    /// Why, where the curve does not say it alone.
    pub note: String,
}

/// The choice at one damping ratio and period of the sweep.
#[derive(Debug, Clone, PartialEq)]
pub struct Design {
    /// The damping ratio's and the period's indices.
    pub at: [usize; 2],
    /// The limit states with a target: their keys, names and targets
    /// \[1/year\].
    pub targets: Vec<(String, String, f64)>,
    /// The candidates, in the order of the cases.
    pub candidates: Vec<Candidate>,
    /// `checks[candidate][target]`.
    pub checks: Vec<Vec<Check>>,
    /// The recommended candidate: the fewest gaps meeting every target
    /// (the first listed among equals); none if no candidate does.
    pub recommended: Option<usize>,
    /// Its margin: the smallest ratio of a target to its checked value
    /// (infinite when every checked value is 0), and the limit state it is
    /// on.
    pub margin: (f64, String),
}

/// The choice at each damping ratio and period of a multiple-stripe
/// sweep whose limit states carry targets (none without targets or a
/// hazard curve): `rows` are the curves of `f` ([`super::rows`]), the
/// candidates the sweep's cases in order.
pub fn designs(f: &StoredFragility, rows: &[CurveRow], candidates: &[Candidate]) -> Vec<Design> {
    let targets: Vec<(String, String, f64)> =
        f.spec.limit_states.iter().filter_map(|ls| ls.target.map(|t| (ls.key.clone(), ls.name.clone(), t))).collect();
    let Some(hazard) = f.spec.hazard.as_ref().filter(|_| !targets.is_empty()) else { return Vec::new() };
    let levels = &f.stripes.levels;
    let mut ats: Vec<[usize; 2]> = rows.iter().map(|r| [r.at[1], r.at[2]]).collect();
    ats.sort_unstable();
    ats.dedup();
    ats.into_iter()
        .map(|at| {
            let checks: Vec<Vec<Check>> = (0..candidates.len())
                .map(|c| {
                    targets
                        .iter()
                        .map(|(key, _, target)| {
                            let row = rows.iter().find(|r| &r.key == key && r.at == [c, at[0], at[1]]);
                            check(row, *target, levels, &hazard.curve)
                        })
                        .collect()
                })
                .collect();
            let passing = |c: &usize| checks[*c].iter().all(|k| k.pass);
            let recommended = (0..candidates.len()).filter(passing).min_by_key(|&c| (candidates[c].cells, c));
            let margin = recommended.map_or((f64::NAN, String::new()), |c| {
                checks[c]
                    .iter()
                    .zip(&targets)
                    .map(|(k, (_, name, t))| (t / k.upper, name.clone()))
                    .fold((f64::INFINITY, String::new()), |m, x| if x.0 < m.0 { x } else { m })
            });
            Design { at, targets: targets.clone(), candidates: candidates.to_vec(), checks, recommended, margin }
        })
        .collect()
}

/// A curve (none: the sweep has none there) against `target`, with the
/// stripes' `levels` \[g\] and the site's `hazard`.
fn check(row: Option<&CurveRow>, target: f64, levels: &[f64], hazard: &quakejoint_model::fragility::Hazard) -> Check {
    let Some(r) = row else {
        return Check { frequency: f64::NAN, upper: f64::NAN, pass: false, note: "no curve".into() };
    };
    let counted: u32 = r.runs.iter().sum();
    let (frequency, upper, note) = if r.annual_frequency.is_finite() {
        let hi = r.annual_frequency_interval[1];
        match hi.is_finite() {
            true => (r.annual_frequency, hi, String::new()),
            false => (r.annual_frequency, r.annual_frequency, "no bootstrap: the frequency itself is checked".into()),
        }
    } else if counted == 0 {
        (0.0, 0.0, "no run reports it (a fuse's limit state of a joint without a fuse): it cannot happen".into())
    } else {
        // no fit: every run survived up to some stripe (or at every one);
        // every run beyond it counted as exceeding
        let survived = |i: usize| r.exceeded[..=i].iter().all(|&e| e == 0) && r.runs[..=i].iter().any(|&n| n > 0);
        match (0..levels.len()).filter(|&i| survived(i)).map(|i| levels[i]).reduce(f64::max) {
            Some(safe) => (
                f64::NAN,
                hazard.rate(safe),
                format!(
                    "no fit: every run survived up to {} g; taken as exceeding beyond it, the hazard's frequency \
                     there",
                    quakejoint_motion::number(safe)
                ),
            ),
            None => {
                (f64::NAN, f64::NAN, "not determined: runs exceeded at the lowest stripe (lower the stripes)".into())
            }
        }
    };
    Check { frequency, upper, pass: upper <= target, note }
}

/// The choice for a terminal, within 100 columns.
pub fn summary(designs: &[Design], confidence: f64, label: &dyn Fn([usize; 2]) -> String) -> String {
    let mut out = String::new();
    for d in designs {
        out += &format!(
            "design{}: each candidate against the targets (annual frequency, checked at the upper end of its {} % \
             interval)\n",
            if designs.len() > 1 { format!(" [{}]", label(d.at)) } else { String::new() },
            (100.0 * confidence).round()
        );
        for (c, cand) in d.candidates.iter().enumerate() {
            let ok = d.checks[c].iter().all(|k| k.pass);
            out += &format!(
                "  {} ({} gaps, {}): {}\n",
                cand.name,
                cand.cells,
                if cand.fuse == "none" { "no fuse".to_string() } else { format!("fuse {}", cand.fuse) },
                if ok { "meets every target" } else { "FAILS" }
            );
            for ((_, name, target), k) in d.targets.iter().zip(&d.checks[c]) {
                let value = if k.upper == 0.0 {
                    "0".to_string()
                } else if k.frequency.is_finite() && k.upper != k.frequency {
                    format!("{:.2e} (upper {:.2e})", k.frequency, k.upper)
                } else {
                    format!("{:.2e}", k.upper)
                };
                out += &format!(
                    "      {name:<34} {value:<26} target {target:.2e}  {}\n",
                    if k.pass { "pass" } else { "FAIL" }
                );
                if !k.note.is_empty() {
                    out += &super::wrapped(&k.note, 8, 100);
                }
            }
        }
        out += &match d.recommended {
            Some(c) => format!(
                "  recommended: {} ({} gaps): the fewest gaps meeting every target; margin {:.2} on {}\n",
                d.candidates[c].name, d.candidates[c].cells, d.margin.0, d.margin.1
            ),
            None => "  recommended: none: no candidate meets every target\n".to_string(),
        };
    }
    out
}

/// Writes `designs` into `/fragility/design` (`g`: the `/fragility` group)
/// for a sweep of `dims` (case, record, damping, period): the candidates,
/// the targets and, per (case, damping, period, target), the annual
/// frequency, the value checked, pass and note; per (damping, period) the
/// recommended case (-1: none) and its margin (docs/hdf5-layout.md).
pub fn write_design(g: &hdf5::Group, designs: &[Design], dims: [usize; 4]) -> hdf5::Result<()> {
    use ndarray::{ArrayView2, ArrayView4};
    use quakejoint_io::h5::{array, attr_str, label_axes, strings, strings_1d};
    let Some(first) = designs.first() else { return Ok(()) };
    let [nc, _, nz, nt] = dims;
    let nk = first.targets.len();
    let d = g.create_group("design")?;
    strings_1d(&d, "candidate", &first.candidates.iter().map(|c| c.name.clone()).collect::<Vec<_>>())?;
    let cells: Vec<u32> = first.candidates.iter().map(|c| c.cells.min(u32::MAX as usize) as u32).collect();
    let ds = array(&d, "cells", &cells[..])?;
    attr_str(&ds, "units", "1")?;
    strings_1d(&d, "fuse", &first.candidates.iter().map(|c| c.fuse.clone()).collect::<Vec<_>>())?;
    strings_1d(&d, "target_limit_state", &first.targets.iter().map(|t| t.0.clone()).collect::<Vec<_>>())?;
    let targets: Vec<f64> = first.targets.iter().map(|t| t.2).collect();
    let ds = array(&d, "target", &targets[..])?;
    attr_str(&ds, "units", "1/year")?;
    let n = nc * nz * nt * nk;
    let (mut freq, mut checked, mut pass, mut notes) =
        (vec![f64::NAN; n], vec![f64::NAN; n], vec![0u8; n], vec![String::new(); n]);
    let (mut recommended, mut margin, mut margin_on) =
        (vec![-1i32; nz * nt], vec![f64::NAN; nz * nt], vec![String::new(); nz * nt]);
    for design in designs {
        let [z, t] = design.at;
        for (c, checks) in design.checks.iter().enumerate() {
            for (k, check) in checks.iter().enumerate() {
                let i = ((c * nz + z) * nt + t) * nk + k;
                (freq[i], checked[i], pass[i]) = (check.frequency, check.upper, u8::from(check.pass));
                notes[i] = check.note.clone();
            }
        }
        if let Some(c) = design.recommended {
            recommended[z * nt + t] = c as i32;
            (margin[z * nt + t], margin_on[z * nt + t]) = (design.margin.0, design.margin.1.clone());
        }
    }
    let axes = ["case", "damping", "period", "target"];
    for (name, data, units, meaning) in [
        ("annual_frequency", &freq, "1/year", "the fitted curve's mean annual frequency (0: no run reports the limit state, a fuse's of a joint without one; NaN: not determined)"),
        ("checked", &checked, "1/year", "the value checked against the target: the upper end of the bootstrap interval (the frequency without a bootstrap)"),
    ] {
        let ds = array(&d, name, ArrayView4::from_shape((nc, nz, nt, nk), &data[..]).map_err(shape)?)?;
        label_axes(&ds, &axes)?;
        attr_str(&ds, "units", units)?;
        attr_str(&ds, "meaning", meaning)?;
    }
    let ds = array(&d, "pass", ArrayView4::from_shape((nc, nz, nt, nk), &pass[..]).map_err(shape)?)?;
    label_axes(&ds, &axes)?;
    attr_str(&ds, "units", "1")?;
    label_axes(&strings(&d, "note", &notes, &[nc, nz, nt, nk])?, &axes)?;
    let ds = array(&d, "recommended", ArrayView2::from_shape((nz, nt), &recommended[..]).map_err(shape)?)?;
    attr_str(&ds, "meaning", "index into candidate of the recommended joint (-1: none meets every target)")?;
    attr_str(&ds, "units", "1")?;
    let ds = array(&d, "margin", ArrayView2::from_shape((nz, nt), &margin[..]).map_err(shape)?)?;
    attr_str(&ds, "meaning", "the recommended joint's smallest ratio of a target to its checked value")?;
    attr_str(&ds, "units", "1")?;
    strings(&d, "margin_on", &margin_on, &[nz, nt])?;
    Ok(())
}

fn shape(e: ndarray::ShapeError) -> hdf5::Error {
    hdf5::Error::from(format!("the design's arrays: {e}"))
}
