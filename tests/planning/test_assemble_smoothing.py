"""Algorithm 1, line 13 on hand-made homes: tube re-planning straightens the zig-zag through place centres,
stays on the route Eq. 28 chose, never lengthens, keeps every guarantee; the arrival cut; territories."""

from __future__ import annotations

import itertools
import math
import warnings

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from spcotmhp.datasets.bundled import load_bundled
from spcotmhp.evaluation.tasks import build_places
from spcotmhp.learning.supervised import fit_supervised
from spcotmhp.metric.grid_search import shortest_paths
from spcotmhp.planning.assemble import (
    arrival,
    better,
    path_cost,
    path_length,
    replan_segment,
    shorten,
    smooth,
    smooth_anchored,
)
from spcotmhp.planning.avoid import avoided_view
from spcotmhp.planning.places import most_probable_place, place_regions
from spcotmhp.planning.planner import HierarchicalPlanner
from spcotmhp.planning.territory import grown_territories
from tests.helpers.graphs import GRAPHS
from tests.helpers.planning import RES, draw_blocked, draw_ends, home_log_p, home_model, make_home, world

SQ2 = math.sqrt(2.0)


# A kitchen (A) opens at its bottom right into a large living room (B), whose top-left door leads to the
# bedroom (C). The partial paths run to the living room's centre (8, 14), far right of the route.
DETOUR = {
    "rooms": {"A": (1, 5, 1, 5), "B": (1, 15, 7, 21), "C": (17, 21, 7, 11)},
    "doors": [(slice(2, 5), 6), (16, slice(8, 11))],
    "names": {"A": "kitchen", "B": "living", "C": "bedroom"},
    "edges": [("A", "B"), ("B", "C")],
    "shape": (23, 23),
}
# The same, plus a hall (D) that joins the kitchen and an (extended) bedroom directly, but psi never links it:
# Eq. 28 plans kitchen -> living -> bedroom, and smoothing must not cut through the hall.
TUBE = {
    "rooms": {"A": (1, 5, 1, 5), "B": (1, 15, 7, 21), "C": (17, 21, 1, 11), "D": (7, 15, 1, 5)},
    "doors": [(slice(2, 5), 6), (16, slice(8, 11)), (6, slice(2, 5)), (16, slice(2, 5))],
    "names": {"A": "kitchen", "B": "living", "C": "bedroom", "D": "hall"},
    "edges": [("A", "B"), ("B", "C")],
    "shape": (23, 23),
}


def planners(spec: dict, **kw) -> tuple[HierarchicalPlanner, HierarchicalPlanner]:
    model = make_home(**spec)
    log_p = home_log_p(model.map)
    raw_kw = {k: v for k, v in kw.items() if k == "adjacent_only"}
    return (
        HierarchicalPlanner(model, log_p=log_p, **kw),
        HierarchicalPlanner(model, log_p=log_p, smooth=False, **raw_kw),
    )


def check_cells(planner: HierarchicalPlanner, cells: np.ndarray, start) -> None:
    assert (cells[0] == start).all()
    steps = np.abs(np.diff(cells, axis=0))
    assert len(cells) == 1 or (steps.max(axis=1) == 1).all()
    assert (planner.model.map.data[cells[:, 0], cells[:, 1]] == 0).all()
    occ_free = planner.model.map.data == 0
    for (r0, c0), (r1, c1) in itertools.pairwise(cells):  # no squeeze between two wall corners
        if r0 != r1 and c0 != c1:
            assert occ_free[r0, c1] or occ_free[r1, c0]


