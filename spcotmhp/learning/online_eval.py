"""Evaluation of online learning: a dataset's teaching events streamed one at a time in their recorded order
(``OnlineSpCoTMHP.partial_fit`` per event), NMI and ARI of the final assignments against the truth (means and
standard deviations over seeds) beside batch learning (``table6``, SpCoTMHP with reverse replay, as many runs),
and the update time per event (median, 95th percentile and maximum over every event of every seed)."""

from __future__ import annotations

import warnings
from typing import Any

import numpy as np

from spcotmhp.datasets.dataset import Dataset
from spcotmhp.learning.gibbs import TruncationWarning
from spcotmhp.learning.online import OnlineSpCoTMHP, TeachingEvent
from spcotmhp.learning.table6 import concept_truth, evaluate_learning, score_run

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
    **params,
) -> dict:
    """{"dataset", "events", "seeds", "online": {scores, "std", "update_ms": {median, p95, max}}, "batch": {...},
    "difference": online - batch}; seed s of ``seeds`` is ``seed + s``; ``params`` go to OnlineSpCoTMHP."""
    concept_truth(dataset)
    events = dataset_events(dataset, use_features)
    scores, times = [], []
    for s in range(seeds):
        learner = OnlineSpCoTMHP(
            K=K, L=L, use_features=use_features, map=dataset.map, check_map=False, seed=seed + s, **params
        )
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", TruncationWarning)
            for event in events:
                learner.partial_fit([event])
        scores.append(score_run(dataset, learner.places_, learner.concepts_))
        times.extend(learner.update_times_)
    ms = 1000.0 * np.asarray(times)
    out: dict[str, Any] = {
        "dataset": dataset.name,
        "events": len(events),
        "seeds": seeds,
        "online": {
            **_mean_std(scores),
            "update_ms": {
                "median": float(np.median(ms)),
                "p95": float(np.percentile(ms, 95)),
                "max": float(ms.max()),
            },
        },
    }
    if batch:
        b = evaluate_learning(
            dataset,
            runs=seeds,
            seed=seed,
            iterations=iterations,
            n_jobs=n_jobs,
            methods=("tmhp_replay",),
            use_features=use_features,
            K=K,
            L=L,
        )["tmhp_replay"]
        out["batch"] = {**{k: getattr(b, k) for k in SCORES}, "std": b.std, "time_s": b.time_s}
        out["difference"] = {k: out["online"][k] - out["batch"][k] for k in SCORES}
    return out


def _mean_std(scores: list[dict]) -> dict:
    return {
        **{k: float(np.mean([s[k] for s in scores])) for k in SCORES},
        "std": {k: float(np.std([s[k] for s in scores])) for k in SCORES},
    }


def format_report(result: dict) -> str:
    """The evaluation as a short table."""
    lines = [
        (
            f"Online learning on {result['dataset']}: {result['events']} events streamed in recorded order, "
            f"{result['seeds']} seeds"
        ),
        f"{'':<8}" + "".join(f"{k.upper().replace('_', ' '):>15}" for k in SCORES),
    ]
    for name in ("online", "batch"):
        if name in result:
            r = result[name]
            lines.append(f"{name:<8}" + "".join(f"{r[k]:>8.3f} ± {r['std'][k]:.3f}" for k in SCORES))
    t = result["online"]["update_ms"]
    lines.append(f"update time per event: median {t['median']:.1f} ms, p95 {t['p95']:.1f} ms, max {t['max']:.1f} ms")
    return "\n".join(lines)
