"""The Ray backend against a local Ray instance (one CPU): same records as the in-process run."""

import os

import pytest

from spcotmhp.datasets import load_bundled
from spcotmhp.evaluation.context import build_context
from spcotmhp.evaluation.runner import evaluate_home
from spcotmhp.evaluation.tasks import make_tasks, subset

ray = pytest.importorskip("ray")


@pytest.fixture(scope="module")
def local_ray():
    saved = dict(os.environ)
    ray.init(num_cpus=1, include_dashboard=False, log_to_driver=False, configure_logging=False)
    yield
    ray.shutdown()
    # ray.init sets variables for its workers (RAY_*, PYTHONBREAKPOINT) that shutdown leaves behind; the later
    # tests and the processes they start run without them (tests/helpers/environment.py)
    os.environ.clear()
    os.environ.update(saved)


def key(res):
    return [
        (
            r.task_index,
            r.method,
            r.outcome.success,
            r.outcome.n_success,
            r.outcome.w_success,
            round(r.outcome.p, 9),
            r.error,
        )
        for r in res.records
    ]


@pytest.mark.slow
def test_ray_backend_matches_local(local_ray, monkeypatch):
    ctx = build_context(load_bundled("3LDK_06"), "supervised", seed=0)
    tasks = subset(make_tasks(ctx.dataset, "advanced", ctx.adjacency, places=ctx.places).tasks, 5, seed=2)
    methods = ["spcotmhp", "astar", "hpp1", "spconavi-astar"]
    local = evaluate_home(ctx, tasks, methods, seed=7, workers=1)
    monkeypatch.setattr("spcotmhp.evaluation.work.CHUNK", 2)  # three remote chunks
    remote = evaluate_home(ctx, tasks, methods, seed=7, backend="ray", ray_address="local")
    assert key(remote) == key(local)
    assert remote.metrics().keys() == local.metrics().keys()
