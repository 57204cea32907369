//! Command-line interface. Spellings here are contracts: users' scripts and
//! outside checks depend on them; extend, never rename.

use std::path::PathBuf;

use clap::builder::PossibleValue;
use clap::{ArgGroup, Args, Parser, Subcommand, ValueEnum};

use crate::sim::method::MethodName;

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
    /// A folder of decks to open besides the bundled decks, the library and
    /// the config's `deck_paths` (repeatable).
    #[arg(long, global = true, env = "FLIPCARD_DECKS", value_name = "DIR")]
    pub decks: Vec<PathBuf>,
    #[command(subcommand)]
    pub command: Option<Command>,
}

#[derive(Debug, Subcommand)]
pub enum Command {
    /// Open the review of a deck directly (default: the first deck).
    Review(ReviewArgs),
    /// Validate decks and their explanation texts; report every problem.
    Check(CheckArgs),
    /// Run the simulator headless: a rigid body from its inertia and spin, or
    /// any deck scene (`--scene`), a rigid body or an ODE system.
    Sim(SimArgs),
    /// Work–precision sweep of every solver: error against run time.
    Bench(BenchArgs),
    /// Grade a formula answer against a deck's formula card or prompt, as
    /// the app would (exit 0 right, 1 wrong, 2 a usage or deck error): for
    /// testing answer keys in CI.
    Grade(GradeArgs),
    /// Review statistics.
    Stats(StatsArgs),
    /// Export the review log or a deck's cards.
    Export(ExportArgs),
    /// Turn a CSV of cards (front, back, tags) into a deck file on stdout.
    Import(ImportArgs),
    /// Maintenance of the review database.
    Db(DbArgs),
    /// Fit FSRS's parameters to your own reviews.
    Optimize(OptimizeArgs),
    /// Plan the reviews that bring every card to a target recall on an exam day.
    Plan(PlanArgs),
    /// List items with their schedule and status; suspend, unsuspend, bury.
    Cards(CardsArgs),
    /// Write the JSON Schemas of deck and content files, for editors.
    Schema(SchemaArgs),
    /// The deck library: list every deck, add one, remove one.
    Decks(DecksArgs),
    /// A class report from learners' exported reviews and prompt attempts.
    Report(ReportArgs),
    /// Exchange reviews with this learner's other machines through a
    /// folder that another tool (Syncthing, Dropbox, a network drive) syncs.
    Sync(SyncArgs),
}

#[derive(Debug, Args)]
pub struct ReviewArgs {
    /// Deck id (without it: the first deck, or every deck when a filter
    /// --tag, --state or --due-within is given).
    pub deck: Option<String>,
    /// Cram: review now regardless of due dates (does not change scheduling).
    #[arg(long)]
    pub cram: bool,
    /// Only cards with this tag (repeat for several: all must hold).
    #[arg(long, value_name = "T")]
    pub tag: Vec<String>,
    /// Only items in this state: new, learning, review, relearning,
    /// suspended, leech or buried (repeat for any of several).
    #[arg(long, value_name = "STATE")]
    pub state: Vec<String>,
    /// Only items due within this span from now (3d, 12h, 2w).
    #[arg(long, value_name = "SPAN")]
    pub due_within: Option<String>,
}

#[derive(Debug, Args)]
pub struct CheckArgs {
    /// Deck files or folders of decks (default: the bundled decks/).
    pub paths: Vec<PathBuf>,
    /// Skip running each prompt's scene to check its expected answer.
    #[arg(long)]
    pub no_simulate: bool,
}

