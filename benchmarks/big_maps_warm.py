"""Warm plans on big maps, this version beside the previous one in the same run, by the median of many.

    python benchmarks/big_maps_warm.py --previous /tmp/prev [--this DIR] [--work /tmp/big_maps]
        [--sides 1300 2600 4000] [--plans 30] [--rounds 3]

``benchmarks/big_maps.py`` prints each plan command's one warm plan (the same plan again in its process): one
sample of a few milliseconds, which another job on a shared 2-core machine easily doubles. This takes many:
for each map side, the model folder that big_maps.py learned with the previous version
(``WORK/model{side}-previous``, so both versions plan on the same files), and per round one fresh process of
each checkout (alternating, so both meet the same load): ``HierarchicalPlanner(load_model(folder))``, the
first plan of "go to the office" from the teaching walk's first pose, then ``--plans`` more, each timed. Prints
a markdown table: median, 10th and 90th percentile of all warm plans per side and version, and the ratio of
the medians.
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
from pathlib import Path

HERE = Path(__file__).resolve().parents[1]
CHILD = """
import json, sys, time
from spcotmhp.persistence.io import load_model
from spcotmhp.planning.planner import HierarchicalPlanner
planner = HierarchicalPlanner(load_model(sys.argv[1]))
start = (float(sys.argv[2]), float(sys.argv[3]))
planner.plan("go to the office", start)
times = []
for _ in range(int(sys.argv[4])):
    t0 = time.perf_counter()
    planner.plan("go to the office", start)
    times.append(time.perf_counter() - t0)
print(json.dumps(times))
"""


def warm_plans(code: Path, model: Path, start: tuple[str, str], plans: int) -> list[float]:
    """The warm plan times (s) of one fresh process of checkout ``code`` (module docstring)."""
    env = {**os.environ, "PYTHONPATH": str(code)}
    out = subprocess.run(
        [sys.executable, "-c", CHILD, str(model), *start, str(plans)],
        cwd=code, env=env, capture_output=True, text=True, check=True,
    )  # fmt: skip
    return list(json.loads(out.stdout.strip().splitlines()[-1]))


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--previous", type=Path, required=True, help="checkout of the previous version")
    ap.add_argument("--this", type=Path, default=HERE, help="checkout of this version (default: this script's)")
    ap.add_argument("--work", type=Path, default=Path("/tmp/big_maps"), help="big_maps.py's --work")
    ap.add_argument("--sides", type=int, nargs="+", default=[1300, 2600, 4000])
    ap.add_argument("--plans", type=int, default=30, help="warm plans per process")
    ap.add_argument("--rounds", type=int, default=3, help="processes per version and side")
    args = ap.parse_args(argv)
    versions = {"this": args.this.resolve(), "previous": args.previous.resolve()}
    print("| megapixels | version | warm plan: median | 10th percentile | 90th percentile | median / previous |")
    print("|---|---|---|---|---|---|")
    for side in args.sides:
        model = args.work / f"model{side}-previous"
        rows = (args.work / f"office{side}" / "trajectory.csv").read_text().splitlines()
        start = (rows[1].split(",")[1], rows[1].split(",")[2])
        times: dict[str, list[float]] = {v: [] for v in versions}
        for _ in range(args.rounds):
            for version, code in versions.items():
                times[version] += warm_plans(code, model, start, args.plans)
        medians = {v: statistics.median(t) for v, t in times.items()}
        for version, t in times.items():
            q = statistics.quantiles(t, n=10)
            print(
                f"| {side * side / 1e6:.1f} | {version} | {medians[version] * 1e3:.2f} ms | {q[0] * 1e3:.2f} ms "
                f"| {q[-1] * 1e3:.2f} ms | {medians[version] / medians['previous']:.2f} |",
                flush=True,
            )
    return 0


if __name__ == "__main__":
    sys.exit(main())
