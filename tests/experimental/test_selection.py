"""The research run-selection criteria (experimental/selection.py) through MultiRunSelector's RunScore hook."""

from __future__ import annotations

import numpy as np
import pytest

from spcotmhp.errors import ModelError
from spcotmhp.experimental import fit_runs
from spcotmhp.experimental.run_scores import switch_mode_log_joint
from spcotmhp.experimental.selection import CRITERIA, SCORES, NamedScore, criterion, scores
from spcotmhp.learning import selection
from spcotmhp.learning.selection import MultiRunSelector
from tests.helpers.learning import planted_dataset


@pytest.fixture(scope="module")
def data():
    return planted_dataset(E=80)


def test_the_switch_mode_criterion_keeps_the_run_of_highest_switch_mode_joint(data):
    sel = fit_runs(data, runs=3, iterations=10, criterion="log_joint_switch_mode", connectivity="hmm")
    got = [switch_mode_log_joint(e) for e in sel.estimators_]
    assert sel.criterion_ == "log_joint_switch_mode" and sel.best_index_ == int(np.argmax(got))
    assert all(s >= e.log_joint_ for s, e in zip(got, sel.estimators_, strict=True))


@pytest.mark.parametrize("name", ["log_joint_switch_marginal", "log_joint_switch_plugin", "log_joint_tail_mean"])
def test_each_switch_criterion_keeps_the_run_of_highest_score(data, name):
    sel = fit_runs(data, runs=3, iterations=10, criterion=name, connectivity="hmm")
    want = [SCORES[name](e) for e in sel.estimators_]
    assert scores(sel, name) == want
    assert sel.criterion_ == name and sel.best_index_ == int(np.argmax(want))
    assert sel.model_.info["criterion"] == name


def test_names_route_to_the_core_or_to_a_run_score():
    assert CRITERIA[: len(selection.CRITERIA)] == selection.CRITERIA and set(SCORES) <= set(CRITERIA)
    assert criterion("log_joint") == "log_joint"
    assert criterion("held_out_words") == NamedScore("held_out_words", SCORES["held_out_words"])
    with pytest.raises(ModelError, match=r"criterion must be one of \('auto', .*'held_out_words'\), got 'vibes'"):
        criterion("vibes")


def test_the_core_refuses_a_research_name_and_a_nameless_score(data):
    """The core knows its own criteria only: a research criterion's name alone is refused (one line)."""
    with pytest.raises(ModelError, match=r"criterion must be one of \('auto', 'mutual_information', 'log_joint'\)"):
        MultiRunSelector(runs=1, criterion="log_joint_switch_mode").fit(data)
    with pytest.raises(ModelError, match="or a named run score"):
        MultiRunSelector(runs=1, criterion=len).fit(data)  # type: ignore[arg-type]
