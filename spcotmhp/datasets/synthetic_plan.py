"""Seeded synthetic floor plans: named rooms, corridors and doors on an occupancy grid.

``generate_floor_plan`` lays out a ``flat``, a ``house`` or an ``office`` (see ``synthetic_layouts``) of
axis-aligned rectangular rooms separated by walls 1-2 cells thick, from a 3-room flat on 60 x 60 cells to an
office of 60 places (rooms along corridors) on 1000 x 1000 cells. Corridors are places too, named ``corridor``;
other names repeat (several bedrooms, many offices).

Doors are ``door_m`` >= 0.6 m wide (1.0 m by default), so a robot still passes after costmap_2d inflation with
inscribed radius 0.22 m: the door's middle cells are at least 0.3 m from both jambs, outside the lethal (254)
and inscribed (253) zones (a 0.6 m door at 0.1 m per cell leaves a gap of two cells). Outside the building is unknown
(-1), walls are
occupied (100), inside is free (0). Every random choice comes from one ``np.random.default_rng(seed)``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from spcotmhp.datasets.synthetic_corridors import house_layout, office_layout
from spcotmhp.datasets.synthetic_layouts import Box, Door, Geometry, flat_layout
from spcotmhp.datasets.synthetic_vocab import CORRIDOR
from spcotmhp.errors import DatasetError
from spcotmhp.limits import MAX_SYNTH_ROOMS, check_count
from spcotmhp.metric.maps import FREE, OCCUPIED, UNKNOWN, OccupancyMap
from spcotmhp.safe_read import MAX_MAP_ASPECT, max_map_pixels

__all__ = ["Door", "FloorPlan", "Room", "generate_floor_plan"]

KINDS = ("flat", "house", "office")
DEFAULT_ROOMS = {"flat": 3, "house": 11, "office": 20}
AREA_PER_ROOM_M2 = {"flat": 12.0, "house": 12.0, "office": 150.0}
MIN_ROOMS = {"flat": 1, "house": 4, "office": 3}
MIN_DOOR_M = 0.6
JAMB_M = 0.2  # the least wall left between a door and the corner of a room

LAYOUTS = {"flat": flat_layout, "house": house_layout, "office": office_layout}


@dataclass
class Room:
    """One place of the plan: ``box`` is its free interior (row0, col0, row1, col1), half-open, in cells;
    ``doors`` the middle cell (row, col) of each of its openings (see ``Door.cell``)."""

    name: str
    index: int
    box: Box
    doors: list[tuple[int, int]] = field(default_factory=list)

    @property
    def is_corridor(self) -> bool:
        """A corridor place: "corridor" or a name ending in it ("east corridor")."""
        return self.name == CORRIDOR or self.name.endswith(" " + CORRIDOR)


@dataclass
class FloorPlan:
    """A synthetic environment: the map, its rooms and the doors between them.

    ``adjacency[i, j]`` is 1 when rooms i and j are directly connected through a door or an open boundary
    (diagonal 1); ``wall_cells`` is the wall thickness in cells.
    """

    map: OccupancyMap
    rooms: list[Room]
    adjacency: np.ndarray
    kind: str
    doors: list[Door] = field(default_factory=list)
    wall_cells: int = 1

    @property
    def names(self) -> list[str]:
        return [room.name for room in self.rooms]

    @property
    def distinct_names(self) -> list[str]:
        """Distinct room names in order of first appearance (index = concept)."""
        return list(dict.fromkeys(self.names))


def seeded_rng(seed: int | np.random.Generator) -> np.random.Generator:
    """``seed`` itself when it is a Generator, else ``np.random.default_rng(seed)`` for a non-negative integer;
    anything else raises DatasetError (numpy's own message for a negative seed is a traceback)."""
    if isinstance(seed, np.random.Generator):
        return seed
    if isinstance(seed, bool) or not isinstance(seed, (int, np.integer)) or seed < 0:
        raise DatasetError(f"seed must be a non-negative integer or a numpy Generator, got {seed!r}")
    return np.random.default_rng(int(seed))


def _check_plan_settings(
    kind: str, n_rooms: int | None, resolution: float, door_m: float, wall_cells: int | None
) -> int:
    """The number of places of the plan, once the settings are checked (a one-line DatasetError otherwise)."""
    if kind not in KINDS:
        raise DatasetError(f"unknown floor plan kind {kind!r}; accepted: {', '.join(KINDS)}")
    if not (0.01 <= resolution <= 0.2):
        raise DatasetError(f"resolution {resolution} m per cell is outside 0.01 .. 0.2")
    if not door_m >= MIN_DOOR_M:
        raise DatasetError(
            f"door width {door_m} m is below {MIN_DOOR_M} m: an inflated robot (inscribed radius 0.22 m) would not pass"
        )
    if wall_cells is not None and wall_cells not in (1, 2):
        raise DatasetError(f"wall_cells must be 1 or 2, got {wall_cells}")
    n = DEFAULT_ROOMS[kind] if n_rooms is None else n_rooms
    if isinstance(n, bool) or not isinstance(n, (int, np.integer)) or n < MIN_ROOMS[kind]:
        raise DatasetError(f"n_rooms must be an integer >= {MIN_ROOMS[kind]} for a {kind}, got {n_rooms!r}")
    return check_count(n, f"n_rooms ({kind})", MIN_ROOMS[kind], MAX_SYNTH_ROOMS, DatasetError)


def generate_floor_plan(
    kind: str = "flat",
    n_rooms: int | None = None,
    size: int | tuple[int, int] | None = None,
    resolution: float = 0.1,
    seed: int | np.random.Generator = 0,
    door_m: float = 1.0,
    wall_cells: int | None = None,
    origin: tuple[float, float] = (0.0, 0.0),
) -> FloorPlan:
    """A random floor plan of ``n_rooms`` places (corridor places included) on a ``size`` grid.

    Args:
        kind: "flat", "house" or "office".
        n_rooms: number of places, corridors included (default 3 / 11 / 20).
        size: grid cells, an int (square) or (height, width); default from ``n_rooms`` (12 m^2 per place in
            flats and houses, 150 m^2 in offices: 60 office places -> about 1000 x 1000 cells at 0.1 m).
        resolution: metres per cell (0.01 .. 0.2).
        seed: an int or a numpy Generator; the same seed gives the same plan.
        door_m: door width in metres, >= 0.6 (see the module docstring).
        wall_cells: wall thickness 1 or 2 cells (default: drawn at random).
        origin: (x, y) of the map's lower-left corner in metres.
    """
    n = _check_plan_settings(kind, n_rooms, resolution, door_m, wall_cells)
    rng = seeded_rng(seed)
    shape = _shape(kind, int(n), size, resolution)
    door = math.ceil(door_m / resolution - 1e-9)
    jamb = max(1, math.ceil(JAMB_M / resolution - 1e-9))
    geo = Geometry(
        wall=int(wall_cells or rng.integers(1, 3)),
        door=door,
        jamb=jamb,
        min_side=max(math.ceil(2.0 / resolution), door + 2 * jamb + 2),
        res=resolution,
    )
    margin = max(1, round(0.02 * min(shape))) + int(rng.integers(0, 3))
    inner = (margin + geo.wall, margin + geo.wall, shape[0] - margin - geo.wall, shape[1] - margin - geo.wall)
    if min(inner[2] - inner[0], inner[3] - inner[1]) < geo.min_side:
        raise DatasetError(f"size {shape} cells is too small for any {kind} at {resolution} m per cell")
    boxes, names, doors = LAYOUTS[kind](inner, int(n), geo, rng)
    data = _rasterise(shape, boxes, doors, geo.wall)
    rooms = [Room(name, i, box) for i, (name, box) in enumerate(zip(names, boxes, strict=False))]
    adjacency = np.eye(len(rooms), dtype=np.int64)
    for d in doors:
        a, b = d.rooms
        adjacency[a, b] = adjacency[b, a] = 1
        rooms[a].doors.append(d.cell)
        rooms[b].doors.append(d.cell)
    occupancy = OccupancyMap(data=data, resolution=float(resolution), origin=(float(origin[0]), float(origin[1]), 0.0))
    return FloorPlan(map=occupancy, rooms=rooms, adjacency=adjacency, kind=kind, doors=doors, wall_cells=geo.wall)


def _shape(kind: str, n: int, size: int | tuple[int, int] | None, res: float) -> tuple[int, int]:
    """The grid's (height, width): ``size``, else what ``n`` places need; at most the map loader's pixel cap and
    aspect ratio (so that every map written here loads back)."""
    shape = _requested_shape(kind, n, size, res)
    cap = max_map_pixels()
    if shape[0] * shape[1] > cap:
        asked = f"size {size!r}" if size is not None else f"{n} places of a {kind} at {res:g} m per cell"
        raise DatasetError(
            f"a {shape[0]} x {shape[1]} map ({asked}) has {shape[0] * shape[1]} pixels, over the cap of {cap} of "
            "the map loader (SPCOTMHP_MAX_MAP_PIXELS); use a smaller size or fewer rooms"
        )
    if max(shape) > MAX_MAP_ASPECT * min(shape):
        raise DatasetError(
            f"a {shape[0]} x {shape[1]} map is longer than {MAX_MAP_ASPECT} times its width, the map loader's "
            "largest aspect ratio; use a squarer size"
        )
    return shape


def _requested_shape(kind: str, n: int, size: int | tuple[int, int] | None, res: float) -> tuple[int, int]:
    if size is None:  # houses: a corridor between two rows of rooms, 9.5 m deep, as long as their area needs
        area = n * AREA_PER_ROOM_M2[kind]
        height = 9.5 if kind == "house" else math.sqrt(area)
        width = max(area / height, 9.0) if kind == "house" else height
        pad = 2 * (max(1, round(0.02 * min(height, width) / res)) + 4)
        return (round(height / res) + pad, round(width / res) + pad)
    try:
        shape = (size, size) if isinstance(size, (int, np.integer)) else tuple(size)
    except TypeError:
        shape = ()
    if len(shape) != 2 or not all(isinstance(s, (int, np.integer)) and s > 0 for s in shape):
        raise DatasetError(f"size must be a positive int or (height, width) in cells, got {size!r}")
    return (int(shape[0]), int(shape[1]))


def _rasterise(shape: tuple[int, int], boxes: list[Box], doors: list[Door], wall: int) -> np.ndarray:
    """Unknown outside; each room's box plus its wall ring occupied; then the boxes and doors carved free."""
    data = np.full(shape, UNKNOWN, dtype=np.int8)
    for r0, c0, r1, c1 in boxes:
        data[r0 - wall : r1 + wall, c0 - wall : c1 + wall] = OCCUPIED
    for r0, c0, r1, c1 in boxes:
        data[r0:r1, c0:c1] = FREE
    for d in doors:
        r0, c0, r1, c1 = d.cells
        data[r0:r1, c0:c1] = FREE
    return data
