//! What the fragility of a multiple-stripe sweep is fitted for
//! (`[sweep.fragility]`): the limit states, the runs that do not count,
//! the bootstrap and the site's hazard curve.
//!
//! ```toml
//! [sweep.fragility]
//! failed = "exclude"       # or "exceed": a failed run counts as exceeding every limit state
//! bootstrap = 1000         # resamples of the records for the intervals (0: none)
//! seed = 1
//! confidence = 0.9
//! hazard = { intensity = [0.05, 0.1, 0.2, 0.4, 0.8], frequency = [0.1, 0.03, 0.008, 0.0015, 2e-4] }
//! # or hazard = { file = "hazard.csv" }: two columns, intensity [g] and annual frequency of exceedance
//!
//! [[sweep.fragility.limit_states]]
//! kind = "pounding"        # capacity, pounding, contact_force, penetration, bearing_off_support,
//! speed = 0.5              # abutment_force, fuse_broken, fuse_stroke_exhausted, field, deck
//! ```

use std::path::Path;

use quakejoint_model::fragility::Hazard;
use quakejoint_model::validity::Flags;

use crate::error::SweepError;
use crate::results::FIELDS;

/// The keys of `[sweep.fragility]`.
pub const FRAGILITY_KEYS: [&str; 6] = ["limit_states", "failed", "bootstrap", "seed", "confidence", "hazard"];

/// The kinds of limit state, in the order docs/sweep.md lists them.
pub const KINDS: [&str; 10] = [
    "capacity",
    "pounding",
    "contact_force",
    "penetration",
    "bearing_off_support",
    "abutment_force",
    "fuse_broken",
    "fuse_stroke_exhausted",
    "field",
    "deck",
];

/// The deck's own measures a `deck` limit state may take (the arrays with
/// and without the joint hold them alike).
pub const DECK_MEASURES: [&str; 4] = {
    let s = quakejoint_model::fields::SPECTRAL;
    [s[0].0, s[1].0, s[2].0, s[3].0]
};

/// What a limit state tests in a run's results.
#[derive(Debug, Clone, PartialEq)]
pub enum Kind {
    /// A validity flag of the run (a cell opened beyond
    /// `joint.capacity.max_subgap`, a bearing off its support beam).
    Flag(Flags),
    /// A per-job field above (or below) a threshold.
    Field {
        /// Index into [`FIELDS`].
        field: usize,
        /// The threshold, in the field's units.
        threshold: f64,
        /// Exceeded above the threshold (else below it).
        above: bool,
    },
    /// The bridge alone's measure (`without_joint`, index into
    /// [`DECK_MEASURES`]) above a threshold.
    Without {
        /// Index into [`DECK_MEASURES`].
        measure: usize,
        /// The threshold, in the measure's units.
        threshold: f64,
    },
}

/// A limit state of the joint or the deck.
#[derive(Debug, Clone, PartialEq)]
pub struct LimitState {
    /// Its key: the group `/fragility/<key>`, unique.
    pub key: String,
    /// Its name in every output.
    pub name: String,
    /// Its kind as the config names it.
    pub kind: String,
    /// What it tests.
    pub test: Kind,
    /// The test in words.
    pub definition: String,
    /// The annual frequency of exceedance a candidate joint must stay
    /// under \[1/year\] (`target`; docs/design.md), if any.
    pub target: Option<f64>,
}

/// What a failed run counts as.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Failed {
    /// Left out of the counts (reported).
    Exclude,
    /// Counted as exceeding every limit state (reported).
    Exceed,
}

impl Failed {
    /// Its value in a config: `exclude` or `exceed`.
    pub fn key(self) -> &'static str {
        match self {
            Failed::Exclude => "exclude",
            Failed::Exceed => "exceed",
        }
    }
}

/// The site's hazard curve and where it comes from.
#[derive(Debug, Clone)]
pub struct SiteHazard {
    /// The curve: (intensity \[g\], annual frequency of exceedance
    /// \[1/year\]).
    pub curve: Hazard,
    /// Its source in words (a file's path as written, or the config's table).
    pub source: String,
    /// The file it was read from, if any (an input of the sweep).
    pub file: Option<std::path::PathBuf>,
}

/// Two sites' hazards are the same when their curves are, wherever they
/// were read from: the same sweep run from another folder has the same
/// hazard.
impl PartialEq for SiteHazard {
    fn eq(&self, other: &Self) -> bool {
        self.curve == other.curve
    }
}

