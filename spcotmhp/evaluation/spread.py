"""Mean and spread over seeds: every table of the README is a mean over independent seeds with its standard
deviation, never one seed's result.

:func:`aggregate` turns one metrics dictionary per seed into one dictionary that keeps every key (now the mean
over the seeds) and adds ``<key>_sd`` beside each numeric key (the sample standard deviation, n - 1 in the
denominator; 0 for a single seed) and ``seeds``.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence

import numpy as np

COUNTS = ("n_tasks", "runs")
"""Keys that are counts, equal in every seed: kept as they are, no spread."""


def aggregate(per_seed: Sequence[Mapping]) -> dict:
    """Mean and sample standard deviation over seeds of every numeric key (see the module docstring); keys that
    are not numbers (or are counts, :data:`COUNTS`) keep the first seed's value.

    Raises:
        ValueError: no seeds.
    """
    if not per_seed:
        raise ValueError("no seeds to aggregate")
    out: dict = {}
    for key, first in per_seed[0].items():
        if key in COUNTS or isinstance(first, bool) or not isinstance(first, (int, float)):
            out[key] = first
            continue
        values = np.array([float(d[key]) for d in per_seed if key in d])
        out[key] = float(values.mean())
        out[f"{key}_sd"] = float(values.std(ddof=1)) if len(values) > 1 else 0.0
    out["seeds"] = len(per_seed)
    return out


def aggregate_methods(per_seed: Sequence[Mapping[str, Mapping]]) -> dict[str, dict]:
    """:func:`aggregate` for each method of ``{method: metrics}`` dictionaries (one per seed), methods in the
    first seed's order."""
    if not per_seed:
        return {}
    return {m: aggregate([d[m] for d in per_seed if m in d]) for m in per_seed[0]}


def pm(values: Mapping, key: str, digits: int = 3) -> str:
    """``mean ± sd`` of ``key`` (just the mean when there is no ``<key>_sd`` or only one seed)."""
    sd = values.get(f"{key}_sd")
    text = f"{values[key]:.{digits}f}"
    return text if sd is None or values.get("seeds", 1) <= 1 else f"{text} ± {sd:.{digits}f}"
