//! The command implementations: each parses what it reads, calls the
//! library crates and prints.

use std::path::{Path, PathBuf};
use std::process::ExitCode;

use anyhow::{Context, Result};
use quakejoint_io::run_h5::{Provenance, RecordSource};
use quakejoint_model::config::base_dir;
use quakejoint_model::generator::{build, Drive};
use quakejoint_model::run::RunOptions;
use quakejoint_model::runspec::{Named, Overrides, RecordOverride, RunSpec};
use quakejoint_model::service::service;
use quakejoint_model::{Config, ModelError};
use quakejoint_motion::{load_record, period_range, spectrum, LoadedRecord, RecordStats, SpectrumOptions};
use quakejoint_solver::{Assembly, AssemblyOptions};
use quakejoint_sweep::{run_sweep, Plan, SweepOptions};

use crate::args::*;
use crate::continuation;
use crate::interrupt::{interrupted_code, Signals, TerminalProgress};
use crate::output;

/// An error caused by the input (exit code 2).
#[derive(Debug)]
pub struct InputError(pub String);

impl std::fmt::Display for InputError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for InputError {}

/// Exit code for an error: 2 for bad input, 1 otherwise.
pub fn exit_code(err: &anyhow::Error) -> u8 {
    for cause in err.chain() {
        if cause.downcast_ref::<InputError>().is_some() {
            return 2;
        }
        if let Some(m) = cause.downcast_ref::<ModelError>() {
            return if m.is_input_error() { 2 } else { 1 };
        }
        if let Some(s) = cause.downcast_ref::<quakejoint_sweep::SweepError>() {
            return if s.is_input_error() { 2 } else { 1 };
        }
        if cause.downcast_ref::<quakejoint_motion::RecordError>().is_some()
            || cause.downcast_ref::<quakejoint_motion::SpectrumError>().is_some()
        {
            return 2;
        }
    }
    1
}

/// Runs a parsed command line.
pub fn run(cli: Cli) -> Result<ExitCode> {
    let config = cli.command.config().map(Path::to_path_buf);
    let result = match cli.command {
        Command::Model(a) => model(a),
        Command::Simulate(a) => simulate(a),
        Command::Service(a) => service_cmd(a),
        Command::Calibrate(a) => crate::calibrate::calibrate_cmd(a),
        Command::Record(a) => record_cmd(a),
        Command::Spectrum(a) => spectrum_cmd(a),
        Command::Sweep(a) => sweep_cmd(a),
        Command::Merge(a) => merge_cmd(a),
        Command::Plan(a) => plan_cmd(a),
        Command::Compare(a) => compare_cmd(a),
    };
    result.map_err(|e| match config {
        Some(path) => name_the_config(e, &path),
        None => e,
    })
}

impl Command {
    /// Whether the command prints JSON.
    pub fn json(&self) -> bool {
        match self {
            Command::Model(a) => a.print.json,
            Command::Simulate(a) => a.print.json,
            Command::Service(a) => a.print.json,
            Command::Calibrate(a) => a.print.json,
            Command::Record(a) => a.print.json,
            Command::Spectrum(a) => a.print.json,
            Command::Sweep(a) => a.print.json,
            Command::Merge(a) => a.print.json,
            Command::Plan(a) => a.print.json,
            Command::Compare(a) => a.print.json,
        }
    }

    /// The config file the command reads, if any.
    fn config(&self) -> Option<&Path> {
        match self {
            Command::Model(a) => Some(&a.config),
            Command::Simulate(a) => Some(&a.config),
            Command::Service(a) => Some(&a.config),
            Command::Calibrate(a) => Some(&a.config),
            Command::Sweep(a) => Some(&a.config),
            Command::Plan(a) => Some(&a.config),
            Command::Record(_) | Command::Spectrum(_) | Command::Merge(_) | Command::Compare(_) => None,
        }
    }
}

