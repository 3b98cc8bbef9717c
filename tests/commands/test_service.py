"""`spcotmhp serve` as a real process: it starts, answers over HTTP on localhost, and reports bad input."""

from __future__ import annotations

import subprocess
import sys

import httpx
import pytest

from spcotmhp.persistence.io import load_model
from tests.helpers.server import INSTRUCTION, ServerProcess, start_near


@pytest.fixture(scope="module")
def model_dir(model_3ldk06_dir):
    return model_3ldk06_dir


def test_serve_answers_plan_requests_over_http(model_dir):
    start = start_near(load_model(model_dir))
    with ServerProcess([f"home={model_dir}"]) as server:
        health = httpx.get(server.url + "/healthz", timeout=10)
        assert health.json() == {"status": "ok", "models": ["home"]}
        r = httpx.post(server.url + "/plan", json={"instruction": INSTRUCTION, "start": start}, timeout=30)
        assert r.status_code == 200, r.text
        body = r.json()
        assert body["model"] == "home" and len(body["path"]) > 2
        assert "corridor (waypoint)" in body["explanation"]
        bad = httpx.post(server.url + "/plan", json={"instruction": "go to the garage", "start": start}, timeout=30)
        assert bad.status_code == 422 and "garage" in bad.json()["detail"]
        page = httpx.get(server.url + "/", timeout=10)
        assert page.status_code == 200 and "SpCoTMHP" in page.text
        png = httpx.get(server.url + "/map.png", timeout=10)
        assert png.content[:8] == b"\x89PNG\r\n\x1a\n"
        # one line a script can read the address from (it wrapped at 80 columns: second audit)
        served = f"serving 1 model(s) on {server.url}/ (API docs: /docs, schema: /openapi.json)"
        assert served in server.output_tail().splitlines(), server.output_tail()


def test_serve_help_names_every_endpoint(model_dir):
    """`serve --help` left out POST /teach, GET /map.json, /models and /healthz (second audit)."""
    from typer.testing import CliRunner

    from spcotmhp.cli import app
    from spcotmhp.server import create_app

    text = " ".join(CliRunner().invoke(app, ["serve", "--help"], terminal_width=200).output.split())
    paths = create_app({"home": model_dir}).openapi()["paths"]
    assert [p for p in paths if f"{p}," not in text and f"{p};" not in text and f"{p} " not in text] == []


def test_serve_reports_a_missing_model_folder(tmp_path):
    run = subprocess.run(
        [sys.executable, "-m", "spcotmhp.cli", "serve", str(tmp_path / "nope")],
        capture_output=True,
        text=True,
        timeout=120,
        check=False,
    )
    assert run.returncode == 2
    assert run.stderr.strip().splitlines()[-1] == f"error: model folder {tmp_path / 'nope'} does not exist"


def _serve(*args: str) -> subprocess.CompletedProcess:
    return subprocess.run(
        [sys.executable, "-m", "spcotmhp.cli", "serve", *args], capture_output=True, text=True, timeout=120, check=False
    )


def test_serve_reports_a_port_in_use_in_one_line(model_dir):
    """Audit item 10: with the port taken, one error line and status 2, and no "serving" line before it."""
    import socket

    with socket.socket() as holder:
        holder.bind(("127.0.0.1", 0))
        holder.listen()
        port = holder.getsockname()[1]
        run = _serve(str(model_dir), "--port", str(port))
    assert run.returncode == 2, run.stderr
    assert run.stderr.strip().splitlines() == [
        f"error: cannot listen on 127.0.0.1:{port}: the port is already in use; stop what holds it or choose "
        "another --port (--port 0: any free port)"
    ]
    assert "serving" not in run.stdout + run.stderr


@pytest.mark.parametrize("damage", ["missing", "hostile"])
def test_serve_checks_its_models_before_its_port(model_dir, tmp_path, damage):
    """Issue 26: on a busy port, serve reported the port before a missing (or bad) model; the model is what
    to fix first, and a port is only held once the models are known to load."""
    import json
    import shutil
    import socket

    from tests.helpers.learning import reseal

    bad = tmp_path / "bad"
    if damage == "hostile":
        shutil.copytree(model_dir, bad)
        meta = json.loads((bad / "model.json").read_text(encoding="utf-8"))
        meta["hyper"]["place_size"] = 1e308
        (bad / "model.json").write_text(json.dumps(meta), encoding="utf-8")
        reseal(bad)
    with socket.socket() as holder:
        holder.bind(("127.0.0.1", 0))
        holder.listen()
        run = _serve(str(model_dir), f"other={bad}", "--port", str(holder.getsockname()[1]))
    assert run.returncode == 2, run.stderr
    lines = run.stderr.strip().splitlines()
    expected = "does not exist" if damage == "missing" else "hyper-parameter place_size must be a finite number"
    assert len(lines) == 1 and lines[0].startswith("error: ") and str(bad) in lines[0] and expected in lines[0], lines


def test_serve_reports_an_unusable_host_in_one_line(model_dir):
    run = _serve(str(model_dir), "--host", "192.0.2.1", "--port", "0")  # TEST-NET-1: not this machine's
    assert run.returncode == 2
    assert run.stderr.strip().splitlines()[-1].startswith("error: cannot listen on 192.0.2.1:0: ")


@pytest.mark.parametrize("option", ["--time-budget", "--body-timeout"])
@pytest.mark.parametrize("value", ["nan", "inf", "0", "601"])
def test_serve_time_options_must_be_finite_seconds(model_dir, option, value):
    """Audit item 12: --time-budget nan said "should be less than or equal to 600"."""
    run = _serve(str(model_dir), option, value)
    assert run.returncode == 2
    assert f"Invalid value for '{option}': must be a finite number of seconds in [0.1, 600], got " in run.stderr


def test_serve_a_buildings_model(tmp_path):
    """A building's model folder is served with its building planner: /plan takes the start's floor."""
    import warnings

    from spcotmhp.building.io import save_building_model
    from spcotmhp.building.learn import learn_building
    from spcotmhp.building.loader import load_building
    from spcotmhp.building.synthetic import example_path

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        bm = learn_building(load_building(example_path()))
    folder = save_building_model(bm, tmp_path / "m")
    stairs = next(c for c in bm.spec.connectors if c.kind == "stairs")
    start = [stairs.stops[0].x + 0.5, stairs.stops[0].y]
    with ServerProcess([f"house={folder}"]) as server:
        body = {"instruction": "go to the bedroom upstairs", "start": start, "floor": "ground"}
        r = httpx.post(server.url + "/plan", json=body, timeout=30)
        assert r.status_code == 200, r.text
        assert [s["floor"] for s in r.json()["segments"]] == [1, 2]
