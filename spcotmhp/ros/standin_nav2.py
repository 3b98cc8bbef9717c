"""A stand-in for Nav2, for tests and demos without a ROS installation: real rclpy action servers on Nav2's types.

It serves what the node drives on a real robot, with the nav2_msgs built from Nav2's files (nav2_types):

* ``follow_path`` (nav2_msgs/FollowPath, as controller_server): moves a simulated pose along the goal's path,
  from the pose where it is to the path's first pose and then through every pose, at ``speed`` m/s; feedback
  ``distance_to_goal`` (along the rest of the path) and ``speed``;
* ``navigate_through_poses`` (nav2_msgs/NavigateThroughPoses, as bt_navigator): the same through the goal's
  poses in straight lines (no planner, no map: it drives through walls); feedback current pose, navigation time,
  time and distance remaining, poses remaining;
* ``speed_limit`` (nav2_msgs/SpeedLimit, in, as controller_server): a limit in m/s, or in percent of ``speed``;
  0 removes it;
* ``amcl_pose`` (geometry_msgs/PoseWithCovarianceStamped, out, latched as AMCL): the simulated pose, at every step;
* ``standin_nav2/abort`` (std_msgs/Empty, in): aborts the running goal, as Nav2 does when the controller fails
  (FollowPath ``FAILED_TO_MAKE_PROGRESS``), to test how a client takes a failure;
* ``standin_nav2/events`` (std_msgs/String, out): one JSON object per goal accepted (its poses), rejected,
  finished (succeeded, canceled, aborted, preempted: with the pose) and per speed limit, for tests to read.

As Nav2's servers do, a new goal on an action pre-empts the one running (that one ends aborted, error_msg
"preempted"); a cancel ends the goal canceled where the pose is. With ``reject`` every goal is rejected; with
``mute`` none is answered. The pose moves in steps of ``1 / rate`` s of the clock, so a goal takes its
length / speed in real time.
Run: ``python -m spcotmhp.ros.standin_nav2 [--speed 0.5] [--x 0 --y 0] [--reject] [--mute]``.
"""

from __future__ import annotations

import argparse
import json
import math
import threading
import time
from dataclasses import dataclass
from typing import Any

import numpy as np
from builtin_interfaces.msg import Duration
from geometry_msgs.msg import PoseWithCovarianceStamped
from rclpy.action import ActionServer, CancelResponse, GoalResponse
from rclpy.callback_groups import ReentrantCallbackGroup
from rclpy.executors import MultiThreadedExecutor
from rclpy.node import Node
from rclpy.task import Future
from std_msgs.msg import Empty, String

from spcotmhp.ros.nav2_types import import_nav2_msgs
from spcotmhp.ros.node import EVENTS, LATCHED
from spcotmhp.ros.shapes import quaternion_yaw, yaw_quaternion
from spcotmhp.ros.spinning import bounded_shutdown, quiet_shutdown, ros_running, spin_until_shutdown

FAILED_TO_MAKE_PROGRESS = 105  # FollowPath's result code for a controller that cannot go on (FollowPath.action)
NO_LIMIT = 0.0  # SpeedLimit.speed_limit meaning "no limit" (SpeedLimit.msg)


@dataclass
class Route:
    """A polyline (n x 2 points, metres) and how far along it the pose is (``travelled``, metres)."""

    points: np.ndarray
    travelled: float = 0.0

    def __post_init__(self) -> None:
        self.points = np.asarray(self.points, dtype=float).reshape(-1, 2)
        steps = np.linalg.norm(np.diff(self.points, axis=0), axis=1)
        self.ends = np.concatenate([[0.0], np.cumsum(steps)])  # distance along the route at every point

    @property
    def length(self) -> float:
        return float(self.ends[-1])

    @property
    def remaining(self) -> float:
        return max(self.length - self.travelled, 0.0)

    def advance(self, distance: float) -> None:
        """Move ``distance`` metres on (never past the end)."""
        self.travelled = min(self.travelled + max(distance, 0.0), self.length)

    def pose(self, fallback_yaw: float) -> tuple[float, float, float]:
        """(x, y, yaw) at the distance travelled: yaw along the segment there (``fallback_yaw`` on a route of no
        length)."""
        i = int(np.searchsorted(self.ends, self.travelled, side="right")) - 1
        i = min(max(i, 0), len(self.points) - 2) if len(self.points) > 1 else 0
        if len(self.points) == 1 or self.ends[i + 1] == self.ends[i]:
            x, y = self.points[min(i + 1, len(self.points) - 1)]
            return float(x), float(y), fallback_yaw
        a, b = self.points[i], self.points[i + 1]
        t = (self.travelled - self.ends[i]) / (self.ends[i + 1] - self.ends[i])
        x, y = a + t * (b - a)
        return float(x), float(y), math.atan2(b[1] - a[1], b[0] - a[0])

    def poses_after(self) -> int:
        """How many of the route's points (after the first, where the pose started) are still ahead."""
        return int(np.count_nonzero(self.ends[1:] > self.travelled + 1e-9))


