"""A building's model: one :class:`~spcotmhp.learning.model.SpatialConceptModel` learned in the joint frame
(:mod:`spcotmhp.building.joint`), the floors' layout and the connectors; each floor seen as an ordinary model.

Places know their floor: place k is on the floor whose tile holds its mean (:meth:`BuildingModel.place_floor`;
tiles are a floor's diagonal apart, so a place fitted to one floor's events has its mean in that floor's tile).
The concepts, the vocabulary, pi, phi, W and theta are the building's: "kitchen" is one concept whose places lie
on several floors.

:meth:`BuildingModel.floor_model` is floor f as a single-floor model that every planner, exporter and picture of
the package takes unchanged: the joint model's arrays, with the means moved into floor f's own map frame, only
floor f's places active, floor f's map (cut out of the joint grid, the same cells and origin as its dataset's)
and psi renormalised over floor f's places (a step of a floor's planning graph stays on the floor: psi_f[a, b] =
psi[a, b] / sum_{b' on f} psi[a, b']). phi is not renormalised, so the word term of Eq. 28 is the same number on
every floor and plans that compare floors compare like with like.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass, field

import numpy as np

from spcotmhp.building.layout import Layout
from spcotmhp.building.spec import BuildingSpec
from spcotmhp.errors import ModelError, UnknownFloor
from spcotmhp.learning.model import SpatialConceptModel

RELATIVE = {"upstairs": 1, "up": 1, "above": 1, "downstairs": -1, "down": -1, "below": -1}
"""Floor words read relative to the start's floor: the next floor up or down, in index order."""
ENDS = {"top": 1, "bottom": -1}
"""Floor words for the highest and lowest floor (index order), unless a floor has that name."""


@dataclass
class BuildingModel:
    """The joint model, the layout of its floors and the building's spec (floors, connectors)."""

    model: SpatialConceptModel
    layout: Layout
    spec: BuildingSpec
    _views: dict = field(default_factory=dict, repr=False, compare=False)

    def __post_init__(self) -> None:
        if self.layout.indices != self.spec.indices:
            raise ModelError(f"the layout's floors {self.layout.indices} are not the building's {self.spec.indices}")
        occ = self.model.require_map()
        if occ.shape != (self.layout.height, self.layout.width) or occ.resolution != self.layout.resolution:
            raise ModelError(
                f"the model's map ({occ.height} x {occ.width} at {occ.resolution:g} m) is not the building's joint "
                f"grid ({self.layout.height} x {self.layout.width} at {self.layout.resolution:g} m)"
            )

    @property
    def name(self) -> str:
        return self.spec.name

    @property
    def indices(self) -> list[int]:
        return self.spec.indices

    def place_floor(self) -> np.ndarray:
        """(K,) the floor index of each place (the tile holding its mean; module docstring)."""
        return self.layout.floor_of(self.model.mu)

    def floor_places(self, index: int) -> np.ndarray:
        """(K,) bool: the active places of floor ``index``."""
        return np.asarray(self.model.active_places, dtype=bool) & (self.place_floor() == index)

    def floor_model(self, index: int) -> SpatialConceptModel:
        """Floor ``index`` as a single-floor model (module docstring), made once per floor."""
        if index not in self._views:
            self._views[index] = self._view(self.check_floor(index))
        return self._views[index]

    def _view(self, index: int) -> SpatialConceptModel:
        m = self.model
        mine = self.floor_places(index)
        if not mine.any():
            raise ModelError(f"floor {index} ({self.spec.floor(index).name}) has no learned place to plan with")
        psi = np.array(m.psi, dtype=float)
        within = psi[mine][:, mine]
        rows = within.sum(axis=1, keepdims=True)
        block = np.where(rows > 0, within / np.where(rows > 0, rows, 1.0), 1.0 / mine.sum())
        psi[np.ix_(mine, mine)] = block
        psi[np.ix_(mine, ~mine)] = 0.0
        mu = self.layout.from_joint(index, m.mu)
        info = {**m.info, "building": self.name, "floor": index}
        return dataclasses.replace(
            m,
            mu=mu,
            psi=psi,
            active_places=mine,
            map=self.layout.crop(m.require_map(), index),
            info=info,
            learner=None,
            psi_learned=None,
        )

    # ---- floors named by users ------------------------------------------------------------------------
    def check_floor(self, value: object) -> int:
        """The index of the floor ``value`` names: an index (an int, or its digits) or a floor's name (any
        case); else UnknownFloor listing the floors."""
        for f in self.spec.floors:
            if isinstance(value, str) and value.strip().lower() == f.name.lower():
                return f.index
        if isinstance(value, str) and value.strip().lstrip("-").isdigit() and len(value.strip()) < 6:
            value = int(value.strip())
        if isinstance(value, (int, np.integer)) and not isinstance(value, bool) and int(value) in self.indices:
            return int(value)
        raise UnknownFloor(f"the building has no floor {str(value)[:40]!r}; its floors: {self.spec.describe_floors()}")

    def resolve_floor(self, value: object, start_floor: int) -> int:
        """:meth:`check_floor` (an index, or a floor's name in any case: "Ground"), "upstairs"/"downstairs"
        (:data:`RELATIVE`): the next floor up or down from ``start_floor``, in index order (UnknownFloor when there
        is none), and, when no floor has that name, "top"/"bottom" (:data:`ENDS`): the highest or lowest index.
        An int is the index the words gave: "the second floor" is the floor of index 2, whatever its name.

        >>> from spcotmhp.building.spec import parse_spec
        >>> spec = parse_spec({"floors": [{"index": 0, "name": "Ground", "dataset": "g"},
        ...                               {"index": 1, "name": "first", "dataset": "f"}]}, "b")
        >>> bm = BuildingModel.__new__(BuildingModel); bm.spec = spec
        >>> [bm.resolve_floor(v, 0) for v in ("ground", "UPSTAIRS", "top", "bottom", 1, "1")]
        [0, 1, 1, 0, 1, 1]
        """
        if (
            isinstance(value, str)
            and value.strip().lower() in ENDS
            and not any(f.name.lower() == value.strip().lower() for f in self.spec.floors)
        ):
            return self.indices[-1] if ENDS[value.strip().lower()] > 0 else self.indices[0]
        if isinstance(value, str) and value.strip().lower() in RELATIVE:
            step = RELATIVE[value.strip().lower()]
            order = self.indices
            k = order.index(start_floor) + step
            if not 0 <= k < len(order):
                where = "above" if step > 0 else "below"
                raise UnknownFloor(
                    f"no floor lies {where} floor {start_floor}; the floors: {self.spec.describe_floors()}"
                )
            return order[k]
        return self.check_floor(value)
