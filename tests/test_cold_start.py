"""Cold start: a fresh process that loads a model and plans imports none of the modules the planning path does
not use (benchmarks/cold_start.py times it; the README's "Cold start" paragraph gives the figures)."""

import json
import os
import subprocess
import sys
from pathlib import Path

from tests.helpers.server import INSTRUCTION, supervised_model_dir

NOT_ON_THE_PATH = ("scipy.ndimage", "scipy.sparse", "scipy.special", "rapidfuzz", "spcotmhp.datasets")

CHILD = """
import json, sys
from spcotmhp.persistence.io import load_model
from spcotmhp.planning.planner import HierarchicalPlanner
model = load_model(sys.argv[1])
plan = HierarchicalPlanner(model).plan(sys.argv[2], start=tuple(model.mu[0]))
print(json.dumps({"cells": len(plan.cells), "modules": sorted(sys.modules)}))
"""


def test_loading_and_planning_import_no_unused_module(tmp_path: Path):
    folder = supervised_model_dir("3LDK_06", tmp_path / "model")
    root = Path(__file__).resolve().parent.parent
    env = dict(os.environ, PYTHONPATH=str(root))
    out = subprocess.run(
        [sys.executable, "-c", CHILD, str(folder), INSTRUCTION], env=env, capture_output=True, text=True, check=True
    )
    seen = json.loads(out.stdout.strip().splitlines()[-1])
    assert seen["cells"] > 1
    loaded = [m for m in seen["modules"] if any(m == n or m.startswith(n + ".") for n in NOT_ON_THE_PATH)]
    assert loaded == []