#[derive(Debug, Args)]
#[command(group(ArgGroup::new("item").args(["prompt", "card"]).required(true)))]
pub struct GradeArgs {
    /// The deck's id (among the bundled decks, the library and --decks).
    #[arg(long, value_name = "ID")]
    pub deck: String,
    /// A formula prompt of the deck.
    #[arg(long, value_name = "P")]
    pub prompt: Option<String>,
    /// A formula card of the deck.
    #[arg(long, value_name = "C")]
    pub card: Option<String>,
    /// The answer, as a learner types it: (I2-I3)*w2*w3/I1, ^ for powers,
    /// 2x for 2*x, I_2 or I2 alike.
    #[arg(allow_hyphen_values = true, value_name = "ANSWER")]
    pub answer: String,
}

/// `--method`: a view of the one vocabulary of methods
/// (`sim::method`), which gives the spellings, the help and which
/// scenes take which.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum MethodArg {
    Exact,
    Adaptive,
    Splitting,
    Splitting4,
    Rk4,
    Auto,
    Radau,
    Verlet,
    Verlet4,
}

impl MethodArg {
    const ALL: [MethodArg; 9] = [
        MethodArg::Exact,
        MethodArg::Adaptive,
        MethodArg::Splitting,
        MethodArg::Splitting4,
        MethodArg::Rk4,
        MethodArg::Auto,
        MethodArg::Radau,
        MethodArg::Verlet,
        MethodArg::Verlet4,
    ];

    /// The method of the vocabulary (same order).
    pub fn method(self) -> MethodName {
        MethodName::ALL[self as usize]
    }

    /// The spelling on the command line.
    pub fn name(self) -> &'static str {
        self.method().name()
    }
}

impl ValueEnum for MethodArg {
    fn value_variants<'a>() -> &'a [Self] {
        &MethodArg::ALL
    }

    fn to_possible_value(&self) -> Option<PossibleValue> {
        let row = self.method().row();
        let value = PossibleValue::new(row.name);
        Some(match row.help {
            Some(help) => value.help(help),
            None => value,
        })
    }
}

impl TryFrom<MethodArg> for crate::sim::Kind {
    type Error = anyhow::Error;
    /// The rigid-body family; `auto` and `radau` are for systems.
    fn try_from(m: MethodArg) -> anyhow::Result<Self> {
        Self::from_method(m.method()).map_err(|e| anyhow::anyhow!("--method {}: {e}", m.name()))
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
    /// Number of samples at t = k·T/(N−1) (default 101; with --scene,
    /// prints the scene's run sampled so instead of its measurements).
    #[arg(long, value_name = "N", allow_hyphen_values = true)]
    pub samples: Option<usize>,
    /// Default: exact for a rigid body, auto for a system scene.
    #[arg(long, value_enum)]
    pub method: Option<MethodArg>,
    /// With --scene: print this measure of the run (repeatable), e.g.
    /// 'period(theta)' on a system scene or 'flips' on a rigid body.
    #[arg(
        long,
        value_name = "EXPR",
        requires = "scene",
        conflicts_with = "samples"
    )]
    pub measure: Vec<String>,
    /// Tolerance of the adaptive solver (default 1e-10; 1e-8 relative for
    /// systems; the step for rk4 on a system).
    #[arg(long, value_name = "TOL", allow_hyphen_values = true)]
    pub tol: Option<f64>,
    /// With a system scene: the absolute tolerance, one number for every
    /// variable or NAME=VALUE pairs for some (`y2=1e-20,y3=1e-20`; the
    /// others keep the scene's or the default); replaces the scene's `atol`.
    #[arg(long, value_name = "ATOL", requires = "scene")]
    pub atol: Option<String>,
    /// Step of the fixed-step solvers (default: 256 steps per turn of the
    /// fastest rate of the motion).
    #[arg(long, value_name = "DT", allow_hyphen_values = true)]
    pub dt: Option<f64>,
    #[arg(long, value_enum, default_value_t = SimFormat::Csv)]
    pub format: SimFormat,
    /// With --samples: say what the run did (steps, rejected steps,
    /// right-hand-side and Jacobian evaluations, LU decompositions and
    /// their form: dense, banded or sparse; when auto switched), one line
    /// on stderr after the CSV. JSON always holds it, as "stats".
    #[arg(long)]
    pub stats: bool,
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
    /// With --scene: a prompt on the scene; prints its question and the
    /// answer the run gives (with --variant, of that variant).
    #[arg(long, value_name = "P", requires = "scene", conflicts_with_all = ["samples", "measure"])]
    pub prompt: Option<String>,
    /// With --prompt: the seed of a varied prompt's numbers (0 to 2^53 − 1,
    /// as an attempt stores it): prints the drawn values, the question and
    /// the computed answer.
    #[arg(long, value_name = "SEED", requires = "prompt")]
    pub variant: Option<u64>,
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
    #[arg(
        long,
        conflicts_with_all = ["deck", "attempts", "apkg"],
        required_unless_present_any = ["deck", "attempts", "apkg"]
    )]
    pub reviews: bool,
    /// Export every predict-then-check attempt.
    #[arg(long, conflicts_with_all = ["deck", "apkg"])]
    pub attempts: bool,
    /// Export a deck's cards (front, back, tags); with --apkg, only that
    /// deck goes into the package.
    #[arg(long, value_name = "ID")]
    pub deck: Option<String>,
    #[arg(long, value_enum, conflicts_with = "apkg")]
    pub format: Option<ExportFormat>,
    /// Write an Anki package (.apkg) to FILE: every deck (or --deck ID)
    /// with its notes, tags, card states and review history.
    #[arg(long, value_name = "FILE")]
    pub apkg: Option<PathBuf>,
}

