"""The occupancy grid map (metric level) and world <-> cell transforms.

Storage follows nav_msgs/OccupancyGrid: ``data[row, col]`` with row 0 the row at the map origin (the BOTTOM
row of the map_server image), values 0 (free) .. 100 (occupied) and -1 (unknown).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

FREE = 0
OCCUPIED = 100
UNKNOWN = -1
FAR_CELL = 2.0**62  # the cell index given to a point too far to index (world_to_cell): off any map


@dataclass(eq=False)
class OccupancyMap:
    """An occupancy grid in OccupancyGrid order.

    Attributes:
        data: int8 array (height, width); 0 free, 100 occupied, -1 unknown, 1..99 only in ``scale`` mode.
        resolution: metres per cell.
        origin: (x, y, yaw) of the lower-left corner of cell (0, 0) in the map frame; yaw must be 0.
        mode, negate, occupied_thresh, free_thresh: the map_server settings it was loaded with (kept for saving).
        source: the YAML file it came from, if any.
    """

    data: np.ndarray
    resolution: float
    origin: tuple[float, float, float] = (0.0, 0.0, 0.0)
    mode: str = "trinary"
    negate: bool = False
    occupied_thresh: float = 0.65
    free_thresh: float = 0.196
    source: Path | None = field(default=None, compare=False)

    def __eq__(self, other: object) -> bool:
        """Same grid values, resolution, origin and map_server settings (the source path is ignored)."""
        if not isinstance(other, OccupancyMap):
            return NotImplemented
        return (
            self.data.shape == other.data.shape
            and bool(np.array_equal(self.data, other.data))
            and self.resolution == other.resolution
            and tuple(self.origin) == tuple(other.origin)
            and self.mode == other.mode
            and self.negate == other.negate
            and self.occupied_thresh == other.occupied_thresh
            and self.free_thresh == other.free_thresh
        )

    __hash__ = None  # type: ignore[assignment]  # mutable array inside

    @property
    def height(self) -> int:
        return int(self.data.shape[0])

    @property
    def width(self) -> int:
        return int(self.data.shape[1])

    @property
    def shape(self) -> tuple[int, int]:
        return (self.height, self.width)

    @property
    def free(self) -> np.ndarray:
        """Boolean mask of free cells (value 0)."""
        return self.data == FREE

    @property
    def occupied(self) -> np.ndarray:
        """Boolean mask of occupied cells (value >= 100 after map_server thresholds)."""
        return self.data >= OCCUPIED

    @property
    def unknown(self) -> np.ndarray:
        return self.data < 0

    def world_to_cell(self, xy: np.ndarray) -> np.ndarray:
        """Map-frame metres (..., 2) as (x, y) -> integer cells (..., 2) as (row, col); may lie off the map.

        >>> occ = OccupancyMap(np.zeros((4, 5), np.int8), resolution=0.5, origin=(-1.0, -1.0, 0.0))
        >>> occ.world_to_cell(np.array([0.3, 0.9])).tolist(), occ.cell_to_world(np.array([0, 0])).tolist()
        ([3, 2], [-0.75, -0.75])
        """
        xy = np.asarray(xy, dtype=float)
        # a coordinate past ~1e300 m divides to inf (and a NaN stays NaN), which no int64 holds: such a point lies
        # off every map, so it becomes a cell far off the map (+-2**62), the answer in_bounds and every caller
        # needs; the overflow is then expected, not a warning for the user
        with np.errstate(over="ignore", invalid="ignore"):
            cells = np.floor((xy[..., ::-1] - np.array(self.origin[1::-1], dtype=float)) / self.resolution)
        return np.clip(np.nan_to_num(cells, nan=-FAR_CELL), -FAR_CELL, FAR_CELL).astype(np.int64)

    def cell_to_world(self, rc: np.ndarray) -> np.ndarray:
        """Cells (..., 2) as (row, col) -> the map-frame coordinates (x, y) of their centres."""
        # (col, row) + 1/2 cell, scaled, plus the origin's (x, y): one expression for any shape
        return (np.asarray(rc, dtype=float)[..., ::-1] + 0.5) * self.resolution + np.array(self.origin[:2], dtype=float)

    def in_bounds(self, rc: np.ndarray) -> np.ndarray:
        rc = np.asarray(rc)
        return (rc[..., 0] >= 0) & (rc[..., 0] < self.height) & (rc[..., 1] >= 0) & (rc[..., 1] < self.width)

    def cell_centres(self) -> np.ndarray:
        """World coordinates of every cell centre, shape (height, width, 2)."""
        return self.window_centres(0, 0, *self.shape)

    def window_centres(self, r0: int, c0: int, h: int, w: int) -> np.ndarray:
        """:meth:`cell_to_world` of every cell of the window of ``h`` x ``w`` cells whose corner is cell (r0, c0),
        shape (h, w, 2): the same arithmetic on each row's and column's number, written out over the window
        (no (h, w, 2) array of cell numbers first: 0.5 GB and 2 s at 16 megapixels)."""
        x = (np.arange(c0, c0 + w, dtype=float) + 0.5) * self.resolution + float(self.origin[0])
        y = (np.arange(r0, r0 + h, dtype=float) + 0.5) * self.resolution + float(self.origin[1])
        out = np.empty((h, w, 2))
        out[..., 0] = x[None, :]
        out[..., 1] = y[:, None]
        return out
