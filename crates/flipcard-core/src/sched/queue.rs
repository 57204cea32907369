//! The day's review queue and the cram queue.
//!
//! A study day runs from `day_starts_at` local time to the same time the
//! next day. The queue offers, in this order: learning and relearning items
//! whose due time has come (earliest first), due reviews (most overdue
//! first), new items in deck order; when none of those is left, a learning
//! item due within the learn-ahead limit (20 minutes, as Anki) is offered
//! early. New items and reviews are limited per day.

use std::collections::{HashMap, VecDeque};
use std::fmt;

use chrono::{DateTime, NaiveTime, TimeDelta, TimeZone, Utc};

use super::config::Config;
use super::types::{
    AsItem, CardState, Direction, ItemKey, ItemRef, ReviewKind, ReviewRecord, State, States,
};
use crate::deck::model::{CardKind, Deck};

/// How far ahead a learning item may be shown when nothing else is left.
pub(crate) const LEARN_AHEAD: TimeDelta = TimeDelta::minutes(20);

/// The review items of a deck in deck order: one per card, two for a
/// reversed card (front → back, then back → front), one per deletion
/// number of a cloze card; then one per predict-then-check prompt
/// (direction `predict`), then one per derivation (direction `derive`).
pub fn deck_items(deck: &Deck) -> Vec<ItemKey> {
    cram_items(deck, None)
}

/// [`deck_items`], borrowed from the deck: what counting and queueing read
/// (the queue copies only the items it takes).
pub fn deck_item_refs(deck: &Deck) -> Vec<ItemRef<'_>> {
    cram_item_refs(deck, None)
}

/// The items of a deck, or only of its cards (and derivations) carrying
/// `tag`, in deck order: the cards', then the derivations'.
pub fn cram_items(deck: &Deck, tag: Option<&str>) -> Vec<ItemKey> {
    cram_item_refs(deck, tag)
        .iter()
        .map(ItemRef::to_key)
        .collect()
}

/// [`cram_items`], borrowed from the deck.
pub fn cram_item_refs<'a>(deck: &'a Deck, tag: Option<&str>) -> Vec<ItemRef<'a>> {
    let mut items = Vec::with_capacity(deck.cards.len() + deck.derivations.len());
    let item = |card, direction| ItemRef {
        deck: &deck.id,
        card,
        direction,
    };
    for card in &deck.cards {
        if tag.is_some_and(|t| !card.tags.iter().any(|c| c == t)) {
            continue;
        }
        let key = |direction| item(&card.id, direction);
        match card.kind {
            CardKind::Cloze => items.extend(
                card.cloze_numbers()
                    .into_iter()
                    .map(|n| key(Direction::Cloze(n))),
            ),
            CardKind::Reversed => {
                items.push(key(Direction::Forward));
                items.push(key(Direction::Backward));
            }
            CardKind::Basic | CardKind::Typed | CardKind::Formula => {
                items.push(key(Direction::Forward))
            }
        }
    }
    for prompt in &deck.prompts {
        if tag.is_some_and(|t| !prompt.tags.iter().any(|c| c == t)) {
            continue;
        }
        items.push(item(&prompt.id, Direction::Predict));
    }
    for d in &deck.derivations {
        if tag.is_some_and(|t| !d.tags.iter().any(|c| c == t)) {
            continue;
        }
        items.push(item(&d.id, Direction::Derive));
    }
    items
}

/// The study day containing `now`: from the last `starts_at` (local time in
/// `tz`) at or before `now` to the next one.
pub fn study_day<Tz: TimeZone>(
    now: DateTime<Utc>,
    starts_at: NaiveTime,
    tz: &Tz,
) -> (DateTime<Utc>, DateTime<Utc>) {
    super::day::DayGrid::new(tz.clone(), starts_at).bounds(now)
}

/// New items and reviews already answered in the current study day.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct DoneToday {
    pub new: u32,
    pub reviews: u32,
}

/// Where a queued item comes from.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum QueueKind {
    Learning,
    Review,
    New,
}

/// What is left today, for the progress line.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Counts {
    /// Reviews due today (within the daily limit).
    pub due: usize,
    /// Learning and relearning items due before the day ends.
    pub learning: usize,
    /// New items still to introduce today.
    pub new: usize,
}

impl Counts {
    pub fn total(&self) -> usize {
        self.due + self.learning + self.new
    }
}

impl fmt::Display for Counts {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "{} due · {} learning · {} new",
            self.due, self.learning, self.new
        )
    }
}

/// One deck of a queue over a deck and its subdecks (Anki's v3 limits:
/// a deck's limits bound what its whole subtree offers, and every deck
/// from an item's own up to the one studied bounds it).
#[derive(Debug, Clone, Copy)]
pub struct Part<'a> {
    /// The deck's id and its items in deck order.
    pub deck: &'a str,
    pub items: &'a [ItemRef<'a>],
    /// The part of its parent deck (parts come parents first); `None` for
    /// the deck studied.
    pub parent: Option<usize>,
    pub new_per_day: u32,
    pub reviews_per_day: u32,
    /// Answered today in this deck and every deck below it.
    pub done: DoneToday,
}

/// New items kept beyond what the limits offer, per deck: an item set
/// aside (suspended, buried) leaves its place to the next one.
const NEW_SPARE: usize = 64;

/// The day's queue. Build it once, take [`Queue::next`], report each answer
/// with [`Queue::answered`] (or an undo with [`Queue::restore`]).
#[derive(Debug, Clone)]
pub struct Queue {
    day: (DateTime<Utc>, DateTime<Utc>),
    /// Sorted by due time; items answered later go after equal due times.
    learning: Vec<(DateTime<Utc>, ItemKey)>,
    reviews: VecDeque<ItemKey>,
    /// New items in the order they are offered; those the limits leave
    /// out today wait behind (see [`Queue::offered_new`]).
    new: VecDeque<ItemKey>,
    /// New items each part may still introduce today, and its parent.
    new_left: Vec<usize>,
    parents: Vec<Option<usize>>,
    /// Which part each deck is.
    part_of: HashMap<String, usize>,
}

impl Queue {
    /// The queue for the study day containing `now`, with the day boundary
    /// in the machine's local time zone.
    pub fn build_local(
        items: &[ItemKey],
        states: &States,
        done: DoneToday,
        now: DateTime<Utc>,
        config: &Config,
    ) -> Queue {
        Queue::build(items, states, done, now, config, &chrono::Local)
    }

