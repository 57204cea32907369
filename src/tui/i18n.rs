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
    FormulaSheet,
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
    CannotKeepUp,
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
    FormulaUnreadable,
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
    PromptScheduled,
    BackIn,
    NotRatedPractice,
    PredictItem,
    PredictItemHint,
    EscOnHome,
    SiblingWaits,
    Relearning,
    InReview,
    AllTime,
    // The memory panel of the stats screen.
    Calendar,
    Less,
    More,
    TrueRetention,
    Young,
    Mature,
    Yesterday,
    Week,
    Month,
    Year,
    RecallNow,
    FsrsDefault,
    FsrsFitted,
    Exam,
    // Suspend, bury, leeches, the card browser and the study filter.
    Filtered,
    /// After the cards left of a session from the exam plan.
    LeftInExamPlan,
    /// After the cards left of a filtered session.
    LeftInFilter,
    CardSuspended,
    CardBuried,
    CardUnsuspended,
    SuspendedMeanwhile,
    LeechSuspended,
    LeechMarked,
    Browser,
    DeckCheck,
    FilterTitle,
    KeyBrowse,
    KeyFilter,
    ColDeck,
    ColCard,
    ColQuestion,
    ColDirection,
    ColState,
    CardInfo,
    SuspendUndone,
    BuryUndone,
    UnsuspendUndone,
    ColDue,
    ColStability,
    ColDifficulty,
    ColRetrievability,
    ColReviews,
    ColLapses,
    ColStatus,
    Suspended,
    Buried,
    Leech,
    Items,
    SortedBy,
    SearchHint,
    NothingMatches,
    FieldTag,
    FieldState,
    FieldDueWithin,
    FieldCram,
    AnyState,
    Yes,
    No,
    Matching,
    StartFiltered,
    NoExplanation,
    SuspendedNeedsCram,
    BrowserKeys,
}

