"""The HTTP service in-process (FastAPI TestClient): every endpoint, several models, bad input as 4xx."""

from __future__ import annotations

import io
import json
import shutil
import subprocess
import sys
import threading
import warnings

import numpy as np
import pytest
from PIL import Image

from spcotmhp.commands.service import model_mapping
from spcotmhp.errors import ModelError, PlanningError
from spcotmhp.persistence.io import load_model
from spcotmhp.planning.planner import HierarchicalPlanner
from spcotmhp.server import create_app
from spcotmhp.server.limits import AUDIO_LIMIT, JSON_LIMIT, BodySizeLimit
from spcotmhp.server.registry import ServedModel, load_served
from spcotmhp.server.scheduling import Budget
from spcotmhp.viz.draw import topological_edges, used_extent
from spcotmhp.viz.labels import place_display_labels
from tests.helpers.graphs import GRAPHS
from tests.helpers.server import INSTRUCTION, start_near, supervised_model_dir, wall_point
from tests.helpers.threads import in_threads

with warnings.catch_warnings():
    warnings.simplefilter("ignore")
    from fastapi.testclient import TestClient


@pytest.fixture(scope="module")
def dirs(tmp_path_factory):
    root = tmp_path_factory.mktemp("models")
    return {
        "home6": supervised_model_dir("3LDK_06", root / "3LDK_06"),
        "home1": supervised_model_dir("3LDK_01", root / "3LDK_01"),
    }


@pytest.fixture(scope="module")
def model6(dirs):
    return load_model(dirs["home6"])


@pytest.fixture(scope="module")
def client(dirs):
    return TestClient(create_app(dirs), base_url="http://localhost")


@pytest.fixture(scope="module")
def start(model6):
    return start_near(model6)


def plan(client, **body):
    return client.post("/plan", json=body)


# ---- planning --------------------------------------------------------------------------------------------
def test_plan_from_text_is_the_planners_plan(client, model6, start):
    r = plan(client, instruction=INSTRUCTION, start=start)
    assert r.status_code == 200, r.text
    got = r.json()
    want = HierarchicalPlanner(model6, cache=GRAPHS).plan(INSTRUCTION, start).to_dict()
    assert got["model"] == "home6"
    assert got["explanation"] == want["explanation"]
    assert got["path"] == want["path"] and len(got["path"]) > 2
    assert [(p["id"], p["role"]) for p in got["places"]] == [(p["id"], p["role"]) for p in want["places"]]
    assert got["places"][0] == {**want["places"][0], "point": pytest.approx(want["places"][0]["point"])}
    roles = {p["role"]: p["name"] for p in got["places"]}
    assert roles["waypoint"] == "corridor" and roles["goal"] == "bedroom"
    assert got["path"][0] == pytest.approx(start, abs=0.051)  # the start cell's centre (0.1 m cells)
    assert got["instruction"]["goal"] == {"bedroom": 1} and got["instruction"]["waypoints"] == [{"corridor": 1}]


def test_plan_from_nbest_and_structured(client, start):
    r = plan(
        client,
        nbest=[
            {"text": "go to the kitchen", "score": -1.0},
            {"text": "go to the kitchen via the corridor", "score": -4.0},
        ],
        start=start,
    )
    assert r.status_code == 200, r.text
    assert r.json()["places"][-1]["name"] == "kitchen"
    r = plan(client, structured={"goal": ["bedroom"], "waypoints": [["corridor"]], "avoid": []}, start=start)
    assert r.status_code == 200, r.text
    assert [p["name"] for p in r.json()["places"] if p["role"] == "waypoint"] == ["corridor"]


def test_plan_picks_the_model_by_query_or_body(client, dirs):
    s1 = start_near(load_model(dirs["home1"]))
    for r in (
        client.post("/plan?model=home1", json={"instruction": "go to the kitchen", "start": s1}),
        plan(client, instruction="go to the kitchen", start=s1, model="home1"),
    ):
        assert r.status_code == 200, r.text
        assert r.json()["model"] == "home1" and r.json()["places"][-1]["name"] == "kitchen"
    r = client.post("/plan?model=home6", json={"instruction": "go to the kitchen", "start": s1, "model": "home1"})
    assert r.status_code == 422
    assert r.json()["detail"] == "the query names model 'home6' and the body 'home1'; give one"


