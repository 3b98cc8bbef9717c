"""The ``teach`` command (spcotmhp/commands/teaching.py)."""

from __future__ import annotations

import shutil
import subprocess
import sys


def test_teach_into_a_model_folder_holding_other_files_gives_teach_advice(model_3ldk06_dir, tmp_path):
    """Audit item 12: the advice was "choose an empty or new folder", which teach (an update in place) cannot
    follow. It is refused before any teaching, with the folder unchanged."""
    folder = tmp_path / "m"
    shutil.copytree(model_3ldk06_dir, folder)
    (folder / "picture.png").write_bytes(b"\x89PNG\r\n\x1a\n")
    before = {p.name: p.read_bytes() for p in folder.iterdir()}
    cmd = [sys.executable, "-m", "spcotmhp.cli", "teach", str(folder), "this is the study", "--at", "5.5", "-4.0"]
    out = subprocess.run(cmd, capture_output=True, text=True, timeout=120, check=False)
    assert out.returncode == 2
    assert out.stderr.strip().splitlines() == [
        f"error: cannot save the model to {folder}: the folder holds files that are not a model's (picture.png); "
        "teach replaces the model folder whole: move those files out of it first"
    ]
    assert {p.name: p.read_bytes() for p in folder.iterdir()} == before


def test_questions_lists_where_to_ask_as_json(model_3ldk06_dir):
    """`spcotmhp questions MODEL --max 2 --json` prints {"questions": [...]} (issue 24)."""
    import json

    cmd = [sys.executable, "-m", "spcotmhp.cli", "questions", str(model_3ldk06_dir), "--max", "2", "--json"]
    out = subprocess.run(cmd, capture_output=True, text=True, timeout=120, check=False)
    assert out.returncode == 0, out.stderr
    asked = json.loads(out.stdout)["questions"]
    assert 1 <= len(asked) <= 2 and asked[0]["ask"] == "What is this place called?" and asked[0]["candidates"]
