//! Whether a run stays inside what the model can stand behind.
//!
//! The model has no limits on its joints, so a run can reach states a real
//! joint cannot: a bearing sliding off its support beam, a joist pulled out
//! of its box, a sub-gap opened beyond the joint's capacity; and beams
//! pressed so hard together that the compliant contact stands for crushing,
//! not touching (or, with contact disabled, beams passing through each
//! other). Such a run still ends with numbers; its [`Validity`] says which
//! limits it crossed, when and where, and every output carries it. A run
//! whose energy balance does not close is flagged too: its numbers are not
//! converged. Pounding itself (beams touching through their contacts) is
//! physics the model stands behind, not a flag.
//!
//! The flags are bits of a `u32` (HDF5 `validity`, JSON `validity`):
//!
//! | bit | name | meaning |
//! |---|---|---|
//! | 1 | `collision` | with `joint.contact.enabled = false`: a clear sub-gap went below zero: neighbouring beams (or a beam and an edge beam) overlap |
//! | 2 | `bearing_off_support` | a bearing left the part of its support beam between the pivot (or abutment) and the joist box (or deck) |
//! | 4 | `joist_pulled_out` | the distance from a joist's pivot to its box exceeded the joist's length (`joint.support_beam.length`) |
//! | 8 | `energy_balance` | the energy balance error exceeded [`ENERGY_TOLERANCE`] of the earthquake's work |
//! | 16 | `penetration` | a contact penetrated deeper than `joint.contact.max_penetration` |
//! | 32 | `capacity_exceeded` | a clear sub-gap opened beyond `joint.capacity.max_subgap` |
//! | 32768 | `not_checked` | nothing was checked: the run failed or did not run (a sweep job), or had no joint (the exact linear solution) |
//!
//! `not_checked` is not a finding about the model: a run that carries only
//! it is not "flagged" ([`Flags::is_flagged`]), but it is not "ok" either.

use quakejoint_solver::{Assembly, BodyId, Coord};

use crate::config::{Config, SupportKind};
use crate::error::ModelError;
use crate::generator::JointModel;
use crate::geometry::Geometry;

/// Largest energy balance error, relative to the earthquake's work, of a
/// run whose numbers are trusted [-] (converged runs stay below 1e-6).
pub const ENERGY_TOLERANCE: f64 = 1e-3;

/// The validity flags of a run (a bit set).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Hash)]
pub struct Flags(pub u32);

impl Flags {
    /// Nothing crossed.
    pub const OK: Flags = Flags(0);
    /// A clear sub-gap below zero.
    pub const COLLISION: Flags = Flags(1);
    /// A bearing off its support beam.
    pub const BEARING_OFF_SUPPORT: Flags = Flags(2);
    /// A joist longer than its length from pivot to box.
    pub const JOIST_PULLED_OUT: Flags = Flags(4);
    /// The energy balance does not close.
    pub const ENERGY_BALANCE: Flags = Flags(8);
    /// A contact deeper than the contact stands for.
    pub const PENETRATION: Flags = Flags(16);
    /// A sub-gap beyond the joint's capacity.
    pub const CAPACITY_EXCEEDED: Flags = Flags(32);
    /// Nothing was checked (a failed job, a run without the joint).
    pub const NOT_CHECKED: Flags = Flags(1 << 15);
    /// Every flag with its name.
    pub const ALL: [(Flags, &'static str); 7] = [
        (Flags::COLLISION, "collision"),
        (Flags::BEARING_OFF_SUPPORT, "bearing_off_support"),
        (Flags::JOIST_PULLED_OUT, "joist_pulled_out"),
        (Flags::ENERGY_BALANCE, "energy_balance"),
        (Flags::PENETRATION, "penetration"),
        (Flags::CAPACITY_EXCEEDED, "capacity_exceeded"),
        (Flags::NOT_CHECKED, "not_checked"),
    ];

    /// Whether the run was checked and no flag is set.
    pub fn is_ok(self) -> bool {
        self.0 == 0
    }

    /// Whether the run crossed a limit of the model (any flag but
    /// [`Flags::NOT_CHECKED`]).
    pub fn is_flagged(self) -> bool {
        self.0 & !Flags::NOT_CHECKED.0 != 0
    }

    /// Whether every flag of `other` is set.
    pub fn contains(self, other: Flags) -> bool {
        self.0 & other.0 == other.0
    }

    /// The names of the flags set.
    pub fn names(self) -> Vec<&'static str> {
        Flags::ALL.iter().filter(|(f, _)| self.contains(*f) && !f.is_ok()).map(|(_, n)| *n).collect()
    }

