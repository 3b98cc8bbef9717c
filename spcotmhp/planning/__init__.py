"""Hierarchical path planning from instructions (SpCoTMHP, Algorithm 1; Taniguchi, Ito and Taniguchi 2024).

    >>> from spcotmhp.datasets import load_bundled
    >>> from spcotmhp.learning.supervised import fit_supervised
    >>> from spcotmhp.planning import HierarchicalPlanner
    >>> model = fit_supervised(load_bundled("3LDK_06"))         # the paper's "ideal" parameters of a home
    >>> planner = HierarchicalPlanner(model)                     # precomputation (Alg. 1, lines 1-7)
    >>> plan = planner.plan("go to the bedroom via the corridor", start=(-3.95, -3.55))
    >>> plan.explanation
    'entrance -> corridor (waypoint) -> dining -> bedroom #3 (closest of 3 bedrooms), 10.3 m'

Modules: ``instructions`` + ``grammar`` (understanding), ``places`` (candidates, connectivity, instances,
regions), ``graph`` (precomputation), ``search`` (Eq. 28), ``assemble`` (joining, smoothing), ``planner``,
``graph_cache`` (graphs shared by the planners given one cache), ``avoid`` (avoidance views of a graph), ``plan``
(the result), ``terms`` (model terms for fast queries), ``vocabulary`` (place words and labels).
Pictures of plans are drawn by :mod:`spcotmhp.viz.plan`.
"""

from spcotmhp.planning.graph import GraphSettings, PlanningGraph
from spcotmhp.planning.graph_cache import GraphCache
from spcotmhp.planning.instructions import (
    Instruction,
    PlaceQuery,
    parse_nbest,
    parse_structured,
    parse_text,
    to_instruction,
)
from spcotmhp.planning.plan import Plan, PlanPlace
from spcotmhp.planning.planner import HierarchicalPlanner, PlannerSettings
from spcotmhp.planning.vocabulary import place_labels, place_vocabulary

# the one-call ``plan(model, instruction, start)`` lives in spcotmhp.planning.planner (exporting it here would
# hide the ``spcotmhp.planning.plan`` module)

__all__ = [
    "GraphCache",
    "GraphSettings",
    "HierarchicalPlanner",
    "Instruction",
    "PlaceQuery",
    "Plan",
    "PlanPlace",
    "PlannerSettings",
    "PlanningGraph",
    "parse_nbest",
    "parse_structured",
    "parse_text",
    "place_labels",
    "place_vocabulary",
    "to_instruction",
]
