"""Learning a building: the package's learners on the joint dataset (:mod:`spcotmhp.building.joint`), unchanged;
teaching with a floor.

* :func:`learn_building` fits the supervised ("ideal") model or the batch Gibbs learner (several runs, one kept,
  :class:`~spcotmhp.learning.selection.MultiRunSelector`) on the joint dataset; K defaults to
  ``PLACES_PER_FLOOR`` per floor (the single-floor default, 20, per floor: every floor's places share one
  truncation).
* One prior adapts to the joint frame (:func:`building_hyper`). The place prior mu_k ~ N(m0, Sigma_k / kappa0)
  (Eq. 5) with m0 = 0 adds kappa0 n / (kappa0 + n) (xbar - m0)(xbar - m0)^T to a place's scatter: a weight that
  grows with the square of the place's distance from the frame's origin. On one floor that distance is at most
  the floor's extent D_floor; in the joint frame a floor's tile lies up to the joint grid's diagonal D_joint away,
  which would widen the places of the upper floors by metres. So a building's kappa0 is the single floor's times
  (D_floor / D_joint)^2 (at least the hyper-parameter floor 1e-6): the largest pull any place of the building
  gets is the largest it could get on its floor alone.
* :func:`learn_building_online` streams every floor's events, floor by floor, through the online learner.
* :func:`teach_building` teaches events said on one floor (positions in that floor's map frame): they are moved
  into the joint frame and taught to the joint model (:func:`~spcotmhp.teaching.teach.teach`); a new place lands
  on that floor.

    >>> from spcotmhp.building.synthetic import generate_building
    >>> bm = learn_building(generate_building(2, seed=0, n_rooms=4, events_per_room=4))
    >>> [int(bm.floor_places(f).sum()) for f in bm.indices]
    [4, 4]
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Callable, Iterable, Mapping

import numpy as np

from spcotmhp.building.joint import joint_dataset
from spcotmhp.building.layout import Layout
from spcotmhp.building.loader import Building
from spcotmhp.building.model import BuildingModel
from spcotmhp.errors import TeachingError
from spcotmhp.language.said_names import record_dataset_names
from spcotmhp.learning.model import DERIVED, Hyperparameters
from spcotmhp.learning.online import TeachingEvent
from spcotmhp.limits import MAX_PLACES
from spcotmhp.teaching.teach import Taught, teach

PLACES_PER_FLOOR = 20
MIN_KAPPA0 = 1e-6  # the least kappa0 a model accepts (learning/model_values.py)


def building_hyper(layout: Layout, base: Hyperparameters) -> Hyperparameters:
    """``base`` with kappa0 scaled to the joint frame (module docstring); alpha, gamma and omega that ``base``
    derives from the truncation stay derived."""
    floor = max(math.hypot(*np.abs(np.array(t.origin)) + layout.resolution * np.array(t.shape[::-1]))
                for t in layout.tiles)  # fmt: skip
    joint = layout.resolution * math.hypot(layout.height, layout.width)
    values = {f.name: getattr(base, f.name) for f in dataclasses.fields(base)}
    values["kappa0"] = max(base.kappa0 * min(floor / joint, 1.0) ** 2, MIN_KAPPA0)
    values.update({name: DERIVED for name in getattr(base, "_derived", ())})
    return Hyperparameters(**values)


def default_places(n_floors: int) -> int:
    """K of a building's learner: PLACES_PER_FLOOR per floor, at most MAX_PLACES."""
    return min(PLACES_PER_FLOOR * n_floors, MAX_PLACES)


