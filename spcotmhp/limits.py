"""Upper bounds of the counts and sizes that commands and library constructors accept, in one place.

Every count a user chooses (runs, sweeps, truncation levels, rooms, events, map side, seeds, workers, candidate
points, the topological horizon) is checked against these bounds where it enters (the command's option, the
constructor or ``fit``), before anything is allocated, with a one-line typed error naming the setting, its value
and the accepted range (:func:`check_count`). Each bound is far above any use the paper or the bundled homes
make, and low enough that what it sizes fits in memory:

- ``MAX_PLACES`` / ``MAX_CONCEPTS`` (K, L of the learners' Dirichlet-process truncations; the paper uses 20):
  the sampler keeps K x K transition counts and L x K, L x V tables, and one (E, K) table of place densities per
  sweep; 1,000 keeps K x K at 8 MB and, with ``MAX_EVENT_PLACES``, the (E, K) tables at most 400 MB. The model
  loader's own caps (``MODEL_MAX_SIZES``) are larger, so every model the learners write loads.
- ``MAX_EVENT_PLACES``: events x K of one fit (the (E, K) float64 tables: 400 MB).
- ``MAX_RUNS`` (independent Gibbs runs; the paper keeps 1 of 10) and ``MAX_ITERATIONS`` (sweeps per run; the
  paper: 100; also the online learner's resamples and moves per event): a fit keeps every run's model and one
  log joint per sweep.
- ``MAX_JOBS``: worker processes (and evaluation workers).
- ``MAX_SEEDS``: seeds of an evaluation (each one a full learning or planning pass).
- ``MAX_SYNTH_ROOMS``, ``MAX_SYNTH_EVENTS`` (rooms x events per room of a synthetic teaching walk: its
  teaching.csv stays well under the loader's 64 MiB CSV cap) and the synthetic map's pixels, at most the map
  loader's cap (``spcotmhp.safe_read.max_map_pixels``, 16,000,000 by default) and its aspect ratio
  (``spcotmhp.safe_read.MAX_MAP_ASPECT``, 1000:1), so that ``check-dataset`` loads every dataset ``synth`` writes.
- ``MAX_CANDIDATES`` (candidate points per place, N of Section 3.4; the paper: 1) and ``MAX_STEPS`` (the
  topological horizon E of Eq. 28, per stage or in all): the search's tables hold steps x nodes x stages.
"""

from __future__ import annotations

import numpy as np

MAX_PLACES = 1_000
MAX_CONCEPTS = 1_000
MAX_EVENT_PLACES = 50_000_000
MAX_RUNS = 1_000
MAX_ITERATIONS = 100_000
MAX_JOBS = 256
MAX_SEEDS = 1_000
MAX_HOMES = 10_000
MAX_SYNTH_ROOMS = 1_000
MAX_SYNTH_EVENTS = 200_000
MAX_CANDIDATES = 100
MAX_STEPS = 1_000
MAX_GRAPH_BYTES = 8 * 2**30
"""Bytes of arrays a saved planning graph (graph.npz beside a model, :mod:`spcotmhp.planning.graph_store`) may
describe, counted at 8 bytes a number (1 a tree code) before anything is read: a 16-megapixel office's graph
with 200 places (the largest map the loader takes) describes 2.1 GiB at that count, so a file asking for four
times more is damaged or hostile."""
MODEL_MAX_SIZES = {"K": 10_000, "L": 10_000, "V": 1_000_000, "D": 100_000}
"""Largest sizes of a model file the loader accepts (``spcotmhp.persistence.model_checks``)."""
MODEL_MAX_ELEMENTS = 32 * 1024 * 1024
"""Numbers in all arrays of arrays.npz together, and in learner.npz (256 MiB of float64 each): a model folder
holds at most this many numbers in each, checked from model.json and learner.json before either is hashed."""


def is_count(value: object) -> bool:
    """Whether ``value`` is an integer (a Python or numpy int, not a bool)."""
    return isinstance(value, (int, np.integer)) and not isinstance(value, bool)


def check_count(value: object, name: str, low: int, high: int, error: type[Exception]) -> int:
    """``value`` as an int when it is an integer in [low, high], else ``error`` naming ``name``, the value and
    the range.

    >>> check_count(3, "runs", 1, MAX_RUNS, ValueError)
    3
    >>> check_count(10**9, "runs", 1, MAX_RUNS, ValueError)
    Traceback (most recent call last):
    ...
    ValueError: runs must be an integer in [1, 1000], got 1000000000
    """
    if not is_count(value) or not low <= value <= high:  # type: ignore[operator]
        raise error(f"{name} must be an integer in [{low}, {high}], got {value!r}")
    return int(value)  # type: ignore[call-overload]


def check_event_places(n_events: int, K: int, error: type[Exception]) -> None:
    """``error`` when a fit of ``n_events`` events with ``K`` places needs (E, K) tables of more than
    ``MAX_EVENT_PLACES`` numbers."""
    if n_events * K > MAX_EVENT_PLACES:
        raise error(
            f"{n_events} events x K={K} places is {n_events * K} numbers per (E, K) table, more than the "
            f"{MAX_EVENT_PLACES} accepted; use a smaller K (max places)"
        )
