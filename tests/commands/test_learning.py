"""The learn and evaluate-learning commands."""

from __future__ import annotations

import json
import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from typer.testing import CliRunner

from spcotmhp.cli import app
from spcotmhp.persistence.io import load_model

pytestmark = pytest.mark.filterwarnings("ignore::spcotmhp.datasets.loader.DatasetWarning")
DATA = Path(__file__).resolve().parents[2] / "spcotmhp" / "data"
EXE = Path(sys.executable).parent / "spcotmhp"


def test_learn_a_bundled_home(tmp_path):
    out = tmp_path / "model"
    result = CliRunner().invoke(app, ["learn", "3LDK_01", "--out", str(out), "--runs", "2", "--iterations", "15"])
    assert result.exit_code == 0, result.output
    assert "model written to" in result.output and "psi from map" in result.output
    model = load_model(out)
    assert model.info["runs"] == 2 and model.info["iterations"] == 15 and model.info["dataset"] == "3LDK_01"
    assert model.info["criterion"] == "log_joint"  # "auto" without image features
    assert model.map is not None and model.active_places.sum() >= 8


def test_learn_supervised_and_gmm(tmp_path):
    runner = CliRunner()
    res = runner.invoke(app, ["learn", "3LDK_05", "--out", str(tmp_path / "s"), "--supervised"])
    assert res.exit_code == 0, res.output
    assert load_model(tmp_path / "s").info["psi_from"] == "adjacency.csv"
    res = runner.invoke(
        app,
        [
            "learn",
            "3LDK_05",
            "--out",
            str(tmp_path / "g"),
            "--gmm",
            "--runs",
            "1",
            "--iterations",
            "5",
            "--lang",
            "ja",
        ],
    )
    assert res.exit_code == 0, res.output
    g = load_model(tmp_path / "g")
    assert g.info["method"] == "SpCoSLAM (GMM)"
    np.testing.assert_allclose(g.psi, 1.0 / g.K)


def test_evaluate_learning_json(tmp_path):
    res = CliRunner().invoke(
        app, ["evaluate-learning", "3LDK_06", "--runs", "2", "--iterations", "10", "--seeds", "3", "--json"]
    )
    assert res.exit_code == 0, res.output
    table = json.loads(res.stdout[res.stdout.index("{") :])
    assert set(table) == {"tmhp_replay", "tmhp", "gmm", "seeds"} and table.pop("seeds") == 3
    for scores in table.values():
        keys = ("nmi_c", "nmi_i", "ari_c", "ari_i", "time_s")
        assert {*keys, *(f"{k}_sd" for k in keys), "runs", "seeds"} <= set(scores)
        assert scores["runs"] == 2 and scores["seeds"] == 3 and 0.5 < scores["nmi_i"] <= 1.0
        assert 0.0 <= scores["nmi_i_sd"] < 0.5


def _ours_rows(table: str) -> list[list[float]]:
    """The numbers of the "ours" rows of the text table (NMI C, NMI i, ARI C, ARI i, time), in table order."""
    return [[float(v) for v in line.split()[1:]] for line in table.splitlines() if line.split()[:1] == ["ours"]]