    /// `ok`, or the names joined with `+`.
    pub fn label(self) -> String {
        if self.is_ok() {
            "ok".into()
        } else {
            self.names().join("+")
        }
    }

    /// The meaning of the bits, for file attributes.
    pub fn legend() -> String {
        let bits: Vec<String> = Flags::ALL.iter().map(|(f, n)| format!("{} {n}", f.0)).collect();
        format!("bit set: 0 ok; {}", bits.join(", "))
    }
}

impl std::ops::BitOrAssign for Flags {
    fn bitor_assign(&mut self, rhs: Flags) {
        self.0 |= rhs.0;
    }
}

/// What a run crossed: the flags and, for each, when and where, in words.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Validity {
    /// The flags.
    pub flags: Flags,
    /// One sentence per flag set (first time, place and extreme value).
    pub findings: Vec<String>,
}

impl Validity {
    /// A run of which nothing was checked, and why.
    pub fn not_checked(reason: &str) -> Self {
        Validity { flags: Flags::NOT_CHECKED, findings: vec![format!("not_checked: {reason}")] }
    }

    /// The findings as one line.
    pub fn message(&self) -> String {
        self.findings.join("; ")
    }
}

/// A bearing and how to find its position along its support beam.
#[derive(Debug, Clone)]
struct Bearing {
    /// Its x and y coordinates.
    x: usize,
    y: usize,
    /// Its support beam's index, and the joist's angle coordinate (None for
    /// a guide, which does not turn).
    support: usize,
    phi: Option<usize>,
    /// Center beam (1-based) for messages.
    beam: usize,
}

/// The first time and worst value of a crossed limit.
#[derive(Debug, Clone, Copy)]
struct Crossing {
    first: f64,
    worst: f64,
    at: f64,
    place: usize,
}

impl Crossing {
    /// Records a crossing of size `excess` (> 0) at `t` in place `place`.
    fn update(slot: &mut Option<Crossing>, t: f64, excess: f64, place: usize) {
        match slot {
            None => *slot = Some(Crossing { first: t, worst: excess, at: t, place }),
            Some(c) if excess > c.worst => {
                c.worst = excess;
                c.at = t;
                c.place = place;
            }
            _ => {}
        }
    }
}

/// The limits whose crossing is located on the dense output, in the order
/// of [`Monitor::excesses`]: beams overlapping without contacts, a cell
/// beyond its capacity, a bearing off its support, a joist pulled out of
/// its box.
pub(crate) const LIMITS: usize = 4;

/// Watches the limits of a run at its output times.
#[derive(Debug, Clone)]
pub struct Monitor {
    geometry: Geometry,
    joist_length: f64,
    /// Deepest penetration a contact stands for [m] (None: no contact, any
    /// overlap is a collision).
    max_penetration: Option<f64>,
    max_subgap: f64,
    bearings: Vec<Bearing>,
    /// The deck's y coordinate, when it moves across: the joist boxes move
    /// with it.
    deck_y: Option<usize>,
    /// The adjacent segment's deck x coordinate, when the abutment side is
    /// one: the pivots and guides move with it.
    far: Option<usize>,
    contact_places: Vec<crate::generator::ContactPlace>,
    /// Whether the abutment's edge beam is free (its fuse broke): the edge
    /// cell's opening is then the fuse's travel, not the joint's capacity.
    edge_free: bool,
    /// A fuse element's beam (1 to `Nc`) that left the plane, and when
    /// \[s\]: after that its two cells are one.
    released: Option<(usize, f64)>,
    collision: Option<Crossing>,
    off_support: Option<Crossing>,
    pulled_out: Option<Crossing>,
    penetration: Option<Crossing>,
    capacity: Option<Crossing>,
    /// Scratch of [`Monitor::excesses`]: each support's joist length
    /// between its pivot and its box \[m\], and its angle's sine and cosine.
    reach: Vec<f64>,
    turned: Vec<Option<(f64, f64)>>,
}

