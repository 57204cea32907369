#!/usr/bin/env python3
"""Generate the golden FSRS sequences that `tests/sched_golden.rs` replays.

Needs the PyPI package `fsrs` (py-fsrs) 6.x:

    pip install 'fsrs>=6,<7'
    python3 crates/flipcard-core/tests/golden/gen_fsrs_golden.py > crates/flipcard-core/tests/golden/fsrs_py.json

Every sequence starts from a new card (or from a stated card, for the edge
cases where the steps were changed under a card), reviews it with fuzzing off
and records the card after every review. Floats are written as their shortest
round-trip decimal strings, so the replay reads exactly the numbers Python
computed. The output is deterministic (fixed random seed).
"""

import json
import random
import sys
from datetime import datetime, timedelta, timezone
from importlib.metadata import version

from fsrs import Card, Rating, Scheduler, State
from fsrs.scheduler import DEFAULT_PARAMETERS

SEED = 20260501
START = datetime(2026, 1, 5, 9, 30, 0, tzinfo=timezone.utc)

MIN = 60
HOUR = 3600
DAY = 86400

# (name, desired_retention, learning_steps [s], relearning_steps [s])
CONFIGS = [
    ("default", 0.9, [1 * MIN, 10 * MIN], [10 * MIN]),
    ("retention-0.70", 0.70, [1 * MIN, 10 * MIN], [10 * MIN]),
    ("retention-0.80", 0.80, [1 * MIN, 10 * MIN], [10 * MIN]),
    ("retention-0.95", 0.95, [1 * MIN, 10 * MIN], [10 * MIN]),
    ("retention-0.97", 0.97, [1 * MIN, 10 * MIN], [10 * MIN]),
    ("no-steps", 0.9, [], []),
    ("one-step", 0.9, [10 * MIN], [10 * MIN]),
    ("three-steps", 0.9, [1 * MIN, 10 * MIN, 1 * HOUR], [10 * MIN, 1 * HOUR]),
    ("odd-seconds", 0.9, [45, 7 * MIN + 3], [5 * MIN + 1]),
    ("day-step", 0.9, [1 * DAY], [1 * DAY]),
]

RATINGS = [Rating.Again, Rating.Hard, Rating.Good, Rating.Easy]
RATING_WEIGHTS = [0.17, 0.15, 0.53, 0.15]


def fmt_time(t):
    return t.astimezone(timezone.utc).isoformat().replace("+00:00", "Z")


def fmt_float(x):
    return None if x is None else repr(float(x))


def card_json(card):
    return {
        "state": int(card.state.value),
        "step": card.step,
        "stability": fmt_float(card.stability),
        "difficulty": fmt_float(card.difficulty),
        "due": fmt_time(card.due),
        "last_review": None if card.last_review is None else fmt_time(card.last_review),
    }


def scheduler_for(config):
    _, retention, learning, relearning = config
    return Scheduler(
        desired_retention=retention,
        learning_steps=[timedelta(seconds=s) for s in learning],
        relearning_steps=[timedelta(seconds=s) for s in relearning],
        enable_fuzzing=False,
    )


