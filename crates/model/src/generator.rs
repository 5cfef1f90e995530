//! Builds the solver system of a swivel-joist joint on a single-DOF bridge.
//!
//! Bodies: `Nc` center beams, `Ns` support beams, `Nc * Ns` bearings (the
//! joint), plus the deck, a body restricted to x whose coordinate is the
//! opening `u`. Force elements: a bushing and a friction element per bearing,
//! the bridge spring and damper on `u`, and, unless `joint.contact.enabled`
//! is false, a contact at each end of each sub-gap (2 (Nc + 1)): the corner
//! of the beam on the abutment side against the face of the next beam (the
//! abutment's edge beam is a line on the ground, the deck's a line on the
//! deck); for the small yaw angles of the beams the gap at an end is the
//! same to first order whichever beam's corner is taken. Constraints: a
//! sliding joint per bearing on its support beam ([`BearingJoint`]: by
//! default the bearing translates only and stays on the beam's axis, its
//! rotation carried by the beam), a revolute joint per joist pivot, a
//! point-on-line per joist box (the deck point `(G0 + u, y_box)` on the
//! joist axis), a weld per guide. The earthquake acts as `-m a_g(t)` on every
//! body (x), optionally `-m a_gy(t)` on the joint bodies (y).

use quakejoint_solver::{
    Body, BodyId, Bushing, ConstraintId, ContactLaw, Coord, CoordinateSpring, Driver, Excitation, ForceElement,
    Friction, FrictionLaw, PointOnLine, Prismatic, Revolute, SmoothTriangle, System, TimeFunction, TimeSeries, Weld,
    NO_GROUP,
};

use crate::cells::{cell_contact, CellBodies, Side};
use crate::config::{Config, ContactLawConfig, FuseKind, LawConfig, SupportKind};
use crate::error::ModelError;
use crate::geometry::Geometry;
use crate::modal::{add_modes, EndSpec, ModalDeck};
use crate::scenario::Scenario;

/// How a bearing's sliding joint on its support beam is written
/// (`docs/model.md`, "Constraints").
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum BearingJoint {
    /// The bearing translates only (x, y). The prismatic joint makes its
    /// rotation that of its support beam, so its moment of inertia is carried
    /// by the support beam, and the joint keeps the bearing's centre on the
    /// beam's axis (1 equation). Exact for this model, where no element acts
    /// on a bearing's rotation (the bushing and the friction act at its
    /// centre): 2 coordinates and 1 equation per bearing instead of 3 and 2.
    #[default]
    Translational,
    /// The spec's prismatic joint: the bearing a full body (x, y, phi) whose
    /// angle equation keeps it parallel to its support beam.
    Prismatic,
}

/// How the deck is moved.
#[derive(Debug, Clone)]
pub enum Drive {
    /// No load (the reference state).
    None,
    /// Base excitation in x and optionally y [m/s^2].
    Earthquake {
        /// Ground acceleration along the bridge.
        x: TimeSeries,
        /// Ground acceleration across the bridge, on the joint bodies.
        y: Option<TimeSeries>,
    },
    /// The deck opening prescribed as a function of time \[m\].
    Service(SmoothTriangle),
}

/// The bridge as a single-DOF oscillator.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Bridge {
    /// Mass \[kg\].
    pub mass: f64,
    /// Circular frequency [rad/s].
    pub omega: f64,
    /// Damping ratio [-].
    pub damping: f64,
    /// Circular frequency [rad/s] and damping ratio [-] across the bridge,
    /// when the deck moves across.
    pub transverse: Option<(f64, f64)>,
    /// Mass \[kg\], circular frequency [rad/s] and damping ratio [-] of the
    /// adjacent segment on the abutment side, if there is one.
    pub far: Option<(f64, f64, f64)>,
}

impl Bridge {
    /// Spring stiffness `m w0^2` [N/m].
    pub fn stiffness(&self) -> f64 {
        self.mass * self.omega * self.omega
    }
    /// Damper `2 zeta m w0` [N s/m].
    pub fn damper(&self) -> f64 {
        2.0 * self.damping * self.mass * self.omega
    }
}

