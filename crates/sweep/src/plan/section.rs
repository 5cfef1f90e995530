//! The `[sweep]` table of a config read once ([`SweepSection`]): its keys
//! checked against the known ones, each value taken into its typed form
//! (the lists of numbers, the records, the cases' tables, the checkpoint
//! interval). The swept grids, the suite, the stripes and the fragility
//! stay values for their readers, which resolve them against the config
//! (the grids' ranges against its parameters' limits, the suite and the
//! stripes against the records).

use quakejoint_motion::RecordSpec;

use super::{f64_of, known_keys, list_of_f64, sweep_err, MAX_INTERVAL, SWEEP_KEYS};
use crate::error::SweepError;

/// The `[sweep]` table, read.
#[derive(Debug, Clone)]
pub(crate) struct SweepSection {
    /// The table as written (the sweep's identity hashes it).
    pub table: toml::Table,
    /// `periods`: a list or a range of periods \[s\].
    pub periods: Option<toml::Value>,
    /// `period_scales`: a list or a range of factors on a modal bridge's
    /// periods [-].
    pub period_scales: Option<toml::Value>,
    /// `damping`: damping ratios [-].
    pub damping: Option<Vec<f64>>,
    /// `records`: the records, each as `[record]` describes one.
    pub records: Option<Vec<RecordSpec>>,
    /// `[[sweep.cases]]`: each case's table (none: the config alone).
    pub cases: Option<Vec<toml::Table>>,
    /// `histories`: the periods (period scales) whose histories are kept.
    pub histories: Vec<f64>,
    /// `checkpoint_seconds`: seconds between checkpoints (default 60).
    pub checkpoint_seconds: f64,
    /// `[sweep.suite]`.
    pub suite: Option<toml::Value>,
    /// `[sweep.stripes]`.
    pub stripes: Option<toml::Value>,
    /// `[sweep.fragility]`.
    pub fragility: Option<toml::Value>,
}

impl SweepSection {
    /// Reads `[sweep]`; an error names the key.
    pub fn read(table: toml::Table) -> Result<Self, SweepError> {
        known_keys(&table, "sweep", &SWEEP_KEYS)?;
        if table.contains_key("stripes") && table.contains_key("suite") {
            return Err(sweep_err(
                "sweep.stripes",
                "the stripes scale every record to every level; a suite's scaling to a target ([sweep.suite]) would \
                 be undone: remove [sweep.suite] and list its records in sweep.records",
            ));
        }
        let get = |key: &str| table.get(key).cloned();
        Ok(SweepSection {
            periods: get("periods"),
            period_scales: get("period_scales"),
            damping: table.get("damping").map(|v| list_of_f64(v, "sweep.damping")).transpose()?,
            records: table.get("records").map(records_of).transpose()?,
            cases: table.get("cases").map(cases_of).transpose()?,
            histories: table
                .get("histories")
                .map(|v| list_of_f64(v, "sweep.histories"))
                .transpose()?
                .unwrap_or_default(),
            checkpoint_seconds: checkpoint_of(table.get("checkpoint_seconds"))?,
            suite: get("suite"),
            stripes: get("stripes"),
            fragility: get("fragility"),
            table,
        })
    }
}

/// `sweep.records`: a list of tables, each a record as `[record]` gives it.
fn records_of(v: &toml::Value) -> Result<Vec<RecordSpec>, SweepError> {
    let toml::Value::Array(items) = v else { return Err(sweep_err("sweep.records", "must be a list of tables")) };
    items
        .iter()
        .enumerate()
        .map(|(i, v)| {
            v.clone().try_into().map_err(|e: toml::de::Error| sweep_err(&format!("sweep.records[{i}]"), e.to_string()))
        })
        .collect()
}

/// `[[sweep.cases]]`: a list of tables.
fn cases_of(v: &toml::Value) -> Result<Vec<toml::Table>, SweepError> {
    let toml::Value::Array(items) = v else {
        return Err(sweep_err("sweep.cases", "must be a list of tables ([[sweep.cases]])"));
    };
    items
        .iter()
        .enumerate()
        .map(|(i, v)| match v {
            toml::Value::Table(t) => Ok(t.clone()),
            _ => Err(sweep_err(&format!("sweep.cases[{i}]"), "must be a table")),
        })
        .collect()
}

/// `sweep.checkpoint_seconds`, 60 s unless given.
fn checkpoint_of(v: Option<&toml::Value>) -> Result<f64, SweepError> {
    let seconds = v.map(|v| f64_of(v, "sweep.checkpoint_seconds")).transpose()?.unwrap_or(60.0);
    if !(seconds.is_finite() && seconds > 0.0 && seconds <= MAX_INTERVAL) {
        return Err(sweep_err(
            "sweep.checkpoint_seconds",
            format!("{seconds}: seconds between checkpoints, above 0 and at most {MAX_INTERVAL:e}"),
        ));
    }
    Ok(seconds)
}
