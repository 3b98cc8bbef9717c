"""Evaluation of unsupervised learning (paper Table 6, Experiment II): NMI and ARI of the concepts C and the
places i against the truth, means over independent runs, plus learning time.

Methods: ``tmhp_replay`` (SpCoTMHP with reverse replay), ``tmhp`` (without) and ``gmm`` (the SpCoSLAM Gaussian
mixture, the same sampler with ``transitions="none"``).  Scores use scikit-learn's
``normalized_mutual_info_score`` (arithmetic normalisation) and ``adjusted_rand_score``.  The truth of C is the
dataset's concept column; without one, events whose true places share a name share a concept (three bedrooms
are one concept "bedroom"); without names, C is scored against the places.  ``time_s`` is the wall time of all
the runs of a method together (the paper's 1.3e2 s is for its ten runs), measured after the numba kernels have
been compiled (:func:`warm_up`).

:func:`evaluate_seeds` repeats the whole evaluation for ``seeds`` seeds (seed, seed + 1, ...; each with its
``runs`` runs) and reports each metric as the mean over the seeds of the per-seed means with ``<metric>_sd``,
the standard deviation over seeds (:mod:`spcotmhp.evaluation.spread`).
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
from spcotmhp.limits import MAX_SEEDS, check_count

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
    counts the runs whose place / concept truncation was saturated (``posterior.TruncationWarning``)."""

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
    return {
        "nmi_c": float(normalized_mutual_info_score(tc, concepts)),
        "nmi_i": float(normalized_mutual_info_score(ti, places)),
        "ari_c": float(adjusted_rand_score(tc, concepts)),
        "ari_i": float(adjusted_rand_score(ti, places)),
    }


def evaluate_learning(
    dataset: Dataset,
    runs: int = 10,
    seed: int = 0,
    iterations: int = 100,
    n_jobs: int = 1,
    methods: tuple[str, ...] = tuple(METHODS),
    progress: Callable[[int], None] | None = None,
    on_fit: Callable[[str, MultiRunSelector], None] | None = None,
    **params,
) -> dict[str, MethodScores]:
    """Table 6 on ``dataset``: ``runs`` runs of each method (run r = r-th child of ``seed``); ``params`` go to
    SpCoTMHP (e.g. use_features=False, K=30).  ``progress(n)`` reports completed sweeps; ``on_fit(method,
    selector)`` sees each method's fitted runs (``selector.estimators_``)."""
    concept_truth(dataset)
    out = {}
    for name in methods:
        est = SpCoTMHP(iterations=iterations, seed=seed, connectivity="hmm", **{**params, **METHODS[name]})
        t0 = time.perf_counter()
        sel = MultiRunSelector(est, runs=runs, n_jobs=n_jobs).fit(dataset, progress=progress)
        elapsed = time.perf_counter() - t0
        if on_fit is not None:
            on_fit(name, sel)
        scores = [score_run(dataset, e.places_, e.concepts_) for e in sel.estimators_]
        mean = {k: float(np.mean([s[k] for s in scores])) for k in scores[0]}
        std = {k: float(np.std([s[k] for s in scores])) for k in scores[0]}
        saturated = {
            what: sum(what in e.model_.info["truncation_saturated"] for e in sel.estimators_)
            for what in ("places", "concepts")
        }
        out[name] = MethodScores(**mean, time_s=elapsed, runs=runs, std=std, saturated=saturated)
    return out


def warm_up(dataset: Dataset, **params) -> None:
    """Compile (or load) the numba kernels the sampler uses, so that no timed run pays for compilation."""
    for method in METHODS.values():
        SpCoTMHP(iterations=2, seed=0, connectivity="hmm", **{**params, **method}).fit(dataset)