/// What the home screen says when no deck could be opened: how many deck
/// files failed and the command that shows why, or where decks were looked
/// for.
/// `from`: the folder (or file) the decks came from; `failed_files`: the
/// deck files with errors.
pub fn no_decks(lang: &str, from: Option<&std::path::Path>, failed_files: usize) -> String {
    let hi = lang == HINGLISH;
    let dir = from.map_or_else(|| "decks/".to_string(), |d| d.display().to_string());
    match (failed_files, hi) {
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
        FormulaSheet => pick!("Formula sheet", "Formula sheet"),
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
        CannotKeepUp => pick!(
            "slower than shown: the steps cannot keep up",
            "dikhaye se dheema: steps saath nahi de pa rahe"
        ),
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
        FormulaUnreadable => pick!("cannot read this formula", "yeh formula padha nahi gaya"),
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
        SiblingWaits => pick!(
            "its other direction waits until tomorrow (siblings are buried)",
            "iski doosri direction kal aayegi (siblings bury hote hain)"
        ),
        EscOnHome => pick!(
            "you are on the first screen: q quits",
            "yeh pehli screen hai: band karne ke liye q dabao"
        ),
        PromptScheduled => pick!("prediction scheduled", "prediction schedule hua"),
        BackIn => pick!("back in", "wapas aayega"),
        NotRatedPractice => pick!(
            "practice: this prompt was not due, so its schedule is unchanged",
            "practice: yeh prompt due nahi tha, iska schedule wahi hai"
        ),
        PredictItem => pick!("Predict, then check", "Pehle predict, phir check"),
        PredictItemHint => pick!(
            "Enter opens it with new numbers; the verdict rates it (wrong: Again, right: Good)",
            "Enter se naye numbers ke saath khulega; verdict hi rating dega (galat: Again, sahi: Good)"
        ),
        NoStepToChange => pick!(
            "exact: no step to change (press m for another method)",
            "exact: koi step nahi badalta (doosra method: m dabao)"
        ),
        Relearning => pick!("relearning", "dobara seekh rahe"),
        InReview => pick!("review", "review"),
        AllTime => pick!("all time", "hamesha"),
        Calendar => pick!("Reviews by day", "Roz ke reviews"),
        Less => pick!("less", "kam"),
        More => pick!("more", "zyada"),
        TrueRetention => pick!("True retention", "Asli yaad"),
        Young => pick!("young <21d", "naye <21d"),
        Mature => pick!("mature", "pakke"),
        Yesterday => pick!("yesterday", "kal"),
        Week => pick!("7 days", "7 din"),
        Month => pick!("30 days", "30 din"),
        Year => pick!("365 days", "365 din"),
        RecallNow => pick!("Recall now", "Abhi yaad"),
        FsrsDefault => pick!("FSRS defaults", "FSRS default"),
        FsrsFitted => pick!("FSRS fitted", "FSRS fit kiya"),
        Exam => pick!("Exam", "Exam"),
        Filtered => pick!("filtered", "filtered"),
        LeftInExamPlan => pick!("left today in the exam plan", "exam plan mein aaj baaki"),
        LeftInFilter => pick!("left in this filter", "is filter mein baaki"),
        CardSuspended => pick!(
            "card suspended (u undoes)",
            "card suspend kiya (u se wapas)"
        ),
        CardBuried => pick!(
            "card buried until tomorrow (u undoes)",
            "card kal tak ke liye hataya (u se wapas)"
        ),
        CardUnsuspended => pick!("card back in the queues", "card wapas queue mein"),
        SuspendedMeanwhile => pick!(
            "this card was suspended or buried meanwhile: the rating was not recorded",
            "yeh card is beech suspend ya bury hua: rating record nahi hui"
        ),
        LeechSuspended => pick!(
            "leech: forgotten too often, so suspended (u undoes)",
            "leech: baar baar bhoola, isliye suspend kiya (u se wapas)"
        ),
        LeechMarked => pick!(
            "leech: forgotten too often (marked in the browser)",
            "leech: baar baar bhoola (browser mein nishaan laga)"
        ),
        Browser => pick!("Card browser", "Card browser"),
        DeckCheck => pick!("Deck check", "Deck check"),
        FilterTitle => pick!("Study filter", "Padhai filter"),
        KeyBrowse => pick!("browse", "browse"),
        KeyFilter => pick!("filter", "filter"),
        ColDeck => pick!("deck", "deck"),
        ColCard => pick!("card", "card"),
        ColQuestion => pick!("question", "sawaal"),
        ColDirection => pick!("dir", "dir"),
        ColState => pick!("state", "state"),
        CardInfo => pick!("Card info", "Card info"),
        SuspendUndone => pick!("suspend undone", "suspend wapas liya"),
        BuryUndone => pick!("bury undone", "bury wapas liya"),
        UnsuspendUndone => pick!("unsuspend undone", "unsuspend wapas liya"),
        ColDue => pick!("due", "baaki"),
        ColStability => pick!("stab", "stab"),
        ColDifficulty => pick!("diff", "diff"),
        ColRetrievability => pick!("recall", "yaad"),
        ColReviews => pick!("revs", "revs"),
        ColLapses => pick!("lapses", "bhoole"),
        ColStatus => pick!("status", "status"),
        Suspended => pick!("suspended", "suspended"),
        Buried => pick!("buried", "buried"),
        Leech => pick!("leech", "leech"),
        Items => pick!("items", "items"),
        SortedBy => pick!("sorted by", "sort"),
        SearchHint => pick!(
            "/ search: text deck: tag: is:due|new|leech rated:7 prop:ivl>30 or - ()",
            "/ khojo: text deck: tag: is:due|new|leech rated:7 prop:ivl>30 or - ()"
        ),
        NothingMatches => pick!("nothing matches", "kuch nahi mila"),
        FieldTag => pick!("tag", "tag"),
        FieldState => pick!("state", "state"),
        FieldDueWithin => pick!("due within", "itne mein baaki"),
        FieldCram => pick!("cram", "cram"),
        AnyState => pick!("any", "koi bhi"),
        Yes => pick!("yes", "haan"),
        No => pick!("no", "nahi"),
        Matching => pick!("matching items", "milte items"),
        StartFiltered => pick!("Enter starts the session", "Enter se session shuru"),
        BrowserKeys => pick!(
            "/ search  s suspend  b bury  U unsuspend  Enter preview  e explain  o sort",
            "/ khojo  s suspend  b bury  U unsuspend  Enter dekho  e samjhaav  o sort"
        ),
        SuspendedNeedsCram => pick!(
            "suspended cards are out of every queue: add cram to look through them, or unsuspend them",
            "suspended cards har queue se bahar hain: dekhne ke liye cram lagao, ya unsuspend karo"
        ),
        NoExplanation => pick!(
            "this card links to no explanation",
            "is card se koi explanation juda nahi"
        ),
    }
}

