"""The ROS 2 node on a building's model for the robot's own body (issue 35): `spcotmhp ros2 M --floor ground
--robot-radius 0.30 --inflation-radius 0.55 --cost-scaling-factor 3` plans every floor for that robot: the
segments it publishes on /spcotmhp/plan, on floor 1 and after the ride on floor 2, keep every pose out of its
inscribed cells. Skipped only when the `ros2` extra is not installed."""

from __future__ import annotations

import json

import pytest

pytest.importorskip("rclpy")
pytest.importorskip("nav_msgs.msg")

from spcotmhp.building.model import BuildingModel  # noqa: E402
from spcotmhp.metric.nav2_params import resolve_body  # noqa: E402
from spcotmhp.planning.body import with_body  # noqa: E402
from tests.building.test_building_body import clear_on_every_floor, route  # noqa: E402
from tests.ros.test_building_node import _building_setup, xy_of  # noqa: E402
from tests.ros.test_node import ros_environment  # noqa: E402

DOMAIN = "101"  # not the other ROS tests' domains (1..100)
BODY = ("--robot-radius", "0.30", "--inflation-radius", "0.55", "--cost-scaling-factor", "3")


@pytest.fixture(scope="module")
def setup(tmp_path_factory):
    root = tmp_path_factory.mktemp("ros2body")
    with ros_environment(root, DOMAIN) as env:
        yield from _building_setup(root, env, BODY)


def test_every_floor_is_planned_for_the_body(setup):
    client, bm = setup["client"], setup["bm"]
    stairs = next(c for c in bm.spec.connectors if c.kind == "stairs")
    client.set_pose(stairs.stops[0].x + 0.5, stairs.stops[0].y)
    client.plans.clear()
    status = client.ask(client.instruction_pub, json.dumps({"goal": {"words": ["bedroom"], "floor": 2}}))
    assert status["ok"] and [s["floor"] for s in status["segments"]] == [1, 2], status
    assert client.spin_until(lambda: client.plans, 5)
    first = xy_of(client.plans[-1][1])
    client.plans.clear()
    assert client.ask(client.floor_pub, "2")["floor"] == 2
    assert client.spin_until(lambda: client.plans, 5)
    second = xy_of(client.plans[-1][1])
    body = resolve_body(robot_radius=0.30, inflation_radius=0.55, cost_scaling_factor=3.0)
    mine = BuildingModel(with_body(bm.model, body), bm.layout, bm.spec)
    segments = [{"floor": 1, "path": first.tolist()}, {"floor": 2, "path": second.tolist()}]
    assert clear_on_every_floor(mine, segments) == 0
    assert clear_on_every_floor(mine, route(bm)) > 0  # the default body's route is not: the node used the body
