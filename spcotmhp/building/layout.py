"""The joint frame of a building: its floors' maps side by side in one grid, so that one model learns them all.

A building's model is one :class:`~spcotmhp.learning.model.SpatialConceptModel` (one vocabulary, one concept
set, every floor's places) learned in a *joint frame*: floor f's map is copied into a tile of one occupancy grid,
the tiles in index order along x, all starting at row 0, separated by ``gap`` cells of unknown space. The gap is
the largest floor's diagonal, so any two points on different floors are farther apart than any two points on one
floor: a place's Gaussian fitted to one floor's events gives another floor's events less density than to any
event of its own floor, and a place's floor is the tile its mean lies in (:meth:`Layout.floor_of`). The learners
run unchanged on the joint dataset; the free space of two tiles never touches, so no path, territory or adjacency
computed on the joint map crosses floors.

A point (x, y) of floor f (its own map frame, origin (ox, oy)) is (x - ox + col0 * res, y - oy) in the joint
frame, whose origin is (0, 0); floors must share one resolution (a BuildingError otherwise). The joint grid must
pass the map loader's bounds (pixels and aspect ratio), checked before it is allocated.

    >>> import numpy as np
    >>> from spcotmhp.metric.maps import OccupancyMap
    >>> a = OccupancyMap(np.zeros((30, 40), np.int8), 0.1, (-1.0, -2.0, 0.0))
    >>> b = OccupancyMap(np.zeros((20, 20), np.int8), 0.1)
    >>> lay = Layout.plan({1: a, 2: b})
    >>> lay.gap, lay.width, lay.height
    (51, 111, 30)
    >>> lay.to_joint(2, np.array([0.55, 0.25])).tolist(), int(lay.floor_of(np.array([[9.5, 0.5]]))[0])
    ([[9.65, 0.25]], 2)
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np

from spcotmhp.errors import BuildingError
from spcotmhp.metric.maps import UNKNOWN, OccupancyMap
from spcotmhp.safe_read import MAX_MAP_ASPECT, excerpt, finite_number, max_map_pixels


@dataclass(frozen=True)
class Tile:
    """Where floor ``index`` sits in the joint grid: its map's origin (x, y), shape (rows, columns) and first
    column ``col0``."""

    index: int
    origin: tuple[float, float]
    shape: tuple[int, int]
    col0: int


@dataclass(frozen=True)
class Layout:
    """The joint grid of a building's floors (module docstring)."""

    resolution: float
    tiles: tuple[Tile, ...]
    gap: int

    @property
    def height(self) -> int:
        return max(t.shape[0] for t in self.tiles)

    @property
    def width(self) -> int:
        last = self.tiles[-1]
        return last.col0 + last.shape[1]

    @property
    def indices(self) -> list[int]:
        return [t.index for t in self.tiles]

    def tile(self, index: int) -> Tile:
        for t in self.tiles:
            if t.index == index:
                return t
        raise KeyError(index)

    @classmethod
    def plan(cls, maps: Mapping[int, OccupancyMap]) -> Layout:
        """The layout of the floors' ``maps`` (index -> map): BuildingError when their resolutions differ or the
        joint grid would exceed the map loader's bounds."""
        indices = sorted(maps)
        res = {float(maps[i].resolution) for i in indices}
        if len(res) > 1:
            listed = ", ".join(f"floor {i}: {maps[i].resolution:g} m" for i in indices)
            raise BuildingError(f"the floors' maps must share one resolution to form a building, got {listed}")
        gap = max(math.ceil(math.hypot(*maps[i].shape)) for i in indices) + 1
        tiles, col = [], 0
        for i in indices:
            m = maps[i]
            tiles.append(Tile(i, (float(m.origin[0]), float(m.origin[1])), (m.height, m.width), col))
            col += m.width + gap
        layout = cls(res.pop(), tuple(tiles), gap)
        layout.check_size()
        return layout

    def check_size(self, error: type[Exception] = BuildingError) -> None:
        """``error`` unless the joint grid fits the map loader's bounds (pixels, aspect ratio)."""
        h, w = self.height, self.width
        if h * w > max_map_pixels() or w > MAX_MAP_ASPECT * h:
            raise error(
                f"the building's {len(self.tiles)} floors side by side make a grid of {h} x {w} cells, over the "
                f"map bounds ({max_map_pixels()} pixels, aspect {MAX_MAP_ASPECT}:1; SPCOTMHP_MAX_MAP_PIXELS raises "
                "the first)"
            )

    def to_joint(self, index: int, xy: np.ndarray) -> np.ndarray:
        """(n, 2) joint-frame points of floor ``index``'s points ``xy`` ((2,) or (n, 2))."""
        t = self.tile(index)
        shift = np.array([t.col0 * self.resolution - t.origin[0], -t.origin[1]])
        return np.atleast_2d(np.asarray(xy, dtype=float)) + shift

    def from_joint(self, index: int, xy: np.ndarray) -> np.ndarray:
        """(n, 2) floor ``index``'s frame of joint-frame points ``xy``."""
        t = self.tile(index)
        shift = np.array([t.col0 * self.resolution - t.origin[0], -t.origin[1]])
        return np.atleast_2d(np.asarray(xy, dtype=float)) - shift

    def floor_of(self, xy: np.ndarray) -> np.ndarray:
        """(n,) the floor index of each joint-frame point: the tile whose columns hold its x, else the nearest."""
        x = np.atleast_2d(np.asarray(xy, dtype=float))[:, 0] / self.resolution
        lo = np.array([t.col0 for t in self.tiles], dtype=float)
        hi = lo + np.array([t.shape[1] for t in self.tiles], dtype=float)
        away = np.maximum(lo[None, :] - x[:, None], 0) + np.maximum(x[:, None] - hi[None, :], 0)
        return np.array(self.indices)[np.argmin(away, axis=1)]

    def stitch(self, maps: Mapping[int, OccupancyMap]) -> OccupancyMap:
        """The joint occupancy grid: every floor's cells in its tile, unknown elsewhere."""
        data = np.full((self.height, self.width), UNKNOWN, dtype=np.int8)
        for t in self.tiles:
            data[: t.shape[0], t.col0 : t.col0 + t.shape[1]] = maps[t.index].data
        first = maps[self.tiles[0].index]
        return OccupancyMap(data, self.resolution, (0.0, 0.0, 0.0), first.mode, first.negate,
                            first.occupied_thresh, first.free_thresh)  # fmt: skip

    def crop(self, joint: OccupancyMap, index: int) -> OccupancyMap:
        """Floor ``index``'s map cut back out of the joint grid (the same cells, origin and resolution)."""
        t = self.tile(index)
        data = np.ascontiguousarray(joint.data[: t.shape[0], t.col0 : t.col0 + t.shape[1]])
        return OccupancyMap(data, self.resolution, (t.origin[0], t.origin[1], 0.0), joint.mode, joint.negate,
                            joint.occupied_thresh, joint.free_thresh)  # fmt: skip

    def to_dict(self) -> dict:
        return {
            "resolution": self.resolution,
            "gap": self.gap,
            "tiles": [
                {"index": t.index, "origin": list(t.origin), "shape": list(t.shape), "col0": t.col0} for t in self.tiles
            ],  # fmt: skip
        }

    @classmethod
    def from_dict(cls, doc: object, where: str, error: type[Exception] = BuildingError) -> Layout:
        """The layout saved by :meth:`to_dict`, every field checked (``error`` naming ``where``)."""

        def bad(what: str, value: object) -> Exception:
            return error(f"{where}: layout {what}, got {excerpt(value)}")

        if not isinstance(doc, dict) or set(doc) != {"resolution", "gap", "tiles"}:
            raise bad("must be an object with resolution, gap and tiles", doc)
        res, gap, raw = doc["resolution"], doc["gap"], doc["tiles"]
        if not (finite_number(res) and 0 < float(res) <= 1e3) or isinstance(res, bool):
            raise bad("resolution must be a number in (0, 1000]", res)
        if not isinstance(gap, int) or isinstance(gap, bool) or not 1 <= gap <= 10**6:
            raise bad("gap must be an integer in [1, 1e6]", gap)
        if not isinstance(raw, list) or not 1 <= len(raw) <= 64:
            raise bad("tiles must be a list of 1 to 64 tiles", raw)
        tiles: list[Tile] = []
        col = 0
        for i, t in enumerate(raw):
            ok = isinstance(t, dict) and set(t) == {"index", "origin", "shape", "col0"}
            ok = ok and _ints([t["index"]], -99, 999) and _ints(t["shape"], 1, 10**6) and len(t["shape"]) == 2
            ok = ok and isinstance(t["origin"], list) and len(t["origin"]) == 2
            ok = ok and all(finite_number(v) and not isinstance(v, bool) and abs(float(v)) <= 1e9 for v in t["origin"])
            if not ok or t["col0"] != col or (tiles and t["index"] <= tiles[-1].index):
                raise bad(f"tiles[{i}] must be {{index, origin [x, y], shape [rows, cols], col0}} in order", t)
            shape = (int(t["shape"][0]), int(t["shape"][1]))
            tiles.append(Tile(t["index"], (float(t["origin"][0]), float(t["origin"][1])), shape, col))
            col += t["shape"][1] + gap
        layout = cls(float(res), tuple(tiles), gap)
        layout.check_size(error)
        return layout


def _ints(values: object, low: int, high: int) -> bool:
    return isinstance(values, list) and all(
        isinstance(v, int) and not isinstance(v, bool) and low <= v <= high for v in values
    )