    /// The queue for the study day containing `now`, the day starting at
    /// `config.day_starts_at` in `tz`. `items` are in deck order; an item
    /// without a state (or in state `New`) is new.
    pub fn build<Tz: TimeZone>(
        items: &[ItemKey],
        states: &States,
        done: DoneToday,
        now: DateTime<Utc>,
        config: &Config,
        tz: &Tz,
    ) -> Queue {
        let deck = items.first().map_or("", |k| k.deck.as_str());
        let items: Vec<ItemRef> = items.iter().map(ItemKey::as_ref).collect();
        let part = Part {
            deck,
            items: &items,
            parent: None,
            new_per_day: config.new_per_day,
            reviews_per_day: config.reviews_per_day,
            done,
        };
        Queue::build_parts(&[part], states, now, config, tz)
    }

    /// The queue of a deck and its subdecks, `parts[0]` the deck studied
    /// (see [`Part`]); the day and the sibling rule are `config`'s.
    ///
    /// New items are offered in deck order (a deck's own, then each
    /// subdeck's), reviews most overdue first; an item counts against its
    /// own deck's limits and each parent's. With `bury_siblings`, a new
    /// item whose card already has an item in today's queue is left for
    /// another day, as Anki leaves a buried sibling: it would be set aside
    /// when its sibling is answered, and must not take a place of the new
    /// limit meanwhile.
    pub fn build_parts<Tz: TimeZone>(
        parts: &[Part<'_>],
        states: &States,
        now: DateTime<Utc>,
        config: &Config,
        tz: &Tz,
    ) -> Queue {
        let day = study_day(now, config.day_starts_at, tz);
        let end = day.1;
        let parents: Vec<Option<usize>> = parts
            .iter()
            .enumerate()
            .map(|(i, p)| p.parent.filter(|&up| up < i))
            .collect();
        let new_left: Vec<usize> = parts
            .iter()
            .map(|p| p.new_per_day.saturating_sub(p.done.new) as usize)
            .collect();
        let mut reviews_left: Vec<usize> = parts
            .iter()
            .map(|p| p.reviews_per_day.saturating_sub(p.done.reviews) as usize)
            .collect();

        let mut learning = Vec::new();
        // (due, part, deck position) of every due review.
        let mut due_reviews: Vec<(DateTime<Utc>, usize, usize)> = Vec::new();
        // (part, deck position) of every new item.
        let mut new_items: Vec<(usize, usize)> = Vec::new();
        for (p, part) in parts.iter().enumerate() {
            for (i, key) in part.items.iter().enumerate() {
                match states.get(key as &dyn AsItem) {
                    None => new_items.push((p, i)),
                    Some(card) => match card.state {
                        State::New => new_items.push((p, i)),
                        State::Learning | State::Relearning => {
                            if card.due < end {
                                learning.push((card.due, p, i));
                            }
                        }
                        State::Review => {
                            if card.due < end {
                                due_reviews.push((card.due, p, i));
                            }
                        }
                    },
                }
            }
        }
        // The most overdue first, each within its decks' review limits.
        due_reviews.sort_unstable();
        let mut reviews = VecDeque::new();
        for (_, p, i) in due_reviews {
            if take(&mut reviews_left, &parents, p) {
                reviews.push_back(parts[p].items[i].to_key());
            }
        }
        learning.sort_unstable();
        let learning: Vec<(DateTime<Utc>, ItemKey)> = learning
            .into_iter()
            .map(|(due, p, i)| (due, parts[p].items[i].to_key()))
            .collect();

        // Cards already in today's queue: their new siblings wait.
        let mut in_queue: std::collections::HashSet<(&str, &str)> =
            std::collections::HashSet::new();
        if config.bury_siblings {
            for key in learning.iter().map(|(_, k)| k).chain(&reviews) {
                if let Some(card) = sibling_card(key.as_ref()) {
                    in_queue.insert(card);
                }
            }
        }
        // At most what each deck (and those above it) may introduce, and
        // a few spare for items set aside.
        let mut room: Vec<usize> = (0..parts.len())
            .map(|p| chain(&parents, p).map(|a| new_left[a]).min().unwrap_or(0) + NEW_SPARE)
            .collect();
        let mut new = VecDeque::new();
        for (p, i) in new_items {
            if room[p] == 0 {
                continue;
            }
            let key = &parts[p].items[i];
            if config.bury_siblings
                && let Some(card) = sibling_card(*key)
                && !in_queue.insert(card)
            {
                continue;
            }
            room[p] -= 1;
            new.push_back(key.to_key());
        }
        Queue {
            day,
            learning,
            reviews,
            new,
            new_left,
            parents,
            part_of: parts
                .iter()
                .enumerate()
                .map(|(i, p)| (p.deck.to_string(), i))
                .collect(),
        }
    }

    /// A queue over a fixed list (a filtered session): each item once, in
    /// the list's order, with no daily limits. Answers are taken as in the
    /// day's queue ([`Queue::answered`]): an item left (re)learning comes
    /// back at its step time, before the rest of the list, if that is within
    /// the study day `day`.
    pub fn listed(items: Vec<ItemKey>, day: (DateTime<Utc>, DateTime<Utc>)) -> Queue {
        Queue {
            day,
            learning: Vec::new(),
            reviews: items.into(),
            new: VecDeque::new(),
            new_left: Vec::new(),
            parents: Vec::new(),
            part_of: HashMap::new(),
        }
    }

    /// The study day this queue covers, as UTC instants.
    pub fn day(&self) -> (DateTime<Utc>, DateTime<Utc>) {
        self.day
    }

    /// The item to show at `now`, or `None` when nothing is left to show
    /// now (see [`Queue::next_learning_due`] for when to come back).
    pub fn next(&self, now: DateTime<Utc>) -> Option<(&ItemKey, QueueKind)> {
        let first_learning = self.learning.first();
        if let Some((due, key)) = first_learning
            && *due <= now
        {
            return Some((key, QueueKind::Learning));
        }
        if let Some(key) = self.reviews.front() {
            return Some((key, QueueKind::Review));
        }
        if let Some(&i) = self.offered_new().first() {
            return Some((&self.new[i], QueueKind::New));
        }
        match first_learning {
            Some((due, key)) if *due <= now + LEARN_AHEAD => Some((key, QueueKind::Learning)),
            _ => None,
        }
    }

    /// When the next learning item falls due, if any is left today.
    pub fn next_learning_due(&self) -> Option<DateTime<Utc>> {
        self.learning.first().map(|(due, _)| *due)
    }

    /// Takes an answer into account: the item leaves the queue, and comes
    /// back later today if it is (re)learning and due before the day ends.
    /// Cram answers leave the day's queue untouched.
    pub fn answered(&mut self, record: &ReviewRecord) {
        if record.kind == ReviewKind::Cram {
            return;
        }
        self.take_out(&record.key);
        let after = &record.after;
        if matches!(after.state, State::Learning | State::Relearning) && after.due < self.day.1 {
            self.insert_learning(after.due, record.key.clone());
        }
    }

    /// Puts an item back as it was before an undone answer: `before` is its
    /// state before that answer (`None` for a new card).
    pub fn restore(&mut self, key: &ItemKey, before: Option<&CardState>) {
        self.remove(key);
        match before {
            None => self.unintroduce(key),
            Some(card) => match card.state {
                State::New => self.unintroduce(key),
                State::Review => self.reviews.push_front(key.clone()),
                State::Learning | State::Relearning => self.insert_learning(card.due, key.clone()),
            },
        }
    }

    /// Takes an item out of today's queue (suspended, buried) without an
    /// answer.
    pub fn set_aside(&mut self, key: &ItemKey) {
        self.remove(key);
    }

    pub fn contains(&self, key: &ItemKey) -> bool {
        self.learning.iter().any(|(_, k)| k == key)
            || self.reviews.contains(key)
            || self.new.contains(key)
    }

    pub fn counts(&self) -> Counts {
        Counts {
            due: self.reviews.len(),
            learning: self.learning.len(),
            new: self.offered_new().len(),
        }
    }

    /// The new items offered today, by position in `new`: in order, each
    /// within what its deck and every deck above it may still introduce
    /// (an item of no part, in a listed queue, always).
    fn offered_new(&self) -> Vec<usize> {
        let mut left = self.new_left.clone();
        let mut out = Vec::new();
        for (i, key) in self.new.iter().enumerate() {
            match self.part_of.get(&key.deck) {
                Some(&p) => {
                    if take(&mut left, &self.parents, p) {
                        out.push(i);
                    }
                }
                None => out.push(i),
            }
            // Every deck studied has introduced its day's share.
            let mut roots = self
                .parents
                .iter()
                .zip(&left)
                .filter(|(up, _)| up.is_none());
            if !self.parents.is_empty() && roots.all(|(_, l)| *l == 0) {
                break;
            }
        }
        out
    }

    /// Takes an answered item out: a new one uses a place of its decks'
    /// limits.
    fn take_out(&mut self, key: &ItemKey) {
        if self.remove(key)
            && let Some(&p) = self.part_of.get(&key.deck)
        {
            for a in chain(&self.parents, p).collect::<Vec<_>>() {
                self.new_left[a] = self.new_left[a].saturating_sub(1);
            }
        }
    }

    /// A new item put back by an undo: first in line, and its place of
    /// the limits given back.
    fn unintroduce(&mut self, key: &ItemKey) {
        if let Some(&p) = self.part_of.get(&key.deck) {
            for a in chain(&self.parents, p).collect::<Vec<_>>() {
                self.new_left[a] += 1;
            }
        }
        self.new.push_front(key.clone());
    }

    /// Nothing left today, not even learning items due later.
    pub fn is_finished(&self) -> bool {
        self.counts().total() == 0
    }

    /// Takes `key` out of the queue; whether it was a new item.
    fn remove(&mut self, key: &ItemKey) -> bool {
        self.learning.retain(|(_, k)| k != key);
        self.reviews.retain(|k| k != key);
        let before = self.new.len();
        self.new.retain(|k| k != key);
        self.new.len() < before
    }

    fn insert_learning(&mut self, due: DateTime<Utc>, key: ItemKey) {
        let at = self.learning.partition_point(|(d, _)| *d <= due);
        self.learning.insert(at, (due, key));
    }
}

/// Part `p` and every part above it.
fn chain(parents: &[Option<usize>], p: usize) -> impl Iterator<Item = usize> + '_ {
    let mut at = Some(p);
    // Parents come before their children, so each step goes up.
    std::iter::from_fn(move || {
        let here = at?;
        at = parents.get(here).copied().flatten().filter(|&up| up < here);
        Some(here)
    })
}

