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

An estimate can be wrong (other processes take the cores, a burst arrives between two answers), so it is backed by
a deadline on the wait itself (:class:`Admission`): the guard stamps each admitted request with the time it
entered, and the planning lane, when the request's turn comes, plans it only if it has waited at most
``max_wait`` since, or if no plan ran ahead of it on the lane (then it waited only for the server to read it,
and planning it keeps the service from shedding everyone); else it is shed then, with the same 503
``Overloaded``, before any planning. So **every plan the service answers (200) either started within
``max_wait`` of the server's reading the request, or had no plan ahead of it**, and is answered within that
plus its own plan time, whatever the load, inside or outside the service; every other request gets its 503 at
once (the estimate) or when its turn comes past ``max_wait`` (the deadline), a shed that costs the lane nothing.
The 200s carry the measured wait and the plans ahead in a ``Server-Timing: queue;dur=<ms>;desc="<n> ahead"``
header. A shed is no answer to time the service by: it does not enter the estimate's interval.
"""

from __future__ import annotations

import json
import math
import time
from collections.abc import Iterable, Mapping
from dataclasses import dataclass, field
from typing import Any

from spcotmhp.server.scheduling import RETRY_AFTER_S, ServiceBusy

SMOOTHING = 0.1  # weight of the latest answer: about the last ten count, so the estimate follows a change in load
PLAN_PATHS = ("/plan", "/plan/audio")


ENTERED = "spcotmhp.entered"  # the key of the guard's entry time in the ASGI scope's state
SHED = "spcotmhp.shed"  # ... and of the lane's refusal past the deadline


class Overloaded(ServiceBusy):
    """The request waited, or would wait, longer than ``max_wait`` for the requests ahead of it (503)."""


@dataclass
class Admission:
    """One plan request's deadline on its wait (module docstring): ``entered`` (``time.perf_counter()``, stamped by
    the guard), ``max_wait`` seconds; ``waited`` and ``ahead`` (the plans the lane finished while it was queued)
    are set when the plan starts; ``state`` is the request's ASGI state, where a shed is noted for the
    guard (a refusal is no answer to time the service by)."""

    entered: float
    max_wait: float
    state: dict = field(default_factory=dict)
    waited: float | None = None
    ahead: int = 0

    @classmethod
    def of(cls, scope: Mapping[str, Any], max_wait: float) -> Admission:
        """The admission of a request the guard stamped (a request it did not see counts from now)."""
        state = scope.get("state")
        state = state if isinstance(state, dict) else {}
        entered = state.get(ENTERED)
        return cls(time.perf_counter() if entered is None else float(entered), max_wait, state)

    def start(self, ahead: int) -> None:
        """Called when the plan is about to run (on the lane's worker, holding its lock), ``ahead`` plans having
        finished on the lane since the request was queued: Overloaded when it has waited longer than ``max_wait`` behind
        them; else the wait is recorded. A request with nothing planned ahead of it is always planned (as the
        guard always admits one with nothing ahead), so the service never sheds everyone."""
        waited = time.perf_counter() - self.entered
        if waited > self.max_wait and ahead > 0:
            self.state[SHED] = True
            raise Overloaded(
                f"the service is overloaded: this plan request waited {waited:.1f} s for the {ahead} plans ahead of "
                f"it, more than the {self.max_wait:g} s a request may wait; try again in {RETRY_AFTER_S} s"
            )
        self.waited, self.ahead = waited, ahead

    def timing(self) -> str:
        """The ``Server-Timing`` header of the answer: the measured wait in milliseconds and the plans ahead."""
        return f'queue;dur={1000 * (self.waited or 0.0):.1f};desc="{self.ahead} ahead"'


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

    def leave(self, entered: float, timed: bool = True) -> None:
        """One answer: the interval since the previous answer when others were waiting, else its own time; not
        ``timed`` (shed past its deadline, unplanned) it only leaves: a refusal's speed says nothing of the
        plans', and counting it would lower the estimate exactly when the service is overloaded."""
        if not timed:
            self.in_flight -= 1
            return
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
        state = scope.setdefault("state", {})
        state[ENTERED] = entered  # the lane's deadline counts from here (Admission)
        try:
            await self.app(scope, receive, send)
        finally:
            self.load.leave(entered, timed=not state.get(SHED, False))


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
