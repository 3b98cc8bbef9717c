"""Benchmark of the planning graph's precomputation (Algorithm 1, lines 1-7) against a previous version: time,
the bytes of the cost-to-go fields and links, and the peak memory the build allocates, on the bundled homes and
on generated homes plain, furnished (seating groups that cut islands out of rooms,
:mod:`spcotmhp.datasets.synthetic_furniture`) and furnished with a closed door; supervised parameters.

The homes are written once as dataset folders (by this checkout: the previous one may not have furniture), then
every checkout loads the same folders and builds ``HierarchicalPlanner(model)`` with a fresh graph cache: the
fastest of ``--repeat`` builds (on a machine shared with other jobs the slower ones measure the other jobs) and
the least CPU time of the process (which other jobs inflate less), then one more build under ``tracemalloc`` for
the peak of the allocations (numpy's included). Ratios are this checkout's over the previous one's, measured in
the same run. Each checkout runs in a subprocess with that checkout first on the path, ``--rounds`` times,
alternating, and each home keeps its fastest round.

    .venv/bin/python benchmarks/precompute.py --previous DIR [--repeat 3] [--homes 10] [--rounds 2]
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import statistics
import subprocess
import sys
import tempfile
import time
import tracemalloc
import warnings
from pathlib import Path

BUNDLED = ("3LDK_01", "3LDK_05", "3LDK_06", "albert-b")
KINDS = ("bundled", "plain", "furnished", "furnished, a door closed")


def write_homes(folder: Path, n: int) -> dict[str, list[str]]:
    """The generated homes as dataset folders under ``folder``, by kind (the bundled ones are loaded by name)."""
    import numpy as np

    from spcotmhp.datasets.synthetic import write_dataset
    from spcotmhp.datasets.synthetic_battery import battery_home
    from spcotmhp.datasets.synthetic_furniture import close_doors, furnish
    from spcotmhp.datasets.synthetic_plan import generate_floor_plan
    from spcotmhp.datasets.synthetic_walk import teaching_walk

    out: dict[str, list[str]] = {"bundled": list(BUNDLED), "plain": [], "furnished": [], "furnished, a door closed": []}
    for seed in range(n):
        for kind, furniture in (("plain", False), ("furnished", True)):
            path = folder / f"{kind}-{seed}"
            write_dataset(battery_home(seed, furniture=furniture), path)
            out[kind].append(str(path))
        rng = np.random.default_rng(seed)
        plan = generate_floor_plan("house", seed=rng)
        data = teaching_walk(plan, seed=rng)
        furnish(plan, rng)
        close_doors(plan, rng, 1)
        data.map = plan.map
        path = folder / f"closed-{seed}"
        write_dataset(data, path)
        out["furnished, a door closed"].append(str(path))
    return out


def measure(homes: dict[str, list[str]], repeat: int) -> dict[str, dict]:
    """Per home: the fastest build (s), field bytes, peak traced bytes, nodes in all regions, region graphs."""
    from spcotmhp.datasets.bundled import load_bundled
    from spcotmhp.datasets.loader import load_dataset
    from spcotmhp.learning.supervised import fit_supervised
    from spcotmhp.planning.graph_cache import GraphCache
    from spcotmhp.planning.planner import HierarchicalPlanner

    out = {}
    for kind, names in homes.items():
        for name in names:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                lang = "ja" if name == "albert-b" else "en"
                data = load_bundled(name, lang=lang) if kind == "bundled" else load_dataset(name, lang=lang)
            model = fit_supervised(data)
            best = cpu = float("inf")
            for _ in range(max(1, repeat)):
                c0, t0 = time.process_time(), time.perf_counter()
                planner = HierarchicalPlanner(model, cache=GraphCache())
                best = min(best, time.perf_counter() - t0)
                cpu = min(cpu, time.process_time() - c0)
            tracemalloc.start()
            planner = HierarchicalPlanner(model, cache=GraphCache())
            peak = tracemalloc.get_traced_memory()[1]
            tracemalloc.stop()
            graph = planner.graph
            regions = getattr(graph, "regions", {})
            out[name] = {
                "kind": kind,
                "seconds": best,
                "cpu": cpu,
                "field_bytes": graph.field_bytes,
                "peak_bytes": peak,
                "nodes": graph.n_nodes + sum(g.n_nodes for g in regions.values()),
                "regions": len(regions),
            }
    return out


def run_in(checkout: str, homes: dict[str, list[str]], repeat: int) -> dict[str, dict]:
    """:func:`measure` in a subprocess with ``checkout`` first on the path."""
    env = {**os.environ, "PYTHONPATH": os.path.abspath(checkout)}
    code = (
        f"import sys, json; sys.path.insert(0, {os.path.dirname(os.path.abspath(__file__))!r}); "
        f"import precompute as b; from spcotmhp.warmup import warm_up; warm_up(); "
        f"print(json.dumps(b.measure({homes!r}, {repeat})))"
    )
    done = subprocess.run(  # run from the checkout: "python -c" puts the working folder first on the path
        [sys.executable, "-c", code], env=env, cwd=os.path.abspath(checkout), capture_output=True, text=True, check=True
    )
    return json.loads(done.stdout.strip().splitlines()[-1])


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--previous", required=True, help="a checkout of an earlier version")
    parser.add_argument("--repeat", type=int, default=3, help="builds per home; the fastest is kept")
    parser.add_argument("--homes", type=int, default=10, help="generated homes of each kind")
    parser.add_argument("--rounds", type=int, default=2, help="alternated runs of each checkout; the fastest kept")
    args = parser.parse_args(argv)
    here = str(Path(__file__).resolve().parent.parent)
    with tempfile.TemporaryDirectory() as tmp:
        homes = write_homes(Path(tmp), args.homes)
        now, before = {}, {}
        for _ in range(args.rounds):  # alternated, so that a busy spell on the machine falls on both
            for out, checkout in ((now, here), (before, args.previous)):
                for name, row in run_in(checkout, homes, args.repeat).items():
                    if name not in out or row["seconds"] < out[name]["seconds"]:
                        out[name] = row
    print(
        f"machine: {platform.machine()}, {os.cpu_count()} logical CPUs, Python {platform.python_version()}; "
        f"load average {os.getloadavg()[0]:.1f} at the end; fastest of {args.repeat} builds x {args.rounds} rounds; "
        f"ratios: this checkout / {args.previous}"
    )
    print(
        "\n| homes | n | region graphs (median, max) | nodes: now / before | precompute s: now / before (ratio, "
        "median [max]) | CPU s: now / before (ratio, median [max]) | fields MiB: now / before (ratio max) "
        "| peak MiB: now / before (ratio max) |"
    )
    print("|---|---|---|---|---|---|---|---|")
    for kind in KINDS:
        names = [n for n in now if now[n]["kind"] == kind]
        a, b = [now[n] for n in names], [before[n] for n in names]
        t = [x["seconds"] / y["seconds"] for x, y in zip(a, b, strict=True)]
        c = [x["cpu"] / y["cpu"] for x, y in zip(a, b, strict=True)]
        f = [x["field_bytes"] / y["field_bytes"] for x, y in zip(a, b, strict=True)]
        p = [x["peak_bytes"] / y["peak_bytes"] for x, y in zip(a, b, strict=True)]
        regions = [x["regions"] for x in a]
        print(
            f"| {kind} | {len(names)} | {statistics.median(regions):g}, {max(regions)} | "
            f"{sum(x['nodes'] for x in a)} / {sum(y['nodes'] for y in b)} | "
            f"{sum(x['seconds'] for x in a):.3f} / {sum(y['seconds'] for y in b):.3f} "
            f"({statistics.median(t):.2f} [{max(t):.2f}]) | "
            f"{sum(x['cpu'] for x in a):.3f} / {sum(y['cpu'] for y in b):.3f} "
            f"({statistics.median(c):.2f} [{max(c):.2f}]) | "
            f"{sum(x['field_bytes'] for x in a) / 2**20:.1f} / {sum(y['field_bytes'] for y in b) / 2**20:.1f} "
            f"({max(f):.2f}) | {max(x['peak_bytes'] for x in a) / 2**20:.1f} / "
            f"{max(y['peak_bytes'] for y in b) / 2**20:.1f} ({max(p):.2f}) |"
        )
    return 0


if __name__ == "__main__":
    sys.exit(main())
