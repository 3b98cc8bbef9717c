"""Hierarchical planning on the hand-made four-room home (tests/helpers/planning.py)."""

from __future__ import annotations

import dataclasses
import json

import numpy as np
import pytest

from spcotmhp.errors import InstructionError, PlanningError, UnknownPlaceWord
from spcotmhp.planning.assemble import path_length
from spcotmhp.planning.places import inside_places
from spcotmhp.planning.planner import HierarchicalPlanner, PlannerSettings, plan
from spcotmhp.planning.terms import ModelTerms
from tests.helpers.graphs import GRAPHS
from tests.helpers.learning import brute_word_term
from tests.helpers.planning import home_log_p, home_model, world

L, M, K, R = 0, 1, 2, 3


@pytest.fixture(scope="module")
def planner() -> HierarchicalPlanner:
    model = home_model()
    return HierarchicalPlanner(model, log_p=home_log_p(model.map), cache=GRAPHS)


def check_path(planner: HierarchicalPlanner, plan, start_cell) -> None:
    cells = plan.cells
    assert (cells[0] == start_cell).all()
    steps = np.abs(np.diff(cells, axis=0))
    assert (steps.max(axis=1) == 1).all()  # 8-connected, no repeated cell
    assert (planner.model.map.data[cells[:, 0], cells[:, 1]] == 0).all()
    assert plan.length_m == pytest.approx(path_length(cells, planner.model.map.resolution))
    assert np.allclose(plan.path, planner.model.map.cell_to_world(cells))


def territory_of(planner, cells, places) -> np.ndarray:
    """Bool per path cell: inside the territory of one of ``places`` (what avoidance blocks)."""
    crop = planner.graph.to_crop(cells)
    return np.isin(planner.graph.territory[crop[:, 0], crop[:, 1]], places)


def test_goes_to_the_closest_bedroom(planner):
    start = (3, 12)  # in the corridor, next to bedroom #1's door
    p = planner.plan("go to the bedroom", world(planner.model.map, *start))
    check_path(planner, p, start)
    assert [(q.id, q.role) for q in p.places] == [(M, "start"), (L, "goal")]
    assert (p.cells[-1] == planner.model.map.world_to_cell(planner.model.mu[L])).all()
    assert p.explanation == f"corridor -> bedroom #1 (closest of 2 bedrooms), {p.length_m:.1f} m"
    assert [o.id for o in p.goal_options] == [L, R]
    assert p.goal_options[0].length_m < p.goal_options[1].length_m
    q = planner.plan("go to the bedroom", world(planner.model.map, 3, 18))
    assert q.goal.id == R and q.goal.label == "bedroom #2"


def test_waypoint_changes_the_goal_instance(planner):
    # the kitchen opens only into bedroom #2, so "via the kitchen" makes bedroom #2 the right goal
    start = (3, 12)
    p = planner.plan("go to the bedroom via the kitchen", world(planner.model.map, *start))
    check_path(planner, p, start)
    assert [(q.id, q.role) for q in p.places] == [(M, "start"), (R, "via"), (K, "waypoint"), (R, "goal")]
    assert p.explanation.startswith("corridor -> bedroom #2 -> kitchen (waypoint) -> bedroom #2 (closest of 2")
    model = planner.model
    in_k = inside_places(model, p.path, [K])
    assert in_k.any()
    assert inside_places(model, p.path[-1:], [R]).all()
    assert (p.cells[-1] == model.map.world_to_cell(model.mu[R])).all()
    # passes the kitchen candidate exactly (an anchor of the smoothing)
    assert (p.cells == model.map.world_to_cell(model.mu[K])).all(axis=1).any()


def test_two_waypoints_in_order(planner):
    start = (3, 12)
    p = planner.plan("go to the corridor via the kitchen and then the bedroom", world(planner.model.map, *start))
    roles = [(q.id, q.role) for q in p.places if q.role != "via"]
    assert roles == [(M, "start"), (K, "waypoint"), (R, "waypoint"), (M, "goal")]
    check_path(planner, p, start)


