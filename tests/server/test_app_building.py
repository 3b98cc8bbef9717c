"""The HTTP service with a building's model beside a single floor's: ``POST /plan`` takes the start's ``floor``
and answers with one segment per floor; ``floor`` is required for a building and refused for a single floor; a
single floor's answer is unchanged (no building keys)."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

from spcotmhp.building.io import save_building_model
from spcotmhp.building.learn import learn_building
from spcotmhp.building.loader import load_building
from spcotmhp.building.synthetic import example_path
from spcotmhp.server.app import create_app
from tests.helpers.planning import home_model, world

with warnings.catch_warnings():
    warnings.simplefilter("ignore")
    from fastapi.testclient import TestClient


@pytest.fixture(scope="module")
def served(tmp_path_factory):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        bm = learn_building(load_building(example_path()))
    folder = save_building_model(bm, tmp_path_factory.mktemp("b") / "m")
    return bm, TestClient(create_app({"house": folder, "flat": home_model()}), base_url="http://localhost")


def start_of(bm):
    stairs = next(c for c in bm.spec.connectors if c.kind == "stairs")
    return [stairs.stops[0].x + 0.5, stairs.stops[0].y]


def test_plan_in_a_building(served):
    bm, client = served
    body = {"structured": {"goal": {"words": ["bedroom"], "floor": 2}}, "start": start_of(bm), "floor": "ground"}
    res = client.post("/plan?model=house", json=body)
    assert res.status_code == 200, res.text
    d = res.json()
    assert [s["floor"] for s in d["segments"]] == [1, 2] and d["floor"] == 1 and d["goal_floor"] == 2
    assert d["path"] == d["segments"][0]["path"] and d["rides"][0]["from"]["floor"] == 1
    assert d["places"][-1]["floor"] == 2 and d["places"][-1]["role"] == "goal"
    assert "to floor 2 (first)" in d["explanation"]
    same = client.post(
        "/plan?model=house", json={"instruction": "go to the kitchen", "start": start_of(bm), "floor": 1}
    )
    assert same.status_code == 200 and same.json()["segments"][0]["floor"] == 1


def test_floor_rules(served):
    bm, client = served
    start = start_of(bm)
    missing = client.post("/plan?model=house", json={"instruction": "go to the kitchen", "start": start})
    assert missing.status_code == 422 and "give 'floor'" in missing.json()["detail"]
    unknown = client.post("/plan?model=house", json={"instruction": "go to the kitchen", "start": start, "floor": 5})
    assert unknown.status_code == 422 and "no floor '5'" in unknown.json()["detail"]
    flat = client.post("/plan?model=flat", json={"instruction": "go to the kitchen", "start": [1.0, 1.0], "floor": 1})
    assert flat.status_code == 422 and "is one floor" in flat.json()["detail"]
    taught = client.post("/teach?model=house", json={"utterance": "this is the study", "x": 1.0, "y": 1.0})
    assert taught.status_code == 422 and "give 'floor'" in taught.json()["detail"]
    body = {"utterance": "this is the study", "x": 1.0, "y": 1.0, "floor": 1}
    assert client.post("/teach?model=flat", json=body).status_code == 422
    nowhere = client.post("/teach?model=house", json={**body, "floor": 7})
    assert nowhere.status_code == 422 and "no floor '7'" in nowhere.json()["detail"]


def test_teach_on_a_floor(tmp_path):
    """A teach on floor 2 of a building makes a place there that later plans reach across floors."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        building = load_building(example_path())
        bm = learn_building(building)
    client = TestClient(create_app({"house": save_building_model(bm, tmp_path / "m")}), base_url="http://localhost")
    d2 = building.floors[2]
    spot = d2.positions[int(np.argmax(np.hypot(*(d2.positions - d2.positions.mean(axis=0)).T)))]
    taught = client.post("/teach", json={"utterance": "this is the library", "x": spot[0], "y": spot[1], "floor": 2})
    assert taught.status_code == 200, taught.text
    res = client.post("/plan", json={"instruction": "go to the library", "start": start_of(bm), "floor": 1})
    assert res.status_code == 200, res.text
    goal = res.json()["places"][-1]
    assert goal["floor"] == 2 and "library" in goal["label"] and [s["floor"] for s in res.json()["segments"]] == [1, 2]


def test_a_single_floor_answer_is_unchanged(served):
    _, client = served
    model = home_model()
    start = world(model.map, 3, 12).tolist()  # the corridor of the hand-made home
    res = client.post("/plan?model=flat", json={"instruction": "go to the bedroom", "start": start})
    assert res.status_code == 200, res.text
    assert not {"segments", "rides", "floor", "goal_floor", "route_m"} & set(res.json())
    assert res.json()["path"][0] == pytest.approx(start, abs=0.05)


def test_plan_from_speech_in_a_building(served, monkeypatch):
    """/plan/audio takes the start's floor too (the recogniser replaced: what it heard is given)."""
    import spcotmhp.speech as speech

    bm, client = served

    class Heard:
        def recognise(self, data, nbest, name):
            return [("go to the bedroom upstairs", 0.0)]

    monkeypatch.setattr(speech, "cached_recogniser", lambda words: Heard())
    start = ",".join(str(v) for v in start_of(bm))
    wav = {"audio": ("say.wav", b"RIFF", "audio/wav")}
    res = client.post("/plan/audio?model=house", files=wav, data={"start": start, "floor": "1"})
    assert res.status_code == 200, res.text
    d = res.json()
    assert [s["floor"] for s in d["segments"]] == [1, 2] and d["hypotheses"][0]["text"] == "go to the bedroom upstairs"
