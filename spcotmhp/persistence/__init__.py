"""Model folders on disk: saving and loading a learned model (:mod:`.io`), the folder as a unit with its checksum
manifest and atomic replacement (:mod:`.folder`), what loading checks (:mod:`.model_checks`), and the online
learner's state kept with a model (:mod:`.learner`).

This package sits above ``learning`` (it stores the models learning makes) and below planning's and the front
ends' loaders; nothing in ``learning`` imports it. Public names are imported lazily, so that
``import spcotmhp.persistence`` stays light.
"""

from __future__ import annotations

from spcotmhp.lazy import lazy_exports

_EXPORTS = {"save_model": "io", "load_model": "io", "prepare_model_folder": "io"}
__all__ = sorted(_EXPORTS)
__getattr__ = lazy_exports(__name__, _EXPORTS)