def test_unknown_model_is_404_with_the_served_names(client, start):
    r = plan(client, instruction=INSTRUCTION, start=start, model="nope")
    assert r.status_code == 404
    assert r.json() == {"detail": "no model named 'nope'; served: home6, home1", "models": ["home6", "home1"]}
    assert client.get("/places?model=nope").status_code == 404
    assert client.get("/map.png?model=nope").status_code == 404


def test_unknown_place_word_is_422_with_the_known_words(client, model6, start):
    r = plan(client, instruction="go to the garage", start=start)
    assert r.status_code == 422
    body = r.json()
    words = HierarchicalPlanner(model6, cache=GRAPHS).place_words
    assert body["place_words"] == words and "corridor" in words
    assert body["detail"].startswith("no known place word in 'go to the garage' (not understood: garage)")
    r = plan(client, structured={"goal": ["garage"]}, start=start)
    assert r.status_code == 422 and r.json()["detail"].startswith("goal: unknown place word(s) 'garage'")


def test_start_in_a_wall_or_off_the_map_is_422(client, model6):
    wall = wall_point(model6)
    r = plan(client, instruction=INSTRUCTION, start=wall)
    assert r.status_code == 422
    assert r.json()["detail"].startswith(f"the start ({wall[0]:.2f}, {wall[1]:.2f}) is in an occupied cell")
    r = plan(client, instruction=INSTRUCTION, start=[100.0, 0.0])
    assert r.status_code == 422
    assert r.json()["detail"].startswith("the start (100.00, 0.00) is outside the map")


def test_each_planning_error_has_its_status_and_cause(client, model6, start):
    # typed errors: the service answers each cause with its own status and names it
    r = plan(client, instruction="go to the bedroom, don't go through the dining", start=start)
    assert r.status_code == 409 and r.json()["cause"] == "NoReachablePlace"
    assert r.json()["detail"].startswith("no free path from")
    r = plan(client, instruction="go to the second bedroom", start=start)
    assert r.status_code == 422 and r.json()["cause"] == "UnsupportedPhrase"
    r = plan(client, instruction="go to the kitchen avoiding the kitchen", start=start)
    assert r.status_code == 422 and r.json()["cause"] == "ConflictingInstruction"
    r = plan(client, instruction=INSTRUCTION, start=wall_point(model6))
    assert r.status_code == 422 and r.json()["cause"] == "StartBlocked"


def test_a_huge_start_is_a_short_422_without_overflow(client, model6):
    r = plan(client, instruction=INSTRUCTION, start=[1e308, -1e308])
    assert r.status_code == 422
    assert r.json()["detail"].startswith("the start (1e+308, -1e+308) is outside the map (x ")
    assert len(r.json()["detail"]) < 100
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # no overflow RuntimeWarning from the cell index
        with pytest.raises(PlanningError, match="the start \\(1e\\+308, 1e\\+308\\) is outside the map"):
            HierarchicalPlanner(model6, cache=GRAPHS).plan(INSTRUCTION, (1e308, 1e308))


@pytest.mark.parametrize(
    ("body", "detail"),
    [
        ({"instruction": INSTRUCTION}, "start: Field required"),
        ({"start": [0, 0]}, "body: give exactly one of 'instruction', 'nbest' or 'structured'"),
        (
            {"instruction": INSTRUCTION, "nbest": [{"text": "go to the bath", "score": 0}], "start": [0, 0]},
            "body: give exactly one of 'instruction', 'nbest' or 'structured' (got instruction, nbest)",
        ),
        (
            {"instruction": INSTRUCTION, "start": [0, "north"]},
            "start/1: Input should be a valid number",
        ),
        ({"instruction": INSTRUCTION, "start": [0]}, "start/1: Field required"),
        ({"instruction": "", "start": [0, 0]}, "instruction: String should have at least 1 character"),
        ({"instruction": INSTRUCTION, "start": [0, 0], "speed": 3}, "speed: Extra inputs are not permitted"),
        ({"nbest": [], "start": [0, 0]}, "nbest: List should have at least 1 item after validation, not 0"),
        ({"instruction": INSTRUCTION, "start": [0, 0], "lang": "fr"}, "lang: Input should be 'en' or 'ja'"),
    ],
)
def test_invalid_bodies_are_422_with_the_field_named(client, body, detail):
    r = plan(client, **body)
    assert r.status_code == 422
    assert r.json()["detail"] == detail


