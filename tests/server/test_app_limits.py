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