impl Monitor {
    /// A monitor of a joint model built from `config` (None without the
    /// joint).
    pub fn new(model: &JointModel, asm: &Assembly, config: &Config) -> Result<Option<Self>, ModelError> {
        let j = &config.joint;
        let Some(geometry) = model.geometry.clone() else { return Ok(None) };
        let coord = |b: BodyId, c: Coord| {
            asm.coordinate(b, c).ok_or_else(|| ModelError::Geometry(format!("body {} lacks a coordinate", b.index())))
        };
        let mut bearings = Vec::new();
        for (i, row) in model.bearings.iter().enumerate() {
            for (k, &b) in row.iter().enumerate() {
                let phi = match geometry.supports[k].kind {
                    SupportKind::Joist => Some(coord(model.supports[k], Coord::Phi)?),
                    SupportKind::Guide => None,
                };
                bearings.push(Bearing { x: coord(b, Coord::X)?, y: coord(b, Coord::Y)?, support: k, phi, beam: i + 1 });
            }
        }
        Ok(Some(Self {
            geometry,
            joist_length: j.support_beam.length,
            max_penetration: j.contact.enabled.then_some(j.contact.max_penetration),
            max_subgap: j.capacity.max_subgap,
            bearings,
            deck_y: asm.coordinate(model.deck, Coord::Y),
            far: model.far_deck.and_then(|b| asm.coordinate(b, Coord::X)),
            contact_places: model.contacts.clone(),
            edge_free: false,
            released: None,
            collision: None,
            off_support: None,
            pulled_out: None,
            penetration: None,
            capacity: None,
            reach: Vec::new(),
            turned: Vec::new(),
        }))
    }

    /// The abutment's edge beam broke free (its fuse): its cell's opening
    /// no longer counts against the capacity.
    pub fn free_edge(&mut self) {
        self.edge_free = true;
    }

    /// A fuse element's `beam` (1 to `Nc`) left the plane at `t` \[s\]:
    /// the findings after it name its merged cell.
    pub fn release_beam(&mut self, beam: usize, t: f64) {
        self.released = Some((beam, t));
    }

    /// Cell `s` (0 at the abutment) at `t` \[s\] in words: the two sides it
    /// lies between, or, once a fuse element's beam left the plane, its
    /// merged cell's.
    fn cell(&self, s: usize, t: f64) -> String {
        crate::generator::cell_words(s, self.geometry.center_beams, self.released, t)
    }

    /// Checks a contact's penetration `depth` \[m\] at `t` (contact number
    /// `place` of [`JointModel::contacts`]).
    pub fn contact(&mut self, t: f64, depth: f64, place: usize) {
        if let Some(max) = self.max_penetration {
            if depth > max {
                Crossing::update(&mut self.penetration, t, depth, place);
            }
        }
    }

    /// Checks one output time: positions `q`, deck opening `u`, the clear
    /// sub-gaps (abutment side first) at their narrower end `subgaps` and
    /// at their wider end `largest`.
    pub fn sample(&mut self, t: f64, q: &[f64], u: f64, subgaps: &[f64], largest: &[f64]) {
        for (limit, (excess, place)) in self.excesses(q, u, subgaps, largest).into_iter().enumerate() {
            if excess > 0.0 {
                Crossing::update(self.slot(limit), t, excess, place);
            }
        }
    }

    /// A limit crossed at `t` as the dense output locates it, between the
    /// samples (`excess` \[m\] just after, at `place`): the crossing starts
    /// there, or earlier than its first sample.
    pub(crate) fn crossed(&mut self, limit: usize, t: f64, excess: f64, place: usize) {
        match self.slot(limit) {
            Some(c) => c.first = c.first.min(t),
            slot => Crossing::update(slot, t, excess.max(0.0), place),
        }
    }

