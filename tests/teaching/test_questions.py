"""Questions where the map is unsure (spcotmhp/teaching/questions.py): the measure, the order, and an answer."""

from __future__ import annotations

import dataclasses
import math
import warnings

import numpy as np
import pytest

from spcotmhp.datasets import load_bundled
from spcotmhp.learning.supervised import fit_supervised
from spcotmhp.teaching.questions import SPACING_M, questions
from spcotmhp.teaching.teach import teach


@pytest.fixture(scope="module")
def blurred():
    """3LDK_06 (supervised) with the kitchen's Gaussian moved onto the dining room's: at the dining room the model
    cannot tell the two names apart (p = 1/2 each, log 2 nats), everywhere else one name is near certain."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        model = fit_supervised(load_bundled("3LDK_06"))
    names = model.place_names()
    kitchen, dining = names.index("kitchen"), names.index("dining")
    mu, Sigma = model.mu.copy(), model.Sigma.copy()
    mu[kitchen], Sigma[kitchen] = mu[dining], Sigma[dining]
    return dataclasses.replace(model, mu=mu, Sigma=Sigma), dining


def brute_entropy(model, xy) -> float:
    """H[p(n | x)] by loops: p(k | x) of Eq. 3, p(w | k) = sum_l p(l | k) W_l(w), a name's p(n | k) the geometric
    mean of its words' (one word here), normalised over the active places' names."""
    from spcotmhp.planning.vocabulary import place_labels, place_vocabulary

    words = place_vocabulary(model)
    labels = place_labels(model, words)
    act = [k for k in range(model.K) if model.active_places[k]]
    names = sorted({labels[k] for k in act})
    dens = {k: math.exp(float(model.log_place_density(np.array(xy))[k] + model.log_place_prior()[k])) for k in act}
    total = sum(dens.values())
    p_l_k = np.exp(model.log_concept_given_place())  # (L, K)
    p = dict.fromkeys(names, 0.0)
    for k in act:
        said = {n: sum(p_l_k[l, k] * model.W[l, model.word_index[n]] for l in range(model.L)) for n in names}
        z = sum(said.values())
        for n in names:
            p[n] += dens[k] / total * said[n] / z
    z = sum(p.values())
    return -sum(v / z * math.log(v / z) for v in p.values() if v > 0)


def test_the_spot_where_two_names_meet_is_asked_first(blurred):
    model, dining = blurred
    asked = questions(model, 5)
    first = asked[0]
    assert np.hypot(first["x"] - model.mu[dining][0], first["y"] - model.mu[dining][1]) < 0.5
    assert sorted(first["candidates"]) == ["dining", "kitchen"]
    assert first["information"] == pytest.approx(brute_entropy(model, (first["x"], first["y"])), abs=1e-4)
    assert first["information"] > math.log(2)  # at least the two names' even split
    assert first["ask"] == "What is this place called?" and "two places meet here" in first["why"]
    info = [q["information"] for q in asked]
    assert info == sorted(info, reverse=True)
    for i, a in enumerate(asked):
        for b in asked[i + 1 :]:
            assert np.hypot(a["x"] - b["x"], a["y"] - b["y"]) >= SPACING_M
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        plain = questions(fit_supervised(load_bundled("3LDK_06")), 5)
    assert first["information"] > max(q["information"] for q in plain)  # the planted doubt is the largest


def test_an_answer_is_a_teach_and_moves_the_name_toward_it(blurred):
    """An answer is an ordinary teach at the asked spot: the model updates at once and the name it expects there
    moves toward the answer (one teach against the place's 15 events moves it a little: p(dining) 0.45 -> 0.47)."""
    from spcotmhp.teaching.questions import name_distribution

    model, _ = blurred
    first = questions(model, 1)[0]
    xy = np.array([[first["x"], first["y"]]])
    taught = teach(model, [{"x": first["x"], "y": first["y"], "utterance": "this is the dining"}]).model
    names = ["dining", "kitchen"]
    before = name_distribution(model, xy, names, names)[0]
    after = name_distribution(taught, xy, names, names)[0]
    assert after[0] > before[0] and after[1] < before[1]