#[derive(Debug, Args)]
pub struct ImportArgs {
    /// CSV file with front, back, tags columns; with --reviews, a review
    /// log as `export --reviews` writes it; or an Anki .apkg / .colpkg.
    pub file: PathBuf,
    /// Id of the deck to write (CSV of cards only).
    #[arg(long, value_name = "ID")]
    pub deck_id: Option<String>,
    /// Language of the texts (a BCP 47 tag such as en or hi-Latn).
    #[arg(long, value_name = "TAG", default_value = "en")]
    pub lang: String,
    /// FILE is a review log (JSON or CSV) to merge into this one.
    #[arg(long, conflicts_with_all = ["deck_id", "out"])]
    pub reviews: bool,
    /// Format of the review log (default: from the file's extension).
    #[arg(long, value_enum, requires = "reviews")]
    pub format: Option<ExportFormat>,
    /// Where an Anki import writes its deck folder (default: ./anki-import).
    #[arg(long, value_name = "DIR")]
    pub out: Option<PathBuf>,
    /// Anki import: merge the decks' options into config.toml as presets
    /// (`[preset.NAME]`, `[deck.ID] preset = "NAME"`) instead of only
    /// writing them to DIR/anki-presets.toml.
    #[arg(long, conflicts_with = "reviews")]
    pub merge_presets: bool,
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

#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum ReportFormat {
    Text,
    Json,
}