/// What the interface counts.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Noun {
    Card,
    Prompt,
    Section,
    DeckProblem,
    Link,
    /// A count of new cards: "1 new", "1 naya", "20 naye".
    New,
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
        Noun::Link => ("link", "links"),
        Noun::New if hi => ("naya", "naye"),
        Noun::New => ("new", "new"),
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

/// How a measurement reads in the verdict (its row's `words` in the
/// measure vocabulary).
pub fn measure(m: crate::deck::Measure) -> Words {
    let (en, hi) = crate::sim::scene::vocabulary::row_of(m).words;
    Words(en, hi)
}

/// A system measure's statistic, as the verdict reads it.
pub fn stat_words(stat: crate::sim::scene::spec::Stat) -> Words {
    use crate::sim::scene::vocabulary::{MeasureKind, row_kind};
    let (en, hi) = row_kind(MeasureKind::System(stat)).words;
    Words(en, hi)
}

/// How a measurement is named in the verdict: the rigid-body measure's
/// words, or the statistic with the quantity it is of ("period of θ",
/// "θ ka period").
pub fn measure_label(m: crate::deck::Measure, lang: &str) -> String {
    match m {
        crate::deck::Measure::Of(stat, name) => {
            let name = crate::text::variable_name(name.as_str());
            let stat = stat_words(stat).get(lang);
            if lang == HINGLISH {
                format!("{name} ka {stat}")
            } else {
                format!("{stat} of {name}")
            }
        }
        m => measure(m).get(lang).to_string(),
    }
}

/// The other language of the two.
pub fn other(lang: &str) -> &'static str {
    if lang == HINGLISH { ENGLISH } else { HINGLISH }
}

/// The exam mode's words.
pub mod exam {
    use super::{HINGLISH, Words};

    pub const DATE_PROMPT: Words = Words(
        "Exam date (YYYY-MM-DD), then Enter:",
        "Exam ki tareekh (YYYY-MM-DD), phir Enter:",
    );
    pub const DATE_HINT: Words = Words(
        "Today's share of the plan is studied at once; the rest comes on its days.",
        "Plan ka aaj ka hissa abhi padhoge; baaki apne din aayega.",
    );
    pub const NOT_A_DATE: Words = Words(
        "Not a date: write it as YYYY-MM-DD, for example 2026-11-22.",
        "Yeh tareekh nahi hai: YYYY-MM-DD likho, jaise 2026-11-22.",
    );
    pub const IN_PAST: Words = Words(
        "That day has passed: choose today or a later day.",
        "Woh din beet gaya: aaj ya baad ka din chuno.",
    );
    pub const TOO_FAR: Words = Words(
        "That is more than ten years away: choose a nearer day.",
        "Woh das saal se zyada door hai: paas ka din chuno.",
    );

    /// "Exam 2026-03-20 · in 18 days · target 0.9 · today 5 of 12 planned reviews".
    pub fn header(
        lang: &str,
        exam: &str,
        days: i64,
        target: &str,
        today: usize,
        all: usize,
    ) -> String {
        let hi = lang == HINGLISH;
        let when = match (days, hi) {
            (0, false) => "today".to_string(),
            (0, true) => "aaj".to_string(),
            (1, false) => "tomorrow".to_string(),
            (1, true) => "kal".to_string(),
            (d, false) => format!("in {d} days"),
            (d, true) => format!("{d} din mein"),
        };
        if hi {
            format!("Exam {exam} · {when} · target {target} · aaj {today} / {all} planned reviews")
        } else {
            format!(
                "Exam {exam} · {when} · target {target} · today {today} of {all} planned reviews"
            )
        }
    }

    /// "Expected recall on exam day: 14.2 of 30 cards (from 12.3; the whole plan: 27.9)".
    pub fn expected(lang: &str, now: &str, n: usize, start: &str, whole: &str) -> String {
        if lang == HINGLISH {
            format!(
                "Exam ke din yaad rahenge: {now} / {n} cards (shuru mein {start}; poora plan: {whole})"
            )
        } else {
            format!(
                "Expected recall on exam day: {now} of {n} cards (from {start}; the whole plan: {whole})"
            )
        }
    }

