//! `/fragility` of a sweep file (layout in `docs/hdf5-layout.md`): the
//! stripes, the limit states' definitions, every run's outcome, the
//! counts and the fitted curves. Written from the results at every
//! write; read back, it is computed again from the results and must
//! agree bit for bit.

use ndarray::{ArrayView3, ArrayView4};

use quakejoint_io::h5::{array, attr_str, label_axes, scalar, strings, strings_1d};
use quakejoint_io::read::{attr, group, number, text, values};

use std::sync::Arc;

use super::eval::{evaluate, LimitStateResult, Memo};
use super::spec::FragilitySpec;
use crate::plan::{Measure, StripeRun, Stripes};
use crate::results::Results;

/// The fitting method's version (`/fragility` attribute `method`): 5
/// (2: separated bootstrap resamples entering the intervals at beta = 0;
/// 3: counts that fall with the intensity, or a beta beyond 10, refused,
/// and the notes on what a fit rests on beyond the data; 4: the interval
/// of the annual frequency; 5: the annual frequency in closed form, and
/// each bootstrap's key and counts stored, so that a read takes the
/// intervals from the file instead of resampling again). A
/// file of another method has its counts checked on reading, not its fits,
/// which this program would compute otherwise (it writes its own).
pub const METHOD: u32 = 5;

/// A sweep's stripes and what is fitted on them.
#[derive(Debug, Clone)]
pub struct StoredFragility {
    /// The stripes.
    pub stripes: Stripes,
    /// The limit states, hazard and fitting.
    pub spec: FragilitySpec,
    /// The bootstrap intervals computed or read so far.
    pub memo: Arc<Memo>,
}

/// Two sweeps' fragilities are the same when their stripes and specs are.
impl PartialEq for StoredFragility {
    fn eq(&self, other: &Self) -> bool {
        (&self.stripes, &self.spec) == (&other.stripes, &other.spec)
    }
}

impl StoredFragility {
    /// The stripes and spec, with no intervals known yet.
    pub fn new(stripes: Stripes, spec: FragilitySpec) -> Self {
        Self { stripes, spec, memo: Arc::default() }
    }

    /// Every limit state on `results` (the intervals known taken as known).
    pub fn evaluate(&self, results: &Results) -> Vec<LimitStateResult> {
        evaluate(&self.spec, &self.stripes, results, &self.memo)
    }
}

/// What each curve's bootstrap stored beside its intervals: the key of
/// its inputs and its counts of separated and undetermined resamples.
const BOOTSTRAP_FIELDS: [(&str, &str); 2] = [
    ("bootstrap_separated", "bootstrap resamples with separated counts (entered at beta = 0)"),
    ("bootstrap_undetermined", "bootstrap resamples that determined no fragility (left out)"),
];

fn shape_err(e: ndarray::ShapeError) -> hdf5::Error {
    hdf5::Error::from(e.to_string())
}

/// The datasets of a curve, per case, damping ratio and period.
const CURVE_FIELDS: [(&str, &str, &str); 13] = [
    ("median", "g", "the fragility's median: the level at which half the runs exceed the limit state"),
    ("beta", "1", "the fragility's dispersion (lognormal standard deviation)"),
    ("se_ln_median", "1", "standard error of ln(median) from the likelihood's curvature"),
    ("se_beta", "1", "standard error of beta from the likelihood's curvature"),
    ("log_likelihood", "1", "the binomial log-likelihood at the fit"),
    ("median_lo", "g", "lower end of the bootstrap interval of the median"),
    ("median_hi", "g", "upper end of the bootstrap interval of the median"),
    ("beta_lo", "1", "lower end of the bootstrap interval of beta"),
    ("beta_hi", "1", "upper end of the bootstrap interval of beta"),
    ("annual_frequency", "1/year", "mean annual frequency of exceeding the limit state at the site"),
    ("return_period", "year", "1 / annual_frequency"),
    ("annual_frequency_lo", "1/year", "lower end of the bootstrap interval of annual_frequency"),
    ("annual_frequency_hi", "1/year", "upper end of the bootstrap interval of annual_frequency"),
];

/// The counts of a curve, per case, damping ratio, period and stripe.
const COUNT_FIELDS: [(&str, &str); 6] = [
    ("runs", "runs that count"),
    ("exceeded", "of them, runs that exceeded the limit state"),
    ("failed", "failed runs (left out, or counted as exceeding: the group's attribute failed)"),
    ("not_run", "runs not run (another shard's, or not reached yet)"),
    ("undetermined", "finished runs that do not report what the limit state tests (left out)"),
    ("flagged", "runs counted that the model flags for another reason than the limit state"),
];

