"""Tests for spcotmhp.metric.grid_search: hand-computed cases, scipy's Dijkstra as an independent reference on
random weighted grids (4/8-connectivity, blocked cells, every corner rule), property tests, bad input, and the
bundled SIGVerse home."""

from __future__ import annotations

import itertools
import math
from pathlib import Path

import numpy as np
import pytest
import yaml
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.sparse import csr_matrix
from scipy.sparse.csgraph import dijkstra

from spcotmhp.errors import PlanningError, SpcotmhpError
from spcotmhp.metric.grid_search import (
    GridPath,
    GridSearchError,
    cost_to_go,
    geodesic_distance,
    path_from_field,
    shortest_paths,
    step_cost_map,
)
from spcotmhp.metric.maps import OccupancyMap

SQRT2 = math.sqrt(2.0)
HOME = Path(__file__).resolve().parents[2] / "spcotmhp" / "data" / "sigverse-3ldk" / "3LDK_01"
ORTHO = [(-1, 0), (1, 0), (0, -1), (0, 1)]
DIAG = [(-1, -1), (-1, 1), (1, -1), (1, 1)]


# ----------------------------------------------------------------------------------------------- reference
def allowed(cost: np.ndarray, u: tuple[int, int], v: tuple[int, int], rule: str) -> bool:
    """Independent statement of the move model: v in bounds and free; diagonal moves obey the corner rule."""
    H, W = cost.shape
    if not (0 <= v[0] < H and 0 <= v[1] < W) or not np.isfinite(cost[v]):
        return False
    if abs(u[0] - v[0]) + abs(u[1] - v[1]) == 2 and rule != "free":
        b1 = not np.isfinite(cost[u[0], v[1]])
        b2 = not np.isfinite(cost[v[0], u[1]])
        return not (b1 and b2) if rule == "no_squeeze" else not (b1 or b2)
    return True


def reference_graph(cost: np.ndarray, connectivity: int, rule: str, diag: float) -> csr_matrix:
    """Sparse digraph between free cells: edge u -> v weighs cost[v] * (1 or diag). Costs must be > 0 (scipy
    drops zero-weight edges)."""
    H, W = cost.shape
    rows, cols, w = [], [], []
    moves = ORTHO + (DIAG if connectivity == 8 else [])
    for r in range(H):
        for c in range(W):
            for dr, dc in moves:
                v = (r + dr, c + dc)
                if np.isfinite(cost[r, c]) and allowed(cost, (r, c), v, rule):
                    rows.append(r * W + c)
                    cols.append(v[0] * W + v[1])
                    w.append(cost[v] * (diag if dr and dc else 1.0))
    return csr_matrix((w, (rows, cols)), shape=(H * W, H * W))


def check_path(
    path: GridPath, cost: np.ndarray, start, target, connectivity: int, rule: str, diag: float, resolution=1.0
):
    """The path is a legal walk from start to target whose step costs sum to path.cost and lengths to length_m."""
    cells = path.cells
    assert tuple(cells[0]) == tuple(start) and tuple(cells[-1]) == tuple(target)
    total, length = 0.0, 0.0
    for a, b in itertools.pairwise(cells):
        d = np.abs(b - a)
        assert d.max() == 1 and (connectivity == 8 or d.sum() == 1)
        assert allowed(cost, tuple(a), tuple(b), rule)
        total += cost[tuple(b)] * (diag if d.sum() == 2 else 1.0)
        length += SQRT2 if d.sum() == 2 else 1.0
    assert path.cost == pytest.approx(total, rel=1e-12, abs=1e-12)
    assert path.length_m == pytest.approx(resolution * length, rel=1e-12)


def random_grid(seed: int, shape=(23, 31), blocked=0.25, low=0.1, high=5.0) -> np.ndarray:
    rng = np.random.default_rng(seed)
    cost = rng.uniform(low, high, size=shape)
    cost[rng.random(shape) < blocked] = np.inf
    return cost


