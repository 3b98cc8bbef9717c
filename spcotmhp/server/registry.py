"""The models a service serves: each loaded once, its planner precomputed and its map picture drawn at start-up.

Concurrency: each :class:`ServedModel` owns its graph cache (:class:`~spcotmhp.planning.graph_cache.GraphCache`),
its planner and its two lanes; nothing is shared between served models, not even between two served copies of
one model (there is no module-level table). A planner's graph keeps memos that queries fill (partial paths,
avoidance views), guarded by the graph's own lock (:mod:`spcotmhp.planning.graph`), so plans from several
threads are safe and give the same answers as one after another. The lanes are a scheduling choice, not a
safety one: :meth:`ServedModel.plan` holds the light lane's lock, and :meth:`ServedModel.plan_async` runs the plan
on the light lane's worker thread, off the event loop; costly instructions run on the *heavy* lane, with the
same planner, within admission limits and a time budget (:mod:`spcotmhp.server.scheduling`). A plan takes about
a millisecond of mostly CPU-bound Python (the GIL would serialise it anyway); one worker per lane instead of the
web framework's shared pool of 40 threads saves the threads' contention for the GIL (measured with
benchmarks/load_test.py; docs/results.md gives the throughputs). Requests for different models run in parallel,
and recognition (the slow part of ``/plan/audio``) runs outside the lock (the recogniser has its own).

A building's model (a folder with building.json, or a :class:`~spcotmhp.building.model.BuildingModel`) is served
as its joint model (``/map``, ``/places``: the floors side by side, :mod:`spcotmhp.building.joint`) with a
:class:`~spcotmhp.building.planner.BuildingPlanner` beside it: ``/plan`` then needs the start's ``floor`` and
answers with one segment per floor. ``floor`` with a single floor's model is refused (422).
"""

from __future__ import annotations

import io
import re
import threading
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from spcotmhp.errors import MalformedInstruction, ModelError, TeachingBusy, TeachingError, UnknownFloor
from spcotmhp.learning.model import SpatialConceptModel
from spcotmhp.planning.graph_cache import GraphCache
from spcotmhp.planning.plan import Plan
from spcotmhp.planning.planner import HierarchicalPlanner
from spcotmhp.server.scheduling import Budget, Lane, check_cost, estimate_cost, run_in_lane
from spcotmhp.teaching.questions import said_merges
from spcotmhp.viz.draw import MapImage, map_image, place_colours, render, topological_edges
from spcotmhp.viz.labels import place_display_labels

if TYPE_CHECKING:
    from spcotmhp.building.model import BuildingModel
    from spcotmhp.building.plan import BuildingPlan
    from spcotmhp.building.planner import BuildingPlanner
    from spcotmhp.server.overload import Admission

NAME = re.compile(r"[A-Za-z0-9_.-]{1,64}")