/// `[sweep.fragility]` as resolved.
#[derive(Debug, Clone, PartialEq)]
pub struct FragilitySpec {
    /// The limit states, the defaults when none is given.
    pub limit_states: Vec<LimitState>,
    /// What a failed run counts as.
    pub failed: Failed,
    /// Bootstrap resamples (0: no intervals).
    pub bootstrap: usize,
    /// The bootstrap's seed.
    pub seed: u64,
    /// The intervals' level [-].
    pub confidence: f64,
    /// The site's hazard curve.
    pub hazard: Option<SiteHazard>,
    /// The limit states' tables as given (or the defaults').
    pub tables: Vec<toml::Table>,
}

fn err(field: &str, message: impl Into<String>) -> SweepError {
    SweepError::Config { field: field.to_string(), message: message.into() }
}

fn number(v: Option<&toml::Value>, field: &str) -> Result<Option<f64>, SweepError> {
    match v {
        None => Ok(None),
        Some(toml::Value::Float(x)) => Ok(Some(*x)),
        Some(toml::Value::Integer(i)) => Ok(Some(*i as f64)),
        Some(other) => Err(err(field, format!("expected a number, found {other}"))),
    }
}

/// A value as the config writes it (`"capacty"`, `3`), or `missing`.
pub(crate) fn shown(v: Option<&toml::Value>) -> String {
    v.map_or("missing".to_string(), |v| v.to_string())
}

fn positive(v: Option<&toml::Value>, field: &str, units: &str) -> Result<Option<f64>, SweepError> {
    match number(v, field)? {
        Some(x) if !(x.is_finite() && x > 0.0) => Err(err(field, format!("{x}: a value in {units} above 0"))),
        x => Ok(x),
    }
}

fn field_index(name: &str, at: &str) -> Result<usize, SweepError> {
    if crate::results::MACHINE_DEPENDENT.contains(&name) {
        return Err(err(
            at,
            format!(
                "{name:?} depends on the machine that ran the job, not on the job: a fragility of it would differ \
                 between machines and runs"
            ),
        ));
    }
    FIELDS.iter().position(|&f| f == name).ok_or_else(|| {
        let nearest = FIELDS.iter().min_by_key(|f| distance(f, name)).copied().unwrap_or("sd");
        err(
            at,
            format!(
                "{name:?} is not a per-job field; did you mean {nearest:?}? (the fields of /spectrum/with_joint, \
                 docs/hdf5-layout.md)"
            ),
        )
    })
}

/// The edit distance of two names (Levenshtein).
fn distance(a: &str, b: &str) -> usize {
    let b: Vec<char> = b.chars().collect();
    let mut row: Vec<usize> = (0..=b.len()).collect();
    for (i, ca) in a.chars().enumerate() {
        let mut prev = row[0];
        row[0] = i + 1;
        for (j, cb) in b.iter().enumerate() {
            let next = (prev + usize::from(ca != *cb)).min(row[j] + 1).min(row[j + 1] + 1);
            prev = row[j + 1];
            row[j + 1] = next;
        }
    }
    row[b.len()]
}

/// The joint's limit states when `[sweep.fragility]` names none.
fn defaults() -> Vec<toml::Table> {
    ["capacity", "pounding", "bearing_off_support"]
        .iter()
        .map(|k| toml::Table::from_iter([("kind".to_string(), toml::Value::String(k.to_string()))]))
        .collect()
}