def test_tube_replanning_takes_the_door_corner_the_old_assembly_missed():
    # the first step follows the place graph too (adjacent_only), so the assembled path runs through the
    # living room's centre and smoothing has work to do
    new, raw = planners(DETOUR, adjacent_only=True)
    start = (3, 3)  # the kitchen's centre
    a = new.plan("go to the bedroom", world(new.model.map, *start))
    b = raw.plan("go to the bedroom", world(raw.model.map, *start))
    assert [p.name for p in a.places] == [p.name for p in b.places] == ["kitchen", "living", "bedroom"]
    assert a.log_prob == b.log_prob
    check_cells(new, a.cells, start)
    goal = new.model.map.world_to_cell(new.model.mu[2])  # (19, 9), the bedroom's candidate
    assert (a.cells[-1] == goal).all() and (b.cells[-1] == goal).all()
    # by hand: through the door corner (4, 6), then 3 diagonal and 12 straight steps to (19, 9):
    # (1 + 3) diagonals and (2 + 12) straight steps; every path must pass a door cell (r, 6), r <= 4, and the
    # octile distances through (2, 6) and (3, 6) are longer
    assert a.length_m == pytest.approx(RES * (14 + 4 * SQ2))
    # the old assembly goes to the living room's centre (8, 14): at least the octile distances (3, 3) -> door
    # (4, 6) -> (8, 14) -> door (16, 10) -> (19, 9) (the cheapest door cells), and its line-of-sight
    # shortcuts cannot reach the door corners
    assert b.length_m >= RES * ((2 + SQ2) + (4 + 4 * SQ2) + (4 + 4 * SQ2) + (2 + SQ2)) - 1e-9
    old = smooth(raw.graph.to_crop(b.cells), raw.graph.traversable, [len(b.cells) - 1])
    assert path_length(old, RES) > a.length_m + 1.0
    assert a.smoothed and not b.smoothed


def test_tube_keeps_the_route_that_eq28_chose():
    new, raw = planners(TUBE, adjacent_only=True)
    model, g = new.model, new.graph
    hall = g.to_map(np.argwhere(g.territory == 3))
    rows, cols = hall[:, 0], hall[:, 1]
    in_hall = (rows >= 7) & (rows <= 15) & (cols >= 1) & (cols <= 5)
    assert in_hall.sum() == 9 * 5  # the hall's room is all hall territory
    start = (3, 3)
    a = new.plan("go to the bedroom", world(model.map, *start))
    b = raw.plan("go to the bedroom", world(model.map, *start))
    assert [p.name for p in a.places] == ["kitchen", "living", "bedroom"]
    check_cells(new, a.cells, start)
    assert not ((a.cells[:, 0] >= 7) & (a.cells[:, 0] <= 15) & (a.cells[:, 1] <= 5)).any()
    assert a.length_m < b.length_m
    # through the hall would have been shorter still: the tube, not the map, kept the path out
    free = np.where(model.map.data == 0, 1.0, np.inf)
    through_hall = shortest_paths(free, start, a.cells[-1][None], 8)
    assert through_hall.length_m * RES < a.length_m - 1.0


def test_waypoints_stay_anchored_and_avoidance_holds():
    new, raw = planners(TUBE, arrival_quantile=None)
    model = new.model
    start = (3, 3)
    a = new.plan("go to the kitchen via the living", world(model.map, *start))
    wp = model.map.world_to_cell(model.mu[1])
    assert (a.cells == wp).all(axis=1).any()  # passes the living room's candidate exactly
    assert a.length_m <= raw.plan("go to the kitchen via the living", world(model.map, *start)).length_m
    c = new.plan("go to the bedroom avoiding the hall", world(model.map, *start))
    crop = new.graph.to_crop(c.cells)
    assert not (new.graph.territory[crop[:, 0], crop[:, 1]] == 3).any()
    check_cells(new, c.cells, start)


def test_arrival_stops_at_the_first_cell_inside_the_goal_region():
    model = home_model()
    log_p = home_log_p(model.map)
    q = 0.39
    full = HierarchicalPlanner(model, log_p=log_p, cache=GRAPHS)
    cut = HierarchicalPlanner(model, log_p=log_p, arrival_quantile=q, cache=GRAPHS)
    start = (3, 12)  # in the corridor, next to bedroom #1's door
    a = full.plan("go to the bedroom", world(model.map, *start))
    b = cut.plan("go to the bedroom", world(model.map, *start))
    assert b.goal.id == a.goal.id == 0 and b.log_prob == a.log_prob
    assert (b.cells == a.cells[: len(b.cells)]).all()  # the same path, cut
    xy = model.map.cell_to_world(b.cells)
    region = place_regions(model, xy, [0], q)
    assert region[-1] and not region[:-1].any()
    # bedroom #1's 0.39 ellipse has half-axes of 2.24 (cols) x 2.73 (rows) cells around (6, 5): it is entered
    # at col 7 or less, at least 2 steps before the centre
    assert (a.cells[-1] == [6, 5]).all()
    assert b.length_m <= a.length_m - 2 * 0.5 + 1e-9
    check_cells(cut, b.cells, start)
    # already inside the goal region: nothing to drive
    inside = cut.plan("go to the bedroom", world(model.map, 6, 5))
    assert len(inside.cells) == 1 and inside.length_m == 0.0