def free_cells(cost: np.ndarray) -> np.ndarray:
    return np.argwhere(np.isfinite(cost))


# ---------------------------------------------------------------------------------------- step_cost_map
def test_step_cost_map_is_eq26_in_log_form():
    with np.errstate(divide="ignore"):
        log_p = np.log(np.array([[0.5, 1.0], [0.25, 0.0]]))
    log_n = np.log(np.array([[0.1, 0.2], [0.3, 0.4]]))
    cost = step_cost_map(log_p, log_n, connectivity=4)
    assert cost[0, 0] == pytest.approx(-math.log(0.5) - math.log(0.1) + math.log(5))
    assert cost[0, 1] == pytest.approx(-math.log(0.2) + math.log(5))
    assert cost[1, 0] == pytest.approx(-math.log(0.25) - math.log(0.3) + math.log(5))
    assert cost[1, 1] == np.inf  # p = 0: blocked
    assert step_cost_map(log_p[:1], connectivity=8)[0, 1] == pytest.approx(math.log(9))
    assert step_cost_map(log_p[:1], n_actions=3)[0, 0] == pytest.approx(math.log(2) + math.log(3))


def test_step_cost_map_does_not_underflow():
    """p * N underflows to 0 in probability space; the log form keeps a finite, usable cost."""
    log_p = np.full((3, 3), -800.0)
    log_n = np.full((3, 3), -5000.0)
    assert np.exp(log_p[0, 0]) * np.exp(log_n[0, 0]) == 0.0
    cost = step_cost_map(log_p, log_n)
    assert np.all(np.isfinite(cost))
    assert cost[1, 1] == pytest.approx(5800.0 + math.log(5))
    path = shortest_paths(cost, (0, 0), [(2, 2)], connectivity=4)
    assert path.cost == pytest.approx(4 * (5800.0 + math.log(5)))


def test_step_cost_map_negative_cost_is_reported_with_cell_and_reason():
    log_p = np.zeros((2, 3))
    log_n = np.zeros((2, 3))
    log_n[1, 2] = 2.0  # density e^2 > |A| = 5 there
    with pytest.raises(GridSearchError, match=r"negative at 1 cell\(s\), first \(row, col\) = \(1, 2\).*non-negative"):
        step_cost_map(log_p, log_n, connectivity=4)
    with pytest.raises(ValueError, match="widen Sigma"):
        step_cost_map(log_p, log_n, connectivity=4)
    assert step_cost_map(log_p, log_n, connectivity=8)[1, 2] == pytest.approx(math.log(9) - 2.0)


@pytest.mark.parametrize(
    ("log_p", "log_n", "kwargs", "message"),
    [
        (np.array([[0.0, np.nan]]), None, {}, r"log_p must be a log-probability.*\(0, 1\) holds nan"),
        (np.array([[0.0, 0.3]]), None, {}, r"log_p must be a log-probability.*\(0, 1\) holds 0.3"),
        (np.zeros(3), None, {}, r"log_p must be a non-empty 2-D array.*\(3,\)"),
        (np.array([["a"]]), None, {}, "log_p must hold numbers"),
        (
            np.zeros((2, 2)),
            np.zeros((2, 3)),
            {},
            r"log_density has shape \(2, 3\) but log_p has shape \(2, 2\)",
        ),
        (
            np.zeros((1, 2)),
            np.array([[0.0, np.inf]]),
            {},
            r"log_density must be finite or -inf.*\(0, 1\) holds inf",
        ),
        (np.zeros((1, 2)), np.array([[np.nan, 0.0]]), {}, r"log_density must be finite or -inf.*\(0, 0\)"),
        (np.zeros((1, 2)), None, {"connectivity": 6}, "connectivity must be 4 or 8, got 6"),
        (np.zeros((1, 2)), None, {"n_actions": 0}, "n_actions must be a positive integer, got 0"),
        (np.zeros((1, 2)), None, {"n_actions": 2.5}, "n_actions must be a positive integer, got 2.5"),
    ],
)
def test_step_cost_map_bad_input(log_p, log_n, kwargs, message):
    with pytest.raises(GridSearchError, match=message):
        step_cost_map(log_p, log_n, **kwargs)


