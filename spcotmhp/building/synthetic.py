"""Seeded test buildings: floors from the synthetic home generator, joined by stairs and one lift.

``generate_building(n_floors, seed)`` draws every floor with :func:`~spcotmhp.datasets.synthetic_plan.
generate_floor_plan` (one kind, one number of rooms and one map size for every floor, as storeys share a
footprint) and its teaching walk (:func:`~spcotmhp.datasets.synthetic_walk.teaching_walk`), all from one
``np.random.default_rng(seed)``. By construction:

* **names repeat across floors**: every floor is a home of the same kind (a kitchen, bedrooms and a corridor on
  each), so "the kitchen" has an instance on every floor;
* **stairs** join consecutive floors other than the lift-only one (a stop in a corridor of each, else in a
  room), cost ``STAIRS_M`` metres drawn per flight
  (a flight per storey climbed);
* **one lift** stops on every floor (cost ``LIFT_M`` drawn once), and with two floors or more **one floor is
  reachable only by the lift** (drawn among all floors; the stairs join the others in order, passing it by).

Stops lie at least ``STOP_CLEARANCE_M`` from the walls of their room. ``write_building`` writes the building
folder: building.yaml and one dataset folder per floor (``f1``, ``f2``, ...), built beside the target and
swapped in whole.
"""

from __future__ import annotations

import dataclasses
import math
from pathlib import Path

import numpy as np
import yaml

from spcotmhp.building.loader import Building
from spcotmhp.building.spec import SPEC_FILE, BuildingSpec, Connector, FloorSpec, Stop
from spcotmhp.datasets.synthetic import write_dataset
from spcotmhp.datasets.synthetic_plan import FloorPlan, Room, generate_floor_plan, seeded_rng
from spcotmhp.datasets.synthetic_walk import teaching_walk
from spcotmhp.errors import BuildingError
from spcotmhp.limits import check_count
from spcotmhp.safe_write import build_folder

MAX_SYNTH_FLOORS = 20
STAIRS_M = (6.0, 10.0)
LIFT_M = (10.0, 20.0)
STOP_CLEARANCE_M = 0.5
FLOOR_NAMES = ("ground", "first", "second", "third", "fourth", "fifth", "sixth", "seventh", "eighth", "ninth")


def generate_building(
    n_floors: int = 2,
    seed: int = 0,
    kind: str = "house",
    n_rooms: int | None = None,
    events_per_room: int = 15,
    word_noise: float = 0.0,
    lift_only: bool = True,
) -> Building:
    """A seeded building of ``n_floors`` floors indexed 1..N (module docstring), named
    ``synthetic-building-<N>-<seed>``; its floors' datasets are in memory (``path`` None). ``lift_only`` False:
    no floor is reached by the lift only (stairs join every pair of consecutive floors)."""
    n_floors = check_count(n_floors, "floors", 1, MAX_SYNTH_FLOORS, BuildingError)
    rng = seeded_rng(seed)
    plans: list[FloorPlan] = []
    floors = {}
    for f in range(1, n_floors + 1):
        size = None if not plans else plans[0].map.shape
        plan = generate_floor_plan(kind, n_rooms=n_rooms, size=size, seed=rng)
        data = teaching_walk(plan, events_per_room=events_per_room, word_noise=word_noise, seed=rng)
        data.name = f"floor-{f}"
        plans.append(plan)
        floors[f] = data
    connectors = _connectors(plans, rng, lift_only)
    names = [FLOOR_NAMES[f - 1] if f <= len(FLOOR_NAMES) else f"floor {f}" for f in range(1, n_floors + 1)]
    spec = BuildingSpec(
        f"synthetic-building-{n_floors}-{seed}",
        tuple(FloorSpec(f, names[f - 1], f"f{f}") for f in range(1, n_floors + 1)),
        connectors,
    )
    return Building(spec, floors)


def lift_only_floor(spec: BuildingSpec) -> int | None:
    """The floor that only a lift reaches (no stairs stop there), if any."""
    stairs = {s.floor for c in spec.connectors if c.kind == "stairs" for s in c.stops}
    lifts = {s.floor for c in spec.connectors if c.kind == "lift" for s in c.stops}
    only = sorted(lifts - stairs)
    return only[0] if only else None


