//! The suite and statistics groups of a sweep file (`/suite`,
//! `/spectrum/statistics`; layout in `docs/hdf5-layout.md`).

use ndarray::{ArrayView2, ArrayView3};

use crate::plan::Suite;
use crate::statistics::Statistics;
use quakejoint_io::h5::{array, attr_str, label_axes, scalar};

/// A suite as stored in `/suite`: the target, the factors and the
/// Eurocode 8 check.
#[derive(Debug, Clone, PartialEq)]
pub struct StoredSuite {
    /// The target spectrum in words.
    pub target: String,
    /// The target as the config gives it (TOML).
    pub target_config: String,
    /// `ec8` or `check`.
    pub rule: String,
    /// Periods of the fit \[s\].
    pub range: [f64; 2],
    /// Factor of each record [-] (in the records' `scale` already).
    pub factors: Vec<f64>,
    /// The rule's common factor [-].
    pub rule_factor: f64,
    /// Periods of the fit \[s\].
    pub fit_periods: Vec<f64>,
    /// The target there [m/s^2].
    pub fit_target: Vec<f64>,
    /// The mean of the scaled records' spectra there [m/s^2].
    pub fit_mean: Vec<f64>,
    /// Lowest ratio of the mean to the target [-] and its period \[s\].
    pub min_ratio: [f64; 2],
    /// Whether the mean stays at or above 90 % of the target.
    pub ec8_satisfied: bool,
    /// The scaled records' mean PGA over the target at T = 0 [-].
    pub pga_ratio: f64,
    /// The target at the swept periods [m/s^2].
    pub target_sa: Vec<f64>,
}

impl StoredSuite {
    /// What a plan's suite stores, with the target at the swept `periods`.
    pub fn of(suite: &Suite, periods: &[f64]) -> Self {
        let s = &suite.scaling;
        let target_config = toml::Table::try_from(&suite.target).map(|t| t.to_string()).unwrap_or_default();
        StoredSuite {
            target: suite.target.label(),
            target_config,
            rule: toml::Value::try_from(suite.rule)
                .ok()
                .and_then(|v| v.as_str().map(str::to_string))
                .unwrap_or_default(),
            range: [suite.range.0, suite.range.1],
            factors: s.factors.clone(),
            rule_factor: s.rule_factor,
            fit_periods: s.periods.clone(),
            fit_target: s.target.clone(),
            fit_mean: s.mean.clone(),
            min_ratio: [s.min_ratio.0, s.min_ratio.1],
            ec8_satisfied: s.ec8_satisfied,
            pga_ratio: s.pga_ratio,
            target_sa: periods.iter().map(|&t| suite.target.sa(t)).collect(),
        }
    }
}

/// Writes `/suite`; `axis` names the period axis (`period`, or
/// `period_scale` for a bridge given by its modes).
pub fn write_suite(file: &hdf5::File, s: &StoredSuite, axis: &str) -> hdf5::Result<()> {
    let g = file.create_group("suite")?;
    attr_str(&g, "target", &s.target)?;
    attr_str(&g, "target_config", &s.target_config)?;
    attr_str(&g, "rule", &s.rule)?;
    g.new_attr::<u8>().create("ec8_satisfied")?.write_scalar(&u8::from(s.ec8_satisfied))?;
    let ds = array(&g, "factor", &s.factors[..])?;
    attr_str(&ds, "units", "1")?;
    label_axes(&ds, &["record"])?;
    let ds = array(&g, "range", &s.range[..])?;
    attr_str(&ds, "units", "s")?;
    scalar(&g, "rule_factor", s.rule_factor, "1")?;
    scalar(&g, "min_ratio", s.min_ratio[0], "1")?;
    scalar(&g, "min_ratio_period", s.min_ratio[1], "s")?;
    scalar(&g, "pga_ratio", s.pga_ratio, "1")?;
    let ds = array(&g, "target_sa", &s.target_sa[..])?;
    attr_str(&ds, "units", "m/s^2")?;
    label_axes(&ds, &[axis])?;
    let fit = g.create_group("fit")?;
    for (name, data, units) in
        [("period", &s.fit_periods, "s"), ("target", &s.fit_target, "m/s^2"), ("mean", &s.fit_mean, "m/s^2")]
    {
        let ds = array(&fit, name, &data[..])?;
        attr_str(&ds, "units", units)?;
    }
    Ok(())
}