/// Where a contact of the joint sits.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub struct ContactPlace {
    /// The sub-gap, 0 (abutment's edge beam and center beam 1) to Nc
    /// (center beam Nc and the deck's edge beam).
    pub gap: usize,
    /// The end of the center beams: 0 at y = -L/2, 1 at y = +L/2.
    pub end: usize,
    /// The joint's number of center beams `Nc`.
    pub center_beams: usize,
}

impl ContactPlace {
    /// The sub-gap in words.
    pub fn describe(&self) -> String {
        self.describe_after(None, 0.0)
    }

    /// The sub-gap in words at `t` \[s\], once a fuse element's beam left
    /// the plane (`released`: the beam, 1 to `Nc`, and when \[s\]): its
    /// merged cell's sides.
    pub fn describe_after(&self, released: Option<(usize, f64)>, t: f64) -> String {
        let side = if self.end == 0 { "y = -L/2" } else { "y = +L/2" };
        format!("{} (end {side})", cell_words(self.gap, self.center_beams, released, t))
    }
}

/// Whether cell `gap` (0 at the abutment) is one of the two cells of
/// center beam `beam` (1 to `Nc`): one cell once a fuse element's beam
/// left the plane.
pub(crate) fn beside(beam: usize, gap: usize) -> bool {
    gap + 1 == beam || gap == beam
}

/// Cell `gap` (0 at the abutment) of a joint of `nc` center beams at `t`
/// \[s\] in words: the two sides it lies between, or, once a fuse
/// element's beam left the plane (`released`: the beam, 1 to `nc`, and
/// when \[s\]), its merged cell's.
pub fn cell_words(gap: usize, nc: usize, released: Option<(usize, f64)>, t: f64) -> String {
    let between = |l: usize, r: usize| match (l, r) {
        (0, r) if r > nc => "the abutment's edge beam and the deck's edge beam".to_string(),
        (0, r) => format!("the abutment's edge beam and center beam {r}"),
        (l, r) if r > nc => format!("center beam {l} and the deck's edge beam"),
        (l, r) => format!("center beams {l} and {r}"),
    };
    match released {
        Some((k, at)) if t >= at && beside(k, gap) => format!(
            "{} (one cell since center beam {k} left the plane at t = {at:.3} s, its sub-gaps each half of it)",
            between(k - 1, k + 1)
        ),
        _ => between(gap, gap + 1),
    }
}

/// The solver's law for the contact config.
fn contact_law(config: &Config) -> ContactLaw {
    let c = &config.joint.contact;
    match c.law {
        ContactLawConfig::Hertz => ContactLaw::Hertz {
            stiffness: c.hertz_stiffness,
            restitution: c.restitution,
            damping: crate::link::hertz_damping(c),
        },
        ContactLawConfig::Linear => ContactLaw::Linear { stiffness: c.linear_stiffness, restitution: c.restitution },
    }
}

/// Adds the contacts of every sub-gap, abutment side first, both ends of
/// each (a center beam's corner on its neighbour's face). `impacts`: the
/// mass an impact at the abutment's and at the deck's edge beam meets,
/// where it is not the reduced mass of the bodies (a modal end, an in-span
/// hinge's deck). Returns every contact's id, in the solver's order.
fn add_contacts(
    sys: &mut System,
    model: &mut JointModel,
    geo: &Geometry,
    law: ContactLaw,
    abutment: BodyId,
    impacts: [Option<f64>; 2],
    prefix: &str,
) -> Vec<quakejoint_solver::ForceId> {
    let nc = model.center_beams.len();
    let mut ids = Vec::with_capacity(2 * (nc + 1));
    let bodies = CellBodies { beams: &model.center_beams, deck: model.deck, abutment };
    let mut contacts = Vec::with_capacity(2 * (nc + 1));
    for gap in 0..=nc {
        let left = if gap == 0 { Side::Abutment } else { Side::Beam(gap - 1) };
        let right = if gap == nc { Side::Deck } else { Side::Beam(gap) };
        for (end, y) in [-geo.half_length, geo.half_length].into_iter().enumerate() {
            contacts.push((gap, end, cell_contact(&bodies, geo, (left, right), y, (law, impacts))));
        }
    }
    for (gap, end, contact) in contacts {
        ids.push(sys.add_force_named(format!("{prefix}contact {gap}/{end}"), ForceElement::Contact(contact)));
        model.contacts.push(ContactPlace { gap, end, center_beams: nc });
    }
    ids
}