def test_non_finite_start_and_bad_json_are_422(client):
    r = client.post(
        "/plan",
        content=b'{"instruction": "go to the bath", "start": [NaN, 0]}',
        headers={"content-type": "application/json"},
    )
    assert r.status_code == 422 and r.json()["detail"] == "start/0: Input should be a finite number"
    r = client.post("/plan", content=b'{"instruction": ', headers={"content-type": "application/json"})
    assert r.status_code == 422 and r.json()["detail"].startswith("body: not valid JSON")


@pytest.mark.parametrize(
    "content_type",
    ["application/x-www-form-urlencoded", "text/plain", "text/plain; charset=utf-8", "multipart/form-data"],
)
@pytest.mark.parametrize("path", ["/plan", "/teach"])
def test_a_body_not_sent_as_json_is_415_naming_its_content_type(client, start, content_type, path):
    """Audit item 11: curl -d sends a form content type; the answer said "body: Input should be a valid
    dictionary". It now names the Content-Type and the one expected."""
    body = json.dumps({"instruction": INSTRUCTION, "start": start}).encode()
    r = client.post(path, content=body, headers={"content-type": content_type})
    assert r.status_code == 415
    assert r.json()["detail"] == (
        f"Content-Type {content_type!r} is not accepted: {path} takes a JSON body, sent with Content-Type: "
        "application/json"
    )


@pytest.mark.parametrize(
    "content_type", ["application/json", "application/json; charset=utf-8", "application/merge+json"]
)
def test_json_content_types_are_accepted(client, start, content_type):
    body = json.dumps({"instruction": INSTRUCTION, "start": start}).encode()
    r = client.post("/plan", content=body, headers={"content-type": content_type})
    assert r.status_code == 200, r.text


def test_a_body_without_content_type_is_415(client, start):
    body = json.dumps({"instruction": INSTRUCTION, "start": start}).encode()
    r = client.post("/plan", content=body)
    assert r.status_code == 415 and r.json()["detail"].startswith("a body without a Content-Type is not accepted")


def test_oversized_bodies_are_413(client):
    r = client.post("/plan", content=b" " * (JSON_LIMIT + 1), headers={"content-type": "application/json"})
    assert r.status_code == 413
    assert r.json()["detail"] == f"request body too large for /plan: {JSON_LIMIT + 1} bytes (limit {JSON_LIMIT} bytes)"
    r = client.post(
        "/plan/audio", files={"audio": ("big.wav", b"\0" * AUDIO_LIMIT, "audio/wav")}, data={"start": "0,0"}
    )
    assert r.status_code == 413 and r.json()["detail"].startswith("request body too large for /plan/audio")


# ---- the body limit on its own (chunked bodies without Content-Length) ---------------------------------
def _asgi_call(chunks, headers=()):
    """Status and the body the application saw, for a POST of ``chunks`` through a 10-byte limit."""
    import asyncio

    sent, seen = [], {}
    messages = [{"type": "http.request", "body": c, "more_body": i < len(chunks) - 1} for i, c in enumerate(chunks)]

    async def receive():
        return messages.pop(0) if messages else {"type": "http.disconnect"}

    async def send(message):
        sent.append(message)

    async def app(scope, receive, send):
        seen["body"] = (await receive())["body"]
        await send({"type": "http.response.start", "status": 200, "headers": []})
        await send({"type": "http.response.body", "body": b"ok"})

    scope = {"type": "http", "method": "POST", "path": "/plan", "headers": list(headers)}
    asyncio.run(BodySizeLimit(app, default=10)(scope, receive, send))
    return sent[0]["status"], seen.get("body")


def test_body_limit_counts_chunked_bodies():
    assert _asgi_call([b"12345", b"67890"]) == (200, b"1234567890")  # exactly the limit: replayed whole
    assert _asgi_call([b"12345", b"67890", b"1"]) == (413, None)  # one byte more: refused
    assert _asgi_call([b"1"], headers=[(b"content-length", b"11")]) == (413, None)
    assert _asgi_call([b"1"], headers=[(b"content-length", b"x")]) == (400, None)


