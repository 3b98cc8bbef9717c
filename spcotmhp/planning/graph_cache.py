"""A cache of planning graphs that its caller owns (Algorithm 1, lines 1-7, done once per model, map and settings).

The precomputation (:class:`~spcotmhp.planning.graph.PlanningGraph`) takes from milliseconds to minutes, so code
that builds several planners over the same model (the evaluation, the benchmarks, a service's teach-and-replan
loop, the tests) shares one :class:`GraphCache` and passes it to each
:class:`~spcotmhp.planning.planner.HierarchicalPlanner` (``cache=``); a planner given none makes its own. There is
no module-level cache: who shares a graph is decided by who shares the cache object.

A graph is keyed by :func:`~spcotmhp.planning.graph_settings.fingerprint` (a hash of the model's parameters, the
map, the cost map and the graph settings), so a changed model or map never reuses a stale graph. The cache is
thread-safe (one lock, held only for look-ups and insertions, never while a graph is computed: two threads that
miss on the same key both compute it, and the first to finish is the one kept and returned to both).
"""

from __future__ import annotations

import threading
from collections import OrderedDict
from collections.abc import Callable, Hashable
from typing import Any, TypeVar

from spcotmhp.errors import ModelError

CACHE_SIZE = 8
G = TypeVar("G")  # a planning graph (this module does not import the graph's, so that the graph may import it)


class GraphCache:
    """A bounded least-recently-used table of planning graphs, key -> graph (module docstring; a graph keeps its
    avoidance views in one too, keyed by the avoided places).

    >>> cache = GraphCache(size=2)
    >>> len(cache), "some key" in cache
    (0, False)
    """

    def __init__(self, size: int = CACHE_SIZE) -> None:
        if isinstance(size, bool) or not isinstance(size, int) or size < 1:
            raise ModelError(f"a graph cache holds at least one graph; got size={size!r}")
        self.size = size
        self._graphs: OrderedDict[Hashable, Any] = OrderedDict()
        self._lock = threading.Lock()

    def get_or_build(self, key: Hashable, build: Callable[[], G]) -> G:
        """The graph cached under ``key``, else ``build()`` stored under it (evicting the least recently used
        graph beyond ``size``). ``build`` runs outside the lock (module docstring)."""
        with self._lock:
            if key in self._graphs:
                self._graphs.move_to_end(key)
                return self._graphs[key]
        graph = build()
        with self._lock:
            graph = self._graphs.setdefault(key, graph)
            self._graphs.move_to_end(key)
            while len(self._graphs) > self.size:
                self._graphs.popitem(last=False)
        return graph

    def __getitem__(self, key: Hashable) -> Any:
        with self._lock:
            return self._graphs[key]

    def __contains__(self, key: object) -> bool:
        with self._lock:
            return key in self._graphs

    def __len__(self) -> int:
        with self._lock:
            return len(self._graphs)

    def __getstate__(self) -> dict:
        """Pickled (with a planner, for a process pool or Ray: every graph it holds) without the lock; the copy
        gets its own."""
        with self._lock:
            return {"size": self.size, "graphs": list(self._graphs.items())}

    def __setstate__(self, state: dict) -> None:
        self.size = state["size"]
        self._graphs = OrderedDict(state["graphs"])
        self._lock = threading.Lock()

    def clear(self) -> None:
        """Forget every cached graph."""
        with self._lock:
            self._graphs.clear()
