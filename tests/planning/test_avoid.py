"""Avoidance views under concurrent queries: threads that share one graph get the values one thread gets."""

from __future__ import annotations

import warnings

import numpy as np

from spcotmhp.datasets.bundled import load_bundled
from spcotmhp.learning.supervised import fit_supervised
from spcotmhp.planning.avoid import avoided_view
from spcotmhp.planning.graph import AVOID_CACHE_SIZE, PlanningGraph
from tests.helpers.threads import in_threads

PLACE_SETS = [(10,), (6,), (4, 9), (2,)]  # corridor, dining, living + washroom, kitchen of 3LDK_06


def model():
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return fit_supervised(load_bundled("3LDK_06"))


def test_threads_sharing_a_graph_see_what_one_thread_sees():
    m = model()
    shared, alone = PlanningGraph.build(m), PlanningGraph.build(m)  # two graphs: no memo in common
    free = np.argwhere(shared.traversable)
    cells = free[np.random.default_rng(1).integers(len(free), size=40)]
    jobs = [(places, cell) for places in PLACE_SETS for cell in cells]

    def query(graph, places, cell):
        view = avoided_view(graph, places)
        if view.blocked[cell[0], cell[1]]:
            return None
        return view.start_w_hat(cell), view.leg(cell, int(np.argmax(view.start_w_hat(cell)))).cost

    want = [query(alone, *job) for job in jobs]
    got = in_threads(6, jobs, lambda job: query(shared, *job))
    for g, w in zip(got, want, strict=True):
        assert (g is None) == (w is None)
        if w is not None:
            assert np.array_equal(g[0], w[0]) and g[1] == w[1]
    for places in PLACE_SETS:  # one view per place set, whichever thread made it
        assert avoided_view(shared, places) is shared._views[tuple(sorted(places))]
    assert len(shared._views) == len(PLACE_SETS) <= AVOID_CACHE_SIZE
