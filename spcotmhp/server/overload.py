"""What the service promises under overload: a plan request is refused at once (503, ``Retry-After``) when the
requests ahead of it are expected to take longer than ``max_wait`` seconds to answer, rather than queued to answer
late (issue 37: at 100 concurrent clients p99 reached 5.2 s on a 2-core machine).

The estimate is Little's law over the whole server, ASGI middleware (:class:`OverloadGuard`) around every plan
endpoint: a request entering it finds ``in_flight`` plan requests ahead (entered, not yet answered), and the server
answers one every ``interval`` seconds (an exponential mean, weight ``SMOOTHING``, of the time between consecutive
answers while others were waiting, or of a request's own time when it was alone), so it expects to wait
``in_flight x interval``. Where the requests wait does not matter: in the planning lanes
(:mod:`spcotmhp.server.scheduling`), or for the event loop that reads bodies and writes plans (which shares the
GIL with the planner threads: past a few dozen clients it is the queue). A refusal costs the loop almost nothing
(no body is read, no plan written), so shedding frees the capacity that admitted requests need.

So an admitted request is expected to be answered within about ``max_wait`` (1 s by default: a fifth of the time
budget, so that an admitted plan finishes within its budget even when the estimate is 4 x low), whatever the number
of clients; the others get 503 ``Overloaded`` with ``Retry-After`` the expected wait in whole seconds (at least 1).
With nothing ahead a request is always admitted, so the service never refuses everyone.
"""

from __future__ import annotations

import json
import math
import time
from collections.abc import Iterable
from typing import Any

from spcotmhp.server.scheduling import RETRY_AFTER_S

SMOOTHING = 0.1  # weight of the latest answer: about the last ten count, so the estimate follows a change in load
PLAN_PATHS = ("/plan", "/plan/audio")


class LoadEstimate:
    """The in-flight count and answer interval of the guarded requests (module docstring). Used on the event loop
    only (ASGI middleware), so it needs no lock."""

    def __init__(self) -> None:
        self.in_flight = 0
        self.interval: float | None = None  # seconds between answers; None before the first
        self._last = 0.0

    def expected_wait(self) -> float:
        """Seconds a request entering now expects to wait for the ones ahead."""
        return self.in_flight * (self.interval or 0.0)

    def enter(self) -> float:
        self.in_flight += 1
        return time.perf_counter()

    def leave(self, entered: float) -> None:
        """One answer: the interval since the previous answer when others were waiting, else its own time."""
        now = time.perf_counter()
        busy = self.in_flight > 1 and self._last > entered
        sample = now - self._last if busy else now - entered
        self.interval = sample if self.interval is None else self.interval + SMOOTHING * (sample - self.interval)
        self.in_flight -= 1
        self._last = now


class OverloadGuard:
    """ASGI middleware: POST requests to ``paths`` get 503 Overloaded when :class:`LoadEstimate` expects them to
    wait over ``max_wait`` seconds (module docstring)."""

    def __init__(self, app: Any, max_wait: float, paths: Iterable[str] = PLAN_PATHS) -> None:
        self.app, self.max_wait, self.paths = app, max_wait, frozenset(paths)
        self.load = LoadEstimate()

    async def __call__(self, scope: dict, receive: Any, send: Any) -> None:
        if scope["type"] != "http" or scope["method"] != "POST" or scope["path"] not in self.paths:
            await self.app(scope, receive, send)
            return
        wait = self.load.expected_wait()
        if wait > self.max_wait:
            await _overloaded(send, wait, self.load.in_flight, self.max_wait)
            return
        entered = self.load.enter()
        try:
            await self.app(scope, receive, send)
        finally:
            self.load.leave(entered)


async def _overloaded(send: Any, wait: float, ahead: int, max_wait: float) -> None:
    retry = max(RETRY_AFTER_S, math.ceil(wait))
    detail = (
        f"the service is overloaded: the {ahead} plan requests ahead are expected to take {wait:.1f} s, more than "
        f"the {max_wait:g} s a request may wait; try again in {retry} s"
    )
    body = json.dumps({"detail": detail, "cause": "Overloaded"}).encode()
    headers = [
        (b"content-type", b"application/json"),
        (b"content-length", str(len(body)).encode()),
        (b"retry-after", str(retry).encode()),
    ]
    await send({"type": "http.response.start", "status": 503, "headers": headers})
    await send({"type": "http.response.body", "body": body})
