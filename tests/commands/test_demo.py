"""The demo (`spcotmhp demo`) and `spcotmhp show` on the bundled 3LDK_06 home."""

from __future__ import annotations

import dataclasses
import json
import os
import re
import signal
import socket
import subprocess
import sys
import time
import warnings

import numpy as np
import pytest
from PIL import Image
from typer.testing import CliRunner

from spcotmhp.cli import app
from spcotmhp.commands.demo import _progress, demo_start, learn_demo_model, next_command, serve_port
from spcotmhp.datasets import load_bundled
from spcotmhp.errors import InstructionError
from spcotmhp.learning.supervised import fit_supervised
from spcotmhp.persistence.io import save_model
from spcotmhp.planning.planner import HierarchicalPlanner

SPCOTMHP = [sys.executable, "-m", "spcotmhp.cli"]


@pytest.fixture(scope="module")
def home():
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return load_bundled("3LDK_06", lang="en")


@pytest.fixture(scope="module")
def demo_run(tmp_path_factory):
    out = tmp_path_factory.mktemp("demo") / "out"
    result = CliRunner().invoke(app, ["demo", "--out", str(out)])
    assert result.exit_code == 0, result.output
    return out, result.output


def test_demo_learns_without_supervision_and_plans_via_the_corridor(demo_run):
    out, text = demo_run
    assert "model:       unsupervised SpCoTMHP (Gibbs sampling, 10 runs x 100 sweeps, seed 0" in text
    assert "all 9 place names of the home" in text
    line = next(x for x in text.splitlines() if x.startswith("plan:"))
    assert line.startswith("plan:        entrance -> corridor (waypoint) -> ")
    assert "bedroom #" in line.split("(waypoint)")[1] and "(closest of 3 bedrooms)" in line
    plan = json.loads((out / "plan.json").read_text())
    roles = [(p["role"], p["name"]) for p in plan["places"]]
    assert roles[0] == ("start", "entrance") and ("waypoint", "corridor") in roles and roles[-1][0] == "goal"
    assert roles[-1][1] == "bedroom"
    assert plan["explanation"] in line
    assert len(plan["path"]) > 10


def test_demo_writes_the_pictures_and_a_loadable_model(demo_run):
    out, text = demo_run
    for name in ("plan.png", "map.png"):
        img = Image.open(out / name)
        assert img.format == "PNG" and img.size[0] > 800 and img.size[1] > 600
    assert (out / "model" / "model.json").is_file()
    assert f"spcotmhp serve {out / 'model'}" in text


def test_demo_supervised_fit(tmp_path):
    result = CliRunner().invoke(
        app, ["demo", "--out", str(tmp_path), "--supervised", "--instruction", "go to the kitchen"]
    )
    assert result.exit_code == 0, result.output
    assert "model:       supervised fit (truth labels), 11 places: asked for with --supervised" in result.output
    assert "-> kitchen, " in result.output


def test_learner_falls_back_to_the_supervised_fit_when_a_name_is_missing(home):
    renamed = dataclasses.replace(home, place_names=[n.replace("corridor", "hallway") for n in home.place_names])
    with _progress() as bar:
        chosen = learn_demo_model(renamed, "go to the bedroom", seed=0, runs=1, iterations=20, bar=bar)
    assert chosen.method == "supervised fit (truth labels)"
    assert chosen.reason == "the unsupervised map lacks the place name(s) hallway"


def test_learner_falls_back_when_the_instruction_is_not_understood(home):
    with _progress() as bar:
        chosen = learn_demo_model(home, "go to the garage", seed=0, runs=1, iterations=20, bar=bar)
    assert chosen.method == "supervised fit (truth labels)"
    assert chosen.reason.startswith(
        "the instruction cannot be understood on the unsupervised map (no known place word in 'go to the garage'"
    )


def test_demo_start_is_the_free_cell_nearest_the_place_mean(home):
    model = fit_supervised(home)
    planner = HierarchicalPlanner(model)
    xy, label = demo_start(planner, "entrance")
    assert label == "entrance"
    cell = planner.graph.to_crop(model.map.world_to_cell(xy))
    assert planner.graph.traversable[cell[0], cell[1]]
    # no traversable cell of the main component is nearer to the entrance's mean
    entrance = model.mu[0]
    rows, cols = np.nonzero(planner.graph.traversable)
    centres = model.map.cell_to_world(planner.graph.to_map(np.stack([rows, cols], axis=1)))
    assert np.linalg.norm(xy - entrance) <= np.linalg.norm(centres - entrance, axis=1).min() + 1e-9
    assert demo_start(planner)[1] == "entrance"  # the default
    with pytest.raises(InstructionError) as info:  # never a silent fallback to another place
        demo_start(planner, "garage")
    assert str(info.value) == (
        "--start-place 'garage' names no place of the learned map; its places: bath, "
        "bedroom, corridor, dining, entrance, kitchen, living, toilet, washroom"
    )


@pytest.fixture(scope="module")
def model_dir(home, tmp_path_factory):
    return save_model(fit_supervised(home), tmp_path_factory.mktemp("model") / "3LDK_06")


