//! The joint as one link element between the deck and the abutment
//! (`joint.model = "link"`, docs/link.md).
//!
//! Along the joint's x, with `u` the deck's opening relative to the
//! abutment:
//!
//! - a spring `k` (the stuck joint: bushings and joists in series), with a
//!   damper `c` beside it, from the deck to the joint's moving mass `m` (its center beams and bearings,
//!   which stay when the joint sticks and move with the deck when it
//!   slides), which slides on the abutment against the Coulomb force `F`
//!   (the bearings' friction as the swivel kinematics pass it to the deck;
//!   regularised below `v_eps`): statically an elastic-perfectly-plastic
//!   force, OpenSees' `ElasticPP` with `E = k` and `epsyP = F / k`;
//! - a gap: once the deck has closed the joint by the sum of its clear
//!   sub-gaps at rest, `(Nc + 1) (pitch - width)`, every cell is closed and
//!   the deck meets the abutment through the linear spring `k_c`
//!   (no damping: OpenSees' `ElasticPPGap`).
//!
//! The cells open alike (the intercept theorem), `g0 + u / (Nc + 1)`, but
//! for their racking: the detailed joint's beams lag on their bushings, so
//! its narrowest cell is narrower than the average by up to
//! `racking_closing` and its widest wider by up to `racking_opening`
//! (calibrated from the detailed joint, docs/link.md). The narrowest cell
//! closes (an impact between beams, counted as the detailed joint's
//! impacts) once the average is `racking_closing`; the widest is checked
//! against `joint.capacity.max_subgap`.

use quakejoint_solver::{
    Body, BodyId, Bushing, Contact, ContactLaw, Coord, ForceElement, Friction, FrictionLaw, System,
};

use quakejoint_solver::IntegratorOptions;

use crate::config::JointConfig;
use crate::error::ModelError;
use crate::placement::Place;

/// The relative and absolute tolerance a run whose joints are all links is
/// integrated to at least [-, m, m/s] (with its steps limited by
/// [`STEP_FRACTION`]: at 1e-10 and 1e-12 the peak forces agree to 0.01 %;
/// docs/link.md).
pub const TOLERANCE: f64 = 1e-10;

/// The largest step of a run of links, as a fraction of the period of its
/// mass on its spring over 2 pi, `sqrt(m / k)` [-]. The step control does
/// not see the error of the slider's release (the error estimate filters
/// the sliders' velocity errors, docs/solver.md), so a run converged in
/// its tolerance alone was not: the reference joint's link on a 1e7 kg
/// deck at 1 s under El Centro 180 (c = 0) gave a peak force of 449.4 kN at
/// every tolerance from 1e-10 to 1e-12; with steps of at most 0.05, 0.02,
/// 0.01 `sqrt(m / k)` 436.50, 436.49, 436.48 kN, the event-driven
/// rigid-plastic solution 436.49 kN and OpenSees 435.9 kN.
pub const STEP_FRACTION: f64 = 0.05;

/// Tightens `options` for a run with the joints of `places` (each resolved
/// alike): where every joint is a link, the tolerances to at most
/// [`TOLERANCE`]; where any is, the steps to at most [`STEP_FRACTION`] of
/// the shortest `sqrt(m / k)` among them.
pub(crate) fn tighten(options: &mut IntegratorOptions, places: &[Place]) {
    let joints = || places.iter().map(|p| &p.config.joint).filter(|j| j.enabled);
    // (a detailed joint's tolerances stay the config's, beside a link too)
    if joints().count() > 0 && joints().all(JointConfig::is_link) {
        options.rtol = options.rtol.min(TOLERANCE);
        options.atol_translation = options.atol_translation.min(TOLERANCE);
        options.atol_velocity = options.atol_velocity.min(TOLERANCE);
    }
    let shortest = joints()
        .filter_map(|j| j.link.as_ref().filter(|_| j.is_link()))
        .map(|l| STEP_FRACTION * (l.mass / l.stiffness).sqrt())
        .reduce(f64::min);
    if let Some(h) = shortest {
        options.h_max = options.h_max.min(h);
    }
}

