"""Issue 35's speed-ups compute what the code before them computed, bit for bit: each optimised kernel beside the
previous computation, written out here as it was, on generated inputs with ties and blocked entries."""

from __future__ import annotations

import contextlib
import itertools
import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from spcotmhp.datasets.synthetic import generate_environment
from spcotmhp.errors import SpcotmhpError
from spcotmhp.learning.supervised import fit_supervised
from spcotmhp.metric import _grid_kernels as _k
from spcotmhp.metric.grid_search import SQRT2
from spcotmhp.metric.map_io import grid_to_pixels
from spcotmhp.planning import explain
from spcotmhp.planning._tree_codes import encode_links
from spcotmhp.planning.assemble import path_length
from spcotmhp.planning.graph import PlanningGraph
from spcotmhp.planning.graph_settings import GraphSettings
from spcotmhp.planning.plan import GoalOption
from spcotmhp.planning.planner import HierarchicalPlanner
from spcotmhp.planning.search import _viterbi

NEG = -np.inf


def viterbi_step_before(value: np.ndarray, transition: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The recursion's inner loop as it was: a column at a time, i ascending, strict > (lowest i on ties)."""
    M = len(value)
    best, arg = np.full(M, NEG), np.zeros(M, dtype=np.int64)
    for j in range(M):
        for i in range(M):
            v = value[i] + transition[i, j]
            if v > best[j]:
                best[j], arg[j] = v, i
    return best, arg


def viterbi_before(transition, start, word, completes, columns, E):
    """:func:`~spcotmhp.planning.search._viterbi`'s tables as the previous kernel filled them."""
    S, M = word.shape[0], start.shape[0]
    pred = np.full((E + 1, S, M), -1, dtype=np.int64)
    from_stage = np.full((E + 1, S, M), -1, dtype=np.int64)
    best_terminal, terminal_step = np.full(M, NEG), np.full(M, -1, dtype=np.int64)
    value = np.full((S, M), NEG)
    value[0] = start + word[0, columns]
    for e in range(1, E + 1):
        if e > 1:
            new = np.empty((S, M))
            for s in range(S):
                best, arg = viterbi_step_before(value[s], transition)
                pred[e, s] = arg
                new[s] = best + word[s, columns]
            value = new
        for s in range(S - 1):
            for j in range(M):
                if completes[s, columns[j]] and value[s, j] > value[s + 1, j]:
                    value[s + 1, j] = value[s, j]
                    from_stage[e, s + 1, j] = s
        t = np.where(completes[S - 1, columns], value[S - 1], NEG)
        better = t > best_terminal
        best_terminal[better], terminal_step[better] = t[better], e
        if not (value > NEG).any():
            break
    return pred, from_stage, best_terminal, terminal_step


@st.composite
def problems(draw):
    """Small problems whose weights are a few integers (many exact ties) or -inf (blocked)."""
    M, S, E = draw(st.integers(1, 7)), draw(st.integers(1, 3)), draw(st.integers(1, 6))
    rng = np.random.default_rng(draw(st.integers(0, 2**32 - 1)))
    blocked = draw(st.floats(0.0, 0.9))

    def weights(shape):
        w = -rng.integers(0, 3, size=shape).astype(float)
        return np.where(rng.random(shape) < blocked, NEG, w)

    completes = rng.random((S, M)) < 0.5
    columns = rng.integers(0, M, size=M).astype(np.int64)
    return weights((M, M)), weights(M), weights((S, M)), completes, columns, E


@settings(max_examples=300, deadline=None)
@given(problems())
def test_viterbi_matches_the_column_order_recursion(problem):
    transition, start, word, completes, columns, E = problem
    tables, terminal, terminal_step, _, ok = _viterbi(transition, start, word, completes, columns, E)
    assert ok
    pred, from_stage, best_terminal, step = viterbi_before(transition, start, word, completes, columns, E)
    np.testing.assert_array_equal(tables[0], pred)
    np.testing.assert_array_equal(tables[1], from_stage)
    np.testing.assert_array_equal(terminal, best_terminal)
    np.testing.assert_array_equal(terminal_step, step)


def goal_options_before(planner, graph, cell, result, goal_places, chosen_length):
    """:func:`~spcotmhp.planning.explain.goal_options` as it was: one :meth:`ending_at` and one octile sum in
    Python per goal instance."""
    if np.count_nonzero(goal_places) < 2:
        return []

    def octile(a, b):
        dr, dc = abs(int(a[0]) - int(b[0])), abs(int(a[1]) - int(b[1]))
        return float(max(dr, dc) + (math.sqrt(2.0) - 1.0) * min(dr, dc))

    options, pending = [], []
    end_place = int(graph.node_place[result.nodes[-1]])
    res = planner.model.require_map().resolution
    for k in np.flatnonzero(goal_places):
        ks = np.flatnonzero(graph.node_place == k)
        if not len(ks) or not np.isfinite(result.terminal[ks]).any():
            continue
        node = int(ks[np.argmax(result.terminal[ks])])
        label = explain.place(planner, int(k), "goal").label
        if k == end_place:
            options.append(GoalOption(int(k), label, chosen_length, result.log_prob))
            continue
        alt = result.ending_at(node)
        anchors = [cell] + [graph.node_cell[n] for n, done in zip(alt.nodes, alt.completed, strict=False) if done]
        bound = res * sum(octile(a, b) for a, b in itertools.pairwise(anchors))
        pending.append((bound, int(k), label, alt))
    shortest = chosen_length
    for bound, kept, label, alt in sorted(pending, key=lambda p: p[0]):
        if planner.settings.arrival_quantile is None and bound > shortest + 1e-9:
            options.append(GoalOption(kept, label, bound, alt.log_prob, exact=False))
            continue
        length = path_length(planner.metric_path(graph, cell, alt)[0], res)
        shortest = min(shortest, length)
        options.append(GoalOption(kept, label, length, alt.log_prob))
    return sorted(options, key=lambda o: -o.log_prob)


@pytest.mark.parametrize("seed", [1, 2])
def test_goal_options_match_the_instance_by_instance_reading(monkeypatch, seed):
    """On generated offices (many offices and labs of one name each; with a waypoint, so that the anchors hold
    more than the goal), every plan's goal options are the previous code's, field for field."""
    ds = generate_environment("office", seed=seed, n_rooms=24, size=400)
    planner = HierarchicalPlanner(fit_supervised(ds, adjacency="given"))
    compared = []
    new = explain.goal_options

    def both(*args):
        got = new(*args)
        assert got == goal_options_before(*args)
        compared.append(len(got))
        return got

    monkeypatch.setattr(explain, "goal_options", both)
    free = np.argwhere(planner.graph.main)
    rng = np.random.default_rng(seed)
    names = sorted(set(planner.names))
    for cell in free[rng.choice(len(free), 6, replace=False)]:
        start = planner.model.require_map().cell_to_world(planner.graph.to_map(cell))
        for text in ("go to the office", "go to the lab via the corridor", f"go to the office via the {names[0]}"):
            with contextlib.suppress(SpcotmhpError):
                planner.plan(text, start)
    assert sum(n >= 2 for n in compared) >= 6  # shared names compared, not only empty lists


def fields_before(cost, territory, cells, terr, win, off, connectivity):
    """The portal graph's tree codes as the previous kernel made them: per node, ``grid_search`` (reverse field
    mode) over a copy of its territory's window, then its links encoded."""
    fcode = np.full(int(off[-1]), 99, dtype=np.int8)
    for a in range(len(cells)):
        r0, c0, r1, c1 = win[terr[a]]
        sub = np.where(territory[r0:r1, c0:c1] == terr[a], cost[r0:r1, c0:c1], np.inf)
        src = (cells[a] - np.array([r0, c0]))[None].astype(np.int64)
        _, parent, _ = _k.grid_search(
            np.ascontiguousarray(sub), src, np.empty((0, 2), np.int64), connectivity, SQRT2,
            _k.CORNER_NO_SQUEEZE, True, _k.MODE_FIELD, 0.0,
        )  # fmt: skip
        encode_links(parent, c1 - c0, fcode[off[a] : off[a + 1]])
    return fcode


@pytest.mark.parametrize("connectivity, seed", [(8, 1), (4, 2), (8, 3)])
def test_local_fields_match_the_node_by_node_search(connectivity, seed):
    """Every abstract node's tree of a generated office's portal graph, computed territory by territory, is the
    tree of the previous per-node search, code for code (and so every cost summed along it)."""
    ds = generate_environment("office", seed=seed, n_rooms=14, size=240)
    model = fit_supervised(ds, adjacency="given")
    graph = PlanningGraph.build(model, GraphSettings(connectivity=connectivity, max_dense_bytes=0))
    h = graph.hier
    assert h is not None and len(h.cells) > 20
    before = fields_before(h.cost, h.territory, h.cells, h.terr, h.win, h.off, connectivity)
    np.testing.assert_array_equal(np.asarray(h.fcode), before)


@pytest.mark.parametrize("mode", ["trinary", "raw"])
@pytest.mark.parametrize("thresholds", [(0.65, 0.196), (0.9, 0.1), (0.5, 0.3)])
def test_map_pixels_by_table_match_the_per_cell_rule(mode, thresholds):
    """save_map's pixels of an int8 grid (a table of the 256 values) are the per-cell rule's (an int16 grid
    takes that rule), for every value a cell can hold."""
    grid = np.random.default_rng(0).integers(-128, 128, size=(300, 200)).astype(np.int8)
    fast = grid_to_pixels(grid, mode, *thresholds)
    rule = grid_to_pixels(grid.astype(np.int16), mode, *thresholds)
    assert fast.dtype == rule.dtype and fast.flags.c_contiguous
    np.testing.assert_array_equal(fast, rule)


def test_kept_start_entries_are_the_computed_ones_and_views_keep_their_own():
    """TerritoryFields.entries keeps the last cells' answers: asked again they are the same arrays' values as
    computed afresh (read-only), and a view without a place (other nodes removed) answers for itself."""
    ds = generate_environment("office", seed=1, n_rooms=14, size=240)
    graph = PlanningGraph.build(fit_supervised(ds, adjacency="given"), GraphSettings(max_dense_bytes=0))
    h = graph.hier
    assert h is not None
    free = np.argwhere(graph.main)
    for cell in free[np.random.default_rng(0).choice(len(free), 20, replace=False)]:
        nodes, costs = h.entries(cell)
        again = h.entries(cell)
        t = int(h.territory[cell[0], cell[1]])
        fresh = h.members[t][~h.removed[h.members[t]]]
        np.testing.assert_array_equal(again[0], fresh)
        np.testing.assert_array_equal(again[1], h._costs(fresh, cell))
        assert not costs.flags.writeable
        view = h.without((t,))
        assert len(view.entries(cell)[0]) == 0 and len(h.entries(cell)[0]) == len(nodes)
