"""The grammar tables: package data read once, checked field by field, the same words the parser always had."""

from __future__ import annotations

import dataclasses
import fnmatch
import json
import tomllib
from importlib import resources
from pathlib import Path

import pytest

from spcotmhp.errors import InstructionError
from spcotmhp.planning.grammar import ENGLISH, GRAMMARS, JAPANESE, ROLES, grammar_from_json

ROOT = Path(__file__).resolve().parents[2]


def table(lang: str) -> dict:
    return json.loads((resources.files("spcotmhp.planning") / "grammars" / f"{lang}.json").read_text("utf-8"))


def test_every_language_file_is_loaded_once_and_read_only():
    assert sorted(GRAMMARS) == ["en", "ja"] and GRAMMARS["en"] is ENGLISH and GRAMMARS["ja"] is JAPANESE
    with pytest.raises(TypeError):
        GRAMMARS["xx"] = ENGLISH  # type: ignore[index]


def test_tables_hold_the_words_the_parser_relies_on():
    assert ENGLISH.markers["via"] == "waypoint" and ENGLISH.markers["avoiding"] == "avoid"
    assert ENGLISH.markers["instead of"] == "not_goal" and ENGLISH.order["finally"] == "last"
    assert JAPANESE.markers["を通って"] == "waypoint" and JAPANESE.markers["を避けて"] == "avoid"
    assert JAPANESE.between_places == {"の": "join", "か": "alternative"} and JAPANESE.by_character
    assert ENGLISH.attach == "prefix" and JAPANESE.attach == "postfix"
    assert "then" in ENGLISH.sequencers and "and" in ENGLISH.connectors
    assert set(ENGLISH.markers.values()) <= set(ROLES)


def test_a_table_round_trips_through_json():
    for lang, grammar in GRAMMARS.items():
        assert dataclasses.asdict(grammar_from_json(json.dumps(table(lang)))) == dataclasses.asdict(grammar)


def test_grammar_files_are_package_data():
    patterns = tomllib.loads((ROOT / "pyproject.toml").read_text())["tool"]["setuptools"]["package-data"]["spcotmhp"]
    for lang in GRAMMARS:
        assert any(fnmatch.fnmatch(f"planning/grammars/{lang}.json", p) for p in patterns)


@pytest.mark.parametrize(
    ("change", "message"),
    [
        (lambda t: "{", "not JSON"),
        (lambda t: json.dumps([1, 2]), "must be a JSON object"),
        (lambda t: json.dumps({**t, "colour": "red"}), r"unknown field\(s\) \['colour'\]"),
        (lambda t: json.dumps({k: v for k, v in t.items() if k != "markers"}), r"missing field\(s\) \['markers'\]"),
        (lambda t: json.dumps({**t, "markers": {"teleport": ["beam me to"]}}), r"unknown kind\(s\) \['teleport'\]"),
        (lambda t: json.dumps({**t, "connectors": "and"}), "connectors must be a list of phrases"),
        (lambda t: json.dumps({**t, "fillers": ["please", ""]}), "fillers must be a non-empty string"),
        (lambda t: json.dumps({**t, "attach": "infix"}), "attach must be 'prefix' or 'postfix'"),
        (lambda t: json.dumps({**t, "by_character": "yes"}), "by_character must be true or false"),
        (lambda t: json.dumps({**t, "hiragana_places": 1}), "hiragana_places must be true or false"),
        (lambda t: json.dumps({**t, "between_places": ["の"]}), "between_places must be an object"),
    ],
)
def test_a_malformed_table_is_refused_in_one_line(change, message):
    with pytest.raises(InstructionError, match=message) as err:
        grammar_from_json(change(table("en")), "grammars/en.json")
    assert "\n" not in str(err.value) and str(err.value).startswith("grammars/en.json")