def test_avoided_place_is_never_entered(planner):
    model = planner.model
    # from bedroom #2, the corridor is reachable; avoiding the kitchen changes nothing but must hold
    p = planner.plan("go to the corridor avoiding the kitchen", world(model.map, 5, 25))
    blocked = territory_of(planner, p.cells, [K])
    assert not blocked.any()
    assert p.explanation.endswith("avoiding kitchen")
    # the only way into the kitchen is through bedroom #2
    with pytest.raises(PlanningError) as info:
        planner.plan("go to the kitchen avoiding the bedroom", world(model.map, 3, 12))
    assert str(info.value) == (
        "no free path from (6.25, 1.75) reaches a place named 'kitchen' (goal) without entering the places to avoid"
    )
    # from inside the bedroom: the path leaves it by the shortest way and never comes back (issue 34)
    p = planner.plan("go to the corridor avoiding the bedroom", world(model.map, 3, 25))
    assert "the start is inside bedroom, to be avoided: the path leaves it by the shortest way" in p.explanation
    inside = territory_of(planner, p.cells, [int(k) for k, n in enumerate(planner.names) if n == "bedroom"])
    assert inside[0] and not inside[int(np.flatnonzero(~inside)[0]) :].any()
    with pytest.raises(PlanningError, match="every place named 'bedroom' is also to be avoided"):
        planner.plan("go to the bedroom avoiding the bedroom", world(model.map, 3, 12))


def test_avoiding_blocks_metric_legs_too():
    # connect bedroom #1 and bedroom #2 directly in psi: topologically L -> R -> K is allowed without the
    # corridor, but the metric leg L -> R can only run through the corridor, so avoiding it must fail
    model = home_model()
    psi = model.psi.copy()
    psi[L, R] = psi[R, L] = psi[L, M]
    psi /= psi.sum(axis=1, keepdims=True)
    model.psi = psi
    pl = HierarchicalPlanner(model, log_p=home_log_p(model.map))
    assert np.isfinite(pl.graph.w_hat[L, R])
    ok = pl.plan("go to the kitchen", world(model.map, 6, 3))
    assert territory_of(pl, ok.cells, [M]).any()
    with pytest.raises(PlanningError, match="reaches a place named 'kitchen' .goal. without entering the places"):
        pl.plan("go to the kitchen avoiding the corridor", world(model.map, 6, 3))


@pytest.mark.parametrize(
    "start, message",
    [
        (
            (0.2, 0.2),
            (
                "the start (0.20, 0.20) is in an occupied cell of the map; start from a free cell, e.g. the "
                "nearest one the robot can plan from, ("
            ),
        ),
        ((-3.0, 1.0), "the start (-3.00, 1.00) is outside the map (x 0.00..15.50, y 0.00..6.50)"),
        ((1.0,), "the start must be two finite numbers (x, y) in metres"),
        ((np.nan, 1.0), "the start must be two finite numbers (x, y) in metres"),
        ("here", "the start must be two numbers (x, y) in metres, got 'here'"),
    ],
)
def test_bad_starts(planner, start, message):
    with pytest.raises(PlanningError) as info:
        planner.plan("go to the kitchen", start)
    assert message in str(info.value)


def test_a_blocked_start_suggests_one_that_plans(planner):
    import re

    with pytest.raises(PlanningError) as info:
        planner.plan("go to the kitchen", (0.2, 0.2))
    x, y = map(float, re.search(r"plan from, \((\S+), (\S+)\)$", str(info.value)).groups())
    assert np.hypot(x - 0.2, y - 0.2) < 1.0
    assert planner.plan("go to the kitchen", (x, y)).length_m > 0


def test_unknown_word(planner):
    with pytest.raises(InstructionError, match="known place words: bedroom, corridor, kitchen"):
        planner.plan("go to the garage", world(planner.model.map, 3, 12))


def test_horizon_too_short():
    model = home_model()
    pl = HierarchicalPlanner(model, log_p=home_log_p(model.map), max_steps=1, cache=GRAPHS)
    with pytest.raises(PlanningError) as info:
        pl.plan("go to the bedroom via the kitchen", world(model.map, 3, 12))
    assert "no sequence of at most 1 place-to-place steps from (6.25, 1.75) satisfies 'bedroom via kitchen'" in str(
        info.value
    )