/// Takes one place of the limit `left` of part `p` and every part above
/// it, when each has one; whether it did.
fn take(left: &mut [usize], parents: &[Option<usize>], p: usize) -> bool {
    if p >= left.len() || chain(parents, p).any(|a| left[a] == 0) {
        return false;
    }
    for a in chain(parents, p).collect::<Vec<_>>() {
        left[a] -= 1;
    }
    true
}

/// The card an item shares with its siblings (the other direction, the
/// other cloze numbers); a prompt or a derivation has none.
fn sibling_card(key: ItemRef<'_>) -> Option<(&str, &str)> {
    match key.direction {
        Direction::Predict | Direction::Derive => None,
        _ => Some((key.deck, key.card)),
    }
}

/// Cram: every item of a deck (or tag) once, regardless of due dates; an
/// item answered Again goes to the back and comes round again.
#[derive(Debug, Clone, Default)]
pub struct CramQueue {
    items: VecDeque<ItemKey>,
}

impl CramQueue {
    pub fn new(items: Vec<ItemKey>) -> CramQueue {
        CramQueue {
            items: items.into(),
        }
    }

    pub fn next(&self) -> Option<&ItemKey> {
        self.items.front()
    }

    pub fn answered(&mut self, record: &ReviewRecord) {
        let Some(pos) = self.items.iter().position(|k| *k == record.key) else {
            return;
        };
        if let Some(key) = self.items.remove(pos)
            && record.rating == super::types::Rating::Again
        {
            self.items.push_back(key);
        }
    }

    /// Puts an item back at the front after an undo.
    pub fn restore(&mut self, key: &ItemKey) {
        if let Some(pos) = self.items.iter().position(|k| k == key) {
            self.items.remove(pos);
        }
        self.items.push_front(key.clone());
    }

