"""A newcomer's first hour (issue 13), run as a new user would: the README's "Use it on your own robot" with a
hand-drawn map and a 10-line CSV, the command line's conventions (help, one-line usage errors, --version),
output that survives a pipe, the Tour's example inputs and install hints that work where the user is."""

from __future__ import annotations

import re
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from PIL import Image

from spcotmhp import __version__
from spcotmhp.commands.conventions import plain_table
from spcotmhp.commands.examples import draw_flat

EXE = Path(sys.executable).parent / "spcotmhp"
CLI = [str(EXE)] if EXE.exists() else [sys.executable, "-m", "spcotmhp.cli"]

# the README's example: x, y in metres on the drawn map, and what was said there
TEACHING = """x,y,words_en
1.5,4.5,this is the kitchen
2.5,5.0,the kitchen
3.0,4.0,kitchen here
4.0,4.5,kitchen
7.0,4.5,this is the bedroom
8.0,5.0,my bedroom
7.5,4.0,the bedroom
2.0,1.5,the hallway
5.0,1.5,hallway
8.0,1.5,this is the hallway
"""


def run(*args: str, cwd: Path) -> subprocess.CompletedProcess:
    return subprocess.run([*CLI, *args], cwd=cwd, capture_output=True, text=True, timeout=300, check=False)


def draw_home(folder: Path) -> None:
    """A 10 m x 6 m flat drawn in a paint program (RGB PNG, black walls on white): a kitchen and a bedroom
    above a hallway, each with a door; 0.05 m per pixel, origin at the bottom left corner (the drawing
    `spcotmhp examples` writes as drawn-map.png, which the README copies)."""
    folder.mkdir()
    draw_flat(folder / "map.png")
    (folder / "map.yaml").write_text(
        "image: map.png\nresolution: 0.05\norigin: [0.0, 0.0, 0.0]\nnegate: 0\n"
        "occupied_thresh: 0.65\nfree_thresh: 0.196\n"
    )


def test_a_hand_written_csv_to_a_plan(tmp_path):
    """The README's steps on a drawn map and 10 utterances; each error met on the way says how to fix it."""
    home = tmp_path / "my-home"
    draw_home(home)
    missing = run("check-dataset", "my-home", cwd=tmp_path)  # forgot teaching.csv: says which file
    assert missing.returncode == 2 and missing.stderr.strip() == (
        "error: dataset folder my-home has no teaching.csv (the teaching events)"
    )
    (home / "teaching.csv").write_text(TEACHING)
    check = run("check-dataset", "my-home", cwd=tmp_path)
    assert check.returncode == 0, check.stderr
    assert "10 teaching events" in check.stdout and "warnings    0" in check.stdout
    early = run("plan", "my-home", "go to the bedroom", "--start", "2", "1.5", cwd=tmp_path)  # before learning
    assert early.returncode == 2 and early.stderr.strip() == (
        "error: my-home is a dataset folder, not a model; learn a model from it first: spcotmhp learn my-home "
        "--out my-home-model"
    )
    learn = run("learn", "my-home", "--out", "my-model", cwd=tmp_path)
    assert learn.returncode == 0, learn.stderr
    places = run("show", "my-model", cwd=tmp_path)
    assert places.returncode == 0 and len(re.findall(r"mean \(", places.stdout)) == 3  # kitchen, bedroom, hall
    plan = run("plan", "my-model", "go to the bedroom", "--start", "2", "1.5", "--json", cwd=tmp_path)
    assert plan.returncode == 0, plan.stderr
    end = np.array(__import__("json").loads(plan.stdout)["path"][-1])
    assert 5.0 < end[0] < 10.0 and 3.5 < end[1] < 6.0  # in the bedroom (x 5..10 m, y 3.5..6 m)
    wall = run("plan", "my-model", "go to the bedroom", "--start", "5", "0.05", cwd=tmp_path)  # on the wall
    assert wall.returncode == 2
    suggested = re.search(r"plan from, \((\S+), (\S+)\)$", wall.stderr.strip())
    assert wall.stderr.count("\n") == 1 and suggested, wall.stderr
    again = run("plan", "my-model", "go to the bedroom", "--start", *suggested.groups(), cwd=tmp_path)
    assert again.returncode == 0, again.stderr


@pytest.mark.parametrize(
    "args, message",
    [
        (["plan", "m", "go"], "error: Missing option '--start' (see 'spcotmhp plan --help')"),
        (
            ["plan", "m", "go", "--start", "-3.9,-3.5"],
            (
                "error: --start takes two numbers separated by a space, e.g. --start -3.9 -3.5 (got '-3.9,-3.5') "
                "(see 'spcotmhp plan --help')"
            ),
        ),
        (
            ["plan", "m", "go", "--start", "1", "2", "--bogus"],
            "error: No such option: --bogus (see 'spcotmhp plan --help')",
        ),
        (["lern", "3LDK_06"], "error: No such command 'lern'. Did you mean 'learn'? (see 'spcotmhp --help')"),
        (
            ["learn", "nosuchdataset", "--out", "m"],
            (
                "error: nosuchdataset is neither a dataset folder nor a bundled dataset name (bundled: 3LDK_01, "
                "3LDK_05, "
                "3LDK_06, albert-b; `spcotmhp datasets` describes them)"
            ),
        ),
        (
            ["plan", "3LDK_06", "go", "--start", "1", "2"],
            (
                "error: model folder 3LDK_06 does not exist (3LDK_06 is the name of a bundled dataset); learn a "
                "model from "
                "it first: spcotmhp learn 3LDK_06 --out 3LDK_06-model"
            ),
        ),
    ],
)
def test_usage_errors_are_one_line_with_status_2(tmp_path, args, message):
    out = run(*args, cwd=tmp_path)
    assert out.returncode == 2 and out.stderr.strip() == message and out.stdout == ""