    /// "3 cards stay below 0.9 (the daily cap or the time left)".
    pub fn short(lang: &str, n: usize, target: &str) -> String {
        if lang == HINGLISH {
            format!("{n} cards {target} se neeche rahenge (daily cap ya kam samay)")
        } else {
            format!(
                "{} stay below {target} (the daily cap or the time left)",
                crate::text::plural(n, "card", "cards")
            )
        }
    }
}

/// Words of the reader's link list, search and position line.
pub mod reader {
    use super::Words;

    pub const TAB_TO_CHOOSE: Words = Words("Tab chooses", "Tab se chuno");
    pub const ENTER_OPENS: Words = Words("Enter opens", "Enter se kholo");
    /// Before "12–31/80".
    pub const LINES: Words = Words("lines", "lines");
    /// The search match count ("match 3/9").
    pub const MATCH: Words = Words("match", "match");
}

/// Words of the formula sheet.
pub mod formulas {
    use super::Words;

    /// Before a card's front.
    pub const CARD: Words = Words("Card", "Card");
    /// Before a section's title.
    pub const SECTION: Words = Words("Section", "Section");
    /// After the count ("42 formulas").
    pub const FORMULAS: Words = Words("formulas", "formulas");
    pub const NONE: Words = Words(
        "This deck has no formulas.",
        "Is deck mein koi formula nahi hai.",
    );
}

/// Words of the study screens: counts with what they count, what comes
/// next after a session, typed answers.
pub mod study {
    use super::Words;

    /// A card asked both ways is two review items.
    pub const REVIEW_ITEMS: Words = Words("review items", "review items");
    pub const FROM_CARDS: Words = Words("from", "inse:");
    pub const BY_WEEK: Words = Words("right, week by week", "sahi, hafte dar hafte");
    pub const DUE: Words = Words("Due", "Baaki");
    pub const TODAY: Words = Words("today", "aaj");
    pub const TOMORROW: Words = Words("tomorrow", "kal");
    pub const NEXT_7_DAYS: Words = Words("next 7 days", "agle 7 din");
    pub const SHOW_BENCH: Words = Words(
        "the solvers' work–precision table",
        "solvers ki work–precision table",
    );
    pub const HIDE_BENCH: Words = Words("hide the table", "table chhupao");
    /// What comes next, after a session.
    pub const DUE_TOMORROW: Words = Words("due tomorrow", "kal baaki");
    pub const LATER_TODAY: Words = Words("due later today", "aaj baad mein baaki");
    pub const NEW_LEFT: Words = Words("new cards not yet seen", "naye cards jo abhi dekhe nahi");
    pub const NEW_TOMORROW: Words = Words(
        "new ones come tomorrow (limit per day)",
        "naye kal aayenge (roz ki limit)",
    );
    pub const CRAM_NOW: Words = Words(
        "review everything now (cram)",
        "sab abhi review karo (cram)",
    );
    pub const NEXT_DUE: Words = Words("next review due", "agla review");
    pub const COME_BACK: Words = Words("Come back", "Wapas aana");
    /// Typed answers.
    pub const EXPECTED: Words = Words("expected", "sahi jawab");
    pub const YOU_TYPED: Words = Words("you typed", "tumne likha");
    pub const CHECK: Words = Words("check the answer", "jawab jaancho");
    pub const END: Words = Words("end", "khatam");
    pub const MORE_BELOW: Words = Words("↓ more: j", "↓ aur: j");
    pub const MORE_ABOVE: Words = Words("↑ k", "↑ k");
    pub const MORE_BELOW_TYPING: Words = Words("↓ more: ↓", "↓ aur: ↓");
}

/// A derivation step by step: in the review screen and the reader.
pub mod derive {
    use super::Words;