    /// Takes an item out without an answer (suspended, buried).
    pub fn set_aside(&mut self, key: &ItemKey) {
        self.items.retain(|k| k != key);
    }

    pub fn contains(&self, key: &ItemKey) -> bool {
        self.items.contains(key)
    }

    pub fn remaining(&self) -> usize {
        self.items.len()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sched::scheduler::Scheduler;
    use crate::sched::types::Rating;
    use chrono::{FixedOffset, LocalResult, NaiveDateTime};

    fn key(card: &str) -> ItemKey {
        ItemKey {
            deck: "d".into(),
            card: card.into(),
            direction: Direction::Forward,
        }
    }

    fn ist() -> FixedOffset {
        FixedOffset::east_opt(5 * 3600 + 1800).unwrap()
    }

    /// An instant given as local (IST) wall-clock time.
    fn at(day: u32, h: u32, m: u32) -> DateTime<Utc> {
        ist()
            .with_ymd_and_hms(2026, 3, day, h, m, 0)
            .unwrap()
            .with_timezone(&Utc)
    }

    fn state(s: State, due: DateTime<Utc>) -> CardState {
        CardState {
            state: s,
            step: matches!(s, State::Learning | State::Relearning).then_some(0),
            stability: Some(5.0),
            difficulty: Some(5.0),
            due,
            last_review: Some(due - TimeDelta::days(3)),
        }
    }

    fn cfg() -> Config {
        Config {
            fuzz: false,
            ..Config::default()
        }
    }

    fn order(q: &Queue, now: DateTime<Utc>) -> Vec<(String, QueueKind)> {
        let mut q = q.clone();
        let mut out = Vec::new();
        while let Some((k, kind)) = q.next(now) {
            out.push((k.card.clone(), kind));
            let k = k.clone();
            q.take_out(&k);
        }
        out
    }

    #[test]
    fn day_starts_at_local_time() {
        let four = NaiveTime::from_hms_opt(4, 0, 0).unwrap();
        // 02:00 local on the 10th still belongs to the 9th's study day.
        assert_eq!(
            study_day(at(10, 2, 0), four, &ist()),
            (at(9, 4, 0), at(10, 4, 0))
        );
        assert_eq!(
            study_day(at(10, 4, 0), four, &ist()),
            (at(10, 4, 0), at(11, 4, 0))
        );
        assert_eq!(
            study_day(at(10, 23, 59), four, &ist()),
            (at(10, 4, 0), at(11, 4, 0))
        );
        // The same instant (08:00 IST = 02:30 UTC) belongs to the 10th's
        // study day in IST and to the 9th's in UTC.
        assert_eq!(study_day(at(10, 8, 0), four, &ist()).0, at(10, 4, 0));
        let utc = FixedOffset::east_opt(0).unwrap();
        let (start, _) = study_day(at(10, 8, 0), four, &utc);
        assert_eq!(start, Utc.with_ymd_and_hms(2026, 3, 9, 4, 0, 0).unwrap());
        // A day starting at midnight.
        let midnight = NaiveTime::from_hms_opt(0, 0, 0).unwrap();
        assert_eq!(
            study_day(at(10, 0, 0), midnight, &ist()),
            (at(10, 0, 0), at(11, 0, 0))
        );
    }

    /// A zone at +01:00 that springs forward to +02:00 at 01:00 UTC on
    /// 29 March 2026 (local 02:00 → 03:00) and falls back at 01:00 UTC on
    /// 25 October 2026 (local 03:00 → 02:00), as central Europe does.
    #[derive(Debug, Clone, Copy)]
    struct Cet;

    impl Cet {
        fn switch() -> (NaiveDateTime, NaiveDateTime) {
            let d = |m, d| {
                chrono::NaiveDate::from_ymd_opt(2026, m, d)
                    .unwrap()
                    .and_hms_opt(1, 0, 0)
                    .unwrap()
            };
            (d(3, 29), d(10, 25))
        }
        fn at_utc(utc: &NaiveDateTime) -> FixedOffset {
            let (spring, fall) = Cet::switch();
            let summer = *utc >= spring && *utc < fall;
            FixedOffset::east_opt(if summer { 7200 } else { 3600 }).unwrap()
        }
    }

    impl TimeZone for Cet {
        type Offset = FixedOffset;
        fn from_offset(_: &FixedOffset) -> Cet {
            Cet
        }
        fn offset_from_local_date(&self, local: &chrono::NaiveDate) -> LocalResult<FixedOffset> {
            self.offset_from_local_datetime(&local.and_hms_opt(12, 0, 0).unwrap())
        }
        fn offset_from_local_datetime(&self, local: &NaiveDateTime) -> LocalResult<FixedOffset> {
            let fits = |secs: i32| {
                let off = FixedOffset::east_opt(secs).unwrap();
                (Cet::at_utc(&(*local - TimeDelta::seconds(i64::from(secs)))) == off).then_some(off)
            };
            match (fits(3600), fits(7200)) {
                (Some(a), Some(b)) => LocalResult::Ambiguous(b, a),
                (Some(a), None) | (None, Some(a)) => LocalResult::Single(a),
                (None, None) => LocalResult::None,
            }
        }
        fn offset_from_utc_date(&self, utc: &chrono::NaiveDate) -> FixedOffset {
            Cet::at_utc(&utc.and_hms_opt(0, 0, 0).unwrap())
        }
        fn offset_from_utc_datetime(&self, utc: &NaiveDateTime) -> FixedOffset {
            Cet::at_utc(utc)
        }
    }

    #[test]
    fn study_days_across_daylight_saving_changes() {
        let utc = |m, d, h, min| Utc.with_ymd_and_hms(2026, m, d, h, min, 0).unwrap();
        let four = NaiveTime::from_hms_opt(4, 0, 0).unwrap();
        // The spring-forward day is 23 hours long, the fall-back day 25.
        assert_eq!(
            study_day(utc(3, 29, 12, 0), four, &Cet),
            (utc(3, 29, 2, 0), utc(3, 30, 2, 0))
        );
        assert_eq!(
            study_day(utc(3, 28, 12, 0), four, &Cet),
            (utc(3, 28, 3, 0), utc(3, 29, 2, 0))
        );
        assert_eq!(
            study_day(utc(10, 25, 12, 0), four, &Cet),
            (utc(10, 25, 3, 0), utc(10, 26, 3, 0))
        );
        // A day starting at 02:30, which is skipped once and doubled once:
        // the first instant after the gap, the earlier of the two.
        let half_two = NaiveTime::from_hms_opt(2, 30, 0).unwrap();
        assert_eq!(
            study_day(utc(3, 29, 12, 0), half_two, &Cet).0,
            utc(3, 29, 1, 0)
        );
        assert_eq!(
            study_day(utc(10, 25, 12, 0), half_two, &Cet).0,
            utc(10, 25, 0, 30)
        );
        // Just before a skipped start, the day is still the previous one.
        assert_eq!(
            study_day(utc(3, 29, 0, 59), half_two, &Cet).0,
            utc(3, 28, 1, 30)
        );
    }

    #[test]
    fn order_is_learning_then_most_overdue_reviews_then_new_in_deck_order() {
        let now = at(10, 12, 0);
        let items: Vec<_> = [
            "n1",
            "r-recent",
            "l-late",
            "n2",
            "r-old",
            "l-early",
            "r-tonight",
            "n3",
        ]
        .iter()
        .map(|c| key(c))
        .collect();
        let mut states = States::default();
        states.insert(key("r-recent"), state(State::Review, at(10, 9, 0)));
        states.insert(key("r-old"), state(State::Review, at(2, 9, 0)));
        // Due later today (before tomorrow 04:00): still today's review.
        states.insert(key("r-tonight"), state(State::Review, at(11, 3, 59)));
        states.insert(key("l-late"), state(State::Learning, at(10, 11, 50)));
        states.insert(key("l-early"), state(State::Relearning, at(10, 11, 0)));
        let q = Queue::build(&items, &states, DoneToday::default(), now, &cfg(), &ist());
        use QueueKind::*;
        let got = order(&q, now);
        let want = [
            ("l-early", Learning),
            ("l-late", Learning),
            ("r-old", Review),
            ("r-recent", Review),
            ("r-tonight", Review),
            ("n1", New),
            ("n2", New),
            ("n3", New),
        ];
        assert_eq!(got, want.map(|(c, k)| (c.to_string(), k)));
        assert_eq!(
            q.counts(),
            Counts {
                due: 3,
                learning: 2,
                new: 3
            }
        );
        assert_eq!(q.counts().to_string(), "3 due · 2 learning · 3 new");
    }

    #[test]
    fn items_due_after_the_day_are_left_out() {
        let now = at(10, 12, 0);
        let items = vec![key("tomorrow"), key("learn-tomorrow")];
        let mut states = States::default();
        states.insert(key("tomorrow"), state(State::Review, at(11, 4, 0)));
        states.insert(key("learn-tomorrow"), state(State::Learning, at(11, 5, 0)));
        let q = Queue::build(&items, &states, DoneToday::default(), now, &cfg(), &ist());
        assert!(q.is_finished());
        assert_eq!(q.next(now), None);
    }

    #[test]
    fn daily_limits_count_what_was_done_today() {
        let now = at(10, 12, 0);
        let mut items = Vec::new();
        let mut states = States::default();
        for i in 0..300 {
            let k = key(&format!("r{i:03}"));
            // r000 is the least overdue, r299 the most.
            states.insert(k.clone(), state(State::Review, now - TimeDelta::hours(i)));
            items.push(k);
        }
        for i in 0..30 {
            items.push(key(&format!("n{i:02}")));
        }
        let q = Queue::build(&items, &states, DoneToday::default(), now, &cfg(), &ist());
        assert_eq!(
            q.counts(),
            Counts {
                due: 200,
                learning: 0,
                new: 20
            }
        );
        let got = order(&q, now);
        assert_eq!(got[0].0, "r299");
        assert_eq!(got[199].0, "r100");
        assert_eq!(got[200].0, "n00");
        assert_eq!(got[219].0, "n19");

        let done = DoneToday {
            new: 15,
            reviews: 190,
        };
        let q = Queue::build(&items, &states, done, now, &cfg(), &ist());
        assert_eq!(
            q.counts(),
            Counts {
                due: 10,
                learning: 0,
                new: 5
            }
        );
        let over = DoneToday {
            new: 40,
            reviews: 999,
        };
        let q = Queue::build(&items, &states, over, now, &cfg(), &ist());
        assert_eq!(
            q.counts(),
            Counts {
                due: 0,
                learning: 0,
                new: 0
            }
        );

        let c = Config {
            new_per_day: 2,
            reviews_per_day: 1,
            ..cfg()
        };
        let q = Queue::build(&items, &states, DoneToday::default(), now, &c, &ist());
        let got = order(&q, now);
        assert_eq!(
            got.iter().map(|g| g.0.as_str()).collect::<Vec<_>>(),
            ["r299", "n00", "n01"]
        );
    }

    #[test]
    fn learning_cards_come_back_when_due_or_early_when_nothing_else() {
        let sched = Scheduler::new(&cfg());
        let t = at(10, 12, 0);
        let items = vec![key("a"), key("b")];
        let mut q = Queue::build(
            &items,
            &States::default(),
            DoneToday::default(),
            t,
            &cfg(),
            &ist(),
        );
        let (k, kind) = q.next(t).unwrap();
        assert_eq!((k.card.as_str(), kind), ("a", QueueKind::New));
        let a = sched.review(&key("a"), None, Rating::Good, t, 0);
        q.answered(&a);
        assert_eq!(
            q.counts(),
            Counts {
                due: 0,
                learning: 1,
                new: 1
            }
        );
        // `a` is due in 10 minutes: `b` first.
        assert_eq!(q.next(t).unwrap().0.card, "b");
        let b = sched.review(&key("b"), None, Rating::Again, t + TimeDelta::seconds(5), 0);
        q.answered(&b);
        // Nothing else left: the earliest learning card is shown early,
        // within the learn-ahead limit, even with the clock standing still.
        let (k, kind) = q.next(t).unwrap();
        assert_eq!((k.card.as_str(), kind), ("b", QueueKind::Learning));
        assert_eq!(q.next_learning_due(), Some(t + TimeDelta::seconds(65)));
        // Once due, `a` comes back.
        assert_eq!(q.next(t + TimeDelta::minutes(10)).unwrap().0.card, "b");
        let b2 = sched.review(
            &key("b"),
            Some(&b.after),
            Rating::Good,
            t + TimeDelta::minutes(2),
            0,
        );
        q.answered(&b2);
        assert_eq!(q.next(t + TimeDelta::minutes(10)).unwrap().0.card, "a");
        // A graduated card leaves the queue.
        let a2 = sched.review(
            &key("a"),
            Some(&a.after),
            Rating::Good,
            t + TimeDelta::minutes(10),
            0,
        );
        assert_eq!(a2.after.state, State::Review);
        q.answered(&a2);
        assert_eq!(
            q.counts(),
            Counts {
                due: 0,
                learning: 1,
                new: 0
            }
        );
    }

    #[test]
    fn learning_beyond_learn_ahead_waits() {
        let t = at(10, 12, 0);
        let items = vec![key("l")];
        let mut states = States::default();
        states.insert(key("l"), state(State::Learning, t + TimeDelta::minutes(21)));
        let q = Queue::build(&items, &states, DoneToday::default(), t, &cfg(), &ist());
        assert_eq!(q.next(t), None);
        assert!(!q.is_finished());
        assert_eq!(
            q.next(t + TimeDelta::minutes(1)).unwrap().1,
            QueueKind::Learning
        );
    }

    #[test]
    fn a_lapse_joins_the_learning_queue() {
        let sched = Scheduler::new(&cfg());
        let t = at(10, 12, 0);
        let items = vec![key("r"), key("n")];
        let mut states = States::default();
        states.insert(key("r"), state(State::Review, t - TimeDelta::days(1)));
        let mut q = Queue::build(&items, &states, DoneToday::default(), t, &cfg(), &ist());
        let rec = sched.review(&key("r"), states.get(&key("r")), Rating::Again, t, 0);
        assert_eq!(rec.after.state, State::Relearning);
        q.answered(&rec);
        assert_eq!(
            q.counts(),
            Counts {
                due: 0,
                learning: 1,
                new: 1
            }
        );
        assert_eq!(q.next(t + TimeDelta::minutes(10)).unwrap().0.card, "r");
    }

    #[test]
    fn undo_puts_the_item_back_where_it_was() {
        let sched = Scheduler::new(&cfg());
        let t = at(10, 12, 0);
        let items = vec![key("r"), key("n1"), key("n2")];
        let mut states = States::default();
        let before = state(State::Review, t - TimeDelta::days(1));
        states.insert(key("r"), before);
        let mut q = Queue::build(&items, &states, DoneToday::default(), t, &cfg(), &ist());
        let original = order(&q, t);
        let rec = sched.review(&key("r"), Some(&before), Rating::Again, t, 0);
        q.answered(&rec);
        q.restore(&key("r"), Some(&before));
        assert_eq!(order(&q, t), original);
        let rec = sched.review(&key("n1"), None, Rating::Good, t, 0);
        q.answered(&rec);
        q.answered(&sched.review(&key("r"), Some(&before), Rating::Good, t, 0));
        q.restore(&key("n1"), None);
        assert_eq!(q.next(t).unwrap().0.card, "n1");
        assert_eq!(
            q.counts(),
            Counts {
                due: 0,
                learning: 0,
                new: 2
            }
        );
    }

    #[test]
    fn cram_answers_do_not_move_the_day_queue() {
        let sched = Scheduler::new(&cfg());
        let t = at(10, 12, 0);
        let mut q = Queue::build(
            &[key("n")],
            &States::default(),
            DoneToday::default(),
            t,
            &cfg(),
            &ist(),
        );
        q.answered(&sched.cram(&key("n"), None, Rating::Good, t, 0));
        assert_eq!(q.counts().new, 1);
    }

    #[test]
    fn a_listed_queue_brings_a_lapse_back_at_its_step_not_at_the_end() {
        let sched = Scheduler::new(&cfg());
        let t = at(10, 12, 0);
        let day = study_day(t, cfg().day_starts_at, &ist());
        let (a, b, c) = (key("a"), key("b"), key("c"));
        let before = state(State::Review, t - TimeDelta::days(1));
        let mut q = Queue::listed(vec![a.clone(), b.clone(), c.clone()], day);
        assert_eq!(q.next(t).unwrap().0, &a, "the list's order");
        let lapse = sched.review(&a, Some(&before), Rating::Again, t, 0);
        assert_eq!(lapse.after.state, State::Relearning);
        let step = lapse.after.due;
        assert!(step > t && step < day.1);
        q.answered(&lapse);
        // Before its step the list goes on; at the step it comes first.
        assert_eq!(q.next(t).unwrap().0, &b);
        assert_eq!(q.next(step), Some((&a, QueueKind::Learning)));
        assert_eq!(q.counts().total(), 3);
        // Listed items are each shown once: Good on a review item ends it.
        q.answered(&sched.review(&b, Some(&before), Rating::Good, t, 0));
        q.answered(&sched.review(&c, Some(&before), Rating::Good, t, 0));
        assert_eq!(q.next_learning_due(), Some(step));
        // With the list done, the step is shown early within the learn-ahead
        // limit, as in the day's queue.
        assert_eq!(q.next(step - LEARN_AHEAD).unwrap().0, &a);
        assert_eq!(q.next(step - LEARN_AHEAD - TimeDelta::minutes(1)), None);
        // Undo puts an item back in the list.
        q.restore(&c, Some(&before));
        assert_eq!(q.next(t).unwrap().0, &c);
    }

    #[test]
    fn cram_queue_repeats_again_answers() {
        let sched = Scheduler::new(&cfg());
        let t = at(10, 12, 0);
        let mut c = CramQueue::new(vec![key("a"), key("b")]);
        let a = c.next().unwrap().clone();
        c.answered(&sched.cram(&a, None, Rating::Again, t, 0));
        assert_eq!(c.next().unwrap().card, "b");
        assert_eq!(c.remaining(), 2);
        c.answered(&sched.cram(&key("b"), None, Rating::Good, t, 0));
        assert_eq!(c.next().unwrap().card, "a");
        c.answered(&sched.cram(&key("a"), None, Rating::Easy, t, 0));
        assert_eq!(c.next(), None);
        c.restore(&key("a"));
        assert_eq!(c.remaining(), 1);
    }
}

#[cfg(test)]
mod deck_tests {
    use super::*;
    use crate::deck::model::{Card, Text};
    use chrono::FixedOffset;