def evaluate_seeds(
    dataset: Dataset,
    seeds: int = 5,
    seed: int = 0,
    runs: int = 10,
    iterations: int = 100,
    n_jobs: int = 1,
    methods: tuple[str, ...] = tuple(METHODS),
    progress: Callable[[int], None] | None = None,
    **params,
) -> dict[str, dict]:
    """Table 6 over ``seeds`` seeds: {method: {nmi_c, nmi_c_sd, ..., time_s, time_s_sd, runs, std, saturated,
    seeds}} (module docstring); ``std`` is the spread over the runs of the first seed, ``saturated`` sums
    over seeds."""
    from spcotmhp.evaluation.spread import aggregate_methods

    check_count(seeds, "seeds", 1, MAX_SEEDS, ValueError)
    warm_up(dataset, **params)
    per_seed = [
        as_json(evaluate_learning(dataset, runs, seed + k, iterations, n_jobs, methods, progress, **params))
        for k in range(seeds)
    ]
    out = aggregate_methods(per_seed)
    for name in out:
        out[name]["saturated"] = {w: sum(d[name]["saturated"][w] for d in per_seed) for w in ("places", "concepts")}
    return out


def as_json(results: dict[str, MethodScores]) -> dict:
    """{method: {nmi_c, nmi_i, ari_c, ari_i, time_s, runs, std, saturated}}."""
    return {name: asdict(s) for name, s in results.items()}


def format_table(results: dict[str, dict], dataset_name: str = "") -> str:
    """Table 6 as text: for each method, the paper's row (albert-b) and ours (mean ± sd over seeds), from
    :func:`evaluate_seeds` (or :func:`as_json`) results."""
    from spcotmhp.evaluation.spread import pm

    keys = ("nmi_c", "nmi_i", "ari_c", "ari_i")
    head = f"{'Method':<32}{'':>7}" + "".join(f"{k.replace('_', ' ').upper()[:3] + ' ' + k[-1]:>16}" for k in keys)
    head += f"{'Time (s)':>16}"
    lines = [
        f"Table 6 - learning of spatial concepts{f' on {dataset_name}' if dataset_name else ''}",
        head,
        "-" * len(head),
    ]
    for name in ("gmm", "tmhp", "tmhp_replay"):
        if name not in results:
            continue
        ours, paper = results[name], PAPER[name]
        lines.append(
            f"{LABELS[name]:<32}{'paper*':>7}"
            + "".join(f"{paper[k]:>16.3f}" for k in keys)
            + f"{paper['time_s']:>16.1f}"
        )
        lines.append(
            f"{'':<32}{'ours':>7}" + "".join(f"{pm(ours, k):>16}" for k in keys) + f"{pm(ours, 'time_s', 2):>16}"
        )
    first = next(iter(results.values()), {})
    lines.append(
        f"ours: mean ± sd over {first.get('seeds', 1)} seed(s) of the means over {first.get('runs', 0)} "
        "runs each; time for all runs of one seed together (numba compiled beforehand); "
        "* the paper's Table 6: albert-b, 10 runs, Python, i7-6850K"
    )
    return "\n".join(lines)


def markdown(results: dict[str, dict], caption: str) -> str:
    """Table 6 as markdown: the paper's row (albert-b) beside ours (mean ± sd over seeds) for each method."""
    from spcotmhp.evaluation.spread import pm

    keys = ("nmi_c", "nmi_i", "ari_c", "ari_i")
    lines = [
        caption,
        "",
        "| Method | | NMI C | NMI i | ARI C | ARI i | Time |",
        "|---|---|---|---|---|---|---|",
    ]
    for name in ("gmm", "tmhp", "tmhp_replay"):
        if name in results:
            paper, ours = PAPER[name], results[name]
            lines.append(
                f"| {LABELS[name]} | paper | "
                + " | ".join(f"{paper[k]:.3f}" for k in keys)
                + f" | {paper['time_s']:.0f} s |"
            )
            lines.append("| | ours | " + " | ".join(pm(ours, k) for k in keys) + f" | {pm(ours, 'time_s', 1)} s |")
    return "\n".join(lines) + "\n"
