"""`spcotmhp export-nav2`: the Route Server graph checked against nav2_route's GeoJSON loader rules, the keepout
mask loaded back with the project's own map_server reader; and the ros2 command without its extra."""

from __future__ import annotations

import json
import math
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from scipy.sparse.csgraph import connected_components

from spcotmhp.metric.map_io import load_map
from spcotmhp.planning import HierarchicalPlanner
from tests.helpers.graphs import GRAPHS

EXE = str(Path(sys.executable).with_name("spcotmhp"))


@pytest.fixture(scope="module")
def model_dir(model_3ldk06_dir) -> Path:
    return model_3ldk06_dir


@pytest.fixture(scope="module")
def export(model_dir, tmp_path_factory) -> Path:
    out = tmp_path_factory.mktemp("export") / "nav2"
    done = run("export-nav2", str(model_dir), "--out", str(out), "--avoid", "kitchen", "--avoid", "bath")
    assert done.returncode == 0, done.stderr
    assert done.stdout.startswith(f"wrote {out}: route graph of 11 places")
    return out


def run(*args: str) -> subprocess.CompletedProcess:
    return subprocess.run([EXE, *args], capture_output=True, text=True, timeout=300, check=False)


def is_uint(value) -> bool:
    return isinstance(value, int) and not isinstance(value, bool) and 0 <= value <= 65535


def metadata_ok(value) -> bool:
    """nav2_route's loader takes numbers, booleans, strings, arrays of those and objects of all these."""
    if isinstance(value, dict):
        return all(isinstance(k, str) and metadata_ok(v) for k, v in value.items())
    if isinstance(value, list):
        return all(isinstance(v, (int, float, str, bool)) for v in value)
    return isinstance(value, (int, float, str, bool))


def test_route_graph_follows_the_route_server_rules(export, model_dir):
    doc = json.loads((export / "route_graph.geojson").read_text())
    assert doc["type"] == "FeatureCollection"
    nodes = [f for f in doc["features"] if f["geometry"]["type"] == "Point"]
    edges = [f for f in doc["features"] if f["geometry"]["type"] in ("MultiLineString", "LineString")]
    assert len(nodes) + len(edges) == len(doc["features"]) and nodes and edges
    ids = [f["properties"]["id"] for f in doc["features"]]
    assert all(is_uint(i) for i in ids) and len(set(ids)) == len(ids)
    planner = HierarchicalPlanner(load_model_dir(model_dir), cache=GRAPHS)
    occ = planner.model.map
    at = {}
    for f in nodes:
        assert f["type"] == "Feature"
        p = f["properties"]
        x, y = f["geometry"]["coordinates"]
        at[p["id"]] = (x, y)
        assert p["frame"] == "map" and metadata_ok(p["metadata"])
        assert p["metadata"]["name"] == planner.names[p["metadata"]["place"]]
        assert p["metadata"]["words"] == p["metadata"]["name"].split()
        cell = occ.world_to_cell(np.array([x, y]))
        assert occ.data[cell[0], cell[1]] == 0
    assert sorted(f["properties"]["metadata"]["name"] for f in nodes) == sorted(planner.names)
    pairs = set()
    for f in edges:
        p = f["properties"]
        assert is_uint(p["startid"]) and is_uint(p["endid"]) and p["startid"] in at and p["endid"] in at
        assert p["overridable"] is False and metadata_ok(p["metadata"])
        (line,) = f["geometry"]["coordinates"]
        xy = np.array(line, dtype=float)
        assert np.allclose(xy[0], at[p["startid"]]) and np.allclose(xy[-1], at[p["endid"]])
        steps = np.diff(xy, axis=0)
        assert math.isclose(p["cost"], np.hypot(steps[:, 0], steps[:, 1]).sum(), abs_tol=1e-3)
        cells = occ.world_to_cell(xy)
        assert (occ.data[cells[:, 0], cells[:, 1]] == 0).all() and (np.abs(np.diff(cells, axis=0)) <= 1).all()
        pairs.add((p["startid"], p["endid"]))
    assert all((b, a) in pairs for a, b in pairs)  # one edge per direction


