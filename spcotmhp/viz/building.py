"""Pictures of a plan in a building: one PNG per floor the route crosses, each that floor's map, places and route
segment, with the start, the waypoints and goal reached there and the connector stops where the robot boards or
leaves a stair or lift (role "stairs" / "lift"), titled with the floor and the whole plan's explanation."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from spcotmhp.building.model import BuildingModel
from spcotmhp.building.plan import BuildingPlan
from spcotmhp.viz.draw import render


def floor_picture_path(out: str | Path, floor: int) -> Path:
    """Where the picture of ``floor`` goes for ``--png out``: ``<stem>-floor<F><suffix>`` beside it.

    >>> floor_picture_path("runs/route.png", 2).as_posix()
    'runs/route-floor2.png'
    """
    out = Path(out)
    return out.with_name(f"{out.stem}-floor{floor}{out.suffix or '.png'}")


def segment_marks(plan: BuildingPlan, k: int) -> list[tuple[np.ndarray, str, str]]:
    """[(xy, label, role)] of segment ``k``: the start (first segment) or the stop it arrives at, the waypoints
    and goal reached on it, and the stop it leaves from."""
    seg = plan.segments[k]
    marks: list[tuple[np.ndarray, str, str]] = []
    if k == 0:
        marks.append((np.asarray(seg.path[0], dtype=float), seg.places[0].label if seg.places else "start", "start"))
    else:
        r = plan.rides[k - 1]
        marks.append((np.asarray(r.leave[1], dtype=float), f"{r.name} from floor {r.board[0]}", r.kind))
    marks += [
        (np.asarray(p.point, dtype=float), p.label, p.role)
        for p in seg.places
        if p.role in ("waypoint", "goal") and p.point is not None
    ]
    if k < len(plan.rides):
        r = plan.rides[k]
        marks.append((np.asarray(r.board[1], dtype=float), f"{r.name} to floor {r.leave[0]}", r.kind))
    return marks


def picture_paths(plan: BuildingPlan, out: str | Path) -> list[Path]:
    """The file of each segment's picture (:func:`floor_picture_path`; a floor crossed again gets ``-<n>``)."""
    paths: list[Path] = []
    seen: dict[int, int] = {}
    for seg in plan.segments:
        seen[seg.floor] = seen.get(seg.floor, 0) + 1
        path = floor_picture_path(out, seg.floor)
        paths.append(path if seen[seg.floor] == 1 else path.with_name(f"{path.stem}-{seen[seg.floor]}{path.suffix}"))
    return paths


def draw_segment(plan: BuildingPlan, bm: BuildingModel, k: int, out: str | Path, dpi: int = 150) -> Path:
    """Write the PNG of segment ``k`` over its floor's map (module docstring); returns the file written."""
    seg = plan.segments[k]
    view = bm.floor_model(seg.floor)
    title = f"{plan.floor_label(seg.floor)}, part {k + 1} of {len(plan.segments)}: {plan.explanation}"
    return render(view.require_map(), Path(out), model=view, path_xy=seg.path, marks=segment_marks(plan, k),
                  title=title, dpi=dpi)  # fmt: skip


def draw_building_plan(plan: BuildingPlan, bm: BuildingModel, out: str | Path, dpi: int = 150) -> list[Path]:
    """One PNG per segment (:func:`picture_paths` of ``out``); returns the files written."""
    return [draw_segment(plan, bm, k, path, dpi) for k, path in enumerate(picture_paths(plan, out))]
