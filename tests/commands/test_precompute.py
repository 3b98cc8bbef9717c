"""`spcotmhp precompute MODEL` and the planning graph in `plan` and `learn` (issue 35, item 4), end to end."""

from __future__ import annotations

import subprocess
import sys
import warnings
from pathlib import Path

import pytest

from spcotmhp.datasets.bundled import load_bundled
from spcotmhp.learning.supervised import fit_supervised
from spcotmhp.persistence.io import save_model

EXE = str(Path(sys.executable).with_name("spcotmhp"))


def run(*args: str) -> subprocess.CompletedProcess:
    return subprocess.run([EXE, *args], capture_output=True, text=True, timeout=300, check=False)


@pytest.fixture(scope="module")
def bare(tmp_path_factory) -> tuple[Path, list[str]]:
    """A model folder saved without a planning graph (as before issue 35), and a start in the kitchen."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        dataset = load_bundled("3LDK_06")
        model = fit_supervised(dataset)
    folder = save_model(model, tmp_path_factory.mktemp("pre") / "model")
    kitchen = model.mu[dataset.place_names.index("kitchen")]
    return folder, [f"{v:.3f}" for v in kitchen]


def test_plan_without_a_saved_graph_builds_it_says_so_and_writes_nothing(bare):
    folder, (x, y) = bare
    before = sorted(p.name for p in folder.iterdir())
    out = run("plan", str(folder), "go to the bedroom", "--start", x, y)
    assert out.returncode == 0, out.stderr
    assert "planning graph built" in out.stderr and f"spcotmhp precompute {folder}" in out.stderr
    assert sorted(p.name for p in folder.iterdir()) == before


def test_precompute_saves_then_plan_loads(bare, tmp_path):
    folder, (x, y) = bare
    copy = tmp_path / "m"
    copy.mkdir()
    for f in folder.iterdir():
        (copy / f.name).write_bytes(f.read_bytes())
    out = run("precompute", str(copy))
    assert out.returncode == 0, out.stderr
    assert "saved (graph.json, graph.npz)" in out.stdout
    assert "up to date" in run("precompute", str(copy)).stdout
    planned = run("plan", str(copy), "go to the bedroom", "--start", x, y)
    assert planned.returncode == 0, planned.stderr
    assert "loaded from the model folder in" in planned.stderr and "planning graph built" not in planned.stderr
    other = run("precompute", str(copy), "--candidates", "2")  # a graph of other settings replaces it only when told
    assert other.returncode != 0 and "--overwrite" in other.stderr and "Traceback" not in other.stderr
    assert run("precompute", str(copy), "--candidates", "2", "--overwrite").returncode == 0
    stale = run("plan", str(copy), "go to the bedroom", "--start", x, y)  # default settings: not the saved ones
    assert "planning graph rebuilt" in stale.stderr and "other graph settings" in stale.stderr


def test_learn_saves_the_graph_unless_told_not_to(tmp_path):
    out = run("learn", "3LDK_06", "--supervised", "--out", str(tmp_path / "with"))
    assert out.returncode == 0, out.stderr
    assert "planning graph precomputed" in out.stdout and (tmp_path / "with" / "graph.npz").is_file()
    out = run("learn", "3LDK_06", "--supervised", "--no-precompute", "--out", str(tmp_path / "without"))
    assert out.returncode == 0, out.stderr
    assert not (tmp_path / "without" / "graph.npz").exists()