/// Adds the bodies of the joint of `config` (`[joint]`) with their
/// bushings, friction elements and sliding joints to `sys`; `sign` -1
/// turns the joint half a turn about the vertical (its bodies then feel the
/// ground's acceleration reversed), `prefix` starts every name.
fn add_joint_bodies(
    sys: &mut System,
    model: &mut JointModel,
    config: &Config,
    bearing_joint: BearingJoint,
    sign: f64,
    prefix: &str,
) -> Result<(), ModelError> {
    let j = &config.joint;
    let geo = Geometry::new(config)?;
    let cb = &j.center_beam;
    let cb_inertia = cb.inertia();
    for (i, &x) in geo.center_x.iter().enumerate() {
        model.center_beams.push(sys.add_body(turned(
            Body::new(format!("{prefix}center beam {}", i + 1), cb.mass, cb_inertia, [x, 0.0, 0.0]),
            sign,
        )));
    }
    let sbc = &j.support_beam;
    let sb_inertia = sbc.inertia();
    for (k, s) in geo.supports.iter().enumerate() {
        let name = match s.kind {
            SupportKind::Guide => format!("{prefix}guide {k}"),
            SupportKind::Joist => format!("{prefix}joist {k}"),
        };
        // the bearings turning with the beam, when they are not bodies of their own
        let inertia = match bearing_joint {
            BearingJoint::Translational => sb_inertia + geo.center_x.len() as f64 * j.bearing.inertia,
            BearingJoint::Prismatic => sb_inertia,
        };
        let body = sys.add_body(turned(Body::new(name, sbc.mass, inertia, [s.centre[0], s.centre[1], s.theta]), sign));
        model.supports.push(body);
    }
    let law = match j.friction.law {
        LawConfig::Linear => FrictionLaw::Linear,
        LawConfig::Smooth => FrictionLaw::Smooth,
    };
    for (i, &x) in geo.center_x.iter().enumerate() {
        let mut row = Vec::with_capacity(geo.supports.len());
        for (k, s) in geo.supports.iter().enumerate() {
            let y = geo.bearing_y[i][k];
            let body =
                Body::new(format!("{prefix}bearing {}/{k}", i + 1), j.bearing.mass, j.bearing.inertia, [x, y, s.theta])
                    .with_tolerance_scale(config.simulation.bearing_atol_factor);
            let bearing = sys.add_body(turned(
                match bearing_joint {
                    BearingJoint::Translational => body.only(&[Coord::X, Coord::Y]),
                    BearingJoint::Prismatic => body,
                },
                sign,
            ));
            sys.add_force_named(
                format!("{prefix}bushing {}/{k}", i + 1),
                ForceElement::Bushing(Bushing {
                    frame_body: model.center_beams[i],
                    frame_point: [0.0, y],
                    body: bearing,
                    point: [0.0, 0.0],
                    stiffness: [j.bushing.kx, j.bushing.ky],
                    damping: [j.bushing.cx, j.bushing.cy],
                    rest: [0.0, 0.0],
                }),
            );
            sys.add_force_named(
                format!("{prefix}friction {}/{k}", i + 1),
                ForceElement::Friction(Friction {
                    slider: bearing,
                    point: [0.0, 0.0],
                    base: model.supports[k],
                    mu: j.friction.mu,
                    normal_force: j.friction.normal_force,
                    surfaces: j.friction.surfaces,
                    v_eps: j.friction.v_eps,
                    law,
                }),
            );
            let slide = match bearing_joint {
                BearingJoint::Translational => quakejoint_solver::Constraint::PointOnLine(PointOnLine {
                    body: bearing,
                    point: [0.0, 0.0],
                    line_body: model.supports[k],
                    line_point: [0.0, 0.0],
                    line_direction: [1.0, 0.0],
                }),
                BearingJoint::Prismatic => quakejoint_solver::Constraint::Prismatic(Prismatic {
                    slider: bearing,
                    point: [0.0, 0.0],
                    base: model.supports[k],
                    axis_point: [0.0, 0.0],
                    axis_direction: [1.0, 0.0],
                }),
            };
            sys.add_constraint_named(format!("{prefix}slide {}/{k}", i + 1), slide);
            row.push(bearing);
        }
        model.bearings.push(row);
    }
    model.geometry = Some(geo);
    Ok(())
}

