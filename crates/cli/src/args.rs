//! The command line's arguments (clap derive): the commands, their options
//! and the option groups they share.

use std::io::IsTerminal;
use std::path::PathBuf;

use anyhow::Result;
use clap::{Args, Parser, Subcommand};
use quakejoint_motion::RecordSpec;

use crate::commands::InputError;

/// Expansion joints on bridges in earthquakes.
#[derive(Debug, Parser)]
#[command(name = "quakejoint", version, about, long_about = None)]
pub struct Cli {
    #[command(subcommand)]
    pub command: Command,
}

#[derive(Debug, Subcommand)]
pub enum Command {
    /// Build the model of a config and print its size.
    Model(ModelArgs),
    /// Run one earthquake on the bridge with the joint (or without it).
    Simulate(SimulateArgs),
    /// Drive the deck through opening and closing cycles (the service case).
    Service(ServiceArgs),
    /// Calibrate the joint's link element and export it (OpenSees, SAP2000, TOML).
    Calibrate(CalibrateArgs),
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
    /// Print JSON on stdout instead of text: one object (`spectrum`: an array of one object per damping and period, with psv and the times of the peaks too).
    #[arg(long)]
    pub json: bool,
}

#[derive(Debug, Args)]
pub struct ModelArgs {
    /// The TOML config.
    pub config: PathBuf,
    /// Write the iteration matrix's sparsity pattern to this HDF5 file.
    #[arg(long)]
    pub sparsity: Option<PathBuf>,
    #[command(flatten)]
    pub print: PrintArgs,
}

