"""Saturated weak-limit truncations: when every place (or concept) component of a learned model holds events,
K (or L) may be too small for the home (Johnson and Willsky 2013's truncation is then no longer loose).

:func:`record_truncation` lists them in ``model.info["truncation_saturated"]`` and warns
(:class:`TruncationWarning`); :func:`truncation_messages` words them for the command line.
"""

from __future__ import annotations

import warnings

from spcotmhp.learning.model import SpatialConceptModel


class TruncationWarning(UserWarning):
    """Every place (or concept) component of the weak-limit truncation holds events: K (or L) may be too small."""


def record_truncation(model: SpatialConceptModel, K: int, L: int) -> None:
    """List the saturated truncations ("places" when all K place components hold events, "concepts" when all L
    concept components do) in ``model.info["truncation_saturated"]`` and warn about each (TruncationWarning,
    attributed to the caller's caller: the code that called ``fit``)."""
    full = [
        what
        for what, used, cap in (
            ("places", model.active_places.sum(), K),
            ("concepts", model.active_concepts.sum(), L),
        )
        if used >= cap
    ]
    model.info["truncation_saturated"] = full
    for message in truncation_messages(model):
        warnings.warn(message, TruncationWarning, stacklevel=3)


def truncation_messages(model: SpatialConceptModel) -> list[str]:
    """One sentence per saturated truncation listed in ``model.info["truncation_saturated"]``."""
    hint = {
        "places": ("place", "K", model.K, "--max-places", "SpCoTMHP(K=...)"),
        "concepts": ("concept", "L", model.L, "--max-concepts", "SpCoTMHP(L=...)"),
    }
    out = []
    for what in model.info.get("truncation_saturated", []):
        noun, symbol, size, option, api = hint[what]
        out.append(
            f"all {symbol} = {size} {noun} components hold events (the weak-limit truncation is "
            f"saturated, so {what} may have been merged): learn again with a larger {option} ({api})"
        )
    return out
