"""How often psi changes a plan (evaluation/psi_effect.py): the uniform psi, a hand-made home where only the
paper's graph follows psi, and the count on a generated home."""

import numpy as np

from spcotmhp.datasets.synthetic_battery import battery_home
from spcotmhp.evaluation.context import VARIANTS
from spcotmhp.evaluation.psi_effect import markdown, psi_effect, uniform_psi
from spcotmhp.planning.places import connected_places
from spcotmhp.planning.planner import HierarchicalPlanner
from tests.helpers.planning import home_log_p, home_model


def test_uniform_psi_is_uniform_over_active_places_and_connects_them_all():
    model = home_model()
    model.active_places = np.array([True, True, False, True])
    flat = uniform_psi(model)
    np.testing.assert_allclose(flat.psi, np.tile([1 / 3, 1 / 3, 0.0, 1 / 3], (4, 1)))
    assert flat.info["psi_from"] == "uniform" and model.psi is not flat.psi
    active = np.flatnonzero(model.active_places)
    assert connected_places(flat)[np.ix_(active, active)].all()


def test_psi_decides_the_papers_route_not_ours():
    """corridor -> kitchen: the kitchen opens only onto the right bedroom. On the paper's graph (psi's edges
    corridor-bedroom R, kitchen-bedroom R) the route runs through bedroom R's candidate point; with a uniform psi
    every place is connected and the leg goes straight to the kitchen. Ours steps between any two candidates
    either way, and psi's factor (a few nats) does not outweigh the longer leg."""
    model = home_model()
    log_p = home_log_p(model.map)
    start = tuple(model.mu[1])  # the corridor's mean
    cells = {}
    for variant in ("ours", "paper"):
        for name, m in (("psi", model), ("uniform", uniform_psi(model))):
            plan = HierarchicalPlanner(m, log_p=log_p, **VARIANTS[variant]).plan("go to the kitchen", start)
            cells[variant, name] = plan.cells
    assert np.array_equal(cells["ours", "psi"], cells["ours", "uniform"])
    assert not np.array_equal(cells["paper", "psi"], cells["paper", "uniform"])
    r_node = model.map.world_to_cell(model.mu[3])
    assert (cells["paper", "psi"] == r_node).all(axis=1).any()  # through the bedroom's candidate point
    assert not (cells["paper", "uniform"] == r_node).all(axis=1).any()
    assert np.array_equal(cells["paper", "psi"][-1], cells["paper", "uniform"][-1])  # the same end


def test_psi_effect_counts_on_a_generated_home():
    rows = psi_effect(battery_home(0), "supervised", max_advanced=10)
    assert [(r.variant, r.params, r.psi_from) for r in rows] == [
        ("ours", "supervised", "adjacency"),
        ("paper", "supervised", "adjacency"),
    ]
    assert rows[0].plans == rows[1].plans > 10
    assert all(0 <= r.end_elsewhere <= r.differ <= r.plans for r in rows)
    assert rows[1].differ > rows[0].differ  # the paper's graph follows psi
    table = markdown(rows)
    assert "| supervised | SpCoTMHP as in the paper | adjacency | 1 |" in table
