"""Room layouts of the synthetic floor plans, in cells: room boxes, their names and the doors between them.

- ``flat``: a rectangle cut recursively into rooms (binary space partition); doors form a random spanning tree
  over the rooms that share a wall, biased through the largest room (the living room), plus a few extra doors.
- ``house``: one corridor (one or two ``corridor`` places) with the entrance at its left end and a row of rooms
  on each side, each with a door onto the corridor (or the entrance) and some with a door to the next room.
- ``office``: horizontal corridors joined by a vertical spine corridor at the left, rooms along both sides of
  every corridor, each with a door onto it; corridors are cut into several ``corridor`` places joined by open
  boundaries (no wall), never across a door.

Rooms are separated by walls ``Geometry.wall`` cells thick; every door keeps ``Geometry.jamb`` cells of wall to
the room's corners.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

from spcotmhp.datasets.synthetic_vocab import (
    CORRIDOR,
    FILLER_NAMES,
    FLAT_NAMES,
    HOUSE_NAMES,
    LIVING,
    OFFICE_SPECIAL,
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


def _door(
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


def _split_length(
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
        return [first] + _split_length(rng, length - first - wall, k - 1, minimum, wall, what)
    spare = length - (k - 1) * wall - k * minimum
    if spare < 0:
        raise DatasetError(
            f"{what}: {k} rooms need {k * minimum + (k - 1) * wall} cells but only {length} "
            f"fit; use fewer rooms or a larger size"
        )
    cuts = np.floor(np.cumsum(rng.dirichlet(np.full(k, 4.0))) * spare).astype(int)
    cuts[-1] = spare
    return [int(w) for w in minimum + np.diff(np.concatenate([[0], cuts]))]


def _names(priority: list[str], filler: list[str], k: int, rng: np.random.Generator) -> list[str]:
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
    names = sorted(_names(FLAT_NAMES, FILLER_NAMES["flat"], n - 1, rng), key=THROUGH_ORDER.index)
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
            return _door(rng, (i, j), axis, span, (hi_p, lo_q), geo)
        if hi_q + geo.wall == lo_p:
            return _door(rng, (i, j), axis, span, (hi_q, lo_p), geo)
    return None


# ---------------------------------------------------------------------------------------------- house/office
@dataclass
class _Band:
    """A row of rooms: interior rows and columns, the wall rows its doors go through, and the corridor it faces."""

    rows: tuple[int, int]
    cols: tuple[int, int]
    wall: tuple[int, int]
    strip: int
    first: int | None = None  # width of its first room, when fixed


def house_layout(inner: Box, n: int, geo: Geometry, rng: np.random.Generator) -> Layout:
    """Entrance at the left end of one corridor, rooms above and below it."""
    r0, c0, r1, c1 = inner
    cw = max(geo.cells(rng.uniform(1.5, 1.9)), geo.door + 2 * geo.jamb)
    depth = (r1 - r0 - cw - 2 * geo.wall) // 2
    if depth < geo.min_side:
        raise DatasetError(
            f"house: {r1 - r0} interior rows cannot hold a corridor and two rows of rooms of at "
            f"least {geo.min_side} cells; use a larger size"
        )
    cr0 = r0 + depth + geo.wall + int(rng.integers(0, (r1 - r0 - cw - 2 * geo.wall) % 2 + 1))
    ew = max(geo.cells(rng.uniform(2.0, 3.0)), geo.min_side)  # entrance width = first room width in each band
    x = c0 + ew
    segments = 2 if n >= 8 and c1 - x - geo.wall >= geo.cells(10.0) else 1
    bands = [
        _Band((r0, cr0 - geo.wall), (c0, c1), (cr0 - geo.wall, cr0), 0, ew),
        _Band((cr0 + cw + geo.wall, r1), (c0, c1), (cr0 + cw, cr0 + cw + geo.wall), 0, ew),
    ]
    n_rooms = n - 1 - segments
    rooms = _band_rooms(bands, n_rooms, geo, rng, geo.min_side, 0.35, "house", avoid=(x, x + geo.wall))
    boxes: list[Box] = [(cr0, c0, cr0 + cw, x)]
    names, doors = ["entrance"], list[Door]()
    corridor = _corridor(boxes, names, doors, (cr0, cr0 + cw), (x + geo.wall, c1), segments, rooms, geo, rng, "house")
    entrance = _door(rng, (0, corridor[0][0]), 1, (cr0, cr0 + cw), (x, x + geo.wall), geo)
    if entrance is None:
        raise DatasetError(f"house: no place for the entrance door in a corridor {cw} cells wide; use a larger size")
    doors.append(entrance)
    new = _add_rooms(boxes, doors, rooms, [[(0, c0, x)] + corridor])
    areas = [(boxes[i][2] - boxes[i][0]) * (boxes[i][3] - boxes[i][1]) for i in new]
    living = new[int(np.argmax(areas))]
    others = iter(_names(HOUSE_NAMES, FILLER_NAMES["house"], n_rooms - 1, rng))
    names += [LIVING if i == living else next(others) for i in new]
    return boxes, names, doors


def office_layout(inner: Box, n: int, geo: Geometry, rng: np.random.Generator) -> Layout:
    """Horizontal corridors joined by a spine at the left; rooms along both sides of each corridor."""
    r0, c0, r1, c1 = inner
    cw = max(geo.cells(rng.uniform(1.8, 2.4)), geo.door + 2 * geo.jamb)
    n_corr, seg, depth = _office_counts(inner, n, cw, geo)
    spare = r1 - r0 - n_corr * (cw + 2 * geo.wall) - (n_corr - 1) * geo.wall - 2 * n_corr * depth
    bands, corridor_rows, row = [], [], r0
    for k in range(n_corr):
        extra = spare // n_corr + (1 if k < spare % n_corr else 0)
        cr0 = row + depth + extra // 2 + geo.wall
        bands.append(_Band((row, cr0 - geo.wall), (c0 if k == 0 else c0 + cw + geo.wall, c1), (cr0 - geo.wall, cr0), k))
        corridor_rows.append((cr0, cr0 + cw))
        last = k == n_corr - 1
        top = r1 if last else cr0 + cw + geo.wall + depth + extra - extra // 2
        bands.append(
            _Band(
                (cr0 + cw + geo.wall, top),
                (c0 if last else c0 + cw + geo.wall, c1),
                (cr0 + cw, cr0 + cw + geo.wall),
                k,
            )
        )
        row = top + geo.wall
    n_rooms = n - (n_corr * seg + n_corr - 1)
    min_width = max(geo.cells(3.0), geo.min_side)
    rooms = _band_rooms(bands, n_rooms, geo, rng, min_width, 0.1, "office")
    boxes: list[Box] = []
    names: list[str] = []
    doors: list[Door] = []
    strips = []
    for k, rows in enumerate(corridor_rows):
        strips.append(_corridor(boxes, names, doors, rows, (c0, c1), seg, rooms, geo, rng, "office", strip=k))
        if k:  # the spine from the corridor below up to this one, joined to both by open boundaries
            below, here = strips[k - 1][0][0], strips[k][0][0]
            boxes.append((corridor_rows[k - 1][1], c0, rows[0], c0 + cw))
            names.append(CORRIDOR)
            spine = len(boxes) - 1
            doors += [
                Door((below, spine), 0, c0, c0 + cw, corridor_rows[k - 1][1], corridor_rows[k - 1][1]),
                Door((here, spine), 0, c0, c0 + cw, rows[0], rows[0]),
            ]
    _add_rooms(boxes, doors, rooms, strips)
    names += _names(OFFICE_SPECIAL[: max(1, n_rooms // 3)], FILLER_NAMES["office"], n_rooms, rng)
    return boxes, names, doors


def _office_counts(inner: Box, n: int, cw: int, geo: Geometry) -> tuple[int, int, int]:
    """Corridors, places per corridor and room depth: about one corridor per 28 m of height and a fifth of the
    places corridors, fewer when the places or the height run short."""
    r0, c0, r1, c1 = inner
    n_corr = max(1, round((r1 - r0) * geo.res / 28.0))
    while True:
        seg = min(max(1, round((0.2 * n - (n_corr - 1)) / n_corr)), max(1, (c1 - c0) // geo.cells(8.0)))
        while seg > 1 and n - (n_corr * seg + n_corr - 1) < 2 * n_corr:
            seg -= 1
        depth = (r1 - r0 - n_corr * (cw + 2 * geo.wall) - (n_corr - 1) * geo.wall) // (2 * n_corr)
        fits = n - (n_corr * seg + n_corr - 1) >= 2 * n_corr and depth >= geo.cells(3.0)
        if fits or n_corr == 1:
            break
        n_corr -= 1
    if not fits:
        raise DatasetError(
            f"office: {n} places do not fit a {r1 - r0}x{c1 - c0}-cell interior (rooms at least "
            f"3 m deep, at least one room on each side of a corridor); change n_rooms or size"
        )
    return n_corr, seg, depth


@dataclass
class _BandRoom:
    box: Box
    strip: int
    door: Door  # rooms (-1, -1) until numbered
    to_previous: Door | None


def _band_rooms(
    bands: list[_Band],
    n_rooms: int,
    geo: Geometry,
    rng: np.random.Generator,
    min_width: int,
    p_between: float,
    what: str,
    avoid: tuple[int, int] | None = None,
) -> list[_BandRoom]:
    """Rooms side by side in each band, each with a door onto its corridor (not overlapping ``avoid``) and, with
    probability ``p_between``, a door to the previous room of its band."""
    lengths = np.array([b.cols[1] - b.cols[0] for b in bands])
    capacity = (lengths + geo.wall) // (min_width + geo.wall)
    if n_rooms < len(bands) or capacity.sum() < n_rooms or any(b.rows[1] - b.rows[0] < geo.min_side for b in bands):
        raise DatasetError(
            f"{what}: {n_rooms} rooms do not fit {len(bands)} rows of rooms (between {len(bands)} "
            f"and {int(capacity.sum())} fit this size); change n_rooms or size"
        )
    counts = np.ones(len(bands), dtype=int)
    for _ in range(n_rooms - len(bands)):  # proportional to length, random ties
        score = np.where(counts < capacity, lengths / counts + rng.random(len(bands)) * 1e-6, -np.inf)
        counts[int(np.argmax(score))] += 1
    rooms = []
    for band, k in zip(bands, counts, strict=False):
        col, length = band.cols[0], band.cols[1] - band.cols[0]
        rest = length - (band.first or 0) - geo.wall  # what the other rooms get when the first one is fixed
        fixed = band.first is not None and k > 1 and rest >= (k - 1) * min_width + (k - 2) * geo.wall
        first = band.first if fixed else None
        for j, width in enumerate(_split_length(rng, length, int(k), min_width, geo.wall, what, first)):
            door = _door(rng, (-1, -1), 0, (col, col + width), band.wall, geo, avoid)
            if door is None:
                raise DatasetError(f"{what}: no place for a door in a room {width} cells wide; use a larger size")
            between = None
            if j and rng.random() < p_between:
                between = _door(rng, (-1, -1), 1, band.rows, (col - geo.wall, col), geo)
            rooms.append(_BandRoom((band.rows[0], col, band.rows[1], col + width), band.strip, door, between))
            col += width + geo.wall
    return rooms


def _corridor(
    boxes: list[Box],
    names: list[str],
    doors: list[Door],
    rows: tuple[int, int],
    cols: tuple[int, int],
    k: int,
    rooms: list[_BandRoom],
    geo: Geometry,
    rng: np.random.Generator,
    what: str,
    strip: int = 0,
) -> list[tuple[int, int, int]]:
    """A horizontal corridor cut into ``k`` places joined by open boundaries, never cut through a door of
    ``rooms``; returns (index, col0, col1) of each place."""
    spans = [(r.door.lo, r.door.hi) for r in rooms if r.strip == strip]
    min_len = geo.cells(3.0)
    cuts = [cols[0]]
    for j in range(1, k):
        ideal = cols[0] + (cols[1] - cols[0]) * (j + rng.uniform(-0.15, 0.15)) / k
        candidates = np.arange(cuts[-1] + min_len, cols[1] - (k - j) * min_len + 1)
        for lo, hi in spans:
            candidates = candidates[(candidates <= lo) | (candidates >= hi)]
        if len(candidates) == 0:
            raise DatasetError(f"{what}: a corridor {cols[1] - cols[0]} cells long cannot be cut into {k} places")
        cuts.append(int(candidates[np.argmin(np.abs(candidates - ideal))]))
    cuts.append(cols[1])
    first = len(boxes)
    for j in range(k):
        boxes.append((rows[0], cuts[j], rows[1], cuts[j + 1]))
        names.append(CORRIDOR)
        if j:
            doors.append(Door((first + j - 1, first + j), 1, rows[0], rows[1], cuts[j], cuts[j]))
    return [(first + j, cuts[j], cuts[j + 1]) for j in range(k)]


def _add_rooms(
    boxes: list[Box], doors: list[Door], rooms: list[_BandRoom], strips: list[list[tuple[int, int, int]]]
) -> list[int]:
    """Number the band rooms after the corridor places; each door goes to the place its centre faces."""
    new = []
    for room in rooms:
        boxes.append(room.box)
        idx = len(boxes) - 1
        new.append(idx)
        centre = (room.door.lo + room.door.hi) / 2
        target = next(i for i, lo, hi in strips[room.strip] if lo <= centre < hi)
        doors.append(replace(room.door, rooms=(target, idx)))
        if room.to_previous is not None:
            doors.append(replace(room.to_previous, rooms=(idx - 1, idx)))
    return new


LAYOUTS = {"flat": flat_layout, "house": house_layout, "office": office_layout}
