//! The limit states evaluated on a sweep's results, counted stripe by
//! stripe and fitted: one curve per case, damping ratio and period.

use quakejoint_model::fragility::{bootstrap_risk, fit, Fragility, FragilityError, Hazard, Intervals, Stripe};
use quakejoint_model::validity::Flags;

use super::spec::{Failed, FragilitySpec, Kind, LimitState};
use crate::plan::Stripes;
use crate::results::{status, Results};

/// A run's outcome for a limit state (`/fragility/<key>/outcome`).
pub mod outcome {
    /// The limit state was exceeded.
    pub const EXCEEDED: i8 = 1;
    /// It was not.
    pub const NOT_EXCEEDED: i8 = 0;
    /// The run failed (stopped, invalid parameters, simulation failed).
    pub const FAILED: i8 = -1;
    /// The run has not run (another shard's, or not reached yet).
    pub const NOT_RUN: i8 = -2;
    /// The run finished but does not report what the limit state tests
    /// (NaN in the field).
    pub const UNDETERMINED: i8 = -3;
}

/// The runs of one stripe for one limit state.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct StripeCounts {
    /// Runs that count.
    pub runs: u32,
    /// Of them, runs that exceeded the limit state.
    pub exceeded: u32,
    /// Failed runs (counted as exceeding, or left out, as the config says).
    pub failed: u32,
    /// Runs not run.
    pub not_run: u32,
    /// Finished runs that do not report what the limit state tests (left out).
    pub undetermined: u32,
    /// Runs counted that the model flags for another reason than the
    /// limit state itself (beams passing through each other, say).
    pub flagged: u32,
}

/// The bootstrap intervals already computed, by the key of their inputs
/// ([`bootstrap_key`]): the resampling, the one costly part of a fit,
/// runs once per set of inputs. A sweep file stores each curve's key
/// beside its intervals, so that reading it back takes them from the file
/// when (and only when) the inputs it recomputes have the same key.
#[derive(Debug, Default)]
pub struct Memo(std::sync::Mutex<std::collections::HashMap<String, Intervals>>);

impl Memo {
    /// The intervals of `key`, computed by `compute` unless known.
    fn get_or(
        &self,
        key: String,
        compute: impl FnOnce() -> Result<Intervals, FragilityError>,
    ) -> Result<Intervals, FragilityError> {
        if let Some(i) = self.lock().get(&key) {
            return Ok(i.clone());
        }
        let i = compute()?;
        self.lock().insert(key, i.clone());
        Ok(i)
    }

    /// Records the intervals of `key` (read from a file).
    pub fn insert(&self, key: String, intervals: Intervals) {
        self.lock().insert(key, intervals);
    }

    fn lock(&self) -> std::sync::MutexGuard<'_, std::collections::HashMap<String, Intervals>> {
        // (a panic while holding it leaves a map of finished entries)
        self.0.lock().unwrap_or_else(std::sync::PoisonError::into_inner)
    }
}

/// The SHA-256 (hex) of everything a curve's bootstrap depends on: the
/// method, the records' outcomes at the stripes, the levels, the number
/// of resamples, the seed, the confidence and the hazard curve.
pub fn bootstrap_key(spec: &FragilitySpec, levels: &[f64], by_record: &[Vec<Option<bool>>]) -> String {
    let mut bytes =
        format!("method {} samples {} seed {} level ", super::h5::METHOD, spec.bootstrap, spec.seed).into_bytes();
    bytes.extend(spec.confidence.to_bits().to_le_bytes());
    for x in levels {
        bytes.extend(x.to_bits().to_le_bytes());
    }
    for record in by_record {
        bytes.push(b'|');
        bytes.extend(record.iter().map(|o| match o {
            Some(true) => 1u8,
            Some(false) => 0,
            None => 2,
        }));
    }
    if let Some(h) = &spec.hazard {
        for (im, rate) in h.curve.points() {
            bytes.extend(im.to_bits().to_le_bytes());
            bytes.extend(rate.to_bits().to_le_bytes());
        }
    }
    quakejoint_motion::sha256_hex(&bytes)
}

/// A limit state's fragility for one case, damping ratio and period.
#[derive(Debug, Clone, PartialEq)]
pub struct Curve {
    /// The counts, stripe by stripe.
    pub counts: Vec<StripeCounts>,
    /// The maximum-likelihood fit (median in g), if the counts determine one.
    pub fit: Option<Fragility>,
    /// Its bootstrap intervals, if asked for and determined.
    pub intervals: Option<Intervals>,
    /// The key of the bootstrap's inputs ([`bootstrap_key`]; empty when
    /// no bootstrap ran).
    pub bootstrap_key: String,
    /// Its mean annual frequency at the site \[1/year\] (NaN without a
    /// hazard curve or a fit).
    pub annual_frequency: f64,
    /// What a user should know about the curve (empty when nothing).
    pub note: String,
}

/// One limit state over the sweep.
#[derive(Debug, Clone, PartialEq)]
pub struct LimitStateResult {
    /// Every job's outcome ([`outcome`]), in the sweep's job order.
    pub outcome: Vec<i8>,
    /// Its curves, by case, damping ratio and period (`(c * nz + z) * nt + t`).
    pub curves: Vec<Curve>,
}

