//! The interface's own words in both languages the app speaks. Deck texts
//! carry their own translations; these are the labels around them.

/// Hinglish (Hindi in Latin script), the second language of the app.
pub const HINGLISH: &str = "hi-Latn";
pub const ENGLISH: &str = "en";

/// Words in both languages, English first: the help text of a key, a
/// label a screen shows.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Words(pub &'static str, pub &'static str);

impl Words {
    pub fn get(&self, lang: &str) -> &'static str {
        if lang == HINGLISH { self.1 } else { self.0 }
    }
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Msg {
    AppTitle,
    Decks,
    New,
    Learning,
    Due,
    LastStudied,
    Never,
    Prompts,
    Sections,
    Help,
    HelpTitle,
    AnyKeyCloses,
    Enlarge,
    Language,
    LanguageName,
    Reader,
    Search,
    NoMatch,
    SeeAlso,
    NoSections,
    Review,
    Cram,
    ShowAnswer,
    Again,
    Hard,
    Good,
    Easy,
    TypeAnswer,
    Suggested,
    YouTyped,
    Accepted,
    RightAnswer,
    Explanation,
    TryPrompt,
    SessionDone,
    Reviewed,
    Time,
    AgainRate,
    NothingDue,
    Undone,
    NothingToUndo,
    Saved,
    Predict,
    Question,
    Commit,
    YourPrediction,
    Measured,
    Formula,
    Right,
    Wrong,
    Paused,
    Speed,
    Method,
    Step,
    Tolerance,
    EnergyDrift,
    MomentumDrift,
    ErrorVsExact,
    PerFrame,
    Running,
    Verdict,
    NotANumber,
    WrongUnit,
    Stats,
    DueForecast,
    ReviewsPerDay,
    Retention,
    PromptAccuracy,
    WorkPrecision,
    NoBench,
    Today,
    Tomorrow,
    Days,
    NoPrompts,
    Scene,
    Omega,
    Body,
    Polhode,
    Diagnostics,
    Back,
    Quit,
    // Short names of the home screen's keys.
    KeyReview,
    KeyCram,
    KeyRead,
    KeyPredict,
    KeyStats,
    // Run controls named under a simulation.
    Pause,
    Restart,
    Undo,
    UnitOptional,
    CommitFirst,
    NoStepToChange,
    Relearning,
    InReview,
    AllTime,
}

/// What the home screen says when no deck could be opened: how many deck
/// files failed and the command that shows why, or where decks were looked
/// for.
pub fn no_decks(lang: &str, load: &super::app::DeckLoad) -> String {
    let hi = lang == HINGLISH;
    let dir = load
        .from
        .as_ref()
        .map_or_else(|| "decks/".to_string(), |d| d.display().to_string());
    match (load.failed_files, hi) {
        (0, false) => {
            format!("No decks found in {dir}. Put deck files (*.toml) there, or pass --decks DIR.")
        }
        (0, true) => format!(
            "{dir} mein koi deck nahi mila. Wahan deck files (*.toml) rakho, ya --decks DIR do."
        ),
        (1, false) => format!(
            "No decks could be opened: 1 file has errors. Run `flipcard check {dir}` to see them."
        ),
        (n, false) => format!(
            "No decks could be opened: {n} files have errors. Run `flipcard check {dir}` to see them."
        ),
        (n, true) => format!(
            "Koi deck khul nahi saka: {} mein galtiyan hain. Dekhne ke liye `flipcard check {dir}` chalao.",
            crate::text::plural(n, "file", "files")
        ),
    }
}