/// The link's parts in the solver system.
#[derive(Debug, Clone, PartialEq)]
pub struct LinkParts {
    /// The deck side.
    pub deck: BodyId,
    /// The joint's moving mass, between the spring and the friction.
    pub slider: BodyId,
    /// The spring \[N/m\].
    pub stiffness: f64,
    /// The damper with the spring \[N s/m\].
    pub damping: f64,
    /// The abutment side (the ground, or a body).
    pub abutment: BodyId,
    /// The closing movement until every cell is closed \[m\].
    pub gap: f64,
    /// Cells (sub-gaps) [-].
    pub cells: usize,
    /// The clear sub-gap at rest \[m\].
    pub clear: f64,
    /// The cells' capacity \[m\].
    pub max_subgap: f64,
    /// The racking `[closing, opening]`: how far the narrowest cell lags
    /// behind the average, and the widest leads it \[m\].
    pub racking: [f64; 2],
    /// The solver's number of the gap's contact (set by the generator;
    /// none without contact).
    pub contact: Option<usize>,
    /// The gap's contact element (none without contact).
    pub gap_force: Option<quakejoint_solver::ForceId>,
}

/// Adds the link of `joint` between `deck` and `abutment` to `sys`
/// (`sign` -1: the joint turned half a turn; `prefix` starts the names).
pub fn add_link(
    sys: &mut System,
    joint: &JointConfig,
    deck: BodyId,
    abutment: BodyId,
    sign: f64,
    prefix: &str,
) -> Result<LinkParts, ModelError> {
    let l = joint.link.as_ref().ok_or_else(|| ModelError::Invalid {
        field: "joint.link".to_string(),
        value: "none".to_string(),
        reason: "joint.model = \"link\" needs [joint.link]".to_string(),
    })?;
    let body = |name: String, mass: f64| {
        let b = Body::new(name, mass, 1.0, [0.0; 3]).only(&[Coord::X]);
        if sign < 0.0 {
            b.with_base_mass([[-mass, 0.0], [0.0, -mass]])
        } else {
            b
        }
    };
    let slider = sys.add_body(body(format!("{prefix}link mass"), l.mass));
    sys.add_force_named(
        format!("{prefix}link spring"),
        ForceElement::Bushing(Bushing {
            frame_body: deck,
            frame_point: [0.0, 0.0],
            body: slider,
            point: [0.0, 0.0],
            stiffness: [l.stiffness, 0.0],
            damping: [l.damping.unwrap_or(0.0), 0.0],
            rest: [0.0, 0.0],
        }),
    );
    if l.friction > 0.0 {
        sys.add_force_named(
            format!("{prefix}link friction"),
            ForceElement::Friction(Friction {
                slider,
                point: [0.0, 0.0],
                base: abutment,
                mu: 1.0,
                normal_force: l.friction,
                surfaces: 1.0,
                v_eps: l.v_eps(),
                law: FrictionLaw::Linear,
            }),
        );
    }
    let cells = joint.cells();
    let clear = joint.clear_subgap();
    let gap = cells as f64 * clear;
    let mut gap_force = None;
    if joint.contact.enabled {
        gap_force = Some(sys.add_force_named(
            format!("{prefix}link gap"),
            ForceElement::Contact(Contact {
                body: deck,
                point: [0.0, 0.0],
                base: abutment,
                edge_point: [-gap, 0.0],
                edge_normal: [1.0, 0.0],
                law: match l.gap_hertz {
                    Some(stiffness) => ContactLaw::Hertz {
                        stiffness,
                        restitution: joint.contact.restitution,
                        damping: hertz_damping(&joint.contact),
                    },
                    None => ContactLaw::Linear { stiffness: l.gap_stiffness, restitution: 1.0 },
                },
                reduced_mass: None,
            }),
        ));
    }
    Ok(LinkParts {
        deck,
        slider,
        stiffness: l.stiffness,
        damping: l.damping.unwrap_or(0.0),
        abutment,
        gap,
        cells,
        clear,
        max_subgap: joint.capacity.max_subgap,
        racking: l.racking(),
        contact: None,
        gap_force,
    })
}