/// Puts the config's name in front of an input error that does not name it
/// yet (a value out of range, a geometry that cannot work, a record the
/// config points to), so that the message says which file to fix.
fn name_the_config(err: anyhow::Error, config: &Path) -> anyhow::Error {
    let name = config.display().to_string();
    let about_a_flag = err.to_string().starts_with("--");
    if about_a_flag || exit_code(&err) != 2 || err.chain().any(|c| c.to_string().contains(&name)) {
        return err;
    }
    err.context(name)
}

/// Reads the plan of a sweep config.
fn read_plan(config: &Path) -> Result<Plan> {
    let text = quakejoint_motion::read_input_text(config, quakejoint_motion::MAX_CONFIG_BYTES)
        .map_err(|e| InputError(format!("{}: cannot read the config: {e}", config.display())))?;
    let plan = Plan::new(&text, &config.display().to_string(), &base_dir(config))?;
    for r in plan.records.iter().chain(&plan.record_y) {
        for w in &r.warnings {
            eprintln!("warning: {w}");
        }
    }
    for w in &plan.warnings {
        eprintln!("warning: {w}");
    }
    Ok(plan)
}

fn sweep_cmd(a: SweepArgs) -> Result<ExitCode> {
    // first: a signal while the config, records and modes are read stops
    // the sweep before its first job, with the command that continues it
    let signals = Signals::install()?;
    quakejoint_sweep::fault::hold_start(&signals.stop);
    let plan = read_plan(&a.config)?;
    let output = a.output.clone().unwrap_or_else(|| {
        PathBuf::from(a.config.file_stem().map_or("sweep".into(), |s| s.to_string_lossy().to_string()) + ".h5")
    });
    let opts = SweepOptions {
        output,
        threads: a.threads,
        resume: a.resume,
        retry_failed: a.retry_failed,
        shard: a.shard,
        progress: a.progress.mode()?,
        config_path: a.config.clone(),
        command: command_line(),
        stop: Some(signals.stop.clone()),
    };
    if a.check {
        let check = quakejoint_sweep::runner::check_sweep(&plan, &opts)?;
        output::sweep_check(&check, a.retry_failed, a.print.json);
        return Ok(ExitCode::SUCCESS);
    }
    let summary = run_sweep(&plan, &opts)?;
    let words: Vec<std::ffi::OsString> = std::env::args_os().collect();
    // interrupted, the same command continues (--resume insists on the
    // journal), with --retry-failed if this run retried: the failures it
    // has not retried yet are still in the journal
    let next = summary.interrupted.then(|| continuation::sweep_next(&words, a.shard, a.retry_failed, true));
    let retry = (!summary.failed.is_empty()).then(|| continuation::sweep_next(&words, a.shard, true, false));
    output::sweep_summary(&summary, next.as_ref(), retry.as_ref(), a.print.json);
    if let Some(next) = next {
        let retried = if a.retry_failed {
            " (with --retry-failed: the failed jobs this run has not retried yet run, and so do those it retried \
             that failed again)"
        } else {
            ""
        };
        eprintln!(
            "interrupted: {} of {} jobs are done and kept in {} (and in {}); continue with{retried}:\n{next}",
            summary.jobs - summary.not_run,
            summary.jobs,
            summary.journal.display(),
            summary.output.display()
        );
        return Ok(ExitCode::from(interrupted_code(&signals)));
    }
    Ok(match (summary.failed.is_empty(), summary.flagged.is_empty()) {
        (false, _) => ExitCode::from(3),
        (true, false) => ExitCode::from(FLAGGED),
        (true, true) => ExitCode::SUCCESS,
    })
}

