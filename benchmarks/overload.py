"""Overload of the HTTP service: N clients send /plan without pause; latency and the share shed with 503.

    python benchmarks/overload.py                     # the supervised 3LDK_06 model; 10, 50 and 100 clients, 10 s
    python benchmarks/overload.py --clients 10,100 --seconds 20 --max-wait 0.25
    python benchmarks/overload.py --cpu-hogs 1       # with a busy process taking a core: outside CPU load

Each client (one keep-alive connection) sends the next plan as soon as the last one is answered (after a 503, once
its Retry-After has passed, unless ``--impolite``), for ``--seconds`` after a warm-up, from the workload of
``load_test.py`` (six instructions from the free cell nearest each place). The table gives, per number of clients,
the answers by status, the p50 / p99 latency of every answer and of the 200s alone, the share shed (503, with
Retry-After), split into those shed at once (the estimate) and at their turn (the deadline), the p99 of the wait
the server measured for its 200s (their ``Server-Timing``) and the plans served per second; the first row (one
client) is the baseline the ratios are against. The service's promise (docs/speed.md, "Under overload"): every
answer is a 200 or a 503, and a 200 started planning within ``--max-wait`` seconds of the server's reading it (or
had no plan ahead of it).
"""

from __future__ import annotations

import argparse
import asyncio
import re
import subprocess
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

Answer = tuple[int, float, str]  # status (-1: a transport error), seconds, how: "", "at once", "deadline", "q=<ms>"


def _how(r: httpx.Response) -> str:
    if r.status_code == 200:
        found = re.match(r"queue;dur=([0-9.]+)", r.headers.get("server-timing", ""))
        return f"q={found.group(1)}" if found else ""
    if r.status_code == 503:
        detail = r.json().get("detail", "")
        return "at once" if "expected to take" in detail else ("deadline" if "plans ahead of it" in detail else "")
    return ""


async def closed_loop(url: str, bodies: list[dict], clients: int, seconds: float, polite: bool = True) -> list[Answer]:
    """(status, seconds, how) of every answer ``clients`` clients got in ``seconds``; a ``polite`` client waits as
    a 503's Retry-After says before its next request."""
    stop = time.perf_counter() + seconds
    answers: list[Answer] = []

    async def client(i: int) -> None:
        async with httpx.AsyncClient(base_url=url, timeout=60.0, limits=httpx.Limits(max_connections=1)) as c:
            await c.get("/healthz")  # open the connection before the clock starts
            await start.wait()
            k = i
            while time.perf_counter() < stop:
                t0 = time.perf_counter()
                retry, how = 0.0, ""
                try:
                    r = await c.post("/plan", json=bodies[k % len(bodies)])
                    status, how = r.status_code, _how(r)
                    if status == 503 and polite:
                        retry = float(r.headers.get("retry-after", 1))
                except httpx.HTTPError:
                    status = -1
                answers.append((status, time.perf_counter() - t0, how))
                k += 1
                await asyncio.sleep(retry)  # a polite client waits as Retry-After says

    start = asyncio.Event()
    tasks = [asyncio.create_task(client(i)) for i in range(clients)]
    await asyncio.sleep(0.5)
    stop = time.perf_counter() + seconds
    start.set()
    await asyncio.gather(*tasks)
    return answers


def row(clients: int, answers: list[Answer], seconds: float, base: float | None) -> str:
    times = np.array([t for _, t, _ in answers]) * 1e3
    ok = np.array([t for s, t, _ in answers if s == 200]) * 1e3
    waits = np.array([float(h[2:]) for s, _, h in answers if s == 200 and h.startswith("q=")])
    counts = Counter(s for s, _, _ in answers)
    hows = Counter(h for _, _, h in answers)
    q99 = np.percentile(waits, 99) if len(waits) else np.nan
    p50, p99 = np.percentile(times, [50, 99]) if len(times) else (np.nan, np.nan)
    ok50, ok99 = np.percentile(ok, [50, 99]) if len(ok) else (np.nan, np.nan)
    shed = counts.get(503, 0) / max(len(answers), 1)
    ratio = f"{ok99 / base:8.1f}x" if base else "  (base)"
    other = sum(n for s, n in counts.items() if s not in (200, 503))
    return (
        f"{clients:>7} {len(answers):>7} {counts.get(200, 0):>6} {counts.get(503, 0):>6} {other:>6} "
        f"{p50:8.1f} {p99:8.1f} {ok50:8.1f} {ok99:8.1f} {shed:7.1%} {hows['at once']:>7} {hows['deadline']:>8} "
        f"{q99:8.1f} {counts.get(200, 0) / seconds:8.1f} {ratio}"
    )


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--model", type=Path, help="model folder (default: supervised fit of 3LDK_06)")
    ap.add_argument("--clients", default="10,50,100", help="comma-separated numbers of clients")
    ap.add_argument("--seconds", type=float, default=10.0, help="seconds each load lasts")
    ap.add_argument("--max-wait", type=float, default=1.0, help="the server's --max-wait (seconds)")
    ap.add_argument("--impolite", action="store_true", help="clients ignore Retry-After (retry at once)")
    ap.add_argument("--cpu-hogs", type=int, default=0, help="busy processes run during the loads (outside CPU load)")
    args = ap.parse_args()
    levels = [int(n) for n in args.clients.split(",")]
    with tempfile.TemporaryDirectory() as tmp:
        model_dir = args.model or supervised_model_dir("3LDK_06", Path(tmp) / "3LDK_06")
        bodies = workload(HierarchicalPlanner(load_model(model_dir)), 60)
        hogs = [subprocess.Popen([sys.executable, "-c", "while True: pass"]) for _ in range(args.cpu_hogs)]
        try:
            with ServerProcess([str(model_dir), "--max-wait", str(args.max_wait)]) as server:
                results = [
                    (n, asyncio.run(closed_loop(server.url, bodies, n, args.seconds, not args.impolite)))
                    for n in [1, *levels]
                ]
                alive = httpx.get(server.url + "/healthz", timeout=10).status_code
        finally:
            for hog in hogs:
                hog.kill()
                hog.wait()
    print(
        f"model {model_dir}: --max-wait {args.max_wait:g} s, {args.seconds:g} s per load, {args.cpu_hogs} CPU "
        "hog(s); latencies in ms; at once / deadline: 503s of the estimate / of the lane's deadline; wait p99: the "
        "server's measured wait of its 200s; ratio: p99 of the 200s / 1 client's"
    )
    print(
        f"{'clients':>7} {'answers':>7} {'200':>6} {'503':>6} {'other':>6} {'p50':>8} {'p99':>8} {'200 p50':>8} "
        f"{'200 p99':>8} {'shed':>7} {'at once':>7} {'deadline':>8} {'wait p99':>8} {'plans/s':>8} {'ratio':>9}"
    )
    ok = np.array([t for s, t, _ in results[0][1] if s == 200]) * 1e3
    base = float(np.percentile(ok, 99)) if len(ok) else None
    for n, answers in results:
        print(row(n, answers, args.seconds, None if n == 1 else base))
    print(f"/healthz after the loads: {alive}")
    bad = sum(s not in (200, 503) for _, answers in results for s, _, _ in answers)
    return 1 if bad or alive != 200 else 0


if __name__ == "__main__":
    sys.exit(main())
