"""Compile every numba kernel once, ahead of the first real use, into numba's on-disk cache.

Every kernel of the package is ``@njit(cache=True)``: the first call in the first process compiles it (tens of
seconds for all of them together), later processes load the compiled code from the cache. :func:`warm_up`
makes that first call on a small seeded synthetic home, through the same code paths (and so the same argument
types) as real use: unsupervised learning (Gibbs sampling, one short run), the supervised fit, the cost map,
the planning graph and plans with a waypoint, a place to avoid and the metric fallback, and the grid searches.
``make demo`` runs it right after installing (``spcotmhp warmup``), so the demo itself starts warm.

Where the cache lives: numba writes it next to the package's sources when they are writable and otherwise in
the user's cache folder; :func:`spcotmhp.numba_cache.cache_dir_default` (run when the package is imported) points
``NUMBA_CACHE_DIR`` at ``$XDG_CACHE_HOME/spcotmhp/numba`` (default ``~/.cache``) when the package folder is not
writable and the variable is unset, so the cache is shared by every environment of the user.
"""

from __future__ import annotations

import contextlib
import time
import warnings

__all__ = ["warm_up"]


def warm_up() -> float:
    """Run every compiled kernel once on a small synthetic home (module docstring); returns the seconds spent."""
    import numpy as np

    from spcotmhp.datasets.synthetic import generate_environment
    from spcotmhp.errors import SpcotmhpError
    from spcotmhp.learning.gibbs import SpCoTMHP
    from spcotmhp.learning.selection import MultiRunSelector
    from spcotmhp.learning.supervised import fit_supervised
    from spcotmhp.metric import grid_search
    from spcotmhp.planning.places import main_component
    from spcotmhp.planning.planner import HierarchicalPlanner

    t0 = time.perf_counter()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        grid_search.warmup()
        data = generate_environment("flat", seed=0, events_per_room=4)
        learned = MultiRunSelector(SpCoTMHP(iterations=3, seed=0), runs=1).fit(data).model_
        for model in (fit_supervised(data), learned):
            model.log_place_given_words(model.vocabulary[:1])  # Eq. 28's word term from numpy (the baselines)
            # Eq. 28 on all pairs; the reference graph; the portal graph of building-scale maps
            for settings in ({}, {"adjacent_only": True}, {"max_dense_bytes": 0}):
                planner = HierarchicalPlanner(model, **settings)  # a cache of its own, dropped after
                graph = planner.graph
                names = sorted(set(planner.spoken_names(np.flatnonzero(model.active_places))))
                if not names:  # a learned place whose events carry no name is "place k": nothing to say
                    continue
                free = np.argwhere(main_component(graph.traversable))
                start = model.require_map().cell_to_world(graph.to_map(free[len(free) // 2]))
                for text in (
                    f"go to the {names[-1]}",
                    f"go to the {names[-1]} via the {names[0]}",
                    f"go to the {names[-1]} avoiding the {names[0]}",
                ):
                    with contextlib.suppress(SpcotmhpError):  # a refused plan has compiled what it needs
                        planner.plan(text, start)
        _goal_option_bounds()
    return time.perf_counter() - t0


def _goal_option_bounds() -> None:
    """The goal options' bounds kernel (:meth:`~spcotmhp.planning.search.SearchResult.anchor_octiles`), which a
    plan reads only when the goal's name is shared (not always so on the small home): on a two-node search."""
    import numpy as np

    from spcotmhp.planning.search import SearchProblem, search

    result = search(SearchProblem(np.zeros((2, 2)), np.zeros(2), np.zeros((1, 2)), np.ones((1, 2), bool), 2))
    if result is not None:
        result.anchor_octiles(np.arange(2), np.zeros((2, 2), dtype=np.int64), np.zeros(2, dtype=np.int64))
