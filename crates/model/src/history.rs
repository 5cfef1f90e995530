//! The time histories of a run at its output times ([`Histories`]): one
//! type for a run's file, a sweep's stored histories and Python.

use serde::{Deserialize, Serialize};

/// Time histories at the output times (the record's sample times). A
/// series a run does not compute is empty.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct Histories {
    /// Time \[s\].
    pub t: Vec<f64>,
    /// Ground acceleration [m/s^2].
    pub ag: Vec<f64>,
    /// Deck displacement relative to the ground `u` \[m\].
    pub u: Vec<f64>,
    /// Deck velocity relative to the ground [m/s].
    pub v: Vec<f64>,
    /// Deck absolute acceleration [m/s^2].
    pub a_abs: Vec<f64>,
    /// The bridge alone's absolute acceleration at the same times, over
    /// the same window, exactly [m/s^2] (NaN past the window;
    /// [`crate::runspec::Reference`]).
    pub a_abs_without_joint: Vec<f64>,
    /// Force of the joint on the deck, x \[N\].
    pub joint_force: Vec<f64>,
    /// Power dissipated by friction \[W\].
    pub friction_power: Vec<f64>,
    /// x displacement of each center beam from its reference position,
    /// `[beam][time]` \[m\].
    pub center_beam_dx: Vec<Vec<f64>>,
    /// Clear sub-gaps at the narrower of the two beam ends (where the beams
    /// close first: pounding), abutment side first, `[gap][time]` \[m\]
    /// (Nc + 1 of them).
    pub subgaps: Vec<Vec<f64>>,
    /// Clear sub-gaps at the wider of the two beam ends (where a cell
    /// opens most: the movement capacity), `[gap][time]` \[m\].
    pub subgaps_wide: Vec<Vec<f64>>,
    /// Largest contact force across each sub-gap (both ends) since the
    /// previous output time, `[gap][time]` \[N\] (empty without contacts): an
    /// impact is shorter than a record's time step.
    pub contact_force: Vec<Vec<f64>>,
    /// Every impact (contact onset), in time order.
    pub impacts: Vec<crate::pounding::Impact>,
    /// Deck displacement across the bridge relative to the ground `u_y` \[m\]
    /// (empty when the deck does not move across).
    pub uy: Vec<f64>,
    /// Deck absolute acceleration across the bridge [m/s^2] (empty when
    /// the deck does not move across).
    pub a_abs_y: Vec<f64>,
    /// Force of the joint on the deck across the bridge, y \[N\] (empty when
    /// the deck does not move across).
    pub joint_force_y: Vec<f64>,
    /// A bridge given by its modes: each point's displacement along the
    /// bridge relative to the ground, `[point][time]` \[m\] (the run's
    /// first joint's histories only).
    pub points_u: Vec<Vec<f64>>,
    /// Each point's absolute acceleration along the bridge,
    /// `[point][time]` [m/s^2].
    pub points_a_abs: Vec<Vec<f64>>,
    /// The same of the bridge alone (exact modal superposition over the same
    /// window; NaN past it) \[m\].
    pub points_u_without_joint: Vec<Vec<f64>>,
    /// The same [m/s^2].
    pub points_a_abs_without_joint: Vec<Vec<f64>>,
}

/// One series of [`Histories`] over the output times: its name in every
/// output, its units, and where it is.
#[derive(Debug, Clone, Copy)]
pub struct Series {
    /// Its name.
    pub name: &'static str,
    /// Its units.
    pub units: &'static str,
    /// What it is (a line of `docs/hdf5-layout.md`).
    pub meaning: &'static str,
    /// The series in a run's histories.
    pub of: fn(&Histories) -> &Vec<f64>,
    /// The same, to fill.
    pub of_mut: fn(&mut Histories) -> &mut Vec<f64>,
}

/// One table of [`Histories`]: a series per beam or sub-gap (rows) over
/// the output times.
#[derive(Debug, Clone, Copy)]
pub struct Table {
    /// Its name.
    pub name: &'static str,
    /// Its units.
    pub units: &'static str,
    /// What it is (a line of `docs/hdf5-layout.md`).
    pub meaning: &'static str,
    /// Its rows, as the docs name their count (`Nc`, `Nc + 1`, `np`).
    pub rows: &'static str,
    /// The rows in a run's histories.
    pub of: fn(&Histories) -> &Vec<Vec<f64>>,
    /// The same, to fill.
    pub of_mut: fn(&mut Histories) -> &mut Vec<Vec<f64>>,
}

