//! The scalar results of a run, listed once ([`FIELDS`]): each with its
//! name, units and meaning and how it is read from a [`RunResult`]. The
//! command's `simulate --json`, a run file's `/result`, a sweep's per-job
//! arrays (`/spectrum/with_joint/<name>`, the fields marked `per_job`),
//! Python's run results and the list in `docs/hdf5-layout.md` all come
//! from it.

use crate::run::RunResult;

/// One scalar result of a run.
#[derive(Debug, Clone, Copy)]
pub struct Field {
    /// Its name in every output.
    pub name: &'static str,
    /// Its units (`1` for counts and ratios).
    pub units: &'static str,
    /// What it is, in a few words.
    pub meaning: &'static str,
    /// Stored for every job of a sweep.
    pub per_job: bool,
    /// A count (written as a whole number where outputs can).
    pub count: bool,
    /// Depends on the machine, not on the inputs (left out of comparisons).
    pub machine_dependent: bool,
    /// Its value in a run's results (NaN where the run does not compute it).
    pub value: fn(&RunResult) -> f64,
}

const fn field(name: &'static str, units: &'static str, meaning: &'static str, value: fn(&RunResult) -> f64) -> Field {
    Field { name, units, meaning, per_job: false, count: false, machine_dependent: false, value }
}

impl Field {
    /// Stored per job in a sweep.
    const fn per_job(self) -> Self {
        Field { per_job: true, ..self }
    }
    /// A count.
    const fn count(self) -> Self {
        Field { count: true, ..self }
    }
    /// Machine-dependent.
    const fn machine(self) -> Self {
        Field { machine_dependent: true, ..self }
    }
}

/// The deck's spectral values and their units, in the order every output
/// keeps them: the bridge alone's (a sweep's `/spectrum/without_joint`)
/// and the measures of a `deck` limit state.
pub const SPECTRAL: [(&str, &str); 4] = [("sa", "m/s^2"), ("psa", "m/s^2"), ("sd", "m"), ("sv", "m/s")];

const TAU: f64 = 2.0 * std::f64::consts::PI;

fn opt(x: Option<f64>) -> f64 {
    x.unwrap_or(f64::NAN)
}

/// A solver counter: NaN for the exact solution without the joint.
fn counter(r: &RunResult, n: u64) -> f64 {
    if r.exact_linear {
        f64::NAN
    } else {
        n as f64
    }
}

fn across(r: &RunResult, f: fn(&crate::run::Transverse) -> f64) -> f64 {
    r.transverse.as_ref().map_or(f64::NAN, f)
}

fn far(r: &RunResult, f: fn(&crate::run::FarSegment) -> f64) -> f64 {
    r.far.as_ref().map_or(f64::NAN, f)
}

/// The first joint's fuse's value `i` of [`crate::run::fuse::FUSE_FIELDS`].
fn fuse(r: &RunResult, i: usize) -> f64 {
    crate::run::fuse::FuseResult::values(r.joints.first().and_then(|j| j.fuse.as_ref()))[i]
}

/// [`crate::run::fuse::FUSE_FIELDS`]' `i`, reading the first joint's fuse.
const fn fuse_field(i: usize, value: fn(&RunResult) -> f64) -> Field {
    let f = crate::run::fuse::FUSE_FIELDS[i];
    field(f.name, f.units, f.meaning, value).per_job()
}

