"""No import arrow runs from a lower layer of the package to a higher one (issue 27: each layer in its own room).

The layers, bottom to top, and why each sits where it does, are listed in docs/architecture.md ("Layers"). Every
import inside spcotmhp counts, at module level or inside a function (the same graph as test_import_cycles): a
module may import its own layer and the ones below it, never one above. A package that is not listed fails the
test, so a new package must be given its place."""

from __future__ import annotations

import pytest

from tests.test_import_cycles import import_graph

LAYERS: list[tuple[str, ...]] = [
    # the package root and what every layer may use: errors, bounds, files, log-space arithmetic, progress bars
    (
        "",
        "errors",
        "limits",
        "logspace",
        "safe_read",
        "safe_write",
        "extras",
        "collector",
        "numba_cache",
        "lazy",
        "progress",
    ),
    ("metric", "language"),  # the occupancy/cost map; the instruction grammar
    ("datasets",),  # maps + trajectories + utterances on disk
    ("learning",),  # the paper's model and samplers (Sections 3.1-3.2)
    ("persistence", "planning", "experimental"),  # model folders; Algorithm 1; research variants of learning
    ("baselines", "teaching", "speech"),  # other planners; run-time teaching; spoken instructions
    ("building",),  # several floors of models and plans
    ("evaluation", "viz", "warmup"),  # Experiments I/II; pictures; compiling every kernel
    ("ros", "server"),  # front ends: the ROS 2 node and Nav2 files, the HTTP service
    ("commands", "cli", "__main__", "data"),  # the command line; data/examples: scripts a user runs
]


def layer_of(module: str) -> str:
    """The top-level part of ``spcotmhp.X.Y`` (``X``); the package root is ``""``."""
    parts = module.split(".")
    return parts[1] if len(parts) > 1 else ""


RANK = {name: rank for rank, names in enumerate(LAYERS) for name in names}


def test_every_package_has_a_layer():
    found = {layer_of(m) for m in import_graph()}
    assert found - RANK.keys() == set(), "give each new package or top-level module its layer in LAYERS"
    assert RANK.keys() - found == set(), "LAYERS names a package that no longer exists"


def test_no_import_arrow_runs_up_the_layers():
    upward = sorted(
        f"{a} -> {b}"
        for a, targets in import_graph().items()
        for b in targets
        if RANK.get(layer_of(b), -1) > RANK.get(layer_of(a), len(LAYERS))
    )
    assert upward == []


@pytest.mark.parametrize(("low", "high"), [("learning", "persistence"), ("learning", "teaching"), ("metric", "ros")])
def test_the_check_sees_an_upward_arrow(low, high, monkeypatch):
    """The check is not vacuous: an added arrow from a lower layer to a higher one is reported."""
    graph = import_graph()
    low_module = next(m for m in graph if layer_of(m) == low)
    high_module = next(m for m in graph if layer_of(m) == high)
    graph[low_module].add(high_module)
    monkeypatch.setattr("tests.test_layers.import_graph", lambda: graph)
    with pytest.raises(AssertionError):
        test_no_import_arrow_runs_up_the_layers()
