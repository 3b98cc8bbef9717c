"""The move of the research variants to spcotmhp/experimental/ (issue 27) changed no result: the default batch
fit, the GMM fit, an online run, the split-merge and off-name fits and every run-selection criterion give the
places, concepts, log joints and parameters that main's code gave before the move, for the same seeds.

tests/data/fits_before_experimental.json was written by main at 87153de (the learner with the variants as
options); the fits here go through the new entry points.  Assignments must be equal, numbers equal to 1e-12
relative (the same arithmetic in the same order; the tolerance only absorbs a different machine's last bit)."""

from __future__ import annotations

import json
import warnings
from pathlib import Path

import numpy as np
import pytest

from spcotmhp.experimental import research_learner
from spcotmhp.experimental.selection import CRITERIA, scores
from spcotmhp.learning.gibbs import SpCoTMHP
from spcotmhp.learning.model import Hyperparameters
from spcotmhp.learning.online import OnlineSpCoTMHP
from spcotmhp.learning.selection import MultiRunSelector
from tests.helpers.learning import planted_dataset

BEFORE = json.loads((Path(__file__).parents[1] / "data" / "fits_before_experimental.json").read_text())


@pytest.fixture(scope="module")
def data():
    return planted_dataset(40, seed=5)


def fingerprint(est, trace: bool = True) -> dict:
    """What the file holds of a fit: its final assignments, five sums over its parameters, its log joint trace."""
    m = est.model_
    out = {
        "places": est.places_.tolist(),
        "concepts": est.concepts_.tolist(),
        "sums": [
            float(m.mu.sum()),
            float(m.Sigma.sum()),
            float(m.psi @ np.arange(m.K) @ np.arange(m.K)),
            float((m.W * np.arange(m.W.shape[1])).sum()),
            float((m.phi * np.arange(m.K)).sum()),
        ],
    }
    if trace:
        out["trace"] = [float(v) for v in est.log_joint_trace_]
    return out


def assert_same(got: dict, want: dict) -> None:
    assert got["places"] == want["places"] and got["concepts"] == want["concepts"]
    for key in ("sums", "trace"):
        if key in want:
            np.testing.assert_allclose(got[key], want[key], rtol=1e-12, atol=0)


def _fit(data, **params):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return research_learner(iterations=5, seed=3, **params).fit(data)


def test_default_and_gmm_fits_are_unchanged(data):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        assert_same(fingerprint(SpCoTMHP(iterations=5, seed=3).fit(data)), BEFORE["default"])
        assert_same(fingerprint(SpCoTMHP(iterations=5, seed=3, transitions="none").fit(data)), BEFORE["gmm"])


def test_an_online_run_is_unchanged(data):
    events = [(float(x), float(y), list(t)) for (x, y), t in zip(data.positions, data.tokens, strict=True)]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        online = OnlineSpCoTMHP(seed=1).partial_fit(events[:30])
    assert_same(fingerprint(online, trace=False), BEFORE["online"])


def test_the_variants_give_their_results_from_their_new_home(data):
    assert_same(fingerprint(_fit(data, split_merge=True)), BEFORE["split_merge"])
    assert_same(fingerprint(_fit(data, hyper=Hyperparameters(off_name=1.0))), BEFORE["off_name"])


def test_every_criterion_scores_the_runs_as_before(data):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        sel = MultiRunSelector(SpCoTMHP(iterations=4, seed=2), runs=2).fit(data)
    assert list(BEFORE["criteria"]) == list(CRITERIA[1:])
    for name, want in BEFORE["criteria"].items():
        np.testing.assert_allclose(scores(sel, name), want, rtol=1e-12, atol=0)