/// `body`, turned half a turn when `sign` is -1: its x and y point the
/// other way, so the ground's acceleration acts on it reversed.
pub(crate) fn turned(body: Body, sign: f64) -> Body {
    if sign < 0.0 {
        let m = body.mass;
        body.with_base_mass([[-m, 0.0], [0.0, -m]])
    } else {
        body
    }
}

/// Connects the joint's support beams to its abutment side (joist pivots,
/// guide welds) and its joists to the deck (joist boxes).
fn connect_joint(sys: &mut System, model: &mut JointModel, deck: BodyId, abutment: BodyId, prefix: &str) {
    let Some(geo) = model.geometry.clone() else { return };
    for (k, s) in geo.supports.iter().enumerate() {
        let body = model.supports[k];
        match s.kind {
            SupportKind::Joist => {
                let pivot = sys.add_constraint_named(
                    format!("{prefix}pivot {k}"),
                    quakejoint_solver::Constraint::Revolute(Revolute {
                        body_a: body,
                        point_a: [-s.half_span, 0.0],
                        body_b: abutment,
                        point_b: [0.0, s.y0],
                    }),
                );
                model.abutment_links.push(pivot);
                let c = sys.add_constraint_named(
                    format!("{prefix}joist box {k}"),
                    quakejoint_solver::Constraint::PointOnLine(PointOnLine {
                        body: deck,
                        point: [geo.gap, s.y0 + s.box_dy],
                        line_body: body,
                        line_point: [0.0, 0.0],
                        line_direction: [1.0, 0.0],
                    }),
                );
                model.joist_boxes.push(c);
            }
            SupportKind::Guide => {
                let weld = sys.add_constraint_named(
                    format!("{prefix}guide weld {k}"),
                    quakejoint_solver::Constraint::Weld(Weld {
                        body_a: body,
                        point_a: [0.0, 0.0],
                        body_b: abutment,
                        point_b: s.centre,
                    }),
                );
                model.abutment_links.push(weld);
            }
        }
    }
}

/// Size of a model as the paper counts it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Counts {
    /// Rigid bodies of the joint (center beams, support beams, bearings).
    pub bodies: usize,
    /// Coordinates (the joint bodies' plus the deck's `u`).
    pub coordinates: usize,
    /// Constraint equations.
    pub constraints: usize,
    /// Degrees of freedom.
    pub dof: usize,
}

/// The generated system and the ids of its parts.
#[derive(Debug, Clone)]
pub struct JointModel {
    /// The solver system.
    pub system: System,
    /// The joint geometry (None when the joint is disabled).
    pub geometry: Option<Geometry>,
    /// The deck.
    pub deck: BodyId,
    /// Center beams, abutment side first.
    pub center_beams: Vec<BodyId>,
    /// Support beams in config order.
    pub supports: Vec<BodyId>,
    /// Bearings `[center beam][support beam]`.
    pub bearings: Vec<Vec<BodyId>>,
    /// The joist-box constraints (the joint's only connection to the deck).
    pub joist_boxes: Vec<ConstraintId>,
    /// The body the joint's abutment side rests on when it moves: the
    /// adjacent segment's deck (`[bridge.far]`), or at an in-span hinge of a
    /// modal bridge the abutment end; none: the ground.
    pub far_deck: Option<BodyId>,
    /// The joist pivots and guide welds (the joint's connection to the
    /// abutment, or to the adjacent segment).
    pub abutment_links: Vec<ConstraintId>,
    /// The service driver, if any.
    pub driver: Option<ConstraintId>,
    /// Where each contact is, in the order the solver numbers them.
    pub contacts: Vec<ContactPlace>,
    /// The bridge.
    pub bridge: Bridge,
    /// The modes, when the bridge is given by them (`deck` is then the
    /// point the joint's deck side moves with).
    pub modal: Option<ModalDeck>,
    /// Size of the model.
    pub counts: Counts,
    /// The joint's name (`[[joints]]`; "joint" for the one of `[joint]`).
    pub name: String,
    /// The solver's number of the joint's first contact.
    pub first_contact: usize,
    /// +1, or -1 for a joint turned half a turn (`deck_side = "-x"`).
    pub sign: f64,
    /// The other joints of `[[joints]]`, each with its parts (their
    /// `system` empty: all are in this one's).
    pub others: Vec<JointModel>,
    /// The link element, when the joint is one (`joint.model = "link"`).
    pub link: Option<crate::link::LinkParts>,
    /// Its seismic fuse (`[joint.fuse]`), if it has one.
    pub fuse: Option<crate::fuse::Fuse>,
}

