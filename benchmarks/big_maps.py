"""Big maps at once (issue 35, item 4): learn + precompute once, then each `plan` command loads the planning graph,
measured beside the previous version in the same run.

    python benchmarks/big_maps.py --previous /tmp/prev [--sides 1300 2600 4000] [--rooms 200] [--work DIR]
        [--memory-limit 12]

For each map side (1300, 2600 and 4000 cells at 0.1 m: 1.7, 6.8 and 16 megapixels) a synthetic office with
``--rooms`` places (``spcotmhp synth office``, the same dataset for both versions), then, for this checkout and
the ``--previous`` one (a checkout of the code before, e.g. ``git worktree add /tmp/prev <commit>``), each as a
fresh process of its own command line (``python -m spcotmhp``):

* ``learn DATASET --supervised``: the fit from the truth labels (which the places come from; the Gibbs learner's
  time does not depend on the map size) and, in this checkout, the planning graph saved with the model;
* ``plan MODEL "go to the office" --start X Y`` (from the teaching walk's first pose), twice (the first fills
  the page cache): the second's wall time and peak resident memory (``os.wait4``'s rusage of the child), its
  setup (the precomputation, or the graph's loading, as the command prints it) and its warm plan (the same plan
  again in the same process, as the command prints it). A plan command taking over a minute runs once.

Each command's CPU time (user + system, ``os.wait4``'s rusage) is printed beside its wall time: on a machine
shared with other jobs the wall time grows with their load, the CPU time far less.

Every process runs under an address-space limit of ``--memory-limit`` GiB (``RLIMIT_AS``), so that a version
needing more fails alone, with its row saying so, instead of taking the machine's memory from everything else.
Untimed, per checkout first: ``compileall`` of the package (this machine sets ``PYTHONDONTWRITEBYTECODE``, so
without it every command compiles the package's sources again), ``spcotmhp warmup`` (every numba kernel,
the portal graph's too, into the cache: without it the first big map pays tens of seconds of compiling, which
is what made an earlier run's 1.7-megapixel learn 157 s), and a learn and plan on a small office (the graph's
saving and loading). ``--reuse-models``: keep a model folder already in ``--work`` (its learn is not
measured again: "reused"), e.g. for a 16-megapixel row whose previous version was learned in an earlier run.
``--this``: the checkout measured as this version (default: the one holding this script; a separate worktree
keeps edits made during a long run out of it). Prints a markdown table (progress on stderr).
"""

from __future__ import annotations

import argparse
import os
import re
import resource
import subprocess
import sys
import tempfile
import time
from pathlib import Path

HERE = Path(__file__).resolve().parents[1]
TARGETS = {"learn": (60.0, 4.0), "plan": (1.5, 1.0), "warm": 0.005}  # issue 35: s, GiB at 16 megapixels


def run(code: Path, args: list[str], limit_gib: float) -> dict:
    """Run ``python -m spcotmhp ARGS`` from checkout ``code``; wall time, CPU time (user + system, which other
    jobs on the machine inflate far less than the wall time), peak RSS (GiB), exit status, output."""

    def limit() -> None:
        cap = int(limit_gib * 2**30)
        resource.setrlimit(resource.RLIMIT_AS, (cap, cap))

    env = {**os.environ, "PYTHONPATH": str(code), "PYTHONDONTWRITEBYTECODE": "1"}
    t0 = time.perf_counter()
    with tempfile.TemporaryFile() as log:
        proc = subprocess.Popen(
            [sys.executable, "-m", "spcotmhp", *args],
            cwd=code,
            env=env,
            stdout=log,
            stderr=subprocess.STDOUT,
            preexec_fn=limit,
        )
        _, status, usage = os.wait4(proc.pid, 0)  # this child's own rusage (its peak RSS)
        wall = time.perf_counter() - t0
        proc.returncode = os.waitstatus_to_exitcode(status)
        log.seek(0)
        out = log.read().decode(errors="replace")
    cpu = usage.ru_utime + usage.ru_stime
    return {"wall": wall, "cpu": cpu, "peak": usage.ru_maxrss / 2**20, "rc": proc.returncode, "out": out}


def first_pose(dataset: Path) -> tuple[str, str]:
    rows = (dataset / "trajectory.csv").read_text().splitlines()
    _, x, y = rows[1].split(",")[:3]
    return x, y


def warm(code: Path, limit: float) -> None:
    """The untimed start of each checkout (module docstring)."""
    subprocess.run([sys.executable, "-m", "compileall", "-q", str(code / "spcotmhp")], check=False)
    run(code, ["warmup"], limit)


