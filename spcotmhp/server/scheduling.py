"""Fair, bounded planning for the service: two lanes per served model, admission limits and a time budget.

A plan of an ordinary instruction takes about a millisecond; one naming many waypoints can take seconds, and
the planner cannot be interrupted. So that such requests cannot starve the others:

* **Two lanes.** Each request gets a cost estimate (:func:`estimate_cost`: the characters of its instruction,
  of every N-best hypothesis, or of the structured form's JSON). Requests up to ``Budget.light_cost`` run on the
  *light* lane (the model's planner on the lane's worker thread); costlier ones run on the *heavy* lane, the
  same planner on a lock and worker thread of its own (the planner is thread-safe). A heavy plan therefore
  never sits in front of a light one (both lanes share the CPU and the GIL, so a light plan
  runs at most a few milliseconds slower while a heavy one is running).
* **Admission.** A lane holds at most ``max_light`` / ``max_heavy`` requests (queued or running); the heavy
  lane also at most ``max_heavy_per_client`` per client address. Past that a request is refused at once with
  ``ServiceBusy`` (503); a request costlier than ``max_cost`` with ``InstructionTooLarge`` (413).
* **Teaching.** ``POST /teach`` has a lane of its own (``max_teach`` queued or running, ``max_teach_per_client``
  per client, ``teach_budget`` seconds; past them ``TeachingBusy``, 503): a teach is applied off the planning
  lanes and swapped in whole, and a flood of teaches is refused rather than queued without bound.
* **Time budget.** A request waits at most ``time_budget`` seconds for its plan, then gets ``PlanningTimeout``
  (503). A request still queued then is dropped from the queue; one already running finishes in the
  background and keeps its lane slot until it does, so a client cannot pile up work by timing out.
  Every 503 carries ``Retry-After: 1`` (``RETRY_AFTER_S``).
* **Overload.** Before any of this, a plan request expected to wait longer than ``max_wait`` for the requests
  ahead of it is refused at once, and one that has waited longer when its turn comes is refused then, unplanned
  (:mod:`spcotmhp.server.overload`).
"""

from __future__ import annotations

import asyncio
import json
import threading
from collections import Counter
from collections.abc import Callable
from concurrent.futures import Future, ThreadPoolExecutor
from dataclasses import dataclass
from typing import Any, Protocol, TypeVar

from spcotmhp.errors import InstructionTooLarge, PlanningError, PlanningTimeout, SpcotmhpError

T = TypeVar("T")
# the Retry-After (seconds) of every 503: a lane frees its slot when a plan ends (about a millisecond for a light
# one), and a timed-out plan runs on for at most its own length; one second is the shortest whole value
RETRY_AFTER_S = 1


class Deadline(Protocol):
    """What a lane asks of a request's deadline (:class:`spcotmhp.server.overload.Admission`) when its turn
    comes: ``start(ahead)`` raises to shed it, ``ahead`` the calls the lane finished while it waited."""

    def start(self, ahead: int) -> None: ...


class ServiceBusy(PlanningError):
    """Too many plans are queued for this model (or for this client); try again shortly."""

    http_status = 503


@dataclass(frozen=True)
class Budget:
    """Limits of the planning service (module docstring); ``create_app(budget=Budget(...))`` changes them."""

    time_budget: float = 5.0  # seconds a request waits for its plan
    # seconds a plan request may expect to wait for those ahead before it is refused (spcotmhp.server.overload):
    # a fifth of the time budget, so that an admitted plan finishes within it even when the estimate is 4x low
    max_wait: float = 1.0
    light_cost: int = 200  # instructions up to this many characters run on the light lane
    max_cost: int = 8192  # instructions beyond this are refused (413)
    max_light: int = 512  # requests queued or running on a light lane
    max_heavy: int = 4  # ... on a heavy lane
    max_heavy_per_client: int = 1  # ... on a heavy lane from one client address
    teach_budget: float = 10.0  # seconds a teach waits to be applied
    max_teach: int = 8  # teaches queued or running for one model (each holds a model copy while it runs)
    max_teach_per_client: int = 2  # ... from one client address