#[derive(Debug, Args)]
pub struct OptimizeArgs {
    /// Fit to one deck's reviews only (default: every deck).
    #[arg(long, value_name = "ID")]
    pub deck: Option<String>,
    /// Write the fitted parameters to the config file (fsrs_parameters),
    /// unless they predict the held-out reviews worse than the current ones.
    #[arg(long)]
    pub apply: bool,
    /// With --apply: write the fitted parameters even when they predict
    /// the held-out reviews worse than the current ones.
    #[arg(long, requires = "apply")]
    pub force: bool,
    #[arg(long, value_enum, default_value_t = ReportFormat::Text)]
    pub format: ReportFormat,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum PlanFormat {
    Text,
    Json,
}

#[derive(Debug, Args)]
pub struct PlanArgs {
    /// The exam day (YYYY-MM-DD, a study day in local time), remembered
    /// until it passes (default: the one remembered).
    #[arg(long, value_name = "DATE", allow_hyphen_values = true)]
    pub exam: Option<String>,
    /// Plan for one deck (default: every deck loaded).
    #[arg(long, value_name = "ID")]
    pub deck: Option<String>,
    /// Recall probability every card should have on the exam day, between
    /// 0 and 1 (default: the configured desired retention).
    #[arg(long, value_name = "R", allow_hyphen_values = true)]
    pub retention: Option<String>,
    /// Most reviews planned on one day (default: the configured daily
    /// review limit).
    #[arg(long, value_name = "N", allow_hyphen_values = true)]
    pub max_per_day: Option<String>,
    #[arg(long, value_enum, default_value_t = PlanFormat::Text)]
    pub format: PlanFormat,
}

#[derive(Debug, Args)]
pub struct CardsArgs {
    #[command(subcommand)]
    pub command: CardsCommand,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum CardsFormat {
    Csv,
    Json,
}

#[derive(Debug, Args)]
pub struct CardsListArgs {
    /// Free text and filters as in Anki's browser: deck:ID tag:T state:S is:due|new|suspended|buried|leech rated:N prop:ivl>30 flag:N due:<3d, `or`, `-term` (cards list -tag:T), parentheses, `*`.
    #[arg(allow_hyphen_values = true)]
    pub query: Vec<String>,
    #[arg(long, value_enum, default_value_t = CardsFormat::Csv)]
    pub format: CardsFormat,
}

#[derive(Debug, Args)]
pub struct CardsItemsArgs {
    /// DECK/CARD (all its directions) or DECK/CARD/DIRECTION.
    #[arg(required = true, value_name = "ITEM")]
    pub items: Vec<String>,
}

#[derive(Debug, Subcommand)]
pub enum CardsCommand {
    /// Print every item matching QUERY, one row each.
    List(CardsListArgs),
    /// Take items out of every queue until unsuspended.
    Suspend(CardsItemsArgs),
    /// Bring suspended (or buried) items back.
    Unsuspend(CardsItemsArgs),
    /// Take items out of the queue until the next study day starts.
    Bury(CardsItemsArgs),
}

#[derive(Debug, Args)]
pub struct SchemaArgs {
    /// Folder to write deck.schema.json and content.schema.json into
    /// (created if missing).
    #[arg(long, value_name = "DIR", default_value = "schema")]
    pub out: PathBuf,
}

#[derive(Debug, Args)]
pub struct DecksArgs {
    #[command(subcommand)]
    pub command: Option<DecksCommand>,
}

#[derive(Debug, Subcommand)]
pub enum DecksCommand {
    /// Copy a deck (its file and content files) into the library, after
    /// `check` passes.
    Add(DecksAddArgs),
    /// Remove a deck from the library (its review history is kept).
    Remove(DecksRemoveArgs),
}

#[derive(Debug, Args)]
pub struct DecksAddArgs {
    /// A deck file, a folder of deck files, or a folder holding `decks/`
    /// and `content/`.
    pub path: PathBuf,
}

#[derive(Debug, Args)]
pub struct DecksRemoveArgs {
    /// Deck id.
    pub id: String,
}

#[derive(Debug, Args)]
pub struct ReportArgs {
    /// Learners' exports (`export --reviews`, `export --attempts`; JSON or
    /// CSV), one learner per file name.
    #[arg(required = true)]
    pub files: Vec<PathBuf>,
    /// Only this deck.
    #[arg(long, value_name = "ID")]
    pub deck: Option<String>,
    /// Where to write report.html and report.csv.
    #[arg(long, value_name = "DIR")]
    pub out: Option<PathBuf>,
    /// The language of the cards', prompts' and answers' texts (a BCP 47
    /// tag such as en or hi-Latn; a deck without it shows its first).
    #[arg(long, value_name = "TAG", default_value = "en")]
    pub lang: String,
}

#[derive(Debug, Args)]
pub struct SyncArgs {
    /// The synced folder (default: `sync_dir` in the config).
    pub dir: Option<PathBuf>,
}
