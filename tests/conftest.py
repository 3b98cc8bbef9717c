"""Fixtures shared across the test packages (helpers that are plain functions live in tests/helpers/)."""

from __future__ import annotations

import os
from pathlib import Path

import pytest
from hypothesis import settings

from tests.helpers.environment import check_unchanged, process_state
from tests.helpers.server import supervised_model_dir


@pytest.fixture(autouse=True, scope="module")
def _module_leaves_the_process_unchanged(request: pytest.FixtureRequest):
    """A module's fixtures restore os.environ and the garbage collector by the module's end
    (tests/helpers/environment.py)."""
    before = process_state()
    yield
    message = check_unchanged(before, process_state(), f"the fixtures of {request.module.__name__}")
    if message:
        pytest.fail(message)


@pytest.fixture(autouse=True)
def _test_leaves_the_process_unchanged(request: pytest.FixtureRequest):
    """A test restores os.environ and the garbage collector (tests/helpers/environment.py): a variable it leaves
    set reaches every later
    test and every subprocess they start (a NUMBA_CACHE_DIR left pointing at an empty folder made each later
    `spcotmhp serve` compile its kernels during its first plans, past the service's time budget)."""
    before = process_state()
    yield
    message = check_unchanged(before, process_state(), request.node.nodeid)
    if message:
        pytest.fail(message)


@pytest.fixture(scope="session")
def model_3ldk06_dir(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """The supervised fit of the bundled 3LDK_06 home (English words), saved once per session; read it only."""
    return supervised_model_dir("3LDK_06", tmp_path_factory.mktemp("shared-model") / "3LDK_06")


# Property tests are reproducible by default: the same examples on every run, in CI and here (a test that fails
# at random is no test). HYPOTHESIS_PROFILE=explore searches fresh examples instead.
settings.register_profile("deterministic", derandomize=True)
settings.register_profile("explore", derandomize=False)
settings.load_profile(os.environ.get("HYPOTHESIS_PROFILE", "deterministic"))
