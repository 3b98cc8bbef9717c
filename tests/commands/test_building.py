"""The CLI on buildings: ``learn BUILDING_DIR --out M`` writes a building model (supervised and Gibbs); errors are
one line."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest
from typer.testing import CliRunner

from spcotmhp.building.io import load_building_model
from spcotmhp.building.synthetic import example_path
from spcotmhp.cli import app

SPCOTMHP = str(Path(sys.executable).with_name("spcotmhp"))


@pytest.mark.parametrize("args", [["--supervised"], ["--runs", "1", "--iterations", "5"]])
def test_learn_a_building(tmp_path, args):
    out = tmp_path / "m"
    res = CliRunner().invoke(app, ["learn", str(example_path()), "--out", str(out), *args])
    assert res.exit_code == 0, res.output
    assert "building building-2f: places per floor: 1 (ground)" in res.output
    bm = load_building_model(out)
    assert bm.indices == [1, 2] and all(bm.floor_places(f).any() for f in bm.indices)
    if "--supervised" in args:
        assert [int(bm.floor_places(f).sum()) for f in bm.indices] == [6, 6]
    else:
        assert bm.model.K == 40  # 20 places a floor


def test_learn_errors_are_one_line(tmp_path):
    bad = tmp_path / "b"
    bad.mkdir()
    (bad / "building.yaml").write_text("floors: [{index: 1, name: g, dataset: none}]\n")
    done = subprocess.run([SPCOTMHP, "learn", str(bad), "--out", str(tmp_path / "m")], capture_output=True,
                          text=True, timeout=120)  # fmt: skip
    assert done.returncode == 2
    assert done.stderr.startswith("error: floor 1 (g, none): dataset folder") and done.stderr.count("\n") == 1