def limited_speed(speed: float, limit: float, percentage: bool) -> float:
    """The speed the stand-in drives at: ``speed``, capped by a SpeedLimit (m/s, or percent of ``speed``; 0 = none),
    as controller_server applies it."""
    if limit <= NO_LIMIT:
        return speed
    return min(speed, speed * limit / 100.0 if percentage else limit)


class StandInNav2(Node):
    """The stand-in's node: its action servers, the simulated pose and the topics above."""

    def __init__(self, speed: float = 0.5, rate: float = 20.0, start: tuple[float, float] = (0.0, 0.0),
                 reject: bool = False, frame: str = "map", mute: bool = False) -> None:  # fmt: skip
        super().__init__("standin_nav2")
        self.action_types, self.msg_types = import_nav2_msgs()
        self.speed, self.step, self.reject, self.frame = speed, 1.0 / rate, reject, frame
        self.limit = (NO_LIMIT, False)
        self.x, self.y, self.yaw = float(start[0]), float(start[1]), 0.0
        self.lock = threading.Lock()
        self.current: Any = None  # the goal handle running (one robot: a goal on either action pre-empts it)
        self.aborting = threading.Event()
        self.received = 0.0
        group = ReentrantCallbackGroup()
        self.pose_pub = self.create_publisher(PoseWithCovarianceStamped, "amcl_pose", LATCHED)
        self.events = self.create_publisher(String, "standin_nav2/events", EVENTS)
        self.create_subscription(self.msg_types.SpeedLimit, "speed_limit", self.on_speed_limit, 10)
        self.create_subscription(Empty, "standin_nav2/abort", lambda _: self.aborting.set(), 10)
        for name, action in (("follow_path", self.action_types.FollowPath),
                             ("navigate_through_poses", self.action_types.NavigateThroughPoses)):  # fmt: skip
            ActionServer(
                self, action, name, execute_callback=self.execute,
                goal_callback=self.on_goal_unanswered if mute else self.on_goal,
                cancel_callback=lambda _: CancelResponse.ACCEPT, handle_accepted_callback=self.on_accepted,
                callback_group=group,
            )  # fmt: skip
        self.publish_pose()

    def event(self, **fields: Any) -> None:
        self.events.publish(String(data=json.dumps(fields)))

    def publish_pose(self) -> None:
        msg = PoseWithCovarianceStamped()
        msg.header.frame_id = self.frame
        msg.header.stamp = self.get_clock().now().to_msg()
        msg.pose.pose.position.x, msg.pose.pose.position.y = self.x, self.y
        q = msg.pose.pose.orientation
        q.x, q.y, q.z, q.w = yaw_quaternion(self.yaw)
        self.pose_pub.publish(msg)

    def on_speed_limit(self, msg: Any) -> None:
        self.limit = (float(msg.speed_limit), bool(msg.percentage))
        speed = limited_speed(self.speed, *self.limit)
        self.event(event="speed_limit", limit=msg.speed_limit, percentage=msg.percentage, speed=speed)

    def on_goal(self, request: Any) -> GoalResponse:
        self.received = time.time()  # when the goal request reached the server (the "goal" event's received_t)
        if self.reject:
            self.event(event="rejected", poses=len(_goal_poses(request)))
            return GoalResponse.REJECT
        return GoalResponse.ACCEPT

    async def on_goal_unanswered(self, request: Any) -> GoalResponse:
        """``mute``: the goal is never answered, as when the transport loses the answer (rclpy's action server
        awaits a coroutine goal callback without blocking its executor)."""
        self.event(event="unanswered", poses=len(_goal_poses(request)))
        await Future()  # never done
        return GoalResponse.REJECT

    def on_accepted(self, handle: Any) -> None:
        """A new goal pre-empts the one running (that one sees it at its next step and ends aborted)."""
        name = _action_name(handle)
        with self.lock:
            self.current = handle
        poses = _goal_poses(handle.request)
        points = [[p.pose.position.x, p.pose.position.y] for p in poses]
        frame = poses[0].header.frame_id if poses else ""
        self.event(event="goal", action=name, poses=points, frame=frame, t=time.time(), received_t=self.received)
        handle.execute()

    def execute(self, handle: Any) -> Any:
        """Drive along the goal's poses step by step, with feedback, until arrived, canceled, aborted or
        pre-empted."""
        name = _action_name(handle)
        follow = name == "follow_path"
        action = self.action_types.FollowPath if follow else self.action_types.NavigateThroughPoses
        poses = _goal_poses(handle.request)
        route = Route(np.array([[self.x, self.y]] + [[p.pose.position.x, p.pose.position.y] for p in poses]))
        last_yaw = quaternion_yaw(*_quaternion(poses[-1])) if poses else self.yaw
        began = last = time.monotonic()
        self.aborting.clear()
        while True:
            time.sleep(self.step)
            ending = self.interrupted(handle)
            if ending is not None:  # stopped where it is: not one step further
                break
            now = time.monotonic()
            speed = limited_speed(self.speed, *self.limit)
            route.advance(speed * (now - last))
            last = now
            self.x, self.y, self.yaw = route.pose(self.yaw)
            self.publish_pose()
            if route.remaining <= 0.0:
                ending = "succeeded"
                break
            handle.publish_feedback(self.feedback(action, route, speed, now - began))
        if ending == "succeeded":
            self.yaw = last_yaw
            self.publish_pose()
        self.event(event=ending, action=name, x=self.x, y=self.y, t=time.time())
        return self.result(action, handle, ending)

    def interrupted(self, handle: Any) -> str | None:
        """Why the goal stops before arriving (pre-empted, canceled, told to abort), or None while it goes on."""
        with self.lock:
            if self.current is not handle:
                return "preempted"
        if handle.is_cancel_requested:
            return "canceled"
        return "aborted" if self.aborting.is_set() else None

    def feedback(self, action: Any, route: Route, speed: float, elapsed: float) -> Any:
        fb = action.Feedback()
        if action is self.action_types.FollowPath:
            fb.distance_to_goal, fb.speed = route.remaining, speed
            return fb
        fb.current_pose.header.frame_id = self.frame
        fb.current_pose.pose.position.x, fb.current_pose.pose.position.y = self.x, self.y
        q = fb.current_pose.pose.orientation
        q.x, q.y, q.z, q.w = yaw_quaternion(self.yaw)
        fb.navigation_time = _duration(elapsed)
        fb.estimated_time_remaining = _duration(route.remaining / speed if speed > 0 else 0.0)
        fb.distance_remaining, fb.number_of_poses_remaining = route.remaining, route.poses_after()
        return fb

    def result(self, action: Any, handle: Any, ending: str) -> Any:
        result = action.Result()
        if ending == "succeeded":
            handle.succeed()
        elif ending == "canceled":
            handle.canceled()
        else:
            result.error_code = FAILED_TO_MAKE_PROGRESS  # bt_navigator passes on its controller's code
            result.error_msg = "preempted by a newer goal" if ending == "preempted" else "aborted (told to)"
            handle.abort()
        return result


