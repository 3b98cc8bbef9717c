"""Benchmark of spcotmhp.learning: wall and CPU time of ten Gibbs runs (100 sweeps each) on the bundled datasets.

    .venv/bin/python benchmarks/learning.py [--runs 10] [--iterations 100] [--jobs 2] [--scale] [--against DIR]

Prints a markdown table on stdout: for each dataset, the seconds for ``--runs`` runs in one process and in
``--jobs`` worker processes (ratio = one process / workers, the speed-up), the CPU seconds of each (this process
and its workers), the CPU seconds of one run (the mean of ``time.process_time`` in each run's own process: on a
machine shared with other jobs, the work itself), and the share of a run's CPU time spent in each stage of the
sweep, measured on one extra run with the stages timed: the places (step 4, FFBS with the emissions of Eq. 9),
the concept sweep (step 5), the trajectory labelling (step 2) and the sufficient statistics with the log joint
of the trace.  The paper reports about 130 s for its ten runs (Python, i7-6850K).  numba compilation happens
before any timing.

``--scale``: learning at scale (issue 11) instead, on a generated office of 200 rooms with 25 teaching events
each (5,000 events, ``datasets.synthetic.generate_environment("office", n_rooms=200, size=2000,
events_per_room=25)``, words only, a 150,000-pose trajectory) with truncations K = L = 250; target: ten runs
<= 120 s.

``--against DIR``: also time another version of the package (a checkout whose ``spcotmhp`` is in DIR, e.g. made
with ``git archive``) in the same run: ``--pairs`` single runs of each, alternating, each in a fresh process,
and print a second table of their CPU seconds per run and the ratio, so that both see the same machine load
(``--runs 0``: that table only).
"""

from __future__ import annotations

import argparse
import json
import os
import resource
import subprocess
import sys
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
STAGES = ("places", "concepts", "trajectory", "statistics")


def _cases(scale: bool) -> list[tuple[str, object, bool, dict]]:
    if scale:
        office = generate_environment("office", seed=0, n_rooms=200, size=2000, events_per_room=25)
        size = {"K": SCALE_SIZE, "L": SCALE_SIZE}
        return [(f"office, 200 rooms, {office.n_events} events, K = L = {SCALE_SIZE}", office, False, size)]
    return [(f"{name} ({lang})", load_bundled(name, lang=lang), feats, {}) for name, lang, feats in CASES]


def stage_shares(data, use_features: bool, iterations: int, **size) -> dict[str, float]:
    """Fractions of one run's CPU time spent in each stage of :data:`STAGES`."""
    spent = dict.fromkeys(STAGES, 0.0)
    patched = {
        "places": (gibbs, "sample_places"),
        "concepts": (concepts.CollapsedConceptSampler, "sweep"),
        "trajectory": (gibbs, "trajectory_places"),
        "statistics": (gibbs.SpCoTMHP, "_stats"),
        "log_joint": (gibbs, "log_joint"),
    }
    originals = {name: getattr(owner, attr) for name, (owner, attr) in patched.items()}

    def timed(name: str, fn):
        stage = "statistics" if name == "log_joint" else name

        def wrapper(*a, **k):
            c = time.process_time()
            out = fn(*a, **k)
            spent[stage] += time.process_time() - c
            return out

        return wrapper

    for name, (owner, attr) in patched.items():
        setattr(owner, attr, timed(name, originals[name]))
    try:
        c0 = time.process_time()
        gibbs.SpCoTMHP(iterations=iterations, use_features=use_features, connectivity="hmm", **size).fit(data)
        total = time.process_time() - c0
    finally:
        for name, (owner, attr) in patched.items():
            setattr(owner, attr, originals[name])
    return {stage: spent[stage] / total for stage in STAGES}


def _cpu_seconds() -> float:
    """CPU time of this process and of its finished worker processes (on a shared machine, the work itself)."""
    own, children = resource.getrusage(resource.RUSAGE_SELF), resource.getrusage(resource.RUSAGE_CHILDREN)
    return own.ru_utime + own.ru_stime + children.ru_utime + children.ru_stime


