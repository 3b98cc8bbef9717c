"""Issue 35, item 3: goals, waypoints and Nav2 route nodes where a robot would stop (spcotmhp/planning/stops.py):
on the bundled and generated homes, every place that has a stop cell gets its points on cells of published cost
below the threshold, inside its territory and ellipse, in the planned region, the mean's point on the most
probable such cell; the previous rule (``stop_cost=None``) puts some goal at or above it, so the check measures
something."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from spcotmhp.metric.costmap import inflate
from spcotmhp.planning.planner import HierarchicalPlanner
from spcotmhp.planning.stops import STOP_COST, published_cost, stop_threshold
from spcotmhp.ros.nav2_export import route_graph
from tests.planning.test_body_plans import HOMES, learned

pytestmark = pytest.mark.filterwarnings("ignore:.*known warning")


def node_costs(planner: HierarchicalPlanner) -> tuple[np.ndarray, np.ndarray]:
    """(place, published cost) of every candidate node of the main graph."""
    graph = planner.graph
    cost = published_cost(graph.log_p)[graph.node_cell[:, 0], graph.node_cell[:, 1]]
    return graph.node_place, cost


def goal_costs(planner: HierarchicalPlanner, published: np.ndarray) -> list[tuple[int, float]]:
    """(goal place, published cost of the plan's last pose) for a plan to every planned place from its first node."""
    occ = planner.model.require_map()
    start = occ.cell_to_world(planner.graph.to_map(planner.graph.node_cell[:1]))[0]
    out = []
    for k in np.flatnonzero(planner.planned):
        plan = planner.plan({"goal": planner.names[k].split()}, tuple(start))
        r, c = occ.world_to_cell(plan.path[-1:])[0]
        out.append((int(plan.goal.id), float(published[r, c])))
    return out


@pytest.mark.parametrize("home", HOMES)
def test_goal_points_stay_below_the_stop_cost(home: str) -> None:
    model = learned(home)
    occ = model.require_map()
    published = published_of(home)
    threshold = stop_threshold(model.costmap, occ.resolution)
    assert threshold == STOP_COST  # a circle: no footprint constraint
    planner = HierarchicalPlanner(model)
    fallback = set(planner.graph.info["stop_fallback"])
    places, costs = node_costs(planner)
    with_stop = ~np.isin(places, list(fallback))
    assert with_stop.any()
    assert (costs[with_stop] < threshold).all()  # every node of a place with a stop cell
    goals = goal_costs(planner, published)
    assert [c for k, c in goals if k not in fallback and c >= threshold] == []
    # the Nav2 route nodes are the places' first candidates: the same cells
    features = route_graph(planner)["features"]
    for f in features:
        if f["geometry"]["type"] == "Point" and f["properties"]["metadata"]["place"] not in fallback:
            r, c = occ.world_to_cell(np.array([f["geometry"]["coordinates"]]))[0]
            assert published[r, c] < threshold


def published_of(home: str) -> np.ndarray:
    """The published cost of every cell of ``home``'s map (100 off its free cells)."""
    occ = learned(home).require_map()
    return np.where(occ.free, inflate(occ, **learned(home).costmap).to_occupancy_grid(), 100).astype(float)


def test_the_previous_rule_puts_goals_in_high_cost_cells() -> None:
    """The check above measures something: under the paper's rule (the nearest traversable cell) some home has
    a goal point at or above the stop cost."""
    worst = {
        home: max(c for _, c in goal_costs(HierarchicalPlanner(learned(home), stop_cost=None), published_of(home)))
        for home in HOMES
    }
    assert max(worst.values()) >= STOP_COST, worst


@pytest.mark.parametrize("home", HOMES[:2])
def test_the_mean_s_point_is_the_most_probable_stop_cell(home: str) -> None:
    model = learned(home)
    planner = HierarchicalPlanner(model)
    graph = planner.graph
    low = published_cost(graph.log_p) < STOP_COST
    occ = model.require_map()
    fallback = set(graph.info["stop_fallback"])
    for n, k in enumerate(graph.node_place.tolist()):
        if k in fallback:
            continue
        own = low & (graph.territory == k) & graph.traversable
        rows, cols = np.nonzero(own)
        xy = occ.cell_to_world(graph.to_map(np.stack([rows, cols], axis=1)))
        d = xy - model.mu[k]
        m2 = np.einsum("ni,ij,nj->n", d, np.linalg.inv(model.Sigma[k]), d)
        node = graph.node_cell[n]
        mean_cell = occ.world_to_cell(model.mu[k : k + 1])[0] - np.array(graph.offset)
        if own[mean_cell[0], mean_cell[1]]:  # the mean's own cell is a stop cell: the point stays there
            assert tuple(node) == tuple(mean_cell)
            continue
        here = occ.cell_to_world(graph.to_map(node[None]))[0] - model.mu[k]
        assert here @ np.linalg.inv(model.Sigma[k]) @ here == pytest.approx(m2.min(), abs=1e-9)


def test_a_footprint_s_circumscribed_cost_lowers_the_threshold() -> None:
    costmap = {
        "inscribed_radius": 0.2,
        "circumscribed_radius": 0.36,
        "inflation_radius": 1.0,
        "cost_scaling_factor": 10.0,
    }
    # computeCost at 0.36 m: int(252 exp(-10 x 0.16)) = 50, published 1 + 97 x 49 // 251 = 19
    assert stop_threshold(costmap, 0.05) == 19
    assert stop_threshold({"inscribed_radius": 0.2, "inflation_radius": 1.0, "cost_scaling_factor": 10.0}, 0.05) == 50


def test_published_cost_inverts_log_p() -> None:
    from spcotmhp.metric.costmap import COST_TRANSLATION_TABLE

    cost = COST_TRANSLATION_TABLE[np.arange(253)].astype(float)
    log_p = np.log((100.0 - cost) / 100.0)
    np.testing.assert_array_equal(published_cost(log_p), cost)
    assert np.isinf(published_cost(np.array([-np.inf])))[0]


def test_a_place_without_a_stop_cell_keeps_the_previous_rule_and_is_listed() -> None:
    from spcotmhp.metric.body import circle
    from spcotmhp.planning.body import with_body

    # inflated over the whole map with a slow decay: every free cell costs more than 90 of 100, no place has a stop cell
    model = with_body(learned("3LDK_01"), circle(0.22, inflation_radius=50.0, cost_scaling_factor=0.01))
    none = HierarchicalPlanner(model).graph
    assert (published_cost(none.log_p)[none.traversable] > 90).all()
    previous = HierarchicalPlanner(model, stop_cost=None).graph
    np.testing.assert_array_equal(none.node_cell, previous.node_cell)
    assert sorted(none.info["stop_fallback"]) == sorted(set(previous.node_place.tolist()))
    assert previous.info["stop_fallback"] == []


@pytest.mark.parametrize("bad", [0, 100, -1, float("nan"), "50"])
def test_stop_cost_range(bad: object) -> None:
    from spcotmhp.errors import InvalidSettings
    from spcotmhp.planning.graph_settings import GraphSettings

    with pytest.raises(InvalidSettings, match=r"stop_cost must be in \(0, 100\)"):
        GraphSettings(stop_cost=bad)  # type: ignore[arg-type]


@given(st.floats(0.05, 1.0), st.floats(0.0, 1.0), st.floats(0.0, 20.0), st.sampled_from([0.025, 0.05, 0.1]))
def test_stop_threshold_is_the_lower_of_50_and_the_circumscribed_cost(
    inscribed: float, extra: float, scaling: float, resolution: float
) -> None:
    from spcotmhp.metric.costmap import COST_TRANSLATION_TABLE, CostMapSettings

    costmap = {"inscribed_radius": inscribed, "circumscribed_radius": inscribed + extra, "cost_scaling_factor": scaling}
    threshold = stop_threshold(costmap, resolution)
    circumscribed = CostMapSettings(**costmap).circumscribed_cost(resolution)
    assert threshold == min(STOP_COST, float(COST_TRANSLATION_TABLE[circumscribed]))
    assert 0 <= threshold <= STOP_COST
    if extra == 0:  # a circle: its circumscribed cost is the inscribed 253 (published 99), no constraint
        assert threshold == STOP_COST
