"""Which places of which floor complete each stage of an instruction in a building, and which are avoided.

Each floor's planner reads the instruction's places as on one floor (:meth:`~spcotmhp.planning.planner.
HierarchicalPlanner.instances`: p(i | S) within ``instance_ratio`` of the best, narrowed to the places whose
label carries the words; a relation picks its instance on that floor, measured in that floor's graph). Across
floors (:func:`joint_instances`):

* a stage whose name some floor's places carry keeps only such floors: on a floor with no place of that name,
  p(i | S) still has a best place (every distribution has a mode), and "the library" must not be guessed there;
* a stage, avoided place or place not to end in that names a floor keeps only that floor (PlaceNotOnFloor when
  no place of the name is there, naming the floors where places of the name are);
* the goal loses the places not to end in, every stage loses the avoided places (ConflictingInstruction when a
  stage has none left on any floor).

A floor on which a place phrase cannot be read (two words that name no place together there, an ambiguous word,
a relation with nothing to measure) is left out for that place; the reason is raised only when no floor reads it.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from spcotmhp.building.floors import PlaceFloors
from spcotmhp.building.model import BuildingModel
from spcotmhp.errors import ConflictingInstruction, PlaceNotOnFloor, SpcotmhpError
from spcotmhp.planning.graph import PlanningGraph
from spcotmhp.planning.places import named_places
from spcotmhp.planning.planner import HierarchicalPlanner
from spcotmhp.planning.query import Instruction, PlaceQuery


@dataclass
class Read:
    """One place phrase read on one floor: (K,) its places there (empty when not read: ``error``) and whether
    their labels carry the phrase's words (``named``)."""

    mask: np.ndarray
    named: bool
    error: SpcotmhpError | None = None


@dataclass
class FloorQueries:
    """An instruction's places read on one floor: (S, K) the word term of Eq. 28 per stage (``semantic``), and the
    :class:`Read` of each stage, avoided place and place not to end in; ``chosen``: what relations picked."""

    floor: int
    semantic: np.ndarray
    stages: list[Read]
    avoid: list[Read]
    not_goal: list[Read]
    chosen: dict[int, str] = field(default_factory=dict)


def floor_queries(
    planner: HierarchicalPlanner, ins: Instruction, floors: PlaceFloors, floor: int, region: PlanningGraph
) -> FloorQueries:
    """The instruction's places read by ``planner`` (floor ``floor``; relations measured in ``region``)."""
    semantic, likely = planner.terms.stage_terms([q.words for q in ins.stages], planner.settings.instance_ratio)
    active = np.asarray(planner.model.active_places, dtype=bool)
    chosen: dict[int, str] = {}

    def read(q: PlaceQuery, row: np.ndarray | None, stage: bool, wanted: object) -> Read:
        named = bool(named_places(planner.label_index, q.phrases).any())
        if wanted is not None and wanted != floor:
            return Read(np.zeros(planner.model.K, dtype=bool), named)
        try:
            mask = planner.instances(q, row, stage=stage) & active
            return Read(planner.related(q, mask, chosen, region), named)
        except SpcotmhpError as exc:
            return Read(np.zeros(planner.model.K, dtype=bool), named, exc)

    stages = [read(q, likely[s], True, floors.stages[s]) for s, q in enumerate(ins.stages)]
    avoid = [read(q, None, False, floors.avoid[a]) for a, q in enumerate(ins.avoid)]
    not_goal = [read(q, None, False, floors.not_goal[n]) for n, q in enumerate(ins.not_goal)]
    return FloorQueries(floor, semantic, stages, avoid, not_goal, chosen)


def _joined(reads: dict[int, Read], query: PlaceQuery, wanted: object, bm: BuildingModel, stage: bool):
    """{floor: (K,) places} of one phrase over the floors (module docstring); raises when no floor reads it."""
    if any(r.named for r in reads.values()):
        out = {f: r.mask if r.named else np.zeros_like(r.mask) for f, r in reads.items()}
    else:
        out = {f: r.mask for f, r in reads.items()}
    if any(m.any() for m in out.values()) or not stage:
        return out
    if isinstance(wanted, int):
        error = reads[wanted].error
        if error is not None:
            raise error
        named_on = [bm.spec.floor(f) for f, r in sorted(reads.items()) if r.named]
        on = ", ".join(f"{f.index} ({f.name})" for f in named_on) or "no floor"
        raise PlaceNotOnFloor(
            f"no place named '{query.label}' is on floor {wanted} ({bm.spec.floor(wanted).name}); "
            f"places so named are on floors {on}"
        )
    errors = [r.error for r in reads.values() if r.error is not None]
    if errors:
        raise errors[0]
    raise PlaceNotOnFloor(f"no floor of the building has a place named '{query.label}'")


def joint_instances(
    queries: dict[int, FloorQueries], ins: Instruction, floors: PlaceFloors, bm: BuildingModel
) -> tuple[dict[int, np.ndarray], dict[int, np.ndarray]]:
    """({floor: (S, K) instances}, {floor: (K,) avoided places}) of the instruction (module docstring)."""
    S = len(ins.stages)
    K = bm.model.K
    inst = {f: np.zeros((S, K), dtype=bool) for f in queries}
    for s, q in enumerate(ins.stages):
        for f, mask in _joined({f: fq.stages[s] for f, fq in queries.items()}, q, floors.stages[s], bm, True).items():
            inst[f][s] = mask
    for n, q in enumerate(ins.not_goal):
        for f, mask in _joined({f: fq.not_goal[n] for f, fq in queries.items()}, q, None, bm, False).items():
            inst[f][-1] &= ~mask
    if not any(m[-1].any() for m in inst.values()):
        raise ConflictingInstruction(
            f"every place named '{ins.goal.label}' is one the instruction says not to end in "
            f"({', '.join(q.label for q in ins.not_goal)})"
        )
    avoided = {f: np.zeros(K, dtype=bool) for f in queries}
    for a, q in enumerate(ins.avoid):
        for f, mask in _joined({f: fq.avoid[a] for f, fq in queries.items()}, q, None, bm, False).items():
            avoided[f] |= mask
    for f in inst:
        inst[f] &= ~avoided[f]
    for s, q in enumerate(ins.stages):
        if not any(m[s].any() for m in inst.values()):
            raise ConflictingInstruction(f"every place named '{q.label}' is also to be avoided")
    return inst, avoided