def test_most_probable_place_and_grown_territories():
    model = make_home(**TUBE)
    g = HierarchicalPlanner(model, log_p=home_log_p(model.map)).graph
    # the territories are the most probable place on every traversable cell (these rooms leave no stray
    # fragment of a place's region to reassign), -1 on walls
    assert (g.territory[g.traversable] == most_probable_place(model, g.centres)[g.traversable]).all()
    assert (g.territory[~g.traversable] == -1).all()
    terr = np.array([[0, 0, 1, 1], [0, 0, 1, 1], [2, 2, 2, 2]])
    grown = grown_territories(terr, np.array([0, 1, 2, 5]), 1.0)
    assert set(grown) == {0, 1, 2}  # place 5 owns no cell
    r, c, m = grown[0]
    assert (r, c) == (0, 0) and m.tolist() == [[True, True, True], [True, True, True], [True, True, True]]
    r, c, m = grown[2]
    assert (r, c) == (1, 0) and m.all() and m.shape == (2, 4)
    r, c, m = grown_territories(terr, np.array([1]), 0.0)[1]
    assert (r, c) == (0, 2) and m.all() and m.shape == (2, 2)


@pytest.mark.parametrize("margin, cells", [(0.2, 0), (0.5, 1), (1.0, 2)])
def test_tube_window_covers_the_grown_territories(margin, cells):
    model = make_home(**TUBE)
    g = HierarchicalPlanner(model, log_p=home_log_p(model.map), tube_margin=margin).graph
    origin, mask = g.tube(np.array([0, 2]))
    full = np.zeros(g.log_p.shape, bool)
    full[origin[0] : origin[0] + mask.shape[0], origin[1] : origin[1] + mask.shape[1]] = mask
    expected = np.isin(g.territory, [0, 2])  # grown by ``cells`` in chessboard distance
    padded = np.pad(expected, cells)
    h, w = expected.shape
    grown = np.zeros_like(expected)
    for dr in range(-cells, cells + 1):
        for dc in range(-cells, cells + 1):
            grown |= padded[cells + dr : cells + dr + h, cells + dc : cells + dc + w]
    assert (full == grown).all()


