"""A picture of a plan (the ``--png`` of ``spcotmhp plan`` and of the demo): map, places, edges, the path with
its start, waypoints and goal marked, and the explanation as the title."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from spcotmhp.learning.model import SpatialConceptModel
from spcotmhp.planning.plan import Plan
from spcotmhp.viz.draw import render


def plan_marks(plan: Plan) -> list[tuple[np.ndarray, str, str]]:
    """[(xy, label, role)]: the start pose, then every waypoint and the goal where the plan reaches them."""
    marks = [(np.asarray(plan.path[0], dtype=float), plan.places[0].label, "start")]
    marks += [
        (np.asarray(p.point, dtype=float), p.label, p.role)
        for p in plan.places[1:]
        if p.role in ("waypoint", "goal") and p.point is not None
    ]
    return marks


def draw_plan(plan: Plan, model: SpatialConceptModel, out: str | Path, dpi: int = 150) -> Path:
    """Write a PNG of ``plan`` over ``model``'s map; returns the file written."""
    return render(
        model.require_map(),
        Path(out),
        model=model,
        path_xy=plan.path,
        marks=plan_marks(plan),
        title=plan.explanation,
        dpi=dpi,
    )
