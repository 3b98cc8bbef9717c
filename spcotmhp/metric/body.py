"""The robot's body as costmap_2d sees it: a circle or a footprint polygon, and the inflation layer's settings.

A :class:`RobotBody` holds what the cost map needs of the robot (:mod:`spcotmhp.metric.costmap`):

* **inscribed radius**: the smallest distance from the robot's centre to its footprint's edges; cells within it of
  an obstacle cost INSCRIBED (253), where the robot overlaps the obstacle whatever its heading, and the
  inflation's exponential decay starts there (``computeCost``);
* **circumscribed radius**: the largest distance from the centre to a vertex; below the cost at that distance
  (``getCircumscribedCost``) no heading of the footprint touches an obstacle;
* the inflation layer's ``inflation_radius`` and ``cost_scaling_factor``.

Both radii of a polygon are costmap_2d's ``calculateMinAndMaxDistances`` (footprint.cpp): over every vertex and
every edge (the closing edge too), the minimum and the maximum of the vertex distance and the distance to the
edge segment. A circle of radius r given directly is exactly that circle (both radii r). A body read from a Nav2
params file is what Nav2 builds (:mod:`spcotmhp.metric.nav2_params`): ``robot_radius`` becomes
``makeFootprintFromRadius``'s 16-gon and every footprint is padded by ``footprint_padding``, then measured as above.

Ranges (one :class:`~spcotmhp.errors.RobotBodyError` line otherwise): radii and coordinates finite and within
``MAX_BODY_M`` = 100 m (no robot is larger; the cell arithmetic stays exact); a polygon of 3 to
``MAX_FOOTPRINT_POINTS`` = 1000 points with the robot's centre strictly inside (the radii are measured from it);
``inflation_radius`` finite in [0, ``MAX_INFLATION_M`` = 1e4 m] and at least the inscribed radius (below it the
inflation stops before the inscribed distance, and cells where the robot overlaps an obstacle would be planned
through; costmap_2d logs the same as an error); ``cost_scaling_factor`` finite in [0, 1e6] (the model's range).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

from spcotmhp.errors import RobotBodyError
from spcotmhp.metric.costmap import DEFAULT_COSTMAP

MAX_BODY_M = 100.0
MAX_FOOTPRINT_POINTS = 1000
MAX_INFLATION_M = 1e4
MAX_SCALING = 1e6
RADIUS_POLYGON_POINTS = 16  # costmap_2d's makeFootprintFromRadius


@dataclass(frozen=True)
class RobotBody:
    """A robot's body for the cost map (module docstring). ``footprint``: the polygon measured (map metres in the
    robot's frame, after any padding), None for a circle given by its radius."""

    inscribed_radius: float
    circumscribed_radius: float
    inflation_radius: float = DEFAULT_COSTMAP.inflation_radius
    cost_scaling_factor: float = DEFAULT_COSTMAP.cost_scaling_factor
    footprint: tuple[tuple[float, float], ...] | None = None
    source: str = "options"

    def __post_init__(self) -> None:
        for name, low, high in (
            ("inscribed_radius", 0.0, MAX_BODY_M),
            ("circumscribed_radius", 0.0, MAX_BODY_M),
        ):
            value = getattr(self, name)
            if not (_number(value) and low < value <= high):
                raise RobotBodyError(
                    f"{self.source}: the robot's {name} must be a number in (0, {high:g}] m, got {value!r}"
                )
        _check_inflation(self.inflation_radius, self.cost_scaling_factor, self.inscribed_radius, self.source)

    def costmap(self) -> dict:
        """The model's cost map settings for this body (``SpatialConceptModel.costmap``, ``inflate(**...)``)."""
        settings = {
            "inscribed_radius": float(self.inscribed_radius),
            "inflation_radius": float(self.inflation_radius),
            "cost_scaling_factor": float(self.cost_scaling_factor),
        }
        if self.circumscribed_radius != self.inscribed_radius:
            settings["circumscribed_radius"] = float(self.circumscribed_radius)
        return settings

    def describe(self) -> str:
        """One line: the shape, its radii and the inflation, e.g. "a 0.30 m circle, inflation 0.55 m, scaling 3"."""
        if self.footprint is None:
            shape = f"a {self.inscribed_radius:.3g} m circle"
        else:
            shape = (
                f"a {len(self.footprint)}-point footprint (inscribed {self.inscribed_radius:.3g} m, "
                f"circumscribed {self.circumscribed_radius:.3g} m)"
            )
        return f"{shape}, inflation {self.inflation_radius:g} m, scaling {self.cost_scaling_factor:g}"