def test_the_hint_keeps_a_free_preferred_port():
    with socket.socket() as probe:
        probe.bind(("127.0.0.1", 0))
        port = probe.getsockname()[1]
    assert serve_port(port) == port


def test_the_hint_serves_on_a_free_port_when_the_preferred_one_is_taken(model_dir):
    """Where something already listens on the default port, the demo's `next:` line names another port, and the
    line, run as typed, serves the model there."""
    with socket.socket() as held:
        held.bind(("127.0.0.1", 0))
        held.listen()
        taken = held.getsockname()[1]
        hint = next_command(model_dir, preferred=taken)
        match = re.fullmatch(r"(.* serve \S+ --port (\d+))   # then open http://127\.0\.0\.1:(\d+)/", hint)
        assert match and match.group(2) == match.group(3) and int(match.group(2)) != taken, hint
        env = {**os.environ, "PYTHONPATH": os.pathsep.join(sys.path)}
        server = subprocess.Popen(
            ["bash", "-c", match.group(1)],
            env=env,
            stdout=subprocess.PIPE,
            stderr=subprocess.STDOUT,
            text=True,
            start_new_session=True,
        )
        try:
            import httpx

            url = f"http://127.0.0.1:{match.group(2)}/healthz"
            for _ in range(600):
                try:
                    if httpx.get(url, timeout=1).status_code == 200:
                        break
                except httpx.TransportError:
                    assert server.poll() is None, server.communicate()[0]
                    time.sleep(0.2)
            else:
                pytest.fail(f"the hint's server did not answer at {url}")
        finally:
            os.killpg(server.pid, signal.SIGKILL)  # the shell and the server it started
            server.communicate()


def test_show_lists_places_and_edges(model_dir):
    result = CliRunner().invoke(app, ["show", str(model_dir)])
    assert result.exit_code == 0, result.output
    lines = result.output.splitlines()
    assert lines[0].startswith("11 places, ") and "1/K = 0.091" in lines[0]
    assert any(" bedroom #1 " in x for x in lines) and any(" bedroom #3 " in x for x in lines)
    corridor = next(x for x in lines if " corridor " in x)
    assert "entrance" in corridor.split("->")[1]


def test_show_notes_the_kept_hmm_transitions(home, model_dir, tmp_path):
    from spcotmhp.learning.gibbs import SpCoTMHP

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        learned = SpCoTMHP(iterations=3, seed=0, connectivity="map").fit(home).model_
    folder = save_model(learned, tmp_path / "learned")
    result = CliRunner().invoke(app, ["show", str(folder)])
    assert result.exit_code == 0, result.output
    assert result.output.splitlines()[1] == (
        "note: the edges come from psi of map; the transitions the HMM learned are kept as psi_learned in arrays.npz"
    )
    plain = CliRunner().invoke(app, ["show", str(model_dir)])  # supervised: nothing learned to keep
    assert "psi_learned" not in plain.output


def test_show_json_and_png(model_dir, tmp_path):
    out = tmp_path / "map.png"
    result = CliRunner().invoke(app, ["show", str(model_dir), "--json", "--png", str(out), "--ids"])
    assert result.exit_code == 0, result.output
    data = json.loads(result.output)
    assert len(data["places"]) == 11
    labels = sorted(p["label"] for p in data["places"])
    assert labels.count("bedroom #1") == 1 and "bedroom #3" in labels
    assert all(len(e) == 2 and e[0] < e[1] for e in data["edges"])
    assert Image.open(out).format == "PNG"


def test_show_and_demo_report_bad_input_without_a_traceback(tmp_path):
    run = subprocess.run(SPCOTMHP + ["show", str(tmp_path / "nope")], capture_output=True, text=True, check=False)
    assert run.returncode == 2
    assert run.stderr.strip() == f"error: model folder {tmp_path / 'nope'} does not exist"
    run = subprocess.run(
        SPCOTMHP + ["demo", "--home", "nowhere", "--out", str(tmp_path)],
        capture_output=True,
        text=True,
        check=False,
    )
    assert run.returncode == 2
    assert "error: nowhere is neither a dataset folder nor a bundled dataset name" in run.stderr
    assert "Traceback" not in run.stderr


def test_demo_reports_an_unwritable_output_folder(tmp_path):
    blocker = tmp_path / "file"
    blocker.write_text("not a folder")
    run = subprocess.run(
        SPCOTMHP + ["demo", "--supervised", "--out", str(blocker / "out")],
        capture_output=True,
        text=True,
        check=False,
    )
    assert run.returncode == 2
    assert f"error: cannot write the demo output to {blocker / 'out'}" in run.stderr


def test_demo_refuses_an_unknown_start_place(tmp_path):
    out = subprocess.run(
        [*SPCOTMHP, "demo", "--supervised", "--start-place", "garage", "--out", str(tmp_path / "d")],
        capture_output=True,
        text=True,
        timeout=300,
        check=False,
    )
    assert out.returncode == 2
    assert "error: --start-place 'garage' names no place of the learned map; its places: bath, bedroom" in out.stderr
    assert "Traceback" not in out.stderr
