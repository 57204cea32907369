#!/usr/bin/env python3
"""Generate the Anki packages that `tests/anki_import.rs` imports.

Needs the PyPI packages genanki (the legacy layout), anki (Anki's own
library, for the current zstd layout) and zstandard:

    pip install anki==26.9.3 genanki==0.13.1 zstandard==0.25.0
    python3 tests/golden/anki/gen_anki_fixtures.py tests/golden/anki
    python3 tests/golden/anki/gen_anki_fixtures.py tests/golden/anki stock   # stock.* only
    python3 tests/golden/anki/gen_anki_fixtures.py tests/golden/anki no-history   # no-history.* only

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
- not-a-zip.apkg  plain text;
- stock.apkg      made by Anki itself (`stock(out)`): every stock note type
                  (Basic, Basic (and reversed card), Basic (optional reversed
                  card), Basic (type in the answer), Cloze) and a custom one,
                  deletions inside MathJax, <sup>/<sub>, bold and italic, a
                  list, a table, an empty field, suspended, buried, flagged
                  and leech cards, review history with their due dates and
                  intervals set as Anki's scheduler leaves them, FSRS on,
                  changed deck options, sub-decks and a deck named like a
                  bundled one. `stock.json` beside it holds what the tests
                  compare with (due dates, revlog ids and eases, fields),
                  read from Anki. Anki's scheduler runs on this machine's
                  clock (only the answer times are set), so due dates and
                  ids differ from one generation to the next: the tests
                  read them from stock.json, never hard-code them.
- no-history.apkg  made by Anki itself (`no_history(out)`): cards Anki
                  scheduled (review, learning and relearning, FSRS on) whose
                  review history was then deleted, as a shared deck with
                  scheduling or a collection whose revlog was cleared has
                  them, beside a new card and a card that keeps its
                  history. `no-history.json` holds what Anki had (type,
                  due, ivl, data, revlog ids) for the tests to compare.
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


# (deck, note type, fields, tags)
STOCK_NOTES = [
    ("Physics::Waves", "Basic", ["Speed of light in vacuum", "<b>c</b> = 3.00 × 10<sup>8</sup> m/s"], ["constants"]),
    ("Physics::Waves", "Basic", ["Bohr radius", "a<sub>0</sub> ≈ 5.3 × 10<sup>−11</sup> m, about <i>half</i> an ångström"], []),
    ("Physics::Waves", "Basic (and reversed card)", ["<i>Snell's law</i>", "n<sub>1</sub> sin θ<sub>1</sub> = n<sub>2</sub> sin θ<sub>2</sub>"], ["optics"]),
    ("Physics::Waves", "Basic (optional reversed card)", ["Hooke's law", "F = −kx", "y"], []),
    ("Physics::Waves", "Basic (optional reversed card)", ["Unit of frequency", "hertz", ""], []),
    ("Physics::Waves", "Basic (type in the answer)", ["SI unit of force", "newton"], []),
    ("Physics::Waves", "Cloze", ["Hooke's law: \\(F = -{{c1::k}} x\\)", ""], []),
    ("Physics::Waves", "Cloze", ["The {{c1::speed of light}} is \\(c = 1/\\sqrt{ {{c2::\\mu_0\\varepsilon_0}} }\\)", "Maxwell, 1865"], ["em"]),
    ("Physics::Waves", "Basic", ["Base quantities of mechanics", "<ul><li>mass</li><li>length</li><li>time</li></ul>"], []),
    ("Physics::Waves", "Basic", ["Units", "<table><tr><td>Force</td><td>N</td></tr><tr><td>Energy</td><td>J</td></tr></table>"], []),
    ("Physics::Waves", "Basic", ["Nothing on the back", ""], []),
    ("Physics::Waves", "Basic", ["<img src=\"only.png\">", "a picture only"], []),
    ("Physics::Waves", "Basic", ["Expectation value of the energy", "\\(\\bra{\\psi} H \\ket{\\psi}\\) costs $0"], []),
    ("Oscillations", "Physics constant", ["Planck constant", "h", "6.626 × 10<sup>−34</sup> J s"], ["constants"]),
    ("Oscillations", "Basic", ["Period of a pendulum", "\\(T = 2\\pi\\sqrt{L/g}\\)"], ["leech"]),
]

# Answers per (note index, card ord): [(days after T0, ease)], answered
# through Anki's own scheduler (its clock set to each answer's time).
STOCK_REVLOG = {
    (0, 0): [(0, 3), (1, 3), (4, 3), (12, 3)],
    (1, 0): [(0, 3), (2, 4)],
    (2, 0): [(0, 3), (1, 3), (5, 3)],
    (2, 1): [(0, 1), (0.01, 3), (1, 3)],
    (3, 1): [(0, 3), (3, 3)],
    (5, 0): [(0, 4)],
    (6, 0): [(0, 3), (3, 3)],
    (7, 1): [(0, 3), (1, 3), (2, 1), (2.01, 3), (5, 3), (9, 3), (20, 3), (30, 3), (40, 3), (45, 3), (50, 3), (52, 3)],
    (13, 0): [(0, 3), (2, 3)],
    (14, 0): [(0, 3), (1, 1), (1.01, 3), (3, 1), (3.01, 3), (6, 1), (6.01, 3)],
}


def stock(out):
    """A collection made and scheduled by Anki itself (see the module doc)."""
    import json
    import time
    from unittest import mock
    from anki.collection import Collection, ExportAnkiPackageOptions
    from anki.collection import DeckIdLimit

    with tempfile.TemporaryDirectory() as d:
        col = Collection(os.path.join(d, "collection.anki2"))
        col.set_config("fsrs", True)
        # The collection's day 0 is T0's day (its day numbers count from it).
        col.db.execute("UPDATE col SET crt = ?", T0 // 1000 - 4 * 3600)
        custom = col.models.new("Physics constant")
        for name in ["Name", "Symbol", "Value"]:
            col.models.add_field(custom, col.models.new_field(name))
        tmpl = col.models.new_template("Card 1")
        tmpl["qfmt"] = "{{Name}}"
        tmpl["afmt"] = "{{FrontSide}}<hr id=answer>{{Symbol}} = {{Value}}"
        col.models.add_template(custom, tmpl)
        col.models.add(custom)
        waves = col.decks.id("Physics::Waves")
        osc = col.decks.id("Oscillations")
        conf = col.decks.add_config_returning_id("Physics preset")
        c = col.decks.get_config(conf)
        c["new"]["perDay"] = 7
        c["rev"]["perDay"] = 70
        c["new"]["delays"] = [2.0, 15.0]
        c["lapse"]["delays"] = [5.0]
        c["desiredRetention"] = 0.85
        c["fsrsParams6"] = [0.2172, 1.1771, 3.2602, 16.1507, 7.0114, 0.57, 2.0966, 0.0069, 1.5261,
                            0.112, 1.0178, 1.849, 0.1133, 0.3127, 2.2934, 0.2191, 3.0004, 0.7536,
                            0.3332, 0.1437, 0.2]
        col.decks.update_config(c)
        deck = col.decks.get(waves)
        deck["conf"] = conf
        col.decks.save(deck)
        with open(os.path.join(col.media.dir(), "only.png"), "wb") as f:
            f.write(b"\x89PNG\r\n\x1a\n" + b"\0" * 16)
        nids = []
        for deck_name, kind, fields, tags in STOCK_NOTES:
            note = col.new_note(col.models.by_name(kind))
            for i, value in enumerate(fields):
                note.fields[i] = value
            note.tags = tags
            col.add_note(note, waves if deck_name == "Physics::Waves" else osc)
            nids.append(note.id)
        cards = {}
        for i, nid in enumerate(nids):
            for cid, ord_ in col.db.all("SELECT id, ord FROM cards WHERE nid = ?", nid):
                cards[(i, ord_)] = cid
        # Answer through Anki's scheduler, in time order, at each answer's time.
        answers = sorted(
            (T0 + int(days * DAY) + i * 60_000 + o * 7_000, i, o, ease)
            for (i, o), rows in STOCK_REVLOG.items()
            for days, ease in rows
        )
        for at, i, o, ease in answers:
            with mock.patch("time.time", return_value=at / 1000):
                card = col.get_card(cards[(i, o)])
                card.start_timer()
                states = col._backend.get_scheduling_states(card.id)
                rating = {1: 0, 2: 1, 3: 2, 4: 3}[ease]
                from anki.scheduler_pb2 import CardAnswer
                answer = col.sched.build_answer(card=card, states=states, rating=rating)
                answer.answered_at_millis = at
                answer.milliseconds_taken = 5000 + i * 100
                col.sched.answer_card(answer)
        col.sched.suspend_cards([cards[(1, 0)]])
        col.sched.bury_cards([cards[(5, 0)]], manual=True)
        col.set_user_flag_for_cards(1, [cards[(0, 0)]])
        col.set_user_flag_for_cards(4, [cards[(2, 1)]])
        path = os.path.join(out, "stock.apkg")
        col.export_anki_package(
            out_path=path,
            options=ExportAnkiPackageOptions(with_scheduling=True, with_deck_configs=True, with_media=True, legacy=False),
            limit=None,
        )
        # What the tests compare with, as Anki has it.
        crt = col.db.scalar("SELECT crt FROM col")
        expect = {"crt": crt, "made_at": int(time.time()), "cards": []}
        for (i, o), cid in sorted(cards.items()):
            ctype, queue, due, ivl, flags, data = col.db.first("SELECT type, queue, due, ivl, flags, data FROM cards WHERE id = ?", cid)
            revlog = col.db.list("SELECT id FROM revlog WHERE cid = ? ORDER BY id", cid)
            eases = col.db.list("SELECT ease FROM revlog WHERE cid = ? ORDER BY id", cid)
            fields = col.get_note(nids[i]).fields
            expect["cards"].append({"note": i, "nid": nids[i], "note_type": STOCK_NOTES[i][1], "ord": o,
                                    "front": STOCK_NOTES[i][2][0], "type": ctype, "queue": queue,
                                    "due": due, "ivl": ivl, "flags": flags, "data": data, "revlog": revlog,
                                    "eases": eases, "fields": fields})
        with open(os.path.join(out, "stock.json"), "w") as f:
            json.dump(expect, f, indent=1, ensure_ascii=False)
            f.write("\n")
        col.close()


def no_history(out):
    """Cards with a schedule and no review history (see the module doc)."""
    import json
    from unittest import mock
    from anki.collection import Collection, ExportAnkiPackageOptions
    from anki.scheduler_pb2 import CardAnswer  # noqa: F401 (the answers below)

    with tempfile.TemporaryDirectory() as d:
        col = Collection(os.path.join(d, "collection.anki2"))
        col.set_config("fsrs", True)
        col.db.execute("UPDATE col SET crt = ?", T0 // 1000 - 4 * 3600)
        deck = col.decks.id("Scheduled")
        fronts = [
            ("Wavelength of red light", "about 700 nm"),
            ("Speed of sound in air", "about 343 m/s"),
            ("Charge of the electron", "1.602 × 10⁻¹⁹ C"),
            ("Boltzmann constant", "1.381 × 10⁻²³ J/K"),
            ("Avogadro constant", "6.022 × 10²³ /mol"),
        ]
        nids = []
        for front, back in fronts:
            note = col.new_note(col.models.by_name("Basic"))
            note.fields[0], note.fields[1] = front, back
            col.add_note(note, deck)
            nids.append(note.id)
        cid = {i: col.db.scalar("SELECT id FROM cards WHERE nid = ?", nid) for i, nid in enumerate(nids)}
        # 0: a review card; 1: a review card lapsed into relearning;
        # 2: a learning card; 3: new; 4: a review card that keeps its history.
        plan = {0: [(0, 3), (3, 3), (12, 3)], 1: [(0, 3), (4, 3), (15, 1)], 2: [(20, 3)], 4: [(0, 3), (5, 4)]}
        answers = sorted((T0 + int(days * DAY) + i * 60_000, i, ease) for i, rows in plan.items() for days, ease in rows)
        for at, i, ease in answers:
            with mock.patch("time.time", return_value=at / 1000):
                card = col.get_card(cid[i])
                card.start_timer()
                states = col._backend.get_scheduling_states(card.id)
                answer = col.sched.build_answer(card=card, states=states, rating={1: 0, 2: 1, 3: 2, 4: 3}[ease])
                answer.answered_at_millis = at
                answer.milliseconds_taken = 4000
                col.sched.answer_card(answer)
        col.db.execute("DELETE FROM revlog WHERE cid IN (?, ?, ?)", cid[0], cid[1], cid[2])
        path = os.path.join(out, "no-history.apkg")
        col.export_anki_package(
            out_path=path,
            options=ExportAnkiPackageOptions(with_scheduling=True, with_deck_configs=True, with_media=False, legacy=False),
            limit=None,
        )
        crt = col.db.scalar("SELECT crt FROM col")
        expect = {"crt": crt, "cards": []}
        for i, nid in enumerate(nids):
            ctype, queue, due, ivl, data = col.db.first("SELECT type, queue, due, ivl, data FROM cards WHERE id = ?", cid[i])
            revlog = col.db.list("SELECT id FROM revlog WHERE cid = ? ORDER BY id", cid[i])
            expect["cards"].append({"nid": nid, "front": fronts[i][0], "type": ctype, "queue": queue,
                                    "due": due, "ivl": ivl, "data": data, "revlog": revlog})
        with open(os.path.join(out, "no-history.json"), "w") as f:
            json.dump(expect, f, indent=1, ensure_ascii=False)
            f.write("\n")
        col.close()


if __name__ == "__main__":
    os.makedirs(OUT, exist_ok=True)
    if sys.argv[2:] == ["stock"]:
        stock(OUT)
        sys.exit(0)
    if sys.argv[2:] == ["no-history"]:
        no_history(OUT)
        sys.exit(0)
    legacy(OUT)
    modern(OUT)
    broken(OUT)
    stock(OUT)
    no_history(OUT)
