"""The guard of tests/conftest.py: a test that leaves os.environ or the garbage collector changed fails, naming
what it changed."""

from __future__ import annotations

import shutil
import subprocess
import sys
from pathlib import Path

from tests.helpers.environment import GC, check_unchanged, state_changes

ROOT = Path(__file__).resolve().parent.parent


def test_changes_are_named_one_per_variable_sorted():
    before = {"A": "1", "B": "2", "D": "4", "PYTEST_CURRENT_TEST": "x (setup)"}  # pytest's and sklearn's: not state
    after = {"A": "1", "B": "3", "C": "x", "PYTEST_CURRENT_TEST": "x (teardown)", "KMP_DUPLICATE_LIB_OK": "True"}
    assert state_changes(before, after) == ["B: '2' -> '3'", "C: set to 'x'", "D: unset (was '4')"]
    assert check_unchanged(before, dict(before), "t") is None
    message = check_unchanged({}, {"NUMBA_CACHE_DIR": "/tmp/x"}, "tests/t.py::test_x")
    assert message is not None and message.startswith("tests/t.py::test_x left the process changed")
    assert message.endswith("NUMBA_CACHE_DIR: set to '/tmp/x'")
    assert state_changes({GC: "enabled"}, {GC: "disabled"}) == [f"{GC}: 'enabled' -> 'disabled'"]


def test_a_test_that_leaks_a_variable_or_pauses_the_collector_fails(tmp_path):
    """A test that sets a variable and does not restore it, or turns the collector off, errors at its teardown,
    and so do its module's fixtures (the variable is still set when the module ends); a test that restores what it
    sets passes."""
    folder = ROOT / "tests" / f"_leak_{tmp_path.name}"
    folder.mkdir()
    try:
        (folder / "__init__.py").write_text("")
        (folder / "test_leak.py").write_text(
            "import os\n\n"
            "def test_leaks():\n    os.environ['SPCOTMHP_LEAK_PROBE'] = '1'\n\n"
            "def test_restores(monkeypatch):\n    monkeypatch.setenv('SPCOTMHP_LEAK_PROBE', '2')\n\n"
            "def test_pauses_the_collector():\n    import gc\n    gc.disable()\n"
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
    assert "test_leaks left the process changed" in run.stdout and "SPCOTMHP_LEAK_PROBE: set to '1'" in run.stdout
    assert (
        "test_pauses_the_collector left the process changed" in run.stdout
        and f"{GC}: 'enabled' -> 'disabled'" in run.stdout
    )
    assert "the fixtures of tests._leak_" in run.stdout and "3 passed, 2 errors" in run.stdout, run.stdout