    fn card(id: &str, kind: CardKind, tags: &[&str]) -> Card {
        Card {
            id: id.into(),
            kind,
            front: Text::default(),
            back: Text::default(),
            accept: if kind == CardKind::Typed {
                vec!["x".into()]
            } else {
                vec![]
            },
            accept_by_lang: Default::default(),
            explain: None,
            prompt: None,
            tags: tags.iter().map(|t| t.to_string()).collect(),
            formula: None,
        }
    }

    fn deck() -> Deck {
        Deck {
            parent: None,
            misconceptions: Vec::new(),
            explore: Vec::new(),
            derivations: Vec::new(),
            id: "rot".into(),
            title: Text::default(),
            description: None,
            languages: vec!["en".into()],
            cards: vec![
                card("basic", CardKind::Basic, &["frames"]),
                card("rev", CardKind::Reversed, &["euler"]),
                card("typed", CardKind::Typed, &["euler", "frames"]),
            ],
            prompts: vec![],
            systems: vec![],
            scenes: vec![],
            sections: vec![],
            units: vec![],
            path: "rot.toml".into(),
        }
    }

    fn names(items: &[ItemKey]) -> Vec<String> {
        items
            .iter()
            .map(|k| format!("{}/{}:{}", k.deck, k.card, k.direction.as_str()))
            .collect()
    }

