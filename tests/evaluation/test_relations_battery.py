"""The relation battery (issue 23): on seeded homes with three bedrooms, every relation request ends at the
instance the stated rule names, or is refused where the rule names none; the oracle itself is checked by hand."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

from spcotmhp.datasets.synthetic_battery import battery_home
from spcotmhp.evaluation.relations_battery import _contacts_by_loop, _grid_graph, _path_metres, evaluate_relations
from spcotmhp.planning.relations import territory_contacts


@pytest.mark.parametrize("seed", [0, 7, 23])
def test_relations_end_where_the_rule_says(seed):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        result = evaluate_relations(battery_home(seed), seed, per_kind=3)
    assert result.wrong == []
    assert sum(n for (_, verdict), n in result.counts.items() if verdict == "refused") == 0
    assert sum(n for (_, verdict), n in result.counts.items() if verdict == "right") >= 5  # not vacuous


def test_oracle_paths_by_hand():
    cost = np.array([[1.0, 1.0, 1.0], [np.inf, np.inf, 1.0], [1.0, 1.0, 1.0]])
    from scipy.sparse.csgraph import dijkstra

    _, pred = dijkstra(_grid_graph(cost), indices=0, return_predecessors=True)
    # from (0, 0) to (2, 0): right, right-down diagonal... the wall forces (0,0)->(0,1)->(1,2)->(2,1)->(2,0)
    assert _path_metres(pred, 0, 6, 3) == pytest.approx(2 + 2 * np.sqrt(2))


def test_contacts_agree_with_the_planners():
    rng = np.random.default_rng(3)
    for _ in range(20):
        territory = rng.integers(-1, 4, size=(7, 9))
        assert (territory_contacts(territory, 4) == _contacts_by_loop(territory, 4)).all()
