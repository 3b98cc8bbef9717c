"""A test's side of the stand-in Nav2 (spcotmhp.ros.standin_nav2, run in a subprocess): real rclpy action clients
on the nav2_msgs built here, the stand-in's events and poses, and its speed limit and abort topics.

Importing this module needs rclpy and the built nav2_msgs; the test modules skip without rclpy (the extra ros2) and
fail, naming the build command, when rclpy is there but nav2_msgs was not built."""

from __future__ import annotations

import contextlib
import json
import os
import signal
import subprocess
import sys
from collections.abc import Iterator
from pathlib import Path

import pytest
from action_msgs.msg import GoalStatus
from geometry_msgs.msg import PoseStamped, PoseWithCovarianceStamped
from nav_msgs.msg import Path as PathMsg
from rclpy.action import ActionClient
from rclpy.executors import SingleThreadedExecutor
from rclpy.node import Node
from std_msgs.msg import Empty, String
from visualization_msgs.msg import MarkerArray

from spcotmhp.ros.nav2_types import Nav2MsgsMissing, import_nav2_msgs
from spcotmhp.ros.node import EVENTS, LATCHED
from tests.ros.test_node import Client, ros_environment

try:
    ACTION, MSG = import_nav2_msgs()
except Nav2MsgsMissing as e:  # the extra ros2 is installed (rclpy imported) but `make nav2-msgs` was not run
    pytest.fail(str(e), pytrace=False)

EXE = str(Path(sys.executable).with_name("spcotmhp"))
WAIT = 60.0  # seconds any one step may take on a loaded machine before the test gives up (not a timing check)


class Nav2Client:
    """Action clients for follow_path and navigate_through_poses, with what the stand-in publishes."""

    def __init__(self, context) -> None:
        self.node = Node("nav2_test_client", context=context)
        self.executor = SingleThreadedExecutor(context=context)
        self.executor.add_node(self.node)
        self.follow = ActionClient(self.node, ACTION.FollowPath, "follow_path")
        self.through = ActionClient(self.node, ACTION.NavigateThroughPoses, "navigate_through_poses")
        self.events: list[dict] = []
        self.poses: list[PoseWithCovarianceStamped] = []
        self.node.create_subscription(String, "standin_nav2/events", lambda m: self.events.append(json.loads(m.data)),
                                      EVENTS)  # fmt: skip
        self.node.create_subscription(PoseWithCovarianceStamped, "amcl_pose", self.poses.append, LATCHED)
        self.speed_limit = self.node.create_publisher(MSG.SpeedLimit, "speed_limit", 10)
        self.abort = self.node.create_publisher(Empty, "standin_nav2/abort", 10)

    def spin_until(self, done, timeout: float = WAIT) -> bool:
        return Client.spin_until(self, done, timeout)  # the node tests' loop, on this client's executor

    def ready(self) -> bool:
        """Both servers, the topics and the first pose are there."""
        return self.spin_until(
            lambda: self.follow.server_is_ready() and self.through.server_is_ready() and bool(self.poses)
            and self.speed_limit.get_subscription_count() > 0 and self.abort.get_subscription_count() > 0
        )  # fmt: skip

    def where(self) -> tuple[float, float]:
        p = self.poses[-1].pose.pose.position
        return p.x, p.y

    def send(self, client: ActionClient, goal, feedback: list):
        """Send ``goal``; the accepted (or rejected) goal handle, feedback appended to ``feedback``."""
        future = client.send_goal_async(goal, feedback_callback=lambda m: feedback.append(m.feedback))
        assert self.spin_until(future.done), "no answer to the goal"
        return future.result()

    def outcome(self, handle) -> tuple[int, object]:
        """Wait for the goal's end: (GoalStatus code, result message)."""
        future = handle.get_result_async()
        assert self.spin_until(future.done), "the goal did not end"
        answer = future.result()
        return answer.status, answer.result

    def event(self, kind: str, after: int = 0) -> dict:
        """The first event of ``kind`` from index ``after`` on (waits for it)."""
        found = lambda: [e for e in self.events[after:] if e["event"] == kind]  # noqa: E731
        assert self.spin_until(lambda: bool(found())), f"no {kind!r} event"
        return found()[0]


def poses(points, frame: str = "map") -> list[PoseStamped]:
    out = []
    for x, y in points:
        p = PoseStamped()
        p.header.frame_id = frame
        p.pose.position.x, p.pose.position.y = float(x), float(y)
        p.pose.orientation.w = 1.0
        out.append(p)
    return out


def follow_goal(points):
    goal = ACTION.FollowPath.Goal()
    goal.path.header.frame_id = "map"
    goal.path.poses = poses(points)
    return goal