impl JointModel {
    /// This joint and the others.
    pub fn joints(&self) -> impl Iterator<Item = &JointModel> {
        std::iter::once(self).chain(&self.others)
    }
}

/// An abutment the ground motion `x` reaches `lag` \[s\] late (wave
/// passage): a body along x driven to `u_g(t - lag) - u_g(t)` relative to
/// the ground the other bodies' coordinates are measured from. Its mass is
/// carried by the driver (it stands for the ground); the driver's work is
/// the earthquake's work through that abutment.
pub fn lagged_abutment(sys: &mut System, x: &TimeSeries, lag: f64, prefix: &str) -> Result<BodyId, ModelError> {
    let body = sys.add_body(Body::new(format!("{prefix}abutment (lagged)"), 1.0, 1.0, [0.0; 3]).only(&[Coord::X]));
    let motion = quakejoint_solver::LaggedGround::new(std::sync::Arc::new(x.clone()), lag)?;
    sys.add_constraint_named(
        format!("{prefix}abutment drive (wave passage)"),
        quakejoint_solver::Constraint::Driver(Driver {
            body,
            coord: Coord::X,
            motion: TimeFunction::LaggedGround(std::sync::Arc::new(motion)),
        }),
    );
    Ok(body)
}

/// Builds the model of `config` with the bridge frequency `omega` [rad/s]
/// (the config's unless given) and the given drive.
pub fn build(config: &Config, omega: Option<f64>, drive: Drive) -> Result<JointModel, ModelError> {
    build_with(config, omega, drive, BearingJoint::default())
}

/// [`build`] with the bearings' joint written as `bearing_joint` (the
/// prismatic form is the check of the translational one).
pub fn build_with(
    config: &Config,
    omega: Option<f64>,
    drive: Drive,
    bearing_joint: BearingJoint,
) -> Result<JointModel, ModelError> {
    build_scenario(&Scenario::new(config.clone())?, omega, drive, bearing_joint)
}

