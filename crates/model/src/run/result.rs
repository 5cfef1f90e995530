//! What a run reports ([`RunResult`]), and its parts: the adjacent
//! segment's, the deck's across the bridge, each more joint's.

use crate::described::{described, Described};
use quakejoint_solver::{ConstraintResiduals, Stats};

use super::Histories;
use crate::pounding::Pounding;
use crate::validity::Validity;

/// The adjacent segment's response (`[bridge.far]`).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct FarSegment {
    /// Its circular frequency [rad/s].
    pub omega: f64,
    /// Peak absolute acceleration of its deck [m/s^2].
    pub sa: f64,
    /// Time of `sa` \[s\].
    pub t_sa: f64,
    /// Peak displacement of its deck relative to the ground \[m\].
    pub sd: f64,
    /// Peak force of the joint on it \[N\].
    pub peak_joint_force: f64,
    /// Its Sa without the joint: the exact linear response to the record
    /// over the run's window [m/s^2].
    pub sa_without: f64,
    /// Largest relative displacement of the two decks, |u - u_far| \[m\].
    pub max_relative_displacement: f64,
}

/// The deck's response across the bridge (`bridge.transverse_period`).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Transverse {
    /// Circular frequency across the bridge [rad/s].
    pub omega: f64,
    /// Peak absolute acceleration of the deck across the bridge [m/s^2].
    pub sa: f64,
    /// Time of `sa` \[s\].
    pub t_sa: f64,
    /// Peak deck displacement across the bridge relative to the ground \[m\].
    pub sd: f64,
    /// Peak deck velocity across the bridge relative to the ground [m/s].
    pub sv: f64,
    /// Peak force of the joint on the deck across the bridge \[N\].
    pub peak_joint_force: f64,
    /// Sa across the bridge without the joint: the exact linear response of
    /// the transverse oscillator to `[record_y]` over the run's window
    /// [m/s^2] (0 without `[record_y]`).
    pub sa_without: f64,
}

/// Results of one earthquake run (SI units).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct RunResult {
    /// Bridge circular frequency [rad/s].
    pub omega: f64,
    /// Peak absolute acceleration of the deck [m/s^2].
    pub sa: f64,
    /// Time of `sa` \[s\].
    pub t_sa: f64,
    /// Pseudo-spectral acceleration `w0^2 Sd` [m/s^2].
    pub psa: f64,
    /// Peak deck displacement relative to the ground \[m\].
    pub sd: f64,
    /// Time of `sd` \[s\].
    pub t_sd: f64,
    /// Peak deck velocity relative to the ground [m/s].
    pub sv: f64,
    /// Time of `sv` \[s\].
    pub t_sv: f64,
    /// Peak force of the joint on the deck \[N\].
    pub peak_joint_force: f64,
    /// Peak force of the joint on its abutment (its pivots, welds and the
    /// abutment's edge-beam contacts; on the adjacent segment with
    /// `[bridge.far]`) \[N\]; NaN without a detailed joint.
    pub peak_abutment_force: f64,
    /// Peak bushing force \[N\].
    pub peak_bushing_force: f64,
    /// Peak friction force of one bearing \[N\].
    pub peak_friction_force: f64,
    /// Energy dissipated by friction \[J\].
    pub friction_energy: f64,
    /// Energy dissipated by dampers (bridge and bushings) \[J\].
    pub damping_energy: f64,
    /// Work of the earthquake load on the whole system \[J\].
    pub earthquake_work: f64,
    /// Smallest clear sub-gap \[m\] (below zero: the beams would collide),
    /// at either end of the center beams ([`crate::geometry::Geometry::subgaps`]), checked
    /// at least every [`super::CHECK_INTERVAL`].
    pub min_subgap: Option<f64>,
    /// Largest clear sub-gap \[m\], at either end of the center beams.
    pub max_subgap: Option<f64>,
    /// Largest deviation of a sub-gap (at either end) from equal spacing \[m\].
    pub max_subgap_deviation: Option<f64>,
    /// Pounding: impacts, contact forces, the closed joint's force on the
    /// deck, contact dissipation.
    pub pounding: Pounding,
    /// The deck's response across the bridge, when it moves across.
    pub transverse: Option<Transverse>,
    /// The adjacent segment's response, when the joint sits between two
    /// segments.
    pub far: Option<FarSegment>,
    /// Largest energy-balance error divided by the largest earthquake work [-].
    pub energy_error: f64,
    /// Largest constraint residuals over the run, by kind and unit.
    pub residuals: ConstraintResiduals,
    /// Whether the run stayed inside what the model can stand behind.
    pub validity: Validity,
    /// True for the exact linear solution of the bridge alone
    /// ([`crate::linear::linear_response`]): the joint's quantities, the
    /// energy balance, the residuals and the solver counters were not
    /// computed (NaN in the outputs).
    pub exact_linear: bool,
    /// Solver counters.
    pub stats: Stats,
    /// Wall-clock time of the integration \[s\].
    pub wall_time_s: f64,
    /// CPU time of the integration on its thread \[s\] (NaN where the system
    /// does not tell).
    pub cpu_time_s: f64,
    /// Simulated duration \[s\].
    pub duration: f64,
    /// Time histories, if requested.
    pub histories: Option<Histories>,
    /// A modal bridge's points: peaks with the joints and, filled in by
    /// [`crate::runspec::RunSpec::run`], of the bridge alone.
    pub points: Vec<crate::modal::PointPeaks>,
    /// A modal bridge's peak base shear along the bridge \[N\] (the kept
    /// modes' forces on the supports).
    pub base_shear: Option<f64>,
    /// The same, of the bridge alone \[N\].
    pub base_shear_without: Option<f64>,
    /// How much of a modal bridge the kept modes hold, and the warnings
    /// where they hold too little at the joints' points.
    pub mode_check: Option<(crate::modal::ModeCheck, Vec<String>)>,
    /// Every joint's results, in the order of `[[joints]]` (the one of
    /// `[joint]` alone; none for the bridge alone). The deck's values above
    /// are at the first joint's deck point; the sub-gaps and the pounding
    /// above are the first joint's (as a sweep stores them per job); the
    /// peak forces and energies above are the whole system's; `validity`
    /// holds every joint's flags.
    pub joints: Vec<JointResult>,
}

