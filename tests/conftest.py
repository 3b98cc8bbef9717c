"""Fixtures shared across the test packages (helpers that are plain functions live in tests/helpers/)."""

from __future__ import annotations

from pathlib import Path

import pytest

from tests.helpers.server import supervised_model_dir


@pytest.fixture(scope="session")
def model_3ldk06_dir(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """The supervised fit of the bundled 3LDK_06 home (English words), saved once per session; read it only."""
    return supervised_model_dir("3LDK_06", tmp_path_factory.mktemp("shared-model") / "3LDK_06")
