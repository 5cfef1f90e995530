//! A linear bridge given by its modes: the modes file (docs/bridge.md,
//! "The modes file") and what a run takes from it.
//!
//! Each mode `i` is a coordinate `q_i` of
//! `q_i'' + 2 zeta_i w_i q_i' + w_i^2 q_i = -Gamma_i a_g + sum_p phi_ip F_p`
//! with mass-normalised shapes `phi_ip` at the file's points and the
//! participation factors `Gamma_i = phi_i^T M r`; a point moves by
//! `u_p = sum_i phi_ip q_i` relative to the ground.

use std::sync::Arc;

use quakejoint_solver::{
    Assembly, Body, BodyId, Constraint, ConstraintId, Coord, CoordinateSpring, ForceElement, Linear, System, Workspace,
};

use crate::config::ModalConfig;
use crate::described::{described, Described};
use crate::error::ModelError;

mod residual;
mod superposition;

pub use crate::config::modes::{
    Direction, ModalBridge, ModalPoint, Mode, StaticResponse, COMPLETE_MASS_RATIO, COMPLETE_SUM_TOLERANCE, FORMAT,
    MAX_MAGNITUDE, MAX_MASS_RATIO, MAX_RIGID_SUM, MIN_PERIOD, MIN_RIGID_SUM,
};
pub use residual::{PseudoMode, StaticCorrection};
pub use superposition::{modal_superposition, ModalAlone};

impl ModalBridge {
    /// The modes a run keeps: the `count` longest periods (all if none),
    /// in order of decreasing period, each period times `period_scale`
    /// (stiffness scaled, masses kept), with the damping ratio `damping`
    /// where the file gives none.
    pub fn kept(&self, count: Option<usize>, period_scale: f64, damping: f64) -> Vec<KeptMode> {
        let mut order: Vec<usize> = (0..self.modes.len()).collect();
        // (stable: equal periods keep the file's order)
        order.sort_by(|&a, &b| self.modes[b].period.total_cmp(&self.modes[a].period));
        order.truncate(count.unwrap_or(usize::MAX));
        order
            .into_iter()
            .map(|i| {
                let m = &self.modes[i];
                KeptMode {
                    index: i,
                    omega: 2.0 * std::f64::consts::PI / (m.period * period_scale),
                    damping: m.damping.unwrap_or(damping),
                    gamma: [m.participation_x, m.participation_y],
                    shape: m.shape.clone(),
                }
            })
            .collect()
    }

    /// The sum of the kept modes' effective masses `Gamma_x^2` over
    /// `total_mass_x` [-] (none when the file gives no total).
    pub fn mass_ratio_x(&self, kept: &[KeptMode]) -> Option<f64> {
        self.total_mass_x.map(|m| kept.iter().map(|k| k.gamma[0] * k.gamma[0]).sum::<f64>() / m)
    }
}

/// A mode as a run uses it.
#[derive(Debug, Clone, PartialEq)]
pub struct KeptMode {
    /// Its index in the file.
    pub index: usize,
    /// Circular frequency [rad/s].
    pub omega: f64,
    /// Damping ratio [-].
    pub damping: f64,
    /// Participation factors along x and y \[kg^0.5\].
    pub gamma: [f64; 2],
    /// Mass-normalised shape at the file's points \[kg^-0.5\].
    pub shape: Vec<f64>,
}

/// The modes file read with `[bridge.modal]`, shared.
pub fn loaded_arc(m: &ModalConfig) -> Result<std::sync::Arc<ModalBridge>, ModelError> {
    m.loaded.clone().ok_or_else(|| not_read(m))
}

/// The modes file read with `[bridge.modal]`.
pub fn loaded(m: &ModalConfig) -> Result<&ModalBridge, ModelError> {
    m.loaded.as_deref().ok_or_else(|| not_read(m))
}

fn not_read(m: &ModalConfig) -> ModelError {
    ModelError::Invalid {
        field: "bridge.modal.modes".to_string(),
        value: format!("\"{}\"", m.modes),
        reason: "the modes file was not read with the config (Config::from_file or Config::load_modes)".to_string(),
    }
}

