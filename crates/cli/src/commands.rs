//! Argument definitions and the command implementations.

use std::io::IsTerminal;
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;

use anyhow::{Context, Result};
use clap::{Args, Parser, Subcommand};
use quakejoint_model::config::base_dir;
use quakejoint_model::generator::{build, Drive};
use quakejoint_model::linear::linear_response;
use quakejoint_model::run::{load_records, simulate_records, RunOptions};
use quakejoint_model::service::service;
use quakejoint_model::{Config, ModelError};
use quakejoint_motion::{load_record, period_range, spectrum, LoadedRecord, RecordSpec, RecordStats, SpectrumOptions};
use quakejoint_solver::{Assembly, AssemblyOptions};
use quakejoint_sweep::run_h5::{Provenance, RecordSource};
use quakejoint_sweep::{run_sweep, Plan, SweepOptions};

use crate::output;

/// Expansion joints on bridges in earthquakes.
#[derive(Debug, Parser)]
#[command(name = "quakejoint", version, about, long_about = None)]
pub struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Debug, Subcommand)]
enum Command {
    /// Build the model of a config and print its size.
    Model(ModelArgs),
    /// Run one earthquake on the bridge with the joint (or without it).
    Simulate(SimulateArgs),
    /// Drive the deck through opening and closing cycles (the service case).
    Service(ServiceArgs),
    /// Read a ground-motion record and print its statistics.
    Record(RecordArgs),
    /// Exact linear response spectrum of a record.
    Spectrum(SpectrumArgs),
    /// Run the spectrum sweep of a config ([sweep] table) on worker threads.
    Sweep(SweepArgs),
    /// Combine the outputs of sweep shards into one file.
    Merge(MergeArgs),
    /// Estimate a sweep's jobs, time and memory, whole or in shards.
    Plan(PlanArgs),
    /// Compare the results of two sweep files, bit for bit.
    Compare(CompareArgs),
}

/// Options shared by the commands that print results.
#[derive(Debug, Args)]
pub struct PrintArgs {
    /// Print one JSON object on stdout instead of a table.
    #[arg(long)]
    pub json: bool,
}

#[derive(Debug, Args)]
struct ModelArgs {
    /// The TOML config.
    config: PathBuf,
    /// Write the iteration matrix's sparsity pattern to this HDF5 file.
    #[arg(long)]
    sparsity: Option<PathBuf>,
    #[command(flatten)]
    print: PrintArgs,
}

#[derive(Debug, Args)]
struct SweepArgs {
    /// The TOML config with a [sweep] table.
    config: PathBuf,
    /// The HDF5 output (default: the config's name with .h5, in the current
    /// directory); the journal is <output>.journal, the lock <output>.lock.
    #[arg(long)]
    output: Option<PathBuf>,
    /// Worker threads (default: all cores).
    #[arg(long)]
    threads: Option<usize>,
    /// Require a journal to continue (without this flag a sweep continues a
    /// journal of the same sweep if there is one, and starts otherwise).
    #[arg(long)]
    resume: bool,
    /// Run the journalled jobs that failed again, keeping the finished ones
    /// (e.g. after raising simulation.max_wall_time or max_steps).
    #[arg(long)]
    retry_failed: bool,
    /// Run only shard K of N (for job arrays), e.g. --shard 2/8.
    #[arg(long, value_parser = parse_shard)]
    shard: Option<(usize, usize)>,
    #[command(flatten)]
    progress: ProgressArgs,
    #[command(flatten)]
    print: PrintArgs,
}

/// How progress is shown on stderr.
#[derive(Debug, Args)]
pub struct ProgressArgs {
    /// auto: bars on a terminal, plain lines otherwise (logs); bars; lines; none.
    #[arg(long, value_enum, default_value_t = ProgressMode::Auto)]
    pub progress: ProgressMode,
    /// Seconds between progress lines.
    #[arg(long, default_value_t = 60.0)]
    pub progress_interval: f64,
}

