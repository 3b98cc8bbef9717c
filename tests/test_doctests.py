"""The ``>>>`` examples of the public API run and give what they show (doctest). Listed here: the modules whose
examples need no optional extra (the server's and the ROS node's need their extras and a model folder)."""

from __future__ import annotations

import doctest
import importlib
import warnings

import pytest

MODULES = [
    "spcotmhp.planning",
    "spcotmhp.planning.protocol",
    "spcotmhp.planning.instructions",
    "spcotmhp.planning.nbest",
    "spcotmhp.planning.start",
    "spcotmhp.planning.regions",
    "spcotmhp.language.naming",
    "spcotmhp.metric.grid_search",
    "spcotmhp.metric.maps",
    "spcotmhp.logspace",
    "spcotmhp.learning.model",
    "spcotmhp.baselines.smoothing",
    "spcotmhp.evaluation.metrics",
    "spcotmhp.evaluation.spread",
    "spcotmhp.datasets.against_wall",
    "spcotmhp.datasets.synthetic",
    "spcotmhp.building.layout",
    "spcotmhp.building.loader",
    "spcotmhp.building.learn",
    "spcotmhp.building.model",
    "spcotmhp.datasets.synthetic_furniture",
    "spcotmhp.speech.lexicon",
    "spcotmhp.limits",
]


@pytest.mark.parametrize("name", MODULES)
def test_examples_run(name: str) -> None:
    module = importlib.import_module(name)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # the bundled data's known warnings are not part of the examples
        result = doctest.testmod(module, optionflags=doctest.ELLIPSIS | doctest.NORMALIZE_WHITESPACE, verbose=False)
    assert result.attempted > 0, f"{name} has no example"
    assert result.failed == 0, f"{result.failed} of {result.attempted} examples of {name} failed (output above)"
