"""Update time of the online learner over a long stream: a home's teaching events repeated with 5 cm jitter up to
``--events`` events, streamed one at a time; the update time per event over the first and the last 100 events
(median, p95, max), with and without split-merge moves in the same run (the machine is shared: compare the
ratios).

    PYTHONPATH=$PWD python benchmarks/online_learning.py --home 3LDK_01 --events 1000 --seeds 1
"""

from __future__ import annotations

import argparse
import json
import warnings

import numpy as np

from spcotmhp.datasets.bundled import load_bundled
from spcotmhp.learning.online import OnlineSpCoTMHP, TeachingEvent
from spcotmhp.learning.online_eval import dataset_events


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


def summary(ms: np.ndarray) -> dict:
    return {"median": float(np.median(ms)), "p95": float(np.percentile(ms, 95)), "max": float(ms.max())}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--home", default="3LDK_01")
    parser.add_argument("--events", type=int, default=1000)
    parser.add_argument("--seeds", type=int, default=1)
    args = parser.parse_args()
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