/// Every scalar result of a run, in the order outputs list them.
pub const FIELDS: &[Field] = &[
    field("omega", "rad/s", "bridge circular frequency", |r| r.omega),
    field("period", "s", "bridge period", |r| TAU / r.omega),
    field("sa", "m/s^2", "peak absolute acceleration of the deck", |r| r.sa).per_job(),
    field("t_sa", "s", "time of `sa`", |r| r.t_sa).per_job(),
    field("psa", "m/s^2", "pseudo-acceleration w0^2 Sd", |r| r.psa).per_job(),
    field("sd", "m", "peak deck displacement relative to the ground", |r| r.sd).per_job(),
    field("t_sd", "s", "time of `sd`", |r| r.t_sd).per_job(),
    field("sv", "m/s", "peak deck velocity relative to the ground", |r| r.sv).per_job(),
    field("t_sv", "s", "time of `sv`", |r| r.t_sv).per_job(),
    field("peak_joint_force", "N", "peak force of the joint on the deck", |r| r.peak_joint_force).per_job(),
    field("peak_abutment_force", "N", "peak force of the joint on its abutment: its joist pivots, guide welds and the abutment's edge-beam contacts (on the adjacent segment with `[bridge.far]`; NaN for a link element)", |r| r.peak_abutment_force).per_job(),
    field("peak_bushing_force", "N", "peak force of a bushing", |r| r.peak_bushing_force).per_job(),
    field("peak_friction_force", "N", "peak friction force of a bearing", |r| r.peak_friction_force).per_job(),
    field("friction_energy", "J", "energy dissipated by the bearings' friction (a broken fuse's freed edge beam's apart: `fuse_energy`)", |r| r.friction_energy).per_job(),
    field("damping_energy", "J", "energy dissipated by dampers (the bridge's and the bushings')", |r| r.damping_energy)
        .per_job(),
    field("earthquake_work", "J", "work of the earthquake load", |r| r.earthquake_work).per_job(),
    field("min_subgap", "m", "smallest clear sub-gap at either end of the center beams, checked at least every 5 ms (below zero: the beams touch, compressing their contacts; overlap without contact)", |r| opt(r.min_subgap)).per_job(),
    field("max_subgap", "m", "largest clear sub-gap at either end of the center beams, checked at least every 5 ms", |r| opt(r.max_subgap)).per_job(),
    field("max_subgap_deviation", "m", "largest deviation of a sub-gap from equal spacing", |r| {
        opt(r.max_subgap_deviation)
    })
    .per_job(),
    field("impacts", "1", "impacts: contact onsets at 5 cm/s or faster, every beam end counted (NaN without the joint)", |r| counter(r, r.pounding.impacts))
        .per_job()
        .count(),
    field("peak_contact_force", "N", "largest force of one contact (one beam end); in a run file, where it acted is the root attribute `peak_contact_place`", |r| r.pounding.peak_contact_force).per_job(),
    field("peak_contact_time", "s", "time of `peak_contact_force`", |r| r.pounding.peak_contact_time),
    field("contact_energy", "J", "energy the impacts dissipated (inside the energy balance)", |r| r.pounding.contact_energy).per_job(),
    field("peak_deck_contact_force", "N", "largest force of the closed joint on the deck through the deck's edge beam", |r| {
        r.pounding.peak_deck_contact_force
    })
    .per_job(),
    field("max_penetration", "m", "deepest penetration of a contact", |r| r.pounding.max_penetration).per_job(),
    field("max_impact_speed", "m/s", "fastest approach of two faces at a contact's onset (0 without contact; NaN for a link element and without the joint)", |r| r.pounding.max_impact_speed).per_job(),
    field("energy_error", "1", "energy balance error relative to the earthquake's work", |r| r.energy_error).per_job(),
    field("max_position_residual", "m", "largest constraint residual of the translational equations", |r| r.residuals.position).per_job(),
    field("max_angle_residual", "rad", "largest constraint residual of the angular equations", |r| r.residuals.angle).per_job(),
    field("max_velocity_residual", "m/s", "the same at velocity level", |r| r.residuals.velocity).per_job(),
    field("max_angular_velocity_residual", "rad/s", "the same at angular-velocity level", |r| {
        r.residuals.angular_velocity
    })
    .per_job(),
    field("steps", "1", "solver counter: accepted steps (NaN without the joint, as for every counter)", |r| counter(r, r.stats.steps)).per_job().count(),
    field("rejected_steps", "1", "solver counter: rejected steps", |r| counter(r, r.stats.rejected)).per_job().count(),
    field("failed_attempts", "1", "solver counter: step attempts whose Newton iteration failed", |r| {
        counter(r, r.stats.failed_attempts)
    })
    .per_job()
    .count(),
    field("newton_iterations", "1", "solver counter: Newton iterations", |r| counter(r, r.stats.newton_iterations)).per_job().count(),
    field("jacobian_evaluations", "1", "solver counter: Jacobian evaluations", |r| counter(r, r.stats.jacobian_evaluations)).count(),
    field("factorizations", "1", "solver counter: factorisations", |r| counter(r, r.stats.factorizations)).per_job().count(),
    field("residual_evaluations", "1", "solver counter: residual evaluations", |r| counter(r, r.stats.residual_evaluations)).count(),
    field("wall_time_s", "s", "wall-clock time of the integration", |r| r.wall_time_s).per_job().machine(),
    field("cpu_time_s", "s", "CPU time of the integration on its thread (NaN where the system does not report a thread's CPU time): beside `wall_time_s` it shows what waiting for a core or the disk cost", |r| r.cpu_time_s).per_job().machine(),
    field("duration", "s", "simulated duration", |r| r.duration),
    field("period_y", "s", "the deck's period across the bridge (`bridge.transverse_period`; NaN when the deck does not move across, as for every `_y` value, and on a bridge given by its modes, whose point across has no one period)", |r| across(r, |y| TAU / y.omega)),
    field("sa_y", "m/s^2", "peak absolute acceleration of the deck across the bridge", |r| across(r, |y| y.sa)).per_job(),
    field("t_sa_y", "s", "time of `sa_y`", |r| across(r, |y| y.t_sa)),
    field("sd_y", "m", "peak displacement of the deck across the bridge", |r| across(r, |y| y.sd)).per_job(),
    field("sv_y", "m/s", "peak velocity of the deck across the bridge", |r| across(r, |y| y.sv)),
    field("peak_joint_force_y", "N", "peak force of the joint on the deck across the bridge", |r| {
        across(r, |y| y.peak_joint_force)
    }),
    field("sa_y_without_joint", "m/s^2", "Sa across without the joint: the exact linear response of the transverse oscillator to `[record_y]` over the run's window (0 without `[record_y]`)", |r| across(r, |y| y.sa_without)).per_job(),
    field("period_far", "s", "the adjacent segment's period (`[bridge.far]`; NaN without one, as for every `_far` value)", |r| far(r, |f| TAU / f.omega)),
    field("sa_far", "m/s^2", "the adjacent segment's peak absolute acceleration", |r| far(r, |f| f.sa)).per_job(),
    field("t_sa_far", "s", "time of `sa_far`", |r| far(r, |f| f.t_sa)),
    field("sd_far", "m", "the adjacent segment's peak displacement", |r| far(r, |f| f.sd)),
    field("peak_joint_force_far", "N", "peak force of the joint on the adjacent segment", |r| {
        far(r, |f| f.peak_joint_force)
    }),
    field("sa_far_without_joint", "m/s^2", "its Sa without the joint (exact linear, over the run's window)", |r| far(r, |f| f.sa_without)).per_job(),
    field("max_relative_displacement", "m", "largest |u - u_far| of the two decks at the output times", |r| {
        far(r, |f| f.max_relative_displacement)
    })
    .per_job(),
    fuse_field(0, |r| fuse(r, 0)),
    fuse_field(1, |r| fuse(r, 1)),
    fuse_field(2, |r| fuse(r, 2)),
    fuse_field(3, |r| fuse(r, 3)),
    fuse_field(4, |r| fuse(r, 4)),
    fuse_field(5, |r| fuse(r, 5)),
    fuse_field(6, |r| fuse(r, 6)),
];

