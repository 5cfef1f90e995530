//! Calibration of the link element (`joint.model = "link"`,
//! [`crate::link`]) from the detailed joint (docs/link.md, "The method").
//!
//! - Spring `k` and slider force `F`: the detailed joint is opened and
//!   closed by the service case ([`crate::service`]) at several amplitudes,
//!   slowly; its force on the deck against the opening is fitted by an
//!   elastic-perfectly-plastic law run over the same opening history (least
//!   squares over every loop's last cycle, each loop weighted alike), `F`
//!   then set so that the widest loop dissipates what the detailed joint's
//!   does. The hand
//!   calculation of the friction force, `F_hand = mu n_s N sum_ik (i / (Nc +
//!   1)) dl_k/du` (`dl/du` = `cos theta_k` on a joist, 1 on the guide: the
//!   swivel kinematics), is reported beside it.
//! - Mass `m`: the joint's kinetic energy with the deck opening at speed
//!   `V`, over `V^2 / 2`: each center beam with its bearings moves at `i /
//!   (Nc + 1) V`, each joist turns about its pivot at `theta' = -dy V /
//!   (G0^2 + dy^2)`; the guide does not move.
//! - Gap stiffness `k_c`: the closed joint is `Nc + 1` cells in series, each
//!   two contacts (the beam ends) in parallel: `2 k / (Nc + 1)` for the
//!   linear law; for the Hertz law the chain's own Hertz law `2 k / (Nc +
//!   1)^1.5` (quakejoint's link) and, for the exports' linear gaps, its
//!   secant stiffness at the force `contact_force`, `F_c / ((Nc + 1) (F_c /
//!   2 k)^(2/3))`.
//! - Damper `c`: the stuck joint's own, the bushings' damping in the same
//!   proportion to their stiffness as the link's spring to the stuck joint
//!   (`c = k joint.bushing.cx / joint.bushing.kx`). A damper beside the
//!   spring acts on the bridge whenever the joint sticks: one larger than
//!   the joint's own adds damping to the bridge that the joint does not.
//! - Mass, dynamically: the detailed joint on the config's bridge under
//!   each record of the calibration suite, against the link with the
//!   kinetic-energy mass times 1/4 to 1 ([`MASS_FACTORS`]: no part of the
//!   joint moves more mass than all of it sliding at once). The mass chosen
//!   holds the peak force on the deck (what the abutment is designed for)
//!   in the band [`BAND`] of the detailed joint's under every record, a
//!   force below it counted double: least sum of the records' distances
//!   outside the band, then least mean of each record's RMS of the force
//!   difference plus difference of the peaks, each over the detailed
//!   joint's peak. Each record's own best mass is reported beside it: their
//!   spread says how much the mass belongs to the joint and how much to
//!   the record. The mass of the kinetic energy is that of a joint sliding
//!   as a whole; its beams lag and ring apart, which a smaller mass stands
//!   for.
//! - The equivalent viscous damping ratio of each loop, `E_D / (4 pi E_S)`:
//!   the joint's own (its secant stiffness) and, on a single-DOF bridge,
//!   the bridge's added damping at that deck amplitude.

use crate::config::{Config, ContactLawConfig, LinkConfig, SupportKind};
use crate::error::ModelError;
use crate::geometry::Geometry;
use crate::runspec::{Named, Overrides, RunSpec};
use crate::scenario::Scenario;

pub mod export;
mod racking;
mod suite;

pub use racking::racking;
use racking::set_racking;
use suite::identify;

/// What the calibration runs.
#[derive(Debug, Clone, PartialEq)]
pub struct CalibrationOptions {
    /// Amplitudes of the service loops \[m\].
    pub amplitudes: Vec<f64>,
    /// Opening speed of the loops [m/s] (slow: the fit is of the static law).
    pub speed: f64,
    /// Cycles per loop (the first starts from rest).
    pub cycles: u32,
    /// The force at which a Hertz contact's secant stiffness is taken \[N\]
    /// (none: the detailed joint's largest closed-joint force under the
    /// calibration suite, or [`DEFAULT_CONTACT_FORCE`] where none closes it).
    pub contact_force: Option<f64>,
    /// The calibration suite (the mass and the damper): records to run
    /// the config's bridge under; none: they are not identified (the
    /// kinetic-energy mass, no damper).
    pub records: Vec<quakejoint_motion::Record>,
}

