"""The graph cache the tests share (:class:`~spcotmhp.planning.graph_cache.GraphCache`): planners of one model
in different tests reuse one precomputed graph, as the package's own callers do by passing one cache around."""

from __future__ import annotations

from spcotmhp.planning.graph_cache import GraphCache

GRAPHS = GraphCache(size=32)