def learn_building(
    building: Building,
    supervised: bool = True,
    *,
    K: int | None = None,
    L: int = 20,
    runs: int = 10,
    iterations: int = 100,
    seed: int = 0,
    jobs: int = 1,
    progress: Callable[[int], None] | None = None,
    **options: object,
) -> BuildingModel:
    """A building's model: the supervised fit (``supervised``; ``options`` go to ``fit_supervised``) or the
    batch Gibbs learner (``options`` go to :class:`~spcotmhp.learning.gibbs.SpCoTMHP`) on the joint dataset."""
    layout = building.layout()
    data = joint_dataset(building, layout)
    if supervised:
        from spcotmhp.learning.supervised import SUPERVISED_HYPER, fit_supervised

        hyper = building_hyper(layout, SUPERVISED_HYPER)
        model = fit_supervised(data, hyper=hyper, **options)  # type: ignore[arg-type]  # fit_supervised's keywords
    else:
        from spcotmhp.learning.gibbs import SpCoTMHP
        from spcotmhp.learning.selection import MultiRunSelector

        hyper = building_hyper(layout, Hyperparameters())
        K = K or default_places(len(layout.tiles))
        est = SpCoTMHP(K=K, L=L, iterations=iterations, seed=seed, hyper=hyper, **options)  # type: ignore[arg-type]
        model = MultiRunSelector(est, runs=runs, n_jobs=jobs).fit(data, progress=progress).model_
    model.info["building"] = building.name
    return BuildingModel(model, layout, building.spec)


def learn_building_online(building: Building, seed: int = 0, **params: object) -> BuildingModel:
    """The online learner over every floor's events, floor by floor (``params`` go to
    :class:`~spcotmhp.learning.online.OnlineSpCoTMHP`; K defaults as :func:`learn_building`'s)."""
    from spcotmhp.learning.online import OnlineSpCoTMHP

    layout = building.layout()
    data = joint_dataset(building, layout)
    params.setdefault("K", default_places(len(layout.tiles)))
    params.setdefault("hyper", building_hyper(layout, Hyperparameters()))
    learner = OnlineSpCoTMHP(map=data.map, seed=seed, **params)  # type: ignore[arg-type]
    feats = data.features if data.features is not None else [None] * data.n_events
    events = [
        TeachingEvent(float(x), float(y), tuple(t), f)
        for (x, y), t, f in zip(data.positions, data.tokens, feats, strict=True)
    ]
    model = learner.partial_fit(events).model_
    record_dataset_names(model, data.tokens, data.lang, learner.state_.place)  # taught names (said_names.py)
    model.info["building"] = building.name
    return BuildingModel(model, layout, building.spec)


def teach_building(bm: BuildingModel, events: Iterable[object], floor: object) -> tuple[BuildingModel, Taught]:
    """Teach ``events`` (the forms :func:`~spcotmhp.teaching.teach.teach` takes, positions in floor ``floor``'s
    map frame) to the building's model; returns the updated building model and what was learned (place ids are
    the joint model's; :meth:`BuildingModel.place_floor` gives their floors). TeachingError for a position off
    that floor's map; UnknownFloor for a floor the building does not have."""
    index = bm.check_floor(floor)
    moved = [_moved(bm, index, item) for item in events]
    taught = teach(bm.model, moved)
    updated = BuildingModel(taught.model, bm.layout, bm.spec)
    return updated, taught


def _moved(bm: BuildingModel, index: int, item: object) -> object:
    """``item`` with its position moved from floor ``index``'s frame into the joint frame."""
    x: object
    y: object
    if isinstance(item, TeachingEvent):
        x, y = item.x, item.y
    elif isinstance(item, Mapping):
        x, y = item.get("x"), item.get("y")
    elif isinstance(item, (tuple, list)) and len(item) in (3, 4):
        x, y = item[0], item[1]
    else:
        return item  # teach refuses it with its own message
    try:
        xy = np.array([float(x), float(y)])  # type: ignore[arg-type]
    except (TypeError, ValueError):
        return item
    t = bm.layout.tile(index)
    res = bm.layout.resolution
    lo, hi = np.array(t.origin), np.array(t.origin) + res * np.array([t.shape[1], t.shape[0]])
    if not (np.isfinite(xy).all() and (xy >= lo).all() and (xy < hi).all()):
        raise TeachingError(
            f"({xy[0]:.4g}, {xy[1]:.4g}) is off floor {index}'s map (x {lo[0]:.2f}..{hi[0]:.2f}, "
            f"y {lo[1]:.2f}..{hi[1]:.2f})"
        )
    jx, jy = bm.layout.to_joint(index, xy)[0]
    if isinstance(item, TeachingEvent):
        return dataclasses.replace(item, x=float(jx), y=float(jy))
    if isinstance(item, Mapping):
        return {**item, "x": float(jx), "y": float(jy)}
    return (float(jx), float(jy), *item[2:])