# --------------------------------------------------------------------------------------- hand-computed
def test_open_grid_4_and_8_connectivity():
    ones = np.ones((3, 3))
    p4 = shortest_paths(ones, (0, 0), [(2, 2)], connectivity=4)
    assert (p4.cost, p4.length_m, len(p4.cells), p4.target_index) == (4.0, 4.0, 5, 0)
    p8 = shortest_paths(ones, (0, 0), [(2, 2)], connectivity=8, resolution=0.1)
    assert p8.cells.tolist() == [[0, 0], [1, 1], [2, 2]]
    assert p8.cost == pytest.approx(2 * SQRT2) and p8.length_m == pytest.approx(0.2 * SQRT2)
    p8u = shortest_paths(ones, (0, 0), [(2, 2)], diagonal_factor=1.0)
    assert p8u.cost == 2.0 and p8u.length_m == pytest.approx(2 * SQRT2)  # length stays geometric


def test_start_cell_is_not_counted_and_target_is():
    cost = np.array([[5.0, 1.0, 7.0]])
    path = shortest_paths(cost, (0, 0), [(0, 2)], connectivity=4)
    assert path.cost == 8.0 and path.cells.tolist() == [[0, 0], [0, 1], [0, 2]]
    back = shortest_paths(cost, (0, 2), [(0, 0)], connectivity=4)
    assert back.cost == 6.0


def test_cheaper_detour_beats_expensive_straight_line():
    cost = np.ones((3, 3))
    cost[1, 1] = 10.0
    path = shortest_paths(cost, (1, 0), [(1, 2)], connectivity=4)
    assert path.cost == 4.0
    assert [1, 1] not in path.cells.tolist()
    assert len(path.cells) == 5


def test_start_equal_to_target_and_zero_costs():
    zero = np.zeros((4, 4))
    same = shortest_paths(zero, (2, 3), [(0, 0), (2, 3)])
    assert same.cells.tolist() == [[2, 3]] and same.cost == 0.0 and same.length_m == 0.0 and same.target_index == 1
    free_ride = shortest_paths(zero, (0, 0), [(3, 3)])
    assert free_ride.cost == 0.0 and free_ride.cells[-1].tolist() == [3, 3]


def test_nearest_target_by_cost_not_by_distance():
    cost = np.ones((1, 9))
    cost[0, 1] = 100.0  # the near target at (0, 0) sits behind an expensive cell
    cost = np.vstack([cost, np.full((1, 9), np.inf)])
    path = shortest_paths(cost, (0, 2), [(0, 0), (0, 8)], connectivity=4)
    assert path.target_index == 1 and path.cost == 6.0


@pytest.mark.parametrize(
    ("rule", "squeeze_ok", "graze_ok"),
    [("free", True, True), ("no_squeeze", False, True), ("no_cut", False, False)],
)
def test_corner_rules(rule, squeeze_ok, graze_ok):
    squeeze = np.array([[1.0, np.inf], [np.inf, 1.0]])  # only a diagonal between two blocked cells
    assert (shortest_paths(squeeze, (0, 0), [(1, 1)], corner_rule=rule) is not None) == squeeze_ok
    graze = np.array([[1.0, np.inf], [1.0, 1.0]])  # diagonal past one blocked corner
    path = shortest_paths(graze, (0, 0), [(1, 1)], corner_rule=rule)
    assert len(path.cells) == (2 if graze_ok else 3)


