"""Overload of the HTTP service: N clients send /plan without pause; latency and the share shed with 503.

    python benchmarks/overload.py                     # the supervised 3LDK_06 model; 10, 50 and 100 clients, 10 s
    python benchmarks/overload.py --clients 10,100 --seconds 20 --max-wait 0.25

Each client (one keep-alive connection) sends the next plan as soon as the last one is answered (after a 503, once
its Retry-After has passed, unless ``--impolite``), for ``--seconds`` after a warm-up, from the workload of
``load_test.py`` (six instructions from the free cell nearest each place). The table gives, per number of clients,
the answers by status, the p50 / p99 latency of every answer and of the 200s alone, the share shed (503, with
Retry-After) and the plans served per second; the first row (one client) is the baseline the ratios are against.
The service's promise (docs/speed.md, "Under overload"): every answer is a 200 or a 503, and a request is admitted
only when the requests ahead of it are expected to be answered within ``--max-wait`` seconds.
"""

from __future__ import annotations

import argparse
import asyncio
import sys
import tempfile
import time
from collections import Counter
from pathlib import Path

import httpx
import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # the repository root: tests/helpers
sys.path.insert(0, str(Path(__file__).resolve().parent))  # load_test's workload
from load_test import workload  # noqa: E402

from spcotmhp.persistence.io import load_model  # noqa: E402
from spcotmhp.planning.planner import HierarchicalPlanner  # noqa: E402
from tests.helpers.server import ServerProcess, supervised_model_dir  # noqa: E402


async def closed_loop(
    url: str, bodies: list[dict], clients: int, seconds: float, polite: bool = True
) -> list[tuple[int, float]]:
    """(status, seconds) of every answer ``clients`` clients got in ``seconds`` (-1: a transport error); a
    ``polite`` client waits as a 503's Retry-After says before its next request."""
    stop = time.perf_counter() + seconds
    answers: list[tuple[int, float]] = []

    async def client(i: int) -> None:
        async with httpx.AsyncClient(base_url=url, timeout=60.0, limits=httpx.Limits(max_connections=1)) as c:
            await c.get("/healthz")  # open the connection before the clock starts
            await start.wait()
            k = i
            while time.perf_counter() < stop:
                t0 = time.perf_counter()
                retry = 0.0
                try:
                    r = await c.post("/plan", json=bodies[k % len(bodies)])
                    status = r.status_code
                    if status == 503 and polite:
                        retry = float(r.headers.get("retry-after", 1))
                except httpx.HTTPError:
                    status = -1
                answers.append((status, time.perf_counter() - t0))
                k += 1
                await asyncio.sleep(retry)  # a polite client waits as Retry-After says

    start = asyncio.Event()
    tasks = [asyncio.create_task(client(i)) for i in range(clients)]
    await asyncio.sleep(0.5)
    stop = time.perf_counter() + seconds
    start.set()
    await asyncio.gather(*tasks)
    return answers


def row(clients: int, answers: list[tuple[int, float]], seconds: float, base: float | None) -> str:
    times = np.array([t for _, t in answers]) * 1e3
    ok = np.array([t for s, t in answers if s == 200]) * 1e3
    counts = Counter(s for s, _ in answers)
    p50, p99 = np.percentile(times, [50, 99]) if len(times) else (np.nan, np.nan)
    ok50, ok99 = np.percentile(ok, [50, 99]) if len(ok) else (np.nan, np.nan)
    shed = counts.get(503, 0) / max(len(answers), 1)
    ratio = f"{ok99 / base:8.1f}x" if base else "  (base)"
    other = sum(n for s, n in counts.items() if s not in (200, 503))
    return (
        f"{clients:>7} {len(answers):>7} {counts.get(200, 0):>6} {counts.get(503, 0):>6} {other:>6} "
        f"{p50:8.1f} {p99:8.1f} {ok50:8.1f} {ok99:8.1f} {shed:7.1%} {counts.get(200, 0) / seconds:8.1f} {ratio}"
    )


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--model", type=Path, help="model folder (default: supervised fit of 3LDK_06)")
    ap.add_argument("--clients", default="10,50,100", help="comma-separated numbers of clients")
    ap.add_argument("--seconds", type=float, default=10.0, help="seconds each load lasts")
    ap.add_argument("--max-wait", type=float, default=1.0, help="the server's --max-wait (seconds)")
    ap.add_argument("--impolite", action="store_true", help="clients ignore Retry-After (retry at once)")
    args = ap.parse_args()
    levels = [int(n) for n in args.clients.split(",")]
    with tempfile.TemporaryDirectory() as tmp:
        model_dir = args.model or supervised_model_dir("3LDK_06", Path(tmp) / "3LDK_06")
        bodies = workload(HierarchicalPlanner(load_model(model_dir)), 60)
        with ServerProcess([str(model_dir), "--max-wait", str(args.max_wait)]) as server:
            results = [
                (n, asyncio.run(closed_loop(server.url, bodies, n, args.seconds, not args.impolite)))
                for n in [1, *levels]
            ]
            alive = httpx.get(server.url + "/healthz", timeout=10).status_code
    print(
        f"model {model_dir}: --max-wait {args.max_wait:g} s, {args.seconds:g} s per load; latencies in ms; "
        "ratio: p99 of the 200s / 1 client's"
    )
    print(
        f"{'clients':>7} {'answers':>7} {'200':>6} {'503':>6} {'other':>6} {'p50':>8} {'p99':>8} {'200 p50':>8} "
        f"{'200 p99':>8} {'shed':>7} {'plans/s':>8} {'ratio':>9}"
    )
    ok = np.array([t for s, t in results[0][1] if s == 200]) * 1e3
    base = float(np.percentile(ok, 99)) if len(ok) else None
    for n, answers in results:
        print(row(n, answers, args.seconds, None if n == 1 else base))
    print(f"/healthz after the loads: {alive}")
    bad = sum(s not in (200, 503) for _, answers in results for s, _ in answers)
    return 1 if bad or alive != 200 else 0


if __name__ == "__main__":
    sys.exit(main())
