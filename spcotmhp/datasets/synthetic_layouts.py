"""Room layouts of the synthetic floor plans, in cells: room boxes, their names and the doors between them.

- ``flat``: a rectangle cut recursively into rooms (binary space partition); doors form a random spanning tree
  over the rooms that share a wall, biased through the largest room (the living room), plus a few extra doors.
- ``house`` (:mod:`spcotmhp.datasets.synthetic_corridors`, as ``office``): one corridor (one or two ``corridor``
  places) with the entrance at its left end and a row of rooms on each side, each with a door onto the corridor
  (or the entrance) and some with a door to the next room.
- ``office``: horizontal corridors joined by a vertical spine corridor at the left, rooms along both sides of
  every corridor, each with a door onto it; corridors are cut into several ``corridor`` places joined by open
  boundaries (no wall), never across a door.

:data:`spcotmhp.datasets.synthetic_plan.LAYOUTS` names the three. Rooms are separated by walls ``Geometry.wall``
cells thick; every door keeps ``Geometry.jamb`` cells of wall to the room's corners.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from spcotmhp.datasets.synthetic_vocab import (
    FILLER_NAMES,
    FLAT_NAMES,
    LIVING,
    THROUGH_ORDER,
)
from spcotmhp.errors import DatasetError

Box = tuple[int, int, int, int]  # (row0, col0, row1, col1), half-open, OccupancyGrid rows
Layout = tuple[list[Box], list[str], list["Door"]]  # room boxes, room names, doors


@dataclass(frozen=True)
class Door:
    """An opening between two rooms.

    ``axis`` 0: the wall runs along the columns (the rooms lie one above the other, crossing changes the row);
    ``axis`` 1: the wall runs along the rows. The opening spans ``[lo, hi)`` along the wall and the wall cells
    ``[w0, w1)`` across it; ``w0 == w1`` for the open boundary between two corridor places (no wall).
    """

    rooms: tuple[int, int]
    axis: int
    lo: int
    hi: int
    w0: int
    w1: int

    @property
    def centre(self) -> tuple[float, float]:
        """Continuous (row, col) of the opening's centre (cell (i, j) spans [i, i+1) x [j, j+1))."""
        along, across = (self.lo + self.hi) / 2, (self.w0 + self.w1) / 2
        return (across, along) if self.axis == 0 else (along, across)

    @property
    def cell(self) -> tuple[int, int]:
        """The middle cell of the opening (for an open boundary, the first cell beyond it)."""
        row, col = self.centre
        return (int(row), int(col))

    @property
    def cells(self) -> Box:
        """The opening's wall cells as a box (empty for an open boundary)."""
        if self.axis == 0:
            return (self.w0, self.lo, self.w1, self.hi)
        return (self.lo, self.w0, self.hi, self.w1)


@dataclass
class Geometry:
    """Cell sizes shared by the layouts: wall thickness, door width, jamb, least room side; metres per cell."""

    wall: int
    door: int
    jamb: int
    min_side: int
    res: float

    def cells(self, metres: float) -> int:
        return round(metres / self.res)


def make_door(
    rng: np.random.Generator,
    rooms: tuple[int, int],
    axis: int,
    span: tuple[int, int],
    wall: tuple[int, int],
    geo: Geometry,
    avoid: tuple[int, int] | None = None,
) -> Door | None:
    """A door of width ``geo.door`` at a random place along ``span`` with jambs kept and not overlapping
    ``avoid`` (cells along the wall); None if it does not fit."""
    starts = np.arange(span[0] + geo.jamb, span[1] - geo.jamb - geo.door + 1)
    if avoid is not None:
        starts = starts[(starts + geo.door <= avoid[0]) | (starts >= avoid[1])]
    if len(starts) == 0:
        return None
    start = int(starts[rng.integers(len(starts))])
    return Door(rooms, axis, start, start + geo.door, wall[0], wall[1])


def split_length(
    rng: np.random.Generator,
    length: int,
    k: int,
    minimum: int,
    wall: int,
    what: str,
    first: int | None = None,
) -> list[int]:
    """Widths of ``k`` parts >= ``minimum`` (the first one ``first`` if given) filling ``length`` with ``wall``
    cells between them."""
    if first is not None and k > 1:
        return [first] + split_length(rng, length - first - wall, k - 1, minimum, wall, what)
    spare = length - (k - 1) * wall - k * minimum
    if spare < 0:
        raise DatasetError(
            f"{what}: {k} rooms need {k * minimum + (k - 1) * wall} cells but only {length} "
            f"fit; use fewer rooms or a larger size"
        )
    cuts = np.floor(np.cumsum(rng.dirichlet(np.full(k, 4.0))) * spare).astype(int)
    cuts[-1] = spare
    return [int(w) for w in minimum + np.diff(np.concatenate([[0], cuts]))]


