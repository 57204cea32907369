#!/usr/bin/env python3
"""Imports an Anki package into a fresh collection with Anki's own library
and prints what it holds as JSON: every note (guid, note type, fields,
tags) and card (ord, type, queue, due, interval, revlog ids and eases), the
collection's day number (`today`) and the end of today (`cutoff`, seconds).
Used by `tests/anki_import.rs` to check `flipcard export --apkg`.

    python3 roundtrip.py PACKAGE.apkg
"""

import json
import os
import sys
import tempfile

from anki.collection import Collection, ImportAnkiPackageOptions, ImportAnkiPackageRequest


def main(path):
    with tempfile.TemporaryDirectory() as d:
        col = Collection(os.path.join(d, "collection.anki2"))
        col.import_anki_package(
            ImportAnkiPackageRequest(
                package_path=os.path.abspath(path),
                options=ImportAnkiPackageOptions(with_scheduling=True, with_deck_configs=True),
            )
        )
        notes = []
        for nid in col.db.list("SELECT id FROM notes ORDER BY id"):
            note = col.get_note(nid)
            cards = []
            for card in note.cards():
                revlog = col.db.all("SELECT id, ease FROM revlog WHERE cid = ? ORDER BY id", card.id)
                cards.append({
                    "ord": card.ord, "type": card.type, "queue": card.queue, "due": card.due,
                    "ivl": card.ivl, "deck": col.decks.name(card.did),
                    "revlog": [r[0] for r in revlog], "eases": [r[1] for r in revlog],
                })
            notes.append({
                "guid": note.guid, "note_type": note.note_type()["name"], "fields": list(note.fields),
                "tags": list(note.tags), "cards": cards,
            })
        out = {"today": col.sched.today, "cutoff": col.sched.day_cutoff, "notes": notes}
        col.close()
    json.dump(out, sys.stdout, ensure_ascii=False)


if __name__ == "__main__":
    main(sys.argv[1])