/// A mode as a body of the solver system: its coordinate `y = s q` is the
/// mode's largest displacement at the file's points \[m\] (`s` the largest
/// `|phi|`, at least [`MIN_COORDINATE_SCALE`] of the largest mode's), so its mass is `1/s^2` \[kg\], its spring `w^2/s^2` \[N/m\], its
/// damper `2 zeta w/s^2` \[N s/m\] and the ground acts on `Gamma/s` \[kg\].
#[derive(Debug, Clone, PartialEq)]
pub struct ModalBody {
    /// The body.
    pub body: BodyId,
    /// Mass \[kg\].
    pub mass: f64,
    /// Spring \[N/m\].
    pub stiffness: f64,
    /// Damper \[N s/m\].
    pub damper: f64,
    /// The mass the ground's acceleration along x acts on \[kg\].
    pub base_mass: f64,
    /// The mass the ground's acceleration across acts on \[kg\].
    pub base_mass_y: f64,
    /// Each point's displacement per unit of `y` [-], `phi_p / s`, in the
    /// modes file's order.
    pub at_point: Vec<f64>,
    /// A pseudo-mode of the static correction ([`StaticCorrection`]): its
    /// displacement counts at the points, its acceleration (of a light
    /// mass standing for none) and base shear do not.
    pub pseudo: bool,
}

/// A point of the modes file a joint moves with: a body in x whose
/// coordinate is the point's displacement in the joint's own x (`sign`
/// times the bridge's), tied to the modes by a linear constraint.
#[derive(Debug, Clone, PartialEq)]
pub struct ModalEnd {
    /// The body.
    pub body: BodyId,
    /// `u - sign sum_i (phi_ip / s_i) y_i = 0`; its multiplier is the
    /// force the end passes to the modes in the joint's x \[N\].
    pub link: ConstraintId,
    /// The point, in the modes file's order.
    pub point: usize,
    /// +1, or -1 for a joint turned half a turn.
    pub sign: f64,
    /// The point across the bridge its y moves with, and the link that ties
    /// it (`u_y - sign sum_i (phi_ip / s_i) y_i = 0`); none: the end does
    /// not move across.
    pub across: Option<(usize, ConstraintId)>,
}

/// The modes in the solver system and the points the joints move with.
#[derive(Debug, Clone, PartialEq)]
pub struct ModalParts {
    /// The modes.
    pub modes: Vec<ModalBody>,
    /// The joints' points.
    pub ends: Vec<ModalEnd>,
    /// At each point of the modes file, the static correction's
    /// displacement per unit ground acceleration along x beyond its
    /// pseudo-modes ([`StaticCorrection::ground`]; empty without the
    /// correction) \[s^2\].
    pub ground: Vec<f64>,
}

/// A joint's view of the modes: all of them and which end is its deck.
#[derive(Debug, Clone, PartialEq)]
pub struct ModalDeck {
    /// The modes and every end.
    pub parts: Arc<ModalParts>,
    /// Which of `parts.ends` is this joint's deck side.
    pub end: usize,
}

/// The deck end's own mass, relative to the kept modes' effective mass
/// along x [-]. The modes hold all of the bridge's mass; the deck end needs
/// a mass only to be a body, and at 1e-6 of the bridge's it changes the
/// response by about as much, below the integrator's tolerances. Much less
/// leaves its block of the iteration matrix below the block elimination's
/// pivot threshold: at 1e-9 the reference joint's factorisations fell back
/// to faer's sparse LU and a run took 40 times longer
/// (`modal_joints::reference_joint_factorises_in_blocks` checks it).
pub const DECK_END_MASS_RATIO: f64 = 1e-6;

/// The smallest coordinate scale of a mode, relative to the largest
/// among the kept modes [-]. A mode's coordinate is its displacement at
/// the point it moves most ([`ModalBody`]); a mode that hardly moves any
/// point of the file (a vertical mode of a planar frame moves the points
/// along x by 1e-13 per unit) would get a mass of 1e26 kg and make the
/// iteration matrix singular. Its coordinate is scaled up to this
/// fraction of the largest mode's instead: its mass stays within 1e6 of
/// the others', and its displacement is still its own (at its points,
/// `phi / s` is small).
pub const MIN_COORDINATE_SCALE: f64 = 1e-3;

