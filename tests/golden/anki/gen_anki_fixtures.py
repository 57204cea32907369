#!/usr/bin/env python3
"""Generate the Anki packages that `tests/anki_import.rs` imports.

Needs the PyPI packages genanki (the legacy layout), anki (Anki's own
library, for the current zstd layout) and zstandard:

    pip install genanki anki zstandard
    python3 tests/golden/anki/gen_anki_fixtures.py tests/golden/anki

Writes:
- legacy.apkg     genanki's collection.anki2 (schema 11): Basic, Basic (and
                  reversed card) and Cloze notes with HTML, MathJax and an
                  image, plus the hand-written revlog below;
- modern.apkg     the same notes and revlog exported by Anki itself without
                  the legacy option (collection.anki21b, zstd, schema 18);
- modern.colpkg   the same as a whole-collection package;
- unknown-type.apkg  a note type with three fields;
- damaged.apkg    a collection whose pages are overwritten;
- bomb.apkg       a zstd collection that unpacks to 600 MiB of zeros;
- not-a-zip.apkg  plain text.
Deterministic apart from Anki's own ids in modern.* (the tests read them
through the notes' content, not their ids).
"""

import io
import os
import shutil
import sqlite3
import sys
import tempfile
import zipfile

import genanki
import zstandard

OUT = sys.argv[1] if len(sys.argv) > 1 else os.path.dirname(os.path.abspath(__file__))

# (kind, fields, tags)
NOTES = [
    ("basic", ["What is <b>torque</b>?", "The rate of change of angular momentum:&nbsp;\\(\\tau = \\dot L\\)"], ["mechanics"]),
    ("basic", ["Moment of inertia of a rod about its end", "\\[I = \\frac{1}{3} m L^2\\]<br><img src=\"rod.png\">"], ["rigid-body"]),
    ("reversed", ["angular momentum", "<div>L = I&omega;</div>"], []),
    ("reversed", ["precession", "slow turning of the spin axis, costs $0"], ["gyro"]),
    ("cloze", ["The {{c1::Euler}} equations hold in the {{c2::body}} frame.", "Extra: see the reader"], []),
]

DAY = 86_400_000
T0 = 1_767_600_000_000  # 2026-01-05T08:00:00Z, in ms

# Hand-written history: (note index, card ord, [(days after T0, ease, type)]).
# Types: 0 learn, 1 review, 2 relearn, 4 manual (left out).
REVLOG = [
    (0, 0, [(0, 3, 0), (0.01, 3, 0), (2, 3, 1), (9, 1, 1), (9.01, 3, 2), (12, 3, 1)]),
    (1, 0, [(1, 4, 0), (8, 3, 1)]),
    (2, 0, [(0, 3, 0), (3, 3, 1)]),
    (2, 1, [(0, 2, 0), (0.01, 3, 0), (1, 1, 1), (20, 0, 4)]),
    (4, 0, [(0, 3, 0), (4, 3, 1)]),
]

BASIC = genanki.Model(
    1607392319, "Basic",
    fields=[{"name": "Front"}, {"name": "Back"}],
    templates=[{"name": "Card 1", "qfmt": "{{Front}}", "afmt": "{{FrontSide}}<hr id=answer>{{Back}}"}],
)
REVERSED = genanki.Model(
    1485830179, "Basic (and reversed card)",
    fields=[{"name": "Front"}, {"name": "Back"}],
    templates=[
        {"name": "Card 1", "qfmt": "{{Front}}", "afmt": "{{FrontSide}}<hr id=answer>{{Back}}"},
        {"name": "Card 2", "qfmt": "{{Back}}", "afmt": "{{FrontSide}}<hr id=answer>{{Front}}"},
    ],
)
THREE = genanki.Model(
    1702925193, "Vocabulary (three fields)",
    fields=[{"name": "Word"}, {"name": "Meaning"}, {"name": "Example"}],
    templates=[{"name": "Card 1", "qfmt": "{{Word}}", "afmt": "{{Meaning}}<br>{{Example}}"}],
)


def genanki_package(path, notes, models, media=()):
    deck = genanki.Deck(2059400110, "Physics::Rotation")
    for i, (kind, fields, tags) in enumerate(notes):
        model = models[kind]
        deck.add_note(genanki.Note(model=model, fields=fields, tags=tags, guid=f"flipcard-{i}"))
    pkg = genanki.Package(deck)
    pkg.media_files = list(media)
    pkg.write_to_file(path, timestamp=1767600000.0)


def rewrite_collection(path, change):
    """Applies `change(sqlite3.Connection)` to the package's collection.anki2."""
    with zipfile.ZipFile(path) as z:
        members = {n: z.read(n) for n in z.namelist()}
    with tempfile.TemporaryDirectory() as d:
        db = os.path.join(d, "c.anki2")
        with open(db, "wb") as f:
            f.write(members["collection.anki2"])
        conn = sqlite3.connect(db)
        change(conn)
        conn.commit()
        conn.close()
        with open(db, "rb") as f:
            members["collection.anki2"] = f.read()
    with zipfile.ZipFile(path, "w", zipfile.ZIP_DEFLATED) as z:
        for n, data in members.items():
            z.writestr(zipfile.ZipInfo(n, date_time=(2026, 1, 5, 0, 0, 0)), data, zipfile.ZIP_DEFLATED)