def test_smoothing_never_lengthens_and_keeps_the_ends(planner):
    model = planner.model
    raw = HierarchicalPlanner(model, log_p=home_log_p(model.map), smooth=False, cache=GRAPHS)
    for text in ["go to the bedroom", "go to the bedroom via the kitchen", "go to the kitchen"]:
        for start in [(3, 12), (9, 3), (10, 28)]:
            a = planner.plan(text, world(model.map, *start))
            b = raw.plan(text, world(model.map, *start))
            assert a.length_m <= b.length_m + 1e-9
            assert (a.cells[-1] == b.cells[-1]).all() and (a.cells[0] == b.cells[0]).all()
            assert a.log_prob == b.log_prob and [p.id for p in a.places] == [p.id for p in b.places]
            check_path(planner, a, start)


def test_structured_and_nbest_instructions(planner):
    start = world(planner.model.map, 3, 12)
    a = planner.plan({"goal": ["bedroom"], "waypoints": [["kitchen"]]}, start)
    b = planner.plan([("go to the bedroom via the kitchen", 0.9), ("go to the bedroom via the corridor", 0.1)], start)
    assert a.goal.id == b.goal.id == R
    assert b.instruction.waypoints[0].words == pytest.approx({"kitchen": 0.9, "corridor": 0.1})


def test_start_place_is_the_posterior_arg_max_and_first_step_follows_the_graph(planner):
    model = planner.model
    x0 = world(model.map, 3, 12)
    post = ModelTerms(model).place_posterior(x0)
    assert post == pytest.approx(model.place_posterior(x0))
    p = planner.plan("go to the kitchen", x0)
    # the kitchen is not next to the corridor: the plan goes corridor -> bedroom #2 -> kitchen
    assert [q.id for q in p.places] == [M, R, K]


def test_terms_are_the_word_term(planner):
    terms, model = planner.terms, planner.model
    for bag in [{"bedroom": 1.0}, {"kitchen": 0.7, "corridor": 0.3}]:
        want = brute_word_term(model.pi, model.phi, model.W, model.bag_vector(bag))
        assert terms.log_semantic(bag) == pytest.approx(want)
        assert np.exp(terms.log_place_given_words(bag)) == pytest.approx(np.exp(want) / np.exp(want).sum())
    assert terms.log_ur == pytest.approx(np.log(model.phi.sum(axis=0)))


def test_terms_when_w_holds_a_zero():
    # a saved model may hold W_l(w) = 0; a word absent from the bag must then add nothing (not 0 * log 0 = NaN)
    model = home_model()
    W = model.W.copy()
    W[0] = [1.0, 0.0, 0.0]  # concept 0 only ever says "bedroom"
    model.W = W
    terms = ModelTerms(model)
    bag = {"bedroom": 1.0}
    assert model.log_word_likelihood(bag)[0] == 0.0
    assert np.isfinite(terms.log_semantic(bag)).all()
    assert terms.log_semantic(bag) == pytest.approx(brute_word_term(model.pi, model.phi, W, [1, 0, 0]))
    assert model.log_word_likelihood({"kitchen": 1.0})[0] == -np.inf


def test_plan_json_and_timings(planner):
    p = planner.plan("go to the bedroom via the kitchen", world(planner.model.map, 3, 12))
    d = json.loads(p.to_json())
    assert {"path", "places", "length_m", "log_prob", "time_online_s", "explanation"} <= set(d)
    assert d["places"][0] == {
        "id": M,
        "name": "corridor",
        "role": "start",
        "label": "corridor",
        "point": [6.25, 1.75],
        "chosen_by": None,  # no relation picked it
    }
    assert d["places"][2]["point"] == pytest.approx(
        list(planner.model.map.cell_to_world(planner.model.map.world_to_cell(planner.model.mu[K])))
    )
    assert d["places"][-1]["role"] == "goal" and d["places"][-1]["label"] == "bedroom #2"
    assert np.allclose(d["path"], p.path, atol=1e-4)
    assert d["time_online_s"] > 0 and p.time_precompute_s > 0
    assert np.isfinite(d["log_prob"]) and d["log_prob"] == p.log_prob


def test_plan_function_and_settings():
    model = home_model()
    p = plan(model, "go to the bedroom", world(model.map, 3, 12), log_p=home_log_p(model.map))
    assert p.goal.id == L
    with pytest.raises(TypeError, match="unknown planner setting"):
        HierarchicalPlanner(model, log_p=home_log_p(model.map), n_candidate=3)
    assert PlannerSettings(n_candidates=3).graph_settings().n_candidates == 3


