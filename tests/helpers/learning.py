"""A dataset drawn from the SpCoTMHP generative model with known parameters (shared by the learning tests)."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np

from spcotmhp.datasets.dataset import Dataset
from spcotmhp.learning.concepts import _concept_sweep, _sweep_with
from spcotmhp.metric.maps import OccupancyMap
from spcotmhp.persistence.folder import MANIFEST, manifest_of

PLANTED_MU = np.array([[0.0, 0.0], [6.0, 0.0], [6.0, 6.0], [0.0, 6.0]])
PLANTED_SIGMA = np.array(
    [
        [[0.30, 0.10], [0.10, 0.20]],
        [[0.15, 0.0], [0.0, 0.40]],
        [[0.25, -0.08], [-0.08, 0.25]],
        [[0.40, 0.0], [0.0, 0.15]],
    ]
)
# a ring 0 - 1 - 2 - 3 - 0, sticky; symmetric, so reverse replay does not bias it
PLANTED_PSI = np.array([[0.6, 0.2, 0.0, 0.2], [0.2, 0.6, 0.2, 0.0], [0.0, 0.2, 0.6, 0.2], [0.2, 0.0, 0.2, 0.6]])
NAMES = ["kitchen", "bedroom", "bath", "toilet"]
CONCEPT_OF_PLACE = np.array([0, 1, 2, 3])


def planted_dataset(E: int = 300, seed: int = 7) -> Dataset:
    """Events drawn from the generative model: i_e ~ psi[i_{e-1}], x_e ~ N(mu, Sigma), C_e from phi (here a
    deterministic place -> concept map), 3 tokens from W_C (the name with p 0.5, function words otherwise)."""
    rng = np.random.default_rng(seed)
    places = [0]
    for _ in range(E - 1):
        places.append(int(rng.choice(4, p=PLANTED_PSI[places[-1]])))
    places = np.array(places)
    X = np.array([rng.multivariate_normal(PLANTED_MU[k], PLANTED_SIGMA[k]) for k in places])
    concepts = CONCEPT_OF_PLACE[places]
    function = ["this", "is", "the", "here"]
    tokens = [[NAMES[c] if rng.random() < 0.5 else function[rng.integers(4)] for _ in range(3)] for c in concepts]
    for c, toks in zip(concepts, tokens, strict=False):
        if NAMES[c] not in toks:
            toks[0] = NAMES[c]
    grid = OccupancyMap(data=np.zeros((100, 100), np.int8), resolution=0.1, origin=(-2.0, -2.0, 0.0))
    return Dataset(name="planted", map=grid, positions=X, tokens=tokens, truth_place=places, truth_concept=concepts)


def sweep_kernel(sampler, C, places, order, uniforms, L, K, hyper, counts, digamma_ld, eta_each=0.0, term=None):
    """One call of the concept-sweep kernel on hand-built ``counts`` = (n_l, n_lk, W_lv, F_ld, F_l) (updated in
    place) and ``hyper`` = (alpha, gamma, beta, chi), over the events ``order`` with ``uniforms``: the sampler's
    tokens, a copy of its switches, its background words with the background model off, and its features. The
    concepts it returns are a new array (``C`` is not changed); ``term``: a research variant's ``ConceptTerm``."""
    n_l, n_lk, W_lv, F_ld, F_l = counts
    bg = sampler.background_words()
    kernel = _concept_sweep if term is None else _sweep_with(term.add)
    return kernel(
        C.copy(),
        places,
        order,
        uniforms,
        L,
        K,
        *hyper,
        sampler.t_ptr,
        sampler.t_word,
        sampler.z.copy(),
        float(sampler.V),
        False,
        bg,
        np.array([bg.sum()]),
        np.array([0.0, float(sampler.z.sum())]),
        sampler.f_ptr,
        sampler.f_idx,
        sampler.f_cnt,
        float(sampler.D),
        sampler.c_val,
        sampler.c_mult,
        sampler.n_feat,
        n_l,
        n_lk,
        W_lv,
        W_lv.sum(axis=1),
        F_ld,
        F_l,
        digamma_ld,
        True,
        eta_each,
        0.0 if term is None else term.param,
    )


