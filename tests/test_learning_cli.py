"""The learn and evaluate-learning commands."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from typer.testing import CliRunner

from spcotmhp.cli import app
from spcotmhp.learning.io import load_model

pytestmark = pytest.mark.filterwarnings("ignore::spcotmhp.datasets.loader.DatasetWarning")
EXE = Path(sys.executable).parent / "spcotmhp"


def test_learn_a_bundled_home(tmp_path):
    out = tmp_path / "model"
    result = CliRunner().invoke(app, ["learn", "3LDK_01", "--out", str(out), "--runs", "2", "--iterations", "15"])
    assert result.exit_code == 0, result.output
    assert "model written to" in result.output and "psi from map" in result.output
    model = load_model(out)
    assert model.info["runs"] == 2 and model.info["iterations"] == 15 and model.info["dataset"] == "3LDK_01"
    assert model.info["criterion"] == "mutual_information"
    assert model.map is not None and model.active_places.sum() >= 8


def test_learn_supervised_and_gmm(tmp_path):
    runner = CliRunner()
    res = runner.invoke(app, ["learn", "3LDK_05", "--out", str(tmp_path / "s"), "--supervised"])
    assert res.exit_code == 0, res.output
    assert load_model(tmp_path / "s").info["psi_from"] == "adjacency.csv"
    res = runner.invoke(app, ["learn", "3LDK_05", "--out", str(tmp_path / "g"), "--gmm", "--runs", "1",
                              "--iterations", "5", "--lang", "ja"])
    assert res.exit_code == 0, res.output
    g = load_model(tmp_path / "g")
    assert g.info["method"] == "SpCoSLAM (GMM)"
    np.testing.assert_allclose(g.psi, 1.0 / g.K)


def test_evaluate_learning_json(tmp_path):
    res = CliRunner().invoke(app, ["evaluate-learning", "3LDK_06", "--runs", "2", "--iterations", "10", "--json"])
    assert res.exit_code == 0, res.output
    table = json.loads(res.stdout[res.stdout.index("{"):])
    assert set(table) == {"tmhp_replay", "tmhp", "gmm"}
    for scores in table.values():
        assert {"nmi_c", "nmi_i", "ari_c", "ari_i", "time_s", "runs"} <= set(scores)
        assert scores["runs"] == 2 and 0.5 < scores["nmi_i"] <= 1.0


def test_evaluate_learning_table():
    res = CliRunner().invoke(app, ["evaluate-learning", "albert-b", "--runs", "1", "--iterations", "5"])
    assert res.exit_code == 0, res.output
    assert "SpCoTMHP (with reverse replay)" in res.stdout and "0.786" in res.stdout   # the paper's row


def _cli(*args):
    return subprocess.run([str(EXE), *args], capture_output=True, text=True, timeout=120, check=False)


def test_unknown_dataset_is_a_one_line_error(tmp_path):
    res = _cli("learn", "no-such-home", "--out", str(tmp_path / "m"))
    assert res.returncode == 2
    assert res.stderr.strip() == "error: no-such-home is neither a dataset folder nor a bundled dataset name"


def test_bad_criterion_is_a_one_line_error(tmp_path):
    res = _cli("learn", "3LDK_01", "--out", str(tmp_path / "m"), "--criterion", "vibes", "--runs", "1",
               "--iterations", "1")
    assert res.returncode == 2
    assert "error: criterion must be one of ('mutual_information', 'log_joint'), got 'vibes'" in res.stderr
    assert "Traceback" not in res.stderr