def test_cost_to_go_field_and_path_from_field():
    cost = np.ones((5, 5))
    cost[2, 1:4] = np.inf
    field, nxt = cost_to_go(cost, [(4, 2)])
    assert field[4, 2] == 0.0 and field[3, 2] == 1.0 and field[4, 0] == 2.0
    assert field[3, 0] == pytest.approx(1 + SQRT2)
    assert np.isinf(field[2, 2]) and nxt[2, 2] == -1 and nxt[4, 2] == -1
    # from (0, 2): down the side corridor, 4 diagonal steps
    assert field[0, 2] == pytest.approx(4 * SQRT2)
    path = path_from_field(field, nxt, (0, 2), sources=[(1, 1), (4, 2)], resolution=0.1)
    assert path.cost == pytest.approx(4 * SQRT2) and path.target_index == 1
    assert path.length_m == pytest.approx(0.4 * SQRT2)
    check_path(path, cost, (0, 2), (4, 2), 8, "no_squeeze", SQRT2, 0.1)


def test_geodesic_distance_octile_and_resolution():
    free = np.ones((3, 4), dtype=bool)
    free[:2, 2] = False
    d = geodesic_distance(free, [(0, 0)], resolution=0.5)
    assert d[0, 3] == pytest.approx(0.5 * (1 + 3 * SQRT2))  # (1,1), (2,2), (1,3) diagonally, then up
    assert d[2, 2] == pytest.approx(0.5 * (2 * SQRT2))
    assert np.isinf(d[0, 2])
    d4 = geodesic_distance(free, [(0, 0)], connectivity=4)
    assert d4[0, 3] == 7.0


def test_world_path_uses_cell_centres():
    occ = OccupancyMap(data=np.zeros((3, 3), np.int8), resolution=0.1, origin=(-1.0, 2.0, 0.0))
    path = shortest_paths(np.ones((3, 3)), (0, 0), [(2, 1)])
    xy = path.world(occ)
    assert xy.shape == (len(path.cells), 2)
    assert xy[0] == pytest.approx([-0.95, 2.05]) and xy[-1] == pytest.approx([-0.85, 2.25])


# --------------------------------------------------------------------------------------- unreachable
def test_unreachable_targets_are_reported():
    cost = np.ones((3, 5))
    cost[:, 2] = np.inf
    assert shortest_paths(cost, (0, 0), [(0, 4)]) is None
    with pytest.raises(PlanningError, match=r"no path from start \(0, 0\) to any of 1 target"):
        shortest_paths(cost, (0, 0), [(0, 4)], strict=True)
    paths = shortest_paths(cost, (0, 0), [(0, 4), (2, 1)], all_targets=True)
    assert paths[0] is None and paths[1].cost == pytest.approx(1 + SQRT2)
    with pytest.raises(PlanningError, match=r"to target\(s\) #0 \(0, 4\)"):
        shortest_paths(cost, (0, 0), [(0, 4), (2, 1)], all_targets=True, strict=True)
    field, nxt = cost_to_go(cost, [(1, 1)])
    assert np.all(np.isinf(field[:, 2:]))
    assert path_from_field(field, nxt, (0, 4)) is None
    with pytest.raises(PlanningError, match=r"start cell \(0, 4\) cannot reach any source"):
        path_from_field(field, nxt, (0, 4), strict=True)