def revlog_rows(card_id_of):
    rows = []
    rid = T0
    for note, ord_, answers in REVLOG:
        cid = card_id_of(note, ord_)
        for days, ease, kind in answers:
            at = T0 + int(days * DAY) + note * 60_000 + ord_ * 7_000
            rows.append((at, cid, -1, ease, 1, 0, 2500, 6000 + note * 100, kind))
            rid += 1
    return rows


def add_revlog_legacy(conn):
    ids = {}
    for cid, guid, ord_ in conn.execute("SELECT c.id, n.guid, c.ord FROM cards c JOIN notes n ON n.id = c.nid"):
        ids[(int(guid.split("-")[1]), ord_)] = cid
    conn.executemany(
        "INSERT INTO revlog (id, cid, usn, ease, ivl, lastIvl, factor, time, type) VALUES (?,?,?,?,?,?,?,?,?)",
        revlog_rows(lambda n, o: ids[(n, o)]),
    )


def legacy(out):
    with tempfile.TemporaryDirectory() as d:
        png = os.path.join(d, "rod.png")
        with open(png, "wb") as f:
            f.write(b"\x89PNG\r\n\x1a\n" + b"\0" * 16)
        path = os.path.join(out, "legacy.apkg")
        genanki_package(path, NOTES, {"basic": BASIC, "reversed": REVERSED, "cloze": genanki.CLOZE_MODEL}, [png])
    rewrite_collection(path, add_revlog_legacy)

    path = os.path.join(out, "unknown-type.apkg")
    genanki_package(path, NOTES[:1] + [("three", ["lever", "a bar on a pivot", "see-saw"], [])],
                    {"basic": BASIC, "three": THREE})


def modern(out):
    from anki.collection import Collection, ExportAnkiPackageOptions, ExportLimit
    from anki.collection import DeckIdLimit

    with tempfile.TemporaryDirectory() as d:
        col = Collection(os.path.join(d, "collection.anki2"))
        did = col.decks.id("Physics::Rotation")
        names = {"basic": "Basic", "reversed": "Basic (and reversed card)", "cloze": "Cloze"}
        nids = []
        for kind, fields, tags in NOTES:
            note = col.new_note(col.models.by_name(names[kind]))
            for i, value in enumerate(fields):
                note.fields[i] = value
            note.tags = tags
            col.add_note(note, did)
            nids.append(note.id)
        with open(os.path.join(col.media.dir(), "rod.png"), "wb") as f:
            f.write(b"\x89PNG\r\n\x1a\n" + b"\0" * 16)
        ids = {}
        for i, nid in enumerate(nids):
            for cid, ord_ in col.db.all("SELECT id, ord FROM cards WHERE nid = ?", nid):
                ids[(i, ord_)] = cid
        for row in revlog_rows(lambda n, o: ids[(n, o)]):
            col.db.execute(
                "INSERT INTO revlog (id, cid, usn, ease, ivl, lastIvl, factor, time, type) VALUES (?,?,?,?,?,?,?,?,?)",
                *row,
            )
        col.export_anki_package(
            out_path=os.path.join(out, "modern.apkg"),
            options=ExportAnkiPackageOptions(with_scheduling=True, with_deck_configs=False, with_media=True, legacy=False),
            limit=DeckIdLimit(did),
        )
        col.export_collection_package(os.path.join(out, "modern.colpkg"), include_media=True, legacy=False)
        col.close()


def broken(out):
    with zipfile.ZipFile(os.path.join(out, "legacy.apkg")) as z:
        good = z.read("collection.anki2")
    page = 4096
    damaged = good[:page] + bytes((b ^ 0x5A) for b in good[page:])
    with zipfile.ZipFile(os.path.join(out, "damaged.apkg"), "w", zipfile.ZIP_DEFLATED) as z:
        z.writestr(zipfile.ZipInfo("collection.anki2", date_time=(2026, 1, 5, 0, 0, 0)), damaged)
        z.writestr(zipfile.ZipInfo("media", date_time=(2026, 1, 5, 0, 0, 0)), "{}")

    buf = io.BytesIO()
    with zstandard.ZstdCompressor(level=19).stream_writer(buf, closefd=False) as w:
        zeros = b"\0" * (1 << 20)
        for _ in range(600):
            w.write(zeros)
    with zipfile.ZipFile(os.path.join(out, "bomb.apkg"), "w", zipfile.ZIP_STORED) as z:
        z.writestr(zipfile.ZipInfo("collection.anki21b", date_time=(2026, 1, 5, 0, 0, 0)), buf.getvalue())

    with open(os.path.join(out, "not-a-zip.apkg"), "w") as f:
        f.write("front,back\nthis is a CSV file, not an Anki package\n")


if __name__ == "__main__":
    os.makedirs(OUT, exist_ok=True)
    legacy(OUT)
    modern(OUT)
    broken(OUT)
