"""A dataset's recorded costmap (costmap_ros.csv) against the cost map of the robot's body: used or refused.

Rule: ``learn`` uses a costmap_ros.csv only as what it is, the costmap the robot's navigation stack computed,
and so requires the model's body to produce it. The body's cost map (:func:`~spcotmhp.metric.costmap.inflate`,
published 0..100) must equal the recorded one on every cell the recording knows (not -1); then the model's cost
map is the recorded one, cell for cell. Any other cell is a contradiction and ``learn`` refuses with one line
saying how many cells the recording keeps the robot out of (>= 99, inscribed or lethal) that the body would plan
through, how many the other way, how many differ only in their inflated cost, and how far from obstacles the
recording's inscribed cells reach (a hint at the radius it was made for). ``check-dataset`` reports the same
against the default body. A recording with marks of other layers (an obstacle layer's) is refused too: remove
the file, or record the static and inflation layers only.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from spcotmhp.metric.costmap import CostMap


@dataclass(frozen=True)
class Comparison:
    """Cells (known to the recording) where the recording and the body's cost map differ."""

    unsafe: int  # recorded >= 99 (inscribed / lethal), the body's < 99: the body would plan through them
    stricter: int  # the body's >= 99, recorded < 99
    other: int  # both below 99 (or both at or above), other values
    reach_m: float  # the largest distance from a lethal cell of a recorded inscribed (99) cell

    @property
    def same(self) -> bool:
        return self.unsafe == self.stricter == self.other == 0

    def describe(self, body: str) -> str:
        """One sentence: how costmap_ros.csv differs from ``body``'s cost map."""
        if self.same:
            return f"costmap_ros.csv is the cost map of {body}, cell for cell"
        return (
            f"costmap_ros.csv differs from the cost map of {body}: {self.unsafe} cells it marks inscribed or lethal "
            f"(99-100) are free for that body, {self.stricter} the other way, {self.other} with another inflated "
            f"cost; its inscribed cells reach {self.reach_m:.3g} m from obstacles"
        )


def compare_recorded(recorded: np.ndarray, costmap: CostMap) -> Comparison:
    """How the recorded grid (OccupancyGrid order, -1 unknown) differs from ``costmap`` (module docstring)."""
    from scipy.ndimage import distance_transform_edt

    ours = costmap.to_occupancy_grid().astype(np.int64)
    rec = np.asarray(recorded, dtype=np.int64)
    known = rec >= 0
    rec_block, our_block = known & (rec >= 99), known & (ours >= 99)
    unsafe = int(np.count_nonzero(rec_block & ~our_block))
    stricter = int(np.count_nonzero(our_block & ~rec_block))
    other = int(np.count_nonzero(known & (rec != ours))) - unsafe - stricter
    lethal = rec == 100
    inscribed = known & (rec == 99)
    reach = 0.0
    if lethal.any() and inscribed.any():
        distance = distance_transform_edt(~lethal) * costmap.map.resolution
        reach = float(distance[inscribed].max())
    return Comparison(unsafe, stricter, other, reach)
