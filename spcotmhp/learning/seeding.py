"""The random stream of one Gibbs run (``make_rng``), shared by the batch and online learners."""

from __future__ import annotations

import numpy as np

from spcotmhp.errors import ModelError


def make_rng(seed: int | np.random.SeedSequence, run: int | None = None) -> np.random.Generator:
    """The generator of one run: run r of seed s uses the r-th child of SeedSequence(s) (what
    ``SeedSequence(s).spawn`` would give), independent of the others; ``run=None`` uses the seed itself.
    Raises ModelError for a seed or run that is not a non-negative integer."""
    if not isinstance(seed, np.random.SeedSequence) and not is_count(seed):
        raise ModelError(f"seed must be a non-negative integer (or a numpy SeedSequence), got {seed!r}")
    if run is not None and not is_count(run):
        raise ModelError(f"run must be a non-negative integer or None, got {run!r}")
    ss = seed if isinstance(seed, np.random.SeedSequence) else np.random.SeedSequence(int(seed))
    if run is not None:
        ss = np.random.SeedSequence(ss.entropy, spawn_key=tuple(ss.spawn_key) + (int(run),))
    return np.random.default_rng(ss)


def is_count(value: object) -> bool:
    """A non-negative integer (numpy integers included, booleans not)."""
    return isinstance(value, (int, np.integer)) and not isinstance(value, bool) and bool(value >= 0)


def seed_repr(seed: int | np.random.SeedSequence) -> int | str:
    return int(seed) if not isinstance(seed, np.random.SeedSequence) else str(seed.entropy)