fn merge_cmd(a: MergeArgs) -> Result<ExitCode> {
    let (expected, fragility) = match &a.config {
        Some(path) => {
            let plan = read_plan(path)?;
            (Some(plan.config_sha256), plan.fragility)
        }
        None => (None, None),
    };
    let options =
        quakejoint_sweep::MergeOptions { allow_partial: a.allow_partial, command: command_line(), expected, fragility };
    let summary = quakejoint_sweep::merge(&a.files, &a.output, options)
        .map_err(|e| continuation::merge_error(e, &a.files, &command_line()))?;
    for n in &summary.notices {
        eprintln!("warning: {n}");
    }
    let shards: Vec<usize> = summary.failed_shards.iter().map(|&(k, _)| k).collect();
    let retry = if summary.failed > 0 { continuation::resubmit_shards(&shards, true) } else { None };
    output::merge_summary(&summary, retry.as_deref(), a.print.json);
    Ok(match (summary.failed, summary.flagged) {
        (0, 0) => ExitCode::SUCCESS,
        (0, _) => ExitCode::from(FLAGGED),
        _ => ExitCode::from(3),
    })
}

fn plan_cmd(a: PlanArgs) -> Result<ExitCode> {
    if a.shards == 0 || a.threads == 0 {
        return Err(InputError("--shards and --threads must be at least 1".into()).into());
    }
    let plan = read_plan(&a.config)?;
    if a.shards > plan.job_count() {
        return Err(InputError(format!(
            "--shards {}: the sweep has only {} jobs (a shard without a job would do nothing)",
            a.shards,
            plan.job_count()
        ))
        .into());
    }
    let shards: Vec<_> = (1..=a.shards)
        .map(|k| {
            let jobs = if a.shards == 1 { (0..plan.job_count()).collect() } else { plan.shard(k, a.shards) };
            plan.estimate(&jobs, a.threads)
        })
        .collect();
    output::plan_summary(&a.config, &plan, &shards, a.threads, a.sbatch, a.print.json);
    Ok(ExitCode::SUCCESS)
}

fn compare_cmd(a: CompareArgs) -> Result<ExitCode> {
    let read = |p: &Path| {
        if !p.exists() {
            return Err(InputError(format!("{}: no such file", p.display())));
        }
        quakejoint_sweep::sweep_h5::read_sweep(p).map_err(|e| InputError(quakejoint_sweep::sweep_read::refusal(&e)))
    };
    let (fa, fb) = (read(&a.a)?, read(&a.b)?);
    let diffs = quakejoint_sweep::compare::differences(&fa, &fb);
    output::compare_summary(&a.a, &a.b, &diffs, a.print.json);
    Ok(if diffs.is_empty() { ExitCode::SUCCESS } else { ExitCode::from(1) })
}

fn record_cmd(a: RecordArgs) -> Result<ExitCode> {
    let loaded = load_record(&a.record.spec(), Path::new(""))?;
    for w in &loaded.warnings {
        eprintln!("warning: {w}");
    }
    output::record_stats(&loaded, &RecordStats::of(&loaded.record), a.print.json);
    Ok(ExitCode::SUCCESS)
}

fn spectrum_cmd(a: SpectrumArgs) -> Result<ExitCode> {
    let loaded = load_record(&a.record.spec(), Path::new(""))?;
    for w in &loaded.warnings {
        eprintln!("warning: {w}");
    }
    let periods = if a.periods.is_empty() { period_range(a.from, a.to, a.count, a.log)? } else { a.periods.clone() };
    let rows = spectrum(&loaded.record, &periods, &a.damping, SpectrumOptions { subdivisions: a.subdivisions })?;
    output::spectrum_rows(&rows, a.print.json);
    Ok(ExitCode::SUCCESS)
}

/// Reads and validates a config file.
pub fn read_config(path: &Path) -> Result<(Config, String)> {
    let text = quakejoint_motion::read_input_text(path, quakejoint_motion::MAX_CONFIG_BYTES)
        .map_err(|e| InputError(format!("{}: cannot read the config: {e}", path.display())))?;
    let mut config = Config::from_toml(&text, &path.display().to_string())?;
    let base = quakejoint_model::config::base_dir(path);
    config.load_modes(&base)?;
    // its [sweep] table too: a config is refused by every command or none
    quakejoint_sweep::plan::check_sweep(&text, &path.display().to_string(), &base)?;
    Ok((config, text))
}