/// The results of one joint of a run (SI units).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct JointResult {
    /// Its name.
    pub name: String,
    /// Peak absolute acceleration of its deck point [m/s^2].
    pub sa: f64,
    /// Time of `sa` \[s\].
    pub t_sa: f64,
    /// Peak displacement of its deck point relative to the ground \[m\].
    pub sd: f64,
    /// Peak velocity of its deck point relative to the ground [m/s].
    pub sv: f64,
    /// Peak force of the joint on the deck \[N\].
    pub peak_joint_force: f64,
    /// Peak force of the joint on its abutment \[N\] (NaN for a link).
    pub peak_abutment_force: f64,
    /// Its largest bushing force \[N\].
    pub peak_bushing_force: f64,
    /// Its largest friction force of one bearing \[N\].
    pub peak_friction_force: f64,
    /// The energy its friction dissipated \[J\].
    pub friction_energy: f64,
    /// Smallest clear sub-gap \[m\].
    pub min_subgap: Option<f64>,
    /// Largest clear sub-gap \[m\].
    pub max_subgap: Option<f64>,
    /// Largest deviation of a sub-gap from equal spacing \[m\].
    pub max_subgap_deviation: Option<f64>,
    /// Its pounding (the contact energy is the whole system's).
    pub pounding: Pounding,
    /// Whether it stayed inside what the model can stand behind.
    pub validity: Validity,
    /// Its time histories (its deck point's motion in its own x, its force
    /// on the deck, its cells), if requested; the first joint's are the
    /// run's ([`RunResult::histories`]).
    pub histories: Option<Histories>,
    /// What its seismic fuse did (none without `[joint.fuse]`).
    pub fuse: Option<crate::run::fuse::FuseResult>,
}

/// A joint's values, in the order of [`JointResult::scalars`]: its own,
/// then its fuse's ([`crate::run::fuse::FUSE_FIELDS`]).
pub const JOINT_FIELDS: [Described; 24] = {
    let mut out = [described("", "", ""); 24];
    let mut i = 0;
    while i < OWN_FIELDS.len() {
        out[i] = OWN_FIELDS[i];
        i += 1;
    }
    while i < 24 {
        out[i] = crate::run::fuse::FUSE_FIELDS[i - OWN_FIELDS.len()];
        i += 1;
    }
    out
};

/// A joint's own values (its fuse's apart).
const OWN_FIELDS: [Described; 17] = [
    described("sa", "m/s^2", "peak absolute acceleration of its deck point (along the bridge)"),
    described("t_sa", "s", "time of `sa`"),
    described("sd", "m", "peak displacement of its deck point relative to the ground"),
    described("sv", "m/s", "peak velocity of its deck point relative to the ground"),
    described("peak_joint_force", "N", "peak force of the joint on the deck"),
    described(
        "peak_abutment_force",
        "N",
        "peak force of the joint on its abutment side (its links' reactions and the edge-beam contacts; NaN for a link)",
    ),
    described("peak_bushing_force", "N", "its own largest bushing force"),
    described("peak_friction_force", "N", "its own largest friction force of one bearing"),
    described(
        "friction_energy",
        "J",
        "the energy its own bearings' friction dissipated (integrated as the system's; the joints' sum is the run's `friction_energy`, a fuse's apart in `fuse_energy`)",
    ),
    described("min_subgap", "m", "its smallest clear sub-gap, as `/result/min_subgap`"),
    described("max_subgap", "m", "its largest clear sub-gap, as `/result/max_subgap`"),
    described("max_subgap_deviation", "m", "its largest deviation of a sub-gap from equal spacing"),
    described("impacts", "1", "its impacts (contact onsets faster than the impact speed)"),
    described("peak_contact_force", "N", "its largest contact force"),
    described("peak_deck_contact_force", "N", "its largest force on the deck through its closed cells"),
    described("max_penetration", "m", "its deepest contact penetration"),
    described("max_impact_speed", "m/s", "its fastest impact (closing speed at a contact's onset)"),
];

impl JointResult {
    /// Its values ([`JOINT_FIELDS`]): name, value (NaN where not computed)
    /// and unit, as a run's `/joints/<k>` and a sweep's `/joints/<k>`
    /// store them (its validity bits apart).
    pub fn scalars(&self) -> [(&'static str, f64, &'static str); 24] {
        let opt = |x: Option<f64>| x.unwrap_or(f64::NAN);
        let p = &self.pounding;
        let values = [
            self.sa,
            self.t_sa,
            self.sd,
            self.sv,
            self.peak_joint_force,
            self.peak_abutment_force,
            self.peak_bushing_force,
            self.peak_friction_force,
            self.friction_energy,
            opt(self.min_subgap),
            opt(self.max_subgap),
            opt(self.max_subgap_deviation),
            p.impacts as f64,
            p.peak_contact_force,
            p.peak_deck_contact_force,
            p.max_penetration,
            p.max_impact_speed,
        ];
        let fuse = crate::run::fuse::FuseResult::values(self.fuse.as_ref());
        let value = |i: usize| if i < values.len() { values[i] } else { fuse[i - values.len()] };
        std::array::from_fn(|i| (JOINT_FIELDS[i].name, value(i), JOINT_FIELDS[i].units))
    }
}
