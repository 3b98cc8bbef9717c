"""ROS costmap_2d cost maps (static layer + inflation layer) and the probabilistic cost map p(x|m).

Reproduces ROS 1 costmap_2d cell for cell (``static_layer.cpp`` with ``trinary_costmap``,
``inflation_layer.cpp``, ``costmap_2d_publisher.cpp``):

* static layer: occupied (>= 100) -> LETHAL 254; unknown (-1) -> NO_INFORMATION 255 if
  ``track_unknown_space`` else FREE 0; everything else FREE 0.
* inflation layer: a wavefront from every lethal cell, processed in order of increasing distance (bins keyed
  by the cached ``hypot(dx, dy)`` kernel, cells appended to the end of their bin, 4-neighbour expansion in
  the order x-1, y-1, x+1, y+1). Each cell keeps the source obstacle that reached it first, so its distance
  is costmap_2d's (occasionally not the exact Euclidean distance to the nearest obstacle, which is why a
  plain distance transform differs from ROS in a few cells per map). Cells are inflated while
  ``d <= ceil(inflation_radius / resolution)`` cells (capped at the map's diagonal, ``max_cell_radius``: no
  two cells are farther apart, so a larger radius gives the same costs and only a larger kernel); the cost at d cells
  is 254 at d = 0, 253 (INSCRIBED)
  while ``d * resolution <= inscribed_radius``, else
  ``int(252 * exp(-cost_scaling_factor * (d * resolution - inscribed_radius)))``; the new cost is the
  maximum with the existing cost (unknown cells take it only if >= 253, or > 0 with ``inflate_unknown``).
* published OccupancyGrid: 0 -> 0, 253 -> 99, 254 -> 100, 255 -> -1, 1..252 -> 1 + (97 * (v - 1)) // 251.

The probabilistic cost map (paper Section 4, the p(x|m) factor of Eqs. 24 and 26) is p(x|m) = (100 - cost) / 100
on the map's free cells below the inscribed cost, and 0 on occupied and unknown cells *and on inscribed cells*;
it is kept as log p (-inf where 0). The authors' code gave inscribed cells p = 0.01; we give them 0 because
costmap_2d's INSCRIBED (253, published as 99) means that a circular robot centred there overlaps an obstacle,
and Nav2's planners treat such cells as collisions. So every cell with p(x|m) > 0 is one the robot's footprint
fits in, and every planner and baseline built on ``log_p`` keeps its footprint clear of obstacles.
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass

import numpy as np

from spcotmhp.errors import MapError
from spcotmhp.metric._wavefront import (  # noqa: F401 - the costs' home is the kernel's module; re-exported
    FREE_SPACE,
    INSCRIBED_INFLATED_OBSTACLE,
    LETHAL_OBSTACLE,
    NO_INFORMATION,
    wavefront,
)
from spcotmhp.metric.maps import OccupancyMap


def _translation_table() -> np.ndarray:
    table = np.empty(256, dtype=np.int8)
    table[0], table[253], table[254], table[255] = 0, 99, 100, -1
    v = np.arange(1, 253)
    table[1:253] = 1 + (97 * (v - 1)) // 251
    return table


COST_TRANSLATION_TABLE = _translation_table()
"""costmap_2d_publisher's table from 0..255 costs to 0..100 OccupancyGrid values (-1 unknown)."""


@dataclass(frozen=True)
class CostMapSettings:
    """costmap_2d parameters (metres). ``inscribed_radius`` is the robot radius for a circular robot;
    ``circumscribed_radius`` the largest distance from the robot's centre to its footprint (None: a circle, the
    inscribed radius). The defaults here are the one home of the package's default body (a 0.22 m circular robot,
    inflation 1.0 m, scaling 10): every model, command and evaluation without a body of its own uses them
    (:mod:`spcotmhp.metric.body`)."""

    inscribed_radius: float = 0.22
    inflation_radius: float = 1.0
    cost_scaling_factor: float = 10.0
    track_unknown_space: bool = False
    inflate_unknown: bool = False
    circumscribed_radius: float | None = None

    def __post_init__(self) -> None:
        if self.circumscribed_radius is None:
            object.__setattr__(self, "circumscribed_radius", self.inscribed_radius)
        for name in ("inscribed_radius", "inflation_radius", "cost_scaling_factor", "circumscribed_radius"):
            value = getattr(self, name)
            if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
                raise MapError(f"cost map setting {name} must be a finite number, got {value!r}")
            if value < 0:
                raise MapError(f"cost map setting {name} must be >= 0, got {value!r}")
        if self.circumscribed_radius < self.inscribed_radius:  # type: ignore[operator]  # set above
            raise MapError(
                f"cost map setting circumscribed_radius ({self.circumscribed_radius!r}) must be at least the "
                f"inscribed radius ({self.inscribed_radius!r}): no point of a footprint is nearer than its nearest edge"
            )

    def as_dict(self) -> dict:
        return asdict(self)

    def circumscribed_cost(self, resolution: float) -> int:
        """costmap_2d's ``getCircumscribedCost``: the inflation cost at the circumscribed radius
        (``computeCost(circumscribed_radius / resolution)``). Below it no heading of the footprint touches an
        obstacle; at or above it some heading may (Nav2's collision checkers test the footprint there)."""
        return compute_cost(float(self.circumscribed_radius) / resolution, resolution, self)  # type: ignore[arg-type]


