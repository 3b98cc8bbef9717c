"""Load test of the HTTP service: start `spcotmhp serve`, send plan requests at once, report latency percentiles.

    python benchmarks/load_test.py                    # the supervised 3LDK_06 model, 200 concurrent requests
    python benchmarks/load_test.py --model demo-output/model --requests 400 --concurrency 100

Requests cycle through six instructions (waypoints, avoidance, plain goals) from the free cell nearest each
place's mean. Baselines measured in the same run: the planner called in-process (no HTTP) and the same requests
over HTTP one at a time. Exits with status 1 if any request fails.
"""

from __future__ import annotations

import argparse
import asyncio
import statistics
import sys
import tempfile
import time
from pathlib import Path

import httpx
import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))
from server_fixtures import ServerProcess, supervised_model_dir

from spcotmhp.commands.demo import demo_start
from spcotmhp.errors import SpcotmhpError
from spcotmhp.learning.io import load_model
from spcotmhp.planning.planner import HierarchicalPlanner
from spcotmhp.viz.labels import place_display_labels

INSTRUCTIONS = ["go to the bedroom via the corridor", "go to the kitchen", "go to the bath avoiding the kitchen",
                "go to the living via the dining", "go to the toilet", "go to the bedroom avoiding the bath"]


def workload(model, n: int) -> list[dict]:
    """n plan bodies: instructions x starts (the free cell nearest each place's mean), those with a path."""
    planner = HierarchicalPlanner(model)
    labels = place_display_labels(model)
    starts = []
    for k in np.flatnonzero(model.active_places):
        xy, _ = demo_start(planner, labels[k].split(" #")[0])
        starts.append([round(float(v), 3) for v in xy])
    bodies = []
    for i in range(len(INSTRUCTIONS) * len(starts)):
        body = {"instruction": INSTRUCTIONS[i % len(INSTRUCTIONS)], "start": starts[i // len(INSTRUCTIONS)]}
        try:
            length = planner.plan(body["instruction"], body["start"]).length_m
        except SpcotmhpError:                            # an infeasible combination is left out
            length = 0.0
        if length > 0:                                   # feasible and not already there
            bodies.append(body)
    return [bodies[i % len(bodies)] for i in range(n)]


def summary(name: str, latencies: list[float], errors: int, wall: float, baseline: float | None) -> str:
    q = np.percentile(np.array(latencies) * 1e3, [50, 95, 99]) if latencies else [float("nan")] * 3
    p50 = q[0]
    ratio = f"{p50 / baseline:9.1f}x" if baseline else "   (base)"
    return (f"{name:<34} {len(latencies) + errors:>5} {errors:>6} {q[0]:8.1f} {q[1]:8.1f} {q[2]:8.1f} "
            f"{(len(latencies) + errors) / wall:9.1f} {ratio}")


async def one(client: httpx.AsyncClient, body: dict) -> tuple[float, bool]:
    t0 = time.perf_counter()
    try:
        r = await client.post("/plan", json=body)
        ok = r.status_code == 200 and len(r.json()["path"]) > 1         # every workload plan moves
    except httpx.HTTPError:
        ok = False
    return time.perf_counter() - t0, ok


async def run_http(url: str, bodies: list[dict], concurrency: int) -> tuple[list[float], int, float]:
    """``concurrency`` clients (httpx.AsyncClient, one keep-alive connection each: one shared pool of hundreds
    of connections makes httpcore itself the bottleneck) send the bodies, all at once; returns the latencies of
    the successful requests, the number of failures and the wall time."""
    clients = [httpx.AsyncClient(base_url=url, timeout=120.0, limits=httpx.Limits(max_connections=1))
               for _ in range(concurrency)]
    try:
        async def lane(i: int, work: list[dict]) -> list[tuple[float, bool]]:
            return [await one(clients[i], body) for body in work]

        await asyncio.gather(*(one(c, bodies[0]) for c in clients))           # warm up: open the connections
        t0 = time.perf_counter()
        lanes = await asyncio.gather(*(lane(i, bodies[i::concurrency]) for i in range(concurrency)))
        wall = time.perf_counter() - t0
    finally:
        await asyncio.gather(*(c.aclose() for c in clients))
    results = [r for lane_results in lanes for r in lane_results]
    latencies = [t for t, ok in results if ok]
    return latencies, sum(not ok for _, ok in results), wall


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--model", type=Path, help="model folder (default: supervised fit of 3LDK_06)")
    ap.add_argument("--requests", type=int, default=200)
    ap.add_argument("--concurrency", type=int, default=200)
    args = ap.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        model_dir = args.model or supervised_model_dir("3LDK_06", Path(tmp) / "3LDK_06")
        model = load_model(model_dir)
        bodies = workload(model, args.requests)
        planner = HierarchicalPlanner(model)
        t0 = time.perf_counter()
        direct = []
        for body in bodies:
            t = time.perf_counter()
            planner.plan(body["instruction"], body["start"])
            direct.append(time.perf_counter() - t)
        direct_wall = time.perf_counter() - t0
        with ServerProcess([str(model_dir)]) as server:
            seq = asyncio.run(run_http(server.url, bodies, 1))
            conc = asyncio.run(run_http(server.url, bodies, args.concurrency))
    base = statistics.median(direct) * 1e3
    print(f"model {model_dir}: {len(set(map(str, bodies)))} distinct requests, {args.requests} per scenario")
    print(f"{'scenario':<34} {'reqs':>5} {'errors':>6} {'p50 ms':>8} {'p95 ms':>8} {'p99 ms':>8} "
          f"{'req/s':>9} {'p50/base':>10}")
    print(summary("in-process planner.plan", direct, 0, direct_wall, None))
    print(summary("HTTP, 1 at a time", seq[0], seq[1], seq[2], base))
    print(summary(f"HTTP, {args.concurrency} concurrent", conc[0], conc[1], conc[2], base))
    return 1 if seq[1] or conc[1] else 0


if __name__ == "__main__":
    sys.exit(main())
