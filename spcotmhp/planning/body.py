"""A model planned for another robot body, without learning again.

The learned parameters (places, concepts, words) do not depend on the robot; the cost map p(x|m) and everything
derived from it (the planning graph, its partial paths, the escape from a start near an obstacle) do, and are
recomputed from the model's stored map: :func:`with_body` returns the model with the body's cost map settings,
and a planner built on it computes its graph afresh (the graph's fingerprint includes the cost map settings,
:func:`~spcotmhp.planning.graph_settings.fingerprint`).
"""

from __future__ import annotations

import dataclasses

from spcotmhp.learning.model import SpatialConceptModel
from spcotmhp.metric.body import RobotBody


def with_body(model: SpatialConceptModel, body: RobotBody | None) -> SpatialConceptModel:
    """``model`` with ``body``'s cost map settings and the body recorded in ``info["body"]`` (its shape and
    source, kept with the model when saved); ``model`` itself when ``body`` is None."""
    if body is None:
        return model
    info = dict(model.info)
    info["body"] = body_info(body)
    return dataclasses.replace(model, costmap=body.costmap(), info=info)


def body_info(body: RobotBody) -> dict:
    """The JSON record of a body kept in a model's info (the cost map settings are in ``costmap``)."""
    return {
        "description": body.describe(),
        "source": body.source,
        "footprint": None if body.footprint is None else [list(p) for p in body.footprint],
    }