DEFAULT_COSTMAP = CostMapSettings()
"""The default body's settings (a 0.22 m circle, inflation 1.0 m, scaling 10; :class:`CostMapSettings`)."""


def default_costmap() -> dict:
    """The cost map settings a model without a body of its own keeps (``SpatialConceptModel.costmap``): the
    radius, inflation radius and scaling of :data:`DEFAULT_COSTMAP`, as old model folders hold them."""
    return {
        "inscribed_radius": DEFAULT_COSTMAP.inscribed_radius,
        "inflation_radius": DEFAULT_COSTMAP.inflation_radius,
        "cost_scaling_factor": DEFAULT_COSTMAP.cost_scaling_factor,
    }


@dataclass
class CostMap:
    """A costmap_2d cost map over ``map``.

    Attributes:
        costs: uint8 (height, width) in OccupancyGrid order; 0 free .. 252 inflated, 253 inscribed,
            254 lethal, 255 no information.
        map: the occupancy map it was built from.
        settings: the costmap_2d parameters used.
        log_p: float64 (height, width), log p(x|m) with p = (100 - cost_ros) / 100 on free cells below the
            inscribed cost, -inf elsewhere (occupied, unknown, lethal and inscribed cells).
    """

    costs: np.ndarray
    map: OccupancyMap
    settings: CostMapSettings
    log_p: np.ndarray

    def to_occupancy_grid(self) -> np.ndarray:
        """The int8 0..100 (-1 unknown) grid that costmap_2d publishes, in OccupancyGrid order."""
        return COST_TRANSLATION_TABLE[self.costs]

    @property
    def free(self) -> np.ndarray:
        """Cells with p(x|m) > 0: the map's free cells below the inscribed cost (the robot fits there)."""
        return np.isfinite(self.log_p)

    @property
    def p(self) -> np.ndarray:
        """p(x|m) itself (0 on occupied and unknown cells)."""
        return np.exp(self.log_p)


def inflate(
    occ_map: OccupancyMap,
    inscribed_radius: float | None = None,
    inflation_radius: float = DEFAULT_COSTMAP.inflation_radius,
    cost_scaling_factor: float = DEFAULT_COSTMAP.cost_scaling_factor,
    track_unknown_space: bool = False,
    inflate_unknown: bool = False,
    robot_radius: float | None = None,
    circumscribed_radius: float | None = None,
) -> CostMap:
    """Build the costmap_2d cost map of ``occ_map`` (static + inflation layers, module docstring).

    ``robot_radius`` (a circular robot) is taken as the inscribed radius; give it or ``inscribed_radius``
    (default 0.22 m, :data:`DEFAULT_COSTMAP`), not both. ``circumscribed_radius`` (a footprint polygon's; default
    the inscribed radius) changes no cost, as in costmap_2d: it is kept in the settings for
    :meth:`CostMapSettings.circumscribed_cost`. ``track_unknown_space`` defaults to False as in ROS 1 (unknown
    space is free for the inflation; it is still excluded from p(x|m)).
    """
    if robot_radius is not None and inscribed_radius is not None:
        raise MapError(
            "give either robot_radius or inscribed_radius, not both (a circular robot's radius is its inscribed radius)"
        )
    radius = inscribed_radius if robot_radius is None else robot_radius
    settings = CostMapSettings(
        DEFAULT_COSTMAP.inscribed_radius if radius is None else radius,
        inflation_radius,
        cost_scaling_factor,
        track_unknown_space,
        inflate_unknown,
        circumscribed_radius,
    )
    costs = static_costs(occ_map, settings.track_unknown_space)
    cap = max_cell_radius(occ_map)  # no two cells are farther apart: a larger radius changes nothing
    reach = min(settings.inflation_radius, cap * occ_map.resolution)  # (1e308 m would overflow the division)
    cell_radius = min(cell_distance(reach, occ_map.resolution), cap)
    if cell_radius > 0:
        bins, kernel_costs = inflation_kernel(cell_radius, occ_map.resolution, settings)
        wavefront(costs, bins, kernel_costs, settings.inflate_unknown)
    return CostMap(costs=costs, map=occ_map, settings=settings, log_p=log_probability(costs, occ_map))