/// A joint's end to tie to the modes: its name, its point along x, its
/// point across (if it moves across) and its sign.
#[derive(Debug, Clone)]
pub struct EndSpec {
    /// The body's name.
    pub name: String,
    /// Its point along x.
    pub point: usize,
    /// Its point across, if it moves across.
    pub point_y: Option<usize>,
    /// +1, or -1 for a joint turned half a turn.
    pub sign: f64,
}

/// Adds the kept modes, the static correction's pseudo-modes (if any) and
/// one end per [`EndSpec`] to `sys` (the ends' bodies first).
pub fn add_modes(
    sys: &mut System,
    kept: &[KeptMode],
    correction: Option<&StaticCorrection>,
    ends: &[EndSpec],
) -> ModalParts {
    let effective: f64 = kept.iter().map(|k| k.gamma[0] * k.gamma[0]).sum();
    let largest: Vec<f64> = kept.iter().map(|k| k.shape.iter().fold(0.0f64, |m, v| m.max(v.abs()))).collect();
    let floor = MIN_COORDINATE_SCALE * largest.iter().copied().fold(0.0f64, f64::max);
    let scales: Vec<f64> = largest
        .iter()
        .map(|&s| {
            if s > floor {
                s
            } else if floor > 0.0 {
                floor
            } else {
                1.0
            }
        })
        .collect();
    let fallback: f64 = scales.iter().map(|s| 1.0 / (s * s)).sum();
    let end_mass = DECK_END_MASS_RATIO * if effective > 0.0 { effective } else { fallback };
    let bodies: Vec<BodyId> = ends
        .iter()
        .map(|e| {
            let coords: &[Coord] = if e.point_y.is_some() { &[Coord::X, Coord::Y] } else { &[Coord::X] };
            let body = Body::new(e.name.clone(), end_mass, 1.0, [0.0; 3]).only(coords);
            let m = e.sign * end_mass;
            sys.add_body(if e.sign < 0.0 { body.with_base_mass([[m, 0.0], [0.0, m]]) } else { body })
        })
        .collect();
    let mut modes = Vec::with_capacity(kept.len());
    for (k, s) in kept.iter().zip(scales) {
        let body = sys.add_body(
            Body::new(format!("mode {}", k.index + 1), 1.0 / (s * s), 1.0, [0.0; 3])
                .only(&[Coord::X])
                .with_base_mass([[k.gamma[0] / s, k.gamma[1] / s], [0.0, 0.0]]),
        );
        let m = ModalBody {
            body,
            mass: 1.0 / (s * s),
            stiffness: k.omega * k.omega / (s * s),
            damper: 2.0 * k.damping * k.omega / (s * s),
            base_mass: k.gamma[0] / s,
            base_mass_y: k.gamma[1] / s,
            at_point: k.shape.iter().map(|phi| phi / s).collect(),
            pseudo: false,
        };
        add_spring(sys, &m, format!("mode {} spring and damper", k.index + 1));
        modes.push(m);
    }
    for (i, p) in correction.map_or(&[][..], |c| &c.pseudo[..]).iter().enumerate() {
        // (its coordinate: the largest displacement at a point, as a mode's;
        // its mass as light as a deck end's)
        let s = p.shape.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        let s = if s > 0.0 { s } else { 1.0 };
        let body = sys.add_body(
            Body::new(format!("static correction {}", i + 1), end_mass, 1.0, [0.0; 3])
                .only(&[Coord::X])
                .with_base_mass([[p.base_mass / s, 0.0], [0.0, 0.0]]),
        );
        // (critically damped: a light mass standing for none settles within
        // 2 / w of its spring's static answer, w = sqrt(k / m) thousands of
        // rad/s, and adds nothing that rings)
        let stiffness = p.stiffness / (s * s);
        let m = ModalBody {
            body,
            mass: end_mass,
            stiffness,
            damper: 2.0 * (stiffness * end_mass).sqrt(),
            base_mass: p.base_mass / s,
            base_mass_y: 0.0,
            at_point: p.shape.iter().map(|v| v / s).collect(),
            pseudo: true,
        };
        add_spring(sys, &m, format!("static correction {} spring", i + 1));
        modes.push(m);
    }
    let ends = ends
        .iter()
        .zip(bodies)
        .map(|(e, body)| {
            let mut link = |coord: Coord, point: usize, what: &str| {
                let mut terms = vec![(body, coord, 1.0)];
                terms.extend(modes.iter().map(|m| (m.body, Coord::X, -e.sign * m.at_point[point])));
                sys.add_constraint_named(format!("{}{what} on the modes", e.name), Constraint::Linear(Linear { terms }))
            };
            let x = link(Coord::X, e.point, "");
            let across = e.point_y.map(|p| (p, link(Coord::Y, p, " across")));
            ModalEnd { body, link: x, point: e.point, sign: e.sign, across }
        })
        .collect();
    ModalParts { modes, ends, ground: correction.map_or_else(Vec::new, |c| c.ground.clone()) }
}