/// Reads `/suite` (None when the sweep has no suite).
pub fn read_suite(file: &hdf5::File) -> hdf5::Result<Option<StoredSuite>> {
    use quakejoint_io::read::{attr, attr_number, group, number, values};
    if !file.link_exists("suite") {
        return Ok(None);
    }
    let g = group(file, "suite")?;
    let fit = group(&g, "fit")?;
    let range: Vec<f64> = values(&g, "range")?;
    Ok(Some(StoredSuite {
        target: attr(&g, "target")?,
        target_config: attr(&g, "target_config")?,
        rule: attr(&g, "rule")?,
        range: [range.first().copied().unwrap_or(f64::NAN), range.get(1).copied().unwrap_or(f64::NAN)],
        factors: values(&g, "factor")?,
        rule_factor: number(&g, "rule_factor")?,
        fit_periods: values(&fit, "period")?,
        fit_target: values(&fit, "target")?,
        fit_mean: values(&fit, "mean")?,
        min_ratio: [number(&g, "min_ratio")?, number(&g, "min_ratio_period")?],
        ec8_satisfied: attr_number::<u8>(&g, "ec8_satisfied")? != 0,
        pga_ratio: number(&g, "pga_ratio")?,
        target_sa: values(&g, "target_sa")?,
    }))
}

/// Writes `/spectrum/statistics` (every sweep; for one record its own
/// values, with the spreads NaN); `axis` names the period axis, and
/// `per_case` says whether the statistics without the joint have a case
/// axis ([`crate::results::Results::without_per_case`]).
pub fn write_statistics(
    spec: &hdf5::Group,
    st: &Statistics,
    dims: [usize; 4],
    axis: &str,
    per_case: bool,
) -> hdf5::Result<()> {
    let [nc, _, nz, nt] = dims;
    let g = spec.create_group("statistics")?;
    attr_str(
        &g,
        "meaning",
        "over the records, per case, damping and period; NaN where a record's job did not finish (count < records)",
    )?;
    let shape = |e: ndarray::ShapeError| hdf5::Error::from(e.to_string());
    let three = |g: &hdf5::Group, name: &str, data: &[f64], units: &str| -> hdf5::Result<()> {
        let view = ArrayView3::from_shape((nc, nz, nt), data).map_err(shape)?;
        let ds = array(g, name, view)?;
        attr_str(&ds, "units", units)?;
        label_axes(&ds, &["case", "damping", axis])
    };
    let two = |g: &hdf5::Group, name: &str, data: &[f64], units: &str| -> hdf5::Result<()> {
        let view = ArrayView2::from_shape((nz, nt), data).map_err(shape)?;
        let ds = array(g, name, view)?;
        attr_str(&ds, "units", units)?;
        label_axes(&ds, &["damping", axis])
    };
    let with = g.create_group("with_joint")?;
    three(&with, "mean", &st.with_mean, "m/s^2")?;
    three(&with, "median", &st.with_median, "m/s^2")?;
    three(&with, "dispersion", &st.with_dispersion, "1")?;
    let without = g.create_group("without_joint")?;
    for (name, data, units) in [
        ("mean", &st.without_mean, "m/s^2"),
        ("median", &st.without_median, "m/s^2"),
        ("dispersion", &st.without_dispersion, "1"),
    ] {
        if per_case {
            three(&without, name, data, units)?;
        } else {
            two(&without, name, data, units)?;
        }
    }
    let red = g.create_group("reduction")?;
    three(&red, "mean", &st.reduction_mean, "1")?;
    three(&red, "median", &st.reduction_median, "1")?;
    three(&red, "std", &st.reduction_std, "1")?;
    three(&red, "of_mean", &st.reduction_of_mean, "1")?;
    for (name, data) in [("count", &st.count), ("flagged", &st.flagged)] {
        let view = ArrayView3::from_shape((nc, nz, nt), &data[..]).map_err(shape)?;
        let ds = array(&g, name, view)?;
        attr_str(&ds, "units", "1")?;
        label_axes(&ds, &["case", "damping", axis])?;
    }
    Ok(())
}
