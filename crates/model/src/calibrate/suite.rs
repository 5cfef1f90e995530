//! The link's mass under the calibration suite: the detailed joint and
//! each candidate link run under every record, the candidate that holds
//! the suite's peak forces in [`BAND`] chosen (see the module
//! documentation of [`super`]).

use super::racking::racking;
use super::{DynamicFit, BAND, MASS_FACTORS};
use crate::config::{Config, LinkConfig};
use crate::error::ModelError;

/// The joint's force on the deck in a run of `config` under `record`:
/// (force history, peak, friction energy, the closed joint's peak force on
/// the deck, the run's flags if any).
fn joint_force(config: &Config, record: &quakejoint_motion::Record) -> Result<JointForce, ModelError> {
    let options = crate::run::RunOptions { histories: true, ..Default::default() };
    let r = crate::run::simulate_records(config, record, None, &options)?;
    let flags = r.validity.flags.is_flagged().then(|| r.validity.flags.label());
    let closed = r.pounding.peak_deck_contact_force;
    let (h, racking) = match r.histories {
        Some(h) => {
            let subgaps = [r.min_subgap.unwrap_or(f64::NAN), r.max_subgap.unwrap_or(f64::NAN)];
            let j = &config.joint;
            (h.joint_force, racking(j.cells(), j.clear_subgap(), &h.u, subgaps))
        }
        None => (Vec::new(), [f64::NAN; 2]),
    };
    Ok(JointForce { force: h, peak: r.peak_joint_force, friction: r.friction_energy, closed, flags, racking })
}

/// What [`joint_force`] gives.
struct JointForce {
    /// The force on the deck at the output times \[N\].
    force: Vec<f64>,
    /// Its peak \[N\].
    peak: f64,
    /// The friction energy \[J\].
    friction: f64,
    /// The closed joint's peak force on the deck \[N\].
    closed: f64,
    /// The run's flags, if any.
    flags: Option<String>,
    /// The racking `[closing, opening]` \[m\] ([`racking`]).
    racking: [f64; 2],
}

/// One candidate link under one record: (RMS of the force difference,
/// peak, friction energy).
type Trial = (f64, f64, f64);

/// How far the peak's error `e` (link over detailed, minus 1) lies outside
/// [`BAND`], a force below it counted double [-].
fn outside_band(e: f64) -> f64 {
    (e - BAND[1]).max(2.0 * (BAND[0] - e)).max(0.0)
}

/// Identifies the link's mass and damper under the suite `records` (see
/// the module documentation), sets them in `link` and returns how the
/// chosen link does under each record.
pub(super) fn identify(
    config: &Config,
    records: &[quakejoint_motion::Record],
    link: &mut LinkConfig,
    warnings: &mut Vec<String>,
) -> Result<Vec<DynamicFit>, ModelError> {
    let mut detailed = Vec::with_capacity(records.len());
    for record in records {
        let JointForce { force, peak, friction, closed, flags, racking } = joint_force(config, record)?;
        if let Some(flags) = flags {
            warnings.push(format!(
                "the detailed joint is flagged under the calibration record {} ({flags}): the mass rests on a run \
                 the model cannot stand behind (choose a record it takes)",
                record.name
            ));
        }
        detailed.push((force, peak, friction, closed, racking));
    }
    let kinetic = link.mass;
    let candidates: Vec<LinkConfig> =
        MASS_FACTORS.iter().map(|f| LinkConfig { mass: f * kinetic, ..link.clone() }).collect();
    // trials[candidate][record]
    let mut trials: Vec<Vec<Trial>> = Vec::with_capacity(candidates.len());
    for candidate in &candidates {
        let mut lc = config.clone();
        lc.joint.model = Some(crate::config::JointKind::Link);
        lc.joint.link = Some(candidate.clone());
        let mut row = Vec::with_capacity(records.len());
        for (record, (reference, ..)) in records.iter().zip(&detailed) {
            let JointForce { force: f, peak, friction, .. } = joint_force(&lc, record)?;
            let n = f.len().min(reference.len()).max(1);
            let rms = (f.iter().zip(reference).map(|(a, b)| (a - b).powi(2)).sum::<f64>() / n as f64).sqrt();
            row.push((rms, peak, friction));
        }
        trials.push(row);
    }
    // a record's fit: the history and its peak alike
    let fit = |t: &Trial, peak_detailed: f64| t.0 / peak_detailed + (t.1 - peak_detailed).abs() / peak_detailed;
    let suite_score = |row: &[Trial]| {
        let (mut outside, mut mean) = (0.0, 0.0);
        for (t, (_, peak, ..)) in row.iter().zip(&detailed) {
            outside += outside_band(t.1 / peak - 1.0);
            mean += fit(t, *peak) / row.len() as f64;
        }
        10.0 * outside + mean
    };
    let argmin = |score: &dyn Fn(&[Trial]) -> f64| {
        (0..candidates.len()).min_by(|&a, &b| score(&trials[a]).total_cmp(&score(&trials[b]))).unwrap_or(0)
    };
    let chosen = argmin(&suite_score);
    let at_edge = |l: &LinkConfig| {
        l.mass <= MASS_FACTORS[0] * kinetic * (1.0 + 1e-12)
            || l.mass >= MASS_FACTORS[MASS_FACTORS.len() - 1] * kinetic * (1.0 - 1e-12)
    };
    let edges =
        format!("the search: {} to {} times {kinetic:.4e} kg", MASS_FACTORS[0], MASS_FACTORS[MASS_FACTORS.len() - 1]);
    let mut fits = Vec::with_capacity(records.len());
    for (r, (record, (_, peak_detailed, friction_detailed, closed, racking))) in
        records.iter().zip(&detailed).enumerate()
    {
        let own = &candidates[argmin(&|row: &[Trial]| fit(&row[r], *peak_detailed))];
        if at_edge(own) && records.len() > 1 {
            warnings.push(format!(
                "{} alone pulls the mass to {:.4e} kg, at the edge of {edges}: it calls for a link the others do \
                 not",
                record.name, own.mass
            ));
        }
        let (rms, peak_link, friction_link) = trials[chosen][r];
        fits.push(DynamicFit {
            record: record.name.clone(),
            rms,
            peak_detailed: *peak_detailed,
            peak_link,
            friction_detailed: *friction_detailed,
            friction_link,
            closed_detailed: *closed,
            own_mass: own.mass,
            racking: *racking,
        });
    }
    let choice = candidates[chosen].clone();
    if at_edge(&choice) {
        warnings.push(format!("the mass found ({:.4e} kg) is at the edge of {edges}", choice.mass));
    }
    for f in &fits {
        let e = f.peak_link / f.peak_detailed - 1.0;
        if e < BAND[0] {
            warnings.push(format!(
                "under {} the link's peak force on the deck is {:.1} % below the detailed joint's ({:.4e} against \
                 {:.4e} N): no mass of {edges} holds every record of the suite",
                f.record,
                -100.0 * e,
                f.peak_link,
                f.peak_detailed
            ));
        }
    }
    *link = choice;
    Ok(fits)
}