def next_time(rng, card):
    """When the next review happens: at, before or after the due time, or a
    plain gap of minutes, hours, days or months after the last review."""
    last = card.last_review
    interval = card.due - last
    mode = rng.choice(
        ["at-due", "at-due", "early", "late", "minutes", "hours", "days", "months"]
    )
    if mode == "at-due":
        t = card.due + timedelta(seconds=rng.randint(0, 90))
    elif mode == "early":
        t = last + interval * rng.uniform(0.05, 0.95)
    elif mode == "late":
        t = card.due + interval * rng.uniform(0.1, 4.0)
    elif mode == "minutes":
        t = last + timedelta(seconds=rng.randint(30, 3 * HOUR))
    elif mode == "hours":
        t = last + timedelta(seconds=rng.randint(3 * HOUR, 30 * HOUR))
    elif mode == "days":
        t = last + timedelta(seconds=rng.randint(DAY, 40 * DAY))
    else:
        t = last + timedelta(seconds=rng.randint(40 * DAY, 800 * DAY))
    # Review times are stored to the millisecond.
    t = t.replace(microsecond=(t.microsecond // 1000) * 1000)
    return max(t, last)


def review_all(scheduler, card, steps):
    reviews = []
    for rating, at in steps:
        card, _ = scheduler.review_card(card, rating, review_datetime=at)
        reviews.append({"rating": int(rating.value), "at": fmt_time(at), "card": card_json(card)})
    return reviews


def random_sequence(rng, scheduler, length):
    card = Card(card_id=1, due=START)
    at = START + timedelta(seconds=rng.randint(0, 12 * HOUR))
    reviews = []
    for i in range(length):
        if i > 0:
            at = next_time(rng, card)
        rating = rng.choices(RATINGS, RATING_WEIGHTS)[0]
        card, _ = scheduler.review_card(card, rating, review_datetime=at)
        reviews.append({"rating": int(rating.value), "at": fmt_time(at), "card": card_json(card)})
    return reviews


def sequence(name, config, reviews, initial=None):
    _, retention, learning, relearning = config
    return {
        "name": name,
        "desired_retention": repr(retention),
        "learning_steps": learning,
        "relearning_steps": relearning,
        "initial": initial,
        "reviews": reviews,
    }


def handmade(config_by_name):
    """Named paths through the state machine."""
    out = []
    default = config_by_name["default"]
    s = scheduler_for(default)
    t = START

    def at(**kw):
        return t + timedelta(**kw)

    G, H, A, E = Rating.Good, Rating.Hard, Rating.Again, Rating.Easy
    paths = {
        "good-through-steps-then-on-time": [
            (G, at()), (G, at(minutes=1)), (G, at(minutes=11)), (G, at(days=3)),
            (G, at(days=12)), (G, at(days=40)), (G, at(days=130)),
        ],
        "easy-from-new": [(E, at()), (E, at(days=8)), (E, at(days=60))],
        "hard-on-first-step": [(H, at()), (H, at(minutes=6)), (G, at(minutes=12)), (G, at(minutes=25))],
        "again-resets-step": [(G, at()), (A, at(minutes=2)), (G, at(minutes=3)), (G, at(minutes=14))],
        "lapse-and-relearn": [
            (G, at()), (G, at(minutes=1)), (G, at(minutes=11)), (G, at(days=3)),
            (A, at(days=15)), (H, at(days=15, minutes=10)), (G, at(days=15, minutes=30)),
            (G, at(days=17)),
        ],
        "relearning-left-days-later": [
            (E, at()), (A, at(days=9)), (G, at(days=14)), (G, at(days=20)),
        ],
        "learning-left-days-later": [(A, at()), (G, at(days=2)), (G, at(days=2, minutes=10)), (G, at(days=5))],
        "review-same-day-again": [
            (E, at()), (G, at(days=8)), (G, at(days=8, hours=5)), (A, at(days=8, hours=6)),
        ],
        "just-under-and-over-a-day": [
            (E, at()), (G, at(hours=23, minutes=59, seconds=59)), (G, at(days=1, hours=23, minutes=59, seconds=59, milliseconds=999)),
            (G, at(days=3)),
        ],
        "review-much-later": [(G, at()), (G, at(minutes=1)), (G, at(minutes=11)), (G, at(days=900)), (A, at(days=3000))],
        "hammer-easy-to-the-cap": [(E, at())] + [(E, at(days=400 * k)) for k in range(1, 40)],
        "again-forever": [(A, at(minutes=m)) for m in range(0, 30, 3)] + [(A, at(days=d)) for d in range(1, 8)],
    }
    for name, steps in paths.items():
        out.append(sequence(name, default, review_all(s, Card(card_id=1, due=t), steps)))
    return out


def edge_initial(config_by_name):
    """Cards whose step lies beyond the scheduler's steps (the steps were
    shortened since the card was last seen)."""
    out = []
    t = START
    cfg = config_by_name["one-step"]
    s = scheduler_for(cfg)
    for state, step in [(State.Learning, 3), (State.Relearning, 2)]:
        for rating in RATINGS:
            card = Card(
                card_id=1, state=state, step=step, stability=3.1, difficulty=5.5,
                due=t, last_review=t - timedelta(hours=2),
            )
            initial = card_json(card)
            reviews = review_all(s, card, [(rating, t), (Rating.Good, t + timedelta(days=4))])
            out.append(sequence(f"{state.name.lower()}-step-{step}-beyond-steps-{rating.name.lower()}", cfg, reviews, initial))
    # With retention 0.9 the interval equals the stability, and a same-day
    # Good leaves a stability above ~2.1 unchanged: exact half days, where
    # Python's round() goes to the even day.
    cfg = config_by_name["default"]
    s = scheduler_for(cfg)
    for stability in [2.5, 3.5, 4.5, 6.5, 10.5]:
        card = Card(
            card_id=1, state=State.Review, stability=stability, difficulty=5.0,
            due=t, last_review=t - timedelta(hours=1),
        )
        initial = card_json(card)
        reviews = review_all(s, card, [(Rating.Good, t)])
        out.append(sequence(f"interval-tie-{stability}", cfg, reviews, initial))
    return out


def main():
    rng = random.Random(SEED)
    config_by_name = {c[0]: c for c in CONFIGS}
    sequences = handmade(config_by_name) + edge_initial(config_by_name)
    for config in CONFIGS:
        scheduler = scheduler_for(config)
        count = 24 if config[0] == "default" else 10
        for i in range(count):
            length = rng.randint(4, 22)
            reviews = random_sequence(rng, scheduler, length)
            sequences.append(sequence(f"{config[0]}-random-{i}", config, reviews))
    doc = {
        "generator": "crates/flipcard-core/tests/golden/gen_fsrs_golden.py",
        "fsrs_version": version("fsrs"),
        "enable_fuzzing": False,
        "maximum_interval": scheduler_for(CONFIGS[0]).maximum_interval,
        "parameters": [repr(p) for p in DEFAULT_PARAMETERS],
        "sequences": sequences,
    }
    head = {k: v for k, v in doc.items() if k != "sequences"}
    text = json.dumps(head, indent=1)[:-2]
    text += ',\n "sequences": [\n'
    text += ",\n".join("  " + json.dumps(seq, separators=(",", ":")) for seq in sequences)
    text += "\n ]\n}\n"
    sys.stdout.write(text)


if __name__ == "__main__":
    main()
