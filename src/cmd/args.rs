//! Command-line interface. Spellings here are contracts: users' scripts and
//! outside checks depend on them; extend, never rename.

use std::path::PathBuf;

use clap::{ArgGroup, Args, Parser, Subcommand, ValueEnum};

#[derive(Debug, Parser)]
#[command(
    name = "flipcard",
    version,
    about = "Learn physics in the terminal: flashcards, explanations and predict-then-check simulations"
)]
pub struct Cli {
    /// Where the review database lives (default: the platform data dir).
    #[arg(long, global = true, env = "FLIPCARD_DATA_DIR", value_name = "DIR")]
    pub data_dir: Option<PathBuf>,
    /// Configuration file (default: config.toml in the platform config dir).
    #[arg(long, global = true, env = "FLIPCARD_CONFIG", value_name = "FILE")]
    pub config: Option<PathBuf>,
    /// Folder of decks to open (default: the bundled decks).
    #[arg(long, global = true, env = "FLIPCARD_DECKS", value_name = "DIR")]
    pub decks: Option<PathBuf>,
    #[command(subcommand)]
    pub command: Option<Command>,
}

#[derive(Debug, Subcommand)]
pub enum Command {
    /// Open the review of a deck directly (default: the first deck).
    Review(ReviewArgs),
    /// Validate decks and their explanation texts; report every problem.
    Check(CheckArgs),
    /// Run the rigid-body simulator headless.
    Sim(SimArgs),
    /// Work–precision sweep of every solver: error against run time.
    Bench(BenchArgs),
    /// Review statistics.
    Stats(StatsArgs),
    /// Export the review log or a deck's cards.
    Export(ExportArgs),
    /// Turn a CSV of cards (front, back, tags) into a deck file on stdout.
    Import(ImportArgs),
    /// Maintenance of the review database.
    Db(DbArgs),
}

#[derive(Debug, Args)]
pub struct ReviewArgs {
    /// Deck id.
    pub deck: Option<String>,
    /// Cram: review now regardless of due dates (does not change scheduling).
    #[arg(long)]
    pub cram: bool,
}

#[derive(Debug, Args)]
pub struct CheckArgs {
    /// Deck files or folders of decks (default: the bundled decks/).
    pub paths: Vec<PathBuf>,
    /// Skip running each prompt's scene to check its expected answer.
    #[arg(long)]
    pub no_simulate: bool,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum MethodArg {
    Exact,
    Adaptive,
    Splitting,
    Splitting4,
    Rk4,
}

impl From<MethodArg> for crate::sim::Kind {
    fn from(m: MethodArg) -> Self {
        use crate::sim::Kind;
        match m {
            MethodArg::Exact => Kind::Exact,
            MethodArg::Adaptive => Kind::Adaptive,
            MethodArg::Splitting => Kind::Splitting,
            MethodArg::Splitting4 => Kind::Splitting4,
            MethodArg::Rk4 => Kind::Rk4,
        }
    }
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum SimFormat {
    Csv,
    Json,
}

#[derive(Debug, Args)]
#[command(group(ArgGroup::new("scenes").args(["scene", "list"])))]
pub struct SimArgs {
    /// Principal moments I1,I2,I3 (kg·m²), in any order.
    #[arg(long, value_name = "I1,I2,I3", allow_hyphen_values = true)]
    pub inertia: Option<String>,
    /// Body-frame angular velocity W1,W2,W3 at t = 0 (rad/s).
    #[arg(long, value_name = "W1,W2,W3", allow_hyphen_values = true)]
    pub omega: Option<String>,
    /// End time T.
    #[arg(long, value_name = "T", allow_hyphen_values = true)]
    pub t_end: Option<String>,
    /// Number of samples at t = k·T/(N−1).
    #[arg(
        long,
        value_name = "N",
        default_value_t = 101,
        allow_hyphen_values = true
    )]
    pub samples: usize,
    #[arg(long, value_enum, default_value_t = MethodArg::Exact)]
    pub method: MethodArg,
    /// Tolerance of the adaptive solver (default 1e-10).
    #[arg(long, value_name = "TOL", allow_hyphen_values = true)]
    pub tol: Option<f64>,
    /// Step of the fixed-step solvers (default: 256 steps per turn of the
    /// fastest rate of the motion).
    #[arg(long, value_name = "DT", allow_hyphen_values = true)]
    pub dt: Option<f64>,
    #[arg(long, value_enum, default_value_t = SimFormat::Csv)]
    pub format: SimFormat,
    /// Run a deck scene and print its measurements.
    #[arg(long, value_name = "ID", conflicts_with_all = ["inertia", "omega", "t_end", "list"])]
    pub scene: Option<String>,
    /// Deck file or folder to take --scene from, or to --list (default:
    /// --decks, else the bundled decks).
    #[arg(long, value_name = "PATH", requires = "scenes")]
    pub deck: Option<PathBuf>,
    /// List the scenes of the decks (--deck, else --decks, else the bundled
    /// decks).
    #[arg(long, conflicts_with_all = ["inertia", "omega", "t_end"])]
    pub list: bool,
}

#[derive(Debug, Args)]
pub struct BenchArgs {
    /// A short sweep (fewer settings, shorter spans) for a quick look.
    #[arg(long)]
    pub quick: bool,
    /// Where to write work_precision.csv and work_precision.svg.
    #[arg(long, value_name = "DIR", default_value = "bench-out")]
    pub out: PathBuf,
}

#[derive(Debug, Args)]
pub struct StatsArgs {
    #[arg(long, value_name = "ID")]
    pub deck: Option<String>,
    #[arg(long)]
    pub json: bool,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum ExportFormat {
    Json,
    Csv,
}

#[derive(Debug, Args)]
pub struct ExportArgs {
    /// Export the whole review log.
    #[arg(long, conflicts_with = "deck", required_unless_present = "deck")]
    pub reviews: bool,
    /// Export a deck's cards (front, back, tags).
    #[arg(long, value_name = "ID")]
    pub deck: Option<String>,
    #[arg(long, value_enum)]
    pub format: Option<ExportFormat>,
}

#[derive(Debug, Args)]
pub struct ImportArgs {
    /// CSV file with front, back, tags columns.
    pub file: PathBuf,
    /// Id of the deck to write.
    #[arg(long, value_name = "ID")]
    pub deck_id: String,
    /// Language of the texts (a BCP 47 tag such as en or hi-Latn).
    #[arg(long, value_name = "TAG", default_value = "en")]
    pub lang: String,
}

#[derive(Debug, Args)]
pub struct DbArgs {
    #[command(subcommand)]
    pub command: DbCommand,
}

#[derive(Debug, Args)]
pub struct RestoreArgs {
    /// The backup to restore (default: the newest in the data dir).
    pub backup: Option<PathBuf>,
    /// Restore even when the current database is sound (it is set aside,
    /// with every rating made since the backup).
    #[arg(long)]
    pub force: bool,
}

#[derive(Debug, Subcommand)]
pub enum DbCommand {
    /// Rebuild the cached card states from the review log alone.
    Rebuild,
    /// Set a damaged database aside (it is kept) and restore a backup.
    Restore(RestoreArgs),
}
