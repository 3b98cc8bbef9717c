"""The stand-in Nav2 (spcotmhp.ros.standin_nav2): its route geometry and speed limit by hand and by property, then
the real action servers in a subprocess, with this test's rclpy clients: NavigateThroughPoses with its feedback,
cancel, abort, pre-emption, the speed limit, and a stand-in that rejects goals. Skipped only without the extra
ros2; with it, fails (naming `make nav2-msgs`) when nav2_msgs was not built."""

from __future__ import annotations

import math
import os

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

pytest.importorskip("rclpy")

from std_msgs.msg import Empty  # noqa: E402

from spcotmhp.ros.standin_nav2 import FAILED_TO_MAKE_PROGRESS, Route, limited_speed  # noqa: E402
from tests.ros.nav2_client import (  # noqa: E402
    ABORTED,
    CANCELED,
    MSG,
    SUCCEEDED,
    follow_goal,
    standin,
    through_goal,
)

DOMAIN = str(20 + os.getpid() % 10)  # 20..29: not the other ROS tests' domains
REJECTING_DOMAIN = str(1 + os.getpid() % 9)  # 1..9, for the second stand-in (0 is ROS's default)
SPEED = 2.0  # m/s of the module's stand-in


def test_route_by_hand():
    route = Route(np.array([[0.0, 0.0], [3.0, 0.0], [3.0, 4.0]]))
    assert route.length == 7.0 and route.poses_after() == 2
    route.advance(4.0)  # 3 m along x, then 1 m up
    assert route.pose(0.0) == pytest.approx((3.0, 1.0, math.pi / 2))
    assert route.remaining == 3.0 and route.poses_after() == 1
    route.advance(10.0)  # never past the end
    assert route.travelled == 7.0 and route.remaining == 0.0 and route.poses_after() == 0
    assert route.pose(0.0)[:2] == pytest.approx((3.0, 4.0))


def test_route_of_one_point_stays():
    route = Route(np.array([[1.0, 2.0]]))
    route.advance(5.0)
    assert route.length == 0.0 and route.pose(0.3) == (1.0, 2.0, 0.3)


coords = st.floats(-50, 50, allow_nan=False)


@given(st.lists(st.tuples(coords, coords), min_size=1, max_size=6), st.lists(st.floats(0, 30), max_size=8))
def test_route_pose_stays_on_the_polyline(points, steps):
    route = Route(np.array(points, dtype=float))
    for step in steps:
        route.advance(step)
    assert 0.0 <= route.travelled <= route.length
    assert route.travelled + route.remaining == pytest.approx(route.length)
    x, y, _ = route.pose(0.0)
    p = np.array([x, y])
    gaps = [0.0] if len(points) == 1 else []
    for a, b in zip(route.points[:-1], route.points[1:], strict=True):
        d = b - a
        dd = float(np.dot(d, d))  # 0 for a segment of length 0, or so short that its square underflows
        t = 0.0 if dd == 0.0 else float(np.clip(np.dot(p - a, d) / dd, 0.0, 1.0))
        gaps.append(float(np.linalg.norm(a + t * d - p)))
    assert min(gaps) < 1e-6


def test_speed_limit_as_controller_server_applies_it():
    assert limited_speed(0.5, 0.0, False) == 0.5  # 0: no limit
    assert limited_speed(0.5, 0.2, False) == 0.2  # m/s
    assert limited_speed(0.5, 1.0, False) == 0.5  # a limit above the speed changes nothing
    assert limited_speed(0.5, 50.0, True) == 0.25  # percent of the speed


@pytest.fixture(scope="module")
def nav2(tmp_path_factory):
    with standin(tmp_path_factory.mktemp("standin"), DOMAIN, "--speed", str(SPEED)) as client:
        yield client


def test_navigate_through_poses_feedback_and_arrival(nav2):
    x, y = nav2.where()
    points = [(x + 1.0, y), (x + 1.0, y + 1.0)]
    feedback: list = []
    handle = nav2.send(nav2.through, through_goal(points), feedback)
    status, result = nav2.outcome(handle)
    assert status == SUCCEEDED and result.error_code == 0
    remaining = [f.number_of_poses_remaining for f in feedback]
    assert remaining and remaining == sorted(remaining, reverse=True) and set(remaining) <= {1, 2}
    assert all(f.distance_remaining <= 2.0 + 1e-6 and f.current_pose.header.frame_id == "map" for f in feedback)
    assert nav2.spin_until(lambda: math.dist(nav2.where(), points[-1]) < 1e-9)


def test_cancel_stops_where_the_robot_is(nav2):
    x, y = nav2.where()
    feedback: list = []
    before = len(nav2.events)
    handle = nav2.send(nav2.follow, follow_goal([(x + 100.0, y)]), feedback)
    assert nav2.spin_until(lambda: bool(feedback))
    cancel = handle.cancel_goal_async()
    assert nav2.spin_until(cancel.done)
    status, _ = nav2.outcome(handle)
    assert status == CANCELED
    stopped = nav2.event("canceled", before)
    assert x < stopped["x"] < x + 100.0 and stopped["y"] == pytest.approx(y)


def test_abort_is_a_failed_result_with_nav2s_code(nav2):
    x, y = nav2.where()
    feedback: list = []
    handle = nav2.send(nav2.follow, follow_goal([(x, y + 100.0)]), feedback)
    assert nav2.spin_until(lambda: bool(feedback))
    nav2.abort.publish(Empty())
    status, result = nav2.outcome(handle)
    assert status == ABORTED and result.error_code == FAILED_TO_MAKE_PROGRESS and "aborted" in result.error_msg


def test_a_new_goal_preempts_the_running_one(nav2):
    x, y = nav2.where()
    first: list = []
    long_goal = nav2.send(nav2.follow, follow_goal([(x - 100.0, y)]), first)
    assert nav2.spin_until(lambda: bool(first))
    short = nav2.send(nav2.through, through_goal([(x, y)]), [])
    status, result = nav2.outcome(long_goal)
    assert status == ABORTED and "preempted" in result.error_msg
    assert nav2.outcome(short)[0] == SUCCEEDED
    assert nav2.spin_until(lambda: math.dist(nav2.where(), (x, y)) < 1e-9)


def test_speed_limit_sets_the_speed_driven(nav2):
    before = len(nav2.events)
    nav2.speed_limit.publish(MSG.SpeedLimit(percentage=True, speed_limit=25.0))
    assert nav2.event("speed_limit", before)["speed"] == pytest.approx(SPEED / 4)
    x, y = nav2.where()
    feedback: list = []
    handle = nav2.send(nav2.follow, follow_goal([(x + 0.5, y)]), feedback)
    assert nav2.outcome(handle)[0] == SUCCEEDED
    assert feedback and all(f.speed == pytest.approx(SPEED / 4) for f in feedback)
    mark = len(nav2.events)
    nav2.speed_limit.publish(MSG.SpeedLimit(percentage=False, speed_limit=0.0))  # no limit again
    assert nav2.event("speed_limit", mark)["speed"] == pytest.approx(SPEED)


def test_a_rejecting_standin_rejects(tmp_path):
    with standin(tmp_path, REJECTING_DOMAIN, "--reject") as client:
        before = len(client.events)
        handle = client.send(client.follow, follow_goal([(1.0, 0.0)]), [])
        assert not handle.accepted
        assert client.event("rejected", before)["poses"] == 1