/// Progress display modes.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum ProgressMode {
    /// Bars on a terminal, lines otherwise.
    Auto,
    /// Bars redrawn in place.
    Bars,
    /// A timestamped line at every interval.
    Lines,
    /// Nothing.
    None,
}

impl ProgressArgs {
    fn mode(&self) -> Result<quakejoint_sweep::Progress> {
        use quakejoint_sweep::Progress;
        let every = self.progress_interval;
        if !(every.is_finite() && every > 0.0) {
            return Err(InputError(format!("--progress-interval {every}: must be a positive number of seconds")).into());
        }
        let lines = Progress::Lines { every: std::time::Duration::from_secs_f64(every) };
        Ok(match self.progress {
            ProgressMode::Auto if std::io::stderr().is_terminal() => Progress::Bars,
            ProgressMode::Auto | ProgressMode::Lines => lines,
            ProgressMode::Bars => Progress::Bars,
            ProgressMode::None => Progress::Quiet,
        })
    }
}

#[derive(Debug, Args)]
struct MergeArgs {
    /// The shard outputs.
    #[arg(required = true)]
    files: Vec<PathBuf>,
    /// The merged file.
    #[arg(long)]
    output: PathBuf,
    /// Write the merged file even if some jobs have no result (they stay
    /// marked not run; the file says complete = 0).
    #[arg(long)]
    allow_partial: bool,
    #[command(flatten)]
    print: PrintArgs,
}

#[derive(Debug, Args)]
struct PlanArgs {
    /// The TOML config with a [sweep] table.
    config: PathBuf,
    /// Number of shards to estimate.
    #[arg(long, default_value_t = 1)]
    shards: usize,
    /// Worker threads per shard process.
    #[arg(long, default_value_t = 1)]
    threads: usize,
    /// Print only the sbatch resource options of the largest shard
    /// (--cpus-per-task, --mem, --time).
    #[arg(long, conflicts_with = "json")]
    sbatch: bool,
    #[command(flatten)]
    print: PrintArgs,
}

#[derive(Debug, Args)]
struct CompareArgs {
    /// A sweep file.
    a: PathBuf,
    /// The other sweep file.
    b: PathBuf,
    #[command(flatten)]
    print: PrintArgs,
}

fn parse_shard(s: &str) -> std::result::Result<(usize, usize), String> {
    let err = || format!("{s}: expected K/N with 1 <= K <= N, e.g. 2/8");
    let (k, n) = s.split_once('/').ok_or_else(err)?;
    let (k, n): (usize, usize) = (k.trim().parse().map_err(|_| err())?, n.trim().parse().map_err(|_| err())?);
    if n == 0 || k == 0 || k > n {
        return Err(err());
    }
    Ok((k, n))
}

#[derive(Debug, Args)]
struct SimulateArgs {
    /// The TOML config.
    config: PathBuf,
    /// Bridge natural period [s] (default: from the config).
    #[arg(long, allow_negative_numbers = true)]
    period: Option<f64>,
    /// Run the bridge alone (exact linear solution).
    #[arg(long)]
    no_joint: bool,
    /// Record file to use instead of the config's (path relative to the current directory).
    #[arg(long)]
    record: Option<PathBuf>,
    /// Write the time histories to this HDF5 file.
    #[arg(long)]
    output: Option<PathBuf>,
    #[command(flatten)]
    print: PrintArgs,
}

#[derive(Debug, Args)]
struct ServiceArgs {
    /// The TOML config.
    config: PathBuf,
    /// Opening speed [m/s] (default: the config's service.speed).
    #[arg(long, allow_negative_numbers = true)]
    speed: Option<f64>,
    /// Amplitude of the opening [m] (default: service.amplitude).
    #[arg(long, allow_negative_numbers = true)]
    amplitude: Option<f64>,
    /// Number of cycles (default: service.cycles).
    #[arg(long)]
    cycles: Option<u32>,
    /// Write the hysteresis loop to this HDF5 file.
    #[arg(long)]
    output: Option<PathBuf>,
    #[command(flatten)]
    print: PrintArgs,
}

