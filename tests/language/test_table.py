"""The word tables (spcotmhp.language.table): the English table's phrases are read without the dropped g's
dictionary check, which must leave every one of their units as it is (else a sentence's "goin" and the table's
"going" would not meet), and reading a table loads no dictionary."""

from __future__ import annotations

import subprocess
import sys

from spcotmhp.language.table import _g_restored, en_units, word_table


def test_every_english_table_unit_is_its_own_dropped_g_reading():
    table = word_table("en")
    phrases = {p for items in table.surfaces.values() for p in items} | set(table.fillers)
    phrases |= {p for others in table.synonyms.values() for p in others}  # the other names of placewords
    units = {u for p in phrases for u in en_units(p, restore_g=False)}
    assert len(units) > 500  # the whole table, not an empty one
    changed = {u: _g_restored(u) for u in units if _g_restored(u) != u}
    assert not changed, changed
    assert all(en_units(p) == en_units(p, restore_g=False) for p in phrases)


def test_a_sentence_still_has_its_dropped_g_put_back():
    assert en_units("goin to the sittin room", restore_g=True) == ["going", "to", "the", "sitting", "room"]
    assert en_units("the cabin") == ["the", "cabin"]  # a word of its own stays


def test_reading_the_tables_loads_no_dictionary():
    code = (
        "import sys\nfrom spcotmhp.language.table import word_table\n"
        "word_table('en'); word_table('ja')\nprint('lemminflect' in sys.modules)"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True, timeout=120)
    assert out.stdout.strip() == "False"


def test_the_northern_reduced_article_is_the():
    assert en_units("go through to t'kitchen") == ["go", "through", "to", "the", "kitchen"]
    assert en_units("t'other room") == ["the", "other", "room"]
    assert en_units("don't can't i'm t'") == ["don't", "can't", "i'm", "t"]  # no word after it: as before


def test_a_class_phrase_written_as_a_text_word_must_be_written_out_in_its_class():
    """ "goto" in GO is written out as "go to", which would make "go to" one GO token: refused with a clear message;
    "thru" beside "through" in one class is fine."""
    import json

    import pytest

    from spcotmhp.language.table import read_table

    with pytest.raises(ValueError, match="'goto' in GO is written out as 'go to'"):
        read_table(json.dumps({"lang": "en", "classes": {"GO": ["go", "goto"], "TO": ["to"]}}), "test.json")
    read_table(json.dumps({"lang": "en", "classes": {"VIA": ["through", "thru"]}}), "test.json")