    /// Above the steps the first time: every step is shown.
    pub const READER_NEXT: Words = Words(
        "Enter: the next step, once you have thought what it is",
        "Enter: agla step, pehle khud socho woh kya hoga",
    );
    pub const WORKED: Words = Words(
        "Worked example: every step with its reason",
        "Worked example: har step uski wajah ke saath",
    );
    /// Before "2 of 5": how many steps the learner supplies.
    pub const FADED: Words = Words(
        "Your turn: steps to supply",
        "Aapki baari: khud bharne wale steps",
    );
    pub const OF: Words = Words("of", "mein se");
    pub const STEP: Words = Words("Step", "Step");
    pub const WHY: Words = Words("why", "kyun");
    pub const HINT: Words = Words("hint", "ishaara");
    /// The faded step's place, before its math is shown.
    pub const HIDDEN: Words = Words("[ your step ]", "[ aapka step ]");
    /// A reveal ask (or a faded step without one).
    pub const THINK: Words = Words(
        "Work this step out, then press Space to see it.",
        "Yeh step khud nikaalo, phir dekhne ke liye Space dabao.",
    );
    pub const CHOOSE: Words = Words(
        "Choose with 1–9, then Enter to check.",
        "1–9 se chuno, phir jaanchne ke liye Enter.",
    );
    pub const TYPE: Words = Words(
        "Type the formula, then Enter to check.",
        "Formula type karo, phir jaanchne ke liye Enter.",
    );
    pub const CHOOSE_FIRST: Words = Words("Choose one first (1–9).", "Pehle ek chuno (1–9).");
    pub const RIGHT: Words = Words("✓ right", "✓ sahi");
    pub const WRONG: Words = Words("✗ not quite", "✗ theek nahi");
    pub const SEEN: Words = Words("seen", "dekha");
    pub const YOU_CHOSE: Words = Words("you chose", "aapne chuna");
    pub const YOU_TYPED: Words = Words("you typed", "aapne likha");
    /// The key row in the review screen.
    pub const NEXT_STEP: Words = Words("next step", "agla step");
    pub const REVEAL: Words = Words("reveal the step", "step dikhao");
    pub const CHECK: Words = Words("check", "jaancho");
    /// After the last step: how the walk went.
    pub const RESULT: Words = Words("steps you supplied right", "aapke sahi bhare steps");
    /// The reader's list of derivations.
    pub const DERIVATIONS: Words = Words("Derivations", "Derivations");
    pub const NONE: Words = Words(
        "This deck has no derivations.",
        "Is deck mein koi derivation nahi hai.",
    );
}

/// The home screen's line when some decks opened and others did not: which
/// deck files were left out and the command that shows why.
pub fn decks_left_out(lang: &str, files: &[String]) -> String {
    let list = files.join(", ");
    if lang == HINGLISH {
        format!(
            "Galtiyon ki wajah se chhode gaye: {list}. Wajah dekhne ke liye `flipcard decks` chalao."
        )
    } else {
        format!("Left out with errors: {list}. Run `flipcard decks` to see why.")
    }
}

/// Words of the system scene panels.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SystemWord {
    Plot,
    Phase,
    Sketch,
    Steps,
    Explicit,
    /// Followed by the time and unit: "stiff from t = 0.8 s".
    StiffFrom,
    SwitchedToRadau,
    Drift,
    ErrorVsReference,
    /// Before the smallest value plotted so far.
    Lowest,
    /// Before the largest value plotted so far.
    Highest,
}

pub fn system_word(w: SystemWord) -> Words {
    use SystemWord as W;
    match w {
        W::Plot => Words("against time", "time ke saath"),
        W::Phase => Words("phase portrait", "phase portrait"),
        W::Sketch => Words("sketch", "sketch"),
        W::Steps => Words("steps", "steps"),
        W::Explicit => Words("not stiff", "stiff nahi"),
        W::StiffFrom => Words("stiff from", "stiff shuru"),
        W::SwitchedToRadau => Words("switched to radau", "radau pe switch kiya"),
        W::Drift => Words("drift", "drift"),
        W::ErrorVsReference => Words("error vs reference", "reference se error"),
        W::Lowest => Words("min", "min"),
        W::Highest => Words("max", "max"),
    }
}

/// The words of a prediction's verdict and of the simulation around it.
/// The words of a formula answer's verdict (a formula card, a formula
/// prompt, and `flipcard grade`, which reads the English).
pub mod formula_words {
    use super::Words;
    use crate::sim::system::equiv::{Slip, Verdict};

