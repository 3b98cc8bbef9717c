"""Seeded homes for the planner's acceptance battery: the hard cases of real homes, one generator.

Each ``battery_home(seed)`` is a ``house`` (``synthetic_layouts``: an entrance, a corridor with rooms on both
sides) with, by construction,

* **three bedrooms** sharing the name "bedroom" (a plan must pick the closest one);
* **two corridor places with two-word names**, "west corridor" and "east corridor", joined by an open boundary
  ("go to the corridor" names both; "go to the east corridor" one);
* **narrow doors**: every door of a home is 0.6 to 1.0 m wide (drawn per home), so after inflation a 0.22 m
  robot passes some doors through a gap of two or three cells;
* **a place taught partly in unknown space**: after the teaching walk, a strip of one room (about 40% of it,
  on its far side from the door) becomes unknown in the map, as when mapping missed part of a room that people
  still walked in and named; its teaching points there lie in unknown cells;
* **dead-end rooms** (every room with a single door);
* with ``furniture``, **seating groups** in 60% of the rooms (:mod:`spcotmhp.datasets.synthetic_furniture`): a ring
  of pieces whose gaps are narrower than the robot, so the free square inside is an island of the robot's free
  space, which may hold the room's centre.

Everything is drawn from one ``np.random.default_rng(seed)``. The dataset has a trajectory, truth, place names
and the doors' adjacency, like every synthetic environment.
"""

from __future__ import annotations

import numpy as np

from spcotmhp.datasets.dataset import Dataset
from spcotmhp.datasets.synthetic_furniture import furnish
from spcotmhp.datasets.synthetic_plan import FloorPlan, Room, generate_floor_plan, seeded_rng
from spcotmhp.datasets.synthetic_vocab import CORRIDOR, LIVING
from spcotmhp.datasets.synthetic_walk import teaching_walk
from spcotmhp.errors import DatasetError
from spcotmhp.metric.maps import UNKNOWN

DOOR_WIDTHS_M = (0.6, 0.7, 0.8, 0.9, 1.0)
KEEP_NAMES = {LIVING, "entrance", "kitchen", "toilet", "bath"}
UNKNOWN_SHARE = 0.4

__all__ = ["battery_home"]


def battery_home(seed: int, events_per_room: int = 15, furniture: bool = False) -> Dataset:
    """One home of the battery (module docstring), named ``battery-<seed>`` (``battery-<seed>-furniture`` with
    furniture, drawn after everything else: the same home, furnished)."""
    rng = seeded_rng(seed)
    for _ in range(50):
        door_m = float(rng.choice(DOOR_WIDTHS_M))
        plan = generate_floor_plan("house", n_rooms=int(rng.integers(11, 14)), seed=rng, door_m=door_m)
        corridors = [r for r in plan.rooms if r.name == CORRIDOR]
        spare = [r for r in plan.rooms if r.name not in KEEP_NAMES | {CORRIDOR}]
        if len(corridors) == 2 and len(spare) >= 4:
            break
    else:
        raise DatasetError(f"battery home {seed}: no house with two corridor places in 50 draws")
    _rename(plan, corridors, spare, rng)
    data = teaching_walk(plan, events_per_room=events_per_room, seed=rng, clearance_m=min(0.4, door_m / 2))
    room = _unknown_strip(plan, rng)
    if furniture:
        furnish(plan, rng, skip=(room.index,))
    data.name = f"battery-{seed}" + ("-furniture" if furniture else "")
    data.map = plan.map
    assert plan.map.data[room.box[0] : room.box[2], room.box[1] : room.box[3]].min() == UNKNOWN
    return data


def _rename(plan: FloorPlan, corridors: list[Room], spare: list[Room], rng: np.random.Generator) -> None:
    """West/east corridor by position; exactly three bedrooms among the rooms that are not kept by name."""
    for room, side in zip(sorted(corridors, key=lambda r: r.box[1]), ("west", "east"), strict=False):
        room.name = f"{side} {CORRIDOR}"
    bedrooms = [r for r in spare if r.name == "bedroom"]
    others = [r for r in spare if r.name != "bedroom"]
    order = rng.permutation(len(others))
    for k in order[: max(0, 3 - len(bedrooms))]:
        others[k].name = "bedroom"
    for k, room in enumerate([r for r in spare if r.name == "bedroom"][3:]):
        room.name = ("study", "storeroom", "office")[k % 3]


def _unknown_strip(plan: FloorPlan, rng: np.random.Generator) -> Room:
    """Mark the far side of one non-corridor room unknown in the plan's map: a room with one door (the side away
    from it) where the plan has one, else the first room, in a seeded order, with a side no door is near (a strip
    over a door would cut the room off)."""
    rooms = [r for r in plan.rooms if not r.is_corridor and r.name != "entrance" and r.doors]
    single = [r for r in rooms if len(r.doors) == 1]
    order = [single[int(rng.integers(len(single)))]] if single else [rooms[k] for k in rng.permutation(len(rooms))]
    for room in order:
        strip = _far_strip(room)
        if strip is not None:
            plan.map.data[strip] = UNKNOWN
            return room
    raise DatasetError("the generated plan has no room with a side away from its doors to leave unknown")


def _far_strip(room: Room) -> tuple[slice, slice] | None:
    """The cells of ``room`` within UNKNOWN_SHARE of its depth from the side away from its first door (one door),
    or from a side no door is within a cell of (several doors); None when no side is clear."""
    r0, c0, r1, c1 = room.box
    depth_r, depth_c = round(UNKNOWN_SHARE * (r1 - r0)), round(UNKNOWN_SHARE * (c1 - c0))
    sides = {
        "bottom": (slice(r1 - depth_r, r1), slice(c0, c1)),
        "top": (slice(r0, r0 + depth_r), slice(c0, c1)),
        "right": (slice(r0, r1), slice(c1 - depth_c, c1)),
        "left": (slice(r0, r1), slice(c0, c0 + depth_c)),
    }
    if len(room.doors) == 1:
        door_row, door_col = room.doors[0]
        if abs(door_row - (r0 + r1) / 2) >= abs(door_col - (c0 + c1) / 2):  # the door is on a row side
            return sides["bottom" if door_row < (r0 + r1) / 2 else "top"]
        return sides["right" if door_col < (c0 + c1) / 2 else "left"]
    for rows, cols in sides.values():
        near = [
            (dr, dc) for dr, dc in room.doors
            if rows.start - 1 <= dr <= rows.stop and cols.start - 1 <= dc <= cols.stop
        ]  # fmt: skip
        if not near:
            return rows, cols
    return None