/// The field named `name`.
pub fn field_named(name: &str) -> Option<&'static Field> {
    FIELDS.iter().find(|f| f.name == name)
}

/// The rows of `docs/hdf5-layout.md`'s table of a run file's `/result`
/// (every field), and of its list of a sweep's per-job fields: the docs
/// are made from [`FIELDS`] (a test keeps them equal).
pub fn markdown_tables() -> (String, String) {
    let mut result = String::from("| path | units | content |\n|---|---|---|\n| `/result` | | group |\n");
    let mut per_job = String::from("| `<field>` | units | content |\n|---|---|---|\n");
    for f in FIELDS {
        result += &format!("| `/result/{}` | {} | {} |\n", f.name, f.units, f.meaning);
        if f.per_job {
            per_job += &format!("| `{}` | {} | {} |\n", f.name, f.units, f.meaning);
        }
    }
    (result, per_job)
}

impl RunResult {
    /// Scalar results of a run: name, value, unit, in the order of
    /// [`FIELDS`]. Quantities a run did not compute are NaN
    /// (the joint's, the energy balance and the solver counters of the
    /// exact linear solution without the joint).
    pub fn scalars(&self) -> Vec<(&'static str, f64, &'static str)> {
        FIELDS.iter().map(|f| (f.name, (f.value)(self), f.units)).collect()
    }
}

