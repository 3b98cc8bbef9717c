"""nav2_msgs built from Nav2 Jazzy's interface files (ros2/nav2_msgs/, `make nav2-msgs`): their RIHS01 type hashes
equal the recorded Nav2 Jazzy ones (spcotmhp.ros.nav2_types), the plain messages' hashes recomputed by a second
implementation (rosbags), the hash a peer announces on discovery, and a FollowPath goal round-tripped between real
rclpy processes (the stand-in Nav2's action server and this test's client). Skipped only without the extra ros2;
with it, fails (naming `make nav2-msgs`) when nav2_msgs was not built."""

from __future__ import annotations

import math
import os
from pathlib import Path

import pytest

pytest.importorskip("rclpy")

from spcotmhp.ros import nav2_types  # noqa: E402
from spcotmhp.ros.nav2_types import EXPECTED_HASHES, Nav2MsgsMismatch, check_nav2_msgs  # noqa: E402
from spcotmhp.ros.type_hash import TypeHashUnavailable, compiled_type_hash  # noqa: E402
from tests.ros.nav2_client import ACTION, MSG, SUCCEEDED, follow_goal, standin  # noqa: E402

DOMAIN = str(10 + os.getpid() % 5)  # 10..14: not the other ROS tests' domains
INTERFACES = Path(__file__).resolve().parents[2] / "ros2" / "nav2_msgs"


def test_every_type_hash_equals_nav2_jazzys():
    assert check_nav2_msgs() == 40
    assert compiled_type_hash(MSG.SpeedLimit) == "RIHS01_" + EXPECTED_HASHES["nav2_msgs/msg/SpeedLimit"]
    assert compiled_type_hash(ACTION.FollowPath).startswith("RIHS01_9d95513552fb")


def test_a_differing_hash_is_named(monkeypatch):
    changed = dict(EXPECTED_HASHES, **{"nav2_msgs/action/FollowPath_Goal": "0" * 64})
    monkeypatch.setattr(nav2_types, "EXPECTED_HASHES", changed)
    with pytest.raises(Nav2MsgsMismatch, match=r"FollowPath_Goal differ.*make nav2-msgs"):
        check_nav2_msgs()


def test_a_class_without_type_support_has_no_hash():
    with pytest.raises(TypeHashUnavailable, match="no ROS 2 type support"):
        compiled_type_hash(int)


def _action_messages(name: str, text: str) -> dict[str, str]:
    """The messages rosidl derives from an .action file (REP 2016 / rosidl_adapter), as .msg texts."""
    goal, result, feedback = text.split("---")
    p = f"nav2_msgs/action/{name}_"
    return {
        p + "Goal": goal,
        p + "Result": result,
        p + "Feedback": feedback,
        p + "FeedbackMessage": f"unique_identifier_msgs/UUID goal_id\n{p}Feedback feedback",
        p + "SendGoal_Request": f"unique_identifier_msgs/UUID goal_id\n{p}Goal goal",
        p + "SendGoal_Response": "bool accepted\nbuiltin_interfaces/Time stamp",
        p + "GetResult_Request": "unique_identifier_msgs/UUID goal_id",
        p + "GetResult_Response": f"int8 status\n{p}Result result",
    }


def test_message_hashes_recomputed_by_rosbags():
    """A second RIHS01 implementation (rosbags, not rosidl) gives the same hashes from the same files, for the 25
    plain messages (the services, their events and the actions rosidl composes are checked against rosidl only)."""
    typesys = pytest.importorskip("rosbags.typesys")
    store = typesys.get_typestore(typesys.Stores.ROS2_JAZZY)
    texts = {"nav2_msgs/msg/SpeedLimit": (INTERFACES / "msg" / "SpeedLimit.msg").read_text()}
    for name in nav2_types.ACTIONS:
        texts.update(_action_messages(name, (INTERFACES / "action" / f"{name}.action").read_text()))
    for typename, text in texts.items():
        store.register(typesys.get_types_from_msg(text, typename))
    assert len(texts) == 25
    assert {t: store.hash_rihs01(t) for t in texts} == {t: "RIHS01_" + EXPECTED_HASHES[t] for t in texts}


def test_follow_path_round_trip_over_the_wire(tmp_path):
    """The stand-in's action server and this client, two processes: the hash the server announces on discovery
    is Nav2 Jazzy's; a goal's path arrives as sent, feedback comes back, the result says it succeeded."""
    with standin(tmp_path, DOMAIN, "--speed", "4.0") as client:
        topic = "/follow_path/_action/feedback"
        found = lambda: [i for i in client.node.get_publishers_info_by_topic(topic) if i.node_name == "standin_nav2"]  # noqa: E731
        assert client.spin_until(lambda: bool(found()))
        infos = found()
        assert [str(i.topic_type_hash) for i in infos] == [
            "RIHS01_" + EXPECTED_HASHES["nav2_msgs/action/FollowPath_FeedbackMessage"]
        ]
        x, y = client.where()
        points = [(x + 0.5, y), (x + 1.0, y + 0.5), (x + 1.0, y + 1.5)]
        feedback: list = []
        before = len(client.events)
        handle = client.send(client.follow, follow_goal(points), feedback)
        assert handle.accepted
        status, result = client.outcome(handle)
        assert status == SUCCEEDED and result.error_code == 0
        assert client.event("goal", before)["poses"] == [list(p) for p in points]
        assert feedback and all(f.distance_to_goal >= 0 and f.speed == pytest.approx(4.0) for f in feedback)
        end = client.event("succeeded", before)
        assert (end["x"], end["y"]) == pytest.approx(points[-1])
        assert client.spin_until(lambda: math.dist(client.where(), points[-1]) < 1e-9)