impl Default for CalibrationOptions {
    fn default() -> Self {
        Self {
            amplitudes: vec![0.002, 0.005, 0.01, 0.02, 0.05, 0.1],
            speed: 0.02,
            cycles: 2,
            contact_force: None,
            records: Vec::new(),
        }
    }
}

/// The force of the exports' closing secant where neither the user nor the
/// calibration suite gives one \[N\].
pub const DEFAULT_CONTACT_FORCE: f64 = 1e6;

/// The largest closed-joint force at which a secant may be taken \[N\]
/// (100 GN: far beyond any abutment).
pub const MAX_CONTACT_FORCE: f64 = 1e11;

impl CalibrationOptions {
    /// Checks the options a front end gave before the calibration runs,
    /// an error naming each as that front end does (`name("speed")`:
    /// `--speed` on the command line, `speed` in Python): every amplitude
    /// within `service.amplitude`'s range, the speed within
    /// `service.speed`'s, the contact force positive and finite.
    pub fn check(&self, name: impl Fn(&str) -> String) -> Result<(), ModelError> {
        if self.amplitudes.is_empty() {
            return Err(ModelError::Override {
                name: name("amplitudes"),
                value: "none".into(),
                reason: "give at least one amplitude [m]".into(),
            });
        }
        for &a in &self.amplitudes {
            crate::runspec::check_override("service.amplitude", &name("amplitudes"), a)?;
        }
        crate::runspec::check_override("service.speed", &name("speed"), self.speed)?;
        let Some(f) = self.contact_force else { return Ok(()) };
        if !(f.is_finite() && f > 0.0 && f <= MAX_CONTACT_FORCE) {
            return Err(ModelError::Override {
                name: name("contact_force"),
                value: quakejoint_motion::number(f),
                reason: format!(
                    "must be a force above 0 and at most {MAX_CONTACT_FORCE:e} N: the closed joint's stiffness is \
                     the secant of its contact law at it"
                ),
            });
        }
        Ok(())
    }
}

/// One service loop of the detailed joint and the link's at the same
/// amplitude.
#[derive(Debug, Clone, PartialEq)]
pub struct LoopSummary {
    /// Amplitude \[m\].
    pub amplitude: f64,
    /// The detailed joint's loop area over the last cycle, `E_D` \[J\].
    pub energy: f64,
    /// The detailed joint's largest force on the deck over it \[N\].
    pub peak_force: f64,
    /// The link's loop area (closed form, `4 F (A - F/k)`) \[J\].
    pub link_energy: f64,
    /// The joint's equivalent damping ratio with its own secant stiffness,
    /// `E_D / (4 pi (peak_force A / 2))` [-].
    pub damping_joint: f64,
    /// On the config's single-DOF bridge (none for a modal one), the
    /// damping ratio the joint adds at that deck amplitude, `E_D / (4 pi
    /// (K + k_sec) A^2 / 2)` [-].
    pub damping_bridge: Option<f64>,
    /// Times \[s\], openings \[m\] and the detailed joint's force on the deck
    /// \[N\] over the whole run (every cycle).
    pub t: Vec<f64>,
    /// Openings \[m\].
    pub u: Vec<f64>,
    /// The detailed joint's force on the deck \[N\].
    pub force: Vec<f64>,
    /// The index of the last cycle's first sample.
    pub last_cycle: usize,
    /// The loop's racking `[closing, opening]` \[m\] ([`racking`]).
    pub racking: [f64; 2],
}

/// The chosen link under one record of the calibration suite, and that
/// record's own best mass and damper.
#[derive(Debug, Clone, PartialEq)]
pub struct DynamicFit {
    /// The record's name.
    pub record: String,
    /// RMS of the link's force on the deck against the detailed joint's
    /// over the run \[N\].
    pub rms: f64,
    /// The detailed joint's peak force on the deck \[N\].
    pub peak_detailed: f64,
    /// The link's \[N\].
    pub peak_link: f64,
    /// The detailed joint's friction energy \[J\].
    pub friction_detailed: f64,
    /// The link's \[J\].
    pub friction_link: f64,
    /// The detailed joint's largest force on the deck through its closed
    /// cells \[N\] (0: it did not close).
    pub closed_detailed: f64,
    /// The mass that fits this record alone best \[kg\].
    pub own_mass: f64,
    /// The detailed joint's racking under this record `[closing, opening]`
    /// \[m\] ([`racking`]; closing NaN where a cell closed).
    pub racking: [f64; 2],
}