    pub const SIGN: Words = Words(
        "the sign is wrong: yours is minus the answer",
        "sign ulta hai: tumhara jawaab ka minus hai",
    );
    /// `{c}`: the constant.
    pub const FACTOR: Words = Words(
        "off by a constant factor: yours is {c} times the answer",
        "ek constant factor ka farq: tumhara jawaab ka {c} guna hai",
    );
    pub const RECIPROCAL: Words = Words(
        "upside down: yours is 1 over the answer",
        "ulta: tumhara 1/(jawaab) hai",
    );
    /// `{v}`: the variables.
    pub const MISSING: Words = Words(
        "it leaves out {v}, which the answer depends on",
        "isme {v} nahi hai, jis par jawaab nirbhar hai",
    );
    /// `{v}`: the names.
    pub const EXTRA: Words = Words(
        "{v}: not a variable of this problem",
        "{v}: is sawaal ka variable nahi",
    );
    pub const UNDEFINED: Words = Words(
        "it is undefined over most of the domain",
        "yeh zyadatar domain par defined nahi hai",
    );
    pub const DIFFERS: Words = Words(
        "it differs from the answer at points of the domain",
        "domain ke points par yeh jawaab se alag hai",
    );
    /// `{why}`: why the key cannot decide.
    pub const UNDECIDED: Words = Words(
        "the deck's answer key cannot decide: {why}",
        "deck ki answer key faisla nahi kar sakti: {why}",
    );
    pub const EXPECTED: Words = Words("the answer", "jawaab");

    /// What the verdict says beyond right or wrong, in `lang`: the slip a
    /// wrong formula makes, why it does not read, or why the key cannot
    /// decide; `None` for a right one. Names typed by the learner are
    /// quoted on one line (escaped).
    pub fn feedback(v: &Verdict, lang: &str) -> Option<String> {
        let quote = |names: &[String]| {
            names
                .iter()
                .map(|n| format!("`{}`", crate::text::safe::one_line(n)))
                .collect::<Vec<_>>()
                .join(", ")
        };
        Some(match v {
            Verdict::Right => return None,
            Verdict::Wrong(None) => DIFFERS.get(lang).to_string(),
            Verdict::Wrong(Some(slip)) => match slip {
                Slip::Sign => SIGN.get(lang).to_string(),
                Slip::Factor(c) => FACTOR
                    .get(lang)
                    .replace("{c}", &crate::text::num::rounded(*c, 6)),
                Slip::Reciprocal => RECIPROCAL.get(lang).to_string(),
                Slip::Missing(vars) => MISSING.get(lang).replace("{v}", &quote(vars)),
                Slip::Extra(names) => EXTRA.get(lang).replace("{v}", &quote(names)),
                Slip::Undefined => UNDEFINED.get(lang).to_string(),
            },
            Verdict::Unreadable(e) => format!(
                "{}: {}",
                super::tr(lang, super::Msg::FormulaUnreadable),
                crate::text::safe::one_line(&e.to_string())
            ),
            Verdict::Undecided(why) => UNDECIDED
                .get(lang)
                .replace("{why}", &crate::text::safe::one_line(why)),
        })
    }
}

pub mod sim_words {
    use super::Words;

    pub const RIGHT: Words = Words("Right", "Sahi");
    pub const WRONG: Words = Words("Wrong", "Galat");
    /// `{d}`: the run's length with its unit.
    pub const IN_THIS_RUN: Words = Words("in this {d} run", "is {d} ke run mein");
    /// `{m}`: the reference run's method (the scene's default).
    pub const VERDICT_OF_REFERENCE: Words = Words(
        "This verdict describes the reference run ({m}), not the run on screen.",
        "Yeh verdict reference run ({m}) ka hai, screen wale run ka nahi.",
    );
    /// `{m}`: the method of the run on screen.
    pub const ON_SCREEN_AGREES: Words = Words(
        "With {m} the run on screen shows the same.",
        "{m} ke saath screen wala run bhi yahi dikhata hai.",
    );
    /// `{m}`: the method of the run on screen; `{said}`: its readings.
    pub const ON_SCREEN_DIFFERS: Words = Words(
        "With {m} the run on screen shows {said}; the reference run shows {ref}: the method, not the physics, made the difference.",
        "{m} ke saath screen wala run {said} dikhata hai; reference run {ref} dikhata hai: fark method ka hai, physics ka nahi.",
    );
    /// `{m}`: the method of the run on screen; `{e}`: why it stopped.
    pub const ON_SCREEN_STOPPED: Words = Words(
        "With {m} the run on screen stopped ({e}); the reference run reached its end.",
        "{m} ke saath screen wala run ruk gaya ({e}); reference run apne end tak chala.",
    );
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
    /// Before what a wrong formula gets wrong (the banner already says it
    /// is wrong).
    pub const WHERE_WRONG: Words = Words("where it goes wrong", "galti kahan hai");
    pub const WORKED: Words = Words("worked out", "hisaab");
    /// Before a known slip the learner's number matches: "your number is
    /// 1/k = 0.03 s: …".
    pub const YOUR_NUMBER_IS: Words = Words("your number is", "tumhara number hai");
    pub const RIGHT_IN_RUN: Words = Words("right in this run", "is run ke hisaab se sahi");
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