def measure(code: Path, dataset: Path, model: Path, limit: float, reuse: bool = False) -> dict:
    """learn, then plan twice (module docstring)."""
    if reuse and (model / "manifest.json").is_file():
        learn = {"wall": 0.0, "cpu": 0.0, "peak": 0.0, "rc": 0, "out": "", "reused": True}
    else:
        learn = run(code, ["learn", str(dataset), "--supervised", "--out", str(model), "--overwrite"], limit)
    if learn["rc"] != 0:
        return {"learn": learn, "plan": None}
    x, y = first_pose(dataset)
    args = ["plan", str(model), "go to the office", "--start", x, y]
    first = run(code, args, limit)
    if first["rc"] != 0 or first["wall"] > 60:  # failed, or so long that the page cache is not what it measures
        return {"learn": learn, "plan": first}
    return {"learn": learn, "plan": run(code, args, limit)}


def parse_plan(out: str) -> tuple[float | None, float | None]:
    """(setup s, warm plan s) from the plan command's last line."""
    warm = re.search(r"planned in ([0-9.]+) ms warm", out)
    setup = re.search(r"loaded from the model folder in ([0-9.]+) s", out) or re.search(
        r"precomputation ([0-9.]+) s", out
    )
    return (float(setup.group(1)) if setup else None), (float(warm.group(1)) / 1e3 if warm else None)


def row(side: int, version: str, m: dict) -> str:
    learn, plan = m["learn"], m["plan"]
    mp = side * side / 1e6
    if learn["rc"] != 0:
        return f"| {mp:.1f} | {version} | failed (exit {learn['rc']}, {learn['peak']:.2f} GiB) | | | | |"
    learned = (
        "reused"
        if learn.get("reused")
        else f"{learn['wall']:.1f} s ({learn['cpu']:.1f} CPU s), {learn['peak']:.2f} GiB"
    )
    if plan is None or plan["rc"] != 0:
        why = "out of memory" if plan and "MemoryError" in plan["out"] else f"exit {plan['rc'] if plan else '?'}"
        wall = f"failed: {why} after {plan['wall']:.0f} s" if plan else "failed"
        return f"| {mp:.1f} | {version} | {learned} | {wall} | {plan['peak']:.2f} GiB | | |" if plan else ""
    setup, warm = parse_plan(plan["out"])
    setup_text = f"{setup:.2f} s" if setup is not None else "?"
    warm_text = f"{warm * 1e3:.2f} ms" if warm is not None else "?"
    planned = f"{plan['wall']:.2f} s ({plan['cpu']:.2f} CPU s) | {plan['peak']:.2f} GiB"
    return f"| {mp:.1f} | {version} | {learned} | {planned} | {setup_text} | {warm_text} |"


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--previous", type=Path, required=True, help="checkout of the previous version")
    ap.add_argument("--this", type=Path, default=HERE, help="checkout of this version (default: this script's)")
    ap.add_argument("--sides", type=int, nargs="+", default=[1300, 2600, 4000])
    ap.add_argument("--rooms", type=int, default=200)
    ap.add_argument("--work", type=Path, default=Path("/tmp/big_maps"))
    ap.add_argument("--memory-limit", type=float, default=12.0, help="GiB of address space per process")
    ap.add_argument("--reuse-models", action="store_true", help="keep model folders already in --work")
    args = ap.parse_args(argv)
    args.work.mkdir(parents=True, exist_ok=True)
    versions = {"this": args.this.resolve(), "previous": args.previous.resolve()}
    rows = []
    for version, code in versions.items():
        print(f"warming up {version}", file=sys.stderr, flush=True)
        warm(code, args.memory_limit)
    for side in [600, *args.sides]:
        dataset = args.work / f"office{side}"
        if not (dataset / "teaching.csv").is_file():
            rooms = str(min(args.rooms, 60) if side == 600 else args.rooms)
            synth = ["synth", "office", "--rooms", rooms, "--size", str(side), "--out", str(dataset)]
            run(HERE, [*synth, "--overwrite"], args.memory_limit)
        for version, code in versions.items():
            print(f"{side} x {side}: {version}", file=sys.stderr, flush=True)
            m = measure(code, dataset, args.work / f"model{side}-{version}", args.memory_limit, args.reuse_models)
            if side == 600 and side not in args.sides:
                continue  # the warm-up (module docstring)
            rows.append(row(side, version, m))
            print(rows[-1], file=sys.stderr, flush=True)
    print(f"Synthetic offices, {args.rooms} places, 0.1 m cells; each process limited to {args.memory_limit:g} GiB.")
    print()
    print(
        "| megapixels | version | learn (+ precompute): wall (CPU), peak RSS | plan command: wall (CPU) | peak RSS "
        "| setup "
        "| warm plan |"
    )
    print("|---|---|---|---|---|---|---|")
    print("\n".join(rows))
    learn_t, learn_m = TARGETS["learn"]
    plan_t, plan_m = TARGETS["plan"]
    print(
        f"\nTargets at 16 megapixels: learn + precompute <= {learn_t:.0f} s and <= {learn_m:.0f} GiB; each plan "
        f"command <= {plan_t} s and <= {plan_m:.0f} GiB; warm plan <= {TARGETS['warm'] * 1e3:.0f} ms."
    )
    return 0


if __name__ == "__main__":
    sys.exit(main())
