"""The tf tree (spcotmhp.ros.tf_tree): lookups computed by hand, a property (a lookup and its reverse cancel),
every refusal; TFMessage's hash recomputed by rosbags; and transforms heard from real rclpy publishers of /tf and
/tf_static (discovery on localhost, a domain of its own). The rclpy part is skipped without the extra ros2."""

from __future__ import annotations

import math
import os
import time
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from spcotmhp.errors import PoseRejected, TransformUnavailable
from spcotmhp.ros.tf_tree import MAX_FRAMES, TransformTree, feed

DOMAIN = "100"  # not the other ROS tests' domains (1..99)
ROOT = Path(__file__).resolve().parents[2]


def yaw_q(yaw: float) -> tuple[float, float, float, float]:
    return (0.0, 0.0, math.sin(yaw / 2), math.cos(yaw / 2))


def robot_tree() -> TransformTree:
    """map -> odom: (1, 2), turned 90 degrees; odom -> base_link: (1, 0), not turned."""
    tree = TransformTree()
    tree.add("map", "odom", (1.0, 2.0, 0.0), yaw_q(math.pi / 2))
    tree.add("odom", "base_link", (1.0, 0.0, 0.0), yaw_q(0.0))
    return tree


def test_a_chain_by_hand():
    tree = robot_tree()
    # base_link's origin: odom's (1, 0) turned 90 degrees is (0, 1), plus (1, 2)
    assert tree.pose_in("map", "base_link", 0.0, 0.0, 0.0) == pytest.approx((1.0, 3.0, math.pi / 2))
    # a point 1 m ahead of the robot (its x axis is map's y): (1, 4)
    assert tree.pose_in("map", "base_link", 1.0, 0.0, 0.0)[:2] == pytest.approx((1.0, 4.0))
    # a pose in odom at (0, 0) facing odom's y (map's -x)
    assert tree.pose_in("map", "odom", 0.0, 0.0, math.pi / 2) == pytest.approx((1.0, 2.0, math.pi))
    # the reverse: map's origin in base_link. base_link is at (1, 3) facing map's y; the origin lies 3 m behind
    # and 1 m to the right (the robot's -y)
    assert tree.pose_in("base_link", "map", 0.0, 0.0, 0.0) == pytest.approx((-3.0, 1.0, -math.pi / 2))
    assert tree.pose_in("map", "/map", 2.0, 3.0, 0.5) == pytest.approx((2.0, 3.0, 0.5))  # a leading slash


def test_siblings_through_their_common_parent():
    tree = robot_tree()
    tree.add("odom", "laser", (0.0, 1.0, 0.0), yaw_q(math.pi))
    # laser at odom (0, 1) facing odom's -x; base_link at odom (1, 0): base_link's origin seen from the laser is
    # odom's (1, -1) relative, turned by -180 degrees: (-1, 1)
    assert tree.pose_in("laser", "base_link", 0.0, 0.0, 0.0) == pytest.approx((-1.0, 1.0, math.pi))


def test_the_latest_transform_is_used():
    tree = robot_tree()
    tree.add("map", "odom", (5.0, 0.0, 0.0), yaw_q(0.0))
    assert tree.pose_in("map", "base_link", 0.0, 0.0, 0.0) == pytest.approx((6.0, 0.0, 0.0))


angles = st.floats(-math.pi, math.pi)
coords = st.floats(-50, 50)


@given(coords, coords, angles, coords, coords, angles, coords, coords, angles)
def test_a_lookup_and_its_reverse_cancel(x1, y1, a1, x2, y2, a2, px, py, pa):
    tree = TransformTree()
    tree.add("map", "odom", (x1, y1, 0.0), yaw_q(a1))
    tree.add("odom", "base_link", (x2, y2, 0.0), yaw_q(a2))
    x, y, a = tree.pose_in("map", "base_link", px, py, pa)
    back = tree.pose_in("base_link", "map", x, y, a)
    assert back[:2] == pytest.approx((px, py), abs=1e-6)
    assert math.cos(back[2] - pa) == pytest.approx(1.0, abs=1e-9)


