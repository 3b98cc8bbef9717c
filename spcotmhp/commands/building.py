"""CLI pieces for buildings (spcotmhp/building/): ``synth building``, and the building branches of ``learn`` and
``plan``, which dispatch here when their folder holds a building.yaml (a building folder) or a building.json (a
building model)."""

from __future__ import annotations

import warnings
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

import typer

from spcotmhp.errors import BuildingError

if TYPE_CHECKING:
    from spcotmhp.building.layout import Layout
    from spcotmhp.building.loader import Building
    from spcotmhp.datasets.dataset import Dataset
    from spcotmhp.learning.model import Hyperparameters, SpatialConceptModel
    from spcotmhp.metric.body import RobotBody

SHOWN_WARNINGS = 3


def synth_building(
    kind: str,
    out: Path,
    floors: int | None,
    rooms: int | None,
    size: int | None,
    seed: int,
    word_noise: float,
    events_per_room: int,
    overwrite: bool,
) -> None:
    """``spcotmhp synth building --floors N``: a seeded building of houses (:mod:`spcotmhp.building.synthetic`)."""
    from spcotmhp.building.synthetic import check_building_target, generate_building, lift_only_floor, write_building

    if kind != "building":
        raise BuildingError(f"--floors makes a building: give KIND building, not {kind!r}")
    if size is not None:
        raise BuildingError("--size is not used for a building (every floor is a house of --rooms rooms)")
    check_building_target(out, overwrite)
    b = generate_building(floors or 2, seed=seed, n_rooms=rooms, events_per_room=events_per_room,
                          word_noise=word_noise)  # fmt: skip
    write_building(b, out, overwrite=overwrite)
    spec = b.spec
    lines = [f"wrote {out}: {len(spec.floors)} floors, {sum(d.n_events for d in b.floors.values())} events"]
    for f in spec.floors:
        d = b.floors[f.index]
        lines.append(f"  floor {f.index} ({f.name}, {f.dataset}): {len(d.place_names or [])} places, "
                     f"map {d.map.height} x {d.map.width}")  # fmt: skip
    for c in spec.connectors:
        lines.append(f"  {c.kind} '{c.name}': floors {', '.join(str(s.floor) for s in c.stops)}, {c.cost_m:g} m")
    only = lift_only_floor(spec)
    if only is not None:
        lines.append(f"  floor {only} is reached by the lift only")
    typer.echo("\n".join(lines))


@dataclass
class JointBuilding:
    """A building folder read for ``learn``: its floors as one joint dataset (:mod:`spcotmhp.building.joint`)."""

    building: Building
    layout: Layout
    data: Dataset

    @property
    def default_places(self) -> int:
        from spcotmhp.building.learn import default_places

        return default_places(len(self.layout.tiles))

    def hyper(self, supervised: bool) -> Hyperparameters:
        """The priors ``learn`` uses on the joint dataset (:func:`~spcotmhp.building.learn.building_hyper`)."""
        from spcotmhp.building.learn import building_hyper
        from spcotmhp.learning.model import Hyperparameters
        from spcotmhp.learning.supervised import SUPERVISED_HYPER

        return building_hyper(self.layout, SUPERVISED_HYPER if supervised else Hyperparameters())

    def save(self, model: SpatialConceptModel, out: Path, overwrite: bool) -> None:
        """Save ``model`` (learned on ``data``) as the building's model and say how many places each floor has."""
        from spcotmhp.building.io import save_building_model
        from spcotmhp.building.model import BuildingModel

        model.info["building"] = self.building.name
        bm = BuildingModel(model, self.layout, self.building.spec)
        save_building_model(bm, out, overwrite=overwrite)
        counts = ", ".join(f"{f.index} ({f.name}) {int(bm.floor_places(f.index).sum())}" for f in bm.spec.floors)
        typer.echo(f"building {bm.name}: places per floor: {counts}")


def joint_or_none(dataset: str, lang: str | None) -> JointBuilding | None:
    """``learn``'s building branch: None unless ``dataset`` is a building folder; else the building (its floors'
    dataset warnings summarised on stderr as ``learn`` does for one dataset) and its joint dataset."""
    from spcotmhp.building.joint import joint_dataset
    from spcotmhp.building.loader import is_building, load_building
    from spcotmhp.datasets.loader import DatasetWarning

    if not is_building(dataset):
        return None
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always", DatasetWarning)
        building = load_building(dataset, lang)
    messages = [str(w.message) for w in caught if issubclass(w.category, DatasetWarning)]
    if messages:
        lines = [f"{building.name}: {len(messages)} dataset warning(s)"]
        lines += [f"  warning: {m}" for m in messages[:SHOWN_WARNINGS]]
        typer.echo("\n".join(lines), err=True)
    layout = building.layout()
    return JointBuilding(building, layout, joint_dataset(building, layout))


def plan_building(
    model_dir: Path,
    source: object,
    start: tuple[float, float],
    floor: str | None,
    *,
    recognise: Callable[[Any], Any] | None,
    as_json: bool,
    png: Path | None,
    overwrite: bool,
    lang: str | None,
    settings: dict,
    body: RobotBody | None = None,
) -> None:
    """``plan``'s building branch: plan from ``start`` on ``floor`` (the start's floor, index or name) in the
    building model ``model_dir`` (:class:`~spcotmhp.building.planner.BuildingPlanner`); print the explanation or
    the JSON (with ``segments``); ``--png`` writes one picture per floor crossed (:mod:`spcotmhp.viz.building`);
    ``body``: every floor planned for that robot body (:func:`~spcotmhp.building.io.load_building_model`)."""
    from spcotmhp.building.io import load_building_model
    from spcotmhp.building.planner import BuildingPlanner
    from spcotmhp.collector import end_startup
    from spcotmhp.errors import SpcotmhpError
    from spcotmhp.safe_write import atomic_write, check_output, outside_model

    bm = load_building_model(model_dir, body)
    if floor is None:
        if len(bm.indices) > 1:
            raise typer.BadParameter(
                f"a building's model needs --floor F, the start's floor: {bm.spec.describe_floors()}"
            )
        floor = str(bm.indices[0])
    if recognise is not None:  # --audio: recognised with the building's vocabulary
        source = recognise(bm.model)
    planner = BuildingPlanner(bm, **settings)
    plan = planner.plan(source, start, floor, lang=lang)
    warm = None if as_json else planner.plan(source, start, floor, lang=lang).time_online_s
    end_startup()
    if png is not None:
        from spcotmhp.viz.building import draw_segment, picture_paths

        paths = picture_paths(plan, png)
        for path in paths:
            check_output(path, overwrite, [model_dir], SpcotmhpError, "--png")
            outside_model(path, model_dir, "--png")
        for k, path in enumerate(paths):
            atomic_write(path, lambda tmp, k=k: draw_segment(plan, bm, k, tmp), SpcotmhpError)  # type: ignore[misc]
    if as_json:
        typer.echo(plan.to_json())
        return
    typer.echo(plan.explanation)
    assert warm is not None
    typer.echo(
        f"log p = {plan.log_prob:.2f}; planned in {warm * 1e3:.2f} ms warm (the first plan of this process took "
        f"{plan.time_online_s * 1e3:.0f} ms; precomputation {plan.time_precompute_s:.2f} s)",
        err=True,
    )
