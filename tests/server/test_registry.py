"""spcotmhp.server.registry: a served model is built warm (its planner has planned once before any request)."""

from __future__ import annotations

from spcotmhp.planning.planner import HierarchicalPlanner
from spcotmhp.server.registry import ServedModel
from tests.helpers.planning import home_model


def test_a_served_model_warms_its_planner_up_before_serving(monkeypatch):
    warmed: list[HierarchicalPlanner] = []
    monkeypatch.setattr(HierarchicalPlanner, "warm_up", lambda self: warmed.append(self))
    served = ServedModel.build("home", home_model(), "(test)")
    assert warmed == [served.planner]
