"""A pose in another frame waits for its transform (spcotmhp.ros.poses), driven by hand with a stand-in node (its
timer fired by the test, /tf fed by the test): kept once its chain arrives, computed by hand; rejected with
TransformUnavailable, saying how long it waited, at the deadline; refused meanwhile with NoValidPose; refused at
once with a zero timeout. The same through real rclpy messages is in test_hearing.py (the node's --tf-timeout)."""

from __future__ import annotations

import math
import warnings
from types import SimpleNamespace

import pytest

pytest.importorskip("rclpy")

from spcotmhp.datasets.bundled import load_bundled  # noqa: E402
from spcotmhp.errors import InvalidSettings, NoValidPose, PoseRejected, TransformUnavailable  # noqa: E402
from spcotmhp.ros.poses import PoseKeeper  # noqa: E402
from spcotmhp.ros.tf_tree import TransformTree  # noqa: E402


class Timer:
    def __init__(self, period, callback):
        self.period, self.callback, self.running = period, callback, True

    def cancel(self):
        self.running = False

    def reset(self):
        self.running = True


class FakeNode:
    """What PoseKeeper asks of an rclpy node; the /tf subscription's callback kept for the test to call."""

    def __init__(self):
        self.timers, self.subscriptions, self.warnings = [], {}, []

    def create_timer(self, period, callback):
        self.timers.append(Timer(period, callback))
        return self.timers[-1]

    def create_subscription(self, kind, topic, callback, qos):
        self.subscriptions[topic] = callback

    def get_logger(self):
        return SimpleNamespace(warning=self.warnings.append)


def pose(x, y, yaw=0.0, frame="map"):
    return SimpleNamespace(
        header=SimpleNamespace(frame_id=frame),
        pose=SimpleNamespace(
            pose=SimpleNamespace(
                position=SimpleNamespace(x=x, y=y),
                orientation=SimpleNamespace(x=0.0, y=0.0, z=math.sin(yaw / 2), w=math.cos(yaw / 2)),
            )
        ),
    )


def tf_message(parent, child, x, y, yaw):
    t = SimpleNamespace(translation=SimpleNamespace(x=x, y=y, z=0.0),
                        rotation=SimpleNamespace(x=0.0, y=0.0, z=math.sin(yaw / 2), w=math.cos(yaw / 2)))  # fmt: skip
    return SimpleNamespace(
        transforms=[SimpleNamespace(header=SimpleNamespace(frame_id=parent), child_frame_id=child, transform=t)]
    )


@pytest.fixture(scope="module")
def the_map():
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # the bundled data's known warnings
        return load_bundled("3LDK_06").map


def keeper(the_map, timeout=1.0):
    node, reports = FakeNode(), []
    k = PoseKeeper(node, "map", lambda: the_map, reports.append, timeout)
    if k.tf is None:
        pytest.fail("tf2_msgs is not built (make nav2-msgs)", pytrace=False)
    return k, node, reports


def test_a_pose_waits_for_its_transform_and_is_kept_when_it_comes(the_map):
    k, node, reports = keeper(the_map)
    deadline = node.timers[0]
    assert deadline.period == 1.0 and not deadline.running
    k.take(pose(1.0, 0.0, 0.0, frame="odom"))  # no transform yet: no error, it waits
    assert deadline.running and k.pose is None and reports == []
    with pytest.raises(NoValidPose, match="waits up to 1 s for its transform to 'map'.*'odom' was not heard"):
        k.current("an instruction")
    node.subscriptions["/tf"](tf_message("map", "other", 0.0, 0.0, 0.0))  # another frame: still waiting
    assert k.pose is None and deadline.running
    # odom's origin at (-3.9, -4.5) turned 90 degrees: odom's (1, 0) facing its x is map's (-3.9, -3.5) facing y
    node.subscriptions["/tf"](tf_message("map", "odom", -3.9, -4.5, math.pi / 2))
    assert k.current("an instruction") == pytest.approx((-3.9, -3.5, math.pi / 2))
    assert not deadline.running and reports == []
    deadline.callback()  # a late fire does nothing
    assert k.pose is not None and reports == []


def test_no_transform_within_the_timeout_is_a_transform_unavailable_status(the_map):
    k, node, reports = keeper(the_map, 2.5)
    k.take(pose(1.0, 0.0, frame="/odom"))
    node.timers[0].callback()  # the deadline
    assert [r["type"] for r in reports] == ["TransformUnavailable"]
    assert "'odom' was not heard" in reports[0]["error"] and "(waited 2.5 s for it)" in reports[0]["error"]
    with pytest.raises(NoValidPose, match="the latest robot pose was rejected.*waited 2.5 s"):
        k.current("an instruction")
    node.subscriptions["/tf"](tf_message("map", "odom", -3.9, -4.5, 0.0))  # too late: the pose stays rejected
    assert k.pose is None


def test_a_transform_putting_the_pose_off_the_map_rejects_it(the_map):
    k, node, reports = keeper(the_map)
    k.take(pose(0.0, 0.0, frame="odom"))
    node.subscriptions["/tf_static"](tf_message("map", "odom", 500.0, 500.0, 0.0))
    assert [r["type"] for r in reports] == ["PoseRejected"] and "off the model's map" in reports[0]["error"]
    assert not node.timers[0].running


def test_a_new_pose_ends_the_wait(the_map):
    k, node, reports = keeper(the_map)
    k.take(pose(0.0, 0.0, frame="odom"))
    k.take(pose(-3.9, -3.5))  # in map: kept at once, the wait given up silently
    assert k.pose == pytest.approx((-3.9, -3.5, 0.0)) and not node.timers[0].running
    node.timers[0].callback()
    assert reports == [] and k.pose is not None


def test_a_zero_timeout_refuses_at_once(the_map):
    k, _, _ = keeper(the_map, 0.0)
    with pytest.raises(TransformUnavailable, match="'odom' was not heard"):
        k.take(pose(0.0, 0.0, frame="odom"))
    with pytest.raises(NoValidPose, match="rejected"):
        k.current("an instruction")


def test_poses_not_finite_or_off_the_map_do_not_wait(the_map):
    k, node, _ = keeper(the_map)
    with pytest.raises(PoseRejected, match="not finite"):
        k.take(pose(float("nan"), 0.0))
    with pytest.raises(PoseRejected, match="off the model's map"):
        k.take(pose(500.0, 0.0))
    assert not node.timers[0].running


@pytest.mark.parametrize("timeout", [-1.0, 61.0, float("nan"), float("inf")])
def test_bad_timeouts_are_refused(the_map, timeout):
    with pytest.raises(InvalidSettings, match="0 to 60 s"):
        PoseKeeper(FakeNode(), "map", lambda: the_map, print, timeout)


def test_the_tree_is_the_tf_modules():
    assert isinstance(PoseKeeper(FakeNode(), "map", lambda: None, print).tf, TransformTree)
