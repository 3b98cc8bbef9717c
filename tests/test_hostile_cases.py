"""Issue 26 as an outsider checks it: every case of the issue and hostile variants (tests/helpers/hostile_cases.py)
run in a fresh process, as a user runs them; each must exit 0 with its plan or 2 with exactly one ``error:`` line
naming what was wrong, and never print a traceback or a warning. Wall times are printed by
``python -m tests.helpers.hostile_cases`` (no timing assertions here: the machine is shared)."""

from __future__ import annotations

import threading

import pytest

from tests.helpers.hostile_cases import CASES, door_model, judge, run, template_model
from tests.helpers.server import ServerProcess


@pytest.fixture(scope="module")
def root(tmp_path_factory):
    folder = tmp_path_factory.mktemp("hostile")
    template_model(folder)
    door_model(folder)
    return folder


@pytest.mark.parametrize(
    "case", [pytest.param(c, id=c.name, marks=[pytest.mark.slow] if c.slow else []) for c in CASES]
)
def test_hostile_case(root, case):
    args, outcome = run(case, root)
    assert not judge(case, outcome), f"spcotmhp {' '.join(args)}: {judge(case, outcome)}\n{outcome.stderr[-2000:]}"


def test_every_503_of_a_flooded_service_carries_retry_after(root):
    """Issue 26: 503 answers carried no Retry-After. A real `serve` flooded with long plans (one per client on the
    heavy lane) and teaches (two per client) from threads: some are refused with 503, each with Retry-After."""
    import httpx

    from tests.helpers.hostile_cases import template_start

    long = "go to the kitchen " + "via the bedroom " * 20  # over the light lane's 200 characters
    x, y = template_start(root)
    answers: list[httpx.Response] = []
    with ServerProcess([str(template_model(root))]) as server:

        def send(path: str, body: dict) -> None:
            answers.append(httpx.post(server.url + path, json=body, timeout=60))

        bodies = [("/plan", {"instruction": long, "start": [x, y]})] * 8
        bodies += [("/teach", {"utterance": f"this is room {i}", "x": x, "y": y}) for i in range(8)]
        threads = [threading.Thread(target=send, args=b) for b in bodies]
        for t in threads:
            t.start()
        for t in threads:
            t.join()
    busy = [a for a in answers if a.status_code == 503]
    assert len(answers) == len(bodies) and busy, [a.status_code for a in answers]
    # 1 s when a lane is full or the budget ran out; an overload's expected wait, in whole seconds (issue 37)
    expected = [a.headers.get("retry-after") == "1" or a.json().get("cause") == "Overloaded" for a in busy]
    assert all(expected), [(dict(a.headers), a.text[:200]) for a in busy]
    assert all(int(a.headers["retry-after"]) >= 1 for a in busy), [dict(a.headers) for a in busy]
    assert all(a.status_code in (200, 422, 503) for a in answers), [(a.status_code, a.text[:200]) for a in answers]
