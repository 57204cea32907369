//! What happens when the learner does something: the one place both front
//! ends (the terminal app and the subcommands) call to study.
//!
//! The shape is Anki's `answer_card → transact(…)`: a front end turns a
//! key or an argument into one call here; the call decides the policy
//! (which siblings a rating buries, when a lapse makes a leech, when a bury
//! ends) and hands the store one write that holds it all. The store only
//! stores; the screens and commands only draw or print what comes back.
//!
//! - [`Study::rate`]: an answer, scheduled, with its leech and bury policy,
//!   on disk before it returns.
//! - [`Study::mark`]: suspend, bury (until the next study day) or unsuspend.
//! - [`Study::undo`]: the last change of this session, answer or mark.
//! - [`Study::queue`], [`Study::counts`]: what is due today.
//! - [`Study::commit_attempt`], [`Study::judge_attempt`]: a prediction,
//!   kept as the learner commits to it, and its verdict when the run ends.
//! - [`derive`]: a derivation's faded steps (Renkl's backward fading, from
//!   [`Study::progress`]) and the verdict on a faded step's ask.

pub mod derive;

use crate::sched::States;
use std::borrow::Cow;

use chrono::{DateTime, Utc};

use crate::catalog::card_directions;
use crate::deck::Deck;
use crate::sched::balance::{LOAD_DAYS, Load};
use crate::sched::config::LeechAction;
use crate::sched::{
    CardState, Config, Counts, DayOf, Days, ItemKey, Preview, Queue, Rating, ReviewRecord,
    Scheduler, queue::Part,
};
use crate::store::{
    AfterRating, AttemptVerdict, Commitment, Committed, PromptAttempt, Recorded, StatusAction,
    Store, StoreError, Undone,
};

pub use crate::sched::DayZone;

/// A suspend, bury or unsuspend the learner asks for.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Mark {
    /// Out of every queue until unsuspended.
    Suspend,
    /// Out of today's queue: back when the next study day starts.
    Bury,
    /// Back in the queues.
    Unsuspend,
}

/// An answer the learner gives.
#[derive(Debug, Clone, Copy)]
pub struct Answer<'a> {
    pub key: &'a ItemKey,
    /// The item's state before (`None`: new).
    pub before: Option<&'a CardState>,
    pub rating: Rating,
    /// How long the learner took.
    pub duration_ms: i64,
    /// Cramming: logged, never moves a due date, no policy.
    pub cram: bool,
}

/// What a rating did, for the screen to show.
#[derive(Debug, Clone)]
pub struct Rated {
    /// The answer as stored (the item's state after it is `record.after`).
    pub record: ReviewRecord,
    /// The policy that was applied with it (siblings buried, leech rule).
    pub after: AfterRating,
    /// Its row, and whether it made the item a leech.
    pub recorded: Recorded,
}

/// The learner's study: the config, the scheduler built from it, where the
/// day turns, and the store every change lands in.
pub struct Study {
    pub config: Config,
    pub scheduler: Scheduler,
    pub zone: DayZone,
    pub store: Store,
}

impl Study {
    pub fn new(config: Config, zone: DayZone, store: Store) -> Study {
        let scheduler = Scheduler::new(&config);
        Study {
            config,
            scheduler,
            zone,
            store,
        }
    }

    /// The study day containing `now`: (start, end).
    pub fn study_day(&self, now: DateTime<Utc>) -> (DateTime<Utc>, DateTime<Utc>) {
        self.days().bounds(now)
    }

    /// The learning days of this study (its zone and the hour the day
    /// starts), for the statistics that count per day.
    pub fn days(&self) -> Days {
        Days::new(self.zone, self.config.day_starts_at)
    }

    /// The day's queue of a deck, and the item states it was built from.
    /// Suspended and buried items are left out.
    pub fn queue(&self, deck: &Deck, now: DateTime<Utc>) -> Result<(Queue, States), StoreError> {
        self.queue_tree(&[(deck, None)], now)
    }