def pick_names(priority: list[str], filler: list[str], k: int, rng: np.random.Generator) -> list[str]:
    """``k`` names: the first of ``priority``, then random fillers; shuffled."""
    chosen = list(priority[:k]) + [filler[int(rng.integers(len(filler)))] for _ in range(k - len(priority))]
    return [chosen[i] for i in rng.permutation(k)]


# ---------------------------------------------------------------------------------------------------- flat
def flat_layout(inner: Box, n: int, geo: Geometry, rng: np.random.Generator) -> Layout:
    """``n`` rooms filling ``inner``; the largest is the living room, the others named by how many doors."""
    boxes = _bsp(inner, n, geo, rng)
    areas = [(b[2] - b[0]) * (b[3] - b[1]) for b in boxes]
    living = int(np.argmax(areas))
    candidates = []
    for i in range(n):
        for j in range(i + 1, n):
            door = _shared_wall_door(boxes, i, j, geo, rng)
            if door is not None:
                candidates.append(door)
    weights = rng.random(len(candidates)) - np.array([living in d.rooms for d in candidates], dtype=float)
    doors, parent = [], list(range(n))

    def root(i: int) -> int:
        while parent[i] != i:
            parent[i] = parent[parent[i]]
            i = parent[i]
        return i

    extra = rng.random(len(candidates)) < 0.2  # a few loops besides the tree
    for k in np.argsort(weights, kind="stable"):
        a, b = candidates[k].rooms
        if root(a) != root(b):
            parent[root(a)] = root(b)
            doors.append(candidates[k])
        elif extra[k]:
            doors.append(candidates[k])
    if len({root(i) for i in range(n)}) > 1:
        raise DatasetError(f"flat: the {n} rooms do not share walls long enough for doors; use a larger size")
    degree = np.zeros(n, dtype=int)
    for d in doors:
        degree[list(d.rooms)] += 1
    # rooms walked through get the names of rooms people walk through (a kitchen rather than a toilet)
    others = sorted((i for i in range(n) if i != living), key=lambda i: (-degree[i], rng.random()))
    names = sorted(pick_names(FLAT_NAMES, FILLER_NAMES["flat"], n - 1, rng), key=THROUGH_ORDER.index)
    by_room = [LIVING] * n
    for i, name in zip(others, names, strict=False):
        by_room[i] = name
    return boxes, by_room, sorted(doors, key=lambda d: d.rooms)


def _bsp(rect: Box, n: int, geo: Geometry, rng: np.random.Generator) -> list[Box]:
    """Cut ``rect`` into ``n`` rooms: cut across the longer side (either when nearly square) into two parts
    sized for their share of the rooms, with a wall between them; recurse."""
    if n == 1:
        return [rect]
    r0, c0, r1, c1 = rect
    h, w = r1 - r0, c1 - c0
    n_a = n // 2 if n % 2 == 0 else n // 2 + int(rng.integers(0, 2))

    def need(k: int, across: int) -> int:  # length that k rooms need, in rows of as many as fit across
        per_row = max(1, (across + geo.wall) // (geo.min_side + geo.wall))
        rows = -(-k // per_row)
        return rows * geo.min_side + (rows - 1) * geo.wall

    order = [0, 1] if h > w else [1, 0]
    if max(h, w) < 1.2 * min(h, w):
        order = [int(a) for a in rng.permutation(2)]
    for axis in order:
        length, across = (h, w) if axis == 0 else (w, h)
        usable = length - geo.wall
        lo, hi = need(n_a, across), usable - need(n - n_a, across)
        if lo <= hi:
            break
    else:
        raise DatasetError(
            f"flat: a {h}x{w}-cell area cannot hold {n} rooms of at least {geo.min_side} cells a "
            f"side; use fewer rooms or a larger size"
        )
    part = int(np.clip(round(usable * n_a / n * rng.uniform(0.85, 1.15)), lo, hi))
    if axis == 0:
        a, b = (r0, c0, r0 + part, c1), (r0 + part + geo.wall, c0, r1, c1)
    else:
        a, b = (r0, c0, r1, c0 + part), (r0, c0 + part + geo.wall, r1, c1)
    return _bsp(a, n_a, geo, rng) + _bsp(b, n - n_a, geo, rng)


def _shared_wall_door(boxes: list[Box], i: int, j: int, geo: Geometry, rng: np.random.Generator) -> Door | None:
    """A door through the wall that boxes i and j share, if they share one long enough."""
    p, q = boxes[i], boxes[j]
    for axis in (0, 1):
        lo_p, hi_p = (p[0], p[2]) if axis == 0 else (p[1], p[3])
        lo_q, hi_q = (q[0], q[2]) if axis == 0 else (q[1], q[3])
        span = (max(p[1], q[1]), min(p[3], q[3])) if axis == 0 else (max(p[0], q[0]), min(p[2], q[2]))
        if hi_p + geo.wall == lo_q:
            return make_door(rng, (i, j), axis, span, (hi_p, lo_q), geo)
        if hi_q + geo.wall == lo_p:
            return make_door(rng, (i, j), axis, span, (hi_q, lo_p), geo)
    return None