/// The mass factors of the search (times the kinetic-energy mass) [-]: at
/// most the whole joint sliding at once, which no part of it can exceed.
pub const MASS_FACTORS: [f64; 10] = [0.25, 0.375, 0.5, 0.55, 0.6, 0.65, 0.7, 0.75, 0.85, 1.0];
/// The band the link's peak force on the deck is held in, relative to the
/// detailed joint's [-]: at most 5 % below, at most 10 % above.
pub const BAND: [f64; 2] = [-0.05, 0.10];

/// The calibrated link and how well it fits.
#[derive(Debug, Clone, PartialEq)]
pub struct Calibration {
    /// The link's parameters.
    pub link: LinkConfig,
    /// The hand calculation of the friction force \[N\].
    pub hand_friction: f64,
    /// RMS of the fit's force error over the loops \[N\].
    pub fit_rms: f64,
    /// The closing movement until every cell is closed \[m\].
    pub gap: f64,
    /// The opening movement at which the widest cell (the average with
    /// the racking) reaches its capacity \[m\].
    pub capacity: f64,
    /// Cells [-].
    pub cells: usize,
    /// The loops.
    pub loops: Vec<LoopSummary>,
    /// The mass of the joint's kinetic energy sliding as a whole \[kg\].
    pub kinetic_mass: f64,
    /// The chosen link under each record of the calibration suite (none:
    /// no suite ran).
    pub dynamic: Vec<DynamicFit>,
    /// The closed-joint force the exports' linear gap is the Hertz law's
    /// secant at \[N\].
    pub secant_force: f64,
    /// Where [`Calibration::secant_force`] comes from, in words.
    pub secant_from: String,
    /// Where the link's racking comes from, in words.
    pub racking_from: String,
    /// The joint's fuse box as the exports carry it (none without one).
    pub fuse: Option<export::FuseExport>,
    /// The joint's fuse element as the exports carry it (none without
    /// one).
    pub fuse_element: Option<export::ElementExport>,
    /// The options it ran with.
    pub options: CalibrationOptions,
    /// What the calibration cannot stand behind: loops left out, a poor
    /// fit, a calibration earthquake the detailed joint is flagged in, a
    /// mass or damper at the edge of the search.
    pub warnings: Vec<String>,
}

impl Calibration {
    /// Its numbers: name, value (NaN where none) and unit, as every front
    /// end lists them (the command line's JSON, Python).
    pub fn scalars(&self) -> [(&'static str, f64, &'static str); 14] {
        let l = &self.link;
        [
            ("stiffness", l.stiffness, "N/m"),
            ("friction", l.friction, "N"),
            ("hand_friction", self.hand_friction, "N"),
            ("mass", l.mass, "kg"),
            ("kinetic_mass", self.kinetic_mass, "kg"),
            ("damping", l.damping.unwrap_or(0.0), "N s/m"),
            ("gap", self.gap, "m"),
            ("gap_stiffness", l.gap_stiffness, "N/m"),
            ("capacity", self.capacity, "m"),
            ("fit_rms", self.fit_rms, "N"),
            ("speed", self.options.speed, "m/s"),
            ("contact_force", self.secant_force, "N"),
            ("racking_closing", l.racking()[0], "m"),
            ("racking_opening", l.racking()[1], "m"),
        ]
    }
}

impl Calibration {
    /// The closing movement at which the narrowest cell closes, `(Nc + 1)
    /// (g0 - racking_closing)` \[m\].
    pub fn first_closure(&self) -> f64 {
        self.gap - self.cells as f64 * self.link.racking()[0]
    }
}

impl LoopSummary {
    /// Its numbers, as [`Calibration::scalars`] lists the calibration's.
    pub fn scalars(&self) -> [(&'static str, f64, &'static str); 8] {
        [
            ("amplitude", self.amplitude, "m"),
            ("energy", self.energy, "J"),
            ("link_energy", self.link_energy, "J"),
            ("peak_force", self.peak_force, "N"),
            ("damping_joint", self.damping_joint, "1"),
            ("damping_bridge", self.damping_bridge.unwrap_or(f64::NAN), "1"),
            ("racking_closing", self.racking[0], "m"),
            ("racking_opening", self.racking[1], "m"),
        ]
    }
}

