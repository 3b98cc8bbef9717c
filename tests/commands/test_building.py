"""The CLI on buildings: ``learn BUILDING_DIR --out M`` writes a building model (supervised and Gibbs); ``plan M
TEXT --start X Y --floor F`` plans across floors (text, ``--json`` with segments, one ``--png`` per floor); errors
are one line."""

from __future__ import annotations

import json
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


@pytest.fixture(scope="module")
def model_dir(tmp_path_factory):
    out = tmp_path_factory.mktemp("bm") / "m"
    res = CliRunner().invoke(app, ["learn", str(example_path()), "--out", str(out), "--supervised"])
    assert res.exit_code == 0, res.output
    return out


def test_plan_across_floors(model_dir, tmp_path):
    bm = load_building_model(model_dir)
    stairs = next(c for c in bm.spec.connectors if c.kind == "stairs")
    start = [str(stairs.stops[0].x + 0.5), str(stairs.stops[0].y)]
    args = ["plan", str(model_dir), '{"goal": {"words": "bedroom", "floor": 2}}', "--start", *start]
    res = CliRunner().invoke(app, [*args, "--floor", "ground", "--json", "--png", str(tmp_path / "r.png")])
    assert res.exit_code == 0, res.output
    d = json.loads(res.stdout)
    assert [s["floor"] for s in d["segments"]] == [1, 2]
    goal = d["places"][-1]
    assert d["goal_floor"] == goal["floor"] == 2 and goal["role"] == "goal" and "bedroom" in goal["label"]
    assert d["floor"] == 1 and d["path"] == d["segments"][0]["path"]
    assert d["segments"][0]["path"][0] == pytest.approx([float(v) for v in start], abs=0.05)
    ride = d["rides"][0]
    assert d["segments"][1]["path"][0] == pytest.approx([ride["to"]["x"], ride["to"]["y"]], abs=0.05)
    assert d["route_m"] == pytest.approx(d["length_m"] + ride["cost_m"], abs=1e-3)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["r-floor1.png", "r-floor2.png"]
    text = CliRunner().invoke(app, [*args, "--floor", "1"])
    assert text.exit_code == 0 and "to floor 2 (first)" in text.stdout and "bedroom" in text.stdout


@pytest.mark.parametrize(
    ("extra", "message"),
    [
        ([], "error: Invalid value: a building's model needs --floor F"),
        (["--floor", "9"], "error: the building has no floor '9'; its floors: 1 (ground), 2 (first)"),
    ],
)
def test_plan_errors_are_one_line(model_dir, extra, message):
    done = subprocess.run([SPCOTMHP, "plan", str(model_dir), "go to the bedroom", "--start", "3", "5", *extra],
                          capture_output=True, text=True, timeout=120)  # fmt: skip
    assert done.returncode == 2 and done.stderr.startswith(message) and done.stderr.count("\n") == 1, done.stderr


def test_floor_needs_a_building_model(tmp_path):
    from spcotmhp.datasets.bundled import bundled_path

    done = subprocess.run([SPCOTMHP, "plan", str(bundled_path("3LDK_01")), "go to the bedroom", "--start", "0", "0",
                           "--floor", "2"], capture_output=True, text=True, timeout=120)  # fmt: skip
    assert done.returncode == 2 and "--floor is for a building's model" in done.stderr