def test_version_and_help(tmp_path):
    assert run("--version", cwd=tmp_path).stdout.strip() == f"spcotmhp {__version__}"
    text = run("plan", "--help", cwd=tmp_path).stdout
    assert "<" not in text.replace("<=", "")  # no <bool>, <str>, <path> type labels
    assert re.search(r"--start X Y .*\[required\]", " ".join(text.split()))
    assert "[default: 1; 1<=x<=100]" in " ".join(text.split())  # defaults (and bounds) shown
    assert "│" not in text  # plain text: the same piped and in a terminal
    synth = " ".join(run("synth", "--help", cwd=tmp_path).stdout.split())
    assert "--rooms INTEGER" in synth and "--overwrite Replace" in synth


def test_plain_table_keeps_every_number_whole():
    text = plain_table(
        ["Method", "SPL", "Time median"],
        [["SpCoNavi (A* approximation)", "0.822", "30 ms"], ["SpCoTMHP", "0.948", "1.14 ms"]],
        title="basic",
    )
    lines = text.splitlines()
    assert lines == [
        "basic",
        "Method                         SPL  Time median",
        "---------------------------  -----  -----------",
        "SpCoNavi (A* approximation)  0.822        30 ms",
        "SpCoTMHP                     0.948      1.14 ms",
    ]


def test_datasets_piped_is_not_truncated(tmp_path):
    out = run("datasets", cwd=tmp_path).stdout
    assert "…" not in out and re.search(r"^3LDK_05 .* 192x192 @ 0\.1 m .* 11$", out, re.MULTILINE)


def test_examples_are_the_tours_inputs(tmp_path):
    pytest.importorskip("rosbags", reason="the example bag needs rosbags (extra 'ros')")
    made = run("examples", cwd=tmp_path)
    assert made.returncode == 0, made.stderr
    assert {p.name for p in (tmp_path / "examples").iterdir()} == {
        "map.yaml",
        "map.pgm",
        "robot.bag",
        "say.wav",
        "drawn-map.png",  # the README's own-data block copies it (issue 25: map.png did not exist)
        "tell.py",  # the README's ROS 2 client (issue 25: shipped rather than printed in the README)
    }
    drawn = Image.open(tmp_path / "examples" / "drawn-map.png")
    assert drawn.format == "PNG" and drawn.size == (200, 120) and drawn.mode == "RGB"
    again = run("examples", cwd=tmp_path)
    assert again.returncode == 2 and "exists; give --overwrite" in again.stderr
    bag = run(
        "import-bag",
        "examples/robot.bag",
        "--pose-topic",
        "/amcl_pose",
        "--utterance-topic",
        "/speech",
        "--map",
        "examples/map.yaml",
        "--out",
        "my-home",
        cwd=tmp_path,
    )
    assert bag.returncode == 0, bag.stderr
    rows = (tmp_path / "my-home" / "teaching.csv").read_text().splitlines()
    assert len(rows) == 46
    numbers = [v for row in rows[1:] for v in row.split(",")[1:3]]
    assert all(len(v.partition(".")[2]) <= 4 for v in numbers), numbers  # 0.1 mm, not 8.1999999995
    cost = run("costmap", "examples/map.yaml", "--out", "cm.csv", cwd=tmp_path)
    assert cost.returncode == 0, cost.stderr
    learn = run("learn", "my-home", "--out", "my-model", cwd=tmp_path)  # the README's bag steps to a plan
    assert learn.returncode == 0, learn.stderr
    plan = run("plan", "my-model", "go to the kitchen", "--start", "5.3", "3.5", cwd=tmp_path)
    assert plan.returncode == 0 and plan.stdout.strip().endswith("m"), plan.stderr


def test_install_hints_work_where_the_user_is(monkeypatch):
    from spcotmhp import extras

    hint = extras.install_hint("server")  # these tests run from the source tree
    assert re.fullmatch(r"\S+ -m pip install -e '\S*\[server\]'", hint), hint
    monkeypatch.setattr(extras, "source_tree", lambda: None)
    monkeypatch.setattr(extras, "extra_requirements", lambda extra: ["fastapi>=0.110", "uvicorn>=0.29"])
    assert extras.install_hint("server").endswith("-m pip install 'fastapi>=0.110' 'uvicorn>=0.29'")
    assert extras.missing_extra("serving (uvicorn)", "server").startswith(
        "serving (uvicorn) needs the extra 'server': "
    )