    fn slot(&mut self, limit: usize) -> &mut Option<Crossing> {
        match limit {
            0 => &mut self.collision,
            1 => &mut self.capacity,
            2 => &mut self.off_support,
            _ => &mut self.pulled_out,
        }
    }

    /// Each limit's largest excess \[m\] (positive: crossed; negative:
    /// the margin left) with its place, at positions `q`, deck opening `u`
    /// and the sub-gaps `subgaps` (narrower ends) and `largest` (wider
    /// ends), in the order of [`LIMITS`]; a limit with no place to cross
    /// (a collision where contacts act, no joist) is (-1 m, 0).
    pub(crate) fn excesses(&mut self, q: &[f64], u: f64, subgaps: &[f64], largest: &[f64]) -> [(f64, usize); LIMITS] {
        let mut out = [(f64::NEG_INFINITY, 0); LIMITS];
        let mut take = |limit: usize, excess: f64, place: usize| {
            if excess > out[limit].0 {
                out[limit] = (excess, place);
            }
        };
        if self.max_penetration.is_none() {
            for (s, &gap) in subgaps.iter().enumerate() {
                take(0, -gap, s);
            }
        }
        // (a fuse element's merged cell: two cells' capacities and the
        // place of the beam that left, half of it each)
        let width = self.geometry.width;
        for (s, &gap) in largest.iter().enumerate().skip(usize::from(self.edge_free)) {
            let merged = self.released.is_some_and(|(k, _)| crate::generator::beside(k, s));
            let place = if merged { 0.5 * width } else { 0.0 };
            take(1, gap - self.max_subgap - place, s);
        }
        let g = &self.geometry;
        let uy = self.deck_y.map_or(0.0, |c| q[c]);
        // the opening between the pivots' side (abutment or adjacent segment) and the deck
        let u0 = self.far.map_or(0.0, |c| q[c]);
        let open = g.gap + u - u0;
        // each joist's length between its pivot and its box (deck) end, and
        // its angle's sine and cosine, once per support (its bearings share
        // them)
        let (reach, turned) = (&mut self.reach, &mut self.turned);
        reach.clear();
        reach.extend(g.supports.iter().map(|sup| open.hypot(sup.box_dy + uy)));
        turned.clear();
        turned.resize(g.supports.len(), None);
        for (n, b) in self.bearings.iter().enumerate() {
            let sup = &g.supports[b.support];
            // distance along the support from its pivot (abutment) end, and
            // the length between the pivot and the box (deck) end
            let (along, reach) = match b.phi {
                Some(phi) => {
                    let (sin, cos) = *turned[b.support].get_or_insert_with(|| q[phi].sin_cos());
                    ((q[b.x] - u0) * cos + (q[b.y] - sup.y0) * sin, reach[b.support])
                }
                None => (q[b.x] - u0, open),
            };
            take(2, (-along).max(along - reach), n);
        }
        for (k, sup) in g.supports.iter().enumerate() {
            if sup.kind == SupportKind::Joist {
                take(3, reach[k] - self.joist_length, k);
            }
        }
        for o in &mut out {
            if o.0 == f64::NEG_INFINITY {
                *o = (-1.0, 0);
            }
        }
        out
    }