@pytest.mark.parametrize(
    "setting, message",
    [
        ({"n_candidates": 0}, "n_candidates must be an integer in [1, 100], got 0"),
        ({"n_candidates": -1}, "n_candidates must be an integer in [1, 100], got -1"),
        ({"n_candidates": 2.5}, "n_candidates must be an integer in [1, 100], got 2.5"),
        ({"n_candidates": 10**9}, "n_candidates must be an integer in [1, 100], got 1000000000"),
        ({"seed": -1}, "seed must be an integer >= 0, got -1"),
        ({"connectivity": 6}, "connectivity must be 4 or 8, got 6"),
        ({"edge_threshold": 1.5}, "edge_threshold must be in [0, 1] (or None: 1/K), got 1.5"),
        ({"candidate_quantile": 1.0}, "candidate_quantile must be in (0, 1), got 1.0"),
        ({"tube_margin": float("nan")}, "tube_margin must be >= 0, got nan"),
        ({"steps_per_stage": 0}, "steps_per_stage must be an integer in [1, 1000], got 0"),
        ({"steps_per_stage": 1001}, "steps_per_stage must be an integer in [1, 1000], got 1001"),
        ({"max_steps": 0}, "max_steps must be an integer in [1, 1000], got 0"),
        ({"max_steps": -3}, "max_steps must be an integer in [1, 1000], got -3"),
        ({"max_steps": 10**9}, "max_steps must be an integer in [1, 1000], got 1000000000"),
        ({"instance_ratio": 0.5}, "instance_ratio must be >= 1, got 0.5"),
        ({"start_min_posterior": 2}, "start_min_posterior must be in [0, 1], got 2"),
        ({"arrival_quantile": 1.2}, "arrival_quantile must be in (0, 1) (or None), got 1.2"),
    ],
)
def test_bad_settings_are_planning_errors(setting, message):
    with pytest.raises(PlanningError) as info:
        PlannerSettings(**setting)
    assert str(info.value) == message
    model = home_model()
    with pytest.raises(PlanningError):
        HierarchicalPlanner(model, log_p=home_log_p(model.map), **setting)


def test_planner_settings_derive_from_graph_settings():
    from dataclasses import fields

    from spcotmhp.planning.graph import GraphSettings

    graph_fields = [(f.name, f.default) for f in fields(GraphSettings)]
    assert [(f.name, f.default) for f in fields(PlannerSettings)][: len(graph_fields)] == graph_fields
    assert PlannerSettings(tube_margin=0.5, max_steps=3).graph_settings() == GraphSettings(tube_margin=0.5)


def test_several_candidates_per_place():
    model = home_model()
    pl = HierarchicalPlanner(model, log_p=home_log_p(model.map), n_candidates=4, seed=1, cache=GRAPHS)
    for start in [(3, 12), (9, 3)]:
        p = pl.plan("go to the bedroom via the kitchen", world(model.map, *start))
        check_path(pl, p, start)
        assert p.goal.id == R and inside_places(model, p.path[-1:], [R]).all()


def test_nbest_goal_follows_the_recogniser_unless_it_is_a_near_tie(planner):
    x0 = world(planner.model.map, 3, 12)  # bedroom #1 is next door, the kitchen far away
    assert planner.plan([("go to the kitchen", 0.7), ("go to the bedroom", 0.3)], x0).goal.id == K
    # a near tie lets both names in (p(i|S) within the instance ratio); the cheaper path then wins
    assert planner.plan([("go to the kitchen", 0.55), ("go to the bedroom", 0.45)], x0).goal.id == L


