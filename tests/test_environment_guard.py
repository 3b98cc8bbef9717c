"""The guard of tests/conftest.py: a test that leaves os.environ changed fails, naming what it changed."""

from __future__ import annotations

import shutil
import subprocess
import sys
from pathlib import Path

from tests.helpers.environment import check_unchanged, environment_changes

ROOT = Path(__file__).resolve().parent.parent


def test_changes_are_named_one_per_variable_sorted():
    before = {"A": "1", "B": "2", "D": "4", "PYTEST_CURRENT_TEST": "x (setup)"}
    after = {"A": "1", "B": "3", "C": "x", "PYTEST_CURRENT_TEST": "x (teardown)"}
    assert environment_changes(before, after) == ["B: '2' -> '3'", "C: set to 'x'", "D: unset (was '4')"]
    assert check_unchanged(before, dict(before), "t") is None
    message = check_unchanged({}, {"NUMBA_CACHE_DIR": "/tmp/x"}, "tests/t.py::test_x")
    assert message is not None and message.startswith("tests/t.py::test_x left os.environ changed")
    assert message.endswith("NUMBA_CACHE_DIR: set to '/tmp/x'")


def test_a_test_that_leaks_a_variable_fails(tmp_path):
    """A test that sets a variable and does not restore it errors at its teardown, and so do its module's fixtures
    (the variable is still set when the module ends); a test that restores what it sets passes."""
    folder = ROOT / "tests" / f"_leak_{tmp_path.name}"
    folder.mkdir()
    try:
        (folder / "__init__.py").write_text("")
        (folder / "test_leak.py").write_text(
            "import os\n\n"
            "def test_leaks():\n    os.environ['SPCOTMHP_LEAK_PROBE'] = '1'\n\n"
            "def test_restores(monkeypatch):\n    monkeypatch.setenv('SPCOTMHP_LEAK_PROBE', '2')\n"
        )
        run = subprocess.run(
            [sys.executable, "-m", "pytest", "-q", "-p", "no:cacheprovider", str(folder)],
            cwd=ROOT,
            capture_output=True,
            text=True,
            timeout=300,
        )
    finally:
        shutil.rmtree(folder)
    assert run.returncode == 1, run.stdout + run.stderr
    assert "test_leaks left os.environ changed" in run.stdout and "SPCOTMHP_LEAK_PROBE: set to '1'" in run.stdout
    assert "the fixtures of tests._leak_" in run.stdout and "2 passed, 2 errors" in run.stdout, run.stdout
