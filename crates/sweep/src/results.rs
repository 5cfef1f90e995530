//! Results of a sweep: one record per job and the arrays they fill.

use std::sync::LazyLock;

use quakejoint_model::run::Histories;
use quakejoint_model::validity::Flags;
use serde::{Deserialize, Serialize};

/// Per-job values stored in `/spectrum/with_joint/<name>`, in this order:
/// the fields of a run marked `per_job` (`quakejoint_model::fields`).
pub static FIELDS: LazyLock<Vec<&'static str>> = LazyLock::new(|| per_job().map(|f| f.name).collect());

/// Units of [`FIELDS`] (`1` for counts and ratios).
pub static UNITS: LazyLock<Vec<&'static str>> = LazyLock::new(|| per_job().map(|f| f.units).collect());

/// Fields that depend on the machine, not on the inputs (left out of
/// determinism comparisons).
pub static MACHINE_DEPENDENT: LazyLock<Vec<&'static str>> =
    LazyLock::new(|| per_job().filter(|f| f.machine_dependent).map(|f| f.name).collect());

/// Per-job values of every joint of a bridge given by its modes, stored in
/// `/joints/<k>/<name>` (k from 0, in the order of `[[joints]]`), in this
/// order: name and units ([`quakejoint_model::run::JointResult::scalars`]),
/// with the joint's validity bits beside them.
pub static JOINT_FIELDS: LazyLock<Vec<(&'static str, &'static str)>> = LazyLock::new(|| {
    quakejoint_model::run::JointResult::default().scalars().iter().map(|&(name, _, units)| (name, units)).collect()
});

fn per_job() -> impl Iterator<Item = &'static quakejoint_model::fields::Field> {
    quakejoint_model::fields::FIELDS.iter().filter(|f| f.per_job)
}

/// Job status codes in `/spectrum/with_joint/status`.
pub mod status {
    /// Finished.
    pub const OK: i32 = 0;
    /// The simulation failed (the message says why).
    pub const FAILED: i32 = 1;
    /// The job's parameters are invalid (a case that cannot be built).
    pub const INVALID: i32 = 2;
    /// Stopped by the per-job wall-clock or step limit.
    pub const LIMIT: i32 = 3;
    /// Not run (another shard's job, or not reached yet).
    pub const NOT_RUN: i32 = -1;
}

/// The outcome of one job, as journalled.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct JobResult {
    /// Flat job index.
    pub job: u32,
    /// Status code ([`status`]).
    pub status: i32,
    /// Why it failed (empty when it did not).
    pub message: String,
    /// Values in [`FIELDS`] order (NaN when failed).
    pub values: Vec<f64>,
    /// Validity flags of the run (`quakejoint_model::validity::Flags` bits):
    /// 0 when it finished valid, `NOT_CHECKED` when it failed (the arrays
    /// hold `NOT_CHECKED` for a job not run either).
    pub validity: u32,
    /// What the flags found, when and where (empty when valid).
    pub findings: String,
    /// Histories, if requested for this period.
    /// (the series of [`Histories::for_sweep`]).
    pub history: Option<Histories>,
    /// Every joint of a bridge given by its modes, in their order (empty
    /// when the job failed, or with one joint).
    pub joints: Vec<JointJobResult>,
}

/// One more joint's outcome of a job.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct JointJobResult {
    /// Values in [`JOINT_FIELDS`] order.
    pub values: Vec<f64>,
    /// Its validity flags.
    pub validity: u32,
}

/// The arrays of one joint.
#[derive(Debug, Clone, PartialEq)]
pub struct JointResults {
    /// Its name (`[[joints]]`).
    pub name: String,
    /// `values[field][job]`, fields in [`JOINT_FIELDS`] order (NaN where
    /// the job failed or did not run).
    pub values: Vec<Vec<f64>>,
    /// Its validity flags per job (`NOT_CHECKED` where the job failed or
    /// did not run).
    pub validity: Vec<u32>,
}

impl JointResults {
    /// Empty arrays of `jobs` jobs.
    pub fn new(name: &str, jobs: usize) -> Self {
        Self {
            name: name.to_string(),
            values: vec![vec![f64::NAN; jobs]; JOINT_FIELDS.len()],
            validity: vec![quakejoint_model::validity::Flags::NOT_CHECKED.0; jobs],
        }
    }

    fn set(&mut self, job: usize, r: Option<&JointJobResult>) {
        for (k, f) in self.values.iter_mut().enumerate() {
            f[job] = r.and_then(|r| r.values.get(k).copied()).unwrap_or(f64::NAN);
        }
        self.validity[job] = r.map_or(quakejoint_model::validity::Flags::NOT_CHECKED.0, |r| r.validity);
    }

    /// Whether job `j` holds the same values and flags, bit for bit, in
    /// `self` and `other`.
    pub fn same_job(&self, other: &JointResults, j: usize) -> bool {
        self.validity[j] == other.validity[j]
            && self.values.iter().zip(&other.values).all(|(a, b)| a[j].to_bits() == b[j].to_bits())
    }

    /// Copies job `j` from `from`.
    pub fn copy_job(&mut self, from: &JointResults, j: usize) {
        for (a, b) in self.values.iter_mut().zip(&from.values) {
            a[j] = b[j];
        }
        self.validity[j] = from.validity[j];
    }
}