# ----------------------------------------------------------------------------------------- bad input
@pytest.mark.parametrize(
    ("cost", "start", "targets", "kwargs", "message"),
    [
        (
            np.ones((3, 3)),
            (3, 0),
            [(0, 0)],
            {},
            r"start cell \(row, col\) = \(3, 0\) is off the grid of 3 rows x 3 cols",
        ),
        (
            np.ones((3, 3)),
            (0, 0),
            [(1, 1), (0, -1)],
            {},
            r"target cell \(row, col\) = \(0, -1\) is off the grid",
        ),
        (np.array([[np.inf, 1.0]]), (0, 0), [(0, 1)], {}, r"start cell \(row, col\) = \(0, 0\) is blocked"),
        (np.array([[1.0, np.inf]]), (0, 0), [(0, 1)], {}, r"target cell \(row, col\) = \(0, 1\) is blocked"),
        (np.ones((3, 3)), (0, 0), np.empty((0, 2)), {}, r"target cells must be \(row, col\) pairs.*\(0, 2\)"),
        (np.ones((3, 3)), (0, 0, 1), [(1, 1)], {}, r"start cells must be \(row, col\) pairs"),
        (np.ones((3, 3)), [(0, 0), (1, 1)], [(1, 1)], {}, "start must be one"),
        (np.ones((3, 3)), (0.5, 0), [(1, 1)], {}, "start cells must be integer"),
        (np.ones((3, 3)), ("a", "b"), [(1, 1)], {}, "start cells must be integer"),
        (np.array([[1.0, np.nan]]), (0, 0), [(0, 0)], {}, r"cell_cost must be >= 0.*\(0, 1\) holds nan"),
        (np.array([[1.0, -0.5]]), (0, 0), [(0, 0)], {}, r"cell_cost must be >= 0.*\(0, 1\) holds -0.5"),
        (np.ones(4), (0, 0), [(0, 0)], {}, "cell_cost must be a non-empty 2-D array"),
        (np.ones((2, 2)), (0, 0), [(1, 1)], {"connectivity": 6}, "connectivity must be 4 or 8"),
        (
            np.ones((2, 2)),
            (0, 0),
            [(1, 1)],
            {"diagonal_factor": 0.5},
            "diagonal_factor must be a finite number >= 1",
        ),
        (np.ones((2, 2)), (0, 0), [(1, 1)], {"diagonal_factor": np.nan}, "diagonal_factor must be a finite"),
        (np.ones((2, 2)), (0, 0), [(1, 1)], {"corner_rule": "cut"}, "corner_rule must be one of"),
    ],
)
def test_bad_input_messages(cost, start, targets, kwargs, message):
    with pytest.raises(GridSearchError, match=message):
        shortest_paths(cost, start, targets, **kwargs)


def test_error_type_is_both_planning_and_value_error():
    assert issubclass(GridSearchError, PlanningError) and issubclass(GridSearchError, ValueError)
    assert issubclass(GridSearchError, SpcotmhpError)
    with pytest.raises(GridSearchError, match=r"source cell \(row, col\) = \(0, 1\) is blocked"):
        cost_to_go(np.array([[1.0, np.inf]]), [(0, 0), (0, 1)])
    with pytest.raises(GridSearchError, match="must be the same 2-D shape"):
        path_from_field(np.zeros((2, 2)), np.zeros((2, 3), np.int64), (0, 0))
    with pytest.raises(
        GridSearchError, match="next_step must hold int32 or int64 flat cell indices, got dtype float64"
    ):
        path_from_field(np.zeros((2, 2)), np.zeros((2, 2)), (0, 0))


def test_path_from_field_accepts_int64_links():
    cost = random_grid(5)
    free = free_cells(cost)
    field, nxt = cost_to_go(cost, free[:1])
    a = path_from_field(field, nxt, free[-1])
    b = path_from_field(field, nxt.astype(np.int64), free[-1])
    assert a is not None and np.array_equal(a.cells, b.cells) and a.cost == b.cost