def circle(
    radius: object,
    inflation_radius: object = DEFAULT_COSTMAP.inflation_radius,
    cost_scaling_factor: object = DEFAULT_COSTMAP.cost_scaling_factor,
    source: str = "options",
) -> RobotBody:
    """A circular robot of ``radius`` metres: both radii ``radius``."""
    r = check_radius(radius, source, "the robot radius")
    return RobotBody(r, r, _float(inflation_radius), _float(cost_scaling_factor), None, source)


def check_radius(radius: object, source: str, name: str) -> float:
    """``radius`` as a float when it is a finite number in (0, MAX_BODY_M] metres, else RobotBodyError naming
    ``name`` (a radius given as an option, or a params file's ``robot_radius``)."""
    if not (_number(radius) and 0 < radius <= MAX_BODY_M):  # type: ignore[operator]  # a number, checked first
        raise RobotBodyError(f"{source}: {name} must be a number in (0, {MAX_BODY_M:g}] m, got {radius!r}")
    return float(radius)  # type: ignore[arg-type]  # a number, checked above


def polygon(
    points: object,
    inflation_radius: object = DEFAULT_COSTMAP.inflation_radius,
    cost_scaling_factor: object = DEFAULT_COSTMAP.cost_scaling_factor,
    source: str = "options",
    padding: float = 0.0,
) -> RobotBody:
    """A footprint polygon ([[x, y], ...] in metres, the robot's centre at the origin), padded by ``padding`` as
    costmap_2d's ``padFootprint`` does, its radii by ``calculateMinAndMaxDistances`` (module docstring)."""
    pts = pad(footprint_points(points, source), padding)
    if not _inside(pts):
        raise RobotBodyError(
            f"{source}: the robot's centre (0, 0) must lie inside its footprint {_show(pts)}; footprint points are "
            "in the robot's frame, centred on the point the robot turns about"
        )
    inscribed, circumscribed = min_max_distances(pts)
    return RobotBody(inscribed, circumscribed, _float(inflation_radius), _float(cost_scaling_factor), pts, source)


def footprint_points(points: object, source: str) -> tuple[tuple[float, float], ...]:
    """``points`` as a tuple of (x, y) floats: a sequence of 3..MAX_FOOTPRINT_POINTS pairs of finite numbers
    within MAX_BODY_M; RobotBodyError naming what is wrong otherwise."""
    accepted = (
        'a list of at least 3 [x, y] points in metres, e.g. "[[0.3, 0.2], [0.3, -0.2], [-0.3, -0.2], [-0.3, 0.2]]"'
    )
    if not isinstance(points, Sequence) or isinstance(points, (str, bytes)):
        raise RobotBodyError(f"{source}: the footprint must be {accepted}, got {_excerpt(points)}")
    if not 3 <= len(points) <= MAX_FOOTPRINT_POINTS:
        raise RobotBodyError(
            f"{source}: the footprint has {len(points)} points; it must have 3 to {MAX_FOOTPRINT_POINTS} ({accepted})"
        )
    out = []
    for i, point in enumerate(points):
        if not (isinstance(point, Sequence) and not isinstance(point, (str, bytes)) and len(point) == 2):
            raise RobotBodyError(f"{source}: footprint point {i + 1} must be [x, y], got {_excerpt(point)}")
        if not all(_number(v) and abs(v) <= MAX_BODY_M for v in point):
            raise RobotBodyError(
                f"{source}: footprint point {i + 1} must be two numbers within +-{MAX_BODY_M:g} m, "
                f"got {_excerpt(point)}"
            )
        out.append((float(point[0]), float(point[1])))
    return tuple(out)