/// The model of a resolved scenario (its config checked, its joints
/// placed), with the bridge frequency `omega` [rad/s] (the config's unless
/// given), the drive and the bearings' joint.
pub fn build_scenario(
    scenario: &Scenario,
    omega: Option<f64>,
    drive: Drive,
    bearing_joint: BearingJoint,
) -> Result<JointModel, ModelError> {
    let (config, places) = (&scenario.config, &scenario.places);
    let modal = scenario.bridge.modal();
    let bridge = bridge_of(config, omega, modal.map(|m| m.kept.as_slice()))?;
    let mut sys = System::new();
    let mut models = Vec::with_capacity(places.len());
    // (several joints: each one's bodies in its own group, whose friction
    // energy and peak forces the run reports apart)
    let grouped = places.len() > 1;
    for (k, place) in places.iter().enumerate() {
        let mut model = empty_model(place, bridge);
        if place.config.joint.enabled && !place.config.joint.is_link() {
            sys.add_to_group(if grouped { k as u32 } else { NO_GROUP });
            add_joint_bodies(&mut sys, &mut model, &place.config, bearing_joint, place.sign, &place.prefix)?;
            sys.add_to_group(NO_GROUP);
        }
        models.push(model);
    }
    // the abutment, or the adjacent segment's deck the joint rests on there
    let abutment = match bridge.far {
        Some(far) => add_far_segment(&mut sys, &mut models[0], far),
        None => BodyId::GROUND,
    };
    // the decks (and the abutment sides at in-span hinges)
    let (decks, hinges) = match modal {
        Some(m) => add_modal_decks(&mut sys, m, places, &mut models),
        None => {
            let deck_coords: &[Coord] = if bridge.transverse.is_some() { &[Coord::X, Coord::Y] } else { &[Coord::X] };
            (vec![sys.add_body(Body::new("deck", bridge.mass, 1.0, [0.0; 3]).only(deck_coords))], vec![None])
        }
    };
    let ends = Ends { decks: &decks, hinges: &hinges, abutment };
    connect_joints(&mut sys, &mut models, places, &ends, &drive)?;
    let deck = decks[0];
    let mut model = models.remove(0);
    model.others = models;
    add_bridge_springs(&mut sys, deck, &bridge, model.modal.is_none());
    model.counts = Counts {
        bodies: sys.body_count() - 1,
        coordinates: sys.coordinate_count(),
        constraints: sys.equation_count(),
        dof: sys.coordinate_count() - sys.equation_count(),
    };
    match drive {
        Drive::None => {}
        Drive::Earthquake { x, y } => sys.set_excitation(Excitation {
            gravity: [0.0, 0.0],
            ground_x: Some(x.into()),
            ground_y: y.map(TimeFunction::from),
        }),
        Drive::Service(tri) => {
            model.driver = Some(sys.add_constraint_named(
                "deck drive",
                quakejoint_solver::Constraint::Driver(Driver {
                    body: deck,
                    coord: Coord::X,
                    motion: TimeFunction::SmoothTriangle(tri),
                }),
            ));
        }
    }
    model.system = sys;
    Ok(model)
}

/// The bridge of `config` at the circular frequency `omega` [rad/s] (the
/// config's unless given; a modal bridge's first kept mode).
fn bridge_of(
    config: &Config,
    omega: Option<f64>,
    modes: Option<&[crate::modal::KeptMode]>,
) -> Result<Bridge, ModelError> {
    let bridge = Bridge {
        mass: config.bridge.mass,
        omega: omega.unwrap_or_else(|| config.bridge.omega()),
        damping: config.bridge.damping,
        transverse: config.bridge.transverse(),
        far: None,
    };
    let bridge = Bridge { far: config.bridge.far_segment(bridge.omega), ..bridge };
    let bridge = match modes {
        Some(kept) => Bridge { omega: kept[0].omega, damping: kept[0].damping, ..bridge },
        None => bridge,
    };
    if !(bridge.omega.is_finite() && bridge.omega > 0.0) {
        return Err(crate::config::invalid("bridge.w0", bridge.omega, "must be positive"));
    }
    Ok(bridge)
}

/// A joint's model with no bodies yet, at `place` on `bridge`.
fn empty_model(place: &crate::placement::Place, bridge: Bridge) -> JointModel {
    JointModel {
        system: System::new(),
        geometry: None,
        deck: BodyId::GROUND,
        center_beams: Vec::new(),
        supports: Vec::new(),
        bearings: Vec::new(),
        joist_boxes: Vec::new(),
        far_deck: None,
        abutment_links: Vec::new(),
        contacts: Vec::new(),
        driver: None,
        bridge,
        modal: None,
        counts: Counts { bodies: 0, coordinates: 0, constraints: 0, dof: 0 },
        name: place.name.clone(),
        first_contact: 0,
        sign: place.sign,
        others: Vec::new(),
        link: None,
        fuse: None,
    }
}

