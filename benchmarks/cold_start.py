"""Cold start: fresh processes that import the package, load a model folder, build the planner and plan one
instruction, timed stage by stage (import / load / precompute / first plan / total), median and max over runs.

    spcotmhp demo --out /tmp/demo_out
    python benchmarks/cold_start.py --model /tmp/demo_out/model --runs 10 [--cli] [--against /path/to/checkout ...]

``--floor`` adds a row for what spcotmhp cannot remove: a process that imports numpy and numba and calls one
kernel from numba's on-disk cache (the first cached kernel of any program loads numba's type registries, which
import scipy.linalg for numba's BLAS check), timed inside the process and as a whole process.

``--cli`` also times the command line as a user runs it, ``spcotmhp plan MODEL "..." --start X Y`` (``python -m
spcotmhp``; ``python -m spcotmhp.cli`` for a checkout without ``spcotmhp/__main__.py``): the whole process, wall
clock, from its start to its exit.

With ``--against`` the other checkouts' processes run in the same loop, alternating with this one, so both see
the same machine load. One untimed process per checkout comes first: it writes Python's bytecode (the runs
ignore ``PYTHONDONTWRITEBYTECODE``: an installed package has its bytecode) and fills numba's cache for the
checkout if it was empty (``spcotmhp warmup`` does that after installing).
"""

from __future__ import annotations

import argparse
import json
import os
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

STAGES = ("import", "load", "precompute", "first plan", "first cached kernel", "total")
CLI_STAGE = "cli process"
FLOOR_ROW = "floor: numpy + numba + one cached kernel (no spcotmhp)"

FLOOR_MODULE = """
from numba import njit


@njit(cache=True)
def add_one(x):
    return x + 1
"""

FLOOR_CHILD = """
import json, sys, time
t0 = time.perf_counter()
import numpy, numba
from floor_kernel import add_one
t1 = time.perf_counter()
add_one(1.0)
t2 = time.perf_counter()
print(json.dumps({"import": t1 - t0, "first cached kernel": t2 - t1, "total": t2 - t0}))
"""

CHILD = """
import json, sys, time
t0 = time.perf_counter()
if sys.argv[3] == "paused":
    from spcotmhp.collector import pause_for_startup
    pause_for_startup()
from spcotmhp.persistence.io import load_model
from spcotmhp.planning.planner import HierarchicalPlanner
t1 = time.perf_counter()
model = load_model(sys.argv[1])
t2 = time.perf_counter()
planner = HierarchicalPlanner(model)
t3 = time.perf_counter()
plan = planner.plan(sys.argv[2], start=tuple(model.mu[0]))
t4 = time.perf_counter()
print(json.dumps({"import": t1 - t0, "load": t2 - t1, "precompute": t3 - t2, "first plan": t4 - t3, "total": t4 - t0,
                  "start": [float(v) for v in model.mu[0]]}))
"""


def one_run(checkout: Path, model: str, instruction: str, paused: bool = False) -> dict:
    """The stage times (seconds) of one fresh process with ``checkout`` first on the path, and the start used;
    ``paused``: the script begins with ``spcotmhp.collector.pause_for_startup()`` (as the command line does)."""
    env = dict(os.environ, PYTHONPATH=str(checkout))
    env.pop("PYTHONDONTWRITEBYTECODE", None)  # an installed package has its bytecode; a checkout gets it on first run
    out = subprocess.run(
        [sys.executable, "-c", CHILD, model, instruction, "paused" if paused else "-"],
        env=env,
        cwd=str(checkout),
        capture_output=True,
        text=True,
        check=True,
    )
    return json.loads(out.stdout.strip().splitlines()[-1])


def cli_run(checkout: Path, model: str, instruction: str, start: list[float]) -> float:
    """Wall seconds of one ``spcotmhp plan`` process with ``checkout`` first on the path, start to exit."""
    env = dict(os.environ, PYTHONPATH=str(checkout))
    env.pop("PYTHONDONTWRITEBYTECODE", None)
    entry = "spcotmhp" if (checkout / "spcotmhp" / "__main__.py").exists() else "spcotmhp.cli"
    cmd = [sys.executable, "-m", entry, "plan", model, instruction, "--start", *(f"{v:.3f}" for v in start)]
    t0 = time.perf_counter()
    subprocess.run(cmd, env=env, cwd=str(checkout), capture_output=True, text=True, check=True)
    return time.perf_counter() - t0


