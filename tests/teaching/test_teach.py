"""Teaching at run time (issue 15, ``spcotmhp.teaching.teach``): what one teach means, bad teaching refused with
the model unchanged, new places' labels, the language of an utterance."""

from __future__ import annotations

import numpy as np
import pytest

from spcotmhp.errors import NotANaming, TeachingError
from spcotmhp.persistence.io import load_model
from spcotmhp.planning.planner import HierarchicalPlanner
from spcotmhp.teaching.teach import planner_for, teach
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


FAR = (3.0, 3.0)  # a free spot of 3LDK_06 outside every place's 2-sigma ellipse (Mahalanobis^2 6.7 at the nearest)


def test_one_teach_far_from_every_place_makes_a_plannable_place(model6):
    """Issue 24: "this is the study" said once was refused when planning ("'study' was taught once but names no
    place yet"). Taught once where the model prefers a new place to every existing one (teach.py's rule), it is a
    new place labelled 'study', the reply says so, and "go to the study" ends within 1 m of the spot; the old names
    plan where they did."""
    start = start_near(model6)
    kitchen = HierarchicalPlanner(model6).plan("go to the kitchen", start).path[-1]
    taught = teach(model6, [{"x": FAR[0], "y": FAR[1], "utterance": "this is the study"}])
    reply = taught.summary()
    assert (reply["outcome"], reply["named"], reply["new_place"], reply["label"]) == ("new place", True, True, "study")
    assert "is a new place" in reply["message"] and reply["name"] == "study"
    planner, _ = planner_for(taught.model)
    assert "study" in planner.place_words
    assert np.linalg.norm(planner.plan("go to the study", start).path[-1] - np.array(FAR)) <= 1.0
    assert np.linalg.norm(planner.plan("go to the kitchen", start).path[-1] - kitchen) < 0.5
    assert taught.model.info["taught"] == {"study": 1}


def test_one_teach_inside_a_place_says_what_happened(model6):
    """Taught once inside a bedroom (its 15 events), "study" is a place of its own: the model's joint prefers it to
    a second name in the bedroom (Eq. 9's rescaling charges every event of a place that says two names), and the
    reply says so; "go to the study" ends within 1 m of the spot (its territory is seeded at its anchor, the cell
    nearest its mean, although under the bedroom's Gaussian the bedroom is more probable there; it ended at the rim
    of its Gaussian 3.3 m away before). Before, one teach was refused and it took three. Teaching a place's own
    name there joins it, and the reply says it names it."""
    start = start_near(model6)
    once = teach(model6, [{"x": STUDY[0], "y": STUDY[1], "utterance": "this is the study"}])
    assert (once.summary()["outcome"], once.summary()["label"]) == ("new place", "study")
    planner, _ = planner_for(once.model)
    plan = planner.plan("go to the study", start)
    assert plan.places[-1].label == "study"
    assert np.linalg.norm(plan.path[-1] - np.array(STUDY)) <= 1.0
    again = teach(once.model, [{"x": STUDY[0], "y": STUDY[1], "utterance": "this is the bedroom"}]).summary()
    assert (again["outcome"], again["named"], again["label"]) == ("joined place", True, "bedroom")
    assert "is one of its names" in again["message"]


@pytest.mark.parametrize("utterance", ["hello", "is this the kitchen?", "this isn't the study", "go to the kitchen"])
def test_an_utterance_that_names_nothing_is_refused(model6, utterance):
    """These were learned as place words ("hello" became a place's name); now NotANaming, nothing learned."""
    before = {k: np.copy(v) for k, v in vars(model6).items() if isinstance(v, np.ndarray)}
    with pytest.raises(NotANaming):
        teach(model6, [{"x": FAR[0], "y": FAR[1], "utterance": utterance}])
    assert all(np.array_equal(before[k], v) for k, v in vars(model6).items() if isinstance(v, np.ndarray))


def test_a_naming_event_survives_later_teaches_and_a_saved_folder(model6, tmp_path):
    """The naming flag is kept in the learner state (learner.npz ``named``): a later teach elsewhere revisits the
    first event (fixed-lag) with the same rule, so the new place stays; loading the folder keeps it too."""
    from spcotmhp.persistence.io import save_model

    first = teach(model6, [{"x": FAR[0], "y": FAR[1], "utterance": "this is the study"}]).model
    folder = save_model(first, tmp_path / "m")
    again = load_model(folder)
    assert again.learner is not None and again.learner["arrays"]["named"].tolist() == [True]
    second = teach(again, [{"x": STUDY[0], "y": STUDY[1], "utterance": "this is the library"}]).model
    planner, _ = planner_for(second)
    assert np.linalg.norm(planner.plan("go to the study", start_near(model6)).path[-1] - np.array(FAR)) <= 1.0


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
