"""Every test file the README, CONTRIBUTING, CHANGELOG and docs/ point at exists (tests move when the package does:
a path to an old flat ``tests/test_*.py`` would send a reader nowhere)."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[1]
DOCS = [REPO / "README.md", REPO / "CONTRIBUTING.md", REPO / "CHANGELOG.md", *sorted((REPO / "docs").glob("*.md"))]
TEST_PATH = re.compile(r"\btests/[\w/*]*[\w*]\.py\b")  # a path or a glob such as tests/test_fuzz_*.py


@pytest.mark.parametrize("doc", [d for d in DOCS if d.exists()], ids=lambda d: d.name)
def test_every_test_path_named_in_the_docs_exists(doc):
    named = sorted(set(TEST_PATH.findall(doc.read_text(encoding="utf-8"))))
    missing = [p for p in named if not any(f.is_file() for f in REPO.glob(p))]
    assert not missing, f"{doc.name} names test files that do not exist: {missing}"


def test_the_pattern_finds_paths():
    text = "`tests/metric/test_costmap.py`, tests/test_newcomer.py, `tests/test_fuzz_*.py`, not tests/<pkg>/test_<m>.py"
    assert TEST_PATH.findall(text) == ["tests/metric/test_costmap.py", "tests/test_newcomer.py", "tests/test_fuzz_*.py"]
