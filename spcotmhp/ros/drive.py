"""The node as a Nav2 client (``spcotmhp ros2 MODEL --drive follow_path|through_poses``): a plan becomes goals.

* ``follow_path`` (the default): Nav2's controller follows the planned, footprint-safe path itself (FollowPath on
  controller_server's ``follow_path``); ``through_poses``: NavigateThroughPoses on bt_navigator's
  ``navigate_through_poses`` through the plan's waypoints and goal, Nav2's planner re-planning between them.
* The plan is cut into legs at the places where it waits (:func:`plan_legs`): the next leg is sent after the wait
  ("until told": nothing more is sent; the next instruction plans from where the robot is; only the goal may wait
  with no length, the instruction grammar's rule, so no leg is left undriven by it).
* The instruction's speed sets Nav2's speed limit (nav2_msgs/SpeedLimit on ``speed_limit``, controller_server's
  topic): "slowly" ``slow_percent`` % of the controller's maximum; otherwise no limit (Nav2's limit can only lower
  the configured maximum, so "quickly" is the maximum).
* Feedback becomes ``drive`` statuses on spcotmhp/status: the place being passed and the metres remaining (at
  most one a PROGRESS_EVERY_S, and at once when a new place is passed), ``arrived`` at every leg's end.
* "stop", "cancel", "never mind", 止まって... (:func:`is_stop`) cancel the goal; a new instruction pre-empts the
  running one (its goal canceled, its waits dropped); a rejected or aborted goal is an ``error`` status with its
  cause (typed: Nav2Unavailable, Nav2Rejected, Nav2Failed) and the robot's position; so is a goal Nav2 never
  answers (:meth:`Driver.watch`: nothing is left waiting for ever on a message the transport lost).
"""

from __future__ import annotations

import functools
import re
import time
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from action_msgs.msg import GoalStatus
from geometry_msgs.msg import PoseStamped
from rclpy.action import ActionClient

from spcotmhp.errors import DriveError, Nav2Failed, Nav2Rejected, Nav2Unavailable
from spcotmhp.ros.nav2_types import import_nav2_msgs
from spcotmhp.ros.shapes import error_status, path_yaws, yaw_quaternion

FOLLOW_PATH, THROUGH_POSES = "follow_path", "through_poses"
MODES = (FOLLOW_PATH, THROUGH_POSES)
SERVERS = {FOLLOW_PATH: "follow_path", THROUGH_POSES: "navigate_through_poses"}  # Nav2's default action names
SLOW_PERCENT = 50.0  # "slowly": half the controller's maximum speed (a parameter: robots differ)
SERVER_WAIT_S = 2.0  # Nav2 found within this of the node's start is waited for, not an error (discovery lags)
GOAL_ANSWER_S = 10.0  # a goal Nav2 has not answered in this long was lost on the way (or Nav2 hangs): an error status
RESULT_AGAIN_S = 2.0  # Nav2 said the goal ended but no result came in this long: the result was lost, asked again
WATCH_EVERY_S = 0.5
PROGRESS_EVERY_S = 1.0  # a status a second is what a listener (speech, a screen) can follow
ENDED = (GoalStatus.STATUS_SUCCEEDED, GoalStatus.STATUS_ABORTED, GoalStatus.STATUS_CANCELED)
STOP_WORDS = frozenset(
    {"stop", "halt", "cancel", "never mind", "nevermind", "stop there", "stop now", "止まって", "止まれ", "とまって",
     "止まる", "ストップ", "やめて", "キャンセル", "中止"}
)  # fmt: skip


def is_stop(text: str) -> bool:
    """Whether an instruction means "stop the robot": a stop word alone, maybe with "please"/ください and
    punctuation ("Stop!", "please stop", "止まってください")."""
    t = re.sub(r"[\s.,!?。、！？]+", " ", text.lower()).strip()
    t = re.sub(r"^please |,? please$", "", t).removesuffix("ください").strip()
    return t in STOP_WORDS


@dataclass(frozen=True)
class Leg:
    """One goal: path points ``start``..``end`` (indices, inclusive) ending at the stop ``to``; ``stops``: the
    indices of the waypoints on it and its end (NavigateThroughPoses' poses); ``wait``: seconds to wait at its end
    before the next leg (0: none; None: until the next instruction)."""

    start: int
    end: int
    to: str
    stops: tuple[int, ...]
    wait: float | None = 0.0


def _index_near(points: np.ndarray, target: tuple[float, float], lo: int, tol: float) -> int:
    """The first path index from ``lo`` on within ``tol`` of the nearest approach to ``target``."""
    d = np.linalg.norm(points[lo:] - np.asarray(target, dtype=float), axis=1)
    return lo + int(np.flatnonzero(d <= d.min() + tol)[0])