    /// The validity of the run so far, with its energy balance error.
    pub fn validity(&self, energy_error: f64) -> Validity {
        let mut v = Validity::default();
        if let Some(c) = self.collision {
            v.flags |= Flags::COLLISION;
            let between = self.cell(c.place, c.at);
            v.findings.push(format!(
                "collision: the clear sub-gap between {between} reached {:.1} mm at t = {:.3} s (first below zero at \
                 t = {:.3} s); joint.contact.enabled = false, so the beams overlap",
                -c.worst * 1e3,
                c.at,
                c.first
            ));
        }
        if let Some(c) = self.off_support {
            v.flags |= Flags::BEARING_OFF_SUPPORT;
            let b = &self.bearings[c.place];
            v.findings.push(format!(
                "bearing_off_support: the bearing of center beam {} on joint.support_beams[{}] was {:.1} mm beyond \
                 its support beam's span at t = {:.3} s (first at t = {:.3} s)",
                b.beam,
                b.support,
                c.worst * 1e3,
                c.at,
                c.first
            ));
        }
        if let Some(c) = self.pulled_out {
            v.flags |= Flags::JOIST_PULLED_OUT;
            v.findings.push(format!(
                "joist_pulled_out: joint.support_beams[{}] reached {:.3} m beyond its length {} m from pivot to box at \
                 t = {:.3} s (first at t = {:.3} s)",
                c.place, c.worst, self.joist_length, c.at, c.first
            ));
        }
        if let (Some(c), Some(max)) = (self.penetration, self.max_penetration) {
            v.flags |= Flags::PENETRATION;
            let place = self.contact_places.get(c.place).map_or_else(String::new, |p| {
                let end = if p.end == 0 { "y = -L/2" } else { "y = +L/2" };
                format!("{} (end {end})", self.cell(p.gap, c.at))
            });
            v.findings.push(format!(
                "penetration: the contact between {place} reached {:.1} mm at t = {:.3} s (first beyond {:.1} mm at \
                 t = {:.3} s): the beams would be crushed, which the compliant contact does not model",
                c.worst * 1e3,
                c.at,
                max * 1e3,
                c.first
            ));
        }
        if let Some(c) = self.capacity {
            v.flags |= Flags::CAPACITY_EXCEEDED;
            let between = self.cell(c.place, c.at);
            // (a merged cell's half has its share of the beam's place)
            let merged = self.released.is_some_and(|(k, at)| c.at >= at && crate::generator::beside(k, c.place));
            let capacity = self.max_subgap + if merged { 0.5 * self.geometry.width } else { 0.0 };
            v.findings.push(format!(
                "capacity_exceeded: the clear sub-gap between {between} opened to {:.1} mm at t = {:.3} s, {:.1} mm \
                 beyond the capacity of {:.0} mm (joint.capacity.max_subgap{}; first at t = {:.3} s)",
                (capacity + c.worst) * 1e3,
                c.at,
                c.worst * 1e3,
                capacity * 1e3,
                if merged { " and half the width of the beam that left" } else { "" },
                c.first
            ));
        }
        if energy_error.is_nan() || energy_error > ENERGY_TOLERANCE {
            v.flags |= Flags::ENERGY_BALANCE;
            v.findings.push(format!(
                "energy_balance: the energy balance error is {energy_error:.2e} of the earthquake's work (above \
                 {ENERGY_TOLERANCE:e}): the run is not converged; tighten simulation.rtol and atol"
            ));
        }
        v
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_energy_balance_that_does_not_close_is_flagged() {
        let model = crate::generator::build(&crate::Config::default(), None, crate::generator::Drive::None).unwrap();
        let asm = Assembly::new(&model.system, &Default::default()).unwrap();
        let m = Monitor::new(&model, &asm, &crate::Config::default()).unwrap().unwrap();
        assert!(m.validity(1e-8).flags.is_ok());
        assert!(m.validity(ENERGY_TOLERANCE * 0.99).flags.is_ok());
        for bad in [ENERGY_TOLERANCE * 1.01, f64::NAN] {
            let v = m.validity(bad);
            assert_eq!(v.flags, Flags::ENERGY_BALANCE, "{bad}");
            assert!(v.findings[0].starts_with("energy_balance:"), "{:?}", v.findings);
        }
    }

    #[test]
    fn flags_name_themselves() {
        let mut f = Flags::OK;
        assert_eq!(f.label(), "ok");
        f |= Flags::COLLISION;
        f |= Flags::ENERGY_BALANCE;
        assert_eq!(f.label(), "collision+energy_balance");
        assert_eq!(f.0, 9);
        assert!(Flags::legend().contains("1 collision") && Flags::legend().contains("8 energy_balance"));
        assert!(!Flags::NOT_CHECKED.is_ok() && !Flags::NOT_CHECKED.is_flagged());
        assert!(Flags(Flags::NOT_CHECKED.0 | 1).is_flagged());
    }
}
