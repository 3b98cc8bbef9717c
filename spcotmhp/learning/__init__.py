"""Spatial concept learning (paper Sections 3.1-3.2): the model, the Gibbs sampler, the supervised fit,
connectivity and the online learner (model folders on disk: :mod:`spcotmhp.persistence`).

Public names are imported lazily, so that ``import spcotmhp.learning.model`` stays light.
"""

from __future__ import annotations

from spcotmhp.lazy import lazy_exports

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
__all__ = sorted(_EXPORTS)
__getattr__ = lazy_exports(__name__, _EXPORTS)
