"""A building planned for the robot's own body (issue 35): ``learn`` of a building folder takes the body options and
stores the body with the building's model; every floor's view plans for it; ``plan``, ``serve`` (the HTTP app of a
building model loaded with a body) and the building node's loader take a body for a stored building, re-planning
every floor from its stored map, nothing learned again, the stored body left as it was. Every pose of a route for a
0.30 m robot lies outside that robot's inscribed cells, on every floor it crosses."""

from __future__ import annotations

import json
import warnings
from pathlib import Path

import numpy as np
import pytest
from typer.testing import CliRunner

from spcotmhp.building.io import load_building_model
from spcotmhp.building.planner import BuildingPlanner
from spcotmhp.building.synthetic import example_path
from spcotmhp.cli import app
from spcotmhp.metric.costmap import INSCRIBED_INFLATED_OBSTACLE, default_costmap, inflate
from spcotmhp.metric.nav2_params import resolve_body
from tests.metric.test_body import nav2_file

with warnings.catch_warnings():
    warnings.simplefilter("ignore")
    from fastapi.testclient import TestClient

GOAL = {"structured": {"goal": {"words": ["bedroom"], "floor": 2}}}


def run(*args: str):
    return CliRunner().invoke(app, list(args))


@pytest.fixture(scope="module")
def folders(tmp_path_factory: pytest.TempPathFactory) -> tuple[Path, Path, Path]:
    """(a building model learned with the default body, one learned with the 0.30 m Nav2 body, the params file)."""
    root = tmp_path_factory.mktemp("bbody")
    params = nav2_file(root)
    plain, body = root / "plain", root / "body"
    for out, extra in ((plain, []), (body, ["--nav2-params", str(params)])):
        res = run("learn", str(example_path()), "--supervised", "--out", str(out), *extra)
        assert res.exit_code == 0, res.output
    return plain, body, params


def start_of(bm) -> list[float]:
    stairs = next(c for c in bm.spec.connectors if c.kind == "stairs")
    return [stairs.stops[0].x + 0.5, stairs.stops[0].y]


def clear_on_every_floor(bm, segments: list[dict]) -> int:
    """The poses of ``segments`` (one per floor crossed) in the inscribed cells of ``bm``'s body on their floor."""
    hits = 0
    for seg in segments:
        floor = bm.floor_model(seg["floor"])
        occ = floor.require_map()
        inscribed = inflate(occ, **floor.costmap).costs >= INSCRIBED_INFLATED_OBSTACLE
        cells = occ.world_to_cell(np.asarray(seg["path"], dtype=float))
        hits += int(inscribed[cells[:, 0], cells[:, 1]].sum())
    return hits


def test_learn_stores_the_body_and_every_floor_plans_for_it(folders):
    _, folder, _ = folders
    bm = load_building_model(folder)
    assert bm.model.costmap["inscribed_radius"] == pytest.approx(0.30398, abs=1e-4)
    assert bm.model.info["body"]["source"].endswith("nav2_params.yaml (global_costmap)")
    for i in bm.indices:
        assert bm.floor_model(i).costmap == bm.model.costmap
    segments = route(bm)
    assert [s["floor"] for s in segments] == [1, 2]
    assert clear_on_every_floor(bm, segments) == 0
    plain = load_building_model(folders[0])  # the default body's route: 2 of its 70 poses in this body's cells
    assert clear_on_every_floor(bm, route(plain)) > 0


def route(bm) -> list[dict]:
    """The segments (floor, path) of the route to floor 2's bedroom from beside floor 1's stairs."""
    plan = BuildingPlanner(bm).plan(GOAL["structured"], start_of(bm), "ground")
    return [{"floor": s.floor, "path": s.path.tolist()} for s in plan.segments]


def test_plan_takes_a_body_for_a_building_and_leaves_the_stored_one(folders):
    plain, _, params = folders
    x, y = start_of(load_building_model(plain))
    args = ["plan", str(plain), "go to the bedroom on the first floor", "--start", str(x), str(y), "--floor", "ground"]
    default = run(*args, "--json")
    mine = run(*args, "--json", "--nav2-params", str(params))
    assert default.exit_code == 0 and mine.exit_code == 0, default.output + mine.output
    a, b = (json.loads(r.stdout.splitlines()[0]) for r in (default, mine))
    assert a["segments"] != b["segments"]
    assert clear_on_every_floor(load_building_model(plain, resolve_body(params)), b["segments"]) == 0
    assert load_building_model(plain).model.costmap == default_costmap()


def test_a_served_building_plans_for_the_body_it_was_loaded_with(folders):
    plain, _, params = folders
    bm = load_building_model(plain, resolve_body(params))
    from spcotmhp.server.app import create_app

    client = TestClient(create_app({"house": bm}), base_url="http://localhost")
    res = client.post("/plan?model=house", json={**GOAL, "start": start_of(bm), "floor": "ground"})
    assert res.status_code == 200, res.text
    assert clear_on_every_floor(bm, res.json()["segments"]) == 0


def test_a_body_too_big_for_the_goal_is_one_line_naming_it(folders):
    """A 0.6 m robot on the generated building: no bedroom of floor 2 keeps a point in its free space. Before, the
    line named no floor ("reaches floor , where the 'bedroom' (goal) is")."""
    plain, _, _ = folders
    res = run("plan", str(plain), "go to the bedroom on the second floor", "--start", "1.95", "5.55", "--floor",
              "ground", "--robot-radius", "0.6")  # fmt: skip
    assert res.exit_code != 0 and type(res.exception).__name__ == "NoReachablePlace"
    assert "no place named 'bedroom' (goal) has a point in the free space planned from on any floor" in str(
        res.exception
    )
