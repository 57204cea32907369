#!/usr/bin/env python3
"""A synthetic learner whose memory follows FSRS-6 with parameters chosen
here (TRUE_PARAMETERS), studying on py-fsrs's default schedule: the review
log it writes is what `flipcard optimize` should fit back to TRUE_PARAMETERS.

Needs the PyPI package `fsrs` (py-fsrs) 6.x:

    pip install 'fsrs>=6,<7'
    # the small log the tests import and fit (committed):
    python3 tests/golden/gen_synthetic_learner.py > tests/golden/synthetic_learner.csv
    # a year of study, for measuring how close the fit gets:
    python3 tests/golden/gen_synthetic_learner.py --cards 2000 --new-per-day 20 --days 365 > big.csv

On a study day the learner first meets new cards, then answers every card
due by the end of the day, at the due time (learning steps within the day).
A quarter of the days are skipped, and two ten-day breaks leave cards long
overdue: without such spread in the time since the last review, the shape
of the forgetting curve cannot be told from the data. The
learner's true memory of each card is a py-fsrs Card updated with
TRUE_PARAMETERS; an answer after a day or more is recalled with the true
retrievability (py-fsrs's forgetting curve, whole days), then rated Hard,
Good or Easy, else Again. The schedule itself is py-fsrs's with its default
parameters and no fuzz (what flipcard does before a fit). Deterministic for
a given --seed. Output: CSV with the columns `flipcard import --reviews`
needs.
"""

import argparse
import csv
import random
import sys
from datetime import datetime, timedelta, timezone

from fsrs import Card, Rating, Scheduler

# A learner who forgets faster at first, with a steeper forgetting curve
# (decay 0.3 against the default 0.1542), and remembers easy cards longer.
TRUE_PARAMETERS = [
    0.5, 1.8, 4.5, 12.0, 6.8, 0.6, 2.2, 0.01, 1.5, 0.2, 1.0, 1.6, 0.08, 0.35,
    1.9, 0.5, 2.2, 0.5, 0.1, 0.07, 0.3,
]

FIRST_RATING = ([Rating.Again, Rating.Hard, Rating.Good, Rating.Easy], [0.2, 0.1, 0.6, 0.1])
PASS_RATING = ([Rating.Hard, Rating.Good, Rating.Easy], [0.15, 0.75, 0.1])
START = datetime(2026, 1, 5, 8, 0, 0, tzinfo=timezone.utc)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--cards", type=int, default=300)
    ap.add_argument("--new-per-day", type=int, default=10)
    ap.add_argument("--days", type=int, default=150)
    ap.add_argument("--seed", type=int, default=20261124)
    ap.add_argument("--truth", help="also write TRUE_PARAMETERS to this file, one a line")
    args = ap.parse_args()
    if args.truth:
        with open(args.truth, "w") as f:
            f.write("".join(f"{p!r}\n" for p in TRUE_PARAMETERS))

    rng = random.Random(args.seed)
    schedule = Scheduler(enable_fuzzing=False)
    truth = Scheduler(parameters=TRUE_PARAMETERS, enable_fuzzing=False)
    cards = []  # [name, scheduled Card, true Card]
    out = csv.writer(sys.stdout, lineterminator="\n")
    out.writerow(["deck", "card", "direction", "reviewed_at", "rating"])

    def answer(entry, at):
        name, sched_card, true_card = entry
        if true_card.last_review is None:
            rating = rng.choices(*FIRST_RATING)[0]
        else:
            r = truth.get_card_retrievability(true_card, at)
            rating = rng.choices(*PASS_RATING)[0] if rng.random() < r else Rating.Again
        entry[1], _ = schedule.review_card(sched_card, rating, review_datetime=at)
        entry[2], _ = truth.review_card(true_card, rating, review_datetime=at)
        stamp = at.astimezone(timezone.utc).isoformat(timespec="milliseconds").replace("+00:00", "Z")
        out.writerow(["synth", name, "forward", stamp, int(rating.value)])

    breaks = {d for b in (args.days // 3, 2 * args.days // 3) for d in range(b, b + 10)}
    for day in range(args.days):
        if day in breaks or (day > 0 and rng.random() < 0.25):
            continue
        day_start = START + timedelta(days=day)
        day_end = day_start + timedelta(hours=16)
        for _ in range(args.new_per_day):
            if len(cards) < args.cards:
                i = len(cards)
                cards.append([f"c{i:05d}", Card(card_id=i + 1, due=day_start), Card(card_id=i + 1, due=day_start)])
        # Study the day in due order, a few seconds per answer.
        clock = day_start + timedelta(seconds=rng.randint(0, 3600))
        while True:
            due = [e for e in cards if e[1].due <= day_end]
            if not due:
                break
            entry = min(due, key=lambda e: e[1].due)
            clock = max(clock, entry[1].due) + timedelta(seconds=rng.randint(4, 20))
            if clock > day_end + timedelta(hours=4):
                break
            answer(entry, clock.replace(microsecond=(clock.microsecond // 1000) * 1000))


if __name__ == "__main__":
    main()