def floor_run(folder: Path) -> dict:
    """The stage times of one fresh process that imports numpy and numba and calls one numba kernel from its
    on-disk cache (the first call loads numba's type registries, as the first of any cached kernel does), plus
    the process's wall time start to exit under ``CLI_STAGE``: what any program built on cached numba kernels
    pays before its own work."""
    env = dict(os.environ, PYTHONPATH=str(folder), NUMBA_CACHE_DIR=str(folder / "cache"))
    env.pop("PYTHONDONTWRITEBYTECODE", None)
    t0 = time.perf_counter()
    out = subprocess.run(
        [sys.executable, "-c", FLOOR_CHILD], env=env, cwd=str(folder), capture_output=True, text=True, check=True
    )
    run = json.loads(out.stdout.strip().splitlines()[-1])
    run[CLI_STAGE] = time.perf_counter() - t0
    return run


def table(results: dict[str, list[dict]]) -> str:
    """Markdown table: one row per checkout (or variant), each stage's median and max (ms); "-" where the row
    has no such stage."""
    stages = [s for s in (*STAGES, CLI_STAGE) if any(s in r for runs in results.values() for r in runs)]
    head = "| code | runs | " + " | ".join(f"{s} median / max (ms)" for s in stages) + " |"
    rows = [head, "|" + "---|" * (len(stages) + 2)]
    for name, runs in results.items():
        cells = []
        for s in stages:
            values = [r[s] * 1000 for r in runs if s in r]
            cells.append(f"{statistics.median(values):.0f} / {max(values):.0f}" if values else "-")
        rows.append(f"| {name} | {len(runs)} | " + " | ".join(cells) + " |")
    return "\n".join(rows)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--model", required=True, help="a model folder (spcotmhp demo --out DIR writes DIR/model)")
    parser.add_argument("--runs", type=int, default=10, help="fresh processes per checkout")
    parser.add_argument("--instruction", default="go to the bedroom via the corridor")
    parser.add_argument("--cli", action="store_true", help="also time `spcotmhp plan` as a whole process")
    parser.add_argument(
        "--paused", action="store_true", help="also time this checkout's script starting with pause_for_startup()"
    )
    parser.add_argument(
        "--floor", action="store_true", help="also time numpy + numba + one cached kernel alone (no spcotmhp)"
    )
    parser.add_argument("--against", nargs="+", default=[], help="other checkouts to time in the same run, alternating")
    args = parser.parse_args(argv)
    here = Path(__file__).resolve().parent.parent
    checkouts = {"this": here} | {str(Path(d).resolve()): Path(d).resolve() for d in args.against}
    for path in checkouts.values():
        one_run(path, args.model, args.instruction)  # untimed: writes the bytecode, fills numba's cache if empty
    results: dict[str, list[dict]] = {name: [] for name in checkouts}
    paused_row = "this, script starting with pause_for_startup()"
    if args.paused:
        results[paused_row] = []
    floor = Path(tempfile.mkdtemp(prefix="spcotmhp-floor-")) if args.floor else None
    if floor is not None:
        (floor / "floor_kernel.py").write_text(FLOOR_MODULE)
        floor_run(floor)  # untimed: compiles the kernel into its cache
        results[FLOOR_ROW] = []
    for _ in range(args.runs):
        for name, path in checkouts.items():
            run = one_run(path, args.model, args.instruction)
            if args.cli:
                run[CLI_STAGE] = cli_run(path, args.model, args.instruction, run.pop("start"))
            results[name].append(run)
        if args.paused:
            results[paused_row].append(one_run(here, args.model, args.instruction, paused=True))
        if floor is not None:
            results[FLOOR_ROW].append(floor_run(floor))
    if floor is not None:
        shutil.rmtree(floor, ignore_errors=True)
    print(f"load average (1 min) at the end: {os.getloadavg()[0]:.2f}")
    print(table(results))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