/// The arrays of a sweep.
#[derive(Debug, Clone, PartialEq)]
pub struct Results {
    /// (cases, records, dampings, periods).
    pub dims: [usize; 4],
    /// `values[field][job]`.
    pub values: Vec<Vec<f64>>,
    /// Status of each job.
    pub status: Vec<i32>,
    /// Message of each job.
    pub messages: Vec<String>,
    /// Validity flags of each job.
    pub validity: Vec<u32>,
    /// What the flags of each job found.
    pub findings: Vec<String>,
    /// Histories by job.
    pub histories: std::collections::BTreeMap<u32, Histories>,
    /// Without the joint: `[sa, psa, sd, sv][(record, damping, period)]`,
    /// or `[(case, record, damping, period)]` when `without_per_case`.
    pub without: [Vec<f64>; 4],
    /// Whether the bridge alone differs between the cases (a bridge given
    /// by its modes: a case may keep other modes, or place its joint
    /// elsewhere), so that `without` has a case axis.
    pub without_per_case: bool,
    /// Every joint of a bridge given by its modes.
    pub joints: Vec<JointResults>,
}

impl Results {
    /// Empty arrays (every job not run).
    pub fn new(dims: [usize; 4]) -> Self {
        let n: usize = dims.iter().product();
        let m = dims[1] * dims[2] * dims[3];
        Self {
            dims,
            values: vec![vec![f64::NAN; n]; FIELDS.len()],
            status: vec![status::NOT_RUN; n],
            messages: vec![String::new(); n],
            validity: vec![quakejoint_model::validity::Flags::NOT_CHECKED.0; n],
            findings: vec![String::new(); n],
            histories: Default::default(),
            without: [vec![f64::NAN; m], vec![f64::NAN; m], vec![f64::NAN; m], vec![f64::NAN; m]],
            without_per_case: false,
            joints: Vec::new(),
        }
    }

    /// Empty arrays of a sweep over a bridge given by its modes: the
    /// bridge alone per case, and the arrays of the joints after the
    /// first, named `joints`.
    pub fn modal(dims: [usize; 4], joints: &[String]) -> Self {
        let n: usize = dims.iter().product();
        Self {
            without: [vec![f64::NAN; n], vec![f64::NAN; n], vec![f64::NAN; n], vec![f64::NAN; n]],
            without_per_case: true,
            joints: joints.iter().map(|name| JointResults::new(name, n)).collect(),
            ..Self::new(dims)
        }
    }

    /// Empty arrays shaped as `self`'s (the same grid, bridge alone and
    /// joints), with `self`'s results without the joint.
    pub fn empty_like(&self) -> Self {
        let n = self.status.len();
        Self {
            without: self.without.clone(),
            without_per_case: self.without_per_case,
            joints: self.joints.iter().map(|j| JointResults::new(&j.name, n)).collect(),
            ..Self::new(self.dims)
        }
    }

    /// The index into `without` of job `j`.
    pub fn without_index(&self, j: usize) -> usize {
        j % self.without[0].len().max(1)
    }

    /// Stores one job's outcome.
    pub fn insert(&mut self, r: JobResult) {
        let j = r.job as usize;
        for (f, v) in self.values.iter_mut().zip(&r.values) {
            f[j] = *v;
        }
        self.status[j] = r.status;
        self.messages[j] = r.message;
        self.validity[j] = r.validity;
        self.findings[j] = r.findings;
        for (k, joint) in self.joints.iter_mut().enumerate() {
            joint.set(j, r.joints.get(k));
        }
        if let Some(h) = r.history {
            self.histories.insert(r.job, h);
        }
    }

    /// Forgets one job's outcome (it is to be run again).
    pub fn clear(&mut self, job: usize) {
        for f in &mut self.values {
            f[job] = f64::NAN;
        }
        self.status[job] = status::NOT_RUN;
        self.messages[job].clear();
        self.validity[job] = quakejoint_model::validity::Flags::NOT_CHECKED.0;
        self.findings[job].clear();
        for joint in &mut self.joints {
            joint.set(job, None);
        }
        self.histories.remove(&(job as u32));
    }

    /// Jobs finished (any status but not run).
    pub fn finished(&self) -> usize {
        self.status.iter().filter(|&&s| s != status::NOT_RUN).count()
    }

    /// Jobs that failed.
    pub fn failed(&self) -> usize {
        self.status.iter().filter(|&&s| s != status::NOT_RUN && s != status::OK).count()
    }

    /// Finished jobs flagged as outside the model's validity.
    pub fn flagged(&self) -> usize {
        self.validity.iter().zip(&self.status).filter(|&(&v, &s)| Flags(v).is_flagged() && s == status::OK).count()
    }

    /// Index of a field in [`FIELDS`].
    pub fn field(name: &str) -> usize {
        FIELDS.iter().position(|&f| f == name).expect("known field")
    }

    /// Job `j`'s values of the per-job field `field` (index into
    /// [`FIELDS`]): on a bridge with several joints, every joint's own
    /// (`/joints/<k>`) where each joint has the field, else the run's
    /// (the first joint's); one value with a single joint.
    pub fn joint_values(&self, j: usize, field: usize) -> Vec<f64> {
        let own = JOINT_FIELDS.iter().position(|(name, _)| *name == FIELDS[field]);
        match own {
            Some(i) if !self.joints.is_empty() => self.joints.iter().map(|joint| joint.values[i][j]).collect(),
            _ => vec![self.values[field][j]],
        }
    }

    /// `1 - sa_with / sa_without` for every job.
    pub fn reduction(&self) -> Vec<f64> {
        let sa = &self.values[Self::field("sa")];
        sa.iter().enumerate().map(|(j, &s)| 1.0 - s / self.without[0][self.without_index(j)]).collect()
    }
}