    /// A wrong answer that stands for one of the deck's misconceptions:
    /// its name, the steel-man and the fix.
    pub const MISCONCEPTION: Words = Words("Common mistake", "Aam galti");
    pub const WHY_IT_SEEMS_RIGHT: Words = Words("Why it seems right", "Sahi kyun lagta hai");
    pub const FIX: Words = Words("Fix", "Sudhaar");
    /// `{s}`: the title of the section `e` opens.
    pub const READ_MORE: Words = Words("e: read more in {s}", "e: {s} mein aur padho");
    /// `{n}`: lines of the verdict below the screen's last row, counted
    /// (`MORE_LINE`, `MORE_LINES`).
    pub const VERDICT_MORE: Words = Words("↓ {n} (j)", "↓ {n} (j)");
    pub const MORE_LINE: Words = Words("more line", "aur line");
    pub const MORE_LINES: Words = Words("more lines", "aur lines");
}

/// Words of filtered study across decks and of the leech list on the stats
/// screen.
pub mod marks {
    use super::Words;

    /// The filter's field choosing where cards come from.
    pub const FIELD_DECKS: Words = Words("decks", "decks");
    pub const ALL_DECKS: Words = Words("all decks", "saare decks");
    /// The stats screen's panel.
    pub const LEECHES: Words = Words("Leeches", "Leeches");
    pub const NO_LEECHES: Words = Words("no leeches", "koi leech nahi");
    pub const SUSPENDED: Words = Words("suspended", "suspended");
    pub const BURIED: Words = Words("buried", "buried");
    /// After a leech's lapse count: "8 lapses".
    pub const LAPSE: Words = Words("lapse", "baar bhoola");
    pub const LAPSES: Words = Words("lapses", "baar bhoola");
    /// More leeches than room: "+3 more".
    pub const MORE: Words = Words("more", "aur");
}

pub mod sync {
    use super::Words;

    /// The status line after a session synced: "Synced: 3 sent, 2 received".
    pub const SYNCED: Words = Words("Synced", "Sync hua");
    pub const SENT: Words = Words("sent", "bheje");
    pub const RECEIVED: Words = Words("received", "aaye");
}

pub mod browser {
    use super::Words;

    /// In place of the count while the search index is still being built.
    pub const SEARCHING: Words = Words("searching…", "dhoondh rahe…");
    /// The count when the query keeps some items: `{n}` of `{total}`.
    pub const MATCHES: Words = Words("{n} of {total} items", "{total} mein se {n} items");
}

/// Words of the stats screen's added lines: the long forecast, time
/// spent and the answer buttons.
pub mod stats_more {
    use super::Words;

    pub const NEXT_90_DAYS: Words = Words("next 90 days", "agle 90 din");
    pub const TIME: Words = Words("time", "samay");
    pub const TODAY: Words = Words("today", "aaj");
    pub const DAYS_30: Words = Words("30 days", "30 din");
    pub const MATURE_RIGHT: Words = Words("mature right", "mature sahi");
}

/// Words of the card info screen (`i`).
pub mod info {
    use super::Words;

