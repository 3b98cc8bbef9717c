"""What the service promises under overload (issue 37; docs/speed.md, "Under overload"): a plan request is refused
at once with 503 Overloaded and a Retry-After when the requests ahead of it are expected to take longer than
``Budget.max_wait``; every answer under 100 concurrent clients is a 200 or a 503, and the service keeps serving.
Behaviour is asserted, not timing (the machine is shared): the estimate is driven by a hand clock in the unit tests."""

from __future__ import annotations

import asyncio
import json
import math

import httpx
import pytest

from spcotmhp.persistence.io import load_model
from spcotmhp.server import overload
from spcotmhp.server.overload import SMOOTHING, LoadEstimate, OverloadGuard
from tests.helpers.server import INSTRUCTION, ServerProcess, start_near, supervised_model_dir


def test_the_estimate_is_the_answer_interval_times_the_requests_ahead(monkeypatch):
    clock = iter([0.0, 0.1, 0.3, 0.5, 0.6, 10.0, 10.2, 10.3])
    monkeypatch.setattr(overload.time, "perf_counter", lambda: next(clock))
    load = LoadEstimate()
    assert load.expected_wait() == 0.0  # nothing timed, nothing ahead
    a, b, c = load.enter(), load.enter(), load.enter()  # at 0.0, 0.1, 0.3
    load.leave(a)  # at 0.5, alone before: its own time, 0.5 s
    assert load.interval == 0.5 and load.in_flight == 2
    load.leave(b)  # at 0.6, others waiting and b entered before the last answer: the interval, 0.1 s
    assert math.isclose(load.interval, 0.5 + SMOOTHING * (0.1 - 0.5))
    assert math.isclose(load.expected_wait(), 1 * load.interval)
    before = load.interval
    load.leave(c)  # at 10.0: nobody else in flight, so its own time (9.7 s)
    assert math.isclose(load.interval, before + SMOOTHING * (9.7 - before)) and load.in_flight == 0
    assert load.expected_wait() == 0.0  # nothing ahead: always admitted
    e = load.enter()  # at 10.2, after a pause: the next answer is timed from its own entry, not the idle time
    load.leave(e)
    assert load.interval < 2.0


def _scope(path: str, method: str = "POST") -> dict:
    return {"type": "http", "method": method, "path": path, "headers": []}


def test_the_guard_sheds_a_plan_expected_to_wait_past_the_bound():
    seen: list[str] = []

    async def app(scope, receive, send):
        seen.append(scope["path"])

    guard = OverloadGuard(app, max_wait=1.0)
    guard.load.in_flight, guard.load.interval = 10, 0.25  # 2.5 s ahead
    sent: list[dict] = []

    async def send(message):
        sent.append(message)

    asyncio.run(guard(_scope("/plan"), None, send))
    assert sent[0]["status"] == 503 and dict(sent[0]["headers"])[b"retry-after"] == b"3" and not seen
    answer = json.loads(sent[1]["body"])
    assert answer["cause"] == "Overloaded" and "expected to take 2.5 s" in answer["detail"]
    asyncio.run(guard(_scope("/healthz", "GET"), None, send))  # only plan requests are guarded
    asyncio.run(guard(_scope("/teach"), None, send))
    assert seen == ["/healthz", "/teach"]
    guard.load.in_flight = 4  # 1.0 s ahead: within the bound
    asyncio.run(guard(_scope("/plan"), None, send))
    assert seen[-1] == "/plan" and guard.load.in_flight == 4


@pytest.fixture(scope="module")
def folder(tmp_path_factory):
    return supervised_model_dir("3LDK_06", tmp_path_factory.mktemp("m") / "3LDK_06")


async def _flood(url: str, body: dict, clients: int, each: int) -> list[httpx.Response]:
    async def client() -> list[httpx.Response]:
        async with httpx.AsyncClient(base_url=url, timeout=120.0, limits=httpx.Limits(max_connections=1)) as c:
            return [await c.post("/plan", json=body) for _ in range(each)]

    return [r for rs in await asyncio.gather(*(client() for _ in range(clients))) for r in rs]


def test_under_100_concurrent_clients_every_answer_is_200_or_503_and_the_server_keeps_serving(folder):
    """A real `spcotmhp serve` (uvicorn on 127.0.0.1) with a tiny --max-wait, so that it sheds; 100 clients send
    three plans each at once."""
    body = {"instruction": INSTRUCTION, "start": start_near(load_model(folder))}
    with ServerProcess([str(folder), "--max-wait", "0.001"]) as server:
        answers = asyncio.run(_flood(server.url, body, 100, 3))
        after = httpx.post(server.url + "/plan", json=body, timeout=60)
        alive = httpx.get(server.url + "/healthz", timeout=10)
        log = server.output_tail()
    statuses = [a.status_code for a in answers]
    assert len(answers) == 300 and set(statuses) <= {200, 503}, sorted(set(statuses))
    assert 200 in statuses  # the first plan is always admitted: nothing is ahead of it
    for a in answers:
        if a.status_code == 503:
            assert a.json()["cause"] in ("Overloaded", "ServiceBusy", "PlanningTimeout"), a.text
            assert int(a.headers["retry-after"]) >= 1
        else:
            assert len(a.json()["path"]) > 1
    assert after.status_code == 200 and alive.status_code == 200
    assert "Traceback" not in log and "Warning" not in log, log