def static_costs(occ_map: OccupancyMap, track_unknown_space: bool = False) -> np.ndarray:
    """The static layer's costs (``trinary_costmap``): occupied -> 254, unknown -> 255 or 0, else 0; bytes
    128..254 (int8 -128..-2, read as unsigned by costmap_2d: above lethal) -> 254. Looked up per byte."""
    data = np.asarray(occ_map.data)
    unknown_cost = NO_INFORMATION if track_unknown_space else FREE_SPACE
    if data.dtype == np.int8:  # every map loaded: a table of the rule below for each of the 256 values
        table = np.full(256, FREE_SPACE, dtype=np.uint8)
        table[100:255] = LETHAL_OBSTACLE  # 100..127, and -128..-2 as bytes 128..254
        table[255] = unknown_cost  # -1
        return table[np.ascontiguousarray(data).view(np.uint8)]
    costs = np.where(data >= 100, LETHAL_OBSTACLE, FREE_SPACE)
    costs = np.where(data == -1, unknown_cost, costs)
    costs = np.where((data < -1), LETHAL_OBSTACLE, costs)  # bytes 128..254 read as unsigned: above lethal
    return np.ascontiguousarray(costs, dtype=np.uint8)


def cell_distance(world_distance: float, resolution: float) -> int:
    """costmap_2d's ``Costmap2D::cellDistance``: ceil(distance / resolution) cells, at least 0.  A distance
    that is not a finite number, or a resolution that is not a finite number > 0, raises MapError (negative
    radii are refused earlier, by ``CostMapSettings``)."""
    if not _finite(world_distance):
        raise MapError(f"a distance in metres must be a finite number, got {world_distance!r}")
    if not (_finite(resolution) and resolution > 0):
        raise MapError(f"the map resolution must be a finite number > 0 (metres per cell), got {resolution!r}")
    return int(max(0.0, math.ceil(world_distance / resolution)))


def max_cell_radius(occ_map: OccupancyMap) -> int:
    """ceil(hypot(height, width)): no two cells of the map are this many cells apart, so inflating farther
    changes no cost (the kernel would only grow: 1e9 m at 0.05 m per cell is a 2e10-cell square)."""
    return math.ceil(math.hypot(occ_map.height, occ_map.width))


def _finite(value: object) -> bool:
    return (
        isinstance(value, (int, float, np.integer, np.floating))
        and not isinstance(value, bool)
        and math.isfinite(value)
    )


def inflation_kernel(cell_radius: int, resolution: float, settings: CostMapSettings) -> tuple[np.ndarray, np.ndarray]:
    """costmap_2d's cached kernels over offsets (dx, dy) in 0..cell_radius+1: the rank of the distance
    ``hypot(dx, dy)`` among the distinct distances (the bin; -1 beyond the inflation radius), and the cost.
    ``cell_radius`` must be an integer >= 0 (``inflate`` caps it at ``max_cell_radius``)."""
    if isinstance(cell_radius, bool) or not isinstance(cell_radius, (int, np.integer)) or cell_radius < 0:
        raise MapError(f"the inflation radius in cells must be an integer >= 0, got {cell_radius!r}")
    offsets = np.arange(cell_radius + 2, dtype=np.float64)
    dist = np.hypot(offsets[:, None], offsets[None, :])  # the C library's hypot, as costmap_2d's cache
    values, bins = np.unique(dist, return_inverse=True)
    bins = bins.reshape(dist.shape).astype(np.int64)
    costs = np.array([compute_cost(float(d), resolution, settings) for d in values], dtype=np.uint8)[bins]
    bins[dist > cell_radius] = -1
    return bins, costs


def compute_cost(distance_cells: float, resolution: float, settings: CostMapSettings) -> int:
    """costmap_2d's ``InflationLayer::computeCost`` for a distance in cells."""
    if distance_cells == 0:
        return LETHAL_OBSTACLE
    euclidean = distance_cells * resolution
    if euclidean <= settings.inscribed_radius:
        return INSCRIBED_INFLATED_OBSTACLE
    factor = math.exp(-1.0 * settings.cost_scaling_factor * (euclidean - settings.inscribed_radius))
    return int((INSCRIBED_INFLATED_OBSTACLE - 1) * factor)


def log_probability(costs: np.ndarray, occ_map: OccupancyMap) -> np.ndarray:
    """log p(x|m) with p = (100 - cost_ros) / 100 on the map's free cells below the inscribed cost, -inf elsewhere
    (module docstring). Read from :data:`LOG_P_OF_COST`, the same formula for each of the 256 costs (a lookup,
    not a log of every cell: 1.7 s at 16 megapixels; equal, tests/metric/test_learn_path_as_before.py)."""
    return np.where(occ_map.free, LOG_P_OF_COST[costs], -np.inf)


def _log_p_of_cost() -> np.ndarray:
    """log((100 - cost_ros) / 100) for every cost 0..255, -inf from the inscribed cost up (the robot does not fit)."""
    cost_ros = COST_TRANSLATION_TABLE.astype(np.float64)
    out = np.full(256, -np.inf)
    fits = np.arange(256) < INSCRIBED_INFLATED_OBSTACLE
    out[fits] = np.log((100.0 - cost_ros[fits]) / 100.0)
    return out


LOG_P_OF_COST = _log_p_of_cost()
"""log p(x|m) of a free cell of each cost (:func:`log_probability`)."""
