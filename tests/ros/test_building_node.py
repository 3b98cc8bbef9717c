"""The ROS 2 node on a building's model, with real messages: `spcotmhp ros2 M --floor 1` in a subprocess; the
route's first segment on /spcotmhp/plan, the whole route on the status; /spcotmhp/floor switches the floor (its
map on /spcotmhp/map, the next segment from the connector's stop, the old pose dropped). Skipped only when the
`ros2` extra is not installed."""

from __future__ import annotations

import json
import os
import subprocess
import sys
import warnings
from pathlib import Path

import numpy as np
import pytest

rclpy = pytest.importorskip("rclpy")
pytest.importorskip("nav_msgs.msg")

from nav_msgs.msg import OccupancyGrid  # noqa: E402
from std_msgs.msg import String  # noqa: E402

from spcotmhp.building.io import save_building_model  # noqa: E402
from spcotmhp.building.learn import learn_building  # noqa: E402
from spcotmhp.building.loader import load_building  # noqa: E402
from spcotmhp.building.synthetic import example_path  # noqa: E402
from tests.ros.test_node import LATCHED, Client, ros_environment, stop_node  # noqa: E402

EXE = str(Path(sys.executable).with_name("spcotmhp"))
DOMAIN = str(90 + os.getpid() % 10)  # not test_node's domains (30..89)


class FloorClient(Client):
    def __init__(self, context) -> None:
        super().__init__(context)
        self.floors: list[dict] = []
        self.maps: list[OccupancyGrid] = []
        floor_msg = lambda m: self.floors.append(json.loads(m.data))  # noqa: E731
        self.node.create_subscription(String, "/spcotmhp/current_floor", floor_msg, LATCHED)
        self.node.create_subscription(OccupancyGrid, "/spcotmhp/map", self.maps.append, LATCHED)
        self.floor_pub = self.node.create_publisher(String, "/spcotmhp/floor", 10)


@pytest.fixture(scope="module")
def setup(tmp_path_factory):
    root = tmp_path_factory.mktemp("ros2b")
    with ros_environment(root, DOMAIN) as env:
        yield from _building_setup(root, env)


def _building_setup(root: Path, env: dict[str, str], options: tuple[str, ...] = ()):
    """The node on the generated building's model (``options``: more ``ros2`` options, e.g. a robot body)."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        building = load_building(example_path())
        bm = learn_building(building)
    folder = save_building_model(bm, root / "model")
    proc = subprocess.Popen([EXE, "ros2", str(folder), "--floor", "ground", *options], env={**os.environ, **env},
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)  # fmt: skip
    context = rclpy.Context()
    rclpy.init(context=context)
    client = FloorClient(context)
    try:
        ready = client.spin_until(
            lambda: (client.places and client.floors and client.maps) or proc.poll() is not None, 120
        )
        assert ready and proc.poll() is None, proc.communicate(timeout=5)
        yield {"client": client, "bm": bm, "building": building}
    finally:
        stop_node(client, context, proc)


def xy_of(msg) -> np.ndarray:
    return np.array([[p.pose.position.x, p.pose.position.y] for p in msg.poses])


def test_route_across_floors_segment_by_segment(setup):
    client, bm, building = setup["client"], setup["bm"], setup["building"]
    assert client.floors[-1] == {"floor": 1, "name": "ground"}
    f1 = building.floors[1].map
    assert (client.maps[-1].info.width, client.maps[-1].info.height) == (f1.width, f1.height)
    stairs = next(c for c in bm.spec.connectors if c.kind == "stairs")
    start = np.array([stairs.stops[0].x + 0.5, stairs.stops[0].y])
    client.set_pose(*start)
    client.plans.clear()
    status = client.ask(client.instruction_pub, json.dumps({"goal": {"words": ["bedroom"], "floor": 2}}))
    assert status["ok"] and status["kind"] == "plan", status
    assert [s["floor"] for s in status["segments"]] == [1, 2] and status["next_floor"] == 2
    assert client.spin_until(lambda: client.plans, 5)
    first = xy_of(client.plans[-1][1])
    ride = status["rides"][0]
    assert np.allclose(first[0], start) and np.hypot(*(first[-1] - [ride["from"]["x"], ride["from"]["y"]])) < 0.06
    assert status["n_poses"] == len(first)
    # the robot rides, and the floor topic says so
    client.plans.clear()
    switched = client.ask(client.floor_pub, "2")
    assert switched["kind"] == "floor" and switched["floor"] == 2 and switched["next_floor"] is None
    assert client.spin_until(lambda: client.plans and client.floors[-1]["floor"] == 2, 5)
    second = xy_of(client.plans[-1][1])
    assert np.hypot(*(second[0] - [ride["to"]["x"], ride["to"]["y"]])) < 0.06
    goal = status["places"][-1]
    assert goal["floor"] == 2 and np.hypot(*(second[-1] - goal["point"])) < 0.06
    f2 = building.floors[2].map
    cells = f2.world_to_cell(second)
    assert (f2.data[cells[:, 0], cells[:, 1]] == 0).all()
    # the pose held was on floor 1's map: dropped
    refused = client.ask(client.instruction_pub, "go to the kitchen")
    assert refused["ok"] is False and refused["type"] == "NoValidPose" and "floor 2" in refused["error"]
    client.set_pose(ride["to"]["x"], ride["to"]["y"])
    here = client.ask(client.instruction_pub, "go to the kitchen")
    assert here["ok"] and here["floor"] == 2 and here["places"][-1]["floor"] == 2  # the kitchen of this floor
    bad = client.ask(client.floor_pub, "9")
    assert bad["ok"] is False and "no floor '9'" in bad["error"]


def test_teaching_lands_on_the_current_floor(setup):
    client, building = setup["client"], setup["building"]
    if client.floors[-1]["floor"] != 2:
        assert client.ask(client.floor_pub, "first")["floor"] == 2
    spot = building.floors[2].positions[0]
    client.set_pose(*spot)
    taught = client.ask(client.teach_pub, "this is the library", timeout=60)
    assert taught["ok"] and taught["kind"] == "taught" and taught["floor"] == 2, taught
    assert client.ask(client.floor_pub, "ground")["floor"] == 1
    stop = building.spec.connectors[0].stops[0]
    client.set_pose(stop.x, stop.y)
    status = client.ask(client.instruction_pub, "go to the library")
    assert status["ok"] and status["places"][-1]["floor"] == 2 and "library" in status["places"][-1]["label"]