def _action_name(handle: Any) -> str:
    return "follow_path" if hasattr(handle.request, "path") else "navigate_through_poses"


def _goal_poses(goal: Any) -> list:
    return list(goal.path.poses) if hasattr(goal, "path") else list(goal.poses)


def _quaternion(pose: Any) -> tuple[float, float, float, float]:
    q = pose.pose.orientation
    return q.x, q.y, q.z, q.w


def _duration(seconds: float) -> Duration:
    whole = math.floor(seconds)
    return Duration(sec=int(whole), nanosec=int((seconds - whole) * 1e9))


def main(argv: list[str] | None = None) -> None:
    """Command line: run the stand-in until interrupted."""
    parser = argparse.ArgumentParser(prog="python -m spcotmhp.ros.standin_nav2", description=__doc__.split("\n")[0])
    parser.add_argument("--speed", type=float, default=0.5, help="m/s (default 0.5)")
    parser.add_argument("--rate", type=float, default=20.0, help="steps per second (default 20)")
    parser.add_argument("--x", type=float, default=0.0, help="start x in metres")
    parser.add_argument("--y", type=float, default=0.0, help="start y in metres")
    parser.add_argument("--reject", action="store_true", help="reject every goal")
    parser.add_argument("--mute", action="store_true", help="never answer a goal (as when the answer is lost)")
    args = parser.parse_args(argv)
    if not (args.speed > 0 and args.rate > 0 and math.isfinite(args.speed) and math.isfinite(args.rate)):
        parser.error("--speed and --rate must be positive numbers")
    with ros_running():
        node = StandInNav2(args.speed, args.rate, (args.x, args.y), args.reject, mute=args.mute)
        executor = MultiThreadedExecutor(num_threads=4)
        executor.add_node(node)
        try:
            spin_until_shutdown(node, executor)
        finally:
            with bounded_shutdown("the stand-in Nav2"):
                node.destroy_node()
                quiet_shutdown()


if __name__ == "__main__":
    main()
