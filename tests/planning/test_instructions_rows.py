"""Instructions that once sent the robot somewhere the user did not ask for (unknown words dropped, negations
read as goals, alternatives and spatial relations guessed), planned on the supervised 3LDK_06 model in English
and Japanese: each is now either planned as meant or refused with a message saying why."""

from __future__ import annotations

import subprocess
import sys
import warnings
from pathlib import Path

import pytest

from spcotmhp.datasets.bundled import load_bundled
from spcotmhp.errors import InstructionError, PlanningError
from spcotmhp.learning.supervised import fit_supervised
from spcotmhp.persistence.io import save_model
from spcotmhp.planning.planner import HierarchicalPlanner

EXE = str(Path(sys.executable).with_name("spcotmhp"))


def _model(lang: str):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        dataset = load_bundled("3LDK_06", lang=lang)
    return fit_supervised(dataset), dataset.place_names


@pytest.fixture(scope="module")
def planners():
    out = {}
    for lang in ("en", "ja"):
        model, names = _model(lang)
        out[lang] = (HierarchicalPlanner(model), names)
    return out


START = (-3.9, -3.5)  # the entrance


@pytest.mark.parametrize(
    "lang, text, message",
    [
        (
            "en",
            "go to the garage via the kitchen",
            (
                "'garage' (after 'to') is not a known place word; known place "
                "words: bath, bedroom, corridor, dining, entrance, kitchen"
            ),
        ),
        ("en", "go to the kitchen and the attic", "'attic' (after 'and') is not a known place word"),
        ("en", "go to the attic, then the kitchen", "'attic' (after 'to') is not a known place word"),
        (
            "en",
            "go to the bedroom next to the kitchen",  # understood, and answered by the map: no bedroom touches it
            "none of bedroom #1, bedroom #2, bedroom #3 is next to the kitchen",
        ),
        (
            "en",
            "go to the bedroom via the kitchen or the toilet",
            ("'or' leaves the choice of a place open (kitchen or toilet)"),
        ),
        (
            "ja",
            "ガレージへ行ってキッチンを通って",
            ("'ガレージ' (before 'へ行って') is not a known place word; known place words: キッチン"),
        ),
    ],
)
def test_refused(planners, lang, text, message):
    planner, _ = planners[lang]
    with pytest.raises(InstructionError) as info:
        planner.plan(text, START)
    assert message in str(info.value)


@pytest.mark.parametrize(
    "lang, text, goal, avoided",
    [
        ("en", "don't go to the kitchen, go to the bedroom", "bedroom", "kitchen"),
        ("en", "go to the bedroom, never pass the kitchen", "bedroom", "kitchen"),
        ("en", "go to the bedroom without going through the living", "bedroom", "living"),
        ("ja", "キッチンに行かないで寝室へ行って", "寝室", "キッチン"),
        ("ja", "寝室へ行って、キッチンは通らないで", "寝室", "キッチン"),
    ],
)
def test_negations_avoid_the_place(planners, lang, text, goal, avoided):
    planner, names = planners[lang]
    plan = planner.plan(text, START)
    assert plan.goal.name == goal
    assert [dict(a.words) for a in plan.instruction.avoid] == [{avoided: 1}]
    k = names.index(avoided)
    crop = planner.graph.to_crop(plan.cells)
    assert not (planner.graph.territory[crop[:, 0], crop[:, 1]] == k).any()
    assert avoided not in [p.name for p in plan.places]


def test_avoiding_the_only_way_is_refused(planners):
    # 3LDK_06: from the entrance every bedroom lies behind the dining room
    planner, _ = planners["en"]
    with pytest.raises(
        PlanningError,
        match="no free path from \\(-3.90, -3.50\\) reaches a place named 'bedroom' "
        "\\(goal\\) without entering the places to avoid",
    ):
        planner.plan("go to the bedroom, don't go through the dining", START)


@pytest.mark.parametrize(
    "lang, text, goal, not_goal",
    [
        ("en", "go to the bedroom instead of the kitchen", "bedroom", "kitchen"),
        ("ja", "キッチンじゃなくて寝室へ行って", "寝室", "キッチン"),
    ],
)
def test_instead_of_is_not_the_goal(planners, lang, text, goal, not_goal):
    planner, _ = planners[lang]
    plan = planner.plan(text, START)
    assert plan.goal.name == goal
    assert plan.instruction.avoid == ()
    assert [dict(q.words) for q in plan.instruction.not_goal] == [{not_goal: 1}]
    assert plan.explanation.endswith(f", instead of {not_goal}")
    assert plan.to_dict()["instruction"]["not_goal"] == [{not_goal: 1}]


def test_instead_of_the_goal_itself_is_a_planning_error(planners):
    planner, _ = planners["en"]
    with pytest.raises(
        PlanningError,
        match="every place named 'bedroom' is one the instruction says not to end in \\('bedroom'\\)",
    ):
        planner.plan({"goal": ["bedroom"], "not_goal": [["bedroom"]]}, START)


def test_cli_refuses_with_one_line(tmp_path):
    model, _ = _model("en")
    folder = save_model(model, tmp_path / "m")
    out = subprocess.run(
        [EXE, "plan", str(folder), "go to the garage via the kitchen", "--start", *map(str, START)],
        capture_output=True,
        text=True,
        timeout=120,
        check=False,
    )
    assert out.returncode == 2 and out.stdout == ""
    assert out.stderr.startswith("error: 'garage' (after 'to') is not a known place word; known place words: ")
    assert len(out.stderr.strip().splitlines()) == 1