def plan_legs(
    plan: Any, points: np.ndarray, centres: Mapping[int, tuple[float, float]] | None = None
) -> tuple[list[Leg], list[tuple[int, str]]]:
    """The plan's legs (cut at the stops it waits at; the last ends at the goal, the path's end) and every place
    on it as (path index where it is reached, label), in order, for "passing ..." statuses. A place passed on the
    way has no point on the plan: it is reached where the path comes nearest its centre (``centres``, by place
    id), never before the place before it."""
    centres = centres or {}
    n = len(points)
    steps = np.linalg.norm(np.diff(points, axis=0), axis=1)
    tol = 0.5 * float(np.median(steps)) if len(steps) else 0.0  # half a step: the points are cell centres
    marks: list[tuple[int, str]] = []
    stop_at: list[int] = []
    lo = 0
    for place in plan.places:
        if place.role == "start":
            at = 0
        elif place.role == "goal":
            at = n - 1  # the path ends where the plan arrives
        elif place.point is not None:  # on the path (to half a step)
            at = lo = _index_near(points, place.point, lo, tol)
        elif place.id in centres:  # off the path: where it comes nearest
            at = lo = _index_near(points, centres[place.id], lo, 0.0)
        elif place.role == "waypoint":
            at = lo
        else:
            continue  # a place passed on the way with no point on the plan
        marks.append((at, place.label))
        if place.role in ("waypoint", "goal"):
            stop_at.append(at)
    stops = plan.stops
    waits = {s: seconds for s, seconds in plan.instruction.waits if s < len(stops)}
    legs: list[Leg] = []
    first = 0  # the first stop of the leg being made
    for s, stop in enumerate(stops):
        if s in waits or s == len(stops) - 1:
            start = legs[-1].end if legs else 0
            legs.append(Leg(start, stop_at[s], stop.label, tuple(stop_at[first : s + 1]), waits.get(s, 0.0)))
            first = s + 1
    return legs, marks


@dataclass
class Run:
    """A plan being driven: its legs, the one running (``next`` - 1 once sent), and for progress the path's
    cumulative lengths and the places on it."""

    legs: list[Leg]
    marks: list[tuple[int, str]]
    points: np.ndarray
    instruction: str
    cum: np.ndarray = field(init=False)
    next: int = 0
    handle: Any = None
    timer: Any = None
    sent_at: float | None = None  # when the running leg's goal was sent, until Nav2 answers it (Driver.watch)
    ended_at: float | None = None  # when Nav2's status said the goal ended, until its result comes
    said: tuple[str, float] = ("", 0.0)  # the last place said passing, and when
    poses: list | None = None  # the published Path's PoseStamped list (Driver.goal)

    def __post_init__(self) -> None:
        steps = np.linalg.norm(np.diff(self.points, axis=0), axis=1)
        self.cum = np.concatenate([[0.0], np.cumsum(steps)])

    def progress(self, leg: Leg, leg_remaining: float) -> tuple[str, float]:
        """(place being passed, metres remaining to the goal) from the metres Nav2 says remain on ``leg``."""
        along = self.cum[leg.end] - max(leg_remaining, 0.0)
        at = int(np.searchsorted(self.cum, along, side="right")) - 1
        passing = [label for i, label in self.marks if i <= at]
        return (passing[-1] if passing else ""), float(leg_remaining + self.cum[-1] - self.cum[leg.end])


