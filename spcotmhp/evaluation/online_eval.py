"""Evaluation of online learning: a dataset's teaching events streamed one at a time in their recorded order
(``OnlineSpCoTMHP.partial_fit`` per event), NMI and ARI of the final assignments against the truth (means and
standard deviations over seeds) beside batch learning (``table6``, SpCoTMHP with reverse replay, as many runs),
and the update time per event (median, 95th percentile and maximum over every event of every seed).

Beside the scores, each side reports its final samples (``"sample"``: means over seeds / runs of the number of
places and concepts used and of the collapsed log target ``online_split_merge.log_target``, the distribution the
online learner's steps and moves aim at, evaluated for the batch runs' final samples on the same terms, the map's
1 / area for a place's first position included): where online and batch differ in NMI and ARI, this says whether
the online learner ended in a less probable state (it mixed worse) or a more probable one (the model prefers it,
and batch learning stopped short of it)."""

from __future__ import annotations

import warnings
from collections.abc import Mapping
from typing import Any

import numpy as np

from spcotmhp.datasets.dataset import Dataset
from spcotmhp.errors import ModelError
from spcotmhp.evaluation.table6 import concept_truth, evaluate_learning, score_run
from spcotmhp.learning.collapsed import CollapsedState
from spcotmhp.learning.learner_state import state_of_member
from spcotmhp.learning.model import Hyperparameters, SpatialConceptModel
from spcotmhp.learning.online import OnlineSpCoTMHP, TeachingEvent, log_new_place_density
from spcotmhp.learning.online_split_merge import log_target
from spcotmhp.learning.posterior import TruncationWarning
from spcotmhp.learning.selection import MultiRunSelector

SCORES = ("nmi_c", "nmi_i", "ari_c", "ari_i")


def dataset_events(dataset: Dataset, use_features: bool = True) -> list[TeachingEvent]:
    """The dataset's teaching events in recorded order."""
    feats = dataset.features if use_features else None
    return [
        TeachingEvent(float(x), float(y), tuple(words), None if feats is None else np.asarray(feats[e]))
        for e, ((x, y), words) in enumerate(zip(dataset.positions, dataset.tokens, strict=False))
    ]


def evaluate_online(
    dataset: Dataset,
    seeds: int = 5,
    seed: int = 0,
    iterations: int = 100,
    n_jobs: int = 1,
    use_features: bool = True,
    K: int = 20,
    L: int = 20,
    batch: bool = True,
    hyper: Hyperparameters | None = None,
    batch_params: Mapping[str, Any] | None = None,
    **params,
) -> dict:
    """{"dataset", "events", "seeds", "online": {scores, "std", "update_ms": {median, p95, max}}, "batch": {...},
    "difference": online - batch}; seed s of ``seeds`` is ``seed + s``; ``hyper`` (the priors) goes to both
    learners, ``params`` to OnlineSpCoTMHP only and ``batch_params`` (e.g. a research ``variant``) to SpCoTMHP only."""
    concept_truth(dataset)
    events = dataset_events(dataset, use_features)
    scores, times, samples = [], [], []
    for s in range(seeds):
        learner = OnlineSpCoTMHP(
            K=K, L=L, use_features=use_features, map=dataset.map, check_map=False, seed=seed + s, hyper=hyper, **params
        )
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", TruncationWarning)
            for event in events:
                learner.partial_fit([event])
        scores.append(score_run(dataset, learner.places_, learner.concepts_))
        samples.append(sample_summary(learner.state_))
        times.extend(learner.update_times_)
    ms = 1000.0 * np.asarray(times)
    out: dict[str, Any] = {
        "dataset": dataset.name,
        "events": len(events),
        "seeds": seeds,
        "online": {
            **_mean_std_of(scores),
            "update_ms": {
                "median": float(np.median(ms)),
                "p95": float(np.percentile(ms, 95)),
                "max": float(ms.max()),
            },
            "sample": _mean_std_of(samples),
        },
    }
    if batch:
        settings = dict(batch_params or {}, hyper=hyper)
        out["batch"] = evaluate_batch(dataset, seeds, seed, iterations, n_jobs, use_features, K, L, settings)
        out["difference"] = {k: out["online"][k] - out["batch"][k] for k in SCORES}
    return out