/// One limit state's table (two for a `deck` limit state: with and
/// without the joint).
fn limit_state(t: &toml::Table, at: &str) -> Result<Vec<LimitState>, SweepError> {
    let kind = match t.get("kind").map(|k| k.as_str()) {
        Some(Some(k)) if KINDS.contains(&k) => k.to_string(),
        Some(_) => {
            return Err(err(&format!("{at}.kind"), format!("{}: one of {}", shown(t.get("kind")), KINDS.join(", "))))
        }
        None => return Err(err(&format!("{at}.kind"), format!("missing: one of {}", KINDS.join(", ")))),
    };
    let allowed: &[&str] = match kind.as_str() {
        "capacity" | "bearing_off_support" | "fuse_broken" | "fuse_stroke_exhausted" => &[],
        "pounding" => &["speed"],
        "contact_force" => &["force", "at"],
        "penetration" => &["depth"],
        "abutment_force" => &["force"],
        "field" => &["field", "above", "below"],
        _ => &["measure", "above"],
    };
    for key in t.keys() {
        if !["kind", "name", "target"].contains(&key.as_str()) && !allowed.contains(&key.as_str()) {
            return Err(err(
                &format!("{at}.{key}"),
                format!(
                    "not a key of a {kind:?} limit state (its keys: {})",
                    ["kind", "name", "target"].iter().chain(allowed).copied().collect::<Vec<_>>().join(", ")
                ),
            ));
        }
    }
    let name = match t.get("name") {
        Some(toml::Value::String(s)) if !s.trim().is_empty() => Some(s.trim().to_string()),
        Some(_) => return Err(err(&format!("{at}.name"), "a non-empty text")),
        None => None,
    };
    let target = number(t.get("target"), &format!("{at}.target"))?;
    if let Some(x) = target.filter(|x| !(*x > 0.0 && *x < 1.0)) {
        return Err(err(
            &format!("{at}.target"),
            format!("{x}: an annual frequency between 0 and 1 per year (1/2475 = 4.04e-4 for 2 % in 50 years)"),
        ));
    }
    let e = Entry { t, at, kind: kind.clone(), name, target };
    Ok(match kind.as_str() {
        "capacity" => e.one(
            "cell beyond capacity".into(),
            Kind::Flag(Flags::CAPACITY_EXCEEDED),
            "a clear sub-gap opened beyond joint.capacity.max_subgap (the run's flag capacity_exceeded)".into(),
        ),
        "bearing_off_support" => e.one(
            "bearing off its support".into(),
            Kind::Flag(Flags::BEARING_OFF_SUPPORT),
            "a bearing slid off the end of its support beam (the run's flag bearing_off_support)".into(),
        ),
        "pounding" => {
            let speed = positive(t.get("speed"), &format!("{at}.speed"), "m/s")?
                .unwrap_or(quakejoint_model::pounding::IMPACT_SPEED);
            e.one(
                format!("pounding at {} m/s", quakejoint_motion::number(speed)),
                field_test("max_impact_speed", speed, true),
                format!("an impact of two beams (or a beam and an edge beam) faster than {} m/s", speed),
            )
        }
        "contact_force" => e.contact_force()?,
        "penetration" => {
            let depth = e.required("depth", "m")?;
            e.one(
                format!("penetration beyond {} mm", quakejoint_motion::number(depth * 1e3)),
                field_test("max_penetration", depth, true),
                format!("a contact penetrated deeper than {} m (max_penetration)", quakejoint_motion::number(depth)),
            )
        }
        "abutment_force" => {
            let force = e.required("force", "N")?;
            e.one(
                format!("abutment force above {} MN", quakejoint_motion::number(force / 1e6)),
                field_test("peak_abutment_force", force, true),
                format!(
                    "the joint's force on the abutment above {} N (peak_abutment_force)",
                    quakejoint_motion::number(force)
                ),
            )
        }
        "fuse_broken" => e.one(
            "fuse broken".into(),
            field_test("fuse_broken", 0.5, true),
            "the joint's seismic fuse broke (fuse_broken; service interrupted, the joint to be reset and the fuse \
             repaired; a run without a fuse is undetermined)"
                .into(),
        ),
        "fuse_stroke_exhausted" => e.one(
            "fuse stroke exhausted".into(),
            field_test("fuse_stroke_exhausted", 0.5, true),
            "the freed edge beam reached the fuse box's stop (fuse_stroke_exhausted: the joint pushes the abutment \
             again; a run without a fuse is undetermined)"
                .into(),
        ),
        "field" => e.field()?,
        _ => e.deck()?,
    })
}

/// A limit state's table being read: where it is (`at`), its kind and
/// the name it gives itself.
struct Entry<'a> {
    t: &'a toml::Table,
    at: &'a str,
    kind: String,
    name: Option<String>,
    /// The target annual frequency it gives (docs/design.md).
    target: Option<f64>,
}

/// A test of a per-job field against `threshold`, `above` or below it.
fn field_test(name: &str, threshold: f64, above: bool) -> Kind {
    Kind::Field { field: FIELDS.iter().position(|&f| f == name).expect("a per-job field"), threshold, above }
}