def pad(points: tuple[tuple[float, float], ...], padding: float) -> tuple[tuple[float, float], ...]:
    """costmap_2d's ``padFootprint``: every coordinate moved ``padding`` away from 0 along its own sign (a zero
    coordinate stays)."""
    return tuple((x + _sign0(x) * padding, y + _sign0(y) * padding) for x, y in points)


def radius_footprint(radius: float) -> tuple[tuple[float, float], ...]:
    """costmap_2d's ``makeFootprintFromRadius``: 16 points on the circle, at angles i * 2 pi / 16."""
    step = 2.0 * math.pi / RADIUS_POLYGON_POINTS
    return tuple((radius * math.cos(i * step), radius * math.sin(i * step)) for i in range(RADIUS_POLYGON_POINTS))


def min_max_distances(points: Sequence[tuple[float, float]]) -> tuple[float, float]:
    """costmap_2d's ``calculateMinAndMaxDistances``: (inscribed, circumscribed) radii of a polygon about the
    origin, the min and max over vertices and edges (the closing edge too) of the vertex and segment distances."""
    low, high = math.inf, 0.0
    for i, (x0, y0) in enumerate(points):
        x1, y1 = points[(i + 1) % len(points)]
        vertex, edge = math.hypot(x0, y0), _segment_distance(x0, y0, x1, y1)
        low, high = min(low, vertex, edge), max(high, vertex, edge)
    return low, high


def _segment_distance(x0: float, y0: float, x1: float, y1: float) -> float:
    """costmap_2d's ``distanceToLine`` from the origin to the segment (x0, y0)-(x1, y1)."""
    dx, dy = x1 - x0, y1 - y0
    length2 = dx * dx + dy * dy
    t = -1.0 if length2 == 0 else (-x0 * dx - y0 * dy) / length2
    if t < 0:
        return math.hypot(x0, y0)
    if t > 1:
        return math.hypot(x1, y1)
    return math.hypot(x0 + t * dx, y0 + t * dy)


def _inside(points: Sequence[tuple[float, float]]) -> bool:
    """Whether the origin lies strictly inside the polygon (even-odd rule, and not on an edge)."""
    if min_max_distances(points)[0] <= 0:
        return False
    inside = False
    for i, (x0, y0) in enumerate(points):
        x1, y1 = points[(i + 1) % len(points)]
        if (y0 > 0) != (y1 > 0) and 0 < x0 + (0 - y0) * (x1 - x0) / (y1 - y0):
            inside = not inside
    return inside


def _check_inflation(inflation_radius: object, scaling: object, inscribed: float, source: str) -> None:
    if not (_number(inflation_radius) and 0 <= inflation_radius <= MAX_INFLATION_M):  # type: ignore[operator]
        raise RobotBodyError(
            f"{source}: inflation_radius must be a number in [0, {MAX_INFLATION_M:g}] m, got {inflation_radius!r}"
        )
    if inflation_radius < inscribed:  # type: ignore[operator]  # a number, checked above
        raise RobotBodyError(
            f"{source}: inflation_radius {inflation_radius:g} m is below the robot's inscribed radius "
            f"{inscribed:.3g} m: "
            "cells where the robot overlaps an obstacle would not be inflated (costmap_2d reports this as an error); "
            "set inflation_radius to at least the inscribed radius"
        )
    if not (_number(scaling) and 0 <= scaling <= MAX_SCALING):  # type: ignore[operator]
        raise RobotBodyError(f"{source}: cost_scaling_factor must be a number in [0, {MAX_SCALING:g}], got {scaling!r}")


def _number(value: object) -> bool:
    return isinstance(value, (int, float)) and not isinstance(value, bool) and math.isfinite(value)


def _float(value: object) -> float:
    return float(value) if _number(value) else value  # type: ignore[return-value,arg-type]  # checked by RobotBody


def _sign0(value: float) -> int:
    return -1 if value < 0 else (1 if value > 0 else 0)


def _show(points: Sequence[tuple[float, float]]) -> str:
    return "[" + ", ".join(f"[{x:g}, {y:g}]" for x, y in points[:6]) + (", ...]" if len(points) > 6 else "]")


def _excerpt(value: object) -> str:
    from spcotmhp.safe_read import excerpt

    return excerpt(value)
