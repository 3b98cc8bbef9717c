"""Spread that informs: the standard deviation over seeds where seeds change the result, and a bootstrap
confidence interval over tasks where they do not.

:func:`aggregate` turns one metrics dictionary per seed into one dictionary that keeps every key (now the mean
over the seeds) and adds ``<key>_sd`` beside each numeric key (the sample standard deviation, n - 1 in the
denominator; 0 for a single seed) and ``seeds``.

A deterministic method (supervised parameters, no random draw) gives the same outcome in every seed, so its sd
over seeds is 0 and says nothing. What varies its mean is which tasks were asked: :func:`bootstrap_ci` gives the
percentile interval (Efron and Tibshirani 1993, Sec. 13.3) of the mean of per-task terms over tasks resampled with
replacement, stratified by home (each home keeps its number of tasks, as the pooled mean weighs homes by their
tasks), ``BOOTSTRAP_RESAMPLES`` resamples drawn from a seeded generator. Tasks of one home share places, so the
interval reflects the variation of these tasks, not of homes one has not seen.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence

import numpy as np

BOOTSTRAP_RESAMPLES = 2000
CI_LEVEL = 0.95

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
        same = bool((values == values[0]).all())  # the same value every seed: exactly it, spread exactly 0
        out[key] = float(values[0]) if same else float(values.mean())  # (a float mean of equal values can miss)
        out[f"{key}_sd"] = float(values.std(ddof=1)) if len(values) > 1 and not same else 0.0
    out["seeds"] = len(per_seed)
    return out


def aggregate_methods(per_seed: Sequence[Mapping[str, Mapping]]) -> dict[str, dict]:
    """:func:`aggregate` for each method of ``{method: metrics}`` dictionaries (one per seed), methods in the
    first seed's order."""
    if not per_seed:
        return {}
    return {m: aggregate([d[m] for d in per_seed if m in d]) for m in per_seed[0]}


def bootstrap_ci(
    groups: Sequence[np.ndarray], seed: int, resamples: int = BOOTSTRAP_RESAMPLES, level: float = CI_LEVEL
) -> np.ndarray:
    """(k, 2) percentile intervals of the means of k per-task terms: ``groups`` holds one (n_h, k) array per home
    (module docstring); the pooled mean of a resample is sum_h counts_h @ terms_h / sum_h n_h, with counts_h the
    multinomial numbers of times each of the home's tasks is drawn.

    >>> bootstrap_ci([np.array([[1.0], [1.0], [1.0]])], seed=0).tolist()  # no variation, no width
    [[1.0, 1.0]]

    Raises:
        ValueError: no task, a level outside (0, 1) or fewer than 2 resamples.
    """
    groups = [np.asarray(g, dtype=float).reshape(len(g), -1) for g in groups if len(g)]
    if not groups:
        raise ValueError("no tasks to resample")
    if not 0.0 < level < 1.0 or resamples < 2:
        raise ValueError(f"need 0 < level < 1 and at least 2 resamples, got {level} and {resamples}")
    rng = np.random.default_rng(seed)
    sums = np.zeros((resamples, groups[0].shape[1]))
    for terms in groups:
        n = len(terms)
        sums += rng.multinomial(n, np.full(n, 1.0 / n), size=resamples) @ terms
    means = sums / sum(len(g) for g in groups)
    tail = 100.0 * (1.0 - level) / 2.0
    return np.percentile(means, [tail, 100.0 - tail], axis=0).T


def pm(values: Mapping, key: str, digits: int = 3, interval: bool = False) -> str:
    """``mean ± sd`` of ``key`` (just the mean when there is no ``<key>_sd`` or only one seed); with ``interval``
    and a ``<key>_ci`` (:func:`bootstrap_ci`), ``mean [low, high]`` instead."""
    sd, ci = values.get(f"{key}_sd"), values.get(f"{key}_ci")
    text = f"{values[key]:.{digits}f}"
    if interval and ci is not None:
        return f"{text} [{ci[0]:.{digits}f}, {ci[1]:.{digits}f}]"
    return text if sd is None or values.get("seeds", 1) <= 1 else f"{text} ± {sd:.{digits}f}"