def evaluate_batch(
    dataset: Dataset,
    runs: int,
    seed: int,
    iterations: int,
    n_jobs: int,
    use_features: bool,
    K: int,
    L: int,
    learner: Mapping[str, Any] | None = None,
) -> dict:
    """Batch learning's side of ``evaluate_online``: the means of ``runs`` runs of SpCoTMHP with reverse replay
    (``table6.evaluate_learning``; ``learner``: other settings of SpCoTMHP), their standard deviations, the time,
    and their final samples."""
    fitted: list[MultiRunSelector] = []
    b = evaluate_learning(
        dataset,
        runs=runs,
        seed=seed,
        iterations=iterations,
        n_jobs=n_jobs,
        methods=("tmhp_replay",),
        use_features=use_features,
        K=K,
        L=L,
        on_fit=lambda _name, sel: fitted.append(sel),
        **dict(learner or {}),
    )["tmhp_replay"]
    return {
        **{k: getattr(b, k) for k in SCORES},
        "std": b.std,
        "time_s": b.time_s,
        "sample": _mean_std_of([batch_sample_summary(e.model_, dataset) for e in fitted[0].estimators_]),
    }


def sample_summary(st: CollapsedState) -> dict[str, float]:
    """Places and concepts used by a learner state's events, and its ``log_target``."""
    return {
        "places": float((st.n_k > 0).sum()),
        "concepts": float((st.n_l > 0).sum()),
        "log_target": log_target(st),
    }


def batch_sample_summary(model: SpatialConceptModel, dataset: Dataset) -> dict[str, float]:
    """``sample_summary`` of a batch-learned model's final sample (its learner member), with the density of a
    place's first position taken from the dataset's map as the online learner takes it."""
    if model.learner is None:
        raise ModelError("the model keeps no final sample (learner member) to evaluate")
    st = state_of_member(model.learner, model)
    if dataset.map is not None:
        st.log_new_place = log_new_place_density(dataset.map)
    return sample_summary(st)


def _mean_std_of(samples: list[dict[str, float]]) -> dict:
    """{key: mean over the dicts, "std": {key: standard deviation}}."""
    keys = tuple(samples[0])
    return {
        **{k: float(np.mean([s[k] for s in samples])) for k in keys},
        "std": {k: float(np.std([s[k] for s in samples])) for k in keys},
    }


def format_report(result: dict) -> str:
    """The evaluation as a short table."""
    lines = [
        (
            f"Online learning on {result['dataset']}: {result['events']} events streamed in recorded order, "
            f"{result['seeds']} seed{'s' if result['seeds'] != 1 else ''}"
        ),
        f"{'':<8}" + "".join(f"{k.upper().replace('_', ' '):>15}" for k in SCORES),
    ]
    for name in ("online", "batch"):
        if name in result:
            r = result[name]
            lines.append(f"{name:<8}" + "".join(f"{r[k]:>8.3f} ± {r['std'][k]:.3f}" for k in SCORES))
    for name in ("online", "batch"):
        if "sample" in result.get(name, {}):
            m = result[name]["sample"]
            lines.append(
                f"{name} final samples: {m['places']:.1f} places, {m['concepts']:.1f} concepts, "
                f"log target {m['log_target']:.1f} ± {m['std']['log_target']:.1f}"
            )
    t = result["online"]["update_ms"]
    lines.append(f"update time per event: median {t['median']:.1f} ms, p95 {t['p95']:.1f} ms, max {t['max']:.1f} ms")
    return "\n".join(lines)
