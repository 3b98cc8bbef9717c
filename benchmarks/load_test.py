"""Load test of the HTTP service: start `spcotmhp serve`, send plan requests at once, report latency percentiles.

    python benchmarks/load_test.py                    # the supervised 3LDK_06 model, 200 concurrent requests
    python benchmarks/load_test.py --model demo-output/model --requests 400 --concurrency 100

Requests cycle through six instructions (waypoints, avoidance, plain goals) from the free cell nearest each
place's mean. Baselines measured in the same run: the planner called in-process (no HTTP) and the same requests
over HTTP one at a time. Then the heavy-load scenario: ``--heavy-clients`` clients (20) send long instructions
without pause — ~1 KB sentences with many waypoints, and the longest legal ones (10 waypoints, under 500
characters) — while one client sends the normal requests one at a time; the normal requests' latency is
compared with their unloaded latency. Exits with status 1 if a normal request fails, or if the loaded median
exceeds the unloaded one by more than 200 ms.
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

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # the repository root: tests/helpers
from spcotmhp.commands.demo import demo_start
from spcotmhp.errors import SpcotmhpError
from spcotmhp.persistence.io import load_model
from spcotmhp.planning.planner import HierarchicalPlanner
from spcotmhp.viz.labels import place_display_labels
from tests.helpers.server import ServerProcess, supervised_model_dir

INSTRUCTIONS = [
    "go to the bedroom via the corridor",
    "go to the kitchen",
    "go to the bath avoiding the kitchen",
    "go to the living via the dining",
    "go to the toilet",
    "go to the bedroom avoiding the bath",
]


def workload(planner: HierarchicalPlanner, n: int) -> list[dict]:
    """n plan bodies: instructions x starts (the free cell nearest each place's mean), those with a path."""
    model = planner.model
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
        except SpcotmhpError:  # an infeasible combination is left out
            length = 0.0
        if length > 0:  # feasible and not already there
            bodies.append(body)
    return [bodies[i % len(bodies)] for i in range(n)]


def summary(name: str, latencies: list[float], errors: int, wall: float, baseline: float | None) -> str:
    q = np.percentile(np.array(latencies) * 1e3, [50, 95, 99]) if latencies else [float("nan")] * 3
    p50 = q[0]
    ratio = f"{p50 / baseline:9.1f}x" if baseline else "   (base)"
    return (
        f"{name:<34} {len(latencies) + errors:>5} {errors:>6} {q[0]:8.1f} {q[1]:8.1f} {q[2]:8.1f} "
        f"{(len(latencies) + errors) / wall:9.1f} {ratio}"
    )


async def one(client: httpx.AsyncClient, body: dict) -> tuple[float, bool]:
    t0 = time.perf_counter()
    try:
        r = await client.post("/plan", json=body)
        ok = r.status_code == 200 and len(r.json()["path"]) > 1  # every workload plan moves
    except httpx.HTTPError:
        ok = False
    return time.perf_counter() - t0, ok


async def run_http(url: str, bodies: list[dict], concurrency: int) -> tuple[list[float], int, float]:
    """``concurrency`` clients (httpx.AsyncClient, one keep-alive connection each: one shared pool of hundreds
    of connections makes httpcore itself the bottleneck) send the bodies, all at once; returns the latencies of
    the successful requests, the number of failures and the wall time."""
    clients = [
        httpx.AsyncClient(base_url=url, timeout=120.0, limits=httpx.Limits(max_connections=1))
        for _ in range(concurrency)
    ]
    try:

        async def lane(i: int, work: list[dict]) -> list[tuple[float, bool]]:
            return [await one(clients[i], body) for body in work]

        await asyncio.gather(*(one(c, bodies[0]) for c in clients))  # warm up: open the connections
        t0 = time.perf_counter()
        lanes = await asyncio.gather(*(lane(i, bodies[i::concurrency]) for i in range(concurrency)))
        wall = time.perf_counter() - t0
    finally:
        await asyncio.gather(*(c.aclose() for c in clients))
    results = [r for lane_results in lanes for r in lane_results]
    latencies = [t for t, ok in results if ok]
    return latencies, sum(not ok for _, ok in results), wall


def heavy_bodies(planner: HierarchicalPlanner, start: list[float]) -> list[dict]:
    """Long instructions: a ~1 KB sentence of many waypoints (over the service's length limit) and the longest
    legal ones (10 waypoints)."""
    words = [w for w in planner.place_words if w != "corridor"] or ["kitchen"]
    many = "go to the bedroom via the " + " and then the ".join(words[i % len(words)] for i in range(60))
    legal = "go to the bedroom via the " + ", then the ".join(words[i % len(words)] for i in range(10))
    return [{"instruction": many[:1100], "start": start}, {"instruction": legal[:495], "start": start}]


async def under_heavy_load(
    url: str, bodies: list[dict], heavy: list[dict], n_heavy: int
) -> tuple[list[float], int, dict[int, int]]:
    """Normal requests one at a time while ``n_heavy`` clients send ``heavy`` bodies without pause; returns the
    normal latencies, the normal failures and the heavy answers' status counts."""
    stop = asyncio.Event()
    statuses: dict[int, int] = {}

    async def hammer(i: int) -> None:
        async with httpx.AsyncClient(base_url=url, timeout=120.0) as c:
            k = i
            while not stop.is_set():
                try:
                    r = await c.post("/plan", json=heavy[k % len(heavy)])
                    statuses[r.status_code] = statuses.get(r.status_code, 0) + 1
                except httpx.HTTPError:
                    statuses[-1] = statuses.get(-1, 0) + 1
                k += 1

    tasks = [asyncio.create_task(hammer(i)) for i in range(n_heavy)]
    await asyncio.sleep(1.0)  # let the heavy load build up
    latencies, errors = [], 0
    async with httpx.AsyncClient(base_url=url, timeout=120.0) as c:
        for body in bodies:
            t, ok = await one(c, body)
            if ok:
                latencies.append(t)
            else:
                errors += 1
    stop.set()
    await asyncio.gather(*tasks)
    return latencies, errors, statuses


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--model", type=Path, help="model folder (default: supervised fit of 3LDK_06)")
    ap.add_argument("--requests", type=int, default=200)
    ap.add_argument("--concurrency", type=int, default=200)
    ap.add_argument("--heavy-clients", type=int, default=20)
    args = ap.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        model_dir = args.model or supervised_model_dir("3LDK_06", Path(tmp) / "3LDK_06")
        model = load_model(model_dir)
        planner = HierarchicalPlanner(model)
        bodies = workload(planner, args.requests)
        t0 = time.perf_counter()
        direct = []
        for body in bodies:
            t = time.perf_counter()
            planner.plan(body["instruction"], body["start"])
            direct.append(time.perf_counter() - t)
        direct_wall = time.perf_counter() - t0
        heavy = heavy_bodies(planner, bodies[0]["start"])
        with ServerProcess([str(model_dir)]) as server:
            seq = asyncio.run(run_http(server.url, bodies, 1))
            conc = asyncio.run(run_http(server.url, bodies, args.concurrency))
            loaded = asyncio.run(under_heavy_load(server.url, bodies[:100], heavy, args.heavy_clients))
    base = statistics.median(direct) * 1e3
    print(f"model {model_dir}: {len(set(map(str, bodies)))} distinct requests, {args.requests} per scenario")
    print(
        f"{'scenario':<34} {'reqs':>5} {'errors':>6} {'p50 ms':>8} {'p95 ms':>8} {'p99 ms':>8} "
        f"{'req/s':>9} {'p50/base':>10}"
    )
    print(summary("in-process planner.plan", direct, 0, direct_wall, None))
    print(summary("HTTP, 1 at a time", seq[0], seq[1], seq[2], base))
    print(summary(f"HTTP, {args.concurrency} concurrent", conc[0], conc[1], conc[2], base))
    quiet = statistics.median(seq[0]) * 1e3
    busy = statistics.median(loaded[0]) * 1e3 if loaded[0] else float("inf")
    p95 = float(np.percentile(np.array(loaded[0]) * 1e3, 95)) if loaded[0] else float("inf")
    print(
        f"normal /plan while {args.heavy_clients} clients send long instructions: median {busy:.1f} ms "
        f"(unloaded {quiet:.1f} ms, +{busy - quiet:.1f} ms), p95 {p95:.1f} ms, {loaded[1]} failed; "
        f"long instructions answered {dict(sorted(loaded[2].items()))}"
    )
    return 1 if seq[1] or conc[1] or loaded[1] or busy - quiet > 200 else 0


if __name__ == "__main__":
    sys.exit(main())
