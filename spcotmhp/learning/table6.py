"""Evaluation of unsupervised learning (paper Table 6, Experiment II): NMI and ARI of the concepts C and the
places i against the truth, means over independent runs, plus learning time.

Methods: ``tmhp_replay`` (SpCoTMHP with reverse replay), ``tmhp`` (without) and ``gmm`` (the SpCoSLAM Gaussian
mixture, the same sampler with ``transitions="none"``).  Scores use scikit-learn's
``normalized_mutual_info_score`` (arithmetic normalisation) and ``adjusted_rand_score``.  The truth of C is the
dataset's concept column; without one, events whose true places share a name share a concept (three bedrooms
are one concept "bedroom"); without names, C is scored against the places.  ``time_s`` is the wall time of all
the runs of a method together (the paper's 1.3e2 s is for its ten runs).
"""

from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import asdict, dataclass, field

import numpy as np
from sklearn.metrics import adjusted_rand_score, normalized_mutual_info_score

from spcotmhp.datasets.dataset import Dataset
from spcotmhp.errors import DatasetError
from spcotmhp.learning.gibbs import SpCoTMHP
from spcotmhp.learning.selection import MultiRunSelector

METHODS: dict[str, dict] = {
    "tmhp_replay": {"transitions": "hmm", "replay": True},
    "tmhp": {"transitions": "hmm", "replay": False},
    "gmm": {"transitions": "none"},
}
LABELS = {"tmhp_replay": "SpCoTMHP (with reverse replay)", "tmhp": "SpCoTMHP", "gmm": "SpCoSLAM (GMM)"}
# Table 6 of the paper (albert-b, ten runs of 100 iterations, Intel i7-6850K)
PAPER = {
    "gmm": {"nmi_c": 0.767, "nmi_i": 0.803, "ari_c": 0.539, "ari_i": 0.578, "time_s": 128.0},
    "tmhp": {"nmi_c": 0.779, "nmi_i": 0.858, "ari_c": 0.540, "ari_i": 0.656, "time_s": 133.0},
    "tmhp_replay": {"nmi_c": 0.786, "nmi_i": 0.862, "ari_c": 0.562, "ari_i": 0.658, "time_s": 129.0},
}


@dataclass
class MethodScores:
    """Means over ``runs`` runs (and their standard deviations) and the wall time of all runs; ``saturated``
    counts the runs whose place / concept truncation was saturated (``gibbs.TruncationWarning``)."""

    nmi_c: float
    nmi_i: float
    ari_c: float
    ari_i: float
    time_s: float
    runs: int
    std: dict
    saturated: dict = field(default_factory=lambda: {"places": 0, "concepts": 0})


def concept_truth(dataset: Dataset) -> np.ndarray:
    """True concept per event (see module docstring)."""
    if dataset.truth_place is None:
        raise DatasetError(f"{dataset.name}: evaluating learning needs truth.csv (true place per event)")
    if dataset.truth_concept is not None:
        return np.asarray(dataset.truth_concept)
    if dataset.place_names is not None:
        names = sorted(set(dataset.place_names))
        return np.array([names.index(dataset.place_names[p]) for p in dataset.truth_place])
    return np.asarray(dataset.truth_place)


def score_run(dataset: Dataset, places: np.ndarray, concepts: np.ndarray) -> dict[str, float]:
    """NMI and ARI of one run's C and i against the truth."""
    tc, ti = concept_truth(dataset), np.asarray(dataset.truth_place)
    return {"nmi_c": float(normalized_mutual_info_score(tc, concepts)),
            "nmi_i": float(normalized_mutual_info_score(ti, places)),
            "ari_c": float(adjusted_rand_score(tc, concepts)),
            "ari_i": float(adjusted_rand_score(ti, places))}


def evaluate_learning(dataset: Dataset, runs: int = 10, seed: int = 0, iterations: int = 100, n_jobs: int = 1,
                      methods: tuple[str, ...] = tuple(METHODS), progress: Callable[[int], None] | None = None,
                      **params) -> dict[str, MethodScores]:
    """Table 6 on ``dataset``: ``runs`` runs of each method (run r = r-th child of ``seed``); ``params`` go to
    SpCoTMHP (e.g. use_features=False, K=30).  ``progress(n)`` reports completed sweeps."""
    concept_truth(dataset)
    out = {}
    for name in methods:
        est = SpCoTMHP(iterations=iterations, seed=seed, connectivity="hmm", **{**params, **METHODS[name]})
        t0 = time.perf_counter()
        sel = MultiRunSelector(est, runs=runs, n_jobs=n_jobs).fit(dataset, progress=progress)
        elapsed = time.perf_counter() - t0
        scores = [score_run(dataset, e.places_, e.concepts_) for e in sel.estimators_]
        mean = {k: float(np.mean([s[k] for s in scores])) for k in scores[0]}
        std = {k: float(np.std([s[k] for s in scores])) for k in scores[0]}
        saturated = {what: sum(what in e.model_.info["truncation_saturated"] for e in sel.estimators_)
                     for what in ("places", "concepts")}
        out[name] = MethodScores(**mean, time_s=elapsed, runs=runs, std=std, saturated=saturated)
    return out


def as_json(results: dict[str, MethodScores]) -> dict:
    """{method: {nmi_c, nmi_i, ari_c, ari_i, time_s, runs, std, saturated}}."""
    return {name: asdict(s) for name, s in results.items()}


def format_table(results: dict[str, MethodScores], dataset_name: str = "") -> str:
    """Table 6 as text: for each method, the paper's row (albert-b) and ours."""
    head = f"{'Method':<34}{'':>7}{'NMI C':>8}{'NMI i':>8}{'ARI C':>8}{'ARI i':>8}{'Time (s)':>10}"
    lines = [f"Table 6 - learning of spatial concepts{f' on {dataset_name}' if dataset_name else ''}", head,
             "-" * len(head)]
    for name in ("gmm", "tmhp", "tmhp_replay"):
        if name not in results:
            continue
        ours = results[name]
        paper = PAPER[name]
        lines.append(f"{LABELS[name]:<34}{'paper*':>7}" + "".join(f"{paper[k]:>8.3f}" for k in
                                                                 ("nmi_c", "nmi_i", "ari_c", "ari_i"))
                     + f"{paper['time_s']:>10.1f}")
        lines.append(f"{'':<34}{'ours':>7}" + "".join(f"{getattr(ours, k):>8.3f}" for k in
                                                      ("nmi_c", "nmi_i", "ari_c", "ari_i"))
                     + f"{ours.time_s:>10.2f}")
    runs = next(iter(results.values())).runs if results else 0
    lines.append(f"ours: means over {runs} runs each, time for all of them together; "
                 "* the paper's Table 6: albert-b, 10 runs, Python, i7-6850K")
    return "\n".join(lines)