# ------------------------------------------------------------------------------- against scipy's Dijkstra
@pytest.mark.parametrize("connectivity", [4, 8])
@pytest.mark.parametrize("rule", ["free", "no_squeeze", "no_cut"])
@pytest.mark.parametrize(
    ("seed", "diag", "low", "high"),
    [(0, SQRT2, 0.1, 5), (1, 1.0, 0.1, 5), (2, 2.5, 0.1, 5), (3, SQRT2, 1, 1.1)],
)
def test_exact_against_scipy_on_random_grids(connectivity, rule, seed, diag, low, high):
    """(The nearly uniform case makes the A* heuristic tight, so an inadmissible one would show.)"""
    cost = random_grid(seed, low=low, high=high)
    free = free_cells(cost)
    rng = np.random.default_rng(100 + seed)
    start = tuple(free[rng.integers(len(free))])
    W = cost.shape[1]
    ref = dijkstra(reference_graph(cost, connectivity, rule, diag), indices=start[0] * W + start[1])
    kw = {"connectivity": connectivity, "diagonal_factor": diag, "corner_rule": rule}

    # Dijkstra to every free cell at once
    paths = shortest_paths(cost, start, free, all_targets=True, **kw)
    for cell, path in zip(free, paths, strict=False):
        expected = ref[cell[0] * W + cell[1]]
        if np.isinf(expected):
            assert path is None
        else:
            assert path.cost == pytest.approx(expected, rel=1e-12)
    for i in rng.choice(len(free), 15, replace=False):
        if paths[i] is not None:
            check_path(paths[i], cost, start, free[i], connectivity, rule, diag)

    # A* to single targets and to the cheapest of a target set agrees with Dijkstra
    for _ in range(15):
        target = tuple(free[rng.integers(len(free))])
        path = shortest_paths(cost, start, [target], **kw)
        expected = ref[target[0] * W + target[1]]
        assert (path is None) == np.isinf(expected)
        if path is not None:
            assert path.cost == pytest.approx(expected, rel=1e-12)
            check_path(path, cost, start, target, connectivity, rule, diag)
        group = free[rng.choice(len(free), 4, replace=False)]
        best = shortest_paths(cost, start, group, **kw)
        costs = ref[group[:, 0] * W + group[:, 1]]
        if np.isinf(costs.min()):
            assert best is None
        else:
            assert best.cost == pytest.approx(costs.min(), rel=1e-12)
            assert costs[best.target_index] == pytest.approx(costs.min(), rel=1e-12)

    # cost-to-go: the reversed graph, several sources
    sources = free[rng.choice(len(free), 3, replace=False)]
    field, nxt = cost_to_go(cost, sources, connectivity, diag, corner_rule=rule)
    graph_t = reference_graph(cost, connectivity, rule, diag).T.tocsr()
    ref_field = dijkstra(graph_t, indices=sources[:, 0] * W + sources[:, 1], min_only=True).reshape(cost.shape)
    np.testing.assert_allclose(field, ref_field, rtol=1e-12)
    for cell in free[rng.choice(len(free), 10, replace=False)]:
        path = path_from_field(field, nxt, cell, sources)
        if path is not None:
            check_path(path, cost, cell, sources[path.target_index], connectivity, rule, diag)
            assert path.cost == pytest.approx(field[tuple(cell)], rel=1e-12)


def test_geodesic_distance_matches_scipy():
    cost = random_grid(7, blocked=0.3)
    free = np.isfinite(cost)
    unit = np.where(free, 1.0, np.inf)
    src = free_cells(cost)[:2]
    W = cost.shape[1]
    ref = dijkstra(
        reference_graph(unit, 8, "no_squeeze", SQRT2).T.tocsr(),
        indices=src[:, 0] * W + src[:, 1],
        min_only=True,
    )
    np.testing.assert_allclose(
        geodesic_distance(free, src, resolution=0.05), 0.05 * ref.reshape(cost.shape), rtol=1e-12
    )


def test_float32_costs_give_the_float64_answer():
    cost = random_grid(3).astype(np.float32)
    free = free_cells(cost)
    a = shortest_paths(cost, tuple(free[0]), [tuple(free[-1])])
    b = shortest_paths(cost.astype(np.float64), tuple(free[0]), [tuple(free[-1])])
    assert a.cost == b.cost and np.array_equal(a.cells, b.cells)


