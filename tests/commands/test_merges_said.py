"""Merges said out loud (issue 35, item 5): a taught name without a place of its own appears in ``learn``'s
summary, ``show`` (text and JSON), ``GET /places`` (as ``ServedModel.places``) and as the first question; and
``learn`` splits it where a wall separates the two names' teaching points (``--no-split``: the paper's places)."""

from __future__ import annotations

import json

import pytest
from typer.testing import CliRunner

from spcotmhp.cli import app
from spcotmhp.datasets.synthetic import write_dataset
from spcotmhp.persistence.io import load_model, save_model
from spcotmhp.server.registry import ServedModel
from spcotmhp.teaching.questions import questions
from tests.helpers.merged_rooms import merged_fit, two_names

SENTENCE = "playroom and bedroom share place 0; taught 5 and 5 times, 3.0 m apart"


@pytest.fixture(scope="module")
def merged_dir(tmp_path_factory):
    """One open room taught "bedroom" and "playroom" 5 times each, 3 m apart, learned as one place."""
    return save_model(merged_fit(two_names("none")).model_, tmp_path_factory.mktemp("merged") / "model")


def test_show_says_the_merge(merged_dir):
    out = CliRunner().invoke(app, ["show", str(merged_dir)])
    assert out.exit_code == 0, out.output
    assert f"merged: {SENTENCE}" in out.output.splitlines()
    shown = json.loads(CliRunner().invoke(app, ["show", str(merged_dir), "--json"]).output)
    (m,) = shown["merges"]
    assert (m["name"], m["other"], m["place"], m["taught"], m["other_taught"]) == ("playroom", "bedroom", 0, 5, 5)
    assert m["sentence"] == SENTENCE


def test_places_carry_the_merge(merged_dir):
    served = ServedModel.build("home", load_model(merged_dir), "(test)")
    assert [m["sentence"] for m in served.places()["merges"]] == [SENTENCE]


def test_the_first_question_is_the_merge(merged_dir):
    model = load_model(merged_dir)
    first = questions(model)[0]
    assert first["candidates"] == ["playroom", "bedroom"]
    assert SENTENCE in first["why"]
    assert abs(first["x"] - 4.5) < 0.6 and abs(first["y"] - 2.0) < 0.6  # at a playroom teaching point
    out = CliRunner().invoke(app, ["questions", str(merged_dir)])
    assert out.exit_code == 0 and SENTENCE in out.output.splitlines()[0]


@pytest.fixture(scope="module")
def close_rooms(tmp_path_factory):
    """Two rooms whose teaching points are 1.7 m apart across a wall: the default learner keeps them as one
    place (measured: every seed tried)."""
    data = two_names("wall", centres=((2.2, 2.0), (3.9, 2.0)))
    return write_dataset(data, tmp_path_factory.mktemp("close") / "rooms")


def test_learn_splits_where_the_wall_says_two(close_rooms, tmp_path):
    runner = CliRunner()
    paper = runner.invoke(app, ["learn", str(close_rooms), "--out", str(tmp_path / "paper"), "--no-split"])
    assert paper.exit_code == 0, paper.output
    merged = [line for line in paper.output.splitlines() if line.startswith("merged: ")]
    assert len(merged) == 1 and "taught 5 and 5 times, 1.7 m apart" in merged[0]
    assert "taught_split" not in load_model(tmp_path / "paper").info
    split = runner.invoke(app, ["learn", str(close_rooms), "--out", str(tmp_path / "split")])
    assert split.exit_code == 0, split.output
    lines = split.output.splitlines()
    assert any(line.startswith("split: ") and "a wall between" in line for line in lines), split.output
    assert not any(line.startswith("merged: ") for line in lines)
    model = load_model(tmp_path / "split")
    assert int(model.active_places.sum()) == 2 and len(model.info["taught_split"]["splits"]) == 1


def test_teach_says_the_merge_it_leaves(merged_dir, tmp_path):
    import shutil

    folder = shutil.copytree(merged_dir, tmp_path / "model")
    out = CliRunner().invoke(app, ["teach", str(folder), "this is the bedroom", "--at", "1.5", "2.0"])
    assert out.exit_code == 0, out.output
    assert (
        out.output.splitlines()[-1] == "merged: playroom and bedroom share place 0; taught 5 and 6 times, 3.0 m apart"
    )