    #[test]
    fn reversed_cards_are_two_items() {
        assert_eq!(
            names(&deck_items(&deck())),
            [
                "rot/basic:forward",
                "rot/rev:forward",
                "rot/rev:backward",
                "rot/typed:forward"
            ]
        );
    }

    #[test]
    fn cram_items_filter_by_tag() {
        assert_eq!(
            names(&cram_items(&deck(), Some("euler"))),
            ["rot/rev:forward", "rot/rev:backward", "rot/typed:forward"]
        );
        assert_eq!(names(&cram_items(&deck(), Some("frames"))).len(), 2);
        assert!(cram_items(&deck(), Some("none")).is_empty());
    }

    #[test]
    fn the_two_directions_keep_separate_state() {
        let d = deck();
        let items = deck_items(&d);
        let tz = FixedOffset::east_opt(0).unwrap();
        let now = Utc.with_ymd_and_hms(2026, 3, 10, 12, 0, 0).unwrap();
        let mut states = States::default();
        // Forward learnt and due; backward never seen.
        states.insert(
            items[1].clone(),
            CardState {
                state: State::Review,
                step: None,
                stability: Some(3.0),
                difficulty: Some(5.0),
                due: now - TimeDelta::hours(1),
                last_review: Some(now - TimeDelta::days(3)),
            },
        );
        // Siblings not buried: the new backward item is offered too.
        let config = Config {
            bury_siblings: false,
            ..Config::default()
        };
        let q = Queue::build(&items, &states, DoneToday::default(), now, &config, &tz);
        assert_eq!(
            q.counts(),
            Counts {
                due: 1,
                learning: 0,
                new: 3
            }
        );
        // Buried (the default): answering the forward review would set the
        // backward item aside, so it is not counted as today's new.
        let buried = Queue::build(
            &items,
            &states,
            DoneToday::default(),
            now,
            &Config::default(),
            &tz,
        );
        assert_eq!(buried.counts().new, 2);
        assert!(!buried.contains(&items[2]));
        let (first, kind) = q.next(now).unwrap();
        assert_eq!((first, kind), (&items[1], QueueKind::Review));
        assert_eq!(first.direction, Direction::Forward);
    }
}

#[cfg(test)]
mod limit_tests {
    use super::*;
    use crate::sched::scheduler::Scheduler;
    use crate::sched::types::Rating;
    use proptest::prelude::*;