# ---- map and places --------------------------------------------------------------------------------------
def test_places_lists_every_active_place_with_unique_labels_and_the_edges(client, model6):
    r = client.get("/places")
    assert r.status_code == 200
    body = r.json()
    act = [int(k) for k in np.flatnonzero(model6.active_places)]
    assert [p["id"] for p in body["places"]] == act
    labels = [p["label"] for p in body["places"]]
    assert labels == [place_display_labels(model6)[k] for k in act] and len(set(labels)) == len(labels)
    assert {"bedroom #1", "bedroom #2", "bedroom #3"} <= set(labels)
    assert [tuple(e) for e in body["edges"]] == topological_edges(model6)
    for p in body["places"]:
        np.testing.assert_allclose(p["mean"], model6.mu[p["id"]])
        np.testing.assert_allclose(p["covariance"], model6.Sigma[p["id"]])
    assert len({p["colour"] for p in body["places"]}) == len(act)


def test_map_png_is_georeferenced_by_map_json(client, model6):
    info = client.get("/map.json").json()
    assert info["model"] == "home6" and info["image"] == "/map.png?model=home6"
    assert info["extent"] == pytest.approx(used_extent(model6.map)) and info["resolution"] == pytest.approx(0.1)
    r = client.get(info["image"])
    assert r.status_code == 200 and r.headers["content-type"] == "image/png"
    assert Image.open(io.BytesIO(r.content)).size == (info["width"], info["height"])
    framed = client.get("/map.png?frame=true")
    assert framed.status_code == 200 and framed.content != r.content
    assert client.get("/map.png?frame=true").content == framed.content  # cached
    other = client.get("/map.json?model=home1").json()
    assert other["model"] == "home1" and other["image"] == "/map.png?model=home1"


def test_health_models_page_and_openapi(client):
    assert client.get("/healthz").json() == {"status": "ok", "models": ["home6", "home1"]}
    r = client.get("/models")
    models = r.json()
    assert models["default"] == "home6" and [m["name"] for m in models["models"]] == ["home6", "home1"]
    assert all("source" not in m for m in models["models"]) and "3LDK_06" not in r.text  # no folder paths
    assert "corridor" in models["models"][0]["place_words"]
    page = client.get("/")
    assert page.status_code == 200 and page.headers["content-type"].startswith("text/html")
    assert '<script src="/static/app.js">' in page.text
    assert "toWorld" in client.get("/static/app.js").text
    schema = client.get("/openapi.json").json()
    assert {"/plan", "/plan/audio", "/places", "/map.png", "/map.json", "/models", "/healthz"} <= set(schema["paths"])
    assert "PlanRequest" in schema["components"]["schemas"]
    assert "413" in schema["paths"]["/plan"]["post"]["responses"]


@pytest.mark.parametrize(
    "path, body, field",
    [
        ("/plan", {"instruction": INSTRUCTION, "start": [True, False]}, "start/0"),
        ("/plan", {"instruction": INSTRUCTION, "start": ["-3.9", "-3.5"]}, "start/0"),
        ("/plan", {"nbest": [{"text": INSTRUCTION, "score": True}], "start": [0.0, 0.0]}, "nbest/0/score"),
        ("/teach", {"utterance": "this is the den", "x": False, "y": 0.0}, "x"),
        ("/teach", {"utterance": "this is the den", "x": "1", "y": 0.0}, "x"),
    ],
)
def test_numbers_must_be_json_numbers(client, path, body, field):
    """true/false and strings of digits were read as numbers: a start [true, false] planned from (1, 0), as the
    Python API no longer does (first audit, item 13; second audit)."""
    r = client.post(path, json=body)
    assert r.status_code == 422 and r.json()["errors"][0]["field"] == field, r.text
    assert r.json()["detail"].startswith(f"{field}: Input should be a valid number")


