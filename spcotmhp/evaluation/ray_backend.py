"""Optional Ray backend (extra ``dist``): the same chunks as the local pool, as Ray tasks, so a sweep over many
homes and seeds can run on a cluster (``spcotmhp evaluate ... --ray ADDRESS``) or on a local Ray instance.

The home context is put in the object store once per home; each chunk is one remote call of
:func:`spcotmhp.evaluation.work.evaluate_chunk`. Results are identical to the local backend's (seeds come
from the task, not the worker).
"""

from __future__ import annotations

from collections.abc import Callable, Sequence

from spcotmhp.errors import SpcotmhpError
from spcotmhp.evaluation.context import HomeContext
from spcotmhp.evaluation.tasks import Task
from spcotmhp.evaluation.work import chunks, evaluate_chunk, warm_up
from spcotmhp.extras import missing_extra

LOCAL = "local"
"""``--ray`` without an address: start (or join) a Ray instance on this machine."""


def _ray():
    try:
        import ray
    except ImportError:  # pragma: no cover - depends on the installation
        raise SpcotmhpError(missing_extra("the Ray backend", "dist")) from None
    return ray


def connect(address: str | None) -> None:
    """Join the Ray cluster at ``address`` ("auto", "ray://host:10001", "host:6379") or, for None/"local",
    start a local instance; does nothing when this process is already connected."""
    ray = _ray()
    if ray.is_initialized():
        return
    try:
        if address in (None, LOCAL):
            ray.init(include_dashboard=False, log_to_driver=False, configure_logging=False)
        else:
            ray.init(address=address, include_dashboard=False, log_to_driver=False, configure_logging=False)
    except (ConnectionError, ValueError, RuntimeError) as exc:
        raise SpcotmhpError(f"cannot connect to Ray at {address!r}: {exc}") from None


def run_ray(
    ctx: HomeContext,
    tasks: Sequence[Task],
    methods: Sequence[str],
    seed: int,
    address: str | None,
    advance: Callable[[int], None],
) -> list:
    """Evaluate the chunks as Ray tasks; ``advance(n)`` as each chunk of n tasks completes."""

    ray = _ray()
    connect(address)
    remote = ray.remote(_remote_chunk)
    ctx_ref = ray.put(ctx)
    pending = {remote.remote(ctx_ref, part, list(methods), seed): len(part) for part in chunks(tasks)}
    out = []
    while pending:
        done, _ = ray.wait(list(pending), num_returns=1)
        for ref in done:
            out.extend(ray.get(ref))
            advance(pending.pop(ref))
    return out


# Per-process state, by design: the (home, methods) this Ray worker process has already warmed up. What a warm-up
# fills (compiled kernels, their first-call set-up) lives in the process, so the record of it does too; Ray runs
# one task at a time per worker process, so there is no concurrent writer.
_WARM: set = set()


def _remote_chunk(ctx: HomeContext, tasks: Sequence[Task], methods: Sequence[str], seed: int) -> list:

    key = (ctx.name, tuple(methods))
    if key not in _WARM:
        warm_up(ctx, tasks[0], methods)
        _WARM.add(key)
    return evaluate_chunk(ctx, tasks, methods, seed)