def test_route_graph_is_connected_wherever_the_place_graph_is(export, model_dir):
    doc = json.loads((export / "route_graph.geojson").read_text())
    place_of = {
        f["properties"]["id"]: f["properties"]["metadata"]["place"]
        for f in doc["features"]
        if f["geometry"]["type"] == "Point"
    }
    planner = HierarchicalPlanner(load_model_dir(model_dir), cache=GRAPHS)
    K = planner.model.K
    route = np.zeros((K, K), dtype=bool)
    for f in doc["features"]:
        if f["geometry"]["type"] != "Point":
            route[place_of[f["properties"]["startid"]], place_of[f["properties"]["endid"]]] = True
    connected = planner.graph.connected & ~np.eye(K, dtype=bool)
    assert np.array_equal(route, connected)  # every connected pair has its edge
    n_place, place_labels = connected_components(connected, directed=False)
    n_route, route_labels = connected_components(route, directed=True, connection="strong")
    assert n_place == n_route
    assert all(len(set(route_labels[place_labels == c])) == 1 for c in range(n_place))


def test_keepout_mask_is_a_map_of_the_avoided_territories(export, model_dir):
    planner = HierarchicalPlanner(load_model_dir(model_dir), cache=GRAPHS)
    occ = planner.model.map
    mask = load_map(export / "keepout.yaml")
    assert mask.shape == occ.shape and mask.resolution == occ.resolution and mask.origin == occ.origin
    assert set(np.unique(mask.data)) == {0, 100}
    avoided = [k for k, name in enumerate(planner.names) if name in ("kitchen", "bath")]
    graph = planner.graph
    (r0, c0), (h, w) = graph.offset, graph.territory.shape
    expected = np.zeros(occ.shape, dtype=bool)
    expected[r0 : r0 + h, c0 : c0 + w] = np.isin(graph.territory, avoided)
    assert np.array_equal(mask.data == 100, expected)
    # a plan that avoids those places never enters the mask, one that goes there does
    start = occ.cell_to_world(graph.to_map(graph.node_cell[planner.names.index("entrance")]))
    away = planner.plan("go to the bedroom avoiding the kitchen and the bath", tuple(start))
    into = planner.plan("go to the kitchen", tuple(start))
    assert (mask.data[away.cells[:, 0], away.cells[:, 1]] == 0).all()
    assert (mask.data[into.cells[:, 0], into.cells[:, 1]] == 100).any()
    readme = (export / "README.md").read_text()
    for line in ("type: 0", "base: 0.0", "multiplier: 1.0", "keepout.yaml", "nav2_costmap_2d::KeepoutFilter"):
        assert line in readme


def test_refuses_to_overwrite_and_reports_bad_places(export, model_dir, tmp_path):
    before = (export / "route_graph.geojson").read_bytes()
    done = run("export-nav2", str(model_dir), "--out", str(export))
    assert done.returncode == 2 and done.stderr.count("\n") == 1 and "--overwrite" in done.stderr
    done = run("export-nav2", str(model_dir), "--out", str(model_dir.parent))
    assert done.returncode == 2 and "model folder" in done.stderr
    done = run("export-nav2", str(model_dir), "--out", str(tmp_path / "x"), "--avoid", "garage")
    assert done.returncode == 2 and done.stderr.startswith("error: place to avoid (--avoid) 'garage': unknown place")
    assert done.stderr.count("\n") == 1 and not (tmp_path / "x").exists()
    assert (export / "route_graph.geojson").read_bytes() == before
    done = run("export-nav2", str(model_dir), "--out", str(export), "--overwrite")
    assert done.returncode == 0, done.stderr
    assert sorted(p.name for p in export.iterdir()) == ["README.md", "route_graph.geojson"]  # no stale mask
    assert sorted(p.name for p in export.parent.iterdir()) == ["nav2"]  # no leftovers


def test_ros2_without_the_extra_is_one_line(model_dir):
    code = (
        "import sys; sys.modules['rclpy'] = None; sys.argv = ['spcotmhp', 'ros2', sys.argv[1]]; "
        "from spcotmhp.cli import main; main()"
    )
    done = subprocess.run(
        [sys.executable, "-c", code, str(model_dir)], capture_output=True, text=True, timeout=120, check=False
    )
    assert done.returncode == 2
    assert (
        done.stderr == "error: the ROS 2 node needs rclpy and the ROS 2 messages (rclpy is missing): pip "
        "install 'spcotmhp[ros2]'\n"
    )


def load_model_dir(folder: Path):
    from spcotmhp.persistence.io import load_model

    return load_model(folder)