def test_openapi_lists_every_error_status_an_endpoint_answers(client, model6, start):
    """A client generated from /openapi.json knows each status it can get: 409 (no path) was answered by /plan
    but not declared, nor 400 (Host) anywhere, nor 408 (slow body) or 501 (no speech extra); GET endpoints
    declared 413 and 415, which only bodies get (second audit)."""
    paths = client.get("/openapi.json").json()["paths"]
    declared = {
        (path, method): {int(code) for code in op["responses"]}
        for path, ops in paths.items()
        for method, op in ops.items()
    }
    assert declared == {
        ("/healthz", "get"): {200, 400},
        ("/models", "get"): {200, 400},
        ("/places", "get"): {200, 400, 404, 422},
        ("/map.png", "get"): {200, 304, 400, 404, 422},
        ("/map.json", "get"): {200, 400, 404, 422},
        ("/questions", "get"): {200, 400, 404, 422},  # issue 24: a new endpoint
        ("/plan", "post"): {200, 400, 404, 408, 409, 413, 415, 422, 503},
        ("/teach", "post"): {200, 400, 404, 408, 413, 415, 422, 503},  # issue 24: teaching's admission control
        ("/plan/audio", "post"): {200, 400, 404, 408, 409, 413, 422, 501, 503},
    }
    error = {"$ref": "#/components/schemas/ErrorResponse"}
    answer = paths["/plan"]["post"]["responses"]["409"]
    assert answer["content"]["application/json"]["schema"] == error and "NoReachablePlace" in answer["description"]
    r = plan(client, instruction="go to the bedroom, don't go through the dining", start=start)
    assert r.status_code == 409 and set(r.json()) >= {"detail"}
    r = client.get("/healthz", headers={"Host": "example.com"})
    assert r.status_code == 400 and isinstance(r.json()["detail"], str)


def test_the_map_picture_is_revalidated_and_changes_with_a_teach(dirs, model6, tmp_path):
    """The picture was sent with max-age=300 under one URL: after a teach, a reload or another tab showed the old
    map (without the taught place) for five minutes (second audit). Now an ETag that a teach changes."""
    model_dir = tmp_path / "m"
    shutil.copytree(dirs["home6"], model_dir)
    client = TestClient(create_app({"home": model_dir}), base_url="http://localhost")
    first = client.get("/map.png")
    tag = first.headers["etag"]
    assert first.status_code == 200 and first.headers["cache-control"] == "no-cache"
    again = client.get("/map.png", headers={"If-None-Match": tag})
    assert again.status_code == 304 and again.content == b"" and again.headers["etag"] == tag
    framed = client.get("/map.png?frame=true")
    assert framed.headers["etag"] != tag
    x, y = start_near(model6)
    for _ in range(3):
        assert client.post("/teach", json={"utterance": "this is the study", "x": x, "y": y}).status_code == 200
    after = client.get("/map.png", headers={"If-None-Match": tag})
    assert after.status_code == 200 and after.headers["etag"] != tag and after.content != first.content
    assert client.get("/map.png?frame=true", headers={"If-None-Match": framed.headers["etag"]}).status_code == 200


# ---- speech ------------------------------------------------------------------------------------------------
def test_audio_that_is_not_a_wav_file_or_a_bad_start_is_422(client):
    r = client.post("/plan/audio", files={"audio": ("note.txt", b"hello", "text/plain")}, data={"start": "0,0"})
    assert r.status_code == 422
    assert r.json()["detail"].startswith("note.txt is not a WAV file")
    r = client.post("/plan/audio", files={"audio": ("a.wav", b"RIFF", "audio/wav")}, data={"start": "here"})
    assert (
        r.status_code == 422 and r.json()["detail"] == "start must be two finite numbers \"x,y\" in metres, got 'here'"
    )
    r = client.post("/plan/audio", data={"start": "0,0"})
    assert r.status_code == 422 and r.json()["detail"] == "audio: Field required"
    r = client.post("/plan/audio?model=zz", files={"audio": ("a.wav", b"RIFF", "audio/wav")}, data={"start": "0,0"})
    assert r.status_code == 404 and r.json()["models"] == ["home6", "home1"]
    r = client.post(
        "/plan/audio?model=home1",
        files={"audio": ("a.wav", b"RIFF", "audio/wav")},
        data={"start": "0,0", "model": "home6"},
    )
    assert r.status_code == 422 and r.json()["detail"] == "the query names model 'home1' and the body 'home6'; give one"


