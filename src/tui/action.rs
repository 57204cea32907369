//! Everything the learner (or the clock) can do to the app. Keys map to
//! these (`keymap`), and `update::apply` carries them out without a terminal.

use std::time::Duration;

use crate::sched::Rating;

#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Action {
    /// Leave the app (Ctrl-C anywhere, `q` on the home screen).
    Quit,
    /// Close the current screen (or leave a mode) and return to the previous one.
    Back,
    ToggleHelp,
    CloseHelp,
    /// Scroll a help overlay taller than the screen.
    HelpDown,
    HelpUp,
    /// English ⇄ Hinglish, everywhere, remembered between runs.
    ToggleLanguage,

    Up,
    Down,
    PageUp,
    PageDown,
    Top,
    Bottom,
    /// Enter on a list: open what is selected.
    Open,

    // Home
    OpenReview,
    OpenCram,
    OpenReader,
    OpenPrompts,
    OpenStats,
    /// Plan for an exam day and study today's share.
    OpenExam,

    // Review
    Reveal,
    Rate(Rating),
    Undo,
    /// Open the explanation the card (or prompt) links to.
    Explain,
    /// Card info: the item's history and memory (`i`).
    CardInfo,
    /// Open the prompt the card links to.
    OpenCardPrompt,

    // Editing the deck file (review screen and card browser)
    /// Open the item in the learner's editor (`E`; on the check screen, `e`).
    EditItem,
    /// Append a new card of the current card's kind and open it (`A`).
    AddCard,
    /// Put the deck file back as it was before the edit (`r`).
    Revert,

    // Suspend and bury (review screen and card browser)
    Suspend,
    Unsuspend,
    Bury,

    // Card browser and study filter
    OpenBrowser,
    OpenFilter,
    /// Sort by the next column (or reverse the order).
    NextSort,
    ReverseSort,
    /// Move to the next field of a form.
    NextField,
    PrevField,

    // Reader
    PrevSection,
    NextSection,
    StartSearch,
    NextMatch,
    PrevMatch,
    NextLink,
    PrevLink,
    FollowLink,
    /// The deck's formula sheet.
    OpenFormulas,

    // Text fields (typed answers, numeric predictions, search)
    Input(char),
    Backspace,
    Submit,

    // Predict, then check
    Choose(usize),
    TogglePause,
    Faster,
    Slower,
    Restart,
    NextMethod,
    SmallerStep,
    LargerStep,
    /// After a verdict: the deck's next prompt.
    NextPrompt,
    /// Explore the scene with its knobs (the prompt list, after a verdict).
    Explore,
    /// Turn the selected knob one step up or down.
    KnobUp,
    KnobDown,
    /// Select the scene's next knob.
    NextKnob,
    /// Show or hide the solver's diagnostics line.
    ToggleDiagnostics,
    /// The question whole first (the verdict and panels give way), or back.
    ToggleQuestion,

    /// Stats: show or hide the solvers' work–precision table.
    ToggleBench,

    /// Wall-clock time passed while a simulation plays.
    Tick(Duration),
    Resize(u16, u16),
}