/// A mode's (or pseudo-mode's) spring and damper to the ground.
fn add_spring(sys: &mut System, m: &ModalBody, name: String) {
    sys.add_force_named(
        name,
        ForceElement::CoordinateSpring(CoordinateSpring {
            body: m.body,
            coord: Coord::X,
            stiffness: m.stiffness,
            damping: m.damper,
            rest: 0.0,
        }),
    );
}

impl ModalParts {
    /// Each mode's acceleration `y''` \[m/s^2\] at the state `(q, v)` with
    /// the ground's acceleration `ag` (x, y) \[m/s^2\], from its equation with the
    /// forces every end passes to it (their links' multipliers, from the
    /// links' reactions on the ends), into `out`; `forces` is scratch.
    pub fn accelerations(
        &self,
        asm: &Assembly,
        ws: &mut Workspace,
        at: Instant<'_>,
        forces: &mut Vec<(usize, f64)>,
        out: &mut Vec<f64>,
    ) {
        let Instant { t, q, v, lam, ag } = at;
        // (the force each link passes to the modes, at its point)
        forces.clear();
        for e in &self.ends {
            forces.push((e.point, -e.sign * asm.reaction_sum(ws, t, q, lam, &[e.link], e.body)[0]));
            if let Some((p, link)) = e.across {
                forces.push((p, -e.sign * asm.reaction_sum(ws, t, q, lam, &[link], e.body)[1]));
            }
        }
        out.clear();
        for m in &self.modes {
            let c = asm.coordinate(m.body, Coord::X).expect("a mode's x is free");
            let ends: f64 = forces.iter().map(|&(p, f)| m.at_point[p] * f).sum();
            let ground = m.base_mass * ag[0] + m.base_mass_y * ag[1];
            out.push((-m.stiffness * q[c] - m.damper * v[c] - ground + ends) / m.mass);
        }
    }

    /// Point `p`'s displacement, velocity (relative to the ground, along the
    /// bridge's x) \[m, m/s\] and absolute acceleration \[m/s^2\], with the
    /// modes' accelerations `acc` ([`ModalParts::accelerations`]) and the
    /// ground's acceleration `ag` in the point's direction. The static
    /// correction's accelerations are not counted: it is static.
    pub fn point(&self, asm: &Assembly, p: usize, q: &[f64], v: &[f64], acc: &[f64], ag: f64) -> [f64; 3] {
        let mut out = [self.ground.get(p).map_or(0.0, |g| g * ag), 0.0, ag];
        for (m, a) in self.modes.iter().zip(acc) {
            let c = asm.coordinate(m.body, Coord::X).expect("a mode's x is free");
            let phi = m.at_point[p];
            out[0] += phi * q[c];
            out[1] += phi * v[c];
            if !m.pseudo {
                out[2] += phi * a;
            }
        }
        out
    }
}

/// A state of the solver system at one time.
#[derive(Debug, Clone, Copy)]
pub struct Instant<'a> {
    /// Time \[s\].
    pub t: f64,
    /// Positions.
    pub q: &'a [f64],
    /// Velocities.
    pub v: &'a [f64],
    /// Multipliers.
    pub lam: &'a [f64],
    /// The ground's acceleration along x and y \[m/s^2\].
    pub ag: [f64; 2],
}

