//! Watching the clear sub-gaps of a running joint: at both ends of every
//! center beam, their extremes over the run, and the validity limits
//! ([`Monitor`]) at the same instants. Shared by the earthquake and the
//! service runs.

use quakejoint_solver::{Assembly, BodyId, Coord};

use crate::error::ModelError;
use crate::generator::JointModel;
use crate::geometry::Geometry;
use crate::validity::Monitor;

/// The sub-gaps of a joint model and their extremes so far.
#[derive(Debug, Clone)]
pub(crate) struct Gaps {
    pub geometry: Geometry,
    /// x and angle coordinates of each center beam
    pub beams: Vec<usize>,
    angles: Vec<usize>,
    /// x coordinate of the adjacent segment's deck, if the abutment side is one
    far: Option<usize>,
    /// x coordinate of the abutment's edge beam once its fuse broke
    edge: Option<usize>,
    /// A fuse element's beam (index into `beams`) once it left the plane:
    /// cells `released` and `released + 1` are one
    released: Option<usize>,
    x: Vec<f64>,
    phi: Vec<f64>,
    /// clear sub-gaps at both ends [m]
    ends: Vec<[f64; 2]>,
    /// each sub-gap at its narrower end at the last check [m]
    pub smallest: Vec<f64>,
    /// each sub-gap at its wider end at the last check [m]
    pub largest: Vec<f64>,
    /// smallest and largest clear sub-gap so far [m]
    pub min: f64,
    pub max: f64,
    /// largest deviation from equal spacing so far [m]
    pub deviation: f64,
}

impl Gaps {
    /// The sub-gaps of `model` (None without the joint).
    pub fn new(model: &JointModel, asm: &Assembly) -> Result<Option<Self>, ModelError> {
        let Some(g) = &model.geometry else { return Ok(None) };
        let coord = |b: BodyId, c: Coord| {
            asm.coordinate(b, c).ok_or_else(|| ModelError::Geometry(format!("body {} lacks a coordinate", b.index())))
        };
        Ok(Some(Gaps {
            geometry: g.clone(),
            beams: model.center_beams.iter().map(|&b| coord(b, Coord::X)).collect::<Result<_, _>>()?,
            angles: model.center_beams.iter().map(|&b| coord(b, Coord::Phi)).collect::<Result<_, _>>()?,
            far: model.far_deck.map(|b| coord(b, Coord::X)).transpose()?,
            edge: None,
            released: None,
            x: vec![0.0; g.center_beams],
            phi: vec![0.0; g.center_beams],
            ends: Vec::with_capacity(g.center_beams + 1),
            smallest: Vec::with_capacity(g.center_beams + 1),
            largest: Vec::with_capacity(g.center_beams + 1),
            min: f64::INFINITY,
            max: f64::NEG_INFINITY,
            deviation: 0.0,
        }))
    }

    /// Measures the edge cell from the abutment's edge beam at coordinate
    /// `coord`, freed by its fuse.
    pub fn free_edge(&mut self, coord: usize) {
        self.edge = Some(coord);
    }

    /// A fuse element's beam (index into the center beams) left the plane:
    /// its two cells are one, each reported as half of it.
    pub fn release_beam(&mut self, beam: usize) {
        self.released = Some(beam);
    }

    /// The sub-gaps at time `t` for positions `q` and deck opening `u`,
    /// and the validity limits if a monitor is given.
    pub fn check(&mut self, t: f64, q: &[f64], u: f64, monitor: Option<&mut Monitor>) {
        let equal = self.fill(q, u);
        // (the joists keep every beam where they would, the released one's
        // place too: a merged cell's halves each have half its width more)
        for (s, &[a, b]) in self.ends.iter().enumerate() {
            self.min = self.min.min(a.min(b));
            self.max = self.max.max(a.max(b));
            let merged = self.released.is_some_and(|i| crate::generator::beside(i + 1, s));
            let equal = equal + if merged { 0.5 * self.geometry.width } else { 0.0 };
            self.deviation = self.deviation.max((a - equal).abs().max((b - equal).abs()));
        }
        if let Some(m) = monitor {
            m.sample(t, q, u, &self.smallest, &self.largest);
        }
    }

    /// The sub-gaps for positions `q` and deck opening `u` into `ends`,
    /// `smallest` and `largest`, the extremes so far left as they are;
    /// returns the sub-gap of equal spacing \[m\].
    pub fn fill(&mut self, q: &[f64], u: f64) -> f64 {
        for ((x, phi), (&c, &a)) in self.x.iter_mut().zip(&mut self.phi).zip(self.beams.iter().zip(&self.angles)) {
            (*x, *phi) = (q[c], q[a]);
        }
        // (a fuse box only on the ground: far and edge are never both set)
        let u0 = self.far.or(self.edge).map_or(0.0, |c| q[c]);
        self.geometry.subgaps(&self.x, &self.phi, (u, u0), self.released, &mut self.ends);
        self.smallest.clear();
        self.largest.clear();
        for &[a, b] in &self.ends {
            self.smallest.push(a.min(b));
            self.largest.push(a.max(b));
        }
        (self.geometry.gap + u - u0) / (self.geometry.center_beams + 1) as f64 - self.geometry.width
    }
}

/// Why the dense output cannot fail in the observers: the times come from
/// the step's own `OutputTimes::next_in` (or lie between its ends) and the
/// buffers are sized by the same assembly.
pub(crate) const DENSE_OUTPUT: &str = "an output time handed out for a step lies in it, and the buffers fit its system";