    /// The day's queue of a deck and its subdecks: `tree[0]` the deck
    /// studied, each other entry a deck with the position of its parent
    /// (parents first). Each deck's limits are its preset's, and bound
    /// what its subtree offers (see [`crate::sched::queue::Part`]).
    pub fn queue_tree(
        &self,
        tree: &[(&Deck, Option<usize>)],
        now: DateTime<Utc>,
    ) -> Result<(Queue, States), StoreError> {
        let (day_start, _) = self.study_day(now);
        let statuses = self.store.statuses()?;
        let mut states = States::default();
        let mut items = Vec::with_capacity(tree.len());
        let mut done = Vec::with_capacity(tree.len());
        for (deck, _) in tree {
            let of_deck = self.store.states(&deck.id)?;
            if states.is_empty() {
                states = of_deck;
            } else {
                states.extend(of_deck);
            }
            let mut its = crate::sched::deck_item_refs(deck);
            its.retain(|k| {
                statuses
                    .get(k as &dyn crate::sched::AsItem)
                    .is_none_or(|s| s.studyable(now))
            });
            items.push(its);
            done.push(self.store.reviews_today(&deck.id, day_start)?);
        }
        // What a deck's subtree did today counts against its limits.
        for i in (1..tree.len()).rev() {
            if let Some(up) = tree[i].1.filter(|&up| up < i) {
                done[up].new += done[i].new;
                done[up].reviews += done[i].reviews;
            }
        }
        let configs: Vec<Config> = tree
            .iter()
            .map(|(d, _)| self.config.for_deck(&d.id))
            .collect();
        let parts: Vec<Part> = tree
            .iter()
            .enumerate()
            .map(|(i, (deck, parent))| Part {
                deck: &deck.id,
                items: &items[i],
                parent: *parent,
                new_per_day: configs[i].new_per_day,
                reviews_per_day: configs[i].reviews_per_day,
                done: done[i],
            })
            .collect();
        let config = &self.config;
        let queue = match self.zone {
            DayZone::Local => Queue::build_parts(&parts, &states, now, config, &chrono::Local),
            DayZone::Utc => Queue::build_parts(&parts, &states, now, config, &Utc),
        };
        Ok((queue, states))
    }

    /// Today's new, learning and due counts of a deck.
    pub fn counts(&self, deck: &Deck, now: DateTime<Utc>) -> Result<Counts, StoreError> {
        Ok(self.queue(deck, now)?.0.counts())
    }

    /// Today's counts of a deck and its subdecks (see [`Study::queue_tree`]).
    pub fn counts_tree(
        &self,
        tree: &[(&Deck, Option<usize>)],
        now: DateTime<Utc>,
    ) -> Result<Counts, StoreError> {
        Ok(self.queue_tree(tree, now)?.0.counts())
    }

