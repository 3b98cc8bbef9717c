"""Issue 37: every limit a model (or the planner, or the learner) holds its input to, sent through every endpoint of
the service at the limit and one past it. At the limit a request is planned, taught or refused for what it says;
past it the answer is a 4xx naming the field or the limit; never a 500 (a 300-character word in ``POST /teach``
was one: the model's vocabulary check raised a ModelValueError nothing answered)."""

from __future__ import annotations

import warnings

import pytest

from spcotmhp.errors import ModelValueError
from spcotmhp.learning.model_values import MAX_MEAN_M, MAX_WORD_CHARS
from spcotmhp.learning.observations import MAX_UTTERANCE_CHARS
from spcotmhp.persistence.io import load_model
from spcotmhp.planning.instructions import (
    MAX_AVOIDED,
    MAX_CHARS,
    MAX_HYPOTHESES,
    MAX_PLACE_WORDS,
    MAX_WAYPOINTS,
)
from spcotmhp.server import create_app
from tests.helpers.server import start_near, supervised_model_dir

with warnings.catch_warnings():
    warnings.simplefilter("ignore")
    from fastapi.testclient import TestClient

pytestmark = pytest.mark.filterwarnings("error")


@pytest.fixture(scope="module")
def served(tmp_path_factory):
    folder = supervised_model_dir("3LDK_06", tmp_path_factory.mktemp("m") / "3LDK_06")
    app = create_app({"home": folder})
    client = TestClient(app, base_url="http://localhost", raise_server_exceptions=False)
    return app, client, start_near(load_model(folder))


def word(n: int) -> str:
    return "k" * n


def padded(text: str, n: int) -> str:
    """``text`` then spaces and words of "room" up to exactly ``n`` characters."""
    filler = (" room" * n)[: max(n - len(text), 0)]
    return (text + filler)[:n].ljust(n, "m")


def teach_cases(start):
    x, y = start
    at, past = MAX_WORD_CHARS, MAX_WORD_CHARS + 1
    return [
        # (body, accepted: may it be taught or refused for what it says (True), or must it be refused by a limit)
        ({"utterance": f"this is the {word(at)}", "x": x, "y": y}, True),
        ({"utterance": f"this is the {word(past)}", "x": x, "y": y}, "utterance"),
        ({"utterance": word(past), "x": x, "y": y}, "utterance"),
        ({"utterance": f"ここは{'書' * past}です", "x": x, "y": y}, "utterance"),
        ({"utterance": "this is the " + "㍿" * 64, "x": x, "y": y}, "characters"),  # NFKC: a longer word
        ({"utterance": padded("this is the study", MAX_UTTERANCE_CHARS), "x": x, "y": y}, True),
        ({"utterance": padded("this is the study", MAX_UTTERANCE_CHARS + 1), "x": x, "y": y}, "utterance"),
        ({"utterance": "this is the hall", "x": MAX_MEAN_M, "y": y}, True),
        ({"utterance": "this is the hall", "x": 1e308, "y": -1e308}, True),
        ({"utterance": "this is the hall", "x": x, "y": y, "floor": "f" * 65}, "floor"),
        ({"utterance": "this is the hall", "x": x, "y": y, "model": "m" * 201}, "model"),
    ]


def plan_cases(start):
    goal = ["bedroom"]
    return [
        ({"instruction": padded("go to the bedroom", MAX_CHARS), "start": start}, True),
        ({"instruction": padded("go to the bedroom", MAX_CHARS + 1), "start": start}, "characters"),
        ({"instruction": f"go to the {word(MAX_WORD_CHARS + 1)}", "start": start}, True),
        ({"structured": {"goal": [word(MAX_WORD_CHARS)]}, "start": start}, True),
        ({"structured": {"goal": [word(MAX_WORD_CHARS + 1)]}, "start": start}, "structured"),
        ({"structured": {"goal": goal * MAX_PLACE_WORDS}, "start": start}, True),
        ({"structured": {"goal": goal * (MAX_PLACE_WORDS + 1)}, "start": start}, "words"),
        ({"structured": {"goal": goal, "waypoints": [["corridor"]] * MAX_WAYPOINTS}, "start": start}, True),
        ({"structured": {"goal": goal, "waypoints": [["corridor"]] * (MAX_WAYPOINTS + 1)}, "start": start}, "way"),
        ({"structured": {"goal": goal, "avoid": [["kitchen"]] * MAX_AVOIDED}, "start": start}, True),
        ({"structured": {"goal": goal, "avoid": [["kitchen"]] * (MAX_AVOIDED + 1)}, "start": start}, "avoid"),
        ({"nbest": [{"text": "go to the bedroom", "score": -1.0}] * MAX_HYPOTHESES, "start": start}, True),
        ({"nbest": [{"text": "go to the bedroom", "score": -1.0}] * (MAX_HYPOTHESES + 1), "start": start}, "nbest"),
        ({"instruction": "go to the bedroom", "start": [MAX_MEAN_M, -MAX_MEAN_M]}, True),
        ({"instruction": "go to the bedroom", "start": [1e308, 1e308]}, True),
        ({"instruction": "go to the bedroom", "start": start, "floor": "f" * 200}, True),
    ]