    pub const STATE: Words = Words("state", "state");
    pub const REVIEWS: Words = Words("reviews", "reviews");
    pub const LAPSES: Words = Words("lapses", "kitni baar bhoole");
    pub const DUE: Words = Words("due", "agli baar");
    pub const INTERVAL: Words = Words("interval", "antaraal");
    pub const STABILITY: Words = Words("stability", "stability (tikaav)");
    pub const DIFFICULTY: Words = Words("difficulty", "difficulty (kathinai)");
    pub const RECALL_NOW: Words = Words("recall now", "abhi yaad rehne ka chance");
    pub const NO_REVIEWS: Words = Words(
        "Not answered yet: no history.",
        "Abhi tak jawab nahi diya: koi history nahi.",
    );
    /// Column names of the history.
    pub const DATE: Words = Words("date", "tareekh");
    pub const RATING: Words = Words("rating", "rating");
    pub const IVL: Words = Words("ivl", "antrl");
    pub const TOOK: Words = Words("took", "samay");
    pub const LEGEND: Words = Words(
        "R: recall when answered · S, D: stability, difficulty after",
        "R: jawab ke waqt yaad · S, D: uske baad stability, difficulty",
    );
    pub const CRAM_NOTE: Words = Words(
        "*: crammed, the schedule stayed as it was",
        "*: cram, schedule waisa hi raha",
    );
}

/// Editing a deck from the review screen and the browser (`E`, `A`).
pub mod edit {
    use super::Words;

    /// The screen's name in the header while a deck's check fails.
    pub const TITLE: Words = Words("Deck check", "Deck check");
    /// Before the copy's path: a bundled deck was copied to be edited.
    pub const COPIED: Words = Words(
        "bundled deck copied into your library, editing the copy",
        "bundled deck aapki library mein copy hua, copy edit ho rahi hai",
    );
    pub const SAVED: Words = Words(
        "deck checked and reloaded",
        "deck check hua aur dobara load hua",
    );
    pub const UNCHANGED: Words = Words("the deck file is unchanged", "deck file nahi badli");
    pub const CONTENT_SAVED: Words = Words(
        "explanations checked and reloaded",
        "explanations check hue aur dobara load hue",
    );
    pub const CONTENT_UNCHANGED: Words = Words(
        "the explanation file is unchanged",
        "explanation file nahi badli",
    );
    /// The footer's word for the key that edits while a field is typed
    /// in (`F4`).
    pub const EDIT_KEY: Words = Words("edit", "edit");
    /// The footer's word for the key that adds a card while typing (`F7`).
    pub const ADD_KEY: Words = Words("add card", "card jodo");
    pub const NOTHING_ADDED: Words = Words(
        "the new card was left as the template: nothing added",
        "naya card template jaisa hi chhoda: kuch nahi joda",
    );
    /// Before the new card's id.
    pub const ADDED: Words = Words("card added", "card joda gaya");
    /// After the old id: the card's history did not follow it.
    pub const ID_CHANGED: Words = Words(
        "is no longer in the deck: its history stays with that id (give the card its old id back to keep it)",
        "ab deck mein nahi hai: uski history usi id ke saath rehti hai (history rakhni ho to card ko purani id wapas do)",
    );
    /// Above the first error of a deck that fails its check.
    pub const FAILED: Words = Words(
        "The deck does not pass its check after the edit:",
        "Edit ke baad deck check pass nahi karta:",
    );
    pub const CHOICES: Words = Words(
        "e: edit again at the error · r: revert the file to what it was before the edit",
        "e: error par phir se edit karo · r: file ko edit se pehle jaisi wapas karo",
    );
    pub const REVERTED: Words = Words(
        "the file is back as it was before the edit",
        "file edit se pehle jaisi wapas ho gayi",
    );
    pub const KEPT_BROKEN: Words = Words(
        "the file keeps the error: the deck is left out when flipcard next opens, until it passes `flipcard check`",
        "file mein error reh gaya: agli baar flipcard khulne par deck bahar rahega, jab tak `flipcard check` pass na ho",
    );
    pub const NOT_A_FILE: Words = Words(
        "this deck has no file to edit",
        "is deck ki edit karne layak file nahi hai",
    );
    pub const NOTHING_TO_EDIT: Words =
        Words("no card to edit here", "yahan edit karne ko card nahi");
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn counted_words_agree_in_both_languages() {
        assert_eq!(count(ENGLISH, 1, Noun::Link), "1 link");
        assert_eq!(count(ENGLISH, 17, Noun::Link), "17 links");
        assert_eq!(count(HINGLISH, 1, Noun::New), "1 naya");
        assert_eq!(count(HINGLISH, 20, Noun::New), "20 naye");
        assert_eq!(count(ENGLISH, 1, Noun::New), "1 new");
        assert_eq!(count(ENGLISH, 0, Noun::New), "0 new");
    }
}