impl Entry<'_> {
    /// The required positive threshold `k` in `units`.
    fn required(&self, k: &str, units: &str) -> Result<f64, SweepError> {
        let at = self.at;
        positive(self.t.get(k), &format!("{at}.{k}"), units)?
            .ok_or_else(|| err(&format!("{at}.{k}"), format!("missing: the threshold [{units}]")))
    }

    /// The one limit state of this table: its own name, else `default`.
    fn one(&self, default: String, test: Kind, definition: String) -> Vec<LimitState> {
        vec![LimitState {
            key: String::new(),
            name: self.name.clone().unwrap_or(default),
            kind: self.kind.clone(),
            test,
            definition,
            target: self.target,
        }]
    }

    /// A `contact_force` limit state: on one beam end, or on the deck.
    fn contact_force(&self) -> Result<Vec<LimitState>, SweepError> {
        let (t, at) = (self.t, self.at);
        let force = self.required("force", "N")?;
        let deck = match t.get("at").map(|a| a.as_str()) {
            None | Some(Some("beams")) => false,
            Some(Some("deck")) => true,
            Some(_) => return Err(err(&format!("{at}.at"), format!("{}: \"beams\" or \"deck\"", shown(t.get("at"))))),
        };
        let (f, words) = if deck {
            ("peak_deck_contact_force", "the closed joint's force on the deck's edge beam")
        } else {
            ("peak_contact_force", "the force of one contact (one beam end)")
        };
        Ok(self.one(
            format!(
                "contact force{} above {} MN",
                if deck { " on the deck" } else { "" },
                quakejoint_motion::number(force / 1e6)
            ),
            field_test(f, force, true),
            format!("{words} above {} N ({f})", quakejoint_motion::number(force)),
        ))
    }

    /// A `field` limit state: any per-job field above or below a threshold.
    fn field(&self) -> Result<Vec<LimitState>, SweepError> {
        let (t, at) = (self.t, self.at);
        let f = match t.get("field") {
            Some(toml::Value::String(s)) => s.clone(),
            _ => return Err(err(&format!("{at}.field"), "missing: the name of a per-job field")),
        };
        let index = field_index(&f, &format!("{at}.field"))?;
        let (threshold, above) =
            match (number(t.get("above"), &format!("{at}.above"))?, number(t.get("below"), &format!("{at}.below"))?) {
                (Some(x), None) => (x, true),
                (None, Some(x)) => (x, false),
                _ => return Err(err(at, "give one threshold: `above` or `below`")),
            };
        if !threshold.is_finite() {
            return Err(err(at, format!("{threshold}: the threshold must be finite")));
        }
        let units = crate::results::UNITS[index];
        let words =
            format!("{f} {} {} {units}", if above { "above" } else { "below" }, quakejoint_motion::number(threshold));
        Ok(self.one(words.clone(), Kind::Field { field: index, threshold, above }, words))
    }

    /// A `deck` limit state: two, the deck's measure with the joint and
    /// the bridge alone's.
    fn deck(&self) -> Result<Vec<LimitState>, SweepError> {
        let (t, at) = (self.t, self.at);
        let m = match t.get("measure").map(|m| m.as_str()) {
            Some(Some(m)) if DECK_MEASURES.contains(&m) => m.to_string(),
            _ => {
                return Err(err(
                    &format!("{at}.measure"),
                    format!("{}: one of {}", shown(t.get("measure")), DECK_MEASURES.join(", ")),
                ))
            }
        };
        let measure = DECK_MEASURES.iter().position(|&x| x == m).expect("checked");
        let units = quakejoint_model::fields::SPECTRAL[measure].1;
        let threshold = self.required("above", units)?;
        let base =
            self.name.clone().unwrap_or(format!("deck {m} above {} {units}", quakejoint_motion::number(threshold)));
        let words = format!("the deck's {m} above {} {units}", quakejoint_motion::number(threshold));
        Ok(vec![
            LimitState {
                key: String::new(),
                name: format!("{base} (with the joint)"),
                kind: self.kind.clone(),
                test: field_test(&m, threshold, true),
                definition: format!("{words}, with the joint"),
                // (the bridge alone is no candidate's: the target is the joint's)
                target: self.target,
            },
            LimitState {
                key: String::new(),
                name: format!("{base} (without the joint)"),
                kind: self.kind.clone(),
                test: Kind::Without { measure, threshold },
                definition: format!("{words}, the bridge alone (exact, over the runs' window)"),
                target: None,
            },
        ])
    }
}

/// A key for `/fragility/<key>`: the name in lower case, letters, digits
/// and `_` only.
fn key_of(name: &str) -> String {
    let mut k: String =
        name.chars().map(|c| if c.is_ascii_alphanumeric() { c.to_ascii_lowercase() } else { '_' }).collect();
    while k.contains("__") {
        k = k.replace("__", "_");
    }
    k.trim_matches('_').to_string()
}