impl DynamicFit {
    /// Its numbers, as [`Calibration::scalars`] lists the calibration's.
    pub fn scalars(&self) -> [(&'static str, f64, &'static str); 9] {
        [
            ("rms", self.rms, "N"),
            ("own_mass", self.own_mass, "kg"),
            ("closed_detailed", self.closed_detailed, "N"),
            ("peak_link", self.peak_link, "N"),
            ("peak_detailed", self.peak_detailed, "N"),
            ("friction_link", self.friction_link, "J"),
            ("friction_detailed", self.friction_detailed, "J"),
            ("racking_closing", self.racking[0], "m"),
            ("racking_opening", self.racking[1], "m"),
        ]
    }
}

/// Calibrates the link of a scenario's joint (the detailed one of
/// `[joint]`).
pub fn calibrate(scenario: &Scenario, options: &CalibrationOptions) -> Result<Calibration, ModelError> {
    options.check(|k| k.to_string())?;
    // the element is the joint's without its fuse (its loops and the suite
    // run without it); the fuse is added to the link as given
    let fused = &scenario.config;
    let mut unfused = fused.clone();
    unfused.joint.fuse = None;
    let config = &unfused;
    let amplitudes = checked_amplitudes(config, options)?;
    let j = &config.joint;
    let mut warnings = Vec::new();
    let mut loops = service_loops(config, &amplitudes, options, &mut warnings)?;
    if loops.is_empty() {
        return Err(ModelError::Invalid {
            field: "amplitudes".to_string(),
            value: format!("{amplitudes:?}"),
            reason: format!("every service loop was left out: {}", warnings.join("; ")),
        });
    }
    let (stiffness, friction, fit_rms) = fit(&loops);
    let widest = loops.iter().map(|l| l.amplitude).fold(0.0, f64::max);
    if friction / stiffness > 0.5 * widest {
        return Err(ModelError::Invalid {
            field: "amplitudes".to_string(),
            value: format!("{amplitudes:?}"),
            reason: format!(
                "the widest loop ({widest} m) hardly slides (the fitted law yields at {:.3e} m): give amplitudes \
                 several times larger",
                friction / stiffness
            ),
        });
    }
    let geo = Geometry::new(config)?;
    // loops that do not slide: none reaches half the slider force the
    // bearings give by hand, or the law misses them by more than its own
    // slider force (a fit of elastic loops, whose "slider" is noise)
    let hand = hand_friction(config, &geo);
    let strongest = loops.iter().map(|l| l.peak_force).fold(0.0, f64::max);
    if strongest < 0.5 * hand || fit_rms > friction {
        return Err(ModelError::Invalid {
            field: "amplitudes".to_string(),
            value: format!("{amplitudes:?}"),
            reason: format!(
                "the loops do not slide: their largest force is {strongest:.3e} N against the bearings' friction \
                 force of {hand:.3e} N by hand, and the elastic-perfectly-plastic law fitted to them (a slider of \
                 {friction:.3e} N) misses them by {fit_rms:.3e} N RMS: give amplitudes several times larger"
            ),
        });
    }
    if fit_rms > 0.2 * friction {
        warnings.push(format!(
            "the elastic-perfectly-plastic law fits the loops poorly: RMS {:.3e} N, {:.0} % of the slider force",
            fit_rms,
            100.0 * fit_rms / friction
        ));
    }
    let mass = moving_mass(config, &geo);
    let bridge = config.bridge.modal.is_none().then(|| config.bridge.mass * config.bridge.omega().powi(2));
    for l in &mut loops {
        let a = l.amplitude;
        let yield_u = friction / stiffness;
        l.link_energy = if a > yield_u { 4.0 * friction * (a - yield_u) } else { 0.0 };
        let k_sec = l.peak_force / a;
        l.damping_bridge = bridge.map(|kb| l.energy / (4.0 * std::f64::consts::PI * 0.5 * (kb + k_sec) * a * a));
    }
    let cells = j.cells();
    let gap_hertz = (j.contact.law == ContactLawConfig::Hertz)
        .then(|| 2.0 * j.contact.hertz_stiffness / (j.cells() as f64).powf(1.5));
    let gap_stiffness = closed_stiffness(config, DEFAULT_CONTACT_FORCE);
    // the stuck joint's own damping: the bushings' time constant
    let b = &j.bushing;
    let damping = (b.kx > 0.0).then(|| stiffness * b.cx / b.kx);
    let mut link = LinkConfig {
        stiffness,
        friction,
        mass,
        gap_stiffness,
        gap_hertz,
        damping,
        v_eps: None,
        racking_closing: None,
        racking_opening: None,
    };
    let dynamic = if options.records.is_empty() {
        Vec::new()
    } else {
        identify(config, &options.records, &mut link, &mut warnings)?
    };
    let (secant_force, secant_from) = secant_at(options, &dynamic);
    link.gap_stiffness = closed_stiffness(config, secant_force);
    let racking_from = set_racking(&mut link, &loops, &dynamic, j.clear_subgap(), &mut warnings);
    check_fitted(&link)?;
    let capacity = cells as f64 * (j.capacity.max_subgap - j.clear_subgap() - link.racking()[1]);
    let fuse = export::FuseExport::of(fused, link.gap_stiffness, &mut warnings);
    let gap = cells as f64 * j.clear_subgap();
    let fuse_element = export::ElementExport::of(fused, (gap, link.gap_stiffness), &mut warnings);
    Ok(Calibration {
        link,
        kinetic_mass: mass,
        dynamic,
        hand_friction: hand,
        fit_rms,
        gap,
        capacity,
        cells,
        loops,
        secant_force,
        secant_from,
        racking_from,
        fuse,
        fuse_element,
        options: options.clone(),
        warnings,
    })
}