macro_rules! series {
    ($field:ident, $units:literal, $meaning:literal) => {
        Series {
            name: stringify!($field),
            units: $units,
            meaning: $meaning,
            of: |h| &h.$field,
            of_mut: |h| &mut h.$field,
        }
    };
    ($field:ident, $rows:literal, $units:literal, $meaning:literal) => {
        Table {
            name: stringify!($field),
            units: $units,
            meaning: $meaning,
            rows: $rows,
            of: |h| &h.$field,
            of_mut: |h| &mut h.$field,
        }
    };
}

/// Every series of a run's histories, in the order outputs list them (a
/// run's `/history`, a sweep's `/histories/job_<j>`).
pub const SERIES: [Series; 11] = [
    series!(t, "s", "time"),
    series!(ag, "m/s^2", "ground acceleration (in the joint's own x: `u` opens the joint)"),
    series!(u, "m", "deck displacement relative to the ground (at the joint's deck point, in its own x)"),
    series!(v, "m/s", "deck velocity relative to the ground"),
    series!(a_abs, "m/s^2", "deck absolute acceleration (force balance)"),
    series!(
        a_abs_without_joint,
        "m/s^2",
        "the same for the bridge alone (exact linear solution over the same window; the ground is at rest after the record)"
    ),
    series!(joint_force, "N", "force of the joint on the deck (x; NaN without the joint)"),
    series!(
        friction_power,
        "W",
        "power dissipated by the joint's friction (its own bodies' in a run of several joints; NaN without the joint)"
    ),
    series!(uy, "m", "across the bridge (when the deck moves across): the deck's displacement relative to the ground"),
    series!(a_abs_y, "m/s^2", "across the bridge: the deck's absolute acceleration"),
    series!(joint_force_y, "N", "across the bridge: the joint's force on the deck"),
];

/// Every table of a run's histories, in the order outputs list them.
pub const TABLES: [Table; 8] = [
    series!(
        center_beam_dx,
        "Nc",
        "m",
        "x displacement of each center beam from its reference position (absent without the joint)"
    ),
    series!(
        subgaps,
        "Nc + 1",
        "m",
        "clear sub-gaps at the narrower of the two beam ends (where the beams close first: pounding), abutment side \
         first (absent without the joint); for the link element (`joint.model = \"link\"`, docs/link.md) one row, the \
         cells' average `(pitch - width) + u / (Nc + 1)` (its racked narrowest and widest cells: `min_subgap`, \
         `max_subgap`)"
    ),
    series!(
        subgaps_wide,
        "Nc + 1",
        "m",
        "clear sub-gaps at the wider of the two beam ends (where a cell opens most: the movement capacity); its \
         largest value is `/result/max_subgap` when the record's step is at most the 5 ms of the validity checks"
    ),
    series!(
        contact_force,
        "Nc + 1",
        "N",
        "largest contact force across each sub-gap (both ends together) since the previous output time, an impact \
         being shorter than a time step (absent without contact)"
    ),
    series!(
        points_u,
        "np",
        "m",
        "a bridge given by its modes: every point of the modes file (in the order of `/points/name`), its \
         displacement along the bridge relative to the ground (with `--no-joint`, the bridge alone's)"
    ),
    series!(points_a_abs, "np", "m/s^2", "the same point's absolute acceleration"),
    series!(
        points_u_without_joint,
        "np",
        "m",
        "`points_u` of the bridge alone (exact modal superposition of the kept modes over the same window)"
    ),
    series!(points_a_abs_without_joint, "np", "m/s^2", "`points_a_abs` of the bridge alone"),
];

/// The rows of `docs/hdf5-layout.md`'s table of a run file's `/history`:
/// the docs are made from [`SERIES`] and [`TABLES`] (a test keeps them
/// equal).
pub fn markdown_table() -> String {
    let mut out = String::from("| path | shape | units | content |\n|---|---|---|---|\n| `/history` | | | group |\n");
    for s in SERIES {
        out += &format!("| `/history/{}` | (nt) | {} | {} |\n", s.name, s.units, s.meaning);
    }
    for t in TABLES {
        out += &format!("| `/history/{}` | ({}, nt) | {} | {} |\n", t.name, t.rows, t.units, t.meaning);
    }
    out
}

impl Histories {
    /// The series a sweep keeps of a job, in its journal and its file: the
    /// deck's and the joint's along the bridge and the sub-gaps, not the
    /// deck's velocity, the center beams' motion, the log of impacts, the
    /// series across the bridge or a modal bridge's points (a run's own
    /// file holds those).
    pub fn for_sweep(self) -> Histories {
        Histories {
            v: Vec::new(),
            center_beam_dx: Vec::new(),
            impacts: Vec::new(),
            uy: Vec::new(),
            a_abs_y: Vec::new(),
            joint_force_y: Vec::new(),
            points_u: Vec::new(),
            points_a_abs: Vec::new(),
            points_u_without_joint: Vec::new(),
            points_a_abs_without_joint: Vec::new(),
            ..self
        }
    }
}