#[derive(Debug, Args)]
pub struct SweepArgs {
    /// The TOML config with a [sweep] table.
    pub config: PathBuf,
    /// The HDF5 output (default: the config's name with .h5, in the current
    /// directory); the journal is OUTPUT.journal, the lock OUTPUT.lock.
    #[arg(long)]
    pub output: Option<PathBuf>,
    /// Worker threads (default: all cores).
    #[arg(long, value_parser = at_least_one)]
    pub threads: Option<usize>,
    /// Check the config, its records and the output (its journal, if any,
    /// must be of this sweep), say what a run would do, and exit without
    /// running anything.
    #[arg(long)]
    pub check: bool,
    /// Require a journal to continue (without this flag a sweep continues a
    /// journal of the same sweep if there is one, and starts otherwise).
    #[arg(long)]
    pub resume: bool,
    /// Run the journalled jobs that failed again, keeping the finished ones
    /// (e.g. after raising simulation.max_wall_time or max_steps).
    #[arg(long)]
    pub retry_failed: bool,
    /// Run only shard K of N (for job arrays), e.g. --shard 2/8.
    #[arg(long, value_parser = parse_shard)]
    pub shard: Option<(usize, usize)>,
    #[command(flatten)]
    pub progress: ProgressArgs,
    #[command(flatten)]
    pub print: PrintArgs,
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
    pub fn mode(&self) -> Result<quakejoint_sweep::Progress> {
        use quakejoint_sweep::Progress;
        let every = self.progress_interval;
        if !(every.is_finite() && every > 0.0 && every <= quakejoint_sweep::plan::MAX_INTERVAL) {
            return Err(InputError(format!(
                "--progress-interval {every}: seconds between progress lines, above 0 and at most {:e}",
                quakejoint_sweep::plan::MAX_INTERVAL
            ))
            .into());
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
pub struct MergeArgs {
    /// The shard outputs.
    #[arg(required = true)]
    pub files: Vec<PathBuf>,
    /// The merged file.
    #[arg(long)]
    pub output: PathBuf,
    /// Write the merged file even if some jobs have no result (they stay
    /// marked not run; the file says complete = 0).
    #[arg(long)]
    pub allow_partial: bool,
    /// The config the shards must have been computed from (refuses shards
    /// of an earlier version of it); a multiple-stripe sweep is fitted
    /// with its [sweep.fragility], which may have changed since.
    #[arg(long)]
    pub config: Option<PathBuf>,
    #[command(flatten)]
    pub print: PrintArgs,
}

#[derive(Debug, Args)]
pub struct PlanArgs {
    /// The TOML config with a [sweep] table.
    pub config: PathBuf,
    /// Number of shards to estimate.
    #[arg(long, default_value_t = 1)]
    pub shards: usize,
    /// Worker threads per shard process.
    #[arg(long, default_value_t = 1, value_parser = at_least_one)]
    pub threads: usize,
    /// Print only the sbatch resource options of the largest shard
    /// (--cpus-per-task, --mem, --time).
    #[arg(long, conflicts_with = "json")]
    pub sbatch: bool,
    #[command(flatten)]
    pub print: PrintArgs,
}

#[derive(Debug, Args)]
pub struct CompareArgs {
    /// A sweep file.
    pub a: PathBuf,
    /// The other sweep file.
    pub b: PathBuf,
    #[command(flatten)]
    pub print: PrintArgs,
}

/// Most worker threads: a sweep never runs more than one per job, and a
/// machine of more cores than this is not made yet.
pub const MAX_THREADS: usize = 1024;

/// A thread count: a whole number from 1 to [`MAX_THREADS`].
fn at_least_one(s: &str) -> std::result::Result<usize, String> {
    match s.trim().parse::<usize>() {
        Ok(n) if (1..=MAX_THREADS).contains(&n) => Ok(n),
        _ => Err(format!("{s}: expected a whole number of threads from 1 to {MAX_THREADS}")),
    }
}

pub fn parse_shard(s: &str) -> std::result::Result<(usize, usize), String> {
    let err = || format!("{s}: expected K/N with 1 <= K <= N, e.g. 2/8");
    let (k, n) = s.split_once('/').ok_or_else(err)?;
    let (k, n): (usize, usize) = (k.trim().parse().map_err(|_| err())?, n.trim().parse().map_err(|_| err())?);
    if n == 0 || k == 0 || k > n {
        return Err(err());
    }
    Ok((k, n))
}

#[derive(Debug, Args)]
pub struct SimulateArgs {
    /// The TOML config.
    pub config: PathBuf,
    /// Bridge natural period [s] (default: from the config).
    #[arg(long, allow_negative_numbers = true)]
    pub period: Option<f64>,
    /// Run the bridge alone (exact linear solution).
    #[arg(long)]
    pub no_joint: bool,
    /// Record file to use instead of the config's [record] (path relative
    /// to the current directory). It replaces the whole [record] table: say
    /// how to read it with the options below, as for `quakejoint record`.
    #[arg(long)]
    pub record: Option<PathBuf>,
    #[command(flatten)]
    pub read: RecordReadArgs,
    /// Write the time histories to this HDF5 file.
    #[arg(long)]
    pub output: Option<PathBuf>,
    #[command(flatten)]
    pub print: PrintArgs,
}

#[derive(Debug, Args)]
pub struct ServiceArgs {
    /// The TOML config.
    pub config: PathBuf,
    /// Opening speed [m/s] (default: the config's service.speed).
    #[arg(long, allow_negative_numbers = true)]
    pub speed: Option<f64>,
    /// Amplitude of the opening [m] (default: service.amplitude).
    #[arg(long, allow_negative_numbers = true)]
    pub amplitude: Option<f64>,
    /// Number of cycles (default: service.cycles).
    #[arg(long)]
    pub cycles: Option<u32>,
    /// Write the hysteresis loop to this HDF5 file.
    #[arg(long)]
    pub output: Option<PathBuf>,
    #[command(flatten)]
    pub print: PrintArgs,
}

#[derive(Debug, Args)]
pub struct CalibrateArgs {
    /// The TOML config (its detailed [joint], and the bridge for the damping table).
    pub config: PathBuf,
    /// Amplitudes of the service loops [m] (default 0.002,0.005,0.01,0.02,0.05,0.1).
    #[arg(long, value_delimiter = ',', allow_negative_numbers = true)]
    pub amplitudes: Option<Vec<f64>>,
    /// Opening speed of the loops [m/s] (default 0.02).
    #[arg(long, allow_negative_numbers = true)]
    pub speed: Option<f64>,
    /// The force at which the closed joint's Hertz stiffness is taken as a secant [N] (default 1e6).
    #[arg(long, allow_negative_numbers = true)]
    pub contact_force: Option<f64>,
    /// A record of the calibration suite for the link's mass and damper, given once per
    /// record (default: the config's [record] alone; give several, pulse-like ones among
    /// them: docs/link.md): a file relative to the current directory, each read with the
    /// options below as `quakejoint record` reads it (a file of several channels needs
    /// --channel or --azimuth).
    #[arg(long)]
    pub record: Vec<PathBuf>,
    #[command(flatten)]
    pub read: RecordReadArgs,
    /// Skip the calibration suite: the mass of the joint's kinetic energy (the damper is the bushings').
    #[arg(long, conflicts_with = "record")]
    pub no_earthquake: bool,
    /// Folder for the exports: link.toml, link.tcl, link_opensees.py, link_sap2000.txt,
    /// loops.csv (default: the config's name with _link, next to it).
    #[arg(long)]
    pub output_dir: Option<PathBuf>,
    #[command(flatten)]
    pub print: PrintArgs,
}

/// A record file and how to read it (`record` and `spectrum`).
#[derive(Debug, Args)]
pub struct RecordFileArgs {
    /// The record: PEER NGA-West2 .AT2, ESM or K-NET ASCII, COSMOS, CSMIP
    /// Volume 1/2 (CESMD), two-column time/acceleration text or CSV, or
    /// one-column text (give --dt).
    pub file: PathBuf,
    #[command(flatten)]
    pub read: RecordReadArgs,
}

/// How to read a record file.
#[derive(Debug, Args)]
pub struct RecordReadArgs {
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
    /// Column holding the acceleration in a multi-column text file (1-based).
    #[arg(long)]
    pub column: Option<usize>,
    /// Channel of a COSMOS or CSMIP file that holds several, by its number
    /// in the file (`Chan 2`).
    #[arg(long)]
    pub channel: Option<u32>,
    /// Channel of a COSMOS or CSMIP file that holds several, by the
    /// direction it points [degrees clockwise from north].
    #[arg(long)]
    pub azimuth: Option<f64>,
    /// Read a vertical component (refused otherwise: the excitation is
    /// horizontal).
    #[arg(long)]
    pub allow_vertical: bool,
    /// Scale factor applied after the unit conversion (default 1).
    #[arg(long, allow_negative_numbers = true)]
    pub scale: Option<f64>,
    /// Scale the record to this peak ground acceleration [g].
    #[arg(long, allow_negative_numbers = true)]
    pub target_pga_g: Option<f64>,
}

/// Record file formats.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum FormatArg {
    /// From the extension (.at2), the header (ESM, K-NET, COSMOS, CSMIP) and --dt.
    Auto,
    /// PEER NGA-West2 AT2.
    At2,
    /// Time and acceleration columns.
    TwoColumn,
    /// Acceleration only, with --dt.
    OneColumn,
    /// ESM (ORFEUS) ASCII.
    Esm,
    /// K-NET / KiK-net ASCII.
    Knet,
    /// COSMOS V1/V2 acceleration.
    Cosmos,
    /// CSMIP/DMG Volume 1 or 2 (CESMD .v1, .RAW, .V2).
    #[value(alias = "dmg")]
    Csmip,
    /// Values in reading order, any number per line, with --dt.
    Sequence,
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
    pub fn spec(&self) -> RecordSpec {
        self.read.spec(&self.file)
    }
}

impl RecordReadArgs {
    /// Whether any option was given.
    pub fn any(&self) -> bool {
        self.format != FormatArg::Auto
            || self.units.is_some()
            || self.dt.is_some()
            || self.column.is_some()
            || self.channel.is_some()
            || self.azimuth.is_some()
            || self.allow_vertical
            || self.scale.is_some()
            || self.target_pga_g.is_some()
    }

    /// The spec of `file` read with these options.
    pub fn spec(&self, file: &std::path::Path) -> RecordSpec {
        let mut spec = RecordSpec::new(file);
        spec.format = match self.format {
            FormatArg::Auto => quakejoint_motion::Format::Auto,
            FormatArg::At2 => quakejoint_motion::Format::At2,
            FormatArg::TwoColumn => quakejoint_motion::Format::TwoColumn,
            FormatArg::OneColumn => quakejoint_motion::Format::OneColumn,
            FormatArg::Esm => quakejoint_motion::Format::Esm,
            FormatArg::Knet => quakejoint_motion::Format::Knet,
            FormatArg::Cosmos => quakejoint_motion::Format::Cosmos,
            FormatArg::Csmip => quakejoint_motion::Format::Csmip,
            FormatArg::Sequence => quakejoint_motion::Format::Sequence,
        };
        spec.units = self.units.map(|u| match u {
            UnitsArg::G => quakejoint_motion::Units::G,
            UnitsArg::MetersPerSecond2 => quakejoint_motion::Units::MetersPerSecond2,
            UnitsArg::CentimetersPerSecond2 => quakejoint_motion::Units::CentimetersPerSecond2,
        });
        spec.dt = self.dt;
        spec.column = self.column;
        spec.channel = self.channel;
        spec.azimuth = self.azimuth;
        spec.allow_vertical = self.allow_vertical;
        spec.scale = self.scale.unwrap_or(1.0);
        spec.target_pga_g = self.target_pga_g;
        spec
    }
}

#[derive(Debug, Args)]
pub struct RecordArgs {
    #[command(flatten)]
    pub record: RecordFileArgs,
    #[command(flatten)]
    pub print: PrintArgs,
}

#[derive(Debug, Args)]
pub struct SpectrumArgs {
    #[command(flatten)]
    pub record: RecordFileArgs,
    /// Damping ratios (several allowed: --damping 0.02 --damping 0.05, or 0.02,0.05).
    #[arg(long, value_delimiter = ',', default_values_t = [0.05], allow_negative_numbers = true)]
    pub damping: Vec<f64>,
    /// Periods [s] (comma-separated); overrides --from/--to/--count.
    #[arg(long, value_delimiter = ',', allow_negative_numbers = true)]
    pub periods: Vec<f64>,
    /// First period of the grid [s].
    #[arg(long, default_value_t = 0.02, allow_negative_numbers = true)]
    pub from: f64,
    /// Last period of the grid [s].
    #[arg(long, default_value_t = 10.0, allow_negative_numbers = true)]
    pub to: f64,
    /// Number of periods of the grid.
    #[arg(long, default_value_t = 60)]
    pub count: usize,
    /// Space the grid logarithmically (default: linearly).
    #[arg(long)]
    pub log: bool,
    /// Points per sample interval at which peaks are sought (1: the sample times).
    #[arg(long, default_value_t = 1)]
    pub subdivisions: u32,
    /// Print CSV (the default) with the columns damping [1], period [s], sa and psa [m/s^2], sd [m], sv [m/s] (the header gives the units), every digit.
    #[arg(long, conflicts_with = "json")]
    pub csv: bool,
    #[command(flatten)]
    pub print: PrintArgs,
}