fn model(a: ModelArgs) -> Result<ExitCode> {
    let (config, text) = read_config(&a.config)?;
    let model = build(&config, None, Drive::None)?;
    let asm = Assembly::new(&model.system, &AssemblyOptions::default()).map_err(ModelError::from)?;
    if let Some(path) = &a.sparsity {
        quakejoint_io::files::check_overwrite(path, "sparsity", &[&a.config]).map_err(InputError)?;
        let names: Vec<String> = model.system.bodies().iter().map(|b| b.name.clone()).collect();
        let provenance = provenance_of(&a.config, &text, &config, Vec::new(), Vec::new());
        quakejoint_io::run_h5::write_sparsity(path, &provenance, &asm, &names)
            .context("writing the sparsity pattern")?;
    }
    output::model_summary(&a.config, &config, &model, &asm, a.print.json);
    Ok(ExitCode::SUCCESS)
}

/// Words joined into a command a POSIX shell reads back as the same words
/// (see [`shell_word`]).
pub fn shell_words(words: &[std::ffi::OsString]) -> String {
    words.iter().map(|w| shell_word(w)).collect::<Vec<_>>().join(" ")
}

/// A word a POSIX shell reads back as itself: as it is if plain, else
/// single-quoted; bytes that are not UTF-8 (a file name in another
/// encoding) in bash's `$'\xff'` form.
fn shell_word(word: &std::ffi::OsStr) -> String {
    use std::os::unix::ffi::OsStrExt;
    match word.to_str() {
        Some(a)
            if !a.is_empty() && !a.contains(|c: char| c.is_whitespace() || "'\"\\$`!*?;&|<>()[]{}~#".contains(c)) =>
        {
            a.to_string()
        }
        Some(a) => format!("'{}'", a.replace('\'', "'\\''")),
        None => {
            let body: String = word
                .as_bytes()
                .iter()
                .map(|&b| match b {
                    b'\'' | b'\\' => format!("\\{}", b as char),
                    0x20..=0x7e => (b as char).to_string(),
                    _ => format!("\\x{b:02x}"),
                })
                .collect();
            format!("$'{body}'")
        }
    }
}

/// The command line as typed (arguments that are not UTF-8 included).
fn command_line() -> String {
    shell_words(&std::env::args_os().collect::<Vec<_>>())
}

/// The provenance of a single run's output: the command, the config file
/// as read and as used (after command-line overrides), the records.
fn provenance_of(
    path: &Path,
    text: &str,
    used: &Config,
    records: Vec<RecordSource>,
    warnings: Vec<String>,
) -> Provenance {
    Provenance {
        command: command_line(),
        config_path: path.display().to_string(),
        config_file: text.to_string(),
        config: toml::to_string(used).unwrap_or_default(),
        records,
        warnings,
    }
}

/// Prints the warnings raised while reading records.
pub(crate) fn print_warnings(records: &[&LoadedRecord]) {
    for r in records {
        for w in &r.warnings {
            eprintln!("warning: {w}");
        }
    }
}

/// Exit code 4: the run finished outside what the model can stand behind.
pub(crate) const FLAGGED: u8 = 4;

