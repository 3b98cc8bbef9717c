"""Commands that write refuse to overwrite what they did not create (without --overwrite) and never write onto
their own inputs: each data-loss case of issue 10 is a one-line error with exit status 2, inputs unchanged."""

from __future__ import annotations

import hashlib
import shutil
import warnings
from pathlib import Path

import pytest
from typer.testing import CliRunner

from spcotmhp.cli import app
from spcotmhp.datasets.synthetic import generate_environment, write_dataset
from spcotmhp.learning.supervised import fit_supervised
from spcotmhp.persistence.io import save_model

pytestmark = pytest.mark.filterwarnings("ignore")


def _digest(folder: Path) -> dict[str, str]:
    return {p.name: hashlib.sha256(p.read_bytes()).hexdigest() for p in sorted(folder.iterdir()) if p.is_file()}


def _cli(*args: object):
    return CliRunner().invoke(app, [str(a) for a in args])


def _error_line(result) -> str:
    """The one line main() would print: CliRunner sees the SpcotmhpError itself."""
    from spcotmhp.errors import SpcotmhpError

    assert isinstance(result.exception, SpcotmhpError), result.output
    text = f"error: {result.exception}"
    assert "\n" not in text
    return text


@pytest.fixture(scope="module")
def dataset(tmp_path_factory):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return write_dataset(generate_environment("flat", seed=4, n_rooms=4), tmp_path_factory.mktemp("d") / "data")


@pytest.fixture(scope="module")
def model(dataset, tmp_path_factory):
    from spcotmhp.datasets import load_dataset

    return save_model(fit_supervised(load_dataset(dataset)), tmp_path_factory.mktemp("m") / "model")


def test_learn_refuses_the_dataset_folder_and_an_existing_model(dataset, model, tmp_path):
    before = _digest(dataset)
    line = _error_line(_cli("learn", dataset, "--out", dataset, "--supervised"))
    assert "is the dataset folder" in line and _digest(dataset) == before
    target = tmp_path / "m"
    shutil.copytree(model, target)
    kept = _digest(target)
    line = _error_line(_cli("learn", dataset, "--out", target, "--supervised"))
    assert "already holds a model; give --overwrite" in line and _digest(target) == kept
    assert _cli("learn", dataset, "--out", target, "--supervised", "--overwrite").exit_code == 0
    other = tmp_path / "notes"
    other.mkdir()
    (other / "todo.txt").write_text("mine")
    line = _error_line(_cli("learn", dataset, "--out", other, "--supervised", "--overwrite"))
    assert "holds files that are not a model's (todo.txt)" in line and (other / "todo.txt").read_text() == "mine"


def test_costmap_refuses_its_own_map_and_existing_files(dataset, tmp_path):
    before = _digest(dataset)
    for out in (dataset / "map.yaml", dataset / "map.pgm"):
        line = _error_line(_cli("costmap", dataset / "map.yaml", "--out", out))
        assert "is one of this command's inputs" in line
    assert _digest(dataset) == before
    out = tmp_path / "cm.csv"
    out.write_text("keep")
    line = _error_line(_cli("costmap", dataset / "map.yaml", "--out", out))
    assert "exists; give --overwrite" in line and out.read_text() == "keep"
    assert _cli("costmap", dataset / "map.yaml", "--out", out, "--overwrite").exit_code == 0
    assert out.read_text() != "keep"


def test_plan_png_never_onto_the_model(model, tmp_path):
    from spcotmhp.persistence.io import load_model

    m = load_model(model)
    x, y = (float(v) for v in m.mu[int(m.active_places.argmax())])
    before = _digest(model)
    for name in ("model.json", "arrays.npz", "map.pgm"):
        result = _cli("plan", model, "go to the kitchen", "--start", x, y, "--png", model / name, "--overwrite")
        assert "is one of this command's inputs" in _error_line(result)
    assert _digest(model) == before
    png = tmp_path / "p.png"
    png.write_bytes(b"old")
    assert "exists; give --overwrite" in _error_line(
        _cli("plan", model, "go to the kitchen", "--start", x, y, "--png", png)
    )
    assert png.read_bytes() == b"old"


def test_no_output_inside_the_model_folder(model, tmp_path):
    """A PNG, a Nav2 export or a demo written into a model folder made the next `teach` refuse it (audit 2)."""
    from spcotmhp.persistence.io import load_model

    m = load_model(model)
    x, y = (float(v) for v in m.mu[int(m.active_places.argmax())])
    before = _digest(model)
    runs = [
        ("plan", model, "go to the kitchen", "--start", x, y, "--png", model / "plan.png"),
        ("show", model, "--png", model / "map.png"),
        ("export-nav2", model, "--out", model / "nav2"),
        ("demo", "--out", model, "--supervised"),
        ("demo", "--out", model / "demo", "--supervised"),
    ]
    for args in runs:
        assert "the model folder" in _error_line(_cli(*args)), args
    assert _digest(model) == before and sorted(p.name for p in model.iterdir()) == sorted(before)


def test_synth_over_a_dataset_needs_overwrite_and_leaves_nothing_stale(dataset, tmp_path):
    target = tmp_path / "d"
    shutil.copytree(dataset, target)
    (target / "costmap_ros.csv").write_text("0\n")
    before = _digest(target)
    line = _error_line(_cli("synth", "flat", "--rooms", "3", "--out", target))
    assert "already holds a dataset; give --overwrite" in line and _digest(target) == before
    assert _cli("synth", "flat", "--rooms", "3", "--out", target, "--overwrite").exit_code == 0
    assert not (target / "costmap_ros.csv").exists()
    assert _cli("check-dataset", target).exit_code == 0


def test_costmap_refuses_absurd_settings_in_one_line(dataset, tmp_path):
    result = _cli("costmap", dataset / "map.yaml", "--inflation-radius", "1e308", "--out", tmp_path / "x.csv")
    assert _error_line(result) == "error: cost map setting inflation_radius must be at most 1e+12, got 1e+308"
    assert not (tmp_path / "x.csv").exists()


def test_every_overwrite_option_is_one_flag():
    """`import-bag` alone offered `--overwrite / --no-overwrite` (second audit): one spelling everywhere."""
    import typer.main

    group = typer.main.get_command(app)
    spelled = {
        name: sorted(p.opts + p.secondary_opts)
        for name, command in group.commands.items()
        for p in command.params
        if p.name == "overwrite"
    }
    assert "import-bag" in spelled and {name: ["--overwrite"] for name in spelled} == spelled