def test_refusals_name_their_cause():
    tree = robot_tree()
    with pytest.raises(
        TransformUnavailable,
        match=r"from frame 'gps' to 'map': 'gps' was not heard.*frames known: base_link, map, odom",
    ):
        tree.lookup("map", "gps")
    tree.add("world", "gps", (0.0, 0.0, 0.0), yaw_q(0.0))
    with pytest.raises(TransformUnavailable, match="two unconnected tf trees"):
        tree.lookup("map", "gps")
    with pytest.raises(TransformUnavailable, match="close a loop"):
        tree.add("base_link", "map", (0.0, 0.0, 0.0), yaw_q(0.0))
    with pytest.raises(TransformUnavailable, match="not finite"):
        tree.add("map", "x", (math.nan, 0.0, 0.0), yaw_q(0.0))
    with pytest.raises(TransformUnavailable, match="zero quaternion"):
        tree.add("map", "x", (0.0, 0.0, 0.0), (0.0, 0.0, 0.0, 0.0))
    with pytest.raises(TransformUnavailable, match="1 to 256 characters"):
        tree.add("map", "x" * 257, (0.0, 0.0, 0.0), yaw_q(0.0))
    assert issubclass(TransformUnavailable, PoseRejected)  # the node answers it as a rejected pose


def test_the_tree_is_bounded():
    tree = TransformTree()
    for i in range(MAX_FRAMES - 1):
        tree.add("map", f"f{i}", (0.0, 0.0, 0.0), yaw_q(0.0))
    with pytest.raises(TransformUnavailable, match=f"holds {MAX_FRAMES} frames"):
        tree.add("map", "one_more", (0.0, 0.0, 0.0), yaw_q(0.0))
    tree.add("map", "f0", (1.0, 0.0, 0.0), yaw_q(0.0))  # an update of a known frame is still taken


def test_tf_message_hash_recomputed_by_rosbags():
    typesys = pytest.importorskip("rosbags.typesys")
    from spcotmhp.ros.tf_types import TF_MESSAGE_HASH

    store = typesys.get_typestore(typesys.Stores.ROS2_JAZZY)
    text = (ROOT / "ros2" / "tf2_msgs" / "msg" / "TFMessage.msg").read_text()
    store.register(typesys.get_types_from_msg(text, "tf2_msgs/msg/TFMessage"))
    assert store.hash_rihs01("tf2_msgs/msg/TFMessage") == TF_MESSAGE_HASH


def _stamped(parent: str, child: str, xy: tuple[float, float], yaw: float):
    from geometry_msgs.msg import TransformStamped

    ts = TransformStamped()
    ts.header.frame_id, ts.child_frame_id = parent, child
    ts.transform.translation.x, ts.transform.translation.y = xy
    q = yaw_q(yaw)
    ts.transform.rotation.x, ts.transform.rotation.y, ts.transform.rotation.z, ts.transform.rotation.w = q
    return ts


def test_transforms_heard_on_tf_and_tf_static(tmp_path):
    """A robot's publishers (map -> odom on /tf, odom -> base_link latched on /tf_static, the static one sent
    before the listener exists) and a listener that feeds the tree: base_link's pose in map by hand."""
    rclpy = pytest.importorskip("rclpy")
    from rclpy.qos import DurabilityPolicy, QoSProfile

    from spcotmhp.ros.tf_types import import_tf_message
    from tests.ros.test_node import ros_environment

    tf_message = import_tf_message()
    static_qos = QoSProfile(depth=1, durability=DurabilityPolicy.TRANSIENT_LOCAL)
    with ros_environment(tmp_path, DOMAIN):
        context = rclpy.Context()
        rclpy.init(context=context)
        try:
            robot = rclpy.create_node("robot_tf", context=context)
            static = robot.create_publisher(tf_message, "/tf_static", static_qos)
            dynamic = robot.create_publisher(tf_message, "/tf", 10)
            static.publish(tf_message(transforms=[_stamped("odom", "base_link", (1.0, 0.0), 0.0)]))
            tree = TransformTree()
            listener = rclpy.create_node("listener", context=context)
            listener.create_subscription(tf_message, "/tf", lambda m: feed(tree, m), 10)
            listener.create_subscription(tf_message, "/tf_static", lambda m: feed(tree, m), static_qos)
            executor = rclpy.executors.SingleThreadedExecutor(context=context)
            executor.add_node(robot)
            executor.add_node(listener)
            deadline = time.monotonic() + 60  # a loaded machine's discovery; not a timing check
            while time.monotonic() < deadline and tree.frames() != {"map", "odom", "base_link"}:
                dynamic.publish(tf_message(transforms=[_stamped("map", "odom", (1.0, 2.0), math.pi / 2)]))
                executor.spin_once(timeout_sec=0.1)
            assert tree.pose_in("map", "base_link", 0.0, 0.0, 0.0) == pytest.approx((1.0, 3.0, math.pi / 2))
            assert os.environ["ROS_AUTOMATIC_DISCOVERY_RANGE"] == "LOCALHOST"
            np.testing.assert_allclose(tree.lookup("base_link", "base_link").translation, 0.0)
        finally:
            context.try_shutdown()