def test_evaluate_learning_table():
    args = [
        "evaluate-learning",
        "albert-b",
        "--runs",
        "1",
        "--iterations",
        "5",
        "--seed",
        "4",
        "--seeds",
        "1",
    ]
    res = CliRunner().invoke(app, args)
    assert res.exit_code == 0, res.output
    assert "SpCoTMHP (with reverse replay)" in res.stdout and "0.786" in res.stdout  # the paper's row
    as_json = CliRunner().invoke(app, [*args, "--json"])
    assert as_json.exit_code == 0, as_json.output
    table = json.loads(as_json.stdout[as_json.stdout.index("{") :])
    assert set(table) == {"tmhp_replay", "tmhp", "gmm", "seeds"} and table.pop("seeds") == 1
    rows = _ours_rows(res.stdout)
    assert len(rows) == 3
    for name, row in zip(
        ("gmm", "tmhp", "tmhp_replay"), rows, strict=False
    ):  # the table prints our numbers, not the paper's
        scores = table[name]
        keys = ("nmi_c", "nmi_i", "ari_c", "ari_i", "time_s")
        assert set(scores) == {*keys, *(f"{k}_sd" for k in keys), "runs", "std", "saturated", "seeds"}
        assert set(scores["std"]) == {"nmi_c", "nmi_i", "ari_c", "ari_i"}
        assert scores["runs"] == 1 and scores["std"]["nmi_i"] == 0.0  # one run: no spread
        assert scores["saturated"] == {"places": 0, "concepts": 0}
        assert 0.0 <= scores["nmi_c"] <= 1.0 and 0.3 < scores["nmi_i"] <= 1.0  # 5 sweeps already find places
        assert -0.5 <= scores["ari_c"] <= 1.0 and 0.0 < scores["ari_i"] <= 1.0
        assert scores["time_s"] > 0.0
        # same seed, same runs: the text table shows the JSON's scores
        assert row[:4] == [round(scores[k], 3) for k in ("nmi_c", "nmi_i", "ari_c", "ari_i")]
        assert row[:4] != [0.786, 0.862, 0.562, 0.658]


def test_evaluate_learning_reports_saturated_truncations_and_dataset_warnings():
    res = CliRunner().invoke(
        app,
        [
            "evaluate-learning",
            "3LDK_05",
            "--runs",
            "2",
            "--iterations",
            "3",
            "--max-places",
            "3",
            "--seeds",
            "1",
            "--json",
        ],
    )
    assert res.exit_code == 0, res.output
    table = json.loads(res.stdout[res.stdout.index("{") :])
    assert table["tmhp"]["saturated"]["places"] == 2
    assert (
        "warning: SpCoTMHP: all 3 place components hold events in 2 of 2 run(s) (the weak-limit truncation "
        "is saturated, so places may have been merged): evaluate again with a larger --max-places"
    ) in res.stderr
    assert (
        "warning: 3LDK_05: 11 known warning(s) of the bundled data (teaching points recorded at the edge of a "
        "wall; spcotmhp/data/README.md); `spcotmhp check-dataset 3LDK_05` lists them"
    ) in res.stderr


def _cli(*args):
    return subprocess.run([str(EXE), *args], capture_output=True, text=True, timeout=120, check=False)


def test_unknown_dataset_is_a_one_line_error(tmp_path):
    res = _cli("learn", "no-such-home", "--out", str(tmp_path / "m"))
    assert res.returncode == 2
    assert res.stderr.strip() == (
        "error: no-such-home is neither a dataset folder nor a bundled dataset name "
        "(bundled: 3LDK_01, 3LDK_05, 3LDK_06, albert-b; `spcotmhp datasets` describes "
        "them)"
    )


def test_bad_criterion_is_a_one_line_error(tmp_path):
    res = _cli(
        "learn",
        "3LDK_01",
        "--out",
        str(tmp_path / "m"),
        "--criterion",
        "vibes",
        "--runs",
        "1",
        "--iterations",
        "1",
    )
    assert res.returncode == 2
    from spcotmhp.experimental.selection import CRITERIA

    assert "log_joint_switch_marginal" in CRITERIA and "held_out_words" in CRITERIA
    assert f"error: criterion must be one of {CRITERIA}, got 'vibes'" in res.stderr
    assert "Traceback" not in res.stderr


def test_unwritable_out_fails_before_the_fit(tmp_path):
    res = _cli("learn", "3LDK_01", "--out", "/proc/nope/m")  # 10 runs x 100 sweeps if it fitted first
    assert res.returncode == 2
    assert res.stderr.strip().splitlines()[-1].startswith("error: cannot save the model to /proc/nope/m: ")
    assert "learning 3LDK_01" not in res.stderr and "Traceback" not in res.stderr


def test_learn_prints_the_dataset_warnings(tmp_path):
    home = tmp_path / "home"
    shutil.copytree(DATA / "sigverse-3ldk" / "3LDK_05", home)  # a folder of one's own: not the bundled data
    res = _cli("learn", str(home), "--supervised", "--out", str(tmp_path / "m"))
    assert res.returncode == 0, res.stderr
    lines = res.stderr.splitlines()
    start = lines.index("home: 11 dataset warning(s)")
    assert all(line.startswith("  warning: ") for line in lines[start + 1 : start + 4])
    assert lines[start + 4] == f"  ... 8 more (`spcotmhp check-dataset {home}` lists them all)"
    # the same messages as check-dataset's
    check = _cli("check-dataset", str(home))
    listed = [line for line in check.stdout.splitlines() if line.startswith("  warning: ")]
    assert lines[start + 1 : start + 4] == listed[:3]


