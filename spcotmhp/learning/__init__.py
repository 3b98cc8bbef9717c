"""Spatial concept learning (paper Sections 3.1-3.2): the model, the Gibbs sampler, the supervised fit,
connectivity and the online learner (model folders on disk: :mod:`spcotmhp.persistence`).

Public names are imported lazily, so that ``import spcotmhp.learning.model`` stays light.
"""

from __future__ import annotations

import importlib
from typing import Any

_EXPORTS = {
    "Hyperparameters": "model",
    "SpatialConceptModel": "model",
    "SpCoTMHP": "gibbs",
    "make_rng": "gibbs",
    "TruncationWarning": "posterior",
    "MultiRunSelector": "selection",
    "fit_runs": "selection",
    "fit_supervised": "supervised",
    "apply_connectivity": "connectivity",
    "map_adjacency": "connectivity",
    "walk_adjacency": "connectivity",
    "psi_from_adjacency": "connectivity",
}
__all__ = [
    "Hyperparameters",
    "MultiRunSelector",
    "SpCoTMHP",
    "SpatialConceptModel",
    "TruncationWarning",
    "apply_connectivity",
    "fit_runs",
    "fit_supervised",
    "make_rng",
    "map_adjacency",
    "psi_from_adjacency",
    "walk_adjacency",
]


def __getattr__(name: str) -> Any:
    if name in _EXPORTS:
        return getattr(importlib.import_module(f"spcotmhp.learning.{_EXPORTS[name]}"), name)
    raise AttributeError(f"module 'spcotmhp.learning' has no attribute {name!r}")