impl FragilitySpec {
    /// Reads `[sweep.fragility]` (`None`: its defaults); a
    /// hazard file is resolved against `base_dir`.
    pub fn from_toml(v: Option<&toml::Value>, base_dir: &Path) -> Result<Self, SweepError> {
        let empty = toml::Table::new();
        let t = match v {
            None => &empty,
            Some(toml::Value::Table(t)) => t,
            Some(_) => return Err(err("sweep.fragility", "must be a table ([sweep.fragility])")),
        };
        crate::plan::known_keys(t, "sweep.fragility", &FRAGILITY_KEYS)?;
        let tables = match t.get("limit_states") {
            None => defaults(),
            Some(toml::Value::Array(items)) if !items.is_empty() => items
                .iter()
                .enumerate()
                .map(|(i, v)| match v {
                    toml::Value::Table(t) => Ok(t.clone()),
                    _ => Err(err(&format!("sweep.fragility.limit_states[{i}]"), "must be a table")),
                })
                .collect::<Result<_, _>>()?,
            Some(_) => {
                return Err(err(
                    "sweep.fragility.limit_states",
                    "a non-empty list of tables ([[sweep.fragility.limit_states]])",
                ))
            }
        };
        let mut limit_states: Vec<LimitState> = Vec::new();
        for (i, lt) in tables.iter().enumerate() {
            let at = format!("sweep.fragility.limit_states[{i}]");
            for mut ls in limit_state(lt, &at)? {
                ls.key = key_of(&ls.name);
                if ls.key.is_empty() || limit_states.iter().any(|o| o.key == ls.key) {
                    return Err(err(
                        &format!("{at}.name"),
                        format!(
                            "{:?}: two limit states would be stored as /fragility/{}; give one another name",
                            ls.name, ls.key
                        ),
                    ));
                }
                limit_states.push(ls);
            }
        }
        let failed = match t.get("failed").map(|f| f.as_str()) {
            None | Some(Some("exclude")) => Failed::Exclude,
            Some(Some("exceed")) => Failed::Exceed,
            Some(_) => {
                return Err(err(
                    "sweep.fragility.failed",
                    format!(
                        "{}: \"exclude\" (a failed run does not count) or \"exceed\" (it counts as exceeding)",
                        shown(t.get("failed"))
                    ),
                ))
            }
        };
        let bootstrap = match t.get("bootstrap") {
            None => 1000,
            Some(toml::Value::Integer(n)) if (0..=100_000).contains(n) => *n as usize,
            Some(other) => {
                return Err(err("sweep.fragility.bootstrap", format!("{other}: a whole number from 0 to 100000")))
            }
        };
        let seed = match t.get("seed") {
            None => 1,
            Some(toml::Value::Integer(n)) if *n >= 0 => *n as u64,
            Some(other) => return Err(err("sweep.fragility.seed", format!("{other}: a whole number >= 0"))),
        };
        let confidence = number(t.get("confidence"), "sweep.fragility.confidence")?.unwrap_or(0.9);
        if !(confidence > 0.0 && confidence < 1.0) {
            return Err(err("sweep.fragility.confidence", format!("{confidence}: between 0 and 1 (0.9: 5 % to 95 %)")));
        }
        let hazard = t.get("hazard").map(|h| hazard_of(h, base_dir)).transpose()?;
        if let (None, Some(i)) = (&hazard, tables.iter().position(|t| t.contains_key("target"))) {
            return Err(err(
                &format!("sweep.fragility.limit_states[{i}].target"),
                "a target annual frequency needs the site's hazard curve (sweep.fragility.hazard)",
            ));
        }
        Ok(Self { limit_states, failed, bootstrap, seed, confidence, hazard, tables })
    }

    /// The table as resolved (the hazard curve's points inline), which
    /// [`FragilitySpec::from_toml`] reads back to the same spec.
    pub fn to_toml(&self) -> toml::Table {
        let mut t = toml::Table::new();
        t.insert(
            "limit_states".into(),
            toml::Value::Array(self.tables.iter().cloned().map(toml::Value::Table).collect()),
        );
        t.insert("failed".into(), toml::Value::String(self.failed.key().into()));
        t.insert("bootstrap".into(), toml::Value::Integer(self.bootstrap as i64));
        t.insert("seed".into(), toml::Value::Integer(self.seed as i64));
        t.insert("confidence".into(), toml::Value::Float(self.confidence));
        if let Some(h) = &self.hazard {
            let col = |f: fn(&(f64, f64)) -> f64| {
                toml::Value::Array(h.curve.points().iter().map(|p| toml::Value::Float(f(p))).collect())
            };
            let mut h = toml::Table::new();
            h.insert("intensity".into(), col(|p| p.0));
            h.insert("frequency".into(), col(|p| p.1));
            t.insert("hazard".into(), toml::Value::Table(h));
        }
        t
    }
}

