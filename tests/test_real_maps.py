"""Issue 35 on a real map nobody here made: the TurtleBot3 world's SLAM map (ROBOTIS-GIT/turtlebot3, Apache-2.0;
tests/data/real_maps/README.md) with five places taught by hand, 5 points each, in English and Japanese. Learned as
``learn`` does (multi-run Gibbs, then the taught-merge split) for two seeds: every taught room is its own place or
its merge is reported; every name is shown as taught ("room 2", "西の端", "2号室") and "go to" it plans to a point
nearest that room's teaching; for a 0.30 m robot (Nav2's radius and inflation layer) no pose of any plan lies in
its inscribed cells and no goal point in a cell of cost >= the stop rule's threshold. The figures on all three real
maps are benchmarks/real_maps.py's (docs/planning.md)."""

from __future__ import annotations

import warnings
from pathlib import Path

import numpy as np
import pytest

from spcotmhp.datasets.loader import load_dataset
from spcotmhp.learning.selection import fit_runs
from spcotmhp.learning.taught_split import split_selected
from spcotmhp.metric.costmap import INSCRIBED_INFLATED_OBSTACLE, inflate
from spcotmhp.metric.nav2_params import resolve_body
from spcotmhp.planning.body import with_body
from spcotmhp.planning.planner import HierarchicalPlanner
from spcotmhp.planning.stops import STOP_COST, published_cost
from spcotmhp.planning.vocabulary import place_labels, place_vocabulary
from spcotmhp.teaching.questions import name_vocabulary, said_merges

FOLDER = Path(__file__).parent / "data" / "real_maps" / "turtlebot3-world"
ASK = {"en": "go to the {}", "ja": "{}に行って"}


@pytest.fixture(scope="module", params=[("en", 0), ("en", 1), ("ja", 0), ("ja", 1)], ids=str)
def learned(request):
    """(dataset, learned model, merges reported, planner for the 0.30 m body)."""
    lang, seed = request.param
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        data = load_dataset(FOLDER, lang=lang)
        sel = fit_runs(data, runs=4, seed=seed)
    model = sel.model_
    split_selected(sel, data, name_vocabulary(model), place_labels(model, place_vocabulary(model)))
    body = resolve_body(robot_radius=0.30, inflation_radius=0.55, cost_scaling_factor=3.0)
    return data, sel.model_, said_merges(sel.model_), HierarchicalPlanner(with_body(sel.model_, body))


def test_every_taught_room_is_its_own_place_or_its_merge_is_reported(learned):
    data, model, merges, _ = learned
    place = np.asarray(model.learner["arrays"]["place"])
    home = {name: int(np.bincount(place[data.truth_place == r]).argmax()) for r, name in enumerate(data.place_names)}
    reported = {m.name for m in merges} | {m.other for m in merges}
    for name, k in home.items():
        alone = list(home.values()).count(k) == 1
        assert alone or name in reported, (name, home, merges)


def test_names_are_shown_as_taught_and_asked_for_plan_there(learned):
    data, _, _, planner = learned
    shown = {planner.shown[k] for k in np.flatnonzero(planner.model.active_places)}
    assert set(data.place_names) <= shown, shown
    start = tuple(data.positions[0])
    for room, name in enumerate(data.place_names):
        plan = planner.plan(ASK[data.lang].format(name), start)
        nearest = int(np.argmin(np.linalg.norm(data.positions - plan.path[-1], axis=1)))
        assert plan.goal.name == name and data.truth_place[nearest] == room, (name, plan.explanation)


def test_a_030_m_robot_keeps_its_inscribed_cells_clear_and_stops_on_low_cost(learned):
    data, _, _, planner = learned
    occ = planner.model.require_map()
    inscribed = inflate(occ, **planner.model.costmap).costs >= INSCRIBED_INFLATED_OBSTACLE
    for name in data.place_names:
        for start in data.positions[:: len(data.positions) // 3]:
            cells = occ.world_to_cell(planner.plan(ASK[data.lang].format(name), tuple(start)).path)
            assert not inscribed[cells[:, 0], cells[:, 1]].any(), (name, start)
    graph = planner.graph
    first = np.r_[True, graph.node_place[1:] != graph.node_place[:-1]]
    cells = graph.node_cell[first]
    stop = ~np.isin(graph.node_place[first], list(graph.info["stop_fallback"]))
    assert (published_cost(graph.log_p)[cells[stop, 0], cells[stop, 1]] < STOP_COST).all()