/// The force the exports' closing secant is taken at, and where from in
/// words: the one given, or the detailed joint's largest closed-joint force
/// on the deck under the suite, or [`DEFAULT_CONTACT_FORCE`].
fn secant_at(options: &CalibrationOptions, dynamic: &[DynamicFit]) -> (f64, String) {
    let closed = dynamic.iter().max_by(|a, b| a.closed_detailed.total_cmp(&b.closed_detailed));
    match (options.contact_force, closed) {
        (Some(f), _) => (f, "given".to_string()),
        (None, Some(d)) if d.closed_detailed > 0.0 => (
            d.closed_detailed,
            format!(
                "the detailed joint's largest closed-joint force on the deck under the calibration suite ({})",
                d.record
            ),
        ),
        (None, _) => (
            DEFAULT_CONTACT_FORCE,
            "a default: the detailed joint did not close under the calibration suite".to_string(),
        ),
    }
}

/// `config`'s joint and `options`' amplitudes checked for a calibration:
/// the amplitudes sorted, each once.
fn checked_amplitudes(config: &Config, options: &CalibrationOptions) -> Result<Vec<f64>, ModelError> {
    let j = &config.joint;
    if !j.enabled || j.is_link() {
        return Err(ModelError::Invalid {
            field: "joint.model".to_string(),
            value: if j.enabled { "\"link\"".to_string() } else { "joint.enabled = false".to_string() },
            reason: "the calibration needs the detailed joint (joint.model = \"detailed\", the default)".to_string(),
        });
    }
    // (each amplitude in its range, at least one: CalibrationOptions::check)
    // (the opening the cells take, and the closing that closes them all)
    let reach =
        (j.cells() as f64 * (j.capacity.max_subgap - j.clear_subgap())).min(j.cells() as f64 * j.clear_subgap());
    if let Some(a) = options.amplitudes.iter().find(|&&a| a >= reach) {
        return Err(ModelError::Invalid {
            field: "amplitudes".to_string(),
            value: format!("{a}"),
            reason: format!(
                "the loops must stay inside the joint: below {reach} m, where its cells reach their capacity or all \
                 close"
            ),
        });
    }
    let mut amplitudes = options.amplitudes.clone();
    amplitudes.sort_by(f64::total_cmp);
    amplitudes.dedup();
    Ok(amplitudes)
}