@settings(max_examples=60, deadline=None)
@given(
    st.integers(1, 9),
    st.integers(1, 9),
    st.lists(st.sampled_from([0.25, 1.0, 1.0, 2.0, 3.5, 7.0, np.inf]), min_size=81, max_size=81),
    st.sampled_from([4, 8]),
    st.sampled_from(["free", "no_squeeze", "no_cut"]),
    st.sampled_from([1.0, SQRT2, 3.0]),
    st.integers(0, 10_000),
)
def test_astar_equals_dijkstra_property(h, w, values, connectivity, rule, diag, pick):
    cost = np.array(values[: h * w]).reshape(h, w)
    free = free_cells(cost)
    if len(free) == 0:
        return
    start = tuple(free[pick % len(free)])
    target = tuple(free[(pick // 7) % len(free)])
    ref = dijkstra(reference_graph(cost, connectivity, rule, diag), indices=start[0] * w + start[1])
    expected = ref[target[0] * w + target[1]]
    path = shortest_paths(cost, start, [target], connectivity=connectivity, diagonal_factor=diag, corner_rule=rule)
    if np.isinf(expected):
        assert path is None
    else:
        assert path.cost == pytest.approx(expected, rel=1e-12, abs=1e-12)
        check_path(path, cost, start, target, connectivity, rule, diag)


# ------------------------------------------------------------------------------------- bundled SIGVerse home
def load_home():
    meta = yaml.safe_load((HOME / "map.yaml").read_text())
    occ = OccupancyMap(data=np.zeros((192, 192), np.int8), resolution=meta["resolution"], origin=tuple(meta["origin"]))
    ros = np.loadtxt(HOME / "costmap_ros.csv", delimiter=",", dtype=np.int64)
    teach = np.loadtxt(HOME / "teaching.csv", delimiter=",", skiprows=1, usecols=(1, 2))
    place = np.loadtxt(HOME / "truth.csv", delimiter=",", skiprows=1, usecols=1, dtype=np.int64)
    return occ, ros, teach, place


def test_control_as_inference_paths_on_a_bundled_home():
    occ, ros, teach, place = load_home()
    assert ros.shape == (192, 192)
    with np.errstate(divide="ignore"):
        log_p = np.log(np.where(ros < 99, (100 - ros) / 100.0, 0.0))
    mu = np.array([teach[place == k].mean(axis=0) for k in range(11)])
    centres = occ.world_to_cell(mu)
    # the goal place's Gaussian, in log form over every cell centre (Eq. 26's N(x | mu_b, Sigma_b))
    goal = 3
    pts = teach[place == goal]
    sigma = np.cov(pts.T) + 0.05 * np.eye(2)
    diff = occ.cell_centres() - mu[goal]
    maha = np.einsum("...i,ij,...j->...", diff, np.linalg.inv(sigma), diff)
    log_n = -0.5 * maha - math.log(2 * math.pi) - 0.5 * math.log(np.linalg.det(sigma))
    cost = step_cost_map(log_p, log_n, connectivity=8)
    reachable = [k for k in range(11) if np.isfinite(cost[tuple(centres[k])])]
    assert len(reachable) >= 9  # place centres lie in free space
    assert goal in reachable
    field, nxt = cost_to_go(cost, [centres[goal]])
    W = cost.shape[1]
    ref = dijkstra(
        reference_graph(cost, 8, "no_squeeze", SQRT2).T.tocsr(),
        indices=centres[goal][0] * W + centres[goal][1],
    )
    np.testing.assert_allclose(field, ref.reshape(cost.shape), rtol=1e-12)
    for k in reachable:
        a = shortest_paths(cost, centres[k], [centres[goal]], resolution=occ.resolution)
        b = path_from_field(field, nxt, centres[k], [centres[goal]], resolution=occ.resolution)
        assert a is not None and b is not None
        assert a.cost == pytest.approx(b.cost, rel=1e-12) == pytest.approx(field[tuple(centres[k])], rel=1e-12)
        check_path(a, cost, centres[k], centres[goal], 8, "no_squeeze", SQRT2, occ.resolution)
        world = a.world(occ)
        assert (
            np.linalg.norm(world[0] - mu[k]) <= occ.resolution
            and np.linalg.norm(world[-1] - mu[goal]) <= occ.resolution
        )
        # a path is at least as long as the straight line between its end cells
        assert a.length_m >= np.linalg.norm(world[-1] - world[0]) - 1e-9
    every = shortest_paths(cost, centres[goal], centres[reachable], all_targets=True)
    assert all(p is not None for p in every)
