#!/usr/bin/env python3
"""Synthetic learners' exports for timing `flipcard report`.

    python3 benches/class_fixture.py OUT_DIR [LEARNERS]
    time flipcard report OUT_DIR/* --out report-out

Each learner reviews every card of the bundled deck 5 to 15 times (half the
learners as JSON, half as CSV) and predicts the three stability prompts.
"""
import csv
import json
import os
import random
import re
import sys

out = sys.argv[1]
learners = int(sys.argv[2]) if len(sys.argv) > 2 else 200
here = os.path.dirname(os.path.abspath(__file__))
deck = open(os.path.join(here, "..", "decks", "torque-free-rotation.toml")).read()
cards = re.findall(r'^\[\[card\]\]\nid = "([^"]+)"', deck, re.M)
prompts = ["middle-axis", "largest-axis", "smallest-axis"]
random.seed(7)
os.makedirs(out, exist_ok=True)
for i in range(learners):
    rows = []
    for c in cards:
        for k in range(random.randint(5, 15)):
            rows.append(dict(deck="torque-free-rotation", card=c, direction="forward",
                             reviewed_at=f"2026-01-{1 + k % 28:02d}T10:{k % 60:02d}:00.000Z",
                             rating=random.choice([1, 2, 3, 3, 3, 4]),
                             kind="learn" if k == 0 else "review", elapsed_days=1,
                             scheduled_days=2, stability=2.0,
                             difficulty=round(random.uniform(1, 10), 3), state="review",
                             due="2026-03-01T00:00:00.000Z", duration_ms=3000, undone=False))
    if i % 2:
        with open(os.path.join(out, f"learner{i:03}.reviews.json"), "w") as f:
            f.write("[\n" + ",\n".join(json.dumps(r, separators=(",", ":")) for r in rows) + "\n]\n")
    else:
        with open(os.path.join(out, f"learner{i:03}.reviews.csv"), "w", newline="") as f:
            w = csv.writer(f)
            keys = list(rows[0].keys())
            w.writerow(keys)
            for r in rows:
                w.writerow([str(r[k]).lower() if isinstance(r[k], bool) else r[k] for k in keys])
    with open(os.path.join(out, f"learner{i:03}.attempts.csv"), "w") as f:
        f.write("deck,prompt,attempted_at,prediction,measured,correct\n")
        for p in prompts:
            guess = random.choice(["flips", "stable"])
            right = str(random.random() < 0.5).lower()
            f.write(f"torque-free-rotation,{p},2026-01-02T10:00:00Z,{guess},1,{right}\n")
