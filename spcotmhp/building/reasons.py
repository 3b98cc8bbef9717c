"""Why a building's planner finds no route: the typed error of the stitched metric fallback, with floors.

As :func:`~spcotmhp.planning.search.why_no_plan` on one floor: the start reaches no node (StartBlocked); a stage
has no instance among the nodes the start reaches, through the floors' free space and the connectors
(FloorUnreachable when none of its instances' floors is reached at all: no stairs or lift route leads there,
NoReachablePlace when a reached floor has them but the robot's free space there does not lead to them); else the
horizon is too short (HorizonTooShort).
"""

from __future__ import annotations

import numpy as np

from spcotmhp.building.stitch import Stitched
from spcotmhp.errors import FloorUnreachable, HorizonTooShort, NoReachablePlace, StartBlocked
from spcotmhp.planning.query import Instruction
from spcotmhp.planning.search import reachable


def reached(st: Stitched) -> np.ndarray:
    """(M,) the stitched nodes some sequence from the start reaches (breadth-first over finite steps)."""
    return reachable(st.problem)


def why_not(st: Stitched, ins: Instruction, x0: np.ndarray, f0: int, avoiding: bool) -> Exception:
    """The one-line typed error saying why the stitched metric problem ``st`` has no solution (module docstring)."""
    where = f"from ({x0[0]:.2f}, {x0[1]:.2f}) on floor {f0}"
    tail = " without entering the places to avoid" if avoiding else ""
    reach = reached(st)
    if not reach.any():
        return StartBlocked(f"no place can be reached {where}{tail} (the start is cut off from every place)")
    floors_reached = set(st.floor_of[reach].tolist())
    for s, q in enumerate(ins.stages):
        completes = st.problem.completes[s]
        if (reach & completes).any():
            continue
        role = "goal" if s == len(ins.stages) - 1 else f"waypoint {s + 1}"
        on = sorted(set(st.floor_of[completes].tolist()))
        if not on:  # no node of any floor ends the stage: its places have no point in the free space planned from
            return NoReachablePlace(
                f"no place named '{q.label}' ({role}) has a point in the free space planned from on any floor "
                "(for a robot this size its places' free cells are cut off or too narrow)"
            )
        if not floors_reached & set(on):
            listed = ", ".join(map(str, on))
            return FloorUnreachable(
                f"no stairs or lift route {where}{tail} reaches floor {listed}, where the '{q.label}' ({role}) is"
            )
        return NoReachablePlace(f"no free path {where} reaches a place named '{q.label}' ({role}){tail}")
    return HorizonTooShort(
        f"no sequence of at most {st.problem.max_steps} steps {where} satisfies '{ins.describe()}'{tail}; "
        "raise max_steps"
    )