def test_plan_log_prob_is_eq_28_assembled_term_by_term():
    """plan.log_prob = sum_e [log psi[i_{e-1}, i_e] - log sum_c phi_c(i_e) + w-hat_e + log sum_C phi_C(i_e)
    Mult(S_{s(e)} | W_C) pi_C] (Eq. 28, w-hat observed at each leg's end), with the first step's transition predicted
    from the start pose (sum_k p(k | x_0)
    psi[k, i_1]) and its w-hat the start leg's; every term recomputed here from the model's arrays and an
    independent A* search, on a model whose psi is not symmetric (so a transposed psi would not match)."""
    from scipy.stats import multivariate_normal

    from spcotmhp.metric.grid_search import shortest_paths, step_cost_map

    model = home_model()
    model.psi = np.array(
        [
            [0.30, 0.60, 0.05, 0.05],  # L -> M likely, M -> L less so
            [0.20, 0.30, 0.05, 0.45],
            [0.05, 0.05, 0.30, 0.60],
            [0.05, 0.15, 0.50, 0.30],
        ]
    )
    occ = model.map
    log_p = home_log_p(occ)
    pl = HierarchicalPlanner(model, log_p=log_p)
    start_cell = np.array([6, 5])  # in L (bedroom #1)
    x0 = world(occ, *start_cell)
    plan = pl.plan("go to the kitchen via the corridor", x0)

    # the node sequence (one candidate per place: a node is its place) and the stage pursued at each step
    crop = pl.graph.to_crop(occ.world_to_cell(plan.node_points))
    nodes = [int(np.flatnonzero((pl.graph.node_cell == c).all(axis=1))[0]) for c in crop]
    places = pl.graph.node_place[nodes].tolist()
    assert places.count(M) == 1 and places[-1] == K and places.index(M) < len(places) - 1
    stages = [0 if e <= places.index(M) else 1 for e in range(len(places))]
    bags = [1, 2]  # vocabulary index of "corridor", then "kitchen"

    centres = occ.cell_centres()
    cells = [start_cell] + [pl.graph.to_map(pl.graph.node_cell[n]) for n in nodes]

    def w_hat(a: np.ndarray, b: np.ndarray, place: int) -> float:
        # optimality observed at the leg's end (graph module docstring): the map term along the leg, the
        # destination's Gaussian at the end cell
        log_n = multivariate_normal(model.mu[place], model.Sigma[place]).logpdf(centres[b[0], b[1]])
        cost = step_cost_map(log_p, None, connectivity=8)
        return log_n - shortest_paths(cost, tuple(a), tuple(b), connectivity=8).cost

    def total(psi: np.ndarray) -> float:
        prior = (model.pi[:, None] * model.phi).sum(axis=0)
        density = np.array([multivariate_normal(model.mu[k], model.Sigma[k]).pdf(x0) for k in range(model.K)])
        posterior = density * prior / (density * prior).sum()
        out = 0.0
        for e, (i, s) in enumerate(zip(places, stages, strict=False)):
            transition = np.log(posterior @ psi[:, i]) if e == 0 else np.log(psi[places[e - 1], i])
            word = np.log(np.sum(model.phi[:, i] * model.W[:, bags[s]] * model.pi))
            out += transition - np.log(model.phi[:, i].sum()) + w_hat(cells[e], cells[e + 1], i) + word
        return out

    assert plan.log_prob == pytest.approx(total(model.psi), rel=1e-9, abs=1e-9)
    assert abs(total(model.psi.T) - plan.log_prob) > 0.1


def test_goal_option_bounds_are_lower_bounds_of_the_final_paths():
    # instances that cannot beat the shortest option found (the chosen one or a shorter one) get the octile bound
    # through their anchors, not a smoothed path; the bound must never exceed the path the planner would have
    # built for them
    import warnings

    from spcotmhp.datasets import load_bundled
    from spcotmhp.learning.supervised import fit_supervised
    from spcotmhp.planning.search import search
    from spcotmhp.planning.start import start_cell

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        model = fit_supervised(load_bundled("3LDK_06", lang="en"))
    pl = HierarchicalPlanner(model, cache=GRAPHS)
    rng = np.random.default_rng(3)
    free = np.argwhere(pl.graph.main)
    bounded = 0
    for c in free[rng.integers(len(free), size=40)]:
        x0 = model.map.cell_to_world(pl.graph.to_map(c))
        for text in ("go to the bedroom", "go to the bedroom via the kitchen"):
            p = pl.plan(text, x0)
            for o in p.goal_options:
                if o.exact:
                    continue
                bounded += 1
                chosen = next(q for q in p.goal_options if q.id == p.goal.id)
                assert chosen.exact and o.length_m > min(q.length_m for q in p.goal_options if q.exact)
                # the full path into that instance, as the planner would build it
                ins = p.instruction
                _, cell, _ = start_cell(model, pl.graph, x0)
                S = len(ins.stages)
                semantic, inst = pl.stage_instances(ins)
                result = search(pl._problem(pl.graph, pl.terms.place_posterior(x0), cell, semantic, inst, S))
                ks = np.flatnonzero(pl.graph.node_place == o.id)
                alt = result.ending_at(int(ks[np.argmax(result.terminal[ks])]))
                full = path_length(pl.metric_path(pl.graph, cell, alt)[0], model.map.resolution)
                assert o.length_m <= full + 1e-9
            assert ("closest of" in p.explanation) == (p.goal.id == min(p.goal_options, key=lambda q: q.length_m).id)
    assert bounded >= 10


