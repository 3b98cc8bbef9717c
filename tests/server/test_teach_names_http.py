"""Names taught over HTTP (issue 35): ``POST /teach`` "this is the second bedroom" apart from every place makes a
place called "second bedroom" that ``POST /plan`` "go to the second bedroom" ends at; ここは東の廊下です taught to a
Japanese model is shown 東の廊下 in the reply, ``/places`` and the plan (said_names rule 6)."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

from spcotmhp.persistence.io import load_model
from spcotmhp.server.app import create_app
from tests.helpers.server import farthest_spot, start_near, supervised_model_dir

with warnings.catch_warnings():
    warnings.simplefilter("ignore")
    from fastapi.testclient import TestClient


@pytest.fixture(scope="module")
def folders(tmp_path_factory):
    root = tmp_path_factory.mktemp("http_names")
    return supervised_model_dir("3LDK_06", root / "en"), supervised_model_dir("3LDK_06", root / "ja", lang="ja")


def served(folder):
    """(the model, a client of the service serving it, the free spot farthest from every place)."""
    model = load_model(folder)
    client = TestClient(create_app({"home": folder}), base_url="http://localhost")
    x, y = (float(v) for v in farthest_spot(model))
    return model, client, x, y


def test_the_second_bedroom_taught_over_http_is_planned_to(folders):
    model, client, x, y = served(folders[0])
    taught = client.post("/teach", json={"utterance": "this is the second bedroom", "x": x, "y": y})
    assert taught.status_code == 200, taught.text
    assert (taught.json()["label"], taught.json()["new_place"]) == ("second bedroom", True), taught.text
    res = client.post("/plan", json={"instruction": "go to the second bedroom", "start": start_near(model)})
    assert res.status_code == 200, res.text
    goal = res.json()["places"][-1]
    assert goal["name"] == "second bedroom" and np.hypot(*(np.array(res.json()["path"][-1]) - (x, y))) <= 1.0


def test_a_japanese_name_is_shown_as_taught_over_http(folders):
    model, client, x, y = served(folders[1])
    taught = client.post("/teach", json={"utterance": "ここは東の廊下です", "x": x, "y": y})
    assert taught.status_code == 200 and taught.json()["label"] == "東の廊下", taught.text
    places = client.get("/places").json()["places"]
    assert {"東の廊下"} <= {p["name"] for p in places} and {"東の廊下"} <= {p["label"] for p in places}
    res = client.post("/plan", json={"instruction": "東の廊下に行って", "start": start_near(model, "玄関")})
    assert res.status_code == 200 and res.json()["places"][-1]["name"] == "東の廊下", res.text
