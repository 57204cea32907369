#!/usr/bin/env python3
"""Writes a deck of N cards (default 50,000; one in ten reversed, two tags
each, a little math) as DIR/decks/big.toml with its empty content file, for
measuring a large collection as a whole process (benches/first_frame.sh,
`flipcard check`), and DIR/reviews.csv: three answers (Good) to each card's
first side, on 1, 4 and 20 October 2026, for a collection with a history
(`flipcard import --reviews DIR/reviews.csv --format csv` into the data
folder before timing):

    python3 benches/large_deck.py DIR [N]
"""
import pathlib
import random
import sys

WORDS = ("heart lung kidney liver nerve artery vein muscle bone cell protein enzyme "
         "hormone receptor membrane channel potassium sodium calcium glucose insulin "
         "cortisol pressure volume flow rate").split()


def main():
    root = pathlib.Path(sys.argv[1])
    n = int(sys.argv[2]) if len(sys.argv) > 2 else 50_000
    rng = random.Random(7)
    w = lambda k: " ".join(rng.choice(WORDS) for _ in range(k))
    out = ['[deck]', 'id = "big"', 'title = "A big deck"', 'languages = ["en"]', '']
    for i in range(n):
        out.append('[[card]]')
        out.append(f'id = "c{i}"')
        if i % 10 == 0:
            out.append('kind = "reversed"')
        out.append(f'tags = ["med::{rng.choice(WORDS)}", "set{i % 50}"]')
        out.append(f"front.en = '''What does the {w(6)} do when $x^2 + {i}$ rises?'''")
        out.append(f"back.en = '''It {w(8)}, so the {w(4)} falls.'''")
        out.append('')
    (root / "decks").mkdir(parents=True, exist_ok=True)
    (root / "content" / "big").mkdir(parents=True, exist_ok=True)
    (root / "content" / "big" / "en.toml").write_text("")
    (root / "decks" / "big.toml").write_text("\n".join(out) + "\n")
    rows = ["deck,card,direction,reviewed_at,rating"]
    for i in range(n):
        for day in ("2026-10-01", "2026-10-04", "2026-10-20"):
            rows.append(f"big,c{i},forward,{day}T08:{(i // 60) % 60:02d}:{i % 60:02d}.000Z,3")
    (root / "reviews.csv").write_text("\n".join(rows) + "\n")


if __name__ == "__main__":
    main()