def main_table(args: argparse.Namespace) -> None:
    print(
        f"| dataset | features | {args.runs} runs, 1 process (s) | CPU (s) "
        f"| {args.runs} runs, {args.jobs} processes (s) | CPU (s) | ratio | CPU per run (s) "
        "| places | concept sweep | trajectory | statistics |"
    )
    print("|---|---|---|---|---|---|---|---|---|---|---|---|")
    for label, data, feats, size in _cases(args.scale):
        fit_runs(data, runs=1, iterations=2, use_features=feats, **size)  # compile / load the numba caches
        times, cpu, per_run = [], [], []
        for jobs in (1, args.jobs):
            c0 = _cpu_seconds()
            t0 = time.perf_counter()
            sel = fit_runs(
                data, runs=args.runs, iterations=args.iterations, n_jobs=jobs, use_features=feats,
                connectivity="hmm", **size,
            )  # fmt: skip
            times.append(time.perf_counter() - t0)
            cpu.append(_cpu_seconds() - c0)
            per_run += [s.cpu_time for s in sel.summaries_]
        share = stage_shares(data, feats, args.iterations, **size)
        print(
            f"| {label} | {'yes' if feats else 'no'} | {times[0]:.2f} | {cpu[0]:.1f} | {times[1]:.2f} | {cpu[1]:.1f} "
            f"| {times[0] / times[1]:.2f} | {sum(per_run) / len(per_run):.2f} | "
            + " | ".join(f"{share[s]:.0%}" for s in STAGES)
            + " |"
        )


ONE_RUN = """
import json, sys, time, warnings
warnings.simplefilter("ignore")
from learning import _cases
import spcotmhp
from spcotmhp.learning import gibbs
label, data, feats, size = _cases({scale})[{case}]
gibbs.SpCoTMHP(iterations=2, use_features=feats, connectivity="hmm", **size).fit(data)
m = gibbs.SpCoTMHP(iterations={iterations}, use_features=feats, connectivity="hmm", run={run}, **size)
c = time.process_time()
m.fit(data)
print(json.dumps([time.process_time() - c, m.places_.tolist(), spcotmhp.__file__]))
"""


def against_table(args: argparse.Namespace) -> None:
    """CPU seconds per run of this version and of the one in ``args.against``, alternating (module docstring)."""
    here = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    bench = os.path.dirname(os.path.abspath(__file__))
    print("\n| dataset | CPU per run, this version (s) | CPU per run, --against (s) | ratio | same places |")
    print("|---|---|---|---|---|")
    for case, (label, *_rest) in enumerate(_cases(args.scale)):
        spent: dict[str, list[float]] = {here: [], args.against: []}
        same = True
        for run in range(args.pairs):
            places = []
            for root in (args.against, here):
                code = ONE_RUN.format(scale=args.scale, case=case, iterations=args.iterations, run=run)
                env = dict(os.environ, PYTHONPATH=root)  # run from bench: the working directory goes first on the path
                out = subprocess.run(
                    [sys.executable, "-c", code], env=env, cwd=bench, capture_output=True, text=True, check=True
                )
                seconds, seq, package = json.loads(out.stdout.strip().splitlines()[-1])
                if not os.path.abspath(package).startswith(os.path.abspath(root)):
                    raise SystemExit(f"{root}: imported spcotmhp from {package} instead")
                spent[root].append(seconds)
                places.append(seq)
            same = same and places[0] == places[1]
        new, old = (sum(spent[r]) / len(spent[r]) for r in (here, args.against))
        print(f"| {label} | {new:.2f} | {old:.2f} | {old / new:.2f} | {'yes' if same else 'no'} |")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--runs", type=int, default=10)
    parser.add_argument("--iterations", type=int, default=100)
    parser.add_argument("--jobs", type=int, default=2)
    parser.add_argument("--scale", action="store_true", help="the 200-room office (5,000 events) instead")
    parser.add_argument("--against", help="a directory holding another version's spcotmhp package, timed too")
    parser.add_argument("--pairs", type=int, default=2, help="single runs of each version with --against")
    args = parser.parse_args()
    warnings.simplefilter("ignore")
    if args.runs > 0:
        main_table(args)
    if args.against:
        against_table(args)


if __name__ == "__main__":
    main()