def through_goal(points):
    goal = ACTION.NavigateThroughPoses.Goal()
    goal.poses = poses(points)
    return goal


@contextlib.contextmanager
def standin(root: Path, domain: str, *args: str, client_class: type = Nav2Client) -> Iterator:
    """Run the stand-in (``args`` on its command line) in a subprocess on ``domain``; a ready client beside it
    (``client_class``, a Nav2Client)."""
    import rclpy

    with ros_environment(root, domain) as env:
        cmd = [sys.executable, "-m", "spcotmhp.ros.standin_nav2", *args]
        proc = subprocess.Popen(cmd, env={**os.environ, **env}, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                                text=True)  # fmt: skip
        context = rclpy.Context()
        rclpy.init(context=context)
        client = client_class(context)
        try:
            assert client.ready() and proc.poll() is None, proc.communicate(timeout=10) if proc.poll() else "no server"
            yield client
        finally:
            client.node.destroy_node()
            context.try_shutdown()
            stop_node(proc)


class DriveClient(Nav2Client):
    """The stand-in's side (Nav2Client) and the node's topics."""

    def __init__(self, context) -> None:
        super().__init__(context)
        self.status: list[dict] = []
        self.plans: list[PathMsg] = []
        self.node.create_subscription(String, "/spcotmhp/status", lambda m: self.status.append(json.loads(m.data)),
                                      EVENTS)  # fmt: skip
        self.node.create_subscription(PathMsg, "/spcotmhp/plan", self.plans.append, LATCHED)
        self.places: list[MarkerArray] = []  # the node publishes its places (latched) once it is up
        self.node.create_subscription(MarkerArray, "/spcotmhp/places", self.places.append, LATCHED)
        self.say = self.node.create_publisher(String, "/spcotmhp/instruction", EVENTS)

    def drive_events(self, after: int, event: str) -> list[dict]:
        return [s for s in self.status[after:] if s.get("kind") == "drive" and s["event"] == event]

    def tell(self, text: str) -> tuple[int, int]:
        """Publish an instruction; the status and stand-in event counts before it."""
        marks = len(self.status), len(self.events)
        self.say.publish(String(data=text))
        return marks

    def until_drive(self, after: int, event: str) -> dict:
        assert self.spin_until(lambda: bool(self.drive_events(after, event)) or self.errors(after)), event
        seen = [(e["event"], e.get("t")) for e in self.events[-8:]]  # the stand-in's side, should it fail
        assert not self.errors(after), (self.errors(after), seen)
        return self.drive_events(after, event)[0]

    def errors(self, after: int) -> list[dict]:
        return [s for s in self.status[after:] if s.get("ok") is False]


def start_node(folder: Path, env: dict, drive: str = "follow_path", *options: str) -> subprocess.Popen:
    """`spcotmhp ros2 FOLDER --drive DRIVE [OPTIONS]` in a subprocess with ``env`` added to this environment."""
    return subprocess.Popen([EXE, "ros2", str(folder), "--drive", drive, *options], env={**os.environ, **env},
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)  # fmt: skip


def stop_node(proc: subprocess.Popen) -> None:
    """SIGINT (a node's or the stand-in's clean stop), then a kill if it is still there after 20 s."""
    if proc.poll() is None:
        proc.send_signal(signal.SIGINT)
        try:
            proc.wait(20)
        except subprocess.TimeoutExpired:
            proc.kill()
            proc.wait(10)


def node_ready(client: DriveClient, proc: subprocess.Popen, seen: int = 0) -> None:
    """Wait until the node is up: its places arrive (after ``seen`` earlier ones: a killed node's subscriptions
    stay in the graph for a while, so counting subscribers would not tell)."""
    up = lambda: (len(client.places) > seen and client.say.get_subscription_count() > 0) or proc.poll() is not None  # noqa: E731
    assert client.spin_until(up, 300)
    assert proc.poll() is None, proc.communicate(timeout=10)
    for _ in range(100):  # and it holds the stand-in's pose: an empty instruction's error then is not NoValidPose
        mark = client.tell("")[0]
        assert client.spin_until(lambda: bool(client.errors(mark)))  # noqa: B023 - called here, in this turn
        if client.errors(mark)[0]["type"] != "NoValidPose":
            return
        client.spin_until(lambda: False, 0.2)
    raise AssertionError("the node never got the stand-in's pose")


SUCCEEDED, CANCELED, ABORTED = GoalStatus.STATUS_SUCCEEDED, GoalStatus.STATUS_CANCELED, GoalStatus.STATUS_ABORTED