    fn item(deck: &str, card: &str, direction: Direction) -> ItemKey {
        ItemKey {
            deck: deck.into(),
            card: card.into(),
            direction,
        }
    }

    fn now() -> DateTime<Utc> {
        Utc.with_ymd_and_hms(2026, 3, 10, 12, 0, 0).unwrap()
    }

    /// 20 reversed cards: two items each.
    fn reversed(deck: &str, n: usize) -> Vec<ItemKey> {
        (0..n)
            .flat_map(|i| {
                let card = format!("c{i:02}");
                [
                    item(deck, &card, Direction::Forward),
                    item(deck, &card, Direction::Backward),
                ]
            })
            .collect()
    }

    #[test]
    fn buried_siblings_do_not_use_up_the_new_limit() {
        let items = reversed("d", 30);
        let config = Config {
            fuzz: false,
            ..Config::default()
        };
        let sched = Scheduler::new(&config);
        let mut q = Queue::build(
            &items,
            &States::default(),
            DoneToday::default(),
            now(),
            &config,
            &Utc,
        );
        // One item per card, twenty cards.
        assert_eq!(q.counts().new, 20);
        let mut introduced = Vec::new();
        let mut t = now();
        while let Some((key, QueueKind::New)) = q.next(t) {
            let key = key.clone();
            let rec = sched.review(&key, None, Rating::Easy, t, 0);
            q.answered(&rec);
            introduced.push(key);
            t += TimeDelta::seconds(10);
        }
        assert_eq!(introduced.len(), 20);
        let cards: std::collections::HashSet<&str> =
            introduced.iter().map(|k| k.card.as_str()).collect();
        assert_eq!(cards.len(), 20, "twenty notes, not ten");
        assert!(introduced.iter().all(|k| k.direction == Direction::Forward));
        assert_eq!(q.counts().new, 0);

        // Without burying, both directions come, and count.
        let open = Config {
            bury_siblings: false,
            ..config
        };
        let q = Queue::build(
            &items,
            &States::default(),
            DoneToday::default(),
            now(),
            &open,
            &Utc,
        );
        assert_eq!(q.counts().new, 20);
        assert_eq!(order_new(&q).iter().filter(|k| k.card == "c00").count(), 2);
    }