/// The peaks at one point of the modes file over a run (SI units).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct PointPeaks {
    /// The point's name.
    pub name: String,
    /// Peak displacement relative to the ground along the bridge \[m\].
    pub sd: f64,
    /// Time of `sd` \[s\].
    pub t_sd: f64,
    /// Peak absolute acceleration along the bridge \[m/s^2\].
    pub sa: f64,
    /// Time of `sa` \[s\].
    pub t_sa: f64,
    /// `sd` of the bridge alone (exact modal superposition) \[m\].
    pub sd_without: f64,
    /// `sa` of the bridge alone \[m/s^2\].
    pub sa_without: f64,
}

/// A point's values, in the order of [`PointPeaks::scalars`].
pub const POINT_FIELDS: [Described; 6] = [
    described("sd", "m", "peak displacement relative to the ground along the bridge, with the joints"),
    described("t_sd", "s", "time of `sd` (NaN for `--no-joint`)"),
    described("sa", "m/s^2", "peak absolute acceleration along the bridge, with the joints"),
    described("t_sa", "s", "time of `sa` (NaN for `--no-joint`)"),
    described("sd_without_joint", "m", "`sd` of the bridge alone (exact modal superposition of the kept modes)"),
    described("sa_without_joint", "m/s^2", "`sa` of the bridge alone"),
];

impl PointPeaks {
    /// Its peaks ([`POINT_FIELDS`]): name, value and unit, as every output
    /// lists a point's (a run file's `/points/<name>`, JSON, Python).
    pub fn scalars(&self) -> [(&'static str, f64, &'static str); 6] {
        let values = [self.sd, self.t_sd, self.sa, self.t_sa, self.sd_without, self.sa_without];
        std::array::from_fn(|i| (POINT_FIELDS[i].name, values[i], POINT_FIELDS[i].units))
    }
}

impl ModalParts {
    /// The base shear along the bridge \[N\]: the kept modes' elastic and
    /// damping forces summed over the supports,
    /// `sum_i Gamma_i (w_i^2 q_i + 2 zeta_i w_i q_i')` (in the bodies' units
    /// `sum_i (Gamma_i / s_i) (k_i y_i + c_i y_i') / m_i`), at the state
    /// `(q, v)`. The static correction's pseudo-modes are not counted.
    pub fn base_shear(&self, asm: &Assembly, q: &[f64], v: &[f64]) -> f64 {
        self.modes
            .iter()
            .filter(|m| !m.pseudo)
            .map(|m| {
                let c = asm.coordinate(m.body, Coord::X).expect("a mode's x is free");
                m.base_mass * (m.stiffness * q[c] + m.damper * v[c]) / m.mass
            })
            .sum()
    }
}

/// How much of the bridge the kept modes hold: the check of how many modes
/// are enough (docs/bridge.md, "How many modes").
#[derive(Debug, Clone, Default, PartialEq)]
pub struct ModeCheck {
    /// The kept modes' effective mass along x over `total_mass_x` [-] (none
    /// without a total in the file).
    pub mass_ratio: Option<f64>,
    /// At each point of the file, the kept modes' share of the full model's
    /// static flexibility there, `sum_kept phi_p^2 / w^2` over
    /// `static.flexibility[p][p]` [-] (NaN without a `[static]` table): how
    /// well the kept modes let a joint's force move its point.
    pub flexibility: Vec<f64>,
    /// For each pair `(p, q)` of the joints' points, the kept modes' share of
    /// the flexibility between them, `sum_kept (phi_p - phi_q)^2 / w^2`
    /// over `F_pp + F_qq - 2 F_pq` [-]: how well they let two joints'
    /// opposite forces stretch or squeeze the deck between them (NaN
    /// without a `[static]` table).
    pub between: Vec<(usize, usize, f64)>,
}

/// Below this share of the mass or of a joint point's flexibility, a run
/// warns that more modes are needed [-].
pub const ENOUGH: f64 = 0.9;