/// The detailed joint's service loops at `amplitudes` \[m\], each left out
/// (with a warning) where its cells rack beyond their capacity or its beams
/// pound.
fn service_loops(
    config: &Config,
    amplitudes: &[f64],
    options: &CalibrationOptions,
    warnings: &mut Vec<String>,
) -> Result<Vec<LoopSummary>, ModelError> {
    let mut loops = Vec::with_capacity(amplitudes.len());
    for (k, &a) in amplitudes.iter().enumerate() {
        let mut c = config.clone();
        // (each reversal rounded over at most a quarter of a stroke)
        c.service.blend = c.service.blend.min(0.25 * 2.0 * a / options.speed);
        let overrides = Overrides {
            service_amplitude: Some(Named::new(a, format!("amplitudes[{k}]"))),
            service_speed: Some(Named::new(options.speed, "speed")),
            service_cycles: Some(Named::new(options.cycles, "cycles")),
            ..Overrides::default()
        };
        let r = crate::service::service(&RunSpec::new(c, &overrides)?.scenario)?;
        if r.validity.flags.is_flagged() || r.contact_work_per_cycle > 0.0 {
            // (its cells racked beyond their capacity, or its beams pounded:
            // not the law of a joint in service)
            warnings.push(format!(
                "the service loop at {a} m is left out of the fit: {}",
                if r.validity.flags.is_flagged() { r.validity.flags.label() } else { "its beams pound".to_string() }
            ));
            continue;
        }
        let period = r.period;
        let last = r.t.last().copied().unwrap_or(0.0) - period;
        let last_cycle = r.t.partition_point(|t| *t < last);
        let peak_force = r.joint_force[last_cycle..].iter().fold(0.0f64, |m, f| m.max(f.abs()));
        let racking = racking(config.joint.cells(), config.joint.clear_subgap(), &r.u, [r.min_subgap, r.max_subgap]);
        loops.push(LoopSummary {
            amplitude: a,
            energy: r.loop_work_per_cycle,
            peak_force,
            link_energy: 0.0,
            damping_joint: r.loop_work_per_cycle / (4.0 * std::f64::consts::PI * 0.5 * peak_force * a),
            damping_bridge: None,
            t: r.t,
            u: r.u,
            force: r.joint_force,
            last_cycle,
            racking,
        });
    }
    Ok(loops)
}

/// Refuses a fitted link whose parameters lie outside their ranges.
fn check_fitted(link: &LinkConfig) -> Result<(), ModelError> {
    for (key, v) in [
        ("stiffness", link.stiffness),
        ("friction", link.friction),
        ("mass", link.mass),
        ("gap_stiffness", link.gap_stiffness),
    ] {
        let field = format!("joint.link.{key}");
        if let Some((_, bound)) = crate::limits::limit(&field) {
            if !bound.contains(v) {
                return Err(ModelError::Invalid {
                    field,
                    value: format!("{v:e}"),
                    reason: format!("the calibration gives a value outside {}: check the loops", bound.describe()),
                });
            }
        }
    }
    Ok(())
}

/// The elastic-perfectly-plastic force on the deck (resisting the opening)
/// over an opening history, from rest.
pub fn elastoplastic(u: &[f64], stiffness: f64, friction: f64) -> Vec<f64> {
    let mut f = 0.0f64;
    let mut last = u.first().copied().unwrap_or(0.0);
    u.iter()
        .map(|&x| {
            f = (f - stiffness * (x - last)).clamp(-friction, friction);
            last = x;
            f
        })
        .collect()
}

/// Mean over the loops of each loop's mean squared error of the law over
/// its last cycle (the law run from rest over the whole history; the first
/// cycle's start from rest is left out of the error).
fn misfit(loops: &[LoopSummary], stiffness: f64, friction: f64) -> f64 {
    loops
        .iter()
        .map(|l| {
            let law = elastoplastic(&l.u, stiffness, friction);
            let first = l.last_cycle;
            let n = (l.u.len() - first).max(1) as f64;
            law[first..].iter().zip(&l.force[first..]).map(|(a, b)| (a - b).powi(2)).sum::<f64>() / n
        })
        .sum::<f64>()
        / loops.len() as f64
}

/// Golden-section minimum of `f` on `[a, b]` (60 steps: the bracket
/// shrinks by 3e-13).
fn golden(f: impl Fn(f64) -> f64, mut a: f64, mut b: f64) -> f64 {
    let r = (5f64.sqrt() - 1.0) / 2.0;
    let (mut c, mut d) = (b - r * (b - a), a + r * (b - a));
    let (mut fc, mut fd) = (f(c), f(d));
    for _ in 0..60 {
        if fc < fd {
            (b, d, fd) = (d, c, fc);
            c = b - r * (b - a);
            fc = f(c);
        } else {
            (a, c, fc) = (c, d, fd);
            d = a + r * (b - a);
            fd = f(d);
        }
    }
    (a + b) / 2.0
}