    #[test]
    fn an_item_set_aside_leaves_its_place_to_the_next() {
        let items = reversed("d", 30);
        let config = Config {
            new_per_day: 3,
            ..Config::default()
        };
        let mut q = Queue::build(
            &items,
            &States::default(),
            DoneToday::default(),
            now(),
            &config,
            &Utc,
        );
        assert_eq!(q.counts().new, 3);
        q.set_aside(&items[0]);
        assert_eq!(q.counts().new, 3);
        assert_eq!(q.next(now()).unwrap().0, &items[2]);
        // Undo of an introduced item gives its place back.
        let sched = Scheduler::new(&config);
        let rec = sched.review(&items[2], None, Rating::Good, now(), 0);
        q.answered(&rec);
        assert_eq!(q.counts().new, 2);
        q.restore(&items[2], None);
        assert_eq!(q.counts().new, 3);
        assert_eq!(q.next(now()).unwrap().0, &items[2]);
    }

    fn order_new(q: &Queue) -> Vec<ItemKey> {
        let mut q = q.clone();
        let mut out = Vec::new();
        while let Some((k, QueueKind::New)) = q.next(now()) {
            let k = k.clone();
            q.take_out(&k);
            out.push(k);
        }
        out
    }

    #[test]
    fn a_parent_and_its_children_each_bound_the_new_items() {
        let parent: Vec<ItemKey> = (0..3)
            .map(|i| item("p", &format!("a{i}"), Direction::Forward))
            .collect();
        let a: Vec<ItemKey> = (0..10)
            .map(|i| item("p-a", &format!("b{i}"), Direction::Forward))
            .collect();
        let b: Vec<ItemKey> = (0..10)
            .map(|i| item("p-b", &format!("c{i}"), Direction::Forward))
            .collect();
        fn refs(keys: &[ItemKey]) -> Vec<ItemRef<'_>> {
            keys.iter().map(ItemKey::as_ref).collect()
        }
        let (parent, a, b) = (refs(&parent), refs(&a), refs(&b));
        let part = |deck, items, parent, new_per_day, done_new| Part {
            deck,
            items,
            parent,
            new_per_day,
            reviews_per_day: 100,
            done: DoneToday {
                new: done_new,
                reviews: 0,
            },
        };
        let config = Config::default();
        let build =
            |parts: &[Part]| Queue::build_parts(parts, &States::default(), now(), &config, &Utc);
        // Parent 6 a day, child a 2, child b 10: the parent's 3, a's 2, then
        // one of b before the parent's limit stops it.
        let q = build(&[
            part("p", &parent, None, 6, 0),
            part("p-a", &a, Some(0), 2, 0),
            part("p-b", &b, Some(0), 10, 0),
        ]);
        let got: Vec<String> = order_new(&q).into_iter().map(|k| k.card).collect();
        assert_eq!(got, ["a0", "a1", "a2", "b0", "b1", "c0"]);
        assert_eq!(q.counts().new, 6);
        // What a child did today counts against the parent (the caller
        // rolls it up): a introduced 2, the parent has 4 left.
        let q = build(&[
            part("p", &parent, None, 6, 2),
            part("p-a", &a, Some(0), 2, 2),
            part("p-b", &b, Some(0), 10, 0),
        ]);
        let got: Vec<String> = order_new(&q).into_iter().map(|k| k.card).collect();
        assert_eq!(got, ["a0", "a1", "a2", "c0"]);
        // A child studied alone: its own limit only.
        let q = build(&[part("p-b", &b, None, 10, 0)]);
        assert_eq!(q.counts().new, 10);
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(128))]

        /// Whatever the tree and limits, no deck's subtree is offered more
        /// new items than its limit leaves, and an item is left out only
        /// when some deck on its way up is full.
        #[test]
        fn new_items_respect_every_limit_on_the_way_up(
            shape in proptest::collection::vec((0usize..4, 0u32..6, 0u32..4, 0usize..6, proptest::bool::ANY), 1..6),
        ) {
            let ids: Vec<String> = (0..shape.len()).map(|i| format!("d{i}")).collect();
            let items: Vec<Vec<ItemKey>> = shape
                .iter()
                .enumerate()
                .map(|(p, &(_, _, _, n, rev))| {
                    if rev { reversed(&ids[p], n) } else {
                        (0..n).map(|i| item(&ids[p], &format!("c{i}"), Direction::Forward)).collect()
                    }
                })
                .collect();
            let refs: Vec<Vec<ItemRef>> = items
                .iter()
                .map(|keys| keys.iter().map(ItemKey::as_ref).collect())
                .collect();
            let parts: Vec<Part> = shape
                .iter()
                .enumerate()
                .map(|(p, &(up, limit, done, _, _))| Part {
                    deck: &ids[p],
                    items: &refs[p],
                    parent: (p > 0).then(|| up % p),
                    new_per_day: limit,
                    reviews_per_day: 10,
                    done: DoneToday { new: done, reviews: 0 },
                })
                .collect();
            let q = Queue::build_parts(&parts, &States::default(), now(), &Config::default(), &Utc);
            let offered = order_new(&q);
            prop_assert_eq!(offered.len(), q.counts().new);
            let part_of = |k: &ItemKey| ids.iter().position(|d| *d == k.deck).unwrap();
            let up = |p: usize| parts[p].parent;
            let under = |p: usize, mut x: usize| loop {
                if x == p { return true; }
                match up(x) { Some(u) => x = u, None => return false }
            };
            let left = |p: usize| parts[p].new_per_day.saturating_sub(parts[p].done.new) as usize;
            for p in 0..parts.len() {
                let n = offered.iter().filter(|k| under(p, part_of(k))).count();
                prop_assert!(n <= left(p), "deck {} offered {} of {}", p, n, left(p));
            }
            // One item per card.
            let mut cards: Vec<(&str, &str)> = offered.iter().map(|k| (k.deck.as_str(), k.card.as_str())).collect();
            cards.sort_unstable();
            let all = cards.len();
            cards.dedup();
            prop_assert_eq!(cards.len(), all);
            // Left out only when a deck on the way up is full.
            for (p, its) in items.iter().enumerate() {
                for k in its.iter().filter(|k| k.direction == Direction::Forward) {
                    if offered.contains(k) { continue; }
                    let mut x = Some(p);
                    let mut full = false;
                    while let Some(a) = x {
                        let n = offered.iter().filter(|o| under(a, part_of(o))).count();
                        full |= n >= left(a);
                        x = up(a);
                    }
                    prop_assert!(full, "{:?} left out with room", k);
                }
            }
        }
    }
}