def _connectors(plans: list[FloorPlan], rng: np.random.Generator, lift_only: bool) -> tuple[Connector, ...]:
    """The lift (every floor), then stairs between consecutive floors of all but the lift-only floor (drawn among
    every floor: stairs pass it without a door on it)."""
    n = len(plans)
    if n < 2:
        return ()
    only = int(rng.integers(1, n + 1)) if lift_only else 0
    used: list[set[tuple[int, int]]] = [set() for _ in plans]
    lift = Connector(
        "lift",
        "lift",
        tuple(_stop(p, f + 1, rng, used[f], corridor=False) for f, p in enumerate(plans)),
        round(float(rng.uniform(*LIFT_M)), 2),
    )
    stairs = []
    served = [f for f in range(1, n + 1) if f != only]
    for a, b in zip(served, served[1:], strict=False):
        ends = tuple(_stop(plans[f - 1], f, rng, used[f - 1], corridor=True) for f in (a, b))
        cost = round(float(rng.uniform(*STAIRS_M)) * (b - a), 2)  # a flight per storey climbed
        stairs.append(Connector(f"stairs {a}-{b}", "stairs", ends, cost))
    return (lift, *stairs)


def _stop(plan: FloorPlan, floor: int, rng: np.random.Generator, used: set[tuple[int, int]], corridor: bool) -> Stop:
    """A free point at least STOP_CLEARANCE_M from the walls of a room (a corridor when ``corridor`` and the
    floor has one, else any other room), on a cell no other stop of this floor uses."""
    rooms = [r for r in plan.rooms if r.is_corridor == corridor] or plan.rooms
    margin = math.ceil(STOP_CLEARANCE_M / plan.map.resolution)
    for _ in range(100):
        room: Room = rooms[int(rng.integers(len(rooms)))]
        r0, c0, r1, c1 = room.box
        if r1 - r0 <= 2 * margin or c1 - c0 <= 2 * margin:
            continue
        cell = (int(rng.integers(r0 + margin, r1 - margin)), int(rng.integers(c0 + margin, c1 - margin)))
        if cell not in used:
            used.add(cell)
            x, y = plan.map.cell_to_world(np.array(cell))
            return Stop(floor, round(float(x), 3), round(float(y), 3))
    raise BuildingError(f"floor {floor}: no room leaves a free point {STOP_CLEARANCE_M} m from its walls for a stop")


def write_building(building: Building, folder: str | Path, overwrite: bool = True) -> Path:
    """Write ``building`` as a building folder (building.yaml + one dataset folder per floor, ``spec.floors``'
    ``dataset`` names) and return its path. ``folder`` must be absent, empty, or (with ``overwrite``) a building
    folder holding building.yaml and dataset folders only; it is replaced whole."""
    out = Path(folder)
    check_building_target(out, overwrite)
    text = yaml.safe_dump(building.spec.to_dict(), sort_keys=False, allow_unicode=True, default_flow_style=None)

    def fill(staging: Path) -> None:
        (staging / SPEC_FILE).write_text(text, encoding="utf-8")
        for f in building.spec.floors:
            write_dataset(building.floors[f.index], staging / f.dataset)

    return build_folder(out, fill, BuildingError, f"write the building to {out}")


def check_building_target(out: Path, overwrite: bool) -> None:
    """BuildingError unless ``out`` is absent, an empty folder, or (with ``overwrite``) a building folder whose
    entries are building.yaml and folders holding a teaching.csv."""
    if out.is_symlink() or (out.exists() and not out.is_dir()):
        raise BuildingError(f"cannot write a building to {out}: it exists and is not a folder")
    present = sorted(out.iterdir()) if out.is_dir() else []
    if not present:
        return
    others = [p.name for p in present if p.name != SPEC_FILE and not (p.is_dir() and (p / "teaching.csv").is_file())]
    if others or not (out / SPEC_FILE).is_file():
        listed = ", ".join((others or [p.name for p in present])[:5])
        raise BuildingError(
            f"cannot write a building to {out}: the folder holds files that are not a building's ({listed}); "
            "choose an empty or new folder"
        )
    if not overwrite:
        raise BuildingError(f"{out} already holds a building; give --overwrite to replace it, or choose another folder")


EXAMPLE_NAME = "building-2f"


def example_building() -> Building:
    """The bundled example building (``spcotmhp/data/examples/building-2f``, :func:`example_path`), as generated:
    two houses of six rooms, ten utterances a room, joined by stairs and a lift (no lift-only floor)."""
    b = generate_building(2, seed=1, n_rooms=6, events_per_room=10, lift_only=False)
    return Building(dataclasses.replace(b.spec, name=EXAMPLE_NAME), b.floors)


def example_path() -> Path:
    """The folder of the bundled two-floor example building."""
    from spcotmhp.datasets.bundled import data_root

    return data_root() / "examples" / EXAMPLE_NAME
