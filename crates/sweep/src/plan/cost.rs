//! The cost of a sweep's jobs: the cost model of a coupled run
//! ([`cost_seconds`]), the sharding of the jobs by cost, and the time and
//! memory of running some of them in one process ([`Estimate`]).

use quakejoint_model::Config;

use super::records::SweepRecord;
use super::{Job, Plan};

impl Plan {
    /// Estimated cost of a job: seconds on one core of the reference machine
    /// ([`cost_seconds`]).
    pub fn cost(&self, job: Job) -> f64 {
        let case = &self.cases[job.case];
        let record = &self.records[job.record].record;
        let duration = quakejoint_model::run::run_duration(&case.config, record);
        cost_seconds(case.bodies, duration / record.dt, self.periods[job.period])
    }

    /// The jobs of shard `k` of `n` (1-based `k`): jobs sorted by decreasing
    /// cost are dealt to the currently lightest shard (longest processing
    /// time first), which balances cost and depends only on the plan.
    pub fn shard(&self, k: usize, n: usize) -> Vec<usize> {
        let mut order: Vec<usize> = (0..self.job_count()).collect();
        order.sort_by(|&a, &b| self.cost(self.job(b)).total_cmp(&self.cost(self.job(a))).then(a.cmp(&b)));
        let mut load = vec![0.0f64; n];
        let mut mine = Vec::new();
        for i in order {
            let s = (0..n).min_by(|&x, &y| load[x].total_cmp(&load[y]).then(x.cmp(&y))).unwrap_or(0);
            load[s] += self.cost(self.job(i));
            if s + 1 == k {
                mine.push(i);
            }
        }
        mine.sort_unstable();
        mine
    }
}

/// What running some jobs of a plan in one process takes.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Estimate {
    /// Jobs.
    pub jobs: usize,
    /// Cost-model seconds on one core of the reference machine (the wall
    /// time on one thread; on `t` threads about this divided by `t`).
    pub seconds: f64,
    /// Peak resident memory of the process \[MB\].
    pub memory_mb: f64,
}

impl Plan {
    /// The time and memory of running `jobs` (flat indices) in one process
    /// with `threads` workers (docs/sweep.md, "Cost of a job"). The memory
    /// is that of the measured components: the program and HDF5 library,
    /// the records, the result arrays and the stored histories (each held
    /// three times: arrays, journal frame, HDF5 write), and one model per
    /// worker; the sweep reports its measured peak (`peak_memory_mb`), which
    /// a test keeps below this estimate.
    pub fn estimate(&self, jobs: &[usize], threads: usize) -> Estimate {
        const MB: f64 = 1.0 / (1024.0 * 1024.0);
        let seconds = jobs.iter().map(|&j| self.cost(self.job(j))).sum();
        let samples = |r: &SweepRecord| r.record.acceleration.len() as f64;
        let record_bytes: f64 = self.records.iter().chain(&self.record_y).map(|r| samples(r) * 8.0 * 3.0).sum();
        let longest = self.records.iter().map(samples).fold(0.0, f64::max);
        let joints = self.modal.as_ref().map_or(0, |m| m.joints.len()) as f64;
        let per_job =
            crate::results::FIELDS.len() as f64 + 4.0 + joints * (crate::results::JOINT_FIELDS.len() as f64 + 1.0);
        let result_bytes = self.job_count() as f64 * (per_job * 8.0) * 3.0;
        let histories = self.history_periods.len() * self.job_count() / self.periods.len().max(1);
        // seven series, the clear sub-gaps at both ends and their contact
        // forces, Nc + 1 of each
        let gaps = self.cases.iter().filter(|c| c.config.joint.enabled).map(|c| c.config.joint.center_beams + 1).max();
        let history_bytes = histories as f64 * longest * (7 + 3 * gaps.unwrap_or(0)) as f64 * 8.0 * 3.0;
        let bodies = self.cases.iter().map(|c| c.bodies).max().unwrap_or(0) as f64;
        let worker_mb = MEMORY_PER_WORKER_MB + MEMORY_PER_BODY_MB * bodies + longest * 8.0 * 6.0 * MB;
        let memory_mb = MEMORY_BASE_MB
            + (record_bytes + result_bytes + history_bytes) * MB
            + threads.max(1).min(jobs.len().max(1)) as f64 * worker_mb;
        Estimate { jobs: jobs.len(), seconds, memory_mb }
    }
}

/// Memory of the program, the HDF5 library and the allocator \[MB\].
pub const MEMORY_BASE_MB: f64 = 18.0;
/// Memory of a worker without its model \[MB\].
pub const MEMORY_PER_WORKER_MB: f64 = 1.0;
/// Memory of a worker's model per joint body \[MB\].
pub const MEMORY_PER_BODY_MB: f64 = 0.025;

/// Seconds per output sample of a job, whatever the model ([`cost_seconds`]).
pub const COST_PER_SAMPLE: f64 = 4.0e-6;
/// Seconds per joint body and output sample ([`cost_seconds`]).
pub const COST_PER_BODY_SAMPLE: f64 = 1.45e-6;

/// The cost model of a coupled run, measured on this engine (docs/sweep.md,
/// "Cost of a job"): seconds on one core of the reference machine for a
/// joint of `bodies` rigid bodies, `samples` output samples (the steps never
/// cross a sample, so the step count follows the sample count) and bridge
/// period `period` \[s\]:
/// `samples * (COST_PER_SAMPLE + COST_PER_BODY_SAMPLE * bodies) * f(T)` with
/// `f(T) = 1 - 0.45 exp(-(T / 0.2 s)^2)`: a stiff bridge (short period)
/// barely moves the joint, so its friction rarely reverses and Newton needs
/// fewer iterations (T = 0.1 s costs about 60 % of T = 1 s).
pub fn cost_seconds(bodies: usize, samples: f64, period: f64) -> f64 {
    let f = 1.0 - 0.45 * (-(period / 0.2).powi(2)).exp();
    samples.max(1.0) * (COST_PER_SAMPLE + COST_PER_BODY_SAMPLE * bodies as f64) * f
}

/// The bodies of a job's model for the cost estimate: the joints' (each
/// of `[[joints]]` on a bridge given by its modes) and, on a bridge given
/// by its modes, one per kept mode (a one-coordinate body: counted as a
/// joint body, an overestimate the cost model was not measured for).
pub(super) fn bodies_of(config: &Config) -> usize {
    let joint = |j: &quakejoint_model::config::JointConfig| {
        if j.enabled {
            let (nc, ns) = (j.center_beams, j.support_beams.len());
            nc + ns + nc * ns
        } else {
            0
        }
    };
    let Some(m) = &config.bridge.modal else { return joint(&config.joint) };
    let joints: usize = if config.joints.is_empty() {
        joint(&config.joint)
    } else {
        config.joints.iter().map(|p| joint(p.joint.as_ref().unwrap_or(&config.joint))).sum()
    };
    let modes = quakejoint_model::modal::loaded(m).map_or(0, |b| b.modes.len().min(m.modes_used.unwrap_or(usize::MAX)));
    joints + modes
}