def test_replan_segment_by_hand():
    cost = np.ones((5, 7))
    cost[1:4, 3] = np.inf  # a wall at col 3 with gaps at rows 0 and 4
    zero = np.zeros(2, np.int64)
    everything = np.ones((5, 7), bool)
    # over the top gap: 2 + 2 + 1 + 1 + 2 steps, 6 + 2 sqrt 2; the shortest is 2 + 4 sqrt 2 (either gap)
    top = np.array([[2, 0], [1, 0], [0, 1], [0, 2], [0, 3], [0, 4], [0, 5], [1, 6], [2, 6]])
    assert path_length(top, 1.0) == pytest.approx(6 + 2 * SQ2)
    out = replan_segment(top, cost, zero, everything)
    assert path_length(out, 1.0) == pytest.approx(2 + 4 * SQ2)
    assert (out[0] == [2, 0]).all() and (out[-1] == [2, 6]).all()
    # a tube of nothing: only the piece's cells and their neighbours (rows 0-2 here), so the path keeps to the
    # top gap, as short as the best path
    out = replan_segment(top, cost, zero, np.zeros((5, 7), bool))
    assert (out[:, 0] <= 2).all() and [0, 3] in out.tolist()
    assert path_length(out, 1.0) == pytest.approx(2 + 4 * SQ2)
    # the same through a window of rows 3-4 (origin (3, 0)): the bottom gap is open too, equally short
    out = replan_segment(top, cost, np.array([3, 0]), np.ones((2, 7), bool))
    assert path_length(out, 1.0) == pytest.approx(2 + 4 * SQ2)
    # a piece that is already shortest is never made longer; short pieces are returned as they are
    assert path_length(replan_segment(out, cost, zero, everything), 1.0) == pytest.approx(2 + 4 * SQ2)
    assert replan_segment(out[:2], cost, zero, everything).tolist() == out[:2].tolist()
    # the search minimises the map cost, not the length: the diagonal through the costly centre (2 sqrt 2
    # long, cost 6 sqrt 2) loses to a path round it (2 + sqrt 2 long, cost 2 + sqrt 2)
    uneven = np.ones((3, 3))
    uneven[1, 1] = 5.0
    piece = np.array([[0, 0], [0, 1], [1, 2], [2, 2]])
    out = replan_segment(piece, uneven, zero, np.ones((3, 3), bool))
    assert [1, 1] not in out.tolist() and path_length(out, 1.0) == pytest.approx(2 + SQ2)
    assert path_cost(out, uneven) == pytest.approx(2 + SQ2)


def test_shorten_maps_the_anchors_and_keeps_them():
    cost = np.ones((3, 9))
    zigzag = np.array([[0, 0], [1, 1], [2, 2], [1, 3], [0, 4], [1, 5], [2, 6], [1, 7], [0, 8]])
    everything = (np.zeros(2, np.int64), np.ones((3, 9), bool))
    out, anchors = shorten(zigzag, [2, 8], lambda a, b: everything, cost)
    assert out[anchors[0]].tolist() == [2, 2] and out[anchors[1]].tolist() == [0, 8]
    assert out[0].tolist() == [0, 0] and path_length(out, 1.0) == pytest.approx(2 * SQ2 + 2 * SQ2 + 4)
    out, anchors = shorten(zigzag, [8], lambda a, b: everything, cost)
    assert path_length(out, 1.0) == pytest.approx(8.0) and anchors == [len(out) - 1]


def test_arrival_path_cost_and_better():
    cells = np.zeros((4, 2), np.int64)
    assert arrival(cells, np.array([False, True, True, False])) == 1
    assert arrival(cells, np.array([True, True, False, False]), first=2) == 3  # none after 2: the end
    cost = np.array([[1.0, 2.0], [3.0, 4.0]])
    path = np.array([[0, 0], [0, 1], [1, 0]])
    assert path_cost(path, cost) == pytest.approx(2.0 + 3.0 * SQ2)
    assert path_cost(path[:1], cost) == 0.0
    straight, bent = np.array([[0, 0], [1, 1]]), np.array([[0, 0], [0, 1], [1, 1]])
    assert better(straight, bent, cost) and not better(bent, straight, cost)
    a, b = np.array([[0, 0], [0, 1], [1, 1]]), np.array([[0, 0], [1, 0], [1, 1]])  # same length
    assert better(a, b, cost) and not better(b, a, cost)  # 2 + 4 < 3 + 4


@st.composite
def grids(draw):
    blocked = draw_blocked(draw)
    h, w = blocked.shape
    weights = np.array(draw(st.lists(st.floats(1.0, 3.0), min_size=h * w, max_size=h * w))).reshape(h, w)
    tube_bits = draw(st.lists(st.booleans(), min_size=h * w, max_size=h * w))
    a, b = draw_ends(draw, blocked)
    return blocked, weights, np.array(tube_bits).reshape(h, w), a, b


