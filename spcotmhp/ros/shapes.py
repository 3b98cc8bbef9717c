"""What the ROS 2 node publishes, as plain numbers (no rclpy needed): a plan's poses and headings, the learned
map as ellipses, names and topological edges, the JSON status lines, and the check of a published map.

Headings follow Nav2's conventions (nav2_route's path converter): every pose faces the next one, the last keeps
the heading of the last segment (a path of one point keeps the robot's own heading), so a controller neither
spins at the goal nor starts against the path.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Any

import numpy as np
from scipy.stats import chi2

from spcotmhp.metric.maps import OccupancyMap

ELLIPSE_QUANTILE = 0.95
"""Place ellipses are drawn at this chi-square quantile of their Gaussian N(mu_i, Sigma_i) (2 degrees of
freedom: 2.45 standard deviations)."""


def path_poses(path: np.ndarray, cells: np.ndarray, start: Sequence[float], occ: OccupancyMap) -> np.ndarray:
    """(n, 2) poses of a plan for the robot: the plan's cell centres, the first replaced by the start pose itself
    when it lies in the first cell (the plan starts where the robot is), else the start pose put before them."""
    points = np.asarray(path, dtype=float).reshape(-1, 2).copy()
    x0 = np.asarray(start, dtype=float)[:2]
    if len(points) and np.array_equal(occ.world_to_cell(x0), np.asarray(cells)[0]):
        points[0] = x0
        return points
    return np.vstack([x0[None, :], points])


def path_yaws(points: np.ndarray, fallback: float = 0.0) -> np.ndarray:
    """(n,) heading of each pose: towards the next distinct point; the last (and any run of repeated points at
    the end) keeps the heading of the last segment; ``fallback`` when the path has no segment."""
    points = np.asarray(points, dtype=float).reshape(-1, 2)
    n = len(points)
    yaws = np.full(n, float(fallback))
    step = np.diff(points, axis=0)
    moving = np.flatnonzero(np.hypot(step[:, 0], step[:, 1]) > 0)
    if not len(moving):
        return yaws
    seg = np.arctan2(step[moving, 1], step[moving, 0])
    # pose i faces the first segment that leaves it (index >= i); poses after the last segment keep its heading
    nxt = np.searchsorted(moving, np.arange(n))
    yaws[:] = seg[np.minimum(nxt, len(moving) - 1)]
    return yaws


def yaw_quaternion(yaw: float) -> tuple[float, float, float, float]:
    """(x, y, z, w) of a rotation by ``yaw`` about z."""
    return 0.0, 0.0, math.sin(yaw / 2.0), math.cos(yaw / 2.0)


def quaternion_yaw(x: float, y: float, z: float, w: float) -> float:
    """The heading (rotation about z) of a quaternion."""
    return math.atan2(2.0 * (w * z + x * y), 1.0 - 2.0 * (y * y + z * z))


def ellipse(Sigma: np.ndarray, quantile: float = ELLIPSE_QUANTILE) -> tuple[float, float, float]:
    """(length, width, yaw) of the ``quantile`` ellipse of a 2-d Gaussian: full axis lengths in metres, major
    axis first, and its heading."""
    values, vectors = np.linalg.eigh(np.asarray(Sigma, dtype=float))
    scale = chi2.ppf(quantile, 2)
    major, minor = np.sqrt(np.maximum(values[::-1], 0.0) * scale) * 2.0
    return float(major), float(minor), float(math.atan2(vectors[1, 1], vectors[0, 1]))


def place_shapes(planner: Any) -> tuple[list[dict], list[tuple[int, int]]]:
    """The learned map to draw: one dict per active place (id, name, centre mu_i, ellipse of Sigma_i) and the
    topological edges (pairs i < j of connected places, Figure 3 of the paper)."""
    model = planner.model
    active = np.flatnonzero(model.active_places)
    places = []
    for k in active:
        length, width, yaw = ellipse(model.Sigma[k])
        places.append(
            {
                "id": int(k),
                "name": planner.shown[k],
                "centre": [float(v) for v in model.mu[k]],
                "length": length,
                "width": width,
                "yaw": yaw,
            }
        )
    connected = planner.graph.connected
    edges = [(int(a), int(b)) for i, a in enumerate(active) for b in active[i + 1 :] if connected[a, b]]
    return places, edges


def map_mismatches(width: int, height: int, resolution: float, origin: Sequence[float], occ: OccupancyMap) -> list[str]:
    """What differs between a published map (OccupancyGrid info: size, resolution, origin x, y, yaw) and the
    model's map; empty when they agree (origin within a tenth of a cell, resolution to 1e-6 relative)."""
    out = []
    if (int(width), int(height)) != (occ.width, occ.height):
        out.append(f"size {width}x{height} cells, the model's map {occ.width}x{occ.height}")
    if not math.isclose(float(resolution), occ.resolution, rel_tol=1e-6):
        out.append(f"resolution {float(resolution):g} m, the model's map {occ.resolution:g} m")
    x, y, yaw = (float(v) for v in origin)
    tolerance = 0.1 * occ.resolution
    if abs(x - occ.origin[0]) > tolerance or abs(y - occ.origin[1]) > tolerance or abs(yaw) > 1e-6:
        out.append(
            f"origin ({x:.3f}, {y:.3f}, yaw {yaw:.3f}), the model's map ({occ.origin[0]:.3f}, "
            f"{occ.origin[1]:.3f}, yaw 0)"
        )
    return out


def plan_status(plan: Any, instruction: str, start: Sequence[float], points: np.ndarray, frame: str) -> dict:
    """The status line of a plan: what was understood, the places with their roles (and the relation that picked
    one), the speed and waits asked for (for whoever drives the path: the Path itself has no speed), length and
    time."""
    steps = np.diff(points, axis=0)
    return {
        "kind": "plan",
        "ok": True,
        "instruction": instruction,
        "explanation": plan.explanation,
        "places": [
            {
                "id": p.id,
                "name": p.name,
                "label": p.label,
                "role": p.role,
                "point": None if p.point is None else [round(v, 4) for v in p.point],
                **({"chosen_by": plan.chosen[p.id]} if p.id in plan.chosen else {}),
            }
            for p in plan.places
        ],
        "understood": plan.instruction.describe(),
        "speed": plan.instruction.speed,
        "waits": [{"id": p.id, "label": p.label, "seconds": s} for p, s in plan.waits],
        "length_m": round(float(np.hypot(steps[:, 0], steps[:, 1]).sum()), 4),
        "time_s": round(plan.time_online_s, 4),
        "start": [round(float(v), 4) for v in start[:2]],
        "frame": frame,
        "n_poses": len(points),
        "notes": list(plan.notes),
    }


def error_status(exc: BaseException, instruction: str | None = None, kind: str = "error") -> dict:
    """The status line of a message that could not be served: the one-line error and its type, and the text it
    answers (``utterance`` for a teach, as its success line names it; ``instruction`` otherwise)."""
    out = {
        "kind": kind,
        "ok": False,
        "error": str(exc).splitlines()[0] if str(exc) else type(exc).__name__,
        "type": type(exc).__name__,
    }
    if instruction is not None:
        out["utterance" if kind == "taught" else "instruction"] = instruction
    return out