/// The adjacent segment's deck (mass \[kg\], circular frequency [rad/s],
/// damping ratio [-]) on its spring and damper, the first joint's abutment
/// side.
fn add_far_segment(sys: &mut System, model: &mut JointModel, (mass, w, zeta): (f64, f64, f64)) -> BodyId {
    let far = sys.add_body(Body::new("far deck", mass, 1.0, [0.0; 3]).only(&[Coord::X]));
    sys.add_force_named(
        "far segment spring and damper",
        ForceElement::CoordinateSpring(CoordinateSpring {
            body: far,
            coord: Coord::X,
            stiffness: mass * w * w,
            damping: 2.0 * zeta * mass * w,
            rest: 0.0,
        }),
    );
    model.far_deck = Some(far);
    far
}

/// A modal bridge's kept modes with a deck end at every joint's deck
/// point (and an abutment end at each in-span hinge): the decks, and the
/// hinges' abutment sides.
fn add_modal_decks(
    sys: &mut System,
    modal: &crate::bridge::Modal,
    places: &[crate::placement::Place],
    models: &mut [JointModel],
) -> (Vec<BodyId>, Vec<Option<BodyId>>) {
    let mut ends: Vec<EndSpec> = places
        .iter()
        .map(|p| EndSpec {
            name: format!("{}deck end", p.prefix),
            point: p.deck_point,
            point_y: p.deck_point_y,
            sign: p.sign,
        })
        .collect();
    let mut hinges = Vec::new();
    for p in places {
        hinges.push(p.abutment_point.map(|a| {
            ends.push(EndSpec { name: format!("{}abutment end", p.prefix), point: a, point_y: None, sign: p.sign });
            ends.len() - 1
        }));
    }
    // (the static correction at these points, in this order: the scenario's)
    let parts = std::sync::Arc::new(add_modes(sys, &modal.kept, modal.correction.as_ref(), &ends));
    for (k, m) in models.iter_mut().enumerate() {
        m.modal = Some(ModalDeck { parts: parts.clone(), end: k });
    }
    let decks = parts.ends[..places.len()].iter().map(|e| e.body).collect::<Vec<_>>();
    (decks, hinges.into_iter().map(|h| h.map(|e| parts.ends[e].body)).collect::<Vec<_>>())
}

/// What the joints connect to: each joint's deck, the abutment side of an
/// in-span hinge, and the first joint's abutment (the ground, or the
/// adjacent segment's deck).
struct Ends<'a> {
    decks: &'a [BodyId],
    hinges: &'a [Option<BodyId>],
    abutment: BodyId,
}

