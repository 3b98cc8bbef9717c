"""Names as the robot shows them can be said back, and a word several names share names them all (issue 34): on
seeded generated homes (three bedrooms, a west and an east corridor), "go to bedroom 2" / "bedroom number two" /
"bedroom #2" ends at the place the plan calls "bedroom #2"; "go to the corridor" ends at the closer corridor and
says so; a number no place of that name has is refused naming the places there are."""

from __future__ import annotations

import warnings

import pytest

from spcotmhp.datasets.synthetic_battery import battery_home
from spcotmhp.errors import UnknownPlaceWord
from spcotmhp.learning.supervised import fit_supervised
from spcotmhp.planning.planner import HierarchicalPlanner

WORDS = {1: "one", 2: "two", 3: "three"}


@pytest.fixture(scope="module", params=[0, 5, 11])
def planner(request) -> HierarchicalPlanner:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return HierarchicalPlanner(fit_supervised(battery_home(request.param)))


def _start(planner: HierarchicalPlanner) -> tuple[float, float]:
    k = planner.names.index("entrance")
    return float(planner.model.mu[k, 0]), float(planner.model.mu[k, 1])


def test_every_shown_label_can_be_said_back(planner):
    bedrooms = [k for k, n in enumerate(planner.names) if n == "bedroom" and planner.model.active_places[k]]
    assert len(bedrooms) == 3
    for k in bedrooms:
        label = planner.instance_label(k)  # "bedroom #2"
        n = int(label.rsplit("#", 1)[1])
        for said in (f"go to bedroom {n}", f"go to {label}", f"go to bedroom number {WORDS[n]}", f"bedroom {WORDS[n]}"):
            plan = planner.plan(said, _start(planner))
            assert plan.goal.id == k and plan.goal.label == label, (said, plan.explanation)


def test_a_number_no_place_has_is_refused_naming_the_places(planner):
    with pytest.raises(UnknownPlaceWord, match="bedroom #1, bedroom #2, bedroom #3"):
        planner.plan("go to bedroom 4", _start(planner))


@pytest.mark.parametrize("said", ["go to the corridor", "go to a corridor", "go to the nearest corridor"])
def test_a_word_two_names_share_goes_to_the_closer_and_says_so(planner, said):
    plan = planner.plan(said, _start(planner))
    lengths = {
        name: planner.plan(f"go to the {name}", _start(planner)).length_m for name in ("west corridor", "east corridor")
    }
    assert plan.goal.name in lengths
    assert plan.length_m <= min(lengths.values()) + 1e-6
    assert "closest of 2 corridors" in plan.explanation, plan.explanation