def concept_conditional_by_inverse_cdf(sampler, C, places, e, L, K, hyper, grid=20001, eta_each=0.0, term=None):
    """Probabilities p(C_e = l | rest) read off the kernel: it draws by inverse CDF of one uniform (``eta_each``:
    eta / L of the place_concepts term, 0 off)."""
    counts = np.zeros(L)
    for u in np.linspace(0.0, 1.0, grid, endpoint=False) + 0.5 / grid:
        n_l = np.bincount(C, minlength=L).astype(float)
        n_lk = np.zeros((L, K))
        np.add.at(n_lk, (C, places), 1.0)
        onehot = np.eye(L)[C]
        W_lv = onehot.T @ sampler.concept_words()
        F_ld = onehot.T @ sampler.varying
        F_l = onehot.T @ sampler.n_feat
        out = sweep_kernel(
            sampler,
            C,
            places,
            np.array([e]),
            np.array([u]),
            L,
            K,
            hyper,
            (n_l, n_lk, W_lv, F_ld, F_l),
            np.zeros_like(F_ld),
            eta_each,
            term,
        )
        counts[out[e]] += 1
    return counts / grid


def reseal(folder: Path) -> None:
    """Rewrite a model folder's manifest after a test changed a file on purpose (so the check under test is
    reached)."""
    names = sorted(p.name for p in folder.iterdir() if p.is_file() and p.name != MANIFEST)
    (folder / MANIFEST).write_text(json.dumps(manifest_of(folder, names)), encoding="utf-8")


def short_fit(data: Dataset, **kwargs):
    """An 8-sweep batch fit of ``data`` (seed 4) with the learner settings ``kwargs``: the tests of opt-in terms."""
    from spcotmhp.learning.gibbs import SpCoTMHP

    return SpCoTMHP(iterations=8, seed=4, **kwargs).fit(data)


def assert_same_fit(got, want) -> None:
    """Two fits drew the same places and concepts and reached the same log joint and word distributions."""
    np.testing.assert_array_equal(got.places_, want.places_)
    np.testing.assert_array_equal(got.concepts_, want.concepts_)
    assert got.log_joint_ == want.log_joint_
    np.testing.assert_array_equal(got.model_.W, want.model_.W)


def stats_of(places, concepts, words, K: int, L: int):
    """The sufficient statistics of an assignment without features, positions all at the origin (the tests of
    terms that do not look at positions)."""
    from spcotmhp.learning.distributions import GaussianStats
    from spcotmhp.learning.posterior import SufficientStats

    pgc = np.zeros((L, K))
    np.add.at(pgc, (concepts, places), 1.0)
    W = np.zeros((L, words.shape[1]))
    np.add.at(W, concepts, words)
    gauss = GaussianStats.from_assignments(np.zeros((len(places), 2)), places, K)
    return SufficientStats(gauss, np.bincount(concepts, minlength=L).astype(float), pgc, None, W)


def conditional_by_joints(priors, places, C, words, e: int, K: int, L: int, extra=None) -> np.ndarray:
    """p(C_e = l | rest) for every l as the normalised collapsed joints of the L assignments that differ in C_e only
    (brute force, no transitions; ``extra``: a research variant's terms of the joint)."""
    from scipy.special import logsumexp

    from spcotmhp.learning.posterior import log_joint

    lp = []
    for l in range(L):
        C_l = C.copy()
        C_l[e] = l
        lp.append(log_joint(priors, stats_of(places, C_l, words, K, L), None, extra))
    return np.exp(np.array(lp) - logsumexp(lp))


def folder_without_hyper_key(model, folder: Path, key: str) -> Path:
    """``model`` with the paper's priors saved to ``folder``, then its model.json rewritten without
    ``hyper[key]``, as a folder written before that hyper-parameter existed; returns the model.json path."""
    from dataclasses import replace

    from spcotmhp.learning.model import Hyperparameters
    from spcotmhp.persistence.io import save_model

    save_model(replace(model, hyper=Hyperparameters()), folder)
    path = folder / "model.json"
    meta = json.loads(path.read_text())
    del meta["hyper"][key]
    path.write_text(json.dumps(meta))
    reseal(folder)
    return path
