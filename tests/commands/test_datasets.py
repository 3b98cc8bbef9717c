"""The dataset CLI: `spcotmhp datasets` and `spcotmhp check-dataset DIR`."""

from __future__ import annotations

import shutil
import subprocess
import sys
from pathlib import Path

from typer.testing import CliRunner

from spcotmhp.cli import app
from spcotmhp.datasets import bundled_path

SPCOTMHP = str(Path(sys.executable).with_name("spcotmhp"))
runner = CliRunner()


def test_datasets_lists_the_bundled_data():
    result = runner.invoke(app, ["datasets"])
    assert result.exit_code == 0, result.output
    names = ("3LDK", "albert")  # plain rows, one per dataset (readable piped: nothing cut)
    lines = {line.split()[0]: line for line in result.output.splitlines() if line.startswith(names)}
    assert set(lines) == {"3LDK_01", "3LDK_05", "3LDK_06", "albert-b"}
    assert "sigverse-3ldk/3LDK_01" in lines["3LDK_01"] and "192x192 @ 0.1 m" in lines["3LDK_01"]
    assert " 165 " in lines["3LDK_05"] and " 11 " in lines["3LDK_05"] and "en,ja" in lines["3LDK_05"]
    assert " 70 " in lines["albert-b"] and " 12 " in lines["albert-b"] and "800x1184 @ 0.05 m" in lines["albert-b"]


def test_check_dataset_summary_and_warnings():
    result = runner.invoke(app, ["check-dataset", str(bundled_path("3LDK_01"))])
    assert result.exit_code == 0, result.output
    out = result.output
    assert "165 teaching events, lang en, 9 distinct words" in out
    assert "truth       11 places" in out and "adjacency   11 x 11" in out
    assert "warnings    5" in out
    assert "warning: teaching.csv row 67: (x, y) = (2.67, -0.31) lies in an occupied cell of map.pgm" in out
    strict = runner.invoke(app, ["check-dataset", "--strict", str(bundled_path("3LDK_01"))])
    assert strict.exit_code == 1


def test_check_dataset_picks_japanese_for_albert_b():
    result = runner.invoke(app, ["check-dataset", "--strict", str(bundled_path("albert-b"))])
    assert result.exit_code == 0, result.output
    assert "70 teaching events, lang ja" in result.output
    assert "features    365-d per event" in result.output
    assert "truth       12 places, 11 concepts" in result.output


def test_check_dataset_with_trajectory(tmp_path):
    folder = tmp_path / "walk"
    folder.mkdir()
    for name in ("map.yaml", "map.pgm"):
        shutil.copy(bundled_path("3LDK_01") / name, folder / name)
    (folder / "trajectory.csv").write_text("step,x,y\n" + "".join(f"{i},{-4 + 0.1 * i:.1f},0.5\n" for i in range(30)))
    (folder / "teaching.csv").write_text("event,x,y,words_ja,words_en\n0,-3.9,0.5,玄関,entrance\n1,-1.5,0.5,x,hall\n")
    result = runner.invoke(app, ["check-dataset", str(folder)])
    assert result.exit_code == 0, result.output
    assert "trajectory  30 poses; events at steps 1..25" in result.output


def run(*args: str) -> subprocess.CompletedProcess:
    return subprocess.run([SPCOTMHP, *args], check=False, capture_output=True, text=True, timeout=120)


def test_check_dataset_errors_are_one_line(tmp_path):
    result = run("check-dataset", "--lang", "en", str(bundled_path("albert-b")))
    assert result.returncode == 2
    assert result.stderr == (
        "error: albert-b has no words_en column (teaching.csv has event, x, y, words_ja); use lang='ja'\n"
    )
    result = run("check-dataset", str(tmp_path / "missing"))
    assert result.returncode == 2
    assert result.stderr == f"error: dataset folder {tmp_path / 'missing'} does not exist\n"
    assert "Traceback" not in result.stdout + result.stderr


def test_synth_command_writes_a_loadable_dataset(tmp_path):
    from typer.testing import CliRunner

    from spcotmhp.cli import app
    from spcotmhp.datasets import load_dataset

    out = tmp_path / "flat"
    res = CliRunner().invoke(app, ["synth", "flat", "--rooms", "4", "--seed", "2", "--out", str(out)])
    assert res.exit_code == 0, res.output
    d = load_dataset(out)
    assert len(set(d.truth_place.tolist())) == 4
    assert d.trajectory is not None and d.event_steps is not None
