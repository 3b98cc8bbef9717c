"""The places a plan's explanation names (planning/explain.py path_places) on hand-made territories."""

from types import SimpleNamespace

import numpy as np

from spcotmhp.planning.explain import path_places


def _explain(territory_row: list[int], goal: int, diameter: float = 4.0) -> list[tuple[str, str]]:
    """path_places for a straight path along one row of territories, from place 0 to a node of ``goal``."""
    territory = np.array([territory_row], dtype=np.int64)
    cells = np.column_stack([np.zeros(len(territory_row)), np.arange(len(territory_row))]).astype(np.int64)
    names = ["entrance", "corridor", "dining", "study", "bath"]
    planner = SimpleNamespace(
        names=names, shown=names, numbering={k: (1, 1) for k in range(5)}, diameter_cells=diameter
    )
    graph = SimpleNamespace(territory=territory, node_place=np.array([0, goal], dtype=np.int64))
    result = SimpleNamespace(nodes=np.array([0, 1]), completed=((), (0,)), completes_last=0)
    points = np.array([[0.0, 0.0], [1.0, 0.0]])
    out = path_places(planner, graph, 0, np.zeros(2), result, points, cells)
    return [(p.name, p.role) for p in out]


def test_a_goal_with_a_territory_shorter_than_the_dwell_keeps_the_places_passed():
    """Audit item 3: the goal's territory is crossed for 2 cells (under the 4-cell dwell); the corridor and the
    dining room passed on the way were dropped with it."""
    row = [0] * 5 + [1] * 5 + [2] * 5 + [3] * 2
    assert _explain(row, 3) == [("entrance", "start"), ("corridor", "via"), ("dining", "via"), ("study", "goal")]


def test_a_goal_reached_outside_its_territory_still_follows_the_places_passed():
    row = [0] * 5 + [1] * 5 + [2] * 5 + [-1] * 2
    assert _explain(row, 3) == [("entrance", "start"), ("corridor", "via"), ("dining", "via"), ("study", "goal")]


def test_grazes_stay_ignored():
    """A 2-cell graze of the bath on the way is still not a place passed; a long goal territory unchanged."""
    row = [0] * 5 + [1] * 5 + [4] * 2 + [1] * 3 + [3] * 6
    assert _explain(row, 3) == [("entrance", "start"), ("corridor", "via"), ("study", "goal")]
