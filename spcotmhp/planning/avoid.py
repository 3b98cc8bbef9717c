"""Avoidance views of a planning graph: "avoid the dining room" (Algorithm 1 with the avoided places' p(x|m) = 0).

Avoided places (:func:`avoided_view`, a view of a :class:`~spcotmhp.planning.graph.PlanningGraph`) block their
territories: "avoid the dining room" keeps the robot out of every cell that belongs to the dining room, the same
cells the explanation calls the dining room. Blocking cells only removes paths, so a field value whose optimal
path does not enter the blocked cells is still optimal; the view shares those fields with its graph and
recomputes (exactly, with the region blocked) only the fields whose path from a node (:func:`avoided_view`) or
from the query's start (:func:`refresh_shared`, run by :meth:`AvoidanceView.start_w_hat`) crosses the region,
checked by walking the stored next-step links. A portal-graph graph (:mod:`spcotmhp.planning.hierarchy`) drops
the avoided territories' abstract nodes instead: no territory-local field enters another territory, so every
kept field stays exact.

Memos and threads: a graph keeps its most recent views (``AVOID_CACHE_SIZE``) in ``_views``, a
:class:`~spcotmhp.planning.graph_cache.GraphCache` (a view is computed outside its lock: two threads that miss on
the same places both compute it; the first stored is the one both get), and a view recomputes shared fields on
demand in :func:`refresh_shared`, under the view's own lock (``graph._lock``), so concurrent queries on one graph
are safe. Readers of a view's
fields take no lock: a shared field is only ever replaced whole by its exact version for the blocked map, which
has the same value wherever the shared one was valid for a reader's start.
"""

from __future__ import annotations

import time

import numpy as np

from spcotmhp.planning._paths import crosses, crossing_fields
from spcotmhp.planning.graph import PlanningGraph


class AvoidanceView(PlanningGraph):
    """A planning graph with places avoided (``blocked``, ``usable``), made by :func:`avoided_view`: the graph's
    queries, with the start leg made exact for the blocked map first (:func:`refresh_shared`)."""

    def start_w_hat(self, cell: np.ndarray) -> np.ndarray:
        refresh_shared(self, cell)
        return super().start_w_hat(cell)


def avoided_view(graph: PlanningGraph, places: tuple[int, ...]) -> PlanningGraph:
    """The view of ``graph`` with no node in ``places`` whose paths never enter their territories, exact for the
    blocked map (module docstring), memoised in ``graph`` for the most recent place sets."""
    key = tuple(sorted(int(p) for p in places))
    return graph._views.get_or_build(key, lambda: _build_view(graph, key))


def _build_view(graph: PlanningGraph, key: tuple[int, ...]) -> PlanningGraph:
    """The avoidance view of ``graph`` for the places ``key`` (not memoised: :func:`avoided_view` does that)."""
    t0 = time.perf_counter()
    blocked = np.isin(graph.territory, key)
    usable = ~np.isin(graph.node_place, key) & ~blocked[graph.node_cell[:, 0], graph.node_cell[:, 1]]
    if graph.hier is not None:
        return _hier_view(graph, key, blocked, usable, t0)
    base = (graph.dist, graph.next_step) if isinstance(graph.next_step, np.ndarray) else None
    view = _view(graph, key, blocked, usable, dist=list(graph.dist), next_step=list(graph.next_step), _base_fields=base)
    width = graph.log_p.shape[1]
    sources = graph.node_cell[:, 0] * width + graph.node_cell[:, 1]
    flat_blocked = blocked.reshape(-1)
    recomputed = []
    for j in np.flatnonzero(usable):
        into_j = usable.copy()  # every node: the metric fallback may join any two
        into_j[j] = False
        links = graph.next_step[j].reshape(-1)
        if any(crosses(links, int(sources[i]), flat_blocked) for i in np.flatnonzero(into_j)):
            view.dist[j], view.next_step[j] = view._field(int(j))
            recomputed.append(int(j))
        else:
            view._shared.add(int(j))
    view._edges()
    view.info["recomputed_fields"] = recomputed
    view.time_precompute_s = time.perf_counter() - t0
    return view


def refresh_shared(view: PlanningGraph, cell: np.ndarray) -> None:
    """Recompute (and keep) every field that ``view`` still shares with its graph and whose path from crop cell
    ``cell`` enters the blocked region, so that the fields are exact for the blocked map at ``cell``."""
    r, c = int(cell[0]), int(cell[1])
    with view._lock:
        if not view._shared:
            return
        start = r * view.log_p.shape[1] + c
        assert view.blocked is not None  # only views share fields
        if view._base_fields is not None:  # every shared field in one kernel
            dist, links = view._base_fields
            shared = np.array(sorted(view._shared), dtype=np.int64)
            crossing = crossing_fields(dist, links, shared, r, c, view.blocked).tolist()
        else:
            crossing = [
                j
                for j in sorted(view._shared)
                if np.isfinite(view.dist[j][r, c])
                and crosses(view.next_step[j].reshape(-1), start, view.blocked.reshape(-1))
            ]
        for j in crossing:
            view.dist[j], view.next_step[j] = view._field(j)
            view._shared.discard(j)
            view.info["recomputed_fields"].append(int(j))


def _view(graph: PlanningGraph, key: tuple, blocked: np.ndarray, usable: np.ndarray, **kw) -> AvoidanceView:
    return AvoidanceView(
        model=graph.model,
        settings=graph.settings,
        key=graph.key,
        offset=graph.offset,
        log_p=graph.log_p,
        traversable=graph.traversable & ~blocked,
        node_place=graph.node_place,
        node_cell=graph.node_cell,
        end_term=graph.end_term,
        w_hat=np.empty(0),
        w_hat_metric=np.empty(0),
        log_transition=np.empty(0),
        connected=graph.connected,
        time_precompute_s=0.0,
        info={**graph.info, "avoided": key},
        blocked=blocked,
        usable=usable,
        _centres=graph._centres,  # computed by the view itself if ever needed (16 bytes a cell)
        territory=graph.territory,
        main=graph.main,
        _territories=graph._territories,
        **kw,
    )


def _hier_view(graph: PlanningGraph, key: tuple, blocked: np.ndarray, usable: np.ndarray, t0: float) -> PlanningGraph:
    """The avoidance view of a portal-graph graph: the avoided territories' abstract nodes removed; no local field
    enters another territory, so every kept field stays exact (:mod:`~spcotmhp.planning.hierarchy`)."""
    assert graph.hier is not None  # called for portal-graph graphs only
    view = _view(graph, key, blocked, usable, dist=[], next_step=[], hier=graph.hier.without(key))
    view._edges()
    view.info["recomputed_fields"] = []
    view.time_precompute_s = time.perf_counter() - t0
    return view