    /// The scheduler of deck `id`: built from its preset when it has one
    /// (retention, steps, maximum interval, parameters), else the study's.
    pub fn scheduler_for(&self, id: &str) -> Cow<'_, Scheduler> {
        match self.config.preset_of(id) {
            None => Cow::Borrowed(&self.scheduler),
            Some(_) => Cow::Owned(Scheduler::new(&self.config.for_deck(id))),
        }
    }

    /// Every deck's scheduler (see [`Study::scheduler_for`]), for what
    /// reads many decks' items at once: lists, statistics, the exam plan.
    pub fn schedulers(&self) -> crate::sched::Schedulers {
        crate::sched::Schedulers::new(&self.config)
    }

    /// The time an answer given at `now` is recorded at: to the
    /// millisecond, and after the item's latest answer (see
    /// [`Store::answer_time`]).
    pub fn answer_time(
        &self,
        key: &ItemKey,
        now: DateTime<Utc>,
    ) -> Result<DateTime<Utc>, StoreError> {
        self.store.answer_time(key, now)
    }

    /// The daily load an answer at `at` is balanced over: the review items
    /// due on each study day from `at`'s, with the easy days' shares.
    /// `None` when fuzz or load balancing is off (the uniform fuzz, or
    /// none, applies).
    pub fn load(&self, at: DateTime<Utc>) -> Result<Option<Load>, StoreError> {
        let c = &self.config;
        if !(c.fuzz && c.load_balance) {
            return Ok(None);
        }
        let days = self.days();
        let (start, _) = days.bounds(at);
        let counts = self.store.due_per_day(start, LOAD_DAYS)?;
        Ok(Some(Load::new(counts, days.day_of(at), &c.easy_days)))
    }

    /// What each answer button would do for `key` at `now`, as
    /// [`Study::rate`] at that instant would schedule it (the same load).
    pub fn preview(
        &self,
        key: &ItemKey,
        before: Option<&CardState>,
        now: DateTime<Utc>,
    ) -> Result<[Preview; 4], StoreError> {
        let load = self.load(now)?;
        Ok(self
            .scheduler_for(&key.deck)
            .preview_with(key, before, now, load.as_ref()))
    }

    /// What follows a rating of `key` in `deck`: leech detection as the
    /// config says, and its siblings buried until the next study day.
    pub(crate) fn policy(&self, deck: &Deck, key: &ItemKey, now: DateTime<Utc>) -> AfterRating {
        let c = &self.config;
        let card = match key.direction {
            // A derivation or a prompt is one item: it has no siblings (a
            // card of the same id is another item).
            crate::sched::Direction::Derive | crate::sched::Direction::Predict => None,
            _ => deck.card(&key.card),
        };
        let bury = match card {
            Some(card) if c.bury_siblings => card_directions(card)
                .into_iter()
                .filter(|d| *d != key.direction)
                .map(|direction| ItemKey {
                    direction,
                    ..key.clone()
                })
                .collect(),
            _ => Vec::new(),
        };
        AfterRating {
            leech_threshold: c.leech_threshold,
            leech_suspend: c.leech_action == LeechAction::Suspend,
            bury,
            bury_until: self.study_day(now).1,
        }
    }

    /// Records `answer`, given at `now`: at [`Study::answer_time`],
    /// scheduled, with the policy of a review applied in the same write,
    /// and on disk when this returns. `deck` is the item's deck when it is
    /// loaded (without it, or when cramming, no policy applies).
    pub fn rate(
        &mut self,
        deck: Option<&Deck>,
        answer: Answer<'_>,
        now: DateTime<Utc>,
    ) -> Result<Rated, StoreError> {
        let Answer {
            key,
            before,
            rating,
            duration_ms,
            cram,
        } = answer;
        let at = self.answer_time(key, now)?;
        let s = self.scheduler_for(&key.deck);
        let record = if cram {
            s.cram(key, before, rating, at, duration_ms)
        } else {
            let load = self.load(at)?;
            s.review_with(key, before, rating, at, duration_ms, load.as_ref())
        };
        let after = match deck {
            Some(deck) if !cram => self.policy(deck, key, at),
            _ => AfterRating {
                leech_threshold: 0,
                leech_suspend: false,
                bury: Vec::new(),
                bury_until: at,
            },
        };
        let recorded = self.store.record_study(&record, &after)?;
        Ok(Rated {
            record,
            after,
            recorded,
        })
    }

    /// Suspends, buries (until the next study day starts) or unsuspends
    /// every item of `keys`, in one write.
    pub fn mark(
        &mut self,
        keys: &[ItemKey],
        mark: Mark,
        now: DateTime<Utc>,
    ) -> Result<(), StoreError> {
        let (action, until) = match mark {
            Mark::Suspend => (StatusAction::Suspend, None),
            Mark::Bury => (StatusAction::Bury, Some(self.study_day(now).1)),
            Mark::Unsuspend => (StatusAction::Unsuspend, None),
        };
        self.store.set_status(keys, action, now, until)?;
        Ok(())
    }

    /// Undoes the last change of this session (an answer, or a mark with
    /// what it brought about); `None` when there is none.
    pub fn undo(&mut self) -> Result<Option<Undone>, StoreError> {
        self.store.undo_last_change()
    }

    /// Keeps a prediction as the learner commits to it, before the run
    /// plays: on disk when this returns, numbered after the learner's
    /// earlier attempts at the prompt (a later one is a retry). A front end
    /// that gets an error says so and does not start the run.
    pub fn commit_attempt(&mut self, commitment: &Commitment) -> Result<Committed, StoreError> {
        self.store.commit_attempt(commitment)
    }

    /// Writes the verdict of a committed attempt when its run ends, once.
    pub fn judge_attempt(
        &mut self,
        committed: Committed,
        verdict: &AttemptVerdict,
    ) -> Result<(), StoreError> {
        self.store.judge_attempt(committed.id, verdict)
    }

    /// Writes the verdict of an attempt at a prompt and, when the prompt
    /// (as a review item, direction `predict`) is due as the day's queue
    /// would offer it, its rating from the verdict in the same write:
    /// wrong is Again, right is Good ([`Study::lower_to_hard`] then lowers
    /// it). An attempt at a prompt not yet due is practice: judged, not
    /// rated, its schedule left as it is. `None` when not rated.
    pub fn judge_and_rate(
        &mut self,
        deck: &Deck,
        committed: Committed,
        verdict: &AttemptVerdict,
        prompt: &str,
        duration_ms: i64,
    ) -> Result<Option<Rated>, StoreError> {
        let key = ItemKey {
            deck: deck.id.clone(),
            card: prompt.to_string(),
            direction: crate::sched::Direction::Predict,
        };
        let now = verdict.judged_at;
        let before = self.store.state(&key)?;
        // Due as the day's queue offers it: new; a review due by the end of
        // the study day; a learning step within the learn-ahead limit.
        let due = before.as_ref().is_none_or(|s| match s.state {
            crate::sched::State::New => true,
            crate::sched::State::Review => s.due < self.study_day(now).1,
            crate::sched::State::Learning | crate::sched::State::Relearning => {
                s.due <= now + crate::sched::queue::LEARN_AHEAD
            }
        });
        if !due {
            self.store.judge_attempt(committed.id, verdict)?;
            return Ok(None);
        }
        let rating = if verdict.correct {
            Rating::Good
        } else {
            Rating::Again
        };
        let at = self.answer_time(&key, now)?;
        let load = self.load(at)?;
        let record = self.scheduler_for(&key.deck).review_with(
            &key,
            before.as_ref(),
            rating,
            at,
            duration_ms,
            load.as_ref(),
        );
        let after = self.policy(deck, &key, at);
        let recorded =
            self.store
                .record_study_judged(&record, &after, Some((committed.id, verdict)))?;
        Ok(Some(Rated {
            record,
            after,
            recorded,
        }))
    }

    /// Lowers a prompt's rating of Good, given by its verdict just now, to
    /// Hard, as the learner asks: the Good is undone and Hard recorded
    /// with the same time taken. `None` when the last change of this
    /// session is not that rating.
    pub fn lower_to_hard(
        &mut self,
        deck: &Deck,
        rated: &Rated,
        now: DateTime<Utc>,
    ) -> Result<Option<Rated>, StoreError> {
        let r = &rated.record;
        if r.rating != Rating::Good {
            return Ok(None);
        }
        match self.undo()? {
            Some(crate::store::Undone::Review(u)) if u.record.key == r.key => {}
            Some(_) | None => return Ok(None),
        }
        let before = self.store.state(&r.key)?;
        let answer = Answer {
            key: &r.key,
            before: before.as_ref(),
            rating: Rating::Hard,
            duration_ms: r.duration_ms,
            cram: false,
        };
        self.rate(Some(deck), answer, now).map(Some)
    }

    /// Keeps a judged attempt whole: commitment and verdict at once (for a
    /// front end that judges as it commits).
    pub fn record_attempt(&mut self, attempt: &PromptAttempt) -> Result<i64, StoreError> {
        self.store.record_attempt(attempt)
    }
}

#[cfg(test)]
mod tests;