@dataclass
class ServedModel:
    """One served model: the model, its graph cache and precomputed planner, its lanes, display labels and cached
    pictures (module docstring)."""

    name: str
    source: str
    model: SpatialConceptModel
    planner: HierarchicalPlanner
    labels: list[str]
    _image: MapImage | None
    light: Lane = field(default_factory=lambda: Lane("light", Budget.max_light), repr=False)
    heavy: Lane = field(
        default_factory=lambda: Lane("heavy", Budget.max_heavy, Budget.max_heavy_per_client), repr=False
    )
    budget: Budget = field(default_factory=Budget, repr=False)
    cache: GraphCache = field(default_factory=GraphCache, repr=False)
    _figure: bytes | None = field(default=None, repr=False)
    version: int = 0  # teaches so far: the map pictures' ETag (a taught place changes them)
    _teaching: threading.Lock = field(default_factory=threading.Lock, repr=False)
    teach_lane: Lane = field(
        default_factory=lambda: Lane("teach", Budget.max_teach, Budget.max_teach_per_client, TeachingBusy), repr=False
    )
    _draw: threading.Lock = field(default_factory=threading.Lock, repr=False)
    building: BuildingPlanner | None = field(default=None, repr=False)

    @property
    def image(self) -> MapImage:
        """The map picture, drawn on first use after start-up or a teach (a teach does not wait for it)."""
        with self._draw:
            image = self._image
            if image is None:
                image = self._image = map_image(self.model)
            return image

    @property
    def lock(self) -> threading.Lock:
        """The light lane's lock."""
        return self.light.lock

    @classmethod
    def build(
        cls, name: str, item: SpatialConceptModel | BuildingModel, source: str = "", budget: Budget | None = None
    ) -> ServedModel:
        """Precompute the planner (Algorithm 1, lines 1-7), warm it up (:meth:`HierarchicalPlanner.warm_up`: the
        first request does not wait for numba's kernels) and draw the map picture; for a building's model, its
        :class:`~spcotmhp.building.planner.BuildingPlanner` too (module docstring)."""
        model = item if isinstance(item, SpatialConceptModel) else item.model
        if model.map is None:
            raise ModelError(f"model {name!r} ({source}) has no map; the service plans on the model's map")
        budget = budget or Budget()
        cache = GraphCache()
        planner = HierarchicalPlanner(model, cache=cache)
        planner.warm_up()
        light = Lane(f"{name}-light", budget.max_light)
        heavy = Lane(f"{name}-heavy", budget.max_heavy, budget.max_heavy_per_client)
        teach_lane = Lane(f"{name}-teach", budget.max_teach, budget.max_teach_per_client, TeachingBusy)
        return cls(
            name,
            source,
            model,
            planner,
            place_display_labels(model, planner.place_words),
            map_image(model),
            light,
            heavy,
            budget,
            cache,
            teach_lane=teach_lane,
            building=None if isinstance(item, SpatialConceptModel) else _building_planner(item, cache),
        )

    @property
    def place_words(self) -> list[str]:
        return list(self.planner.place_words)

    def plan(
        self, instruction: Any, start: Sequence[float], lang: str | None = None, floor: object = None
    ) -> Plan | BuildingPlan:
        """Plan under this model's lock (module docstring)."""
        with self.lock:
            return self._planned(instruction, start, lang, floor)

    def _planned(
        self, instruction: Any, start: Sequence[float], lang: str | None, floor: object, heavy: bool = False
    ) -> Plan | BuildingPlan:
        """The plan of the building's planner (``floor``: the start's) or of the single floor's (the heavy lane's
        planner when ``heavy``)."""
        if self.building is None:
            if floor is not None:
                raise MalformedInstruction(f"'floor' is for a building's model; model {self.name!r} is one floor")
            return (self._heavy_planner() if heavy else self.planner).plan(instruction, start, lang)
        if floor is None:
            raise UnknownFloor(
                f"model {self.name!r} is a building's: give 'floor', the start's floor "
                f"({self.building.bm.spec.describe_floors()})"
            )
        return self.building.plan(instruction, start, floor, lang=lang)

    async def plan_async(
        self,
        instruction: Any,
        start: Sequence[float],
        lang: str | None = None,
        client: str = "",
        floor: object = None,
        admission: Admission | None = None,
    ) -> Plan | BuildingPlan:
        """Plan on the light or heavy lane by the instruction's cost, within the budget (module docstring), and
        within ``admission``'s deadline on the wait (:class:`spcotmhp.server.overload.Admission`)."""
        cost = estimate_cost(instruction)
        check_cost(cost, self.budget)
        heavy = cost > self.budget.light_cost
        return await run_in_lane(
            self.heavy if heavy else self.light,
            client,
            self.budget.time_budget,
            lambda: self._planned(instruction, start, lang, floor, heavy),
            admission=admission,
        )

    def _heavy_planner(self) -> HierarchicalPlanner:
        """The heavy lane's planner: the light lane's own (its graph's memos are thread-safe), so a heavy request
        never waits for a second precomputation."""
        return self.planner

    async def teach_async(
        self, utterance: str, x: float, y: float, client: str = "", floor: object = None, answer: bool = False
    ) -> dict:
        """:meth:`teach` on the teaching lane, within its admission limits and time budget (TeachingBusy)."""
        return await run_in_lane(
            self.teach_lane,
            client,
            self.budget.teach_budget,
            lambda: self.teach(utterance, x, y, floor, answer),
            lambda why: TeachingBusy(f"the teach was {why}; it is applied when it finishes"),
        )

    def teach(self, utterance: str, x: float, y: float, floor: object = None, answer: bool = False) -> dict:
        """Learn that ``utterance`` was said at (x, y) (online learning, :mod:`spcotmhp.teaching.teach`), update
        the planning graph off the planning lanes (``PlanningGraph.update``: only the fields of new or moved nodes),
        then swap model, planner and labels in at once under the light lane's lock, so that every later plan uses
        the update and no plan sees half of it; the map picture is drawn again on its next request. Teaches of
        one model run one at a time; the served model stays as it was on a TeachingError. The update lives in
        memory (the model folder is not rewritten). A building's model is taught on ``floor`` ((x, y) in that
        floor's map frame: :func:`~spcotmhp.building.learn.teach_building`) and its building planner made again.
        ``answer``: the utterance answers one of the model's questions (:mod:`spcotmhp.teaching.answers`)."""
        from spcotmhp.teaching.teach import planner_for, teach

        if (floor is None) != (self.building is None):
            why = "give 'floor', the floor taught on" if floor is None else "'floor' is for a building's model"
            raise TeachingError(f"model {self.name!r}: {why}")
        with self._teaching:
            building = self.building
            if building is not None:
                updated, taught = _teach_building(building, utterance, x, y, floor)
                building = _building_planner(updated, self.cache, warm=False)
            else:
                taught = teach(self.model, [{"x": x, "y": y, "utterance": utterance, "answer": answer}])
            planner, seconds = planner_for(taught.model, self.planner.settings, self.planner, self.cache)
            labels = place_display_labels(taught.model, planner.place_words)
            with self.lock:
                self.model, self.planner, self.labels, self.building = taught.model, planner, labels, building
                with self._draw:
                    self._image, self._figure = None, None
                self.version += 1
        return {
            "model": self.name,
            **taught.summary(),
            "place_words": self.place_words,
            "time_planner_s": seconds,
        }

    def questions(self, max_questions: int = 5) -> dict:
        """``{"questions": [...]}`` where an answer would help the model most (:mod:`spcotmhp.teaching.questions`);
        answer one with ``POST /teach`` at its (x, y)."""
        from spcotmhp.teaching.questions import questions

        return {"model": self.name, "questions": questions(self.model, max_questions)}

    def figure_png(self) -> bytes:
        """The framed picture of the learned map (axes in metres), drawn on first use."""
        with self._draw:
            if self._figure is None:
                buf = io.BytesIO()
                render(
                    self.model.require_map(),
                    buf,
                    model=self.model,
                    names=self.labels,
                    title=f"learned map '{self.name}'",
                )
                self._figure = buf.getvalue()
            return self._figure

    def places(self) -> dict:
        """Ids, names, labels, means, covariances and colours of the active places, and the Figure 3 edges."""
        m = self.model
        act = [int(k) for k in np.flatnonzero(m.active_places)]
        colours = dict(zip(act, place_colours(len(act)), strict=False))
        names = self.planner.shown
        return {
            "model": self.name,
            "places": [
                {
                    "id": k,
                    "name": names[k],
                    "label": self.labels[k],
                    "mean": m.mu[k].tolist(),
                    "covariance": m.Sigma[k].tolist(),
                    "colour": colours[k],
                }
                for k in act
            ],
            "edges": topological_edges(m),
            "place_words": self.place_words,
            "merges": [found.as_dict() for found in said_merges(m)],
        }

    def summary(self) -> dict:
        """What ``GET /models`` shows: no folder path (the service may be reachable from other machines)."""
        return {
            "name": self.name,
            "places": int(self.model.active_places.sum()),
            "place_words": self.place_words,
            "time_precompute_s": self.planner.graph.time_precompute_s,
        }


