"""The robot-body options on the commands: learn stores the body with the model (an old folder without one loads as
the default body), plan re-plans for another body from the stored map, a costmap_ros.csv is used when it is the
body's cost map and refused when it is not, and every bad value is one line."""

from __future__ import annotations

import json
import re
import shutil
import subprocess
import sys
from pathlib import Path

import pytest
from typer.testing import CliRunner

from spcotmhp.cli import app
from spcotmhp.datasets.bundled import bundled_path
from spcotmhp.metric.costmap import default_costmap
from spcotmhp.persistence.io import load_model
from tests.metric.test_body import nav2_file

pytestmark = pytest.mark.filterwarnings("ignore:.*known warning")


EXE = Path(sys.executable).with_name("spcotmhp")


def run(*args: str):
    return CliRunner().invoke(app, list(args))


def cli(*args: str) -> subprocess.CompletedProcess:
    """The command as a user runs it (errors as one ``error: ...`` line on stderr, exit status 2)."""
    return subprocess.run([str(EXE), *args], capture_output=True, text=True, timeout=300, check=False)


@pytest.fixture(scope="module")
def home(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """A copy of the bundled 3LDK_01 (its costmap_ros.csv is the default body's)."""
    folder = tmp_path_factory.mktemp("home") / "3LDK_01"
    shutil.copytree(bundled_path("3LDK_01"), folder)
    return folder


def test_learn_stores_the_body_and_plan_replans_for_another(home: Path, tmp_path: Path) -> None:
    bare = tmp_path / "bare"
    shutil.copytree(home, bare)
    (bare / "costmap_ros.csv").unlink()  # made for the default body: a 0.30 m robot is learned without it
    out = tmp_path / "m30"
    res = run("learn", str(bare), "--supervised", "--out", str(out), "--nav2-params", str(nav2_file(tmp_path)))
    assert res.exit_code == 0, res.output
    assert (
        "body: a 16-point footprint (inscribed 0.304 m, circumscribed 0.314 m), inflation 0.55 m, scaling 3"
        in res.output
    )
    model = load_model(out)
    assert model.costmap["inscribed_radius"] == pytest.approx(0.30398, abs=1e-4)
    assert model.costmap["circumscribed_radius"] == pytest.approx(0.31414, abs=1e-4)
    assert model.info["body"]["source"].endswith("nav2_params.yaml (global_costmap)")
    assert len(model.info["body"]["footprint"]) == 16
    plan = run("plan", str(out), "go to the kitchen", "--start", "0", "0", "--json")
    assert plan.exit_code == 0, plan.output
    other = run("plan", str(out), "go to the kitchen", "--start", "0", "0", "--json", "--robot-radius", "0.22")
    assert other.exit_code == 0, other.output
    assert json.loads(plan.stdout.splitlines()[0])["path"] != json.loads(other.stdout.splitlines()[0])["path"]
    assert load_model(out).costmap == model.costmap  # planning for another body leaves the stored one


def test_an_old_folder_without_a_body_is_the_default(home: Path, tmp_path: Path) -> None:
    out = tmp_path / "m"
    assert run("learn", str(home), "--supervised", "--out", str(out)).exit_code == 0  # the csv is the default's
    meta = json.loads((out / "model.json").read_text())
    assert meta["costmap"] == default_costmap() and "body" not in meta["info"]
    assert load_model(out).costmap == {"inscribed_radius": 0.22, "inflation_radius": 1.0, "cost_scaling_factor": 10.0}


def test_a_recorded_costmap_for_another_robot_is_refused(home: Path, tmp_path: Path) -> None:
    res = cli("learn", str(home), "--supervised", "--out", str(tmp_path / "m"), "--robot-radius", "0.3")
    assert res.returncode == 2 and "Traceback" not in res.stderr
    line = res.stderr.strip().splitlines()[-1]
    assert line.startswith("error: ") and "costmap_ros.csv differs from the cost map of a 0.3 m circle" in line
    assert "0 cells it marks inscribed or lethal (99-100) are free for that body" in line
    assert "remove costmap_ros.csv" in line
    assert not (tmp_path / "m").exists()
    check = run("check-dataset", str(home))
    assert "the default body's cost map (a 0.22 m circle), used by learn" in check.output


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["--robot-radius", "-1"], r"the robot radius must be a number in \(0, 100\] m"),
        (["--footprint", "[[1, 2]]"], "the footprint has 1 points"),
        (["--nav2-params", "missing.yaml"], "missing.yaml"),
        (["--robot-radius", "0.3", "--inflation-radius", "0.1"], "inflation_radius 0.1 m is below"),
    ],
)
def test_bad_bodies_are_one_line(args: list[str], message: str, tmp_path: Path, home: Path) -> None:
    res = cli("plan", str(tmp_path / "nowhere"), "go to the kitchen", "--start", "0", "0", *args)
    assert res.returncode == 2
    lines = res.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("error: "), res.stderr
    assert re.search(message, lines[0])


@pytest.fixture(scope="module")
def model_dir(home: Path, tmp_path_factory: pytest.TempPathFactory) -> Path:
    out = tmp_path_factory.mktemp("model") / "m"
    assert run("learn", str(home), "--supervised", "--out", str(out)).exit_code == 0
    return out


@pytest.mark.parametrize("command", ["plan", "serve", "ros2"])
def test_every_planning_command_refuses_a_bad_body_in_one_line(command: str, model_dir: Path) -> None:
    args = {
        "plan": [str(model_dir), "go to the kitchen", "--start", "0", "0"],
        "serve": [str(model_dir), "--port", "0"],
    }
    res = cli(command, *args.get(command, [str(model_dir)]), "--footprint", "[[0.3, 0.2], [0.3, -0.2]]")
    if command == "ros2" and "extra" in res.stderr and "ros2" in res.stderr and "install" in res.stderr:
        pytest.skip("rclpy is not installed")
    assert res.returncode == 2
    lines = res.stderr.strip().splitlines()
    assert lines[-1] == (
        "error: --footprint: the footprint has 2 points; it must have 3 to 1000 (a list of at least 3 [x, y] points "
        'in metres, e.g. "[[0.3, 0.2], [0.3, -0.2], [-0.3, -0.2], [-0.3, 0.2]]")'
    )
    assert "Traceback" not in res.stderr


def test_costmap_from_nav2_params(tmp_path: Path) -> None:
    from spcotmhp.metric.costmap import inflate
    from spcotmhp.metric.map_io import load_map
    from spcotmhp.metric.nav2_params import resolve_body

    params = nav2_file(tmp_path)
    yaml_path = bundled_path("3LDK_05") / "map.yaml"
    res = run("costmap", str(yaml_path), "--nav2-params", str(params), "--out", str(tmp_path / "c.csv"))
    assert res.exit_code == 0, res.output
    body = resolve_body(params)
    assert body is not None
    want = inflate(load_map(yaml_path), **body.costmap()).to_occupancy_grid()
    got = [[int(v) for v in line.split(",")] for line in (tmp_path / "c.csv").read_text().splitlines()]
    assert got == want.tolist()