class Driver:
    """Sends a node's plans to Nav2 (module docstring); ``report`` publishes a status dict, ``where`` gives the
    robot's latest pose (x, y, yaw) or None."""

    def __init__(
        self,
        node: Any,
        mode: str,
        frame: str,
        report: Callable[[dict], None],
        where: Callable[[], tuple[float, float, float] | None],
        slow_percent: float = SLOW_PERCENT,
    ) -> None:
        if mode not in MODES:
            raise DriveError(f"--drive must be one of {', '.join(MODES)}, got {mode!r}")
        self.node, self.mode, self.frame, self.report, self.where = node, mode, frame, report, where
        self.slow_percent = slow_percent
        self.action, msg = import_nav2_msgs()
        self.SpeedLimit = msg.SpeedLimit
        kind = self.action.FollowPath if mode == FOLLOW_PATH else self.action.NavigateThroughPoses
        self.client = ActionClient(node, kind, SERVERS[mode])
        self.speed_pub = node.create_publisher(msg.SpeedLimit, "speed_limit", 10)
        self.run: Run | None = None
        node.create_timer(WATCH_EVERY_S, self.watch)

    # ---- commands ----------------------------------------------------------------------------------------------
    def drive(
        self,
        plan: Any,
        points: np.ndarray,
        instruction: str,
        centres: Mapping[int, tuple[float, float]],
        poses: list | None = None,
    ) -> None:
        """Drive ``plan`` (its path poses ``points``; ``centres`` of the places by id, for the places passed;
        ``poses``: the published Path's PoseStamped list, reused for the first FollowPath leg): set the speed
        limit, send the first leg, then cancel what ran before (after: the new goal is on its way sooner, and
        Nav2's servers pre-empt a running goal with a new one anyway). No action server within SERVER_WAIT_S is a
        Nav2Unavailable error status with the robot's position, as every Nav2 failure is."""
        if not self.client.server_is_ready() and not self.client.wait_for_server(timeout_sec=SERVER_WAIT_S):
            unavailable = Nav2Unavailable(
                f"no Nav2 action server on {self.node.resolve_topic_name(SERVERS[self.mode])} "
                f"(is Nav2 up and active? --drive {self.mode})"
            )
            self.report({**error_status(unavailable, instruction), "where": self._where()})
            return
        points = np.asarray(points, dtype=float)
        legs, marks = plan_legs(plan, points, centres)
        before, self.run = self.run, Run(legs, marks, points, instruction, poses=poses)
        self.set_speed(plan.instruction.speed)
        self.start_leg(self.run)
        if before is not None:
            self._end(before, "a new instruction")

    def stopping(self, instruction: str) -> bool:
        """Whether ``instruction`` is a stop word (:func:`is_stop`): then the goal is canceled (a ``canceled``
        status, or ``idle`` when nothing ran) and the instruction is not planned."""
        if not is_stop(instruction):
            return False
        if not self.stop(f"told: {instruction!r}"):
            self.report({"kind": "drive", "event": "idle", "instruction": instruction})
        return True

    def stop(self, reason: str) -> bool:
        """Cancel the goal running and any wait; a ``canceled`` status when something was running."""
        run, self.run = self.run, None
        if run is None:
            return False
        self._end(run, reason)
        return True

    def _end(self, run: Run, reason: str) -> None:
        """Cancel ``run``'s goal and wait (no longer ``self.run``), and say so."""
        if run.timer is not None:
            run.timer.cancel()
            self.node.destroy_timer(run.timer)
        if run.handle is not None:
            run.handle.cancel_goal_async()
        self.say(run, "canceled", reason=reason, where=self._where())

    def set_speed(self, speed: str | None) -> None:
        limit = self.SpeedLimit(percentage=True, speed_limit=self.slow_percent if speed == "slow" else 0.0)
        limit.header.frame_id, limit.header.stamp = self.frame, self.node.get_clock().now().to_msg()
        self.speed_pub.publish(limit)

    # ---- the legs ----------------------------------------------------------------------------------------------
    def start_leg(self, run: Run) -> None:
        leg = run.legs[run.next]
        run.next += 1
        if leg.end <= leg.start:  # already there (a wait at the start): nothing to drive
            self.arrived(run, leg)
            return
        goal = self.goal(run, leg)
        sent = self.client.send_goal_async(goal, feedback_callback=functools.partial(self.on_feedback, run, leg))
        sent.add_done_callback(functools.partial(self.on_sent, run, leg))
        run.sent_at, run.ended_at = time.monotonic(), None
        self.say(run, "goal", action=SERVERS[self.mode], leg=run.next, legs=len(run.legs), to=leg.to,
                 length_m=round(float(run.cum[leg.end] - run.cum[leg.start]), 3))  # fmt: skip

    def goal(self, run: Run, leg: Leg) -> Any:
        """FollowPath with the leg's path, or NavigateThroughPoses through its stops (headings along the path).
        The first leg, sent at once, reuses the Path's poses (the same points, headings and stamp)."""
        if self.mode == FOLLOW_PATH and run.poses is not None and run.next == 1:
            goal = self.action.FollowPath.Goal()
            goal.path.header.frame_id = self.frame
            goal.path.header.stamp = run.poses[0].header.stamp
            goal.path.poses = run.poses[leg.start : leg.end + 1]
            return goal
        pose = self.where()
        yaws = path_yaws(run.points, pose[2] if pose else 0.0)
        indices = range(leg.start, leg.end + 1) if self.mode == FOLLOW_PATH else leg.stops
        stamp = self.node.get_clock().now().to_msg()
        poses = []
        for i in indices:
            pose = PoseStamped()
            pose.header.frame_id, pose.header.stamp = self.frame, stamp
            pose.pose.position.x, pose.pose.position.y = float(run.points[i][0]), float(run.points[i][1])
            q = pose.pose.orientation
            q.x, q.y, q.z, q.w = yaw_quaternion(float(yaws[i]))
            poses.append(pose)
        if self.mode == FOLLOW_PATH:
            goal = self.action.FollowPath.Goal()
            goal.path.header.frame_id, goal.path.header.stamp = self.frame, stamp
            goal.path.poses = poses
            return goal
        return self.action.NavigateThroughPoses.Goal(poses=poses)

    def on_sent(self, run: Run, leg: Leg, future: Any) -> None:
        handle = future.result()
        if run is not self.run:  # pre-empted or stopped meanwhile: the goal must not run on
            if handle.accepted:
                handle.cancel_goal_async()
            return
        run.sent_at = None
        if not handle.accepted:
            self.fail(run, Nav2Rejected(f"Nav2 rejected the goal to {leg.to} ({SERVERS[self.mode]})"))
            return
        run.handle = handle
        handle.get_result_async().add_done_callback(functools.partial(self.on_result, run, leg, handle))

    def watch(self) -> None:
        """What a ROS 2 transport can lose, watched (a service's request or answer sent before both ends matched is
        not delivered, and rclpy waits for it for ever): a goal not answered within GOAL_ANSWER_S is a
        Nav2Unavailable error status (the robot's user hears why, instead of nothing); a goal Nav2's status topic
        says has ended, with no result RESULT_AGAIN_S later, has its result asked for again."""
        run, now = self.run, time.monotonic()
        if run is None:
            return
        if run.sent_at is not None and now - run.sent_at > GOAL_ANSWER_S:
            to = run.legs[run.next - 1].to
            self.fail(run, Nav2Unavailable(f"Nav2 did not answer the goal to {to} within {GOAL_ANSWER_S:g} s "
                                           f"({self.node.resolve_topic_name(SERVERS[self.mode])})"))  # fmt: skip
            return
        handle = run.handle
        if handle is None or handle.status not in ENDED:
            run.ended_at = None
        elif run.ended_at is None:
            run.ended_at = now
        elif now - run.ended_at > RESULT_AGAIN_S:
            run.ended_at = now
            leg = run.legs[run.next - 1]
            handle.get_result_async().add_done_callback(functools.partial(self.on_result, run, leg, handle))

    def on_feedback(self, run: Run, leg: Leg, msg: Any) -> None:
        if run is not self.run:
            return
        fb = msg.feedback
        remaining = fb.distance_to_goal if self.mode == FOLLOW_PATH else fb.distance_remaining
        passing, total = run.progress(leg, float(remaining))
        now = time.monotonic()
        if passing != run.said[0] or now - run.said[1] >= PROGRESS_EVERY_S:
            run.said = (passing, now)
            self.say(run, "progress", passing=passing, remaining_m=round(total, 2), leg=run.next)

    def on_result(self, run: Run, leg: Leg, handle: Any, future: Any) -> None:
        if run is not self.run or handle is not run.handle:  # stopped, or a result asked for again came twice
            return
        answer = future.result()
        run.handle = None
        if answer.status == GoalStatus.STATUS_SUCCEEDED:
            self.arrived(run, leg)
        elif answer.status == GoalStatus.STATUS_ABORTED:
            code, text = answer.result.error_code, answer.result.error_msg or "no message"
            self.fail(run, Nav2Failed(f"Nav2 aborted the goal to {leg.to}: {text} (error code {code})"))
        elif answer.status == GoalStatus.STATUS_CANCELED:  # by someone else than this node (it forgets its own)
            self.run = None
            self.say(run, "canceled", reason="canceled by Nav2 or another client", where=self._where())

    def arrived(self, run: Run, leg: Leg) -> None:
        final = run.next == len(run.legs)
        self.say(run, "arrived", place=leg.to, final=final, wait_s=leg.wait, where=self._where())
        if leg.wait is None:
            self.run = None  # waits until told: the next instruction plans from here
        elif final:
            self.run = None
        elif leg.wait > 0:
            run.timer = self.node.create_timer(leg.wait, functools.partial(self.after_wait, run))
        else:
            self.start_leg(run)

    def after_wait(self, run: Run) -> None:
        if run.timer is not None:
            run.timer.cancel()
            self.node.destroy_timer(run.timer)
            run.timer = None
        if run is self.run:
            self.start_leg(run)

    # ---- statuses ----------------------------------------------------------------------------------------------
    def _where(self) -> list[float] | None:
        pose = self.where()
        return None if pose is None else [round(pose[0], 3), round(pose[1], 3)]

    def say(self, run: Run, event: str, **fields: Any) -> None:
        self.report({"kind": "drive", "event": event, "instruction": run.instruction, **fields})

    def fail(self, run: Run, exc: DriveError) -> None:
        self.run = None
        self.report({**error_status(exc, run.instruction), "where": self._where()})