pub fn tr(lang: &str, msg: Msg) -> &'static str {
    let hi = lang == HINGLISH;
    macro_rules! pick {
        ($en:expr, $hi:expr) => {
            if hi { $hi } else { $en }
        };
    }
    use Msg::*;
    match msg {
        AppTitle => "flipcard",
        Decks => pick!("Decks", "Decks"),
        New => pick!("new", "naye"),
        Learning => pick!("learning", "seekh rahe"),
        Due => pick!("due", "baaki"),
        LastStudied => pick!("last studied", "pichhli padhai"),
        Never => pick!("never", "kabhi nahi"),
        Prompts => pick!("Prompts and simulations", "Prompts aur simulations"),
        Sections => pick!("Sections", "Sections"),
        Help => pick!("help", "madad"),
        HelpTitle => pick!("Keys", "Keys"),
        AnyKeyCloses => pick!("any key closes", "koi bhi key band karti hai"),
        Enlarge => pick!(
            "Please enlarge the terminal (at least 40×12), or press q to quit.",
            "Terminal thoda bada karo (kam se kam 40×12), ya q dabao band karne ke liye."
        ),
        Language => pick!("language", "bhasha"),
        LanguageName => pick!("English", "Hinglish"),
        Reader => pick!("Reader", "Reader"),
        Search => pick!("search", "khojo"),
        NoMatch => pick!("no match", "kuch nahi mila"),
        SeeAlso => pick!("See also", "Yeh bhi dekho"),
        NoSections => pick!(
            "This deck has no explanation sections.",
            "Is deck mein koi explanation section nahi hai."
        ),
        Review => pick!("Review", "Review"),
        Cram => pick!("Cram", "Cram"),
        ShowAnswer => pick!("show answer", "jawab dikhao"),
        Again => pick!("Again", "Phir se"),
        Hard => pick!("Hard", "Mushkil"),
        Good => pick!("Good", "Theek"),
        Easy => pick!("Easy", "Aasaan"),
        TypeAnswer => pick!("Type your answer", "Apna jawab likho"),
        Suggested => pick!("suggested", "sujhaav"),
        YouTyped => pick!("you typed", "tumne likha"),
        Accepted => pick!("accepted", "sahi jawab"),
        RightAnswer => pick!("the physics says", "physics kehti hai"),
        Explanation => pick!("explanation", "samjhaav"),
        TryPrompt => pick!("try the prediction", "prediction try karo"),
        SessionDone => pick!("Session done", "Session khatam"),
        Reviewed => pick!("reviewed", "review kiye"),
        Time => pick!("time", "samay"),
        AgainRate => pick!("again-rate", "phir-se dar"),
        NothingDue => pick!(
            "Nothing due in this deck right now.",
            "Is deck mein abhi kuch baaki nahi hai."
        ),
        Undone => pick!("last rating undone", "pichhli rating wapas li"),
        NothingToUndo => pick!("nothing to undo", "wapas lene ko kuch nahi"),
        Saved => pick!("saved", "save hua"),
        Predict => pick!("Predict, then check", "Pehle andaaza, phir jaanch"),
        Question => pick!("Question", "Sawaal"),
        Commit => pick!("commit", "pakka karo"),
        YourPrediction => pick!("your prediction", "tumhara andaaza"),
        Measured => pick!("measured", "naapa gaya"),
        Formula => pick!("formula", "formula"),
        Right => pick!("Right!", "Sahi!"),
        Wrong => pick!("Not quite.", "Galat."),
        Paused => pick!("paused", "ruka hua"),
        Speed => pick!("speed", "speed"),
        Method => pick!("method", "method"),
        Step => pick!("step", "step"),
        Tolerance => pick!("tol", "tol"),
        EnergyDrift => pick!("ΔE/E", "ΔE/E"),
        MomentumDrift => pick!("Δ|L|/|L|", "Δ|L|/|L|"),
        ErrorVsExact => pick!("err vs exact", "exact se farq"),
        PerFrame => pick!("µs/frame", "µs/frame"),
        Running => pick!("running", "chal raha"),
        Verdict => pick!("Verdict", "Faisla"),
        NotANumber => pick!("not a number", "number nahi hai"),
        WrongUnit => pick!("unit should be", "unit hona chahiye"),
        Stats => pick!("Stats", "Stats"),
        DueForecast => pick!("Due forecast", "Aane wale din"),
        ReviewsPerDay => pick!("Reviews per day (30 days)", "Roz ke reviews (30 din)"),
        Retention => pick!("true retention", "asli yaad"),
        PromptAccuracy => pick!("prompt accuracy", "prompt sahi"),
        WorkPrecision => pick!(
            "Numerics: error against run time",
            "Numerics: error banaam run time"
        ),
        NoBench => pick!(
            "No bench-out/work_precision.csv yet: run `flipcard bench`.",
            "bench-out/work_precision.csv abhi nahi hai: `flipcard bench` chalao."
        ),
        Today => pick!("today", "aaj"),
        Tomorrow => pick!("tomorrow", "kal"),
        Days => pick!("days", "din"),
        NoPrompts => pick!(
            "This deck has no prompts.",
            "Is deck mein koi prompt nahi hai."
        ),
        Scene => pick!("scene", "scene"),
        Omega => pick!("ω₁ ω₂ ω₃ against time", "ω₁ ω₂ ω₃ samay ke saath"),
        Body => pick!("body", "body"),
        Polhode => pick!(
            "polhode on the momentum sphere",
            "momentum sphere par polhode"
        ),
        Diagnostics => pick!("diagnostics", "diagnostics"),
        Back => pick!("back", "wapas"),
        Quit => pick!("quit", "band karo"),
        KeyReview => pick!("review", "review"),
        KeyCram => pick!("cram", "cram"),
        KeyRead => pick!("read", "padho"),
        KeyPredict => pick!("predict", "andaaza"),
        KeyStats => pick!("stats", "stats"),
        Pause => pick!("pause", "roko"),
        Restart => pick!("restart", "phir se"),
        Undo => pick!("undo", "wapas lo"),
        UnitOptional => pick!("optional", "likhna zaroori nahi"),
        CommitFirst => pick!(
            "Commit first (Enter): the simulation runs only after you answer.",
            "Pehle jawab pakka karo (Enter): simulation uske baad hi chalega."
        ),
        NoStepToChange => pick!(
            "exact: no step to change (press m for another method)",
            "exact: koi step nahi badalta (doosra method: m dabao)"
        ),
        Relearning => pick!("relearning", "dobara seekh rahe"),
        InReview => pick!("review", "review"),
        AllTime => pick!("all time", "hamesha"),
    }
}

