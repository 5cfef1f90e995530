//! Reference problems whose independent solution is another program's
//! output, committed as data with its provenance: the linear response
//! spectra of eqsig and OpenSees (`tests/data/reference_spectra`, made by
//! `scripts/reference_spectra.py`) and Exudyn's run of the small joint
//! (`tests/data/exudyn`, made by `scripts/exudyn/small_joint.py`).

use std::path::Path;

use quakejoint_motion::{load_record, peaks, RecordSpec, SpectrumOptions};

use super::Outcome;

/// The records the reference spectra were computed for.
const RECORDS: [&str; 2] = ["RSN753_LOMAP_CLS090-hor2", "RSN6_IMPVALL.I_I-ELC180-hor1"];

/// One row of a reference spectrum: damping [-], period \[s\], Sa, PSa
/// \[m/s^2\], Sd \[m\].
struct Row {
    damping: f64,
    period: f64,
    values: [f64; 3],
}

/// The rows of `tests/data/reference_spectra/<program>_<record>.csv`.
fn rows(root: &Path, program: &str, record: &str) -> Result<Vec<Row>, String> {
    let path = root.join("tests/data/reference_spectra").join(format!("{program}_{record}.csv"));
    let text = quakejoint_motion::read_input_text(&path, quakejoint_motion::MAX_TABLE_BYTES)
        .map_err(|e| format!("{}: {e}", path.display()))?;
    text.lines()
        .skip(1)
        .filter(|l| !l.trim().is_empty())
        .map(|l| {
            let v: Vec<f64> = l
                .split(',')
                .map(|x| x.trim().parse::<f64>())
                .collect::<Result<_, _>>()
                .map_err(|e| format!("{}: {l:?}: {e}", path.display()))?;
            match v[..] {
                [damping, period, sa, psa, sd, ..] => Ok(Row { damping, period, values: [sa, psa, sd] }),
                _ => Err(format!("{}: {l:?}: fewer than five columns", path.display())),
            }
        })
        .collect()
}

/// Sa, PSa and Sd of both records at every period and damping of
/// `program`'s files against quakejoint's exact spectrum: the entry of
/// the largest relative difference.
pub fn spectra_against(root: &Path, program: &str) -> Result<Outcome, String> {
    let mut worst = (0.0f64, Outcome { computed: f64::NAN, reference: f64::NAN });
    for record in RECORDS {
        let spec = RecordSpec::new(format!("{record}.AT2"));
        let rec = load_record(&spec, &root.join("ground_motions")).map_err(|e| e.to_string())?.record;
        for row in rows(root, program, record)? {
            let p = peaks(&rec.acceleration, rec.dt, row.period, row.damping, SpectrumOptions::default());
            for (computed, reference) in [p.sa, p.psa, p.sd].into_iter().zip(row.values) {
                let error = ((computed - reference) / reference).abs();
                if error.is_nan() || error > worst.0 {
                    worst = (error, Outcome { computed, reference });
                }
            }
        }
    }
    Ok(worst.1)
}

/// Against eqsig 1.2.17 (exact piecewise-linear integration).
pub fn spectra_against_eqsig(root: &Path) -> Result<Outcome, String> {
    spectra_against(root, "eqsig")
}

/// Against OpenSees 3.7.1 (Newmark average acceleration, h = 1.25e-4 s).
pub fn spectra_against_opensees(root: &Path) -> Result<Outcome, String> {
    spectra_against(root, "opensees")
}

/// The small joint on a light deck (5e4 kg, T = 1 s, 5 %; the joint raises
/// its Sa by 16.7 %) under Corralitos 090 x 0.15 for 10 s, at tolerances
/// 1e-12 (`tests/data/exudyn/quakejoint_small_light_tight.toml`), and
/// Exudyn's run of the same model (`scripts/exudyn/small_joint.py`,
/// `tests/data/exudyn/exudyn_small_light.json`): `field` of both.
fn against_exudyn(root: &Path, field: &str) -> Result<Outcome, String> {
    let dir = root.join("tests/data/exudyn");
    let json =
        quakejoint_motion::read_input_text(&dir.join("exudyn_small_light.json"), quakejoint_motion::MAX_TABLE_BYTES)
            .map_err(|e| format!("exudyn_small_light.json: {e}"))?;
    // (a flat JSON object of numbers and strings: the value after the key)
    let key = format!("\"{field}\":");
    let reference = json
        .split_once(&key)
        .and_then(|(_, rest)| rest.split([',', '\n', '}']).next())
        .and_then(|v| v.trim().parse::<f64>().ok())
        .ok_or_else(|| format!("exudyn_small_light.json has no number {field}"))?;
    let path = dir.join("quakejoint_small_light_tight.toml");
    let config = crate::Config::from_file(&path).map_err(|e| e.to_string())?;
    let r = crate::run::simulate(&config, &crate::config::base_dir(&path), &crate::run::RunOptions::default())
        .map_err(|e| e.to_string())?;
    let computed = match field {
        "sa" => r.sa,
        "friction_energy" => r.friction_energy,
        other => return Err(format!("no field {other}")),
    };
    Ok(Outcome { computed, reference })
}

/// Sa of the light deck against Exudyn's.
pub fn small_joint_sa_against_exudyn(root: &Path) -> Result<Outcome, String> {
    against_exudyn(root, "sa")
}

/// The friction energy against Exudyn's.
pub fn small_joint_friction_against_exudyn(root: &Path) -> Result<Outcome, String> {
    against_exudyn(root, "friction_energy")
}