impl ModalBridge {
    /// How much of the bridge the `kept` modes hold (`joints`: the joints'
    /// points, for the flexibility between them).
    pub fn mode_check(&self, kept: &[KeptMode], joints: &[usize]) -> ModeCheck {
        let full = |p: usize, q: usize| {
            self.static_response.as_ref().and_then(|s| s.flexibility.get(p).and_then(|row| row.get(q).copied()))
        };
        let mut between = Vec::new();
        for (i, &p) in joints.iter().enumerate() {
            for &q in &joints[i + 1..] {
                let share = match (full(p, p), full(q, q), full(p, q)) {
                    (Some(a), Some(b), Some(c)) if a + b - 2.0 * c > 0.0 => {
                        kept.iter().map(|k| (k.shape[p] - k.shape[q]).powi(2) / (k.omega * k.omega)).sum::<f64>()
                            / (a + b - 2.0 * c)
                    }
                    _ => f64::NAN,
                };
                between.push((p, q, share));
            }
        }
        let flexibility = (0..self.points.len())
            .map(|p| {
                let full = self.static_response.as_ref().and_then(|s| s.flexibility.get(p).map(|row| row[p]));
                match full {
                    Some(f) if f > 0.0 => {
                        kept.iter().map(|k| k.shape[p] * k.shape[p] / (k.omega * k.omega)).sum::<f64>() / f
                    }
                    _ => f64::NAN,
                }
            })
            .collect();
        ModeCheck { mass_ratio: self.mass_ratio_x(kept), flexibility, between }
    }
}

impl ModeCheck {
    /// Warnings for the joints' points `points` (indices) where the kept
    /// modes hold less than [`ENOUGH`], and for the mass. With the static
    /// correction on (`corrected`) the joints' points hold the full model's
    /// static flexibility and only the mass is warned about; a run without
    /// the joints' forces (`joints_act` false: the bridge alone) needs no
    /// flexibility at their points.
    pub fn warnings(&self, bridge: &ModalBridge, points: &[usize], corrected: bool, joints_act: bool) -> Vec<String> {
        let mut out = Vec::new();
        if let Some(r) = self.mass_ratio.filter(|&r| r < ENOUGH) {
            out.push(format!(
                "the kept modes hold {:.1} % of the bridge's mass along x (bridge.modal.modes_used): the ground \
                 motion excites the rest",
                r * 100.0
            ));
        }
        for &p in points {
            let point = &bridge.points[p];
            let sum: f64 = bridge.modes.iter().map(|m| m.participation_x * m.shape[p]).sum();
            if point.direction == Direction::X && !(0.6..=1.6).contains(&sum) {
                out.push(format!(
                    "at \"{}\" the file's modes give sum(participation_x shape) = {sum:.3}: 1 with every mode, 0.6 to \
                     1.6 with the lower ones; check that the shapes are mass-normalised and the participations \
                     follow them (docs/bridge.md, \"What the numbers are\")",
                    point.name
                ));
            }
        }
        if !joints_act {
            return out;
        }
        if corrected {
            if bridge.static_response.as_ref().is_some_and(|s| s.ground_x.is_empty()) {
                out.push(
                    "the modes file's [static] table has no ground_x: the static correction adds the flexibility of \
                     the modes left out but not their static response to the ground motion"
                        .to_string(),
                );
            }
            return out;
        }
        for &p in points {
            let f = self.flexibility[p];
            if f < ENOUGH {
                out.push(format!(
                    "at \"{}\" the kept modes hold {:.1} % of the static flexibility: the joint's force moves that \
                     point less than the full model would (keep more modes: bridge.modal.modes_used)",
                    bridge.points[p].name,
                    f * 100.0
                ));
            }
        }
        for &(p, q, f) in &self.between {
            if f < ENOUGH {
                out.push(format!(
                    "between \"{}\" and \"{}\" the kept modes hold {:.1} % of the static flexibility: joints \
                     pushing the deck from both ends stretch or squeeze it less than the full model would (keep \
                     more modes: bridge.modal.modes_used)",
                    bridge.points[p].name,
                    bridge.points[q].name,
                    f * 100.0
                ));
            }
        }
        out
    }
}