def estimate_cost(source: Any) -> int:
    """The size of an instruction in characters: a sentence's length, the summed lengths of an N-best list's
    hypotheses, or the length of a structured instruction's JSON (planning time grows with the places named,
    and those grow with the text)."""
    if isinstance(source, str):
        return len(source)
    if isinstance(source, (list, tuple)):
        return sum(len(str(item[0])) if isinstance(item, (list, tuple)) and item else len(str(item)) for item in source)
    try:
        return len(json.dumps(source, ensure_ascii=False, default=str))
    except (TypeError, ValueError):
        return len(str(source))


class Lane:
    """One worker thread and its lock, with admission counts (total and per client); ``busy`` is the error class
    raised past them."""

    def __init__(
        self, name: str, limit: int, per_client: int | None = None, busy: type[SpcotmhpError] | None = None
    ) -> None:
        self.busy: type[SpcotmhpError] = busy or ServiceBusy
        self.lock = threading.Lock()
        self.worker = ThreadPoolExecutor(1, thread_name_prefix=f"plan-{name}")
        self.limit, self.per_client = limit, per_client
        self._guard = threading.Lock()
        self._total = 0
        self._clients: Counter[str] = Counter()
        self.finished = 0  # calls run (counted under ``lock``): those a queued request waited for

    def admit(self, client: str) -> None:
        """Count a request in, or raise ``busy`` (the message says which limit was reached)."""
        what = "teach" if self.busy is not ServiceBusy else "plan"
        with self._guard:
            if self._total >= self.limit:
                raise self.busy(
                    f"the {'model' if what == 'teach' else 'planner'} is busy ({self._total} {what}s queued or "
                    "running, the limit); try again shortly"
                )
            if self.per_client is not None and self._clients[client] >= self.per_client:
                raise self.busy(
                    f"this client already has {self._clients[client]} {'' if what == 'teach' else 'long '}"
                    f"{what}(s) running (the limit is {self.per_client}); wait for it"
                    + ("" if what == "teach" else ", or shorten the instruction")
                )
            self._total += 1
            self._clients[client] += 1

    def release(self, client: str) -> None:
        with self._guard:
            self._total -= 1
            self._clients[client] -= 1
            if self._clients[client] <= 0:
                del self._clients[client]

    @property
    def load(self) -> int:
        return self._total


async def run_in_lane(
    lane: Lane,
    client: str,
    budget: float,
    call: Callable[[], T],
    timeout: Callable[[str], Exception] | None = None,
    admission: Deadline | None = None,
) -> T:
    """Run ``call`` under ``lane.lock`` on the lane's worker, admitted for ``client``, waiting at most
    ``budget`` seconds (module docstring); with an ``admission``, only if its wait is within its deadline when its
    turn comes (:class:`spcotmhp.server.overload.Admission`)."""
    lane.admit(client)

    queued = lane.finished

    def locked() -> T:
        with lane.lock:
            if admission is not None:
                admission.start(lane.finished - queued)
            try:
                return call()
            finally:
                lane.finished += 1

    try:
        future: Future = lane.worker.submit(locked)
    except BaseException:
        lane.release(client)
        raise
    future.add_done_callback(lambda _: lane.release(client))
    try:
        return await asyncio.wait_for(asyncio.wrap_future(future), budget)
    except TimeoutError:
        future.cancel()  # dropped if still queued; a running plan finishes and then frees its slot
        if timeout is not None:
            raise timeout(f"not finished within the time budget of {budget:g} s; try again shortly") from None
        raise PlanningTimeout(
            f"planning did not finish within the time budget of {budget:g} s; shorten the "
            "instruction (fewer waypoints) or try again"
        ) from None
    except asyncio.CancelledError:  # the client went away: drop the plan if it has not started
        future.cancel()
        raise


def check_cost(cost: int, limits: Budget) -> None:
    """InstructionTooLarge (413) for an instruction costlier than ``limits.max_cost``."""
    if cost > limits.max_cost:
        raise InstructionTooLarge(
            f"the instruction has {cost} characters; the service plans instructions of at most {limits.max_cost}"
        )