@settings(max_examples=150, deadline=None, derandomize=True)
@given(grids())
def test_replanning_properties(case):
    # whatever the tube: same ends, only finite-cost cells, 8-connected without squeezing, never longer, and
    # only tube cells or cells next to the original piece
    blocked, weights, tube, a, b = case
    cost = np.where(blocked, np.inf, weights)
    uniform = np.where(blocked, np.inf, 1.0)
    start = shortest_paths(np.where(blocked, np.inf, 4.0 - weights), a, b[None], 4)  # some 4-connected piece
    if start is None:
        return
    piece = start.cells
    out = replan_segment(piece, cost, np.zeros(2, np.int64), tube)
    assert (out[0] == a).all() and (out[-1] == b).all()
    assert np.isfinite(cost[out[:, 0], out[:, 1]]).all()
    if len(out) > 1:
        steps = np.abs(np.diff(out, axis=0))
        assert (steps.max(axis=1) == 1).all()
        for (r0, c0), (r1, c1) in itertools.pairwise(out):
            if r0 != r1 and c0 != c1:
                assert not blocked[r0, c1] or not blocked[r1, c0]
    assert path_length(out, 1.0) <= path_length(piece, 1.0) + 1e-9
    near = np.zeros_like(tube)
    for dr in (-1, 0, 1):
        for dc in (-1, 0, 1):
            rr = np.clip(piece[:, 0] + dr, 0, tube.shape[0] - 1)
            cc = np.clip(piece[:, 1] + dc, 0, tube.shape[1] - 1)
            near[rr, cc] = True
    assert (tube | near)[out[:, 0], out[:, 1]].all()
    # and with the whole grid as the tube the result is a shortest path under the cost
    best = replan_segment(piece, uniform, np.zeros(2, np.int64), np.ones_like(tube))
    ref = shortest_paths(uniform, a, b[None], 8)
    assert path_length(best, 1.0) == pytest.approx(ref.length_m)


def test_map_cost_is_the_map_term_of_eq26_and_views_block_avoided_regions():
    model = make_home(**TUBE)
    log_p = home_log_p(model.map)
    log_p[3, 3] = math.log(0.01)  # one inscribed cell
    pl = HierarchicalPlanner(model, log_p=log_p)
    g = pl.graph
    cell = g.to_crop(np.array([3, 3]))
    assert g.map_cost[cell[0], cell[1]] == pytest.approx(math.log(9) - math.log(0.01))
    assert g.map_cost[g.traversable & (g.log_p == 0)] == pytest.approx(math.log(9))
    assert np.isinf(g.map_cost[~g.traversable]).all()
    view = avoided_view(g, (3,))
    assert np.isinf(view.map_cost[view.blocked]).all() and view.blocked.any()
    assert (view.map_cost[~view.blocked] == g.map_cost[~view.blocked]).all()


def test_smooth_anchored_reports_where_the_anchors_went():
    stairs = np.array([[0, 0], [0, 1], [1, 1], [1, 2], [2, 2], [2, 3], [3, 3]])
    out, anchors = smooth_anchored(stairs, np.ones((4, 4), bool), [3, 6])
    assert out[anchors[0]].tolist() == [1, 2] and out[anchors[1]].tolist() == [3, 3]
    assert path_length(out, 1.0) < path_length(stairs, 1.0)
    assert (smooth(stairs, np.ones((4, 4), bool), [3, 6]) == out).all()