/// The linear stiffness of one contact of `joint`'s law at the force at
/// which the closed joint's `gap_stiffness` \[N/m\] is its cells' secant:
/// a fuse box's seat and stop in the exports and in a link whose gap is
/// linear \[N/m\]. The closed joint is `Nc + 1` cells of two contacts in
/// parallel in series: Hertz `k_c (Nc + 1) / 2^(2/3)`, linear `k_c (Nc +
/// 1) / 2`.
pub fn stop_stiffness(joint: &JointConfig, gap_stiffness: f64) -> f64 {
    let n1 = joint.cells() as f64;
    match joint.contact.law {
        crate::config::ContactLawConfig::Hertz => gap_stiffness * n1 / 2f64.powf(2.0 / 3.0),
        crate::config::ContactLawConfig::Linear => gap_stiffness * n1 / 2.0,
    }
}

/// What a run watches of a link: its opening's extremes and its closure.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct LinkWatch {
    /// Smallest opening \[m\] (negative: closing).
    pub min_u: f64,
    /// Largest opening \[m\].
    pub max_u: f64,
    /// First time the joint closed \[s\] (every cell closed).
    pub closed_at: Option<f64>,
    /// First time a cell opened beyond its capacity \[s\].
    pub beyond_capacity_at: Option<f64>,
    /// Times the joint closed [-].
    pub closures: u64,
    /// Whether it is closed now.
    closed: bool,
    /// Times the narrowest cell closed (racked, before the whole joint
    /// does; with no racking the joint's closures) [-].
    pub cell_closures: u64,
    /// Whether the narrowest cell is closed now.
    cell_closed: bool,
    /// Peak force of the closed joint on the deck \[N\].
    pub peak_gap_force: f64,
    /// Time of `peak_gap_force` \[s\].
    pub peak_gap_time: f64,
    /// Deepest closure beyond the gap \[m\].
    pub max_overlap: f64,
}

impl LinkWatch {
    /// Records the opening `u` at time `t` of the link `parts`, its closed
    /// joint pushing the deck with `gap_force` \[N\].
    pub fn update(&mut self, parts: &LinkParts, t: f64, u: f64, gap_force: f64) {
        self.min_u = self.min_u.min(u);
        self.max_u = self.max_u.max(u);
        let overlap = -(u + parts.gap);
        let closed = overlap > 0.0;
        if closed {
            if !self.closed {
                self.closures += 1;
                self.closed_at.get_or_insert(t);
            }
            self.max_overlap = self.max_overlap.max(overlap);
            if gap_force > self.peak_gap_force {
                self.peak_gap_force = gap_force;
                self.peak_gap_time = t;
            }
        }
        self.closed = closed;
        let cell_closed = parts.clear + u / parts.cells as f64 - parts.racking[0] < 0.0;
        if cell_closed && !self.cell_closed {
            self.cell_closures += 1;
        }
        self.cell_closed = cell_closed;
        if self.beyond_capacity_at.is_none()
            && parts.clear + u / parts.cells as f64 + parts.racking[1] > parts.max_subgap
        {
            self.beyond_capacity_at = Some(t);
        }
    }

    /// The narrowest and widest cell \[m\]: the average with the racking,
    /// a racked cell held closed (0) until the whole joint closes (then
    /// the average's overlap, negative).
    pub fn cells(&self, parts: &LinkParts) -> [f64; 2] {
        let n = parts.cells as f64;
        let [rc, ro] = parts.racking;
        let narrow = parts.clear + self.min_u / n;
        let narrowest = if narrow >= rc { narrow - rc } else { narrow.min(0.0) };
        [narrowest, parts.clear + self.max_u / n + ro]
    }
}

/// The solver's Hertz damping of a contact config (the detailed joint's
/// contacts and the link's closed joint alike).
pub(crate) fn hertz_damping(c: &crate::config::ContactConfig) -> quakejoint_solver::HertzDamping {
    match c.damping {
        crate::config::HertzDampingConfig::YeLiZhu => quakejoint_solver::HertzDamping::YeLiZhu,
        crate::config::HertzDampingConfig::LankaraniNikravesh => quakejoint_solver::HertzDamping::LankaraniNikravesh,
    }
}
