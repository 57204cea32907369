//! Suspend and bury from the review screen, what follows a rating (leech,
//! siblings buried), and taking those back with undo.

use crate::sched::ItemKey;
use crate::store::{AfterRating, StatusAction, StatusEvent};
use crate::study::Mark;
use crate::tui::action::Action;
use crate::tui::app::App;
use crate::tui::i18n::Msg;

use super::{ReviewState, Source};

fn set_aside(state: &mut ReviewState, key: &ItemKey) -> bool {
    match &mut state.source {
        Source::Daily(q) | Source::Filtered(q) | Source::Plan(q) if q.contains(key) => {
            q.set_aside(key);
            true
        }
        Source::Cram(c) if c.contains(key) => {
            c.set_aside(key);
            true
        }
        _ => false,
    }
}

/// Puts items back into the queue, each where its state puts it.
pub(super) fn bring_back(app: &App, state: &mut ReviewState, keys: &[ItemKey]) {
    for key in keys {
        match &mut state.source {
            Source::Daily(q) | Source::Filtered(q) | Source::Plan(q) => {
                let now_state = app.services.study.store.state(key).ok().flatten();
                q.restore(key, now_state.as_ref());
            }
            Source::Cram(c) => c.restore(key),
        }
    }
}

/// `s` and `b` on a card: every item of it shown leaves the session
/// (suspended until unsuspended, buried until the next study day).
pub(super) fn mark(app: &mut App, state: &mut ReviewState, action: Action) {
    let Some((key, _)) = state.current.clone() else {
        return;
    };
    let now = app.services.now();
    let (mark, msg) = match action {
        Action::Suspend => (Mark::Suspend, Msg::CardSuspended),
        _ => (Mark::Bury, Msg::CardBuried),
    };
    if let Err(e) = app
        .services
        .study
        .mark(std::slice::from_ref(&key), mark, now)
    {
        app.error(e.to_string());
        return;
    }
    set_aside(state, &key);
    state.marks.push(vec![key]);
    state.next_card(app);
    app.info(app.tr(msg));
}

/// Undo of the last suspend or bury of this screen.
pub(super) fn undo(app: &mut App, state: &mut ReviewState) {
    match app.services.study.undo() {
        Ok(Some(crate::store::Undone::Status(events))) => undone(app, state, &events),
        Ok(Some(crate::store::Undone::Review(_))) => {
            // Only possible when a rating of another screen is newer, which
            // the session start rules out; the card states are re-read.
            app.info(app.tr(Msg::Undone));
        }
        Ok(None) => app.info(app.tr(Msg::NothingToUndo)),
        Err(e) => app.error(e.to_string()),
    }
}

/// A status change was taken back: its items return, the first one shown.
pub(super) fn undone(app: &mut App, state: &mut ReviewState, events: &[StatusEvent]) {
    state.marks.pop();
    let keys: Vec<ItemKey> = events.iter().map(|e| e.key.clone()).collect();
    bring_back(app, state, &keys);
    if let Some(first) = keys.first() {
        state.show(app, Some(first.clone()));
    }
    app.info(app.tr(undone_msg(events)));
}

/// What an undone status change was, said so ("bury undone"), not as a
/// rating.
pub(crate) fn undone_msg(events: &[StatusEvent]) -> Msg {
    match events.first().map(|e| e.action) {
        Some(StatusAction::Suspend) => Msg::SuspendUndone,
        Some(StatusAction::Bury) => Msg::BuryUndone,
        Some(StatusAction::Unsuspend) => Msg::UnsuspendUndone,
        Some(StatusAction::Leech) | None => Msg::Undone,
    }
}

/// A card suspended or buried elsewhere (the browser, `flipcard cards`, a
/// second window) since it was shown: its rating is not written, and the
/// learner is told. True when that is so.
pub(super) fn changed_meanwhile(app: &mut App, state: &mut ReviewState, key: &ItemKey) -> bool {
    let now = app.services.now();
    match app.services.study.store.status(key) {
        Ok(s) if s.studyable(now) => false,
        Ok(_) => {
            set_aside(state, key);
            state.next_card(app);
            app.info(app.tr(Msg::SuspendedMeanwhile));
            true
        }
        Err(e) => {
            app.error(e.to_string());
            true
        }
    }
}

/// After a rating is written: siblings buried leave the queue, and a new
/// leech is announced (and leaves the queue when it was suspended).
pub(super) fn after_rating(
    app: &mut App,
    state: &mut ReviewState,
    key: &ItemKey,
    after: &AfterRating,
    leech: bool,
) {
    let mut aside = Vec::new();
    for sibling in after.bury.iter().filter(|s| *s != key) {
        if set_aside(state, sibling) {
            aside.push(sibling.clone());
        }
    }
    // The first sibling set aside in a session says why the counts moved
    // by two (the new count jumped with no word before).
    let said_bury = !aside.is_empty() && !state.bury_said;
    state.bury_said |= said_bury;
    state.aside.push(aside);
    if said_bury && !leech {
        app.info(app.tr(Msg::SiblingWaits));
    }
    if leech {
        if after.leech_suspend {
            set_aside(state, key);
            app.info(app.tr(Msg::LeechSuspended));
        } else {
            app.info(app.tr(Msg::LeechMarked));
        }
    }
}