/// A job's outcome for `ls`.
fn outcome_of(ls: &LimitState, spec: &FragilitySpec, r: &Results, j: usize) -> i8 {
    if let Kind::Without { measure, threshold } = ls.test {
        let x = r.without[measure][r.without_index(j)];
        return if x.is_nan() { outcome::NOT_RUN } else { i8::from(x > threshold) };
    }
    match r.status[j] {
        status::NOT_RUN => return outcome::NOT_RUN,
        status::OK => {}
        _ => return if spec.failed == Failed::Exceed { outcome::EXCEEDED } else { outcome::FAILED },
    }
    match ls.test {
        Kind::Flag(f) => i8::from(r.validity[j] & f.0 != 0),
        Kind::Field { field, threshold, above } => {
            let test = |x: f64| (!x.is_nan()).then_some(if above { x > threshold } else { x < threshold });
            // (a joint's own value: every joint's, on a bridge with several)
            let tested: Vec<Option<bool>> = r.joint_values(j, field).into_iter().map(test).collect();
            if tested.contains(&Some(true)) {
                outcome::EXCEEDED
            } else if tested.iter().all(Option::is_none) {
                outcome::UNDETERMINED
            } else {
                outcome::NOT_EXCEEDED
            }
        }
        Kind::Without { .. } => unreachable!("handled above"),
    }
}

/// The limit states of `spec` on `results` (a sweep over `stripes`), with
/// the bootstrap intervals `memo` knows taken from it.
pub fn evaluate(spec: &FragilitySpec, stripes: &Stripes, results: &Results, memo: &Memo) -> Vec<LimitStateResult> {
    let [nc, nr, nz, nt] = results.dims;
    let n = results.status.len();
    spec.limit_states
        .iter()
        .map(|ls| {
            let outcome: Vec<i8> = (0..n).map(|j| outcome_of(ls, spec, results, j)).collect();
            let mut curves = Vec::with_capacity(nc * nz * nt);
            for c in 0..nc {
                for z in 0..nz {
                    for t in 0..nt {
                        let jobs: Vec<usize> = (0..nr).map(|rec| ((c * nr + rec) * nz + z) * nt + t).collect();
                        let tally = Tally::of(ls, stripes, results, &outcome, &jobs);
                        curves.push(curve(spec, stripes, tally, memo));
                    }
                }
            }
            LimitStateResult { outcome, curves }
        })
        .collect()
}

/// The runs of one curve, counted.
struct Tally {
    /// Per stripe.
    counts: Vec<StripeCounts>,
    /// `by_record[g][s]`: record `g`'s outcome at stripe `s` (for the
    /// bootstrap; None: the run does not count).
    by_record: Vec<Vec<Option<bool>>>,
    /// How many counted runs carry each other flag (`capacity_exceeded 3`).
    flagged: Vec<String>,
}

impl Tally {
    /// Counts `jobs` (the curve's job of each record of the sweep).
    fn of(ls: &LimitState, stripes: &Stripes, results: &Results, outcome: &[i8], jobs: &[usize]) -> Self {
        let own = match ls.test {
            Kind::Flag(f) => f.0,
            _ => 0,
        };
        let alone = matches!(ls.test, Kind::Without { .. });
        let mut counts = vec![StripeCounts::default(); stripes.levels.len()];
        let mut by_record = vec![vec![None; stripes.levels.len()]; stripes.ground.len()];
        let mut other = vec![0u32; Flags::ALL.len()];
        for (run, &j) in stripes.runs.iter().zip(jobs) {
            let k = &mut counts[run.stripe];
            let ran_ok = results.status[j] == status::OK;
            if results.status[j] != status::NOT_RUN && !ran_ok && !alone {
                k.failed += 1;
            }
            match outcome[j] {
                o @ (outcome::EXCEEDED | outcome::NOT_EXCEEDED) => {
                    k.runs += 1;
                    k.exceeded += u32::from(o == outcome::EXCEEDED);
                    let flags = Flags(results.validity[j] & !own & !Flags::NOT_CHECKED.0);
                    if ran_ok && !alone && flags.is_flagged() {
                        k.flagged += 1;
                        for (n, (f, _)) in other.iter_mut().zip(Flags::ALL.iter()) {
                            *n += u32::from(flags.contains(*f));
                        }
                    }
                    by_record[run.ground][run.stripe] = Some(o == outcome::EXCEEDED);
                }
                outcome::NOT_RUN => k.not_run += 1,
                outcome::UNDETERMINED => k.undetermined += 1,
                _ => {}
            }
        }
        let flagged =
            Flags::ALL.iter().zip(&other).filter(|(_, &n)| n > 0).map(|((_, name), n)| format!("{name} {n}")).collect();
        Self { counts, by_record, flagged }
    }
}