def test_learn_reports_a_saturated_truncation(tmp_path):
    res = _cli(
        "learn",
        "3LDK_01",
        "--out",
        str(tmp_path / "m"),
        "--max-places",
        "3",
        "--runs",
        "1",
        "--iterations",
        "3",
    )
    assert res.returncode == 0, res.stderr
    assert (
        "warning: all K = 3 place components hold events (the weak-limit truncation is saturated, so places "
        "may have been merged): learn again with a larger --max-places (SpCoTMHP(K=...))"
    ) in res.stderr
    assert load_model(tmp_path / "m").info["truncation_saturated"] == ["places"]


@pytest.mark.parametrize(
    "extra,named",
    [
        (["--runs", "3"], "--runs"),
        (["--gmm", "--no-replay"], "--no-replay, --gmm"),
        (["--criterion", "log_joint", "--seed", "2"], "--seed, --criterion"),
        (
            ["--iterations", "5", "--max-places", "30", "--max-concepts", "30", "--jobs", "2"],
            "--iterations, --max-places, --max-concepts, --jobs",
        ),
    ],
)
def test_supervised_refuses_options_of_the_gibbs_learner(tmp_path, extra, named):
    res = _cli("learn", "3LDK_05", "--supervised", "--out", str(tmp_path / "m"), *extra)
    assert res.returncode == 2
    pronoun = "it" if "," not in named else "them"
    assert res.stderr.strip() == (
        f"error: {named}: option(s) of the Gibbs learner, which --supervised (a fit from "
        f"the truth labels) does not use; drop {pronoun}"
    )
    assert not (tmp_path / "m").exists()


@pytest.mark.parametrize("connectivity,psi_from", [("map", "map"), ("hmm", "transitions"), ("given", "adjacency.csv")])
def test_supervised_honours_connectivity(tmp_path, connectivity, psi_from):
    res = CliRunner().invoke(
        app,
        ["learn", "3LDK_05", "--supervised", "--connectivity", connectivity, "--out", str(tmp_path / "m")],
    )
    assert res.exit_code == 0, res.output
    assert load_model(tmp_path / "m").info["psi_from"] == psi_from


def test_supervised_connectivity_must_be_known(tmp_path):
    res = _cli("learn", "3LDK_05", "--supervised", "--connectivity", "psychic", "--out", str(tmp_path / "m"))
    assert res.returncode == 2
    assert res.stderr.strip() == (
        "error: --connectivity must be one of auto, hmm, walk, map, given with --supervised, got 'psychic'"
    )


def test_feature_weight_option(tmp_path):
    runner = CliRunner()
    res = runner.invoke(
        app,
        [
            "learn",
            "albert-b",
            "--supervised",
            "--feature-weight",
            "authors",
            "--connectivity",
            "hmm",
            "--out",
            str(tmp_path / "a"),
        ],
    )
    assert res.exit_code == 0, res.output
    assert load_model(tmp_path / "a").info["feature_weight"] is None
    res = runner.invoke(
        app,
        [
            "learn",
            "albert-b",
            "--feature-weight",
            "2.5",
            "--runs",
            "1",
            "--iterations",
            "2",
            "--connectivity",
            "hmm",
            "--out",
            str(tmp_path / "b"),
        ],
    )
    assert res.exit_code == 0, res.output
    assert load_model(tmp_path / "b").info["feature_weight"] == 2.5
    for bad in ("heavy", "0", "-1", "nan", "inf"):
        out = _cli("learn", "albert-b", "--feature-weight", bad, "--out", str(tmp_path / "c"))
        assert out.returncode == 2
        assert out.stderr.strip() == (
            f"error: --feature-weight must be a number > 0 or 'authors' (the authors' p * 10 + 1 counts), got '{bad}'"
        )