/// Connects each joint to its deck and its abutment side (a hinge's, a
/// lagged abutment, the adjacent segment or the ground), with its contacts
/// numbered across the joints.
fn connect_joints(
    sys: &mut System,
    models: &mut [JointModel],
    places: &[crate::placement::Place],
    ends: &Ends<'_>,
    drive: &Drive,
) -> Result<(), ModelError> {
    let (decks, hinges) = (ends.decks, ends.hinges);
    let models_grouped = places.len() > 1;
    let mut contacts = 0;
    for (k, (model, place)) in models.iter_mut().zip(places).enumerate() {
        let lagged = match drive {
            Drive::Earthquake { x, .. } if place.abutment_lag != 0.0 => {
                Some(lagged_abutment(sys, x, place.abutment_lag, &place.prefix)?)
            }
            _ => None,
        };
        let abutment = hinges[k].or(lagged).unwrap_or(if k == 0 { ends.abutment } else { BodyId::GROUND });
        if let Some(h) = hinges[k].or(lagged) {
            // the abutment side moves: its edge beam with it (the sub-gaps and
            // the validity checks read it, as an adjacent segment's deck)
            model.far_deck = Some(h);
        }
        model.deck = decks[k];
        let j = &place.config.joint;
        if j.enabled && j.is_link() {
            sys.add_to_group(if models_grouped { k as u32 } else { NO_GROUP });
            let link = crate::link::add_link(sys, j, decks[k], abutment, place.sign, &place.prefix);
            sys.add_to_group(NO_GROUP);
            let mut link = link?;
            if let (true, Some(gap)) = (j.contact.enabled, link.gap_force) {
                link.contact = Some(contacts);
                if let (Some(FuseKind::Element), ForceElement::Contact(c)) =
                    (j.fuse.as_ref().map(|f| f.kind), sys.force_mut(gap).clone())
                {
                    // (released at its force: the gap then closes a beam's
                    // width later)
                    let fuse = crate::fuse::FuseElement::in_link(&place.config, (gap, contacts, &c));
                    model.fuse = fuse.map(crate::fuse::Fuse::Element);
                } else if j.fuse.is_some() {
                    // (the closed joint's force breaks it, as the detailed
                    // joint's beam 1 on the edge beam)
                    let field = if places.len() > 1 { format!("joints[{k}].joint.fuse") } else { "joint.fuse".into() };
                    crate::fuse::check_abutment(abutment, &field)?;
                    let group = (places.len() + k) as u32;
                    // (its seat and stop take the gap's law: the joint's with
                    // a Hertz gap, the exports' linear and elastic without)
                    let law = match j.link.as_ref().filter(|l| l.gap_hertz.is_none()) {
                        Some(l) => ContactLaw::Linear {
                            stiffness: crate::link::stop_stiffness(j, l.gap_stiffness),
                            restitution: 1.0,
                        },
                        None => contact_law(&place.config),
                    };
                    let fuse =
                        crate::fuse::FuseBox::new(&place.config, vec![gap], contacts, law, (group, &place.prefix));
                    model.fuse = fuse.map(crate::fuse::Fuse::Box);
                }
                contacts += 1;
            }
            model.link = Some(link);
            continue;
        }
        connect_joint(sys, model, decks[k], abutment, &place.prefix);
        if let (true, Some(geo)) = (j.enabled && j.contact.enabled, model.geometry.clone()) {
            // a modal end weighs nothing of its own: the impact on it meets
            // the bridge, many times the center beam's mass
            let beam = Some(j.center_beam.mass);
            let impacts = [hinges[k].and(beam), model.modal.as_ref().and(beam)];
            model.first_contact = contacts;
            let law = contact_law(&place.config);
            let ids = add_contacts(sys, model, &geo, law, abutment, impacts, &place.prefix);
            match j.fuse.as_ref().map(|f| f.kind) {
                Some(FuseKind::Box) => {
                    let field = if places.len() > 1 { format!("joints[{k}].joint.fuse") } else { "joint.fuse".into() };
                    crate::fuse::check_abutment(abutment, &field)?;
                    let group = (places.len() + k) as u32;
                    let edge = ids[..2].to_vec();
                    let fuse = crate::fuse::FuseBox::new(&place.config, edge, contacts, law, (group, &place.prefix));
                    model.fuse = fuse.map(crate::fuse::Fuse::Box);
                }
                Some(FuseKind::Element) => {
                    let bodies = CellBodies { beams: &model.center_beams, deck: model.deck, abutment };
                    let sides = crate::fuse::ElementSides { ids: &ids, first: contacts, bodies, impacts };
                    let fuse = crate::fuse::FuseElement::new(&place.config, &geo, law, sides);
                    model.fuse = fuse.map(crate::fuse::Fuse::Element);
                }
                None => {}
            }
            contacts += model.contacts.len();
        }
    }
    Ok(())
}

/// The single-DOF deck's spring and damper (`along`: not for a modal
/// bridge, whose modes carry them) and, when it moves across, those across.
fn add_bridge_springs(sys: &mut System, deck: BodyId, bridge: &Bridge, along: bool) {
    if along {
        sys.add_force_named(
            "bridge spring and damper",
            ForceElement::CoordinateSpring(CoordinateSpring {
                body: deck,
                coord: Coord::X,
                stiffness: bridge.stiffness(),
                damping: bridge.damper(),
                rest: 0.0,
            }),
        );
    }
    if let Some((w, zeta)) = bridge.transverse {
        sys.add_force_named(
            "bridge spring and damper across",
            ForceElement::CoordinateSpring(CoordinateSpring {
                body: deck,
                coord: Coord::Y,
                stiffness: bridge.mass * w * w,
                damping: 2.0 * zeta * bridge.mass * w,
                rest: 0.0,
            }),
        );
    }
}
