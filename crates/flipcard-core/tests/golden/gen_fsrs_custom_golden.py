#!/usr/bin/env python3
"""Generate the golden FSRS sequences with custom (fitted) parameters that
`tests/sched_golden_custom.rs` replays.

Needs the PyPI package `fsrs` (py-fsrs) 6.x:

    pip install 'fsrs>=6,<7'
    python3 crates/flipcard-core/tests/golden/gen_fsrs_custom_golden.py > crates/flipcard-core/tests/golden/fsrs_py_custom.json

The same review paths as `gen_fsrs_golden.py`, but each parameter set below
stands for what `flipcard optimize --apply` may write: every number inside
the range the `fsrs` crate fits it in, written as the shortest decimal of an
f32 (as the crate's output is written to the config). Fuzzing off,
deterministic (fixed seed).
"""

import json
import os
import random
import sys
from importlib.metadata import version

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

from fsrs import Scheduler  # noqa: E402
from gen_fsrs_golden import (  # noqa: E402
    random_sequence,
)

SEED = 20261123

# Fitted-looking sets: slower and faster forgetting than the defaults, a
# steep decay (0.5, FSRS-5's), a flat one, strong short-term terms.
PARAMETER_SETS = {
    "slow-forgetter": [
        0.4072, 1.1829, 3.1262, 15.4722, 7.2102, 0.5316, 1.0651, 0.0234, 1.616,
        0.1544, 1.0824, 1.9813, 0.0953, 0.2975, 2.2042, 0.2407, 2.9466, 0.5034,
        0.6567, 0.1, 0.2,
    ],
    "fast-forgetter": [
        0.1, 0.6, 1.4, 4.0, 7.9, 1.1, 2.2, 0.09, 1.2, 0.3, 0.6, 2.4, 0.15, 0.5,
        1.1, 0.4, 2.1, 0.9, 0.3, 0.2, 0.5,
    ],
    "flat-decay-short-term": [
        1.0, 2.0, 5.0, 30.0, 5.5, 0.7, 1.9, 0.2, 2.1, 0.05, 1.3, 0.9, 0.02,
        0.15, 2.6, 0.8, 1.5, 1.6, 1.2, 0.7, 0.1001,
    ],
}

RETENTIONS = [0.9, 0.8]


def main():
    rng = random.Random(SEED)
    sequences = []
    for name, params in PARAMETER_SETS.items():
        for retention in RETENTIONS:
            scheduler = Scheduler(
                parameters=params, desired_retention=retention, enable_fuzzing=False,
            )
            for i in range(12):
                length = rng.randint(4, 22)
                reviews = random_sequence(rng, scheduler, length)
                sequences.append({
                    "name": f"{name}-{retention}-random-{i}",
                    "parameters": [repr(float(p)) for p in params],
                    "desired_retention": repr(retention),
                    "reviews": reviews,
                })
    doc = {
        "generator": "crates/flipcard-core/tests/golden/gen_fsrs_custom_golden.py",
        "fsrs_version": version("fsrs"),
        "enable_fuzzing": False,
        "learning_steps": [60, 600],
        "relearning_steps": [600],
    }
    text = json.dumps(doc, indent=1)[:-2]
    text += ',\n "sequences": [\n'
    text += ",\n".join("  " + json.dumps(seq, separators=(",", ":")) for seq in sequences)
    text += "\n ]\n}\n"
    sys.stdout.write(text)


if __name__ == "__main__":
    main()
