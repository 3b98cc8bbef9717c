"""Benchmark of spcotmhp.learning: wall time of ten Gibbs runs (100 sweeps each) on the bundled datasets.

    .venv/bin/python benchmarks/learning.py [--runs 10] [--iterations 100] [--jobs 2]

Prints a markdown table on stdout: for each dataset, the seconds for ``--runs`` runs in one process and in
``--jobs`` worker processes (ratio = one process / workers, the speed-up), the milliseconds per sweep, and the
share of a sweep spent in the two numba kernels (FFBS of the places, collapsed concept sweep), measured on one
extra run with the kernels timed.  The paper reports about 130 s for its ten runs (Python, i7-6850K); the target
here is <= 10 s on 2 cores.  numba compilation happens before any timing.
"""

from __future__ import annotations

import argparse
import time
import warnings

from spcotmhp.datasets import load_bundled
from spcotmhp.learning import concepts, gibbs
from spcotmhp.learning.selection import fit_runs

CASES = (
    ("albert-b", "ja", True),
    ("albert-b", "ja", False),
    ("3LDK_01", "en", False),
    ("3LDK_06", "ja", False),
)


def kernel_share(data, use_features: bool, iterations: int) -> tuple[float, float]:
    """Fractions of one run's time spent in ffbs and in the concept sweep."""
    spent = {"ffbs": 0.0, "sweep": 0.0}
    ffbs, sweep = gibbs.ffbs, concepts.CollapsedConceptSampler.sweep

    def timed_ffbs(*a, **k):
        t = time.perf_counter()
        out = ffbs(*a, **k)
        spent["ffbs"] += time.perf_counter() - t
        return out

    def timed_sweep(self, *a, **k):
        t = time.perf_counter()
        out = sweep(self, *a, **k)
        spent["sweep"] += time.perf_counter() - t
        return out

    gibbs.ffbs, concepts.CollapsedConceptSampler.sweep = timed_ffbs, timed_sweep
    try:
        t0 = time.perf_counter()
        gibbs.SpCoTMHP(iterations=iterations, use_features=use_features, connectivity="hmm").fit(data)
        total = time.perf_counter() - t0
    finally:
        gibbs.ffbs, concepts.CollapsedConceptSampler.sweep = ffbs, sweep
    return spent["ffbs"] / total, spent["sweep"] / total


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--runs", type=int, default=10)
    parser.add_argument("--iterations", type=int, default=100)
    parser.add_argument("--jobs", type=int, default=2)
    args = parser.parse_args()
    warnings.simplefilter("ignore")
    print(
        f"| dataset | features | {args.runs} runs, 1 process (s) | {args.runs} runs, {args.jobs} processes (s) "
        "| ratio | ms per sweep | FFBS share | concept sweep share |"
    )
    print("|---|---|---|---|---|---|---|---|")
    for name, lang, feats in CASES:
        data = load_bundled(name, lang=lang)
        fit_runs(data, runs=1, iterations=2, use_features=feats)  # compile / load the numba caches
        times = []
        for jobs in (1, args.jobs):
            t0 = time.perf_counter()
            fit_runs(
                data,
                runs=args.runs,
                iterations=args.iterations,
                n_jobs=jobs,
                use_features=feats,
                connectivity="hmm",
            )
            times.append(time.perf_counter() - t0)
        share = kernel_share(data, feats, args.iterations)
        per_sweep = 1000 * times[0] / (args.runs * args.iterations)
        print(
            f"| {name} ({lang}) | {'yes' if feats else 'no'} | {times[0]:.2f} | {times[1]:.2f} "
            f"| {times[0] / times[1]:.2f} | {per_sweep:.2f} | {share[0]:.0%} | {share[1]:.0%} |"
        )


if __name__ == "__main__":
    main()