/// How to read a record file (shared by `record` and `spectrum`).
#[derive(Debug, Args)]
pub struct RecordFileArgs {
    /// The record: PEER NGA-West2 .AT2, two-column time/acceleration text or
    /// CSV, or one-column text (give --dt).
    pub file: PathBuf,
    /// File format.
    #[arg(long, value_enum, default_value_t = FormatArg::Auto)]
    pub format: FormatArg,
    /// Units of the values in the file: required for a text file; an AT2
    /// file states its own (if given, they must agree).
    #[arg(long, value_enum)]
    pub units: Option<UnitsArg>,
    /// Time step of a one-column file [s].
    #[arg(long, allow_negative_numbers = true)]
    pub dt: Option<f64>,
    /// Column holding the acceleration in a multi-column file (1-based).
    #[arg(long)]
    pub column: Option<usize>,
    /// Scale factor applied after the unit conversion.
    #[arg(long, default_value_t = 1.0, allow_negative_numbers = true)]
    pub scale: f64,
    /// Scale the record to this peak ground acceleration [g].
    #[arg(long, allow_negative_numbers = true)]
    pub target_pga_g: Option<f64>,
}

/// Record file formats.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum FormatArg {
    /// From the extension (.at2) and --dt.
    Auto,
    /// PEER NGA-West2 AT2.
    At2,
    /// Time and acceleration columns.
    TwoColumn,
    /// Acceleration only, with --dt.
    OneColumn,
}

/// Acceleration units.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum UnitsArg {
    /// Standard gravity (9.80665 m/s^2).
    G,
    /// m/s^2.
    #[value(name = "m/s2")]
    MetersPerSecond2,
    /// cm/s^2 (gal).
    #[value(name = "cm/s2", alias = "gal")]
    CentimetersPerSecond2,
}

impl RecordFileArgs {
    fn spec(&self) -> RecordSpec {
        let mut spec = RecordSpec::new(&self.file);
        spec.format = match self.format {
            FormatArg::Auto => quakejoint_motion::Format::Auto,
            FormatArg::At2 => quakejoint_motion::Format::At2,
            FormatArg::TwoColumn => quakejoint_motion::Format::TwoColumn,
            FormatArg::OneColumn => quakejoint_motion::Format::OneColumn,
        };
        spec.units = self.units.map(|u| match u {
            UnitsArg::G => quakejoint_motion::Units::G,
            UnitsArg::MetersPerSecond2 => quakejoint_motion::Units::MetersPerSecond2,
            UnitsArg::CentimetersPerSecond2 => quakejoint_motion::Units::CentimetersPerSecond2,
        });
        spec.dt = self.dt;
        spec.column = self.column;
        spec.scale = self.scale;
        spec.target_pga_g = self.target_pga_g;
        spec
    }
}

#[derive(Debug, Args)]
struct RecordArgs {
    #[command(flatten)]
    record: RecordFileArgs,
    #[command(flatten)]
    print: PrintArgs,
}

