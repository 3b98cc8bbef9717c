"""The corridor layouts of the synthetic floor plans (``house`` and ``office``; the room and door primitives and
the ``flat`` layout are in :mod:`spcotmhp.datasets.synthetic_layouts`, whose docstring describes all three).

- ``house``: one corridor (one or two ``corridor`` places) with the entrance at its left end and a row of rooms
  on each side, each with a door onto the corridor (or the entrance) and some with a door to the next room.
- ``office``: horizontal corridors joined by a vertical spine corridor at the left, rooms along both sides of
  every corridor, each with a door onto it; corridors are cut into several ``corridor`` places joined by open
  boundaries (no wall), never across a door.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

from spcotmhp.datasets.synthetic_layouts import Box, Door, Geometry, Layout, make_door, pick_names, split_length
from spcotmhp.datasets.synthetic_vocab import CORRIDOR, FILLER_NAMES, HOUSE_NAMES, LIVING, OFFICE_SPECIAL
from spcotmhp.errors import DatasetError


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
    entrance = make_door(rng, (0, corridor[0][0]), 1, (cr0, cr0 + cw), (x, x + geo.wall), geo)
    if entrance is None:
        raise DatasetError(f"house: no place for the entrance door in a corridor {cw} cells wide; use a larger size")
    doors.append(entrance)
    new = _add_rooms(boxes, doors, rooms, [[(0, c0, x)] + corridor])
    areas = [(boxes[i][2] - boxes[i][0]) * (boxes[i][3] - boxes[i][1]) for i in new]
    living = new[int(np.argmax(areas))]
    others = iter(pick_names(HOUSE_NAMES, FILLER_NAMES["house"], n_rooms - 1, rng))
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
    names += pick_names(OFFICE_SPECIAL[: max(1, n_rooms // 3)], FILLER_NAMES["office"], n_rooms, rng)
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
        for j, width in enumerate(split_length(rng, length, int(k), min_width, geo.wall, what, first)):
            door = make_door(rng, (-1, -1), 0, (col, col + width), band.wall, geo, avoid)
            if door is None:
                raise DatasetError(f"{what}: no place for a door in a room {width} cells wide; use a larger size")
            between = None
            if j and rng.random() < p_between:
                between = make_door(rng, (-1, -1), 1, band.rows, (col - geo.wall, col), geo)
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
