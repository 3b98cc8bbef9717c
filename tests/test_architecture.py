"""docs/architecture.md's equation and Algorithm 1 tables: every row names one home, a file and a function of
the package that exist, so that a reader told where an equation lives opens the right file in one step."""

from __future__ import annotations

import importlib
import re
from pathlib import Path

import pytest

DOC = Path(__file__).resolve().parents[1] / "docs" / "architecture.md"
HOME = re.compile(r"`([a-z_/]+)\.py:([A-Za-z_][A-Za-z0-9_.]*)`")


def _rows(section: str) -> list[list[str]]:
    text = DOC.read_text(encoding="utf-8").split(f"## {section}", 1)[1].split("\n## ", 1)[0]
    rows = [re.split(r"(?<!\\)\|", line.strip())[1:-1] for line in text.splitlines() if line.startswith("| ")]
    header, body = rows[0], rows[2:]
    assert [c.strip() for c in header][:3] in (["Eq.", "What", "Home"], ["Line", "What", "Home"])
    return body


ROWS = [(s, r) for s in ("Equations (Sections 3-4)", "Algorithm 1") for r in _rows(s)]


@pytest.mark.parametrize(("section", "row"), ROWS, ids=[f"{s[:9]} {r[0].strip()}" for s, r in ROWS])
def test_each_row_has_one_home_that_exists(section, row):
    home = row[2]
    found = HOME.findall(home)
    if not found:  # not implemented here (SLAM, the sensor models) or a line with nothing to do
        assert home.strip() == "" or home.strip().startswith(("not ", "not modelled")), row
        return
    assert len(found) == 1, f"{row[0]}: one home, got {found}"
    path, name = found[0]
    assert (DOC.parents[1] / "spcotmhp" / f"{path}.py").is_file(), path
    obj = importlib.import_module("spcotmhp." + path.replace("/", "."))
    for part in name.split("."):
        obj = getattr(obj, part)
    assert callable(obj)


def test_the_newcomers_question_has_one_answer():
    # "find where the place assignments i_e are sampled": one row says so, with one home
    rows = [r for _, r in ROWS if "place assignments" in r[1]]
    assert len(rows) == 1 and HOME.findall(rows[0][2]) == [("learning/place_ffbs", "sample_places")]


def test_every_qualified_name_in_the_tables_exists():
    # the "See also" column too: `planning/graph.PlanningGraph.for_start` must still be there after a move
    text = DOC.read_text(encoding="utf-8").split("## Equations (Sections 3-4)", 1)[1].split("## State and", 1)[0]
    missing = []
    for path, name in set(re.findall(r"`([a-z_]+/[a-z_]+)[.:]([A-Za-z_][A-Za-z0-9_.]*)`", text)):
        if name == "py":  # a file, not a function
            continue
        try:
            obj = importlib.import_module("spcotmhp." + path.replace("/", "."))
            for part in name.split("."):
                obj = getattr(obj, part)
        except (ImportError, AttributeError):
            missing.append(f"{path}.{name}")
    assert not missing