/// `docs/hdf5-layout.md`'s tables of a run file's joints (`/joints/<k>`,
/// their values from [`crate::run::JOINT_FIELDS`]) and a modal bridge's
/// points (`/points`, their values from [`crate::modal::POINT_FIELDS`]):
/// the docs are made from these lists (a test keeps them equal).
pub fn joint_and_point_tables() -> (String, String) {
    const HEAD: &str = "| path | shape | units | content |\n|---|---|---|---|\n";
    let rows = |prefix: &str, shape: &str, fields: &[crate::described::Described]| -> String {
        let row = |f: &crate::described::Described| {
            format!("| `{prefix}/{}` | {shape} | {} | {} |\n", f.name, f.units, f.meaning)
        };
        fields.iter().map(row).collect()
    };
    let joints = format!(
        "{HEAD}| `/joints` | | | group of every joint of the run |\n\
         | `/joints/<k>` | | | group of the joint k of `[[joints]]` (k from 0); attributes `name`, `validity_label` and \
         `validity_findings` |\n\
         {}\
         | `/joints/<k>/validity` | () | 1 | its validity bits (the bits of docs/model.md's flags) |\n\
         | `/joints/<k>/history` | | | k from 1 (the first joint's is `/history`): as `/history` (its deck point's motion \
         and the ground's acceleration `ag` in the joint's own x: `u` opens it, its own `friction_power`) |\n\
         | `/joints/<k>/history/<series>` | | | each of its series and tables, as in `/history` |\n",
        rows("/joints/<k>", "()", &crate::run::JOINT_FIELDS)
    );
    let points = format!(
        "{HEAD}| `/points` | | | group: every point of the modes file, in its order |\n\
         | `/points/name` | (np) | | the points' names |\n\
         {}\
         | `/points/base_shear`, `/points/base_shear_without_joint` | () | N | peak base shear along the bridge of the \
         kept modes, `sum_i Gamma_i (w_i^2 q_i + 2 zeta_i w_i q_i')`, with the joints and without |\n\
         | `/points/flexibility_captured` | (np) | 1 | at each point, the kept modes' share of the full model's static \
         flexibility there (NaN without the modes file's `[static]` table; `docs/bridge.md`, \"How many modes\") |\n\
         | `/points/mass_ratio` | () | 1 | the kept modes' effective mass along x over the file's `total_mass_x` (NaN \
         without it); the group's attribute `warnings` says where the kept modes hold less than 90 % |\n",
        rows("/points", "(np)", &crate::modal::POINT_FIELDS)
    );
    (joints, points)
}
