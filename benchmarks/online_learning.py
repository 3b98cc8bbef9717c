"""Update time of the online learner over a long stream: a home's teaching events repeated with 5 cm jitter up to
``--events`` events, streamed one at a time; the update time per event over the first and the last 100 events
(median, p95, max), with and without split-merge moves in the same run (the machine is shared: compare the
ratios).

    python benchmarks/online_learning.py --home 3LDK_01 --events 1000 --seeds 1

With ``--log-joint`` it instead compares, per seed, the final sample of batch learning (100 sweeps) and of the
online learner streaming the home once: the collapsed log joint the batch learner selects runs by
(``posterior.log_joint``) and the ARI of concepts and places, to tell a sampler that misses the posterior's modes
from a posterior whose modes are not the truth.

    python benchmarks/online_learning.py --home albert-b --log-joint --seeds 5
"""

from __future__ import annotations

import argparse
import json
import warnings

import numpy as np

from spcotmhp.datasets.bundled import load_bundled
from spcotmhp.evaluation.online_eval import dataset_events
from spcotmhp.learning.online import OnlineSpCoTMHP, TeachingEvent


def long_stream(home: str, events: int, seed: int) -> tuple[list[TeachingEvent], object]:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        data = load_bundled(home, lang="ja" if home == "albert-b" else "en")
    base, rng, out = dataset_events(data), np.random.default_rng(seed), []
    while len(out) < events:
        for ev in base[: events - len(out)]:
            dx, dy = rng.normal(0.0, 0.05, 2)
            out.append(TeachingEvent(ev.x + dx, ev.y + dy, ev.words, ev.features))
    return out, data


def log_joint_of(st) -> float:
    """posterior.log_joint of a learner state's counts."""
    from spcotmhp.learning.distributions import GaussianStats
    from spcotmhp.learning.posterior import Priors, SufficientStats, log_joint

    stats = SufficientStats(
        GaussianStats(st.n_k, st.sx, st.sxx), st.n_l, st.n_lk, st.F_ld, st.W_lv, st.bg_v if st.background else None
    )
    return log_joint(Priors.build(st.hyper, st.K, st.L, st.V, st.D), stats, st.trans)


def compare_log_joint(home: str, seeds: int) -> list[dict]:
    """Per seed: log joint and ARI of the batch learner's final sample and of the online learner's."""
    from spcotmhp.evaluation.table6 import score_run
    from spcotmhp.learning.gibbs import SpCoTMHP
    from spcotmhp.learning.learner_state import state_of_member

    _, data = long_stream(home, 0, 0)
    stream = dataset_events(data)
    rows = []
    for seed in range(seeds):
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            batch = SpCoTMHP(iterations=100, seed=seed).fit(data).model_
            online = OnlineSpCoTMHP(map=data.map, check_map=False, seed=seed).partial_fit(stream)
        row = {"seed": seed}
        for name, st in (("batch", state_of_member(batch.learner, batch)), ("online", online.state_)):
            score = score_run(data, st.place, st.concept)
            row[name] = {"log_joint": log_joint_of(st), "ari_c": score["ari_c"], "ari_i": score["ari_i"]}
        rows.append(row)
    return rows


def summary(ms: np.ndarray) -> dict:
    return {"median": float(np.median(ms)), "p95": float(np.percentile(ms, 95)), "max": float(ms.max())}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--home", default="3LDK_01")
    parser.add_argument("--events", type=int, default=1000)
    parser.add_argument("--seeds", type=int, default=1)
    parser.add_argument("--log-joint", action="store_true", help="compare batch and online final samples")
    args = parser.parse_args()
    if args.log_joint:
        print(json.dumps(compare_log_joint(args.home, args.seeds), indent=1))
        return
    result = {}
    for name, moves in (("gibbs only", 0), ("with split-merge", None)):
        first, last, every = [], [], []
        for seed in range(args.seeds):
            stream, data = long_stream(args.home, args.events, seed)
            params = {} if moves is None else {"split_merge": moves}
            learner = OnlineSpCoTMHP(map=data.map, check_map=False, seed=seed, **params)
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                for event in stream:
                    learner.partial_fit([event])
            ms = 1000.0 * np.asarray(learner.update_times_)
            first.append(ms[:100])
            last.append(ms[-100:])
            every.append(ms)
        result[name] = {
            "first 100": summary(np.concatenate(first)),
            "last 100": summary(np.concatenate(last)),
            "all": summary(np.concatenate(every)),
        }
    print(json.dumps({"home": args.home, "events": args.events, "seeds": args.seeds, **result}, indent=1))


if __name__ == "__main__":
    main()
