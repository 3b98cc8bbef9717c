"""A building's floors as one dataset in the joint frame (:mod:`spcotmhp.building.layout`), which the learners of
:mod:`spcotmhp.learning` fit unchanged: one vocabulary and one concept set across floors, every floor's places.

What joins, and why:

* positions and trajectories move into their floor's tile; events and poses are concatenated in floor order
  (the walk of floor 1, then of floor 2, ...), so the HMM sees one walk with a jump between floors; that jump
  adds one count to psi between the last place of a floor and the first of the next, which planning never uses
  (a floor's planner renormalises psi within the floor: :meth:`~spcotmhp.building.model.BuildingModel.floor_model`);
* truth places are numbered building-wide (floor 1's places first); truth concepts are shared *by name* when
  every floor names its places (places.csv: a kitchen is a kitchen on every floor), else taken as given when
  every floor has them (the ids are then read as building-wide), else left out;
* place adjacency (adjacency.csv) is block-diagonal: no place of one floor touches a place of another (the
  connectors join floors, not places);
* image features, trajectories, truth, names and adjacency must be on every floor or on none (a BuildingError
  names the floors that lack them), except truth concepts and names, which are dropped when some floor lacks
  them; costmap_ros.csv is not carried over (the joint grid has no recorded costmap).
"""

from __future__ import annotations

import numpy as np
from scipy.linalg import block_diag

from spcotmhp.building.layout import Layout
from spcotmhp.building.loader import Building
from spcotmhp.datasets.dataset import Dataset
from spcotmhp.errors import BuildingError


def joint_dataset(building: Building, layout: Layout | None = None) -> Dataset:
    """The building's floors as one :class:`~spcotmhp.datasets.dataset.Dataset` in the joint frame (module
    docstring), named after the building, on the joint grid."""
    lay = layout or building.layout()
    floors = [building.floors[i] for i in lay.indices]
    _all_or_none(building, lay, "features", "image features")
    _all_or_none(building, lay, "trajectory", "a trajectory.csv")
    features = None if floors[0].features is None else _stack([d.features for d in floors], "image features")
    trajectory, steps = _walks(floors, lay)
    places, concepts, names, adjacency = _truth(floors)
    return Dataset(
        name=building.name,
        map=lay.stitch({i: building.floors[i].map for i in lay.indices}),
        positions=np.concatenate([lay.to_joint(i, d.positions) for i, d in zip(lay.indices, floors, strict=True)]),
        tokens=[list(t) for d in floors for t in d.tokens],
        lang=building.lang,
        features=features,
        trajectory=trajectory,
        event_steps=steps,
        truth_place=places,
        truth_concept=concepts,
        adjacency=adjacency,
        place_names=names,
        path=building.path,
    )


def _all_or_none(building: Building, lay: Layout, attr: str, what: str) -> None:
    has = [i for i in lay.indices if getattr(building.floors[i], attr) is not None]
    if has and len(has) < len(lay.indices):
        lacking = [i for i in lay.indices if i not in has]
        raise BuildingError(
            f"floor(s) {', '.join(map(str, has))} have {what} and floor(s) {', '.join(map(str, lacking))} do not: "
            "give every floor one or none"
        )


def _stack(arrays: list, what: str) -> np.ndarray:
    widths = {np.shape(a)[1] for a in arrays}
    if len(widths) > 1:
        raise BuildingError(f"the floors' {what} have different widths ({sorted(widths)}); they must agree")
    return np.vstack(arrays)


def _walks(floors: list[Dataset], lay: Layout) -> tuple[np.ndarray | None, np.ndarray | None]:
    """The floors' trajectories one after the other (joint frame) and each event's step in the whole."""
    if floors[0].trajectory is None:
        return None, None
    parts, steps, start = [], [], 0
    for i, d in zip(lay.indices, floors, strict=True):
        assert d.trajectory is not None and d.event_steps is not None
        parts.append(lay.to_joint(i, d.trajectory))
        steps.append(np.asarray(d.event_steps, dtype=np.int64) + start)
        start += len(d.trajectory)
    return np.concatenate(parts), np.concatenate(steps)


def _truth(floors: list[Dataset]):
    """(truth places building-wide, truth concepts, place names, block-diagonal adjacency), each None when some
    floor lacks what it needs (module docstring)."""
    truths = [d.truth_place for d in floors]
    if any(t is None for t in truths):
        return None, None, None, None
    sizes = [len(d.place_names) if d.place_names is not None else int(np.max(np.asarray(d.truth_place))) + 1
             for d in floors]  # fmt: skip
    offsets = np.concatenate([[0], np.cumsum(sizes)[:-1]]).astype(np.int64)
    places = np.concatenate([np.asarray(d.truth_place, np.int64) + o for d, o in zip(floors, offsets, strict=True)])
    names = None
    if all(d.place_names is not None for d in floors):
        names = [n for d in floors for n in (d.place_names or [])]
    if names is not None:
        order = {n: k for k, n in enumerate(dict.fromkeys(names))}
        concepts: np.ndarray | None = np.array([order[names[p]] for p in places], dtype=np.int64)
    elif all(d.truth_concept is not None for d in floors):
        concepts = np.concatenate([np.asarray(d.truth_concept, np.int64) for d in floors])
    else:
        concepts = None
    adjacency = None
    if all(d.adjacency is not None for d in floors):
        adjacency = block_diag(*[np.asarray(d.adjacency) for d in floors]).astype(np.int64)
    return places, concepts, names, adjacency
