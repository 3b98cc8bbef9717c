"""The start of a plan: typed errors, and the escape from a start within the robot's radius of a wall."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

from spcotmhp.datasets import load_bundled
from spcotmhp.errors import PlanningError, StartBlocked, StartOutsideMap
from spcotmhp.learning.supervised import fit_supervised
from spcotmhp.metric.costmap import INSCRIBED_INFLATED_OBSTACLE, inflate
from spcotmhp.planning.planner import HierarchicalPlanner
from tests.helpers.graphs import GRAPHS


@pytest.fixture(scope="module")
def home():
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        data = load_bundled("3LDK_01", lang="en")
    model = fit_supervised(data)
    return model, HierarchicalPlanner(model, cache=GRAPHS), inflate(model.map, **model.costmap)


def test_a_start_next_to_a_wall_leaves_it_first_and_says_so(home):
    model, planner, cm = home
    inscribed = np.argwhere((cm.costs == INSCRIBED_INFLATED_OBSTACLE) & model.map.free)
    rng = np.random.default_rng(0)
    planned = 0
    for cell in inscribed[rng.choice(len(inscribed), 30, replace=False)]:
        try:
            plan = planner.plan("go to the kitchen", model.map.cell_to_world(cell))
        except StartBlocked:
            continue  # a pocket cut off from every place
        planned += 1
        costs = cm.costs[plan.cells[:, 0], plan.cells[:, 1]]
        clear = np.flatnonzero(costs < INSCRIBED_INFLATED_OBSTACLE)
        assert (plan.cells[0] == cell).all() and len(clear)
        assert (costs[clear[0] :] < INSCRIBED_INFLATED_OBSTACLE).all()  # once clear, it stays clear
        assert clear[0] <= 4  # a few cells at most
        assert "the path first moves" in plan.explanation
    assert planned >= 20


def _escape_on(free: np.ndarray, main: np.ndarray, cell: tuple[int, int], radius_m: float) -> np.ndarray | None:
    """planning/start.py _escape on hand-made grids at 0.1 m per cell (crop = map)."""
    from types import SimpleNamespace

    from spcotmhp.planning.start import _escape

    occ = SimpleNamespace(resolution=0.1)
    graph = SimpleNamespace(
        model=SimpleNamespace(require_map=lambda: occ),
        offset=(0, 0),
        main=main,
        plannable=None,
        regions={},
        settings=SimpleNamespace(connectivity=8),
    )
    return _escape(free, graph, np.array(cell), radius_m)


def test_the_escape_is_the_shortest_run_even_past_its_search_window():
    """Audit item 8: the escape is the shortest run of free cells to a cell the robot fits in. Here the window
    (ceil(0.1 / 0.1) + 2 = 3 cells each way) holds a main cell only behind a wall (a 6.8-cell detour); one just
    outside it is 4 cells away in a straight line, and the escape takes it."""
    free = np.ones((21, 21), bool)
    free[8:14, 11] = False  # a wall east of the start, open at row 7
    main = np.zeros_like(free)
    main[10, 12] = main[10, 6] = True
    run = _escape_on(free, main, (10, 10), 0.1)
    assert run is not None and run[-1].tolist() == [10, 6] and len(run) == 5
    main[10, 6] = False  # only the detour is left: it is taken, the same length as before the fix
    run = _escape_on(free, main, (10, 10), 0.1)
    assert run is not None and run[-1].tolist() == [10, 12]
    steps = np.abs(np.diff(run, axis=0)).sum(axis=1)
    assert np.isclose(np.where(steps == 2, np.sqrt(2), steps).sum(), 4 + 2 * np.sqrt(2))


def test_no_escape_beyond_the_window():
    free = np.ones((21, 21), bool)
    main = np.zeros_like(free)
    main[10, 14] = True  # 4 cells east: outside the window of 3
    assert _escape_on(free, main, (10, 10), 0.1) is None
    main[10, 13] = True
    assert _escape_on(free, main, (10, 10), 0.1)[-1].tolist() == [10, 13]


@pytest.mark.parametrize(
    "start, error",
    [
        ("wall", StartBlocked),
        ("unknown", StartBlocked),
        ((1e9, 0.0), StartOutsideMap),
        ((float("nan"), 1.0), StartOutsideMap),
        ("x", StartOutsideMap),
        ((10**400, 0), StartOutsideMap),
        ((True, False), StartOutsideMap),  # audit item 13: booleans were taken as (1, 0)
        ([0.5, np.True_], StartOutsideMap),
        (np.array([True, False]), StartOutsideMap),
        (["1", "2"], StartOutsideMap),  # issue 26: strings were converted, unlike in the HTTP API
        ((1.0, "2"), StartOutsideMap),
        (np.array(["1", "2"]), StartOutsideMap),
        ([1.0, None], StartOutsideMap),
        ((1 + 2j, 0.0), StartOutsideMap),
        ({1.0, 2.0}, StartOutsideMap),
    ],
)
def test_bad_starts_are_typed(home, start, error):
    model, planner, _ = home
    if isinstance(start, str) and start in ("wall", "unknown"):
        start = model.map.cell_to_world(np.argwhere(model.map.data == (100 if start == "wall" else -1))[0])
    with pytest.raises(error) as info:
        planner.plan("go to the kitchen", start)
    assert isinstance(info.value, PlanningError) and "\n" not in str(info.value) and len(str(info.value)) < 200


def test_metric_fallback_when_the_place_graph_has_no_edge(home):
    # with steps restricted to connected places and a psi that connects none, the place graph has no route
    model, _, cm = home
    import dataclasses

    lone = dataclasses.replace(model, psi=np.eye(model.K) * 0.999 + 0.001 / model.K)
    planner = HierarchicalPlanner(lone, adjacent_only=True)
    assert not np.isfinite(planner.graph.w_hat).any()  # no edge at all
    plan = planner.plan("go to the kitchen via the toilet", tuple(model.mu[0]))
    assert "metric route" in plan.explanation
    assert (cm.costs[plan.cells[:, 0], plan.cells[:, 1]] < INSCRIBED_INFLATED_OBSTACLE).all()
    assert [p.role for p in plan.places if p.role != "via"] == ["start", "waypoint", "goal"]


@pytest.mark.parametrize(
    "start, message",
    [
        (["1", "2"], r"the start must be two numbers \(x, y\) in metres, got \['1', '2'\] \(str is not a number\)"),
        ([1, None], r"got \[1, None\] \(NoneType is not a number\)"),
        ([1.0, 2.0, 3.0], r"the start must be two finite numbers \(x, y\) in metres, got \[1.0, 2.0, 3.0\]"),
    ],
)
def test_a_start_is_two_numbers_as_in_the_http_api(start, message):
    from spcotmhp.planning.start import start_point

    with pytest.raises(StartOutsideMap, match=message):
        start_point(start)
    assert start_point([np.int64(1), np.float32(2.5)]).tolist() == [1.0, 2.5]
    assert start_point(np.array([[3, 4]])).tolist() == [3.0, 4.0]