def check(res, accepted) -> None:
    """Never a 500; a refusal is a 4xx (or 503) with a one-line detail; one past a limit names it."""
    assert res.status_code < 500 or res.status_code == 503, res.text[:500]
    detail = res.json().get("detail", "")
    if res.status_code >= 400:
        assert isinstance(detail, str) and detail and "\n" not in detail, res.text[:500]
    if accepted is not True:
        assert 400 <= res.status_code < 500 and accepted in detail, (res.status_code, detail[:300])


def test_teach_at_and_past_every_limit(served):
    _, client, start = served
    for body, accepted in teach_cases(start):
        check(client.post("/teach", json=body), accepted)
    assert client.get("/healthz").status_code == 200


def test_plan_at_and_past_every_limit(served):
    _, client, start = served
    for body, accepted in plan_cases(start):
        check(client.post("/plan", json=body), accepted)


def test_queries_at_and_past_their_limits(served):
    _, client, _ = served
    check(client.get("/questions", params={"max": 100}), True)
    check(client.get("/questions", params={"max": 101}), "max")
    check(client.get("/places", params={"model": "m" * 200}), True)
    check(client.get("/places", params={"model": "m" * 201}), "model")
    files = {"audio": ("a.wav", b"RIFF0000WAVE", "audio/wav")}
    check(client.post("/plan/audio", files=files, data={"start": "0,0", "nbest": "21"}), "nbest")
    check(client.post("/plan/audio", files=files, data={"start": "1e308,nan"}), "start")


def test_a_model_value_error_inside_a_request_is_a_4xx(served):
    """Whatever check a request reaches first, a ModelValueError raised inside it is answered with its
    message (422), not a 500 with a traceback."""
    app, client, start = served
    sm = app.state.served["home"]

    def broken(*args, **kwargs):
        raise ModelValueError('"vocabulary" word 9 has 300 characters; at most 256 are accepted')

    real, sm.teach = sm.teach, broken
    try:
        res = client.post("/teach", json={"utterance": "this is the study", "x": start[0], "y": start[1]})
    finally:
        sm.teach = real
    assert res.status_code == 422 and res.json()["cause"] == "ModelValueError", res.text
    assert "at most 256" in res.json()["detail"]


def test_a_flood_of_teaches_of_1_to_600_characters_is_never_a_500(tmp_path):
    """The issue's flood, on a real `spcotmhp serve`: 50 concurrent clients teaching utterances of 1 to 600
    characters (one word of up to 600 among them, or words of a few letters) got 38 answers 500. Now every answer is
    a 200, a 4xx naming the utterance or a 503 (the teaching lane is full), the server log holds no traceback and no
    warning, it keeps serving, and the model folder is as it was (the service writes nothing)."""
    import asyncio
    import hashlib
    import random

    import httpx

    from tests.helpers.server import ServerProcess

    folder = supervised_model_dir("3LDK_06", tmp_path / "3LDK_06")
    files = lambda: {p.name: hashlib.sha256(p.read_bytes()).hexdigest() for p in sorted(folder.iterdir())}  # noqa: E731
    before = files()
    x, y = start_near(load_model(folder))
    rng = random.Random(37)

    def utterance() -> str:
        n = rng.randint(1, 600)
        if rng.random() < 0.5:
            return "this is the " + "x" * max(n - 12, 1)  # one long word
        return ("this is the study " * 40)[:n].strip() or "x"

    bodies = [{"utterance": utterance(), "x": x, "y": y} for _ in range(100)]

    async def flood(url: str) -> list[tuple[dict, httpx.Response]]:
        async def client(mine: list[dict]) -> list[tuple[dict, httpx.Response]]:
            async with httpx.AsyncClient(base_url=url, timeout=120.0) as c:
                return [(b, await c.post("/teach", json=b)) for b in mine]

        return [r for rs in await asyncio.gather(*(client(bodies[i::50]) for i in range(50))) for r in rs]

    with ServerProcess([str(folder)]) as server:
        answers = asyncio.run(flood(server.url))
        alive = httpx.get(server.url + "/healthz", timeout=10)
        log = server.output_tail(100_000)
    statuses = sorted({a.status_code for _, a in answers})
    assert len(answers) == 100 and all(s < 500 or s == 503 for s in statuses), statuses
    long_words = [a for b, a in answers if len(b["utterance"].split()[-1]) > MAX_WORD_CHARS]
    assert long_words and all(a.status_code in (422, 503) for a in long_words), [a.text for a in long_words][:3]
    assert sum(a.status_code == 422 for a in long_words) >= 5  # refused for what they say, not only shed
    assert all("utterance" in a.json()["detail"] for a in long_words if a.status_code == 422)
    assert alive.status_code == 200
    assert "Traceback" not in log and "Warning" not in log, log[-3000:]
    assert files() == before
