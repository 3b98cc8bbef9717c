"""A picture of a plan (the ``--png`` of ``spcotmhp plan``): map, places, edges, the path and its marks.

Plotting stays at the edge: this only maps a :class:`Plan` onto :func:`spcotmhp.viz.draw.render`.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from spcotmhp.learning.model import SpatialConceptModel
from spcotmhp.planning.plan import Plan


def draw_plan(plan: Plan, model: SpatialConceptModel, out: str | Path, dpi: int = 150) -> Path:
    """Write a PNG of ``plan`` over ``model``'s map; returns the file written."""
    from spcotmhp.viz.draw import render

    marks = [(np.asarray(plan.path[0]), plan.places[0].label, "start")]
    marks += [(np.asarray(p.point), p.label, p.role) for p in plan.places[1:]
              if p.role in ("waypoint", "goal") and p.point is not None]
    return render(model.map, out, model=model, path_xy=plan.path, marks=marks, title=plan.explanation, dpi=dpi)