fn simulate(a: SimulateArgs) -> Result<ExitCode> {
    let (config, text) = read_config(&a.config)?;
    let mut overrides =
        Overrides { period: a.period.map(|t| Named::new(t, "--period")), alone: a.no_joint, ..Overrides::default() };
    if let Some(path) = &a.record {
        // the override is relative to the current directory and replaces the
        // whole [record] table: its units, scale and columns described
        // another file ([record_y] stays the config's, relative to its
        // folder)
        let file = std::path::absolute(path).unwrap_or_else(|_| path.clone());
        if let Some(old) = &config.record {
            eprintln!(
                "note: --record replaces the config's [record] ({}) with all its settings; {} is read with the \
                 options given on the command line",
                old.file.display(),
                path.display()
            );
        }
        overrides.record = Some(RecordOverride::File(a.read.spec(&file)));
    } else if a.read.any() {
        return Err(InputError(
            "--format, --units, --dt, --column, --channel, --azimuth, --allow-vertical, --scale and --target-pga-g \
             describe the file of --record; without --record, set them in the config's [record]"
                .into(),
        )
        .into());
    }
    let base = base_dir(&a.config);
    let spec = RunSpec::new(config, &overrides)?;
    let config = spec.config();
    let (lx, ly) = spec.records(&base)?;
    print_warnings(&[Some(&lx), ly.as_ref()].into_iter().flatten().collect::<Vec<_>>());
    let (rx, ry) = (&lx.record, ly.as_ref().map(|l| &l.record));
    if let Some(out) = &a.output {
        let record_paths: Vec<PathBuf> =
            config.record.iter().chain(&config.record_y).map(|r| r.resolve_path(&base)).collect();
        let mut inputs: Vec<&Path> = record_paths.iter().map(PathBuf::as_path).collect();
        inputs.push(&a.config);
        quakejoint_io::files::check_overwrite(out, "simulate", &inputs).map_err(InputError)?;
    }
    if a.no_joint && config.bridge.transverse_period.is_some() {
        eprintln!(
            "note: --no-joint solves the bridge along x only; across, the run with the joint reports the bridge alone \
             as sa_y_without_joint"
        );
    }
    let histories = a.output.is_some();
    let bar = if a.no_joint { None } else { TerminalProgress::new(quakejoint_model::run::run_duration(config, rx)) };
    let options = RunOptions { histories, progress: bar.as_ref().map(|b| b.callback()), ..Default::default() };
    let outcome = spec.run(rx, ry, &options);
    if let Some(b) = &bar {
        b.bar.finish_and_clear();
    }
    let result = &outcome?;
    if let Some(path) = &a.output {
        let mut records = vec![RecordSource::of("x", rx, &lx.sha256)];
        records.extend(ly.as_ref().map(|l| RecordSource::of("y", &l.record, &l.sha256)));
        let warnings = lx.warnings.iter().chain(ly.iter().flat_map(|l| &l.warnings)).cloned().collect();
        let provenance = provenance_of(&a.config, &text, config, records, warnings);
        quakejoint_io::run_h5::write_run(path, &provenance, result).context("writing the time histories")?;
    }
    output::run_result(&a.config, &lx, result, config, a.print.json);
    Ok(if result.validity.flags.is_flagged() { ExitCode::from(FLAGGED) } else { ExitCode::SUCCESS })
}

fn service_cmd(a: ServiceArgs) -> Result<ExitCode> {
    let (config, text) = read_config(&a.config)?;
    let overrides = Overrides {
        service_speed: a.speed.map(|s| Named::new(s, "--speed")),
        service_amplitude: a.amplitude.map(|x| Named::new(x, "--amplitude")),
        service_cycles: a.cycles.map(|c| Named::new(c, "--cycles")),
        ..Overrides::default()
    };
    let spec = RunSpec::new(config, &overrides)?;
    let config = spec.config();
    if let Some(out) = &a.output {
        quakejoint_io::files::check_overwrite(out, "service", &[&a.config]).map_err(InputError)?;
    }
    let result = service(&spec.scenario)?;
    for w in &result.warnings {
        eprintln!("warning: {w}");
    }
    if let Some(path) = &a.output {
        let provenance = provenance_of(&a.config, &text, config, Vec::new(), result.warnings.clone());
        quakejoint_io::run_h5::write_service(path, &provenance, &result).context("writing the hysteresis loop")?;
    }
    output::service_result(&a.config, &result, a.print.json);
    Ok(if result.validity.flags.is_flagged() { ExitCode::from(FLAGGED) } else { ExitCode::SUCCESS })
}