/// Fits one curve from its tally.
fn curve(spec: &FragilitySpec, stripes: &Stripes, tally: Tally, memo: &Memo) -> Curve {
    let Tally { counts, by_record, flagged } = tally;
    let data: Vec<Stripe> = stripes
        .levels
        .iter()
        .zip(&counts)
        .map(|(&intensity, k)| Stripe { intensity, runs: k.runs, exceeded: k.exceeded })
        .collect();
    let mut notes = Vec::new();
    let (failed, not_run, undetermined) =
        counts.iter().fold((0, 0, 0), |a, k| (a.0 + k.failed, a.1 + k.not_run, a.2 + k.undetermined));
    if failed > 0 {
        notes.push(match spec.failed {
            Failed::Exclude => format!("{failed} failed runs left out (sweep.fragility.failed = \"exclude\")"),
            Failed::Exceed => {
                format!("{failed} failed runs counted as exceeding (sweep.fragility.failed = \"exceed\")")
            }
        });
    }
    if not_run > 0 {
        notes.push(format!("{not_run} runs not run yet (or another shard's): the fit is on the runs finished"));
    }
    if undetermined > 0 {
        notes.push(format!("{undetermined} runs do not report what the limit state tests (NaN): left out"));
    }
    if !flagged.is_empty() {
        notes.push(format!(
            "{} runs counted are flagged by the model for another reason ({}): the curve rests on results the model \
             cannot stand behind",
            counts.iter().map(|k| k.flagged).sum::<u32>(),
            flagged.join(", ")
        ));
    }
    let fitted = fit(&data);
    let mut bootstrap_key = String::new();
    let (fit, intervals, annual_frequency) = match fitted {
        Ok(f) => {
            let hazard = spec.hazard.as_ref().map(|h| &h.curve);
            let intervals = if spec.bootstrap > 0 {
                let levels = &stripes.levels;
                bootstrap_key = self::bootstrap_key(spec, levels, &by_record);
                match memo.get_or(bootstrap_key.clone(), || {
                    bootstrap_risk(&by_record, levels, spec.bootstrap, spec.seed, spec.confidence, hazard)
                }) {
                    Ok(i) => {
                        if i.separated > 0 {
                            notes.push(format!(
                                "{} of {} bootstrap resamples have separated counts: they enter the intervals with \
                                 beta = 0",
                                i.separated, spec.bootstrap
                            ));
                        }
                        if i.undetermined > 0 {
                            notes.push(format!(
                                "{} of {} bootstrap resamples determined no fragility (every run survived or every \
                                 one exceeded): left out of the intervals",
                                i.undetermined, spec.bootstrap
                            ));
                        }
                        Some(i)
                    }
                    Err(e) => {
                        notes.push(format!("no intervals: {e}"));
                        bootstrap_key.clear();
                        None
                    }
                }
            } else {
                None
            };
            let annual = match &spec.hazard {
                Some(h) => h.curve.mean_annual_frequency(&f).unwrap_or_else(|e| {
                    notes.push(format!("no annual frequency: {e}"));
                    f64::NAN
                }),
                None => f64::NAN,
            };
            notes.extend(extrapolation(&f, &data, spec.hazard.as_ref().map(|h| &h.curve)));
            (Some(f), intervals, annual)
        }
        Err(e) => {
            notes.push(format!("no fit: {e}"));
            (None, None, f64::NAN)
        }
    };
    Curve { counts, fit, intervals, bootstrap_key, annual_frequency, note: notes.join("; ") }
}

/// What a fit rests on beyond the data: a median outside the stripes, a
/// dispersion so large that the intensity hardly matters, and, with a
/// hazard curve, a share of the annual frequency above 1 % from below the
/// curve's lowest intensity or from above its highest, where the curve is
/// continued by its end segments' power laws.
fn extrapolation(f: &Fragility, stripes: &[Stripe], hazard: Option<&Hazard>) -> Vec<String> {
    let mut notes = Vec::new();
    let counted = stripes.iter().filter(|s| s.runs > 0).map(|s| s.intensity);
    let (lo, hi) = counted.fold((f64::INFINITY, 0.0f64), |(a, b), x| (a.min(x), b.max(x)));
    if f.median < lo || f.median > hi {
        notes.push(format!(
            "the median ({:.4} g) lies outside the stripes ({lo} to {hi} g): it is extrapolated",
            f.median
        ));
    }
    if f.beta > 1.5 {
        notes.push(format!(
            "beta {:.2}: the limit state hardly depends on the measure over the stripes (a run's outcome is the \
             record's, not the level's)",
            f.beta
        ));
    }
    let Some(h) = hazard else { return notes };
    let parts = h.parts(f);
    let lambda = parts.total();
    if !(lambda.is_finite() && lambda > 0.0) {
        return notes;
    }
    let points = h.points();
    for (share, side, end, which) in [
        (parts.below / lambda, "below", points[0].0, "first"),
        (parts.above / lambda, "above", points[points.len() - 1].0, "last"),
    ] {
        if share > 0.01 {
            let extreme = if side == "below" { "lowest" } else { "highest" };
            notes.push(format!(
                "{:.0} % of the annual frequency comes from {side} the hazard curve's {extreme} intensity ({end} g), \
                 where the curve is continued by its {which} segment's power law",
                100.0 * share.min(1.0)
            ));
        }
    }
    notes
}
