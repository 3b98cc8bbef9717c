"""The caller-owned graph cache: bounded LRU, shared only by who shares the object, safe from threads."""

from __future__ import annotations

import pickle
import time

import numpy as np
import pytest

from spcotmhp.errors import ModelError
from spcotmhp.planning import graph as graph_module
from spcotmhp.planning import graph_cache
from spcotmhp.planning.graph_cache import GraphCache
from spcotmhp.planning.planner import HierarchicalPlanner
from tests.helpers.planning import home_log_p, home_model
from tests.helpers.threads import in_threads


def planner(cache: GraphCache | None = None, **kw) -> HierarchicalPlanner:
    model = home_model()
    return HierarchicalPlanner(model, log_p=home_log_p(model.map), cache=cache, **kw)


def test_a_shared_cache_gives_every_planner_the_same_graph():
    cache = GraphCache()
    a, b = planner(cache), planner(cache, smooth=False)  # planner settings that do not change the graph
    assert a.cache is b.cache is cache and a.graph is b.graph and len(cache) == 1
    c = planner(cache, n_candidates=2)  # a graph setting: another graph in the same cache
    assert c.graph is not a.graph and len(cache) == 2


def test_planners_with_separate_caches_share_no_memo():
    a, b = planner(), planner()  # each makes a cache of its own
    assert a.cache is not b.cache and a.graph is not b.graph and a.graph.key == b.graph.key
    start = a.model.mu[3]  # bedroom #2, next to the kitchen
    a.plan("go to the kitchen via the corridor", a.model.mu[0])
    a.graph.edge_path(0, 1)  # a partial path between two nodes (plans on dense fields read them without the memo)
    a.plan("go to the kitchen avoiding the corridor", start)  # an avoidance view
    assert a.graph._paths and a.graph._views
    assert not b.graph._paths and not b.graph._views
    assert b.plan("go to the kitchen avoiding the corridor", start).explanation == (
        a.plan("go to the kitchen avoiding the corridor", start).explanation
    )


def test_the_cache_keeps_the_most_recently_used_graphs():
    cache = GraphCache(size=2)
    made = {k: object() for k in "abc"}
    built = []

    def build(key):
        built.append(key)
        return made[key]

    assert cache.get_or_build("a", lambda: build("a")) is made["a"]
    cache.get_or_build("b", lambda: build("b"))
    assert cache.get_or_build("a", lambda: build("a")) is made["a"]  # a hit: a is now the most recent
    cache.get_or_build("c", lambda: build("c"))  # evicts b, the least recently used
    assert "a" in cache and "c" in cache and "b" not in cache and built == ["a", "b", "c"]
    cache.clear()
    assert len(cache) == 0


@pytest.mark.parametrize("size", [0, -1, 1.5, True, "8"])
def test_a_cache_must_hold_at_least_one_graph(size):
    with pytest.raises(ModelError, match="at least one graph"):
        GraphCache(size=size)


def test_threads_that_miss_together_all_get_the_graph_kept():
    cache = GraphCache()

    def build():
        time.sleep(0.01)
        return object()

    got = in_threads(6, range(6), lambda _: cache.get_or_build("k", build))
    assert all(g is got[0] for g in got) and len(cache) == 1


def test_no_module_level_graph_cache():
    for module in (graph_module, graph_cache):
        mutable = [n for n, v in vars(module).items() if isinstance(v, (dict, list, set)) and not n.startswith("__")]
        assert mutable == []
    assert not hasattr(graph_module, "clear_cache")


def test_a_pickled_planner_gets_its_own_locks_and_the_same_graph():
    p = planner()
    copy = pickle.loads(pickle.dumps(p))  # what a process pool or Ray does with an evaluation's planners
    g, h = p.graph, copy.graph
    assert h._lock is not g._lock and copy.cache._lock is not p.cache._lock
    assert np.array_equal(h.w_hat, g.w_hat) and np.array_equal(h.dist, g.dist)
    assert copy.cache.get_or_build(g.key, object) is h  # the copy's cache holds the copy's graph
    start = p.model.mu[3]
    assert copy.plan("go to the kitchen avoiding the corridor", start).explanation == (
        p.plan("go to the kitchen avoiding the corridor", start).explanation
    )