def test_bundled_home_entrance_to_storeroom():
    # 3LDK_01, supervised parameters. With the first step on the place graph, Eq. 28 goes from the entrance
    # through the centre of a neighbouring place to the storeroom, while the free-space path stays in the hall:
    # smoothing recovers it. By default the first leg is a
    # free-space path from the start, and the plan is direct.
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        dataset = load_bundled("3LDK_01")
    model = fit_supervised(dataset)
    occ = dataset.map
    entrance, storeroom = (next(p for p in build_places(dataset) if p.name == n) for n in ("entrance", "storeroom"))
    x0 = occ.cell_to_world(np.array(entrance.cell))
    new = HierarchicalPlanner(model, adjacent_only=True, cache=GRAPHS).plan("go to the storeroom", x0)
    raw_planner = HierarchicalPlanner(model, smooth=False, adjacent_only=True, cache=GRAPHS)
    raw = raw_planner.plan("go to the storeroom", x0)
    via = [p.id for p in raw.places if p.role == "via"]
    assert len(raw.node_points) >= 2 and via
    assert new.log_prob == raw.log_prob and new.goal.id == raw.goal.id == storeroom.index
    g = raw_planner.graph
    crop = g.to_crop(raw.cells)
    old = smooth(crop, g.traversable, [len(crop) - 1])
    geodesic = shortest_paths(np.where(g.traversable, 1.0, np.inf), crop[0], crop[-1][None], 8).length_m
    geodesic *= occ.resolution
    # measured: raw 10.8 m, tube re-planning 4.6 m, geodesic 4.2 m
    assert raw.length_m > 2 * geodesic and path_length(old, occ.resolution) > new.length_m
    assert new.length_m < 1.15 * geodesic
    # the path no longer passes the living and the dining room, and the explanation says so
    assert new.explanation == f"entrance -> storeroom, {new.length_m:.1f} m"
    new_crop = g.to_crop(new.cells)
    assert g.traversable[new_crop[:, 0], new_crop[:, 1]].all() and (new.cells[-1] == raw.cells[-1]).all()
    assert not np.isin(g.territory[new_crop[:, 0], new_crop[:, 1]], via).any()
    default = HierarchicalPlanner(model, smooth=False, cache=GRAPHS).plan("go to the storeroom", x0)
    assert default.explanation == f"entrance -> storeroom, {default.length_m:.1f} m"
    assert default.length_m < 1.15 * geodesic


@pytest.mark.parametrize("connectivity, length, steps", [(8, 4 * SQ2 + 2, {1, 2}), (4, 10.0, {1})])
def test_shortcuts_keep_the_planners_move_model(connectivity, length, steps):
    # an L-shaped path (0, 0) -> (0, 6) -> (4, 6) on an open 5 x 7 grid: the 8-connected shortcut is the
    # Bresenham line (octile length), the 4-connected one a staircase of Manhattan length with no diagonal step
    cells = np.array([(0, c) for c in range(7)] + [(r, 6) for r in range(1, 5)])
    out = smooth(cells, np.ones((5, 7), dtype=bool), [], connectivity)
    assert tuple(out[0]) == (0, 0) and tuple(out[-1]) == (4, 6)
    assert set(np.abs(np.diff(out, axis=0)).sum(axis=1).tolist()) == steps
    assert path_length(out, 1.0) == pytest.approx(length)
    with pytest.raises(ValueError, match="connectivity must be 4 or 8, got 6"):
        smooth(cells, np.ones((5, 7), dtype=bool), [], 6)


def test_a_4_connected_planner_never_steps_diagonally():
    model = make_home(**DETOUR)
    pl = HierarchicalPlanner(model, log_p=home_log_p(model.map), connectivity=4)
    plan = pl.plan("go to the bedroom", model.map.cell_to_world(np.array([2, 2])))
    assert plan.smoothed and (np.abs(np.diff(plan.cells, axis=0)).sum(axis=1) == 1).all()


def test_smooth_anchored_with_a_cost_keeps_the_shortcuts_only_if_better():
    """With ``cost``, smooth_anchored is its shortcuts when better() under that cost, else the path and anchors
    as given (one kernel call instead of two): checked on monotone staircases, whose shortcuts are as long, so
    the cost decides either way."""
    rng = np.random.default_rng(4)
    allowed = np.ones((30, 60), dtype=bool)
    outcomes = set()
    for _ in range(200):
        steps = rng.integers(0, 2, size=int(rng.integers(3, 40)))  # 0: right, 1: diagonal
        path = np.cumsum(np.column_stack([steps, np.ones_like(steps)]), axis=0) + np.array([2, 2])
        path = np.vstack([[2, 2], path]).astype(np.int64)
        anchors = sorted(rng.choice(len(path), size=int(rng.integers(0, 3)), replace=False).tolist())
        cost = rng.uniform(1.0, 2.0, size=allowed.shape)
        short, moved = smooth_anchored(path, allowed, anchors)
        expected = (short, moved) if better(short, path, cost) else (path, anchors)
        outcomes.add(better(short, path, cost))
        got = smooth_anchored(path, allowed, anchors, cost=cost)
        assert np.array_equal(got[0], expected[0]) and got[1] == expected[1]
    assert outcomes == {True, False}
