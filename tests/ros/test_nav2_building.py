"""Nav2 exports of a building: one route graph per floor (the floor's places and its connector stops, each stop
joined both ways to the place it lies in) and connectors.json naming each stop's node."""

from __future__ import annotations

import json
import warnings

import numpy as np
import pytest

from spcotmhp.building.io import save_building_model
from spcotmhp.building.learn import learn_building
from spcotmhp.building.planner import BuildingPlanner
from spcotmhp.building.synthetic import generate_building
from spcotmhp.errors import SpcotmhpError
from spcotmhp.ros.nav2_building import building_route_graphs, export_building


@pytest.fixture(scope="module")
def bm():
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return learn_building(generate_building(3, seed=6, n_rooms=5, events_per_room=8))


def test_graphs_per_floor_and_connectors(bm):
    planner = BuildingPlanner(bm)
    graphs, doc = building_route_graphs(planner)
    assert sorted(graphs) == bm.indices and [f["index"] for f in doc["floors"]] == bm.indices
    for f, g in graphs.items():
        feats = g["features"]
        assert [x["properties"]["id"] for x in feats] == list(range(len(feats)))
        points = {x["properties"]["id"]: x for x in feats if x["geometry"]["type"] == "Point"}
        places = {
            x["properties"]["metadata"]["place"] for x in points.values() if "place" in x["properties"]["metadata"]
        }
        assert places == set(np.flatnonzero(bm.floor_places(f)).tolist())
        stops = [s for c in doc["connectors"] for s in c["stops"] if s["floor"] == f]
        assert stops and all(s["node"] in points for s in stops)
        for s in stops:
            node = points[s["node"]]
            assert node["geometry"]["coordinates"] == pytest.approx([s["x"], s["y"]], abs=1e-3)
            edges = [x for x in feats if x["geometry"]["type"] == "MultiLineString" and s["node"] in
                     (x["properties"]["startid"], x["properties"]["endid"])]  # fmt: skip
            assert len(edges) == 2  # there and back, to the place the stop lies in
            out = next(e for e in edges if e["properties"]["startid"] == s["node"])
            assert out["geometry"]["coordinates"][0][0] == pytest.approx([s["x"], s["y"]], abs=0.06)
            end = points[out["properties"]["endid"]]["geometry"]["coordinates"]
            assert out["geometry"]["coordinates"][0][-1] == pytest.approx(end, abs=1e-3)
    assert {c["name"] for c in doc["connectors"]} == {c.name for c in bm.spec.connectors}


def test_export_folder(bm, tmp_path):
    model = save_building_model(bm, tmp_path / "m")
    summary = export_building(model, tmp_path / "nav")
    assert summary.endswith("route graphs of 3 floors and 2 connectors (connectors.json)")
    assert sorted(p.name for p in (tmp_path / "nav").iterdir()) == [
        "README.md", "connectors.json", "floor1", "floor2", "floor3"]  # fmt: skip
    doc = json.loads((tmp_path / "nav" / "connectors.json").read_text())
    assert all((tmp_path / "nav" / f["route_graph"]).is_file() for f in doc["floors"])
    export_building(model, tmp_path / "nav", overwrite=True)  # an earlier building export may be replaced
    with pytest.raises(SpcotmhpError, match="--avoid"):
        export_building(model, tmp_path / "nav2", avoid=["kitchen"])
    from typer.testing import CliRunner

    from spcotmhp.cli import app

    res = CliRunner().invoke(app, ["export-nav2", str(model), "--out", str(tmp_path / "cli")])
    assert res.exit_code == 0 and "route graphs of 3 floors" in res.output, res.output
