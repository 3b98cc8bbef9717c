"""No module-level state that queries change (issue: a codebase a newcomer can carry on): every module-level
container of the package (dict, list, set, array) reads the same after planning (with avoidance, from several
threads), parsing in both languages, serving and teaching. Graph caches are objects their callers own
(:mod:`spcotmhp.planning.graph_cache`); the instruction lexicon is a compile-once ``lru_cache`` of read-only
mappings (:mod:`spcotmhp.language.lexicon`). The only per-process state is listed in ``PER_PROCESS``, each
documented where it is defined."""

from __future__ import annotations

import importlib
import pkgutil
import re
import sys
import warnings
from pathlib import Path

import numpy as np

import spcotmhp

PER_PROCESS = {
    ("spcotmhp.datasets.bundled", "_ANNOUNCED"),  # bundled datasets whose known warnings were summarised
    ("spcotmhp.evaluation.ray_backend", "_WARM"),  # homes a Ray worker process has warmed up
}


def module_containers() -> dict[tuple[str, str], object]:
    """(module, name) -> value of every dict, list, set or array a package module defines at module level."""
    out = {}
    for info in pkgutil.walk_packages(spcotmhp.__path__, "spcotmhp."):
        try:
            module = importlib.import_module(info.name)
        except ImportError:  # an optional extra (ROS 2) that is not installed
            continue
        source = Path(module.__file__ or "").read_text(encoding="utf-8")
        for name, value in vars(module).items():
            defined_here = re.search(rf"^{re.escape(name)}\b[^=\n]*=", source, re.M)
            if isinstance(value, (dict, list, set, np.ndarray)) and not name.startswith("__") and defined_here:
                out[info.name, name] = value
    return out


def snapshot(values: dict) -> dict:
    with np.printoptions(threshold=sys.maxsize):
        return {key: repr(value) for key, value in values.items()}


def test_queries_leave_module_level_state_alone():
    from spcotmhp.datasets.bundled import load_bundled
    from spcotmhp.learning.supervised import fit_supervised
    from spcotmhp.planning.instructions import to_instruction
    from spcotmhp.planning.planner import HierarchicalPlanner
    from spcotmhp.server.registry import ServedModel
    from tests.helpers.threads import in_threads

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        model = fit_supervised(load_bundled("3LDK_06"))
    containers = module_containers()
    assert PER_PROCESS <= set(containers)
    before = snapshot(containers)

    planner = HierarchicalPlanner(model)
    start = (-3.9, -3.5)  # the entrance
    queries = ["go to the bedroom via the corridor", "go to the kitchen avoiding the living", "go to the toilet"]
    in_threads(3, queries * 2, lambda q: planner.plan(q, start))
    to_instruction("廊下を通って寝室へ行って", ["廊下", "寝室"], "ja")
    served = ServedModel.build("state", model)
    served.plan("go to the dining avoiding the kitchen", start)
    served.teach("pantry", -1.0, -1.0)
    served.plan("go to the pantry", start)

    after = snapshot(containers)
    changed = sorted(key for key in containers if before[key] != after[key] and key not in PER_PROCESS)
    assert changed == []