/// What the interface counts.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Noun {
    Card,
    Prompt,
    Section,
    DeckProblem,
}

/// `n` with its noun, agreeing: "1 card", "3 cards". Hinglish borrows the
/// English nouns with their English plurals; its own words take the Hindi
/// ones (galti, galtiyan).
pub fn count(lang: &str, n: usize, noun: Noun) -> String {
    let hi = lang == HINGLISH;
    let (one, many) = match noun {
        Noun::Card => ("card", "cards"),
        Noun::Prompt => ("prompt", "prompts"),
        Noun::Section => ("section", "sections"),
        Noun::DeckProblem if hi => (
            "decks mein galti (`flipcard check` chalao)",
            "decks mein galtiyan (`flipcard check` chalao)",
        ),
        Noun::DeckProblem => (
            "problem in the decks (run `flipcard check`)",
            "problems in the decks (run `flipcard check`)",
        ),
    };
    crate::text::plural(n, one, many)
}

/// "3h ago" / "3h pehle": how long since `secs` seconds, in the largest
/// whole unit.
pub fn ago(lang: &str, secs: i64) -> String {
    let secs = secs.max(0);
    let (n, unit) = match secs {
        s if s < 60 => (s, "s"),
        s if s < 3600 => (s / 60, "m"),
        s if s < 86_400 => (s / 3600, "h"),
        s => (s / 86_400, "d"),
    };
    let words = Words("{n}{unit} ago", "{n}{unit} pehle").get(lang);
    words.replace("{n}", &n.to_string()).replace("{unit}", unit)
}

/// How a measurement reads in the verdict.
pub fn measure(m: crate::deck::Measure) -> Words {
    use crate::deck::Measure as M;
    match m {
        M::Flips => Words("flips", "flips"),
        M::FlipPeriod => Words("flip period", "flip period"),
        M::GrowthRate => Words("growth rate", "growth rate"),
        M::EfoldTime => Words("e-folding time", "e-folding time"),
        M::OscillationFreq => Words("oscillation frequency", "oscillation frequency"),
        M::PrecessionRate => Words("precession rate", "precession rate"),
        M::PrecessionPeriod => Words("precession period", "precession period"),
        M::OmegaChange => Words("largest change of ω", "ω ka sabse bada badlaav"),
        M::EnergyDrift => Words("energy drift", "energy drift"),
        M::MomentumDrift => Words("|L| drift", "|L| drift"),
    }
}

/// The other language of the two.
pub fn other(lang: &str) -> &'static str {
    if lang == HINGLISH { ENGLISH } else { HINGLISH }
}

/// The words of a prediction's verdict and of the simulation around it.
pub mod sim_words {
    use super::Words;

    pub const RIGHT: Words = Words("Right", "Sahi");
    pub const WRONG: Words = Words("Wrong", "Galat");
    /// `{d}`: the run's length with its unit.
    pub const IN_THIS_RUN: Words = Words("in this {d} run", "is {d} ke run mein");
    pub const FLIPPED_NONE: Words = Words("did not flip", "ek baar bhi nahi palta");
    pub const FLIPPED_ONCE: Words = Words("flipped once: at {times}", "ek baar palta: {times} par");
    pub const FLIPPED_MANY: Words = Words(
        "flipped {n} times: at {times}",
        "{n} baar palta: {times} par",
    );
    pub const AND: Words = Words("and", "aur");
    pub const NOT_MEASURED: Words = Words(
        "could not be measured in this run",
        "is run mein naapa nahi ja saka",
    );
    pub const FORMULA: Words = Words("formula", "formula");
    pub const DECK_ANSWER: Words = Words("the deck's answer", "deck ka jawaab");
    pub const WORKED: Words = Words("worked out", "hisaab");
    pub const RIGHT_IN_RUN: Words = Words("right in this run", "is run mein sahi");
    pub const NEXT: Words = Words("next prompt", "agla prompt");
    pub const FLIPS: Words = Words("flips", "flips");
    pub const GROWTH: Words = Words("|ω⊥|, log scale", "|ω⊥|, log scale");
    pub const FORMULA_SLOPE: Words = Words("slope √k", "slope √k");
    pub const NEVER: Words = Words("not tried", "abhi nahi");

    /// The body's shape as the panel's title names it.
    pub const SPHERE: Words = Words("sphere", "sphere (gola)");
    pub const PLATE: Words = Words("flat plate", "patli plate");
    pub const BLOCK: Words = Words("block", "block");
    pub const OBLATE: Words = Words("oblate spheroid", "chapta spheroid");
    pub const PROLATE: Words = Words("prolate spheroid", "lamba spheroid");
    pub const NEEDLE: Words = Words("needle", "needle (sui)");
}