/// The hazard curve: `{ intensity = [...], frequency = [...] }` or
/// `{ file = "..." }` (two columns; `#` comments and a header line of
/// words allowed). Checked as the risk integral needs it.
fn hazard_of(v: &toml::Value, base_dir: &Path) -> Result<SiteHazard, SweepError> {
    let field = "sweep.fragility.hazard";
    let toml::Value::Table(t) = v else {
        return Err(err(field, "{ intensity = [...] (g), frequency = [...] (1/year) } or { file = \"...\" }"));
    };
    let hazard = match (t.get("file"), t.get("intensity"), t.get("frequency")) {
        (Some(toml::Value::String(f)), None, None) if t.len() == 1 => {
            let path = base_dir.join(f);
            let text = quakejoint_motion::read_input_text(&path, quakejoint_motion::MAX_TABLE_BYTES)
                .map_err(|e| err(&format!("{field}.file"), format!("{}: {e}", path.display())))?;
            let (mut points, mut lines) = (Vec::new(), Vec::new());
            let mut header = false;
            for (n, line) in text.lines().enumerate() {
                let line = line.split('#').next().unwrap_or("").trim();
                if line.is_empty() {
                    continue;
                }
                let cols: Vec<&str> =
                    line.split(|c: char| c == ',' || c.is_whitespace()).filter(|c| !c.is_empty()).collect();
                let parsed: Vec<Option<f64>> = cols.iter().map(|c| c.parse::<f64>().ok()).collect();
                match parsed[..] {
                    [Some(a), Some(b)] => {
                        points.push((a, b));
                        lines.push(n + 1);
                    }
                    // one header line of words, before the numbers
                    _ if points.is_empty() && !header && parsed.iter().all(Option::is_none) => header = true,
                    _ => {
                        return Err(err(
                            &format!("{field}.file"),
                            format!(
                                "{} line {}: {line:?}: two numbers, intensity [g] and annual frequency",
                                path.display(),
                                n + 1
                            ),
                        ))
                    }
                }
            }
            let source = path.display().to_string();
            if points.len() < 2 {
                return Err(err(
                    &format!("{field}.file"),
                    format!(
                        "{source}: {} point{}: a hazard curve needs two at least",
                        points.len(),
                        if points.len() == 1 { "" } else { "s" }
                    ),
                ));
            }
            let curve = checked(points, &|i| format!("{source} line {}", lines[i]), field)?;
            SiteHazard { curve, source: f.clone(), file: Some(path) }
        }
        (None, Some(i), Some(f)) if t.len() == 2 => {
            let list = |v: &toml::Value, k: &str| -> Result<Vec<f64>, SweepError> {
                match v {
                    toml::Value::Array(a) => a
                        .iter()
                        .map(|x| number(Some(x), &format!("{field}.{k}")).map(|x| x.unwrap_or(f64::NAN)))
                        .collect(),
                    _ => Err(err(&format!("{field}.{k}"), "a list of numbers")),
                }
            };
            let (i, f) = (list(i, "intensity")?, list(f, "frequency")?);
            if i.len() != f.len() {
                return Err(err(field, format!("{} intensities but {} frequencies", i.len(), f.len())));
            }
            let points: Vec<(f64, f64)> = i.into_iter().zip(f).collect();
            let curve = checked(points, &|i| format!("{field}.intensity[{i}] and frequency[{i}]"), field)?;
            SiteHazard { curve, source: "the config's table".to_string(), file: None }
        }
        _ => return Err(err(field, "either `file` or both `intensity` [g] and `frequency` [1/year]")),
    };
    Ok(hazard)
}

/// The hazard curve of `points`, checked, the point named by `at`.
fn checked(points: Vec<(f64, f64)>, at: &dyn Fn(usize) -> String, field: &str) -> Result<Hazard, SweepError> {
    let n = points.len();
    Hazard::new(points).map_err(|e| match e {
        quakejoint_model::fragility::FragilityError::Hazard { index, reason } if n > 0 => {
            err(field, format!("{}: {reason}", at(index.min(n - 1))))
        }
        e => err(field, e.to_string()),
    })
}
