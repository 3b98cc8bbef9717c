"""The building oracle against a direct computation: routes on the start's floor are its geodesics; routes to
another floor are the best over the connectors of (geodesic to a stop + cost_m + geodesic from the stop there),
found here by enumerating connector sequences of a two-floor building by hand."""

from __future__ import annotations

import math
import warnings

import numpy as np

from spcotmhp.building.synthetic import example_building
from spcotmhp.evaluation.building_battery import BuildingOracle


def test_routes_by_hand():
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        b = example_building()
    oracle = BuildingOracle(b)
    xy = b.floors[1].map.cell_to_world(np.array(oracle.places[1][0].cell))
    routes = oracle.routes(1, xy)
    g1, g2 = oracle.geometry[1], oracle.geometry[2]
    here = g1.from_cell(oracle.cell(1, xy))
    for g, t in enumerate(g1.targets):
        assert routes[(1, g)] == (math.inf if t[0] < 0 else float(here[t[0], t[1]]))
    # two floors, each connector a pair of stops: a route to floor 2 takes exactly one ride
    via = []
    for c in b.spec.connectors:
        s1 = next(s for s in c.stops if s.floor == 1)
        s2 = next(s for s in c.stops if s.floor == 2)
        cell1, cell2 = oracle.cell(1, (s1.x, s1.y)), oracle.cell(2, (s2.x, s2.y))
        via.append((float(here[cell1]) + c.cost_m, g2.from_cell(cell2)))
    for g, t in enumerate(g2.targets):
        expected = min(d + float(field[t[0], t[1]]) for d, field in via)
        assert routes[(2, g)] == expected and math.isfinite(expected)
    assert oracle.named("kitchen") == [(1, 2), (2, 3)]
    assert oracle.ends_in(1, xy) and 0 in oracle.ends_in(1, xy)