def load_served(
    models: Mapping[str, str | Path | SpatialConceptModel | BuildingModel],
    progress: Callable[[str], None] | None = None,
    budget: Budget | None = None,
) -> dict[str, ServedModel]:
    """Build every served model (name -> model folder or model), in order; the first is the default."""
    from spcotmhp.building.io import is_building_model, load_building_model
    from spcotmhp.persistence.io import load_model

    if not models:
        raise ModelError("no model to serve: give at least one model folder")
    out: dict[str, ServedModel] = {}
    for name, item in models.items():
        if not NAME.fullmatch(name):
            raise ModelError(f"bad model name {name!r}: use letters, digits, '-', '_' or '.'")
        if progress is not None:
            progress(name)
        if not isinstance(item, (str, Path)):
            out[name] = ServedModel.build(name, item, "(in memory)", budget)
        else:
            loaded = load_building_model(item) if is_building_model(item) else load_model(item)
            out[name] = ServedModel.build(name, loaded, str(item), budget)
    return out


def _building_planner(bm: BuildingModel, cache: GraphCache, warm: bool = True) -> BuildingPlanner:
    """The building's planner, on the served model's graph cache, warmed up as the single floor's."""
    from spcotmhp.building.planner import BuildingPlanner

    planner = BuildingPlanner(bm, cache=cache)
    for p in planner.floors.values() if warm else ():
        p.warm_up()
    return planner


def _teach_building(building: BuildingPlanner, utterance: str, x: float, y: float, floor: object):
    """:func:`~spcotmhp.building.learn.teach_building` with a floor the building lacks as a TeachingError (422)."""
    from spcotmhp.building.learn import teach_building
    from spcotmhp.errors import UnknownFloor

    try:
        return teach_building(building.bm, [{"x": x, "y": y, "utterance": utterance}], floor)
    except UnknownFloor as exc:
        raise TeachingError(str(exc)) from None
