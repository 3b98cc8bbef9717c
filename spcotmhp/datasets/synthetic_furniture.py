"""Furniture and closed doors for synthetic homes: what cuts a real home's free space into pieces for a robot.

A LiDAR map of a furnished home shows sofas, beds, tables and shelves as occupied blocks. Once the map is inflated
by the robot's inscribed radius, a gap between two pieces narrower than the robot is closed, so the space the
pieces enclose becomes an *island*: free on the map, safe for the robot's footprint, cut off from the room around
it (issue 24's held-out home: a living room whose territory kept only a 17-cell island inside its furniture).

:func:`furnish`: each room that is not a corridor or the entrance (nor one of ``skip``) gets, with probability
``share``, a *seating group*: a free square (side 0.7 to 1.4 m, so that its middle holds cells the robot fits in)
ringed by four pieces 0.3 to 0.6 m deep (sofas, armchairs, a low table), some split by a gap that the map shows
free but that is narrower than the robot (1 to ``2 floor(r / resolution) - 1`` cells for an inscribed radius r:
every cell of it lies within r of a piece, so the inflated map closes it). The group lies at a random position in
the room, at least ``CLEARANCE_M`` from every wall, so that the rest of the room stays one free region around it
and no door is blocked; it may cover the room's centre (where the mean of its teaching is) or not. A room too
small for a group gets none.

:func:`close_doors`: doors (not the open boundaries between corridor places) drawn at random are walled up, as a
closed door is seen by the robot's laser: the free space is then cut into regions.

Both are applied after the teaching walk (:mod:`spcotmhp.datasets.synthetic_walk`), which does not avoid them:
some trajectory poses and teaching points fall on furniture or behind a closed door, as teaching points at the edge
of a wall do in the bundled homes (spcotmhp/data/README.md). Pieces and walls are written over free cells only.
Every random choice comes from the generator passed in, drawn after the plan's and the walk's, so a home without
furniture is the same as before.
"""

from __future__ import annotations

import math

import numpy as np

from spcotmhp.datasets.synthetic_layouts import Box
from spcotmhp.datasets.synthetic_plan import FloorPlan
from spcotmhp.errors import DatasetError
from spcotmhp.metric.costmap import CostMapSettings
from spcotmhp.metric.maps import FREE, OCCUPIED

SIDE_M = (0.7, 1.4)  # the free square inside a seating group
DEPTH_M = (0.3, 0.6)  # a piece's depth
CLEARANCE_M = 0.8  # the least free space between a group and the room's walls (> the robot's 0.44 m diameter)
FURNITURE_SHARE = 0.6  # the share of rooms furnished by the battery's --furniture

__all__ = ["CLEARANCE_M", "FURNITURE_SHARE", "close_doors", "furnish"]


def furnish(
    plan: FloorPlan,
    rng: np.random.Generator,
    share: float = FURNITURE_SHARE,
    skip: tuple[int, ...] = (),
    inscribed_radius: float = CostMapSettings.inscribed_radius,
) -> list[Box]:
    """Put a seating group (module docstring) in a ``share`` of the rooms of ``plan`` (in place, on its map) and
    return the free square inside each group, (row0, col0, row1, col1) half-open in cells.

    >>> from spcotmhp.datasets.synthetic_plan import generate_floor_plan
    >>> plan = generate_floor_plan("house", seed=1)
    >>> squares = furnish(plan, np.random.default_rng(1), share=1.0)
    >>> len(squares) > 0, int((plan.map.data == 100).sum()) > 0
    (True, True)
    """
    if not 0.0 <= share <= 1.0:
        raise DatasetError(f"the furnished share of rooms is a probability in [0, 1], got {share}")
    res = plan.map.resolution
    if not 0.0 < inscribed_radius < 1.0:
        raise DatasetError(f"inscribed_radius must be in (0, 1) m, got {inscribed_radius}")
    widest_gap = max(1, 2 * math.floor(inscribed_radius / res) - 1)
    squares = []
    for room in plan.rooms:
        if room.is_corridor or room.name == "entrance" or room.index in skip:
            continue
        draws = rng.random(7)  # one set of draws per room, used or not, so rooms do not shift each other's
        gaps = rng.integers(1, widest_gap + 1, size=4)
        if draws[0] >= share:
            continue
        square = _seating_group(plan, room.box, draws[1:], gaps, res)
        if square is not None:
            squares.append(square)
    return squares


def close_doors(plan: FloorPlan, rng: np.random.Generator, n: int = 1) -> list[int]:
    """Wall up ``n`` doors of ``plan`` drawn at random among its real doors (not open boundaries), in place on its
    map; returns their indices in ``plan.doors`` (the adjacency still lists them: people walked through them)."""
    real = [i for i, d in enumerate(plan.doors) if d.w1 > d.w0]
    if not 0 <= n <= len(real):
        raise DatasetError(f"cannot close {n} doors: the plan has {len(real)}")
    chosen = sorted(int(i) for i in rng.choice(real, size=n, replace=False)) if n else []
    for i in chosen:
        r0, c0, r1, c1 = plan.doors[i].cells
        _write(plan.map.data, (r0, c0, r1, c1))
    return chosen


def _seating_group(plan: FloorPlan, box: Box, u: np.ndarray, gaps: np.ndarray, res: float) -> Box | None:
    """Draw one group in the room ``box`` from the uniform numbers ``u`` (6) and the gap widths ``gaps`` (4, in
    cells); None when the room is too small for it."""
    side = round((SIDE_M[0] + (SIDE_M[1] - SIDE_M[0]) * u[0]) / res)
    depth = max(1, round((DEPTH_M[0] + (DEPTH_M[1] - DEPTH_M[0]) * u[1]) / res))
    clear = math.ceil(CLEARANCE_M / res)
    outer = side + 2 * depth
    r0, c0, r1, c1 = box
    room_r, room_c = r1 - r0 - 2 * clear - outer, c1 - c0 - 2 * clear - outer
    if room_r < 0 or room_c < 0:
        return None
    R0 = r0 + clear + int(u[2] * (room_r + 1))
    C0 = c0 + clear + int(u[3] * (room_c + 1))
    R1, C1 = R0 + outer, C0 + outer
    pieces = [  # bottom, top (full width), left, right (between them)
        (R0, C0, R0 + depth, C1),
        (R1 - depth, C0, R1, C1),
        (R0 + depth, C0, R1 - depth, C0 + depth),
        (R0 + depth, C1 - depth, R1 - depth, C1),
    ]
    data = plan.map.data
    for piece in pieces:
        _write(data, piece)
    for k, piece in enumerate(pieces):  # a gap in every other piece (which ones: u[4]), at u[5] along it
        if (k + int(u[4] * 4)) % 2:
            continue
        gap = int(min(gaps[k], side))
        pos = int(u[5] * (side - gap + 1))
        pr0, pc0, pr1, pc1 = piece
        if k < 2:  # along the columns, over the square's span
            data[pr0:pr1, C0 + depth + pos : C0 + depth + pos + gap] = FREE
        else:
            data[R0 + depth + pos : R0 + depth + pos + gap, pc0:pc1] = FREE
    return (R0 + depth, C0 + depth, R1 - depth, C1 - depth)


def _write(data: np.ndarray, box: Box) -> None:
    """Occupied over the free cells of ``box``."""
    r0, c0, r1, c1 = box
    window = data[r0:r1, c0:c1]
    window[window == FREE] = OCCUPIED