def test_warm_up_plans_to_the_first_places_and_changes_no_later_plan(planner, monkeypatch):
    start = world(planner.model.map, 3, 12)
    before = planner.plan("go to the bedroom via the corridor", start)
    asked = []
    original = HierarchicalPlanner.plan

    def spy(self, instruction, *args, **kwargs):
        asked.append(instruction)
        return original(self, instruction, *args, **kwargs)

    monkeypatch.setattr(HierarchicalPlanner, "plan", spy)
    planner.warm_up()
    first = sorted({planner.names[k] for k in planner.graph.node_place[:2]})
    assert asked == [{"goal": name.split()} for name in first] and asked
    monkeypatch.undo()
    after = planner.plan("go to the bedroom via the corridor", start)
    assert (after.cells == before.cells).all() and after.explanation == before.explanation


@pytest.mark.parametrize("given, shown", [("m06", "str 'm06'"), (None, "NoneType"), (3, "int")])
def test_the_planner_takes_a_model(given, shown):
    """Audit item 13: HierarchicalPlanner('m06') raised AttributeError: 'str' object has no attribute 'map'."""
    from spcotmhp.errors import ModelError

    with pytest.raises(ModelError) as info:
        HierarchicalPlanner(given)
    assert str(info.value) == (
        f"HierarchicalPlanner takes a SpatialConceptModel, got a {shown}; load a model folder with "
        "spcotmhp.persistence.io.load_model(folder)"
    )


def test_two_names_that_no_place_carries_together_are_refused_with_inactive_places():
    """A learned model keeps inactive places (weak-limit truncation) whose labels carry every word; they name
    nothing, so "the kitchen bedroom" is an unknown place name, as on supervised parameters (audit item 2)."""
    base = home_model()
    K = base.K
    said = base.W.argmax(axis=1)  # each concept's word; the ghost place's concepts say every word equally
    column = 1.0 / np.bincount(said)[said] / len(set(said))
    ghost = dataclasses.replace(
        base,
        mu=np.vstack([base.mu, base.mu[:1]]),
        Sigma=np.concatenate([base.Sigma, base.Sigma[:1]]),
        psi=np.full((K + 1, K + 1), 1.0 / (K + 1)),
        phi=np.hstack([base.phi * (1.0 - column[:, None]), column[:, None]]),  # rows still sum to 1
        active_places=np.array([True] * K + [False]),
    )
    ghost_planner = HierarchicalPlanner(ghost, cache=GRAPHS)
    assert {"bedroom", "kitchen"} <= set(ghost_planner.names[K].split())  # the inactive label carries both
    start = world(ghost.map, 3, 3)
    for p in (ghost_planner, HierarchicalPlanner(base, cache=GRAPHS)):
        with pytest.raises(UnknownPlaceWord, match="no place is called 'kitchen bedroom'.*name one place"):
            p.plan("go to the kitchen bedroom", start)
        assert p.plan("go to the kitchen", start).explanation.split(",")[0].endswith("-> kitchen")


def test_warm_up_and_spoken_names_skip_a_place_that_names_nothing():
    """A place whose events carry no name above chance is labelled "place k" (planning/vocabulary.py); no
    instruction names it, so warming up (and ``spcotmhp warmup``) plans only to labels made of place words."""
    planner = HierarchicalPlanner(home_model(), cache=GRAPHS)
    first = int(planner.graph.node_place[0])
    planner.names = list(planner.names)
    planner.names[first] = f"place {first}"
    spoken = planner.spoken_names(range(len(planner.names)))
    assert f"place {first}" not in spoken and len(spoken) == len(planner.names) - 1
    planner.warm_up()  # no error: the unnamed place is skipped