/// An array of `/fragility/<key>` by its name.
pub type Named<T> = (&'static str, Vec<T>);

/// The per-curve arrays of a limit state as `/fragility/<key>` stores
/// them: name, units and values (case, damping, period).
pub fn curve_arrays(r: &LimitStateResult) -> Vec<(&'static str, &'static str, Vec<f64>)> {
    CURVE_FIELDS.iter().zip(curve_values(r)).map(|(&(name, units, _), v)| (name, units, v)).collect()
}

/// The per-stripe counts of a limit state (case, damping, period, stripe)
/// and its bootstrap's counts (case, damping, period), by name, as
/// `/fragility/<key>` stores them.
pub fn count_arrays(r: &LimitStateResult) -> (Vec<Named<u32>>, Vec<Named<u32>>) {
    let counts = COUNT_FIELDS.iter().zip(count_values(r)).map(|(&(name, _), v)| (name, v)).collect();
    let boot = BOOTSTRAP_FIELDS.iter().zip(bootstrap_counts(r)).map(|(&(name, _), v)| (name, v)).collect();
    (counts, boot)
}

fn curve_values(r: &LimitStateResult) -> [Vec<f64>; 13] {
    let nan = f64::NAN;
    let mut out: [Vec<f64>; 13] = Default::default();
    for c in &r.curves {
        let f = c.fit;
        let i = c.intervals.as_ref();
        let v = [
            f.map_or(nan, |f| f.median),
            f.map_or(nan, |f| f.beta),
            f.map_or(nan, |f| f.se_ln_median),
            f.map_or(nan, |f| f.se_beta),
            f.map_or(nan, |f| f.log_likelihood),
            i.map_or(nan, |i| i.median[0]),
            i.map_or(nan, |i| i.median[1]),
            i.map_or(nan, |i| i.beta[0]),
            i.map_or(nan, |i| i.beta[1]),
            c.annual_frequency,
            1.0 / c.annual_frequency,
            i.and_then(|i| i.annual_frequency).map_or(nan, |a| a[0]),
            i.and_then(|i| i.annual_frequency).map_or(nan, |a| a[1]),
        ];
        for (o, x) in out.iter_mut().zip(v) {
            o.push(x);
        }
    }
    out
}

fn count_values(r: &LimitStateResult) -> [Vec<u32>; 6] {
    let mut out: [Vec<u32>; 6] = Default::default();
    for c in &r.curves {
        for k in &c.counts {
            for (o, x) in out.iter_mut().zip([k.runs, k.exceeded, k.failed, k.not_run, k.undetermined, k.flagged]) {
                o.push(x);
            }
        }
    }
    out
}

/// Writes `/fragility`; `axes` names the sweep's four axes (case, record,
/// damping, and period or period_scale).
pub fn write_fragility(file: &hdf5::File, f: &StoredFragility, results: &Results, axes: [&str; 4]) -> hdf5::Result<()> {
    let (s, spec) = (&f.stripes, &f.spec);
    let g = file.create_group("fragility")?;
    attr_str(&g, "measure", s.measure.key())?;
    attr_str(&g, "measure_label", &s.measure.label())?;
    attr_str(&g, "units", "g")?;
    g.new_attr::<u32>().create("method")?.write_scalar(&METHOD)?;
    if let Measure::Sa { period, damping } = s.measure {
        scalar(&g, "measure_period", period, "s")?;
        scalar(&g, "measure_damping", damping, "1")?;
    }
    attr_str(&g, "config", &toml::to_string(&spec.to_toml()).unwrap_or_default())?;
    attr_str(&g, "failed", spec.failed.key())?;
    let levels = array(&g, "levels", &s.levels[..])?;
    attr_str(&levels, "units", "g")?;
    label_axes(&levels, &["stripe"])?;
    let names: Vec<String> = s.ground.iter().map(|g| g.0.clone()).collect();
    strings_1d(&g, "ground_record", &names)?;
    let im: Vec<f64> = s.ground.iter().map(|g| g.1).collect();
    let ds = array(&g, "ground_intensity", &im[..])?;
    attr_str(&ds, "units", "g")?;
    attr_str(&ds, "meaning", "each record's intensity as read, over the runs' window")?;
    let rg: Vec<u32> = s.runs.iter().map(|r| r.ground as u32).collect();
    let rs: Vec<u32> = s.runs.iter().map(|r| r.stripe as u32).collect();
    let rf: Vec<f64> = s.runs.iter().map(|r| r.factor).collect();
    for (meaning, ds) in [
        ("index into ground_record of each record of the sweep", array(&g, "record_ground", &rg[..])?),
        ("index into levels of each record of the sweep", array(&g, "record_stripe", &rs[..])?),
        ("the factor on the record as read", array(&g, "record_factor", &rf[..])?),
    ] {
        attr_str(&ds, "meaning", meaning)?;
        attr_str(&ds, "units", "1")?;
        label_axes(&ds, &[axes[1]])?;
    }
    if let Some(h) = &spec.hazard {
        let (i, q): (Vec<f64>, Vec<f64>) = h.curve.points().iter().copied().unzip();
        let ds = array(&g, "hazard_intensity", &i[..])?;
        attr_str(&ds, "units", "g")?;
        let ds = array(&g, "hazard_frequency", &q[..])?;
        attr_str(&ds, "units", "1/year")?;
        attr_str(&g, "hazard_source", &h.source)?;
    }
    let [nc, nr, nz, nt] = results.dims;
    let ns = s.levels.len();
    let curve_axes = [axes[0], axes[2], axes[3]];
    for (k, (ls, r)) in spec.limit_states.iter().zip(f.evaluate(results)).enumerate() {
        let lg = g.create_group(&ls.key)?;
        lg.new_attr::<u32>().create("index")?.write_scalar(&(k as u32))?;
        attr_str(&lg, "name", &ls.name)?;
        attr_str(&lg, "kind", &ls.kind)?;
        attr_str(&lg, "definition", &ls.definition)?;
        let view = ArrayView4::from_shape((nc, nr, nz, nt), &r.outcome[..]).map_err(shape_err)?;
        let ds = array(&lg, "outcome", view)?;
        label_axes(&ds, &axes)?;
        attr_str(&ds, "meaning", "1 exceeded, 0 not, -1 failed, -2 not run, -3 not reported by the run (NaN)")?;
        attr_str(&ds, "units", "1")?;
        for ((name, meaning), data) in COUNT_FIELDS.iter().zip(count_values(&r)) {
            let view = ArrayView4::from_shape((nc, nz, nt, ns), &data[..]).map_err(shape_err)?;
            let ds = array(&lg, name, view)?;
            label_axes(&ds, &[curve_axes[0], curve_axes[1], curve_axes[2], "stripe"])?;
            attr_str(&ds, "meaning", meaning)?;
            attr_str(&ds, "units", "1")?;
        }
        for ((name, units, meaning), data) in CURVE_FIELDS.iter().zip(curve_values(&r)) {
            let view = ArrayView3::from_shape((nc, nz, nt), &data[..]).map_err(shape_err)?;
            let ds = array(&lg, name, view)?;
            label_axes(&ds, &curve_axes)?;
            attr_str(&ds, "units", units)?;
            attr_str(&ds, "meaning", meaning)?;
        }
        let notes: Vec<String> = r.curves.iter().map(|c| c.note.clone()).collect();
        let ds = strings(&lg, "note", &notes, &[nc, nz, nt])?;
        label_axes(&ds, &curve_axes)?;
        let keys: Vec<String> = r.curves.iter().map(|c| c.bootstrap_key.clone()).collect();
        let ds = strings(&lg, "bootstrap_key", &keys, &[nc, nz, nt])?;
        attr_str(&ds, "meaning", "SHA-256 of the bootstrap's inputs (empty: no bootstrap)")?;
        label_axes(&ds, &curve_axes)?;
        let checks: Vec<String> = r.curves.iter().map(check_of).collect();
        let ds = strings(&lg, "bootstrap_check", &checks, &[nc, nz, nt])?;
        attr_str(
            &ds,
            "meaning",
            "SHA-256 of the key with the intervals and counts stored for it (empty: no bootstrap)",
        )?;
        label_axes(&ds, &curve_axes)?;
        for ((name, meaning), data) in BOOTSTRAP_FIELDS.iter().zip(bootstrap_counts(&r)) {
            let view = ArrayView3::from_shape((nc, nz, nt), &data[..]).map_err(shape_err)?;
            let ds = array(&lg, name, view)?;
            label_axes(&ds, &curve_axes)?;
            attr_str(&ds, "units", "1")?;
            attr_str(&ds, "meaning", meaning)?;
        }
    }
    Ok(())
}

fn bootstrap_counts(r: &LimitStateResult) -> [Vec<u32>; 2] {
    let of = |f: fn(&quakejoint_model::fragility::Intervals) -> usize| {
        r.curves.iter().map(|c| c.intervals.as_ref().map_or(0, |i| f(i) as u32)).collect()
    };
    [of(|i| i.separated), of(|i| i.undetermined)]
}

/// The SHA-256 (hex) of a curve's bootstrap key with the intervals and
/// counts stored for it (empty without a bootstrap): a value of them
/// rewritten in the file, checksum and all, no longer matches it.
fn check_of(c: &super::Curve) -> String {
    match &c.intervals {
        Some(i) if !c.bootstrap_key.is_empty() => interval_check(&c.bootstrap_key, i),
        _ => String::new(),
    }
}

fn interval_check(key: &str, i: &quakejoint_model::fragility::Intervals) -> String {
    let mut bytes = key.as_bytes().to_vec();
    let a = i.annual_frequency.unwrap_or([f64::NAN; 2]);
    for x in [i.median[0], i.median[1], i.beta[0], i.beta[1], a[0], a[1]] {
        bytes.extend(x.to_bits().to_le_bytes());
    }
    bytes.extend((i.separated as u64).to_le_bytes());
    bytes.extend((i.undetermined as u64).to_le_bytes());
    quakejoint_motion::sha256_hex(&bytes)
}

/// Gives `memo` the intervals each curve of the limit state group `lg`
/// stored under its bootstrap's key, once they match their check.
fn remember(lg: &hdf5::Group, spec: &FragilitySpec, memo: &Memo) -> hdf5::Result<()> {
    let keys = text(lg, "bootstrap_key")?;
    let checks = text(lg, "bootstrap_check")?;
    let f = |name: &str| values::<f64>(lg, name);
    let (m0, m1, b0, b1) = (f("median_lo")?, f("median_hi")?, f("beta_lo")?, f("beta_hi")?);
    let (a0, a1) = (f("annual_frequency_lo")?, f("annual_frequency_hi")?);
    let (sep, und) = (values::<u32>(lg, BOOTSTRAP_FIELDS[0].0)?, values::<u32>(lg, BOOTSTRAP_FIELDS[1].0)?);
    let n = keys.len();
    let lengths = [m0.len(), m1.len(), b0.len(), b1.len(), a0.len(), a1.len(), sep.len(), und.len(), checks.len()];
    if lengths.iter().any(|&l| l != n) {
        return Err(hdf5::Error::from(format!("{}: the bootstrap's arrays do not match its keys", lg.name())));
    }
    for (i, key) in keys.into_iter().enumerate().filter(|(_, k)| !k.is_empty()) {
        let intervals = quakejoint_model::fragility::Intervals {
            level: spec.confidence,
            median: [m0[i], m1[i]],
            beta: [b0[i], b1[i]],
            annual_frequency: spec.hazard.as_ref().map(|_| [a0[i], a1[i]]),
            undetermined: und[i] as usize,
            separated: sep[i] as usize,
        };
        if interval_check(&key, &intervals) != checks[i] {
            return Err(crate::sweep_read::disagrees(
                &format!("{}/bootstrap_check", lg.name()),
                "the bootstrap's key, intervals and counts",
            ));
        }
        memo.insert(key, intervals);
    }
    Ok(())
}

/// Reads `/fragility`'s definitions (None when the sweep has no stripes)
/// and checks every stored array against the one computed again from
/// `results`.
pub fn read_fragility(file: &hdf5::File, results: &Results) -> hdf5::Result<Option<StoredFragility>> {
    if !file.link_exists("fragility") {
        return Ok(None);
    }
    let g = group(file, "fragility")?;
    let measure = match attr(&g, "measure")?.as_str() {
        "sa" => Measure::Sa { period: number(&g, "measure_period")?, damping: number(&g, "measure_damping")? },
        "pga" => Measure::Pga,
        other => return Err(hdf5::Error::from(format!("/fragility attribute measure {other:?}: not sa or pga"))),
    };
    let levels: Vec<f64> = values(&g, "levels")?;
    let names = text(&g, "ground_record")?;
    let im: Vec<f64> = values(&g, "ground_intensity")?;
    let rg: Vec<u32> = values(&g, "record_ground")?;
    let rs: Vec<u32> = values(&g, "record_stripe")?;
    let rf: Vec<f64> = values(&g, "record_factor")?;
    let fits = names.len() == im.len()
        && rg.len() == results.dims[1]
        && rs.len() == rg.len()
        && rf.len() == rg.len()
        && rg.iter().all(|&x| (x as usize) < names.len())
        && rs.iter().all(|&x| (x as usize) < levels.len());
    if !fits {
        return Err(hdf5::Error::from("/fragility: the stripes do not match the sweep's records"));
    }
    let runs = rg
        .iter()
        .zip(&rs)
        .zip(&rf)
        .map(|((&ground, &stripe), &factor)| StripeRun { ground: ground as usize, stripe: stripe as usize, factor })
        .collect();
    let stripes = Stripes { measure, levels, ground: names.into_iter().zip(im).collect(), runs };
    let config: toml::Table = toml::from_str(&attr(&g, "config")?)
        .map_err(|e| hdf5::Error::from(format!("/fragility attribute config: {e}")))?;
    let mut spec = FragilitySpec::from_toml(Some(&toml::Value::Table(config)), std::path::Path::new("."))
        .map_err(|e| hdf5::Error::from(format!("/fragility attribute config: {e}")))?;
    if let Some(h) = &mut spec.hazard {
        // the curve's points stored as arrays are the ones the config holds
        let stored: Vec<(f64, f64)> =
            values::<f64>(&g, "hazard_intensity")?.into_iter().zip(values::<f64>(&g, "hazard_frequency")?).collect();
        if !crate::sweep_read::same_bits(
            &stored.iter().flat_map(|p| [p.0, p.1]).collect::<Vec<_>>(),
            &h.curve.points().iter().flat_map(|p| [p.0, p.1]).collect::<Vec<_>>(),
        ) {
            return Err(crate::sweep_read::disagrees(
                "/fragility/hazard_intensity and hazard_frequency",
                "the hazard curve of the attribute config",
            ));
        }
        h.source = attr(&g, "hazard_source")?;
    } else if g.link_exists("hazard_intensity") || g.link_exists("hazard_frequency") {
        return Err(hdf5::Error::from("/fragility holds a hazard curve its attribute config does not"));
    }
    let disagrees = |what: String| crate::sweep_read::disagrees(&what, "the results");
    let same_method = g.attr("method").and_then(|a| a.read_scalar::<u32>()).ok() == Some(METHOD);
    let stored = StoredFragility::new(stripes, spec);
    if same_method {
        for ls in &stored.spec.limit_states {
            remember(&group(&g, &ls.key)?, &stored.spec, &stored.memo)?;
        }
    }
    for (ls, r) in stored.spec.limit_states.iter().zip(stored.evaluate(results)) {
        let lg = group(&g, &ls.key)?;
        let path = |name: &str| format!("/fragility/{}/{name}", ls.key);
        if values::<i8>(&lg, "outcome")? != r.outcome {
            return Err(disagrees(path("outcome")));
        }
        for ((name, _), data) in COUNT_FIELDS.iter().zip(count_values(&r)) {
            if values::<u32>(&lg, name)? != data {
                return Err(disagrees(path(name)));
            }
        }
        for ((name, _, _), data) in CURVE_FIELDS.iter().zip(curve_values(&r)) {
            if !same_method && !lg.link_exists(name) {
                // a dataset of a later method
                continue;
            }
            let stored = values::<f64>(&lg, name)?;
            if same_method && !crate::sweep_read::same_bits(&stored, &data) {
                return Err(disagrees(path(name)));
            }
        }
        if !same_method {
            continue;
        }
        let notes: Vec<String> = r.curves.iter().map(|c| c.note.clone()).collect();
        if text(&lg, "note")? != notes {
            return Err(disagrees(path("note")));
        }
        let keys: Vec<String> = r.curves.iter().map(|c| c.bootstrap_key.clone()).collect();
        if text(&lg, "bootstrap_key")? != keys {
            return Err(disagrees(path("bootstrap_key")));
        }
        let checks: Vec<String> = r.curves.iter().map(check_of).collect();
        if text(&lg, "bootstrap_check")? != checks {
            return Err(disagrees(path("bootstrap_check")));
        }
        for ((name, _), data) in BOOTSTRAP_FIELDS.iter().zip(bootstrap_counts(&r)) {
            if values::<u32>(&lg, name)? != data {
                return Err(disagrees(path(name)));
            }
        }
    }
    Ok(Some(stored))
}
