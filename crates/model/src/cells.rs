//! The contacts across a joint's cells: a center beam's corner on its
//! neighbour's face, written once for the generator's cells and for the
//! merged cell a fuse element leaves behind (`crate::fuse`).

use quakejoint_solver::{BodyId, Contact, ContactLaw};

use crate::geometry::Geometry;

/// One side of a cell: the abutment's edge beam, a center beam (an index
/// into [`CellBodies::beams`]) or the deck's edge beam.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Side {
    /// The abutment's edge beam (the abutment body's edge at `x = w/2`).
    Abutment,
    /// A center beam.
    Beam(usize),
    /// The deck's edge beam (the deck body's edge at `x = G0 - w/2`).
    Deck,
}

/// The bodies a joint's cells lie between.
pub(crate) struct CellBodies<'a> {
    /// The center beams, abutment side first.
    pub beams: &'a [BodyId],
    /// The deck (its edge beam's body).
    pub deck: BodyId,
    /// The abutment side (the ground, a hinge's deck, an adjacent segment).
    pub abutment: BodyId,
}

/// The contact across the cell from `left` (abutment side) to `right` at
/// the beams' end `y` \[m\]: the corner of the abutment side's beam on the
/// face of the other's (the center beam's corner on the abutment's edge
/// beam's face where `left` is the abutment), with `law` and the masses
/// `impacts` at the abutment and at the deck meet (none: the bodies'
/// reduced mass).
pub(crate) fn cell_contact(
    bodies: &CellBodies<'_>,
    geo: &Geometry,
    (left, right): (Side, Side),
    y: f64,
    (law, impacts): (ContactLaw, [Option<f64>; 2]),
) -> Contact {
    let half_w = 0.5 * geo.width;
    let (base, edge_point, edge_normal) = match right {
        Side::Beam(i) => (bodies.beams[i], [-half_w, 0.0], [-1.0, 0.0]),
        _ => (bodies.deck, [geo.gap - half_w, 0.0], [-1.0, 0.0]),
    };
    let (body, point, base, edge_point, edge_normal) = match (left, right) {
        (Side::Beam(i), _) => (bodies.beams[i], [half_w, y], base, edge_point, edge_normal),
        (_, Side::Beam(i)) => (bodies.beams[i], [-half_w, y], bodies.abutment, [half_w, 0.0], [1.0, 0.0]),
        // (the deck's corner on the abutment's face: a joint without beams
        // in the plane, which no fuse leaves)
        _ => (bodies.deck, [geo.gap - half_w, y], bodies.abutment, [half_w, 0.0], [1.0, 0.0]),
    };
    let reduced_mass = match (left, right) {
        (Side::Abutment, _) => impacts[0],
        (_, Side::Deck) => impacts[1],
        _ => None,
    };
    Contact { body, point, base, edge_point, edge_normal, law, reduced_mass }
}
