"""Benchmark of spcotmhp.learning: wall time of ten Gibbs runs (100 sweeps each) on the bundled datasets.

    .venv/bin/python benchmarks/learning.py [--runs 10] [--iterations 100] [--jobs 2] [--scale]

Prints a markdown table on stdout: for each dataset, the seconds for ``--runs`` runs in one process and in
``--jobs`` worker processes (ratio = one process / workers, the speed-up), the milliseconds per sweep, and the
share of a sweep spent in the two numba kernels (FFBS of the places, collapsed concept sweep), measured on one
extra run with the kernels timed.  The paper reports about 130 s for its ten runs (Python, i7-6850K); the target
here is <= 10 s on 2 cores.  numba compilation happens before any timing.  The CPU columns give the CPU seconds
of the runs (this process and its workers): on a machine shared with other jobs, the work itself.

``--scale``: learning at scale (issue 11) instead, on a generated office of 200 rooms with 25 teaching events
each (5,000 events, ``datasets.synthetic.generate_environment("office", n_rooms=200, size=2000,
events_per_room=25)``, words only, a 150,000-pose trajectory) with truncations K = L = 250; target: ten runs
<= 120 s.
"""

from __future__ import annotations

import argparse
import resource
import time
import warnings

from spcotmhp.datasets import load_bundled
from spcotmhp.datasets.synthetic import generate_environment
from spcotmhp.learning import concepts, gibbs
from spcotmhp.learning.selection import fit_runs

CASES = (
    ("albert-b", "ja", True),
    ("albert-b", "ja", False),
    ("3LDK_01", "en", False),
    ("3LDK_06", "ja", False),
)


SCALE_SIZE = 250  # K = L for the 200-room office


def kernel_share(data, use_features: bool, iterations: int, **size) -> tuple[float, float]:
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
        gibbs.SpCoTMHP(iterations=iterations, use_features=use_features, connectivity="hmm", **size).fit(data)
        total = time.perf_counter() - t0
    finally:
        gibbs.ffbs, concepts.CollapsedConceptSampler.sweep = ffbs, sweep
    return spent["ffbs"] / total, spent["sweep"] / total


def _cpu_seconds() -> float:
    """CPU time of this process and of its finished worker processes (on a shared machine, the work itself)."""
    own, children = resource.getrusage(resource.RUSAGE_SELF), resource.getrusage(resource.RUSAGE_CHILDREN)
    return own.ru_utime + own.ru_stime + children.ru_utime + children.ru_stime


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--runs", type=int, default=10)
    parser.add_argument("--iterations", type=int, default=100)
    parser.add_argument("--jobs", type=int, default=2)
    parser.add_argument("--scale", action="store_true", help="the 200-room office (5,000 events) instead")
    args = parser.parse_args()
    warnings.simplefilter("ignore")
    if args.scale:
        office = generate_environment("office", seed=0, n_rooms=200, size=2000, events_per_room=25)
        size = {"K": SCALE_SIZE, "L": SCALE_SIZE}
        cases = [(f"office, 200 rooms, {office.n_events} events, K = L = {SCALE_SIZE}", office, False, size)]
    else:
        cases = [(f"{name} ({lang})", load_bundled(name, lang=lang), feats, {}) for name, lang, feats in CASES]
    print(
        f"| dataset | features | {args.runs} runs, 1 process (s) | CPU (s) "
        f"| {args.runs} runs, {args.jobs} processes (s) | CPU (s) | ratio | ms per sweep "
        "| FFBS share | concept sweep share |"
    )
    print("|---|---|---|---|---|---|---|---|---|---|")
    for label, data, feats, size in cases:
        fit_runs(data, runs=1, iterations=2, use_features=feats, **size)  # compile / load the numba caches
        times, cpu = [], []
        for jobs in (1, args.jobs):
            c0 = _cpu_seconds()
            t0 = time.perf_counter()
            fit_runs(
                data,
                runs=args.runs,
                iterations=args.iterations,
                n_jobs=jobs,
                use_features=feats,
                connectivity="hmm",
                **size,
            )
            times.append(time.perf_counter() - t0)
            cpu.append(_cpu_seconds() - c0)
        share = kernel_share(data, feats, args.iterations, **size)
        per_sweep = 1000 * times[0] / (args.runs * args.iterations)
        print(
            f"| {label} | {'yes' if feats else 'no'} | {times[0]:.2f} | {cpu[0]:.1f} | {times[1]:.2f} | {cpu[1]:.1f} "
            f"| {times[0] / times[1]:.2f} | {per_sweep:.2f} | {share[0]:.0%} | {share[1]:.0%} |"
        )


if __name__ == "__main__":
    main()