/// `(k, F, rms)`: first the least squares in both (for each `k` the best
/// `F` by golden section up to the largest force seen; `log k` on a grid
/// from 1e4 to 1e12 N/m, refined about the best point); then `F` so that
/// the widest loop's area is the detailed joint's, `4 F (A - F / k) =
/// E_D` (the least squares pull `F` below the sliding plateau where the
/// detailed joint's bearings start to slide one after the other, and the
/// dissipation is what the bridge feels), and `k` again by least squares
/// with that `F`.
fn fit(loops: &[LoopSummary]) -> (f64, f64, f64) {
    let top = loops.iter().map(|l| l.peak_force).fold(0.0f64, f64::max);
    let best_f = |k: f64| golden(|f| misfit(loops, k, f), 0.0, top);
    let cost = |lk: f64| {
        let k = 10f64.powf(lk);
        misfit(loops, k, best_f(k))
    };
    let grid: Vec<f64> = (0..=64).map(|i| 4.0 + 8.0 * i as f64 / 64.0).collect();
    let i = (0..grid.len()).min_by(|&a, &b| cost(grid[a]).total_cmp(&cost(grid[b]))).unwrap_or(0);
    let (lo, hi) = (grid[i.saturating_sub(1)], grid[(i + 1).min(grid.len() - 1)]);
    let mut k = 10f64.powf(golden(cost, lo, hi));
    let mut f = best_f(k);
    if let Some(wide) = loops.iter().max_by(|a, b| a.amplitude.total_cmp(&b.amplitude)) {
        // F^2 / k - A F + E_D / 4 = 0, the root below k A / 2
        let (a, e) = (wide.amplitude, wide.energy);
        let disc = a * a - e / k;
        if disc >= 0.0 && e > 0.0 {
            f = k * (a - disc.sqrt()) / 2.0;
            let lk = golden(|lk| misfit(loops, 10f64.powf(lk), f), lo - 1.0, hi + 1.0);
            k = 10f64.powf(lk);
        }
    }
    (k, f, misfit(loops, k, f).sqrt())
}

/// The hand calculation of the friction force on the deck at rest \[N\].
fn hand_friction(config: &Config, geo: &Geometry) -> f64 {
    let fr = &config.joint.friction;
    let n1 = (geo.center_beams + 1) as f64;
    let per_bearing = fr.mu * fr.surfaces * fr.normal_force;
    geo.supports
        .iter()
        .map(|s| {
            let dl = match s.kind {
                SupportKind::Joist => geo.gap / (geo.gap * geo.gap + s.box_dy * s.box_dy).sqrt(),
                SupportKind::Guide => 1.0,
            };
            (1..=geo.center_beams).map(|i| per_bearing * i as f64 / n1 * dl).sum::<f64>()
        })
        .sum()
}

/// The joint's mass moving with the deck: kinetic energy over `V^2 / 2`
/// \[kg\] (see the module documentation).
fn moving_mass(config: &Config, geo: &Geometry) -> f64 {
    let j = &config.joint;
    let n1 = (geo.center_beams + 1) as f64;
    let beam = j.center_beam.mass + geo.supports.len() as f64 * j.bearing.mass;
    let beams: f64 = (1..=geo.center_beams).map(|i| beam * (i as f64 / n1).powi(2)).sum();
    let joists: f64 = geo
        .supports
        .iter()
        .filter(|s| s.kind == SupportKind::Joist)
        .map(|s| {
            let r2 = geo.gap * geo.gap + s.box_dy * s.box_dy;
            // about the pivot: its centre at half the pivot-to-box distance at rest
            let about_pivot = j.support_beam.inertia() + j.support_beam.mass * r2 / 4.0;
            about_pivot * (s.box_dy / r2).powi(2)
        })
        .sum();
    beams + joists
}

/// The closed joint's stiffness \[N/m\] (see the module documentation).
fn closed_stiffness(config: &Config, contact_force: f64) -> f64 {
    let c = &config.joint.contact;
    let n1 = config.joint.cells() as f64;
    match c.law {
        ContactLawConfig::Linear => 2.0 * c.linear_stiffness / n1,
        ContactLawConfig::Hertz => {
            let cell = (contact_force / (2.0 * c.hertz_stiffness)).powf(2.0 / 3.0);
            contact_force / (n1 * cell)
        }
    }
}