def test_spoken_instruction_plans_via_the_corridor(client, start):
    pytest.importorskip("pocketsphinx", reason="speech needs pocketsphinx (extra 'speech')")
    espeak = shutil.which("espeak-ng")
    if espeak is None:
        pytest.skip("espeak-ng is not installed (apt-get install espeak-ng; `make system-deps` does it)")
    wav = subprocess.run([espeak, "-v", "en-us", "--stdout", INSTRUCTION], capture_output=True, check=True).stdout
    r = client.post(
        "/plan/audio",
        files={"audio": ("say.wav", wav, "audio/wav")},
        data={"start": json.dumps(start), "model": "home6"},
    )
    assert r.status_code == 200, r.text
    body = r.json()
    assert body["hypotheses"][0]["text"] == INSTRUCTION
    assert sum(h["score"] for h in body["hypotheses"]) == pytest.approx(1.0)
    roles = {p["role"]: p["name"] for p in body["places"]}
    assert roles["waypoint"] == "corridor" and roles["goal"] == "bedroom"
    # a plan that fails once the words are recognised still says what was heard (second audit)
    r = client.post(
        "/plan/audio", files={"audio": ("say.wav", wav, "audio/wav")}, data={"start": "100,100", "model": "home6"}
    )
    assert r.status_code == 422 and r.json()["cause"] == "StartOutsideMap"
    assert r.json()["hypotheses"] == body["hypotheses"]


# ---- concurrency and the registry --------------------------------------------------------------------------
def test_concurrent_plans_equal_sequential_ones(model6, start):
    served = ServedModel.build("m", model6)
    queries = [
        INSTRUCTION,
        "go to the kitchen avoiding the toilet",
        "go to the living avoiding the kitchen",
        "go to the bedroom avoiding the bath",
        "go to the washroom avoiding the bath",
        "go to the toilet",
    ] * 4
    want = [HierarchicalPlanner(model6, cache=GRAPHS).plan(q, start).explanation for q in queries]
    assert in_threads(8, queries, lambda q: served.plan(q, start).explanation) == want


def test_threads_and_both_lanes_plan_as_one_thread_does(model6, start):
    """No lane lock: threads call the served planner directly, and light and heavy plans run at once."""
    import asyncio

    served = ServedModel.build("t", model6)
    short = ["go to the kitchen avoiding the toilet", "go to the living avoiding the kitchen", INSTRUCTION]
    long = "go to the bedroom via the corridor, then the dining, then the living, then the kitchen" + " " * 150
    assert len(long) > served.budget.light_cost  # runs on the heavy lane
    queries = (short + ["go to the washroom avoiding the bath", long]) * 3
    alone = HierarchicalPlanner(model6)  # a cache of its own: a graph no other planner has touched

    def key(p):
        return p.explanation, p.cells.tolist(), p.log_prob

    want = [key(alone.plan(q, start)) for q in queries]
    assert in_threads(6, queries, lambda q: key(served.planner.plan(q, start))) == want

    async def both_lanes(sm):
        return await asyncio.gather(*(sm.plan_async(q, start) for q in queries))

    roomy = Budget(time_budget=60.0, max_heavy=8, max_heavy_per_client=8)  # all at once, none refused
    assert [key(p) for p in asyncio.run(both_lanes(ServedModel.build("u", model6, budget=roomy)))] == want


def test_identical_models_have_their_own_cache_planner_and_lanes(model6):
    from spcotmhp.server import registry

    a, b = ServedModel.build("a", model6), ServedModel.build("b", model6)
    assert a.light is not b.light and a.heavy is not b.heavy and a.lock is not b.lock
    assert a.cache is not b.cache and a.planner.graph is not b.planner.graph
    key = a.planner.graph.key
    assert key == b.planner.graph.key and a.cache.get_or_build(key, object) is a.planner.graph
    tables = [n for n, v in vars(registry).items() if isinstance(v, (dict, list, set)) and not n.startswith("__")]
    assert tables == [] and not hasattr(registry, "_LANES") and not hasattr(registry, "_HEAVY_PLANNERS")