#[derive(Debug, Args)]
struct SpectrumArgs {
    #[command(flatten)]
    record: RecordFileArgs,
    /// Damping ratios (several allowed: --damping 0.02 --damping 0.05, or 0.02,0.05).
    #[arg(long, value_delimiter = ',', default_values_t = [0.05], allow_negative_numbers = true)]
    damping: Vec<f64>,
    /// Periods [s] (comma-separated); overrides --from/--to/--count.
    #[arg(long, value_delimiter = ',', allow_negative_numbers = true)]
    periods: Vec<f64>,
    /// First period of the grid [s].
    #[arg(long, default_value_t = 0.02, allow_negative_numbers = true)]
    from: f64,
    /// Last period of the grid [s].
    #[arg(long, default_value_t = 10.0, allow_negative_numbers = true)]
    to: f64,
    /// Number of periods of the grid.
    #[arg(long, default_value_t = 60)]
    count: usize,
    /// Space the grid logarithmically (default: linearly).
    #[arg(long)]
    log: bool,
    /// Points per sample interval at which peaks are sought (1: the sample times).
    #[arg(long, default_value_t = 1)]
    subdivisions: u32,
    /// Print CSV (the default) with the columns damping,period,sa,psa,sd,sv.
    #[arg(long, conflicts_with = "json")]
    csv: bool,
    #[command(flatten)]
    print: PrintArgs,
}

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
    /// The config file the command reads, if any.
    fn config(&self) -> Option<&Path> {
        match self {
            Command::Model(a) => Some(&a.config),
            Command::Simulate(a) => Some(&a.config),
            Command::Service(a) => Some(&a.config),
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
    let text = std::fs::read_to_string(config)
        .map_err(|e| InputError(format!("{}: cannot read the config: {e}", config.display())))?;
    let plan = Plan::new(&text, &config.display().to_string(), &base_dir(config))?;
    for r in plan.records.iter().chain(&plan.record_y) {
        for w in &r.warnings {
            eprintln!("warning: {w}");
        }
    }
    Ok(plan)
}

/// Exit code of a sweep stopped by a signal: 128 + the signal's number.
fn interrupted_code(signals: &Signals) -> u8 {
    if signals.term.load(Ordering::Relaxed) {
        143
    } else {
        130
    }
}

/// SIGINT and SIGTERM (what Ctrl-C, `scancel` and a SLURM time limit send)
/// ask the sweep to stop; a second signal ends the process at once (the
/// journal is crash-safe either way).
struct Signals {
    stop: Arc<AtomicBool>,
    term: Arc<AtomicBool>,
}

impl Signals {
    fn install() -> Result<Self> {
        use signal_hook::consts::{SIGINT, SIGTERM};
        let stop = Arc::new(AtomicBool::new(false));
        let term = Arc::new(AtomicBool::new(false));
        for sig in [SIGINT, SIGTERM] {
            // the second signal: exit at once with 128 + the signal
            signal_hook::flag::register_conditional_shutdown(sig, 128 + sig, stop.clone())
                .context("installing the signal handlers")?;
            signal_hook::flag::register(sig, stop.clone()).context("installing the signal handlers")?;
        }
        signal_hook::flag::register(SIGTERM, term.clone()).context("installing the signal handlers")?;
        Ok(Self { stop, term })
    }
}

fn sweep_cmd(a: SweepArgs) -> Result<ExitCode> {
    let plan = read_plan(&a.config)?;
    let output = a.output.clone().unwrap_or_else(|| {
        PathBuf::from(a.config.file_stem().map_or("sweep".into(), |s| s.to_string_lossy().to_string()) + ".h5")
    });
    let signals = Signals::install()?;
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
    let summary = run_sweep(&plan, &opts)?;
    output::sweep_summary(&summary, a.print.json);
    if summary.interrupted {
        let mut command = format!("quakejoint sweep {} --output {}", a.config.display(), summary.output.display());
        if let Some((k, n)) = a.shard {
            command.push_str(&format!(" --shard {k}/{n}"));
        }
        if let Some(t) = a.threads {
            command.push_str(&format!(" --threads {t}"));
        }
        eprintln!(
            "interrupted: {} of {} jobs are done and kept in {} (and in {}); continue with:\n  {command}",
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
    let options = quakejoint_sweep::MergeOptions { allow_partial: a.allow_partial, command: command_line() };
    let summary = quakejoint_sweep::merge(&a.files, &a.output, options)?;
    for n in &summary.notices {
        eprintln!("warning: {n}");
    }
    output::merge_summary(&summary, a.print.json);
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
        quakejoint_sweep::sweep_h5::read_sweep(p).map_err(|e| InputError(format!("{}: {}", p.display(), e.message)))
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
    output::record_stats(&loaded.record, &RecordStats::of(&loaded.record), &loaded.warnings, a.print.json);
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
    let text = std::fs::read_to_string(path)
        .map_err(|e| InputError(format!("{}: cannot read the config: {e}", path.display())))?;
    let config = Config::from_toml(&text, &path.display().to_string())?;
    Ok((config, text))
}

fn model(a: ModelArgs) -> Result<ExitCode> {
    let (config, text) = read_config(&a.config)?;
    let model = build(&config, None, Drive::None)?;
    let asm = Assembly::new(&model.system, &AssemblyOptions::default()).map_err(ModelError::from)?;
    if let Some(path) = &a.sparsity {
        quakejoint_sweep::files::check_overwrite(path, "sparsity", &[&a.config]).map_err(InputError)?;
        let names: Vec<String> = model.system.bodies().iter().map(|b| b.name.clone()).collect();
        let provenance = provenance_of(&a.config, &text, &config, Vec::new());
        quakejoint_sweep::run_h5::write_sparsity(path, &provenance, &asm, &names)
            .context("writing the sparsity pattern")?;
    }
    output::model_summary(&a.config, &config, &model, &asm, a.print.json);
    Ok(ExitCode::SUCCESS)
}

fn period_to_omega(period: Option<f64>) -> Result<Option<f64>> {
    match period {
        Some(t) if !(t.is_finite() && t > 0.0) => {
            Err(InputError(format!("--period {t}: the period must be positive")).into())
        }
        Some(t) => Ok(Some(2.0 * std::f64::consts::PI / t)),
        None => Ok(None),
    }
}

/// The command line as typed (arguments with spaces or quotes quoted).
fn command_line() -> String {
    std::env::args()
        .map(|a| {
            if a.is_empty() || a.contains(|c: char| c.is_whitespace() || "'\"\\$`".contains(c)) {
                format!("'{}'", a.replace('\'', "'\\''"))
            } else {
                a
            }
        })
        .collect::<Vec<_>>()
        .join(" ")
}

/// The provenance of a single run's output: the command, the config file
/// as read and as used (after command-line overrides), the records.
fn provenance_of(path: &Path, text: &str, used: &Config, records: Vec<RecordSource>) -> Provenance {
    Provenance {
        command: command_line(),
        config_path: path.display().to_string(),
        config_file: text.to_string(),
        config: toml::to_string(used).unwrap_or_default(),
        records,
    }
}

/// Prints the warnings raised while reading records.
fn print_warnings(records: &[&LoadedRecord]) {
    for r in records {
        for w in &r.warnings {
            eprintln!("warning: {w}");
        }
    }
}

/// Exit code 4: the run finished outside what the model can stand behind.
const FLAGGED: u8 = 4;

fn simulate(a: SimulateArgs) -> Result<ExitCode> {
    let (mut config, text) = read_config(&a.config)?;
    let base = if let Some(path) = &a.record {
        // the override is relative to the current directory; keep the other record settings
        let mut spec = config.record.clone().unwrap_or_else(|| RecordSpec::new(path));
        spec.file = std::path::absolute(path).unwrap_or_else(|_| path.clone());
        spec.name = None;
        config.record = Some(spec);
        PathBuf::new()
    } else {
        base_dir(&a.config)
    };
    let omega = period_to_omega(a.period)?;
    if let Some(t) = a.period {
        (config.bridge.period, config.bridge.w0) = (Some(t), None);
    }
    let (lx, ly) = load_records(&config, &base)?;
    print_warnings(&[Some(&lx), ly.as_ref()].into_iter().flatten().collect::<Vec<_>>());
    let (rx, ry) = (&lx.record, ly.as_ref().map(|l| &l.record));
    if let Some(out) = &a.output {
        let record_paths: Vec<PathBuf> =
            config.record.iter().chain(&config.record_y).map(|r| r.resolve_path(&base)).collect();
        let mut inputs: Vec<&Path> = record_paths.iter().map(PathBuf::as_path).collect();
        inputs.push(&a.config);
        quakejoint_sweep::files::check_overwrite(out, "simulate", &inputs).map_err(InputError)?;
    }
    if a.no_joint {
        config.joint.enabled = false;
    }
    let histories = a.output.is_some();
    let result = if a.no_joint {
        linear_response(rx, omega.unwrap_or_else(|| config.bridge.omega()), config.bridge.damping, histories)
    } else {
        let bar = TerminalProgress::new(quakejoint_model::run::run_duration(&config, rx));
        let options =
            RunOptions { omega, histories, progress: bar.as_ref().map(|b| b.callback()), ..Default::default() };
        let result = simulate_records(&config, rx, ry, &options);
        if let Some(b) = &bar {
            b.bar.finish_and_clear();
        }
        result?
    };
    if let Some(path) = &a.output {
        let period = 2.0 * std::f64::consts::PI / result.omega;
        let without = quakejoint_motion::history(&rx.acceleration, rx.dt, period, config.bridge.damping).a_abs;
        let mut records = vec![RecordSource::of("x", rx, &lx.sha256)];
        records.extend(ly.as_ref().map(|l| RecordSource::of("y", &l.record, &l.sha256)));
        let provenance = provenance_of(&a.config, &text, &config, records);
        quakejoint_sweep::run_h5::write_run(path, &provenance, &result, Some(&without))
            .context("writing the time histories")?;
    }
    output::run_result(&a.config, &rx.name, &result, a.print.json);
    Ok(if result.validity.flags.is_ok() { ExitCode::SUCCESS } else { ExitCode::from(FLAGGED) })
}

fn service_cmd(a: ServiceArgs) -> Result<ExitCode> {
    let (mut config, text) = read_config(&a.config)?;
    if let Some(s) = a.speed {
        config.service.speed = s;
    }
    if let Some(x) = a.amplitude {
        config.service.amplitude = x;
    }
    if let Some(c) = a.cycles {
        config.service.cycles = c;
    }
    config.validate()?;
    if let Some(out) = &a.output {
        quakejoint_sweep::files::check_overwrite(out, "service", &[&a.config]).map_err(InputError)?;
    }
    let result = service(&config)?;
    for w in &result.warnings {
        eprintln!("warning: {w}");
    }
    if let Some(path) = &a.output {
        let provenance = provenance_of(&a.config, &text, &config, Vec::new());
        quakejoint_sweep::run_h5::write_service(path, &provenance, &result).context("writing the hysteresis loop")?;
    }
    output::service_result(&a.config, &result, a.print.json);
    Ok(ExitCode::SUCCESS)
}

/// A progress bar of a single run on a terminal, drawn once the run has
/// taken more than a second (shorter runs print nothing extra).
struct TerminalProgress {
    bar: indicatif::ProgressBar,
    start: std::time::Instant,
}

impl TerminalProgress {
    /// `None` when stderr is not a terminal.
    fn new(duration: f64) -> Option<Arc<Self>> {
        if !std::io::stderr().is_terminal() {
            return None;
        }
        let bar = indicatif::ProgressBar::with_draw_target(
            Some((duration * 1000.0).max(1.0) as u64),
            indicatif::ProgressDrawTarget::hidden(),
        );
        bar.set_style(
            indicatif::ProgressStyle::with_template("simulate [{bar:30}] t = {msg} s, {elapsed} elapsed, ETA {eta}")
                .expect("template")
                .progress_chars("=> "),
        );
        Some(Arc::new(Self { bar, start: std::time::Instant::now() }))
    }

    fn callback(self: &Arc<Self>) -> quakejoint_model::run::ProgressFn {
        let me = Arc::clone(self);
        Arc::new(move |t| {
            if me.bar.is_hidden() && me.start.elapsed().as_secs_f64() > 1.0 {
                me.bar.set_draw_target(indicatif::ProgressDrawTarget::stderr());
            }
            me.bar.set_message(format!("{t:.1}"));
            me.bar.set_position((t * 1000.0) as u64);
        })
    }
}
