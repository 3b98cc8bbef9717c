"""Teaching at run time (issue 15, ``spcotmhp.learning.teach``): what one teach means, bad teaching refused with
the model unchanged, new places' labels, the language of an utterance."""

from __future__ import annotations

import numpy as np
import pytest

from spcotmhp.errors import TeachingError, UnknownPlaceWord
from spcotmhp.learning.io import load_model
from spcotmhp.learning.teach import planner_for, teach
from spcotmhp.planning.planner import HierarchicalPlanner
from tests.helpers.server import start_near, supervised_model_dir

STUDY = (5.5, -4.0)  # a free spot of 3LDK_06 in a bedroom's territory (the audit's)


@pytest.fixture(scope="module")
def model6(tmp_path_factory):
    """The supervised fit of 3LDK_06 (no learner state: teaching starts from pseudo-counts)."""
    return load_model(supervised_model_dir("3LDK_06", tmp_path_factory.mktemp("teach") / "m06s"))


def _teach(model, utterance: str, times: int = 1, at=STUDY):
    for _ in range(times):
        model = teach(model, [{"x": at[0], "y": at[1], "utterance": utterance}]).model
    return model


def test_one_teach_never_plans_somewhere_else(model6):
    """One teach of "study" made it a place word that no place's label carried, and "go to the study" planned
    to the start's place (entrance -> entrance, 0.1 m; audit). Now it is refused saying it was taught once; after
    three teaches it plans to the taught spot, and the old names keep planning where they did."""
    start = start_near(model6)
    kitchen = HierarchicalPlanner(model6).plan("go to the kitchen", start).path[-1]
    once = _teach(model6, "this is the study")
    planner, _ = planner_for(once)
    assert "study" not in planner.place_words
    with pytest.raises(UnknownPlaceWord, match="'study' was taught once"):
        planner.plan("go to the study", start)
    thrice = _teach(once, "this is the study", 2)
    planner, _ = planner_for(thrice)
    assert np.linalg.norm(planner.plan("go to the study", start).path[-1] - np.array(STUDY)) < 1.5
    assert np.linalg.norm(planner.plan("go to the kitchen", start).path[-1] - kitchen) < 0.5
    assert thrice.info["taught"]["study"] == 3


def test_a_position_in_unknown_space_is_refused_and_changes_nothing(model6):
    """(-6.11, -7.40) is an unknown cell of 3LDK_06 (a plan start there is refused); teaching "this is the attic"
    there was accepted and made a new place (audit L2)."""
    occ = model6.map
    x, y = -6.11, -7.40
    assert occ.unknown[tuple(occ.world_to_cell(np.array([x, y])))]
    before = {k: np.copy(v) for k, v in vars(model6).items() if isinstance(v, np.ndarray)}
    with pytest.raises(TeachingError, match="unknown space"):
        teach(model6, [{"x": x, "y": y, "utterance": "this is the attic"}])
    assert all(np.array_equal(before[k], v) for k, v in vars(model6).items() if isinstance(v, np.ndarray))
    assert "taught" not in model6.info


@pytest.mark.parametrize(
    ("lang", "utterance", "message"),
    [
        ("en", "ここは書斎です", "is Japanese but the model's words are English"),
        ("ja", "this is the study", "is English"),
    ],
)
def test_an_utterance_in_another_language_is_refused(lang, utterance, message, tmp_path):
    """On an English model, "ここは書斎です" became one place word, "ここは書斎です" (audit L3); and English on a
    Japanese model likewise. Now a TeachingError naming both languages, the model unchanged."""
    model = load_model(supervised_model_dir("3LDK_06", tmp_path / "m", lang=lang))
    with pytest.raises(TeachingError, match=message):
        teach(model, [{"x": STUDY[0], "y": STUDY[1], "utterance": utterance}])
    assert "taught" not in model.info
    same = {"en": "this is the study", "ja": "ここ は 書斎 です"}[lang]
    assert ("study" if lang == "en" else "書斎") in teach(
        model, [{"x": STUDY[0], "y": STUDY[1], "utterance": same}]
    ).model.vocabulary


@pytest.fixture(scope="module")
def model6ja(tmp_path_factory):
    """The supervised fit of 3LDK_06 with its Japanese words."""
    return load_model(supervised_model_dir("3LDK_06", tmp_path_factory.mktemp("teachja") / "m06ja", lang="ja"))


def test_japanese_teaching_works_as_typed(model6ja):
    """Issue 23: "ここは書斎です" typed without spaces is the words ここ, は, 書斎, です (janome), as
    "ここ は 書斎 です" is; three teaches make 書斎 a place word and plan to it; before, the sentence was one word
    no instruction could say."""
    spaced = teach(model6ja, [{"x": STUDY[0], "y": STUDY[1], "utterance": "ここ は 書斎 です"}]).model
    unspaced = teach(model6ja, [{"x": STUDY[0], "y": STUDY[1], "utterance": "ここは書斎です"}]).model
    assert "書斎" in unspaced.vocabulary and "ここは書斎です" not in unspaced.vocabulary
    assert list(unspaced.vocabulary) == list(spaced.vocabulary)
    taught = _teach(model6ja, "ここは書斎です", 3)
    planner, _ = planner_for(taught)
    assert "書斎" in planner.place_words and not {"は", "ここ", "です"} & set(planner.place_words)
    end = planner.plan("書斎に行って", start_near(model6ja, "玄関")).path[-1]
    assert np.linalg.norm(end - np.array(STUDY)) < 1.5