def test_async_plans_run_on_the_graphs_worker_thread(model6, start, monkeypatch):
    import asyncio

    served = ServedModel.build("w", model6)
    threads = []
    plan_once = served.planner.plan

    def recording(*args, **kwargs):
        threads.append((threading.current_thread().name, served.lock.locked()))
        return plan_once(*args, **kwargs)

    monkeypatch.setattr(served.planner, "plan", recording)
    result = asyncio.run(served.plan_async(INSTRUCTION, start))
    assert "corridor (waypoint)" in result.explanation
    assert len(threads) == 1
    name, locked = threads[0]
    assert name.startswith("plan-") and name != threading.main_thread().name and locked


def test_registry_rejects_bad_names_and_no_models(model6, tmp_path):
    with pytest.raises(ModelError, match="no model to serve"):
        load_served({})
    with pytest.raises(ModelError, match=r"bad model name 'a/b': use letters, digits"):
        load_served({"a/b": model6})
    with pytest.raises(ModelError, match="does not exist"):
        create_app({"x": tmp_path / "missing"})


def test_model_mapping_names_models_by_folder_or_prefix(tmp_path):
    got = model_mapping([str(tmp_path / "3LDK_06"), f"home={tmp_path / 'm'}", str(tmp_path / "a b")])
    assert got == {"3LDK_06": tmp_path / "3LDK_06", "home": tmp_path / "m", "a_b": tmp_path / "a b"}
    with pytest.raises(ModelError, match=r"two models are named 'm'"):
        model_mapping([str(tmp_path / "x" / "m"), str(tmp_path / "y" / "m")])


# ---- drawing from worker threads ---------------------------------------------------------------------------
def test_pictures_never_use_pyplot():
    code = (
        "import sys; from spcotmhp.server import create_app; from spcotmhp.viz.draw import render, map_image; "
        "import spcotmhp.viz.plan; print('matplotlib.pyplot' in sys.modules)"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120, check=True)
    assert out.stdout.strip() == "False"


def test_two_models_drawn_at_once_equal_drawn_one_after_the_other(dirs):
    models = [ServedModel.build(name, load_model(folder)) for name, folder in dirs.items()]
    sequential = [m.figure_png() for m in models]
    for m in models:
        m._figure = None
    results: dict[int, bytes] = {}
    barrier = threading.Barrier(len(models))

    def draw(i: int) -> None:
        barrier.wait()
        results[i] = models[i].figure_png()

    threads = [threading.Thread(target=draw, args=(i,)) for i in range(len(models))]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert [results[i] for i in range(len(models))] == sequential


def test_serve_rejects_an_unknown_log_level(dirs):
    from typer.testing import CliRunner

    from spcotmhp.cli import app

    out = CliRunner().invoke(app, ["serve", str(dirs["home6"]), "--log-level", "loud"])
    assert out.exit_code == 2
    text = " ".join(out.output.replace("│", " ").split())
    assert (
        "Invalid value for '--log-level': Value error, 'loud' is not one of 'critical', 'error', 'warning', "
        "'info', 'debug', 'trace'" in text
    )


def test_an_instruction_over_the_planners_limit_is_413_with_its_cause(client, start):
    r = plan(client, instruction="go to the bedroom " + "and then the kitchen " * 40, start=start)
    assert r.status_code == 413 and r.json()["cause"] == "InstructionTooLarge"
    assert "more than the 500 accepted" in r.json()["detail"]


def test_a_teach_marked_as_an_answer_is_learned_as_one(dirs, model6, tmp_path):
    """POST /teach with "answer": true learns the utterance as an answer to a question (teaching/answers.py:
    a segment of its own under the default answer model); without it, as an ordinary teach; "answer": "yes" is
    422."""
    model_dir = tmp_path / "m"
    shutil.copytree(dirs["home6"], model_dir)
    client = TestClient(create_app({"home": model_dir}), base_url="http://localhost")
    x, y = start_near(model6)
    body = {"utterance": "this is the study", "x": x, "y": y}
    assert client.post("/teach", json={**body, "answer": "yes"}).status_code == 422
    assert client.post("/teach", json=body).status_code == 200
    assert client.post("/teach", json={**body, "answer": True}).status_code == 200
    alone = client.app.state.served["home"].model.learner["arrays"].get("alone")
    assert alone is not None and list(alone[-2:]) == [False, True]
