"""`spcotmhp plan MODEL_DIR INSTRUCTION --start X Y [--json] [--png] [--nbest]` end to end (subprocess)."""

from __future__ import annotations

import json
import subprocess
import sys
import warnings
from pathlib import Path

import numpy as np
import pytest

from spcotmhp.datasets.bundled import load_bundled
from spcotmhp.learning.supervised import fit_supervised
from spcotmhp.persistence.io import load_model, save_model

EXE = str(Path(sys.executable).with_name("spcotmhp"))


@pytest.fixture(scope="module")
def model_dir(model_3ldk06_dir) -> tuple[Path, np.ndarray]:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        dataset = load_bundled("3LDK_06")
    kitchen = int(dataset.place_names.index("kitchen"))
    return model_3ldk06_dir, load_model(model_3ldk06_dir).mu[kitchen]


def run(*args: str) -> subprocess.CompletedProcess:
    return subprocess.run([EXE, "plan", *args], capture_output=True, text=True, timeout=120, check=False)


def test_plan_prints_the_explanation_and_json(model_dir, tmp_path):
    folder, kitchen = model_dir
    x, y = (f"{v:.3f}" for v in kitchen)
    out = run(str(folder), "go to the bedroom via the corridor", "--start", x, y)
    assert out.returncode == 0, out.stderr
    line = out.stdout.strip()
    assert line.startswith("kitchen -> ") and "corridor (waypoint)" in line and "bedroom #" in line
    assert line.endswith(" m")
    png = tmp_path / "plan.png"
    out = run(str(folder), "go to the bedroom via the corridor", "--start", x, y, "--json", "--png", str(png))
    assert out.returncode == 0, out.stderr
    data = json.loads(out.stdout)
    assert {"path", "places", "length_m", "log_prob", "time_online_s", "explanation"} <= set(data)
    assert data["explanation"] == line
    assert data["places"][0]["role"] == "start" and data["places"][-1]["role"] == "goal"
    assert np.allclose(data["path"][0], kitchen, atol=0.1)
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_nbest_file(model_dir, tmp_path):
    folder, kitchen = model_dir
    x, y = (f"{v:.3f}" for v in kitchen)
    nbest = tmp_path / "nbest.json"
    nbest.write_text(json.dumps([["go to the bath", 0.7], {"text": "go to the bedroom", "score": 0.3}]))
    out = run(str(folder), "--nbest", str(nbest), "--start", x, y, "--json")
    assert out.returncode == 0, out.stderr
    assert json.loads(out.stdout)["places"][-1]["name"] == "bath"


def test_japanese_instruction(tmp_path):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        dataset = load_bundled("3LDK_06", lang="ja")
    model = fit_supervised(dataset)
    folder = save_model(model, tmp_path / "ja")
    x, y = (f"{v:.3f}" for v in model.mu[dataset.place_names.index("キッチン")])
    out = run(str(folder), "廊下を通って寝室へ行って", "--start", x, y)
    assert out.returncode == 0, out.stderr
    line = out.stdout.strip()
    assert line.startswith("キッチン -> ") and "廊下 (waypoint)" in line
    assert "(closest of 3 places named 寝室)" in line or "places named 寝室;" in line


@pytest.mark.parametrize(
    "args, message",
    [
        (
            ["go to the garage", "--start", "{x}", "{y}"],
            "error: no known place word in 'go to the garage' (not understood: garage); known place words: bath,",
        ),
        (["go to the bath", "--start", "-10.0", "-10.0"], "error: the start (-10.00, -10.00) is in"),
        (["go to the bath", "--start", "50", "0"], "error: the start (50.00, 0.00) is outside the map"),
        (
            ["go to the kitchen avoiding the kitchen", "--start", "{x}", "{y}"],
            "every place named 'kitchen' is also to be avoided",
        ),
    ],
)
def test_errors_are_one_line(model_dir, args, message):
    folder, kitchen = model_dir
    args = [a.format(x=f"{kitchen[0]:.3f}", y=f"{kitchen[1]:.3f}") for a in args]
    out = run(str(folder), *args)
    assert out.returncode == 2
    assert message in out.stderr
    assert len(out.stderr.strip().splitlines()) == 1 and "Traceback" not in out.stderr


def test_usage_errors(model_dir, tmp_path):
    folder, _ = model_dir
    out = run(str(folder), "go to the bath")
    assert out.returncode == 2 and "--start" in out.stderr
    out = run(str(tmp_path / "missing"), "go to the bath", "--start", "0", "0")
    assert out.returncode == 2 and "error: model folder" in out.stderr and "does not exist" in out.stderr
    bad = tmp_path / "bad.json"
    bad.write_text("{not json")
    out = run(str(folder), "--nbest", str(bad), "--start", "0", "0")
    assert out.returncode == 2 and "is not valid JSON" in out.stderr


@pytest.mark.parametrize(
    "args, message",
    [
        (
            ["--candidates", "0"],
            "Invalid value for '--candidates': Input should be greater than or equal to 1",
        ),
        (
            ["--candidates", "-1"],
            "Invalid value for '--candidates': Input should be greater than or equal to 1",
        ),
        (
            ["--max-steps", "-3"],
            "Invalid value for '--max-steps': Input should be greater than or equal to 1",
        ),
        (["--max-steps", "0"], "Invalid value for '--max-steps': Input should be greater than or equal to 1"),
    ],
)
def test_out_of_range_options_are_usage_errors(model_dir, args, message):
    from typer.testing import CliRunner

    from spcotmhp.cli import app

    folder, _ = model_dir
    out = CliRunner().invoke(app, ["plan", str(folder), "go to the bath", "--start", "0", "0", *args])
    assert out.exit_code == 2
    assert message in " ".join(out.output.replace("│", " ").split())
