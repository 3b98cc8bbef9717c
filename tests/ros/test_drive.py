"""The node as a Nav2 client (spcotmhp.ros.drive): stop words and legs by hand, then `spcotmhp ros2 M --drive
follow_path` in a subprocess beside the stand-in Nav2 (another subprocess, which is also the robot's AMCL pose),
talked to with real messages: the goal matches the plan, feedback becomes statuses, a wait splits the plan into
two legs that long apart, a speed word sets the speed limit, "stop" cancels, a new instruction pre-empts, an
abort, a rejection or a goal never answered becomes an error with the robot's position, a lost result is asked
for again, a wait "until told" holds the robot where it arrived until the next instruction, and a restarted node
takes over. Skipped only without the extra ros2; with it,
fails (naming `make nav2-msgs`) when nav2_msgs was not built."""

from __future__ import annotations

import contextlib
import math
import os
import warnings
from collections.abc import Iterator
from types import SimpleNamespace

import numpy as np
import pytest

pytest.importorskip("rclpy")

from std_msgs.msg import Empty, String  # noqa: E402

from spcotmhp.datasets.bundled import load_bundled  # noqa: E402
from spcotmhp.learning.supervised import fit_supervised  # noqa: E402
from spcotmhp.persistence.io import save_model  # noqa: E402
from spcotmhp.planning.plan import PlanPlace  # noqa: E402
from spcotmhp.ros.drive import Leg, is_stop, plan_legs  # noqa: E402
from tests.ros.nav2_client import DriveClient, node_ready, standin, start_node, stop_node  # noqa: E402

DOMAIN = str(15 + os.getpid() % 5)  # 15..19: not the other ROS tests' domains
REJECTING_DOMAIN = str(1 + os.getpid() % 9)  # 1..9, for a rejecting stand-in (test_standin_nav2's, not at once)
NO_NAV2_DOMAIN = str(10 + os.getpid() % 5)  # 10..14, with no Nav2 at all (test_nav2_msgs's, not at once)
START = (-3.9, -3.5)  # the README's start in 3LDK_06 (the entrance)
SPEED = 3.0


@pytest.mark.parametrize(
    "text", ["stop", "Stop!", "please stop", "cancel", "never mind", "止まって", "止まってください", "ストップ"]
)
def test_stop_words(text):
    assert is_stop(text)


@pytest.mark.parametrize("text", ["go to the bus stop", "stop by the kitchen", "kitchen", "", "止まっている"])
def test_not_stop_words(text):
    assert not is_stop(text)


def _plan(places, waits):
    stops = [p for p in places if p.role in ("waypoint", "goal")]
    return SimpleNamespace(places=places, stops=stops, instruction=SimpleNamespace(waits=waits))


def test_legs_cut_at_the_waits():
    points = np.array([[0.0, 0.0], [1.0, 0.0], [2.0, 0.0], [3.0, 0.0], [4.0, 0.0]])
    places = [
        PlanPlace(0, "hall", "start"),
        PlanPlace(1, "corridor", "via"),
        PlanPlace(2, "kitchen", "waypoint", point=(2.0, 0.1)),
        PlanPlace(3, "bath", "goal", point=(4.0, 0.0)),
    ]
    legs, marks = plan_legs(_plan(places, ((0, 3.0),)), points, {1: (1.2, 5.0)})
    assert legs == [Leg(0, 2, "kitchen", (2,), 3.0), Leg(2, 4, "bath", (4,), 0.0)]
    assert marks == [(0, "hall"), (1, "corridor"), (2, "kitchen"), (4, "bath")]
    legs, _ = plan_legs(_plan(places, ()), points)  # no wait: one leg through the waypoint; no centre: no mark
    assert legs == [Leg(0, 4, "bath", (2, 4), 0.0)]
    legs, _ = plan_legs(_plan(places, ((1, None),)), points)  # until told, at the goal
    assert legs == [Leg(0, 4, "bath", (2, 4), None)]


@pytest.fixture(scope="module")
def robot(tmp_path_factory):
    root = tmp_path_factory.mktemp("drive")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        folder = save_model(fit_supervised(load_bundled("3LDK_06")), root / "model")
    args = ("--speed", str(SPEED), "--x", str(START[0]), "--y", str(START[1]))
    with standin(root, DOMAIN, *args, client_class=DriveClient) as client:
        env = {k: os.environ[k] for k in ("ROS_AUTOMATIC_DISCOVERY_RANGE", "ROS_DOMAIN_ID", "ROS_LOG_DIR")}
        robot = SimpleNamespace(client=client, proc=start_node(folder, env), folder=folder, env=env)
        try:
            node_ready(client, robot.proc)
            yield robot
        finally:
            stop_node(robot.proc)  # the node running now (a test restarts it)


def _arrive(client: DriveClient, text: str) -> tuple[int, int]:
    marks = client.tell(text)
    client.until_drive(marks[0], "arrived")
    assert client.spin_until(lambda: any(s["final"] for s in client.drive_events(marks[0], "arrived")))
    return marks


def test_plan_becomes_a_follow_path_goal_with_progress(robot):
    c = robot.client
    status0, events0 = _arrive(c, "go to the bedroom via the corridor")
    plan = c.plans[-1]
    goal = c.event("goal", events0)
    assert goal["action"] == "follow_path" and goal["frame"] == "map"
    assert np.allclose(goal["poses"], [[p.pose.position.x, p.pose.position.y] for p in plan.poses])
    passing = [s["passing"] for s in c.drive_events(status0, "progress")]
    assert "corridor" in passing
    remaining = [s["remaining_m"] for s in c.drive_events(status0, "progress")]
    assert remaining == sorted(remaining, reverse=True)
    final = c.drive_events(status0, "arrived")[-1]
    assert final["final"] and final["place"].startswith("bedroom")
    end = plan.poses[-1].pose.position
    assert math.dist(final["where"], (end.x, end.y)) < 1e-3


@pytest.mark.parametrize(
    "text",
    [
        "go to the kitchen via the corridor, wait in the corridor for 3 seconds",
        "go to the corridor and wait there for 3 s, then go to the kitchen",  # the "wait there for 3 s"
    ],
)
def test_a_wait_makes_two_legs_that_long_apart(robot, text):
    c = robot.client
    _, events0 = _arrive(c, text)
    goals = [e for e in c.events[events0:] if e["event"] == "goal"]
    ends = [e for e in c.events[events0:] if e["event"] == "succeeded"]
    assert len(goals) == 2 and len(ends) == 2
    assert goals[1]["t"] - ends[0]["t"] >= 3.0 - 0.05  # the wait, at least (its duration honoured)
    assert goals[1]["poses"][0] == pytest.approx(goals[0]["poses"][-1])  # the second leg starts where the first ended


def test_slowly_sets_the_speed_limit(robot):
    c = robot.client
    _, events0 = _arrive(c, "go slowly to the bath")
    limits = [e for e in c.events[events0:] if e["event"] == "speed_limit"]
    assert limits[0]["percentage"] and limits[0]["limit"] == 50.0 and limits[0]["speed"] == SPEED / 2
    _, events1 = _arrive(c, "go to the entrance")
    assert [e["limit"] for e in c.events[events1:] if e["event"] == "speed_limit"] == [0.0]  # no limit again


def _driving(c: DriveClient, text: str) -> tuple[int, int]:
    marks = c.tell(text)
    c.until_drive(marks[0], "progress")
    return marks


def test_stop_cancels_the_goal(robot):
    c = robot.client
    status0, events0 = _driving(c, "go to the bedroom")
    c.tell("stop")
    canceled = c.until_drive(status0, "canceled")
    assert "stop" in canceled["reason"]
    assert c.event("canceled", events0)
    assert not c.drive_events(status0, "arrived")


def test_a_new_instruction_preempts(robot):
    c = robot.client
    status0, events0 = _driving(c, "go to the bedroom")
    status1, _ = _arrive(c, "go to the kitchen")
    assert c.drive_events(status0, "canceled")[0]["reason"] == "a new instruction"
    assert [s["place"] for s in c.drive_events(status1, "arrived")] == ["kitchen"]
    assert any(e["event"] in ("canceled", "preempted") for e in c.events[events0:])


def test_an_abort_is_an_error_with_the_position(robot):
    c = robot.client
    status0, _ = _driving(c, "go to the bedroom")
    c.abort.publish(Empty())
    assert c.spin_until(lambda: bool(c.errors(status0)))
    error = c.errors(status0)[0]
    assert error["type"] == "Nav2Failed" and "error code 105" in error["error"]
    assert len(error["where"]) == 2 and all(math.isfinite(v) for v in error["where"])


def test_a_rejected_goal_is_an_error_with_the_cause_and_position(robot, tmp_path):
    """Nav2 rejecting the goal (as a Nav2 that is up but not yet active does): a Nav2Rejected error status naming
    the goal and the action, with the robot's position; nothing is said to be driven or reached; the node keeps
    serving."""
    with _node_beside_a_standin(robot, tmp_path, "--reject") as c:
        for text in ("go to the bedroom", "go to the kitchen via the corridor"):  # twice: it keeps serving
            status0, events0 = c.tell(text)
            assert c.spin_until(lambda: bool(c.errors(status0)))  # noqa: B023 - called here, in this turn
            error = c.errors(status0)[0]
            place = text.split()[3]
            assert error["type"] == "Nav2Rejected" and error["instruction"] == text
            assert f"rejected the goal to {place}" in error["error"] and "follow_path" in error["error"]
            assert error["where"] == pytest.approx(list(START), abs=1e-3)  # the stand-in never moved
            assert c.event("rejected", events0)["poses"] > 1
            assert not c.drive_events(status0, "arrived") and not c.drive_events(status0, "progress")


@contextlib.contextmanager
def _node_beside_a_standin(robot, tmp_path, option: str) -> Iterator[DriveClient]:
    """A stand-in of its own at START with ``option`` (--reject, --mute), and a node of its own driving it."""
    args = (option, "--x", str(START[0]), "--y", str(START[1]))
    with standin(tmp_path, REJECTING_DOMAIN, *args, client_class=DriveClient) as c:
        env = {k: os.environ[k] for k in ("ROS_AUTOMATIC_DISCOVERY_RANGE", "ROS_DOMAIN_ID", "ROS_LOG_DIR")}
        proc = start_node(robot.folder, env)
        try:
            node_ready(c, proc)
            yield c
        finally:
            stop_node(proc)


def test_a_goal_nav2_never_answers_is_an_error_not_silence(robot, tmp_path):
    """A goal whose answer never comes (the stand-in's --mute: as when ROS 2 loses a service answer sent before
    both ends matched): after GOAL_ANSWER_S a Nav2Unavailable error status says so, naming the goal and the
    action, with the robot's position; the node keeps serving (the next instruction is answered the same way)."""
    from spcotmhp.ros.drive import GOAL_ANSWER_S

    with _node_beside_a_standin(robot, tmp_path, "--mute") as c:
        for text in ("go to the bedroom", "go to the kitchen"):
            status0, events0 = c.tell(text)
            assert c.event("unanswered", events0)["poses"] > 1  # the goal reached the stand-in
            assert c.spin_until(lambda: bool(c.errors(status0)), GOAL_ANSWER_S + 30)  # noqa: B023
            error = c.errors(status0)[0]
            place = text.split()[3]
            assert error["type"] == "Nav2Unavailable" and error["instruction"] == text
            assert f"did not answer the goal to {place}" in error["error"]
            assert f"within {GOAL_ANSWER_S:g} s (/follow_path)" in error["error"]
            assert error["where"] == pytest.approx(list(START), abs=1e-3)
            assert not c.drive_events(status0, "arrived")


def test_no_nav2_is_an_error_naming_the_action_with_the_position(robot, tmp_path):
    """--drive with no Nav2 action server (none within SERVER_WAIT_S): the plan is still published, then a
    Nav2Unavailable error status names the action and the option, with the robot's position."""
    import rclpy

    from tests.ros.test_node import Client, ros_environment

    with ros_environment(tmp_path, NO_NAV2_DOMAIN) as env:
        context = rclpy.Context()
        rclpy.init(context=context)
        c = Client(context)
        proc = start_node(robot.folder, env)
        try:
            assert c.spin_until(lambda: bool(c.places) or proc.poll() is not None, 300) and proc.poll() is None
            c.set_pose(*START)
            n = len(c.status)
            c.publish(c.instruction_pub, String(data="go to the bedroom"))
            assert c.spin_until(lambda: any(s.get("ok") is False for s in c.status[n:]), 60), c.status[n:]
            plan = next(s for s in c.status[n:] if s["kind"] == "plan")
            error = next(s for s in c.status[n:] if s.get("ok") is False)
            assert plan["ok"] and error["type"] == "Nav2Unavailable" and error["instruction"] == "go to the bedroom"
            assert "/follow_path" in error["error"] and "--drive follow_path" in error["error"]
            assert error["where"] == pytest.approx(list(START), abs=1e-3)
        finally:
            c.node.destroy_node()
            context.try_shutdown()
            stop_node(proc)


def test_a_wait_until_told_holds_the_robot_until_the_next_instruction(robot):
    """ "wait there until I tell you" (only the goal may wait with no length: the instruction grammar's rule):
    the robot arrives, says it waits with no end, nothing more is sent, and the next instruction is planned and
    driven from where it waits."""
    c = robot.client
    status0, events0 = _arrive(c, "go to the kitchen and wait there until I tell you")
    arrived = c.drive_events(status0, "arrived")
    assert len(arrived) == 1 and arrived[0]["final"] and arrived[0]["place"] == "kitchen"
    assert arrived[0]["wait_s"] is None
    c.spin_until(lambda: False, 1.5)  # while it waits, no goal is sent
    assert [e["event"] for e in c.events[events0:]].count("goal") == 1
    status1, events1 = _arrive(c, "go to the bath")
    assert c.event("goal", events1)["poses"][0] == pytest.approx(arrived[0]["where"], abs=1e-3)
    assert [s["place"] for s in c.drive_events(status1, "arrived")] == ["bath"]
    assert not c.drive_events(status0, "canceled")  # a finished wait is not a canceled goal


def test_a_restarted_node_takes_over_mid_goal(robot):
    c = robot.client
    _driving(c, "go to the bedroom")
    robot.proc.kill()  # the node dies mid-goal; the stand-in drives on
    robot.proc.wait(10)
    seen = len(c.places)
    robot.proc = start_node(robot.folder, robot.env)
    node_ready(c, robot.proc, seen)
    status0, events0 = _arrive(c, "go to the kitchen")
    assert [s["place"] for s in c.drive_events(status0, "arrived")] == ["kitchen"]
    assert any(e["event"] in ("preempted", "canceled", "succeeded") for e in c.events[events0:])


def test_through_poses_mode_sends_the_stops(robot):
    """``--drive through_poses``: one NavigateThroughPoses goal through the plan's waypoint and goal points."""
    c = robot.client
    stop_node(robot.proc)
    seen = len(c.places)
    robot.proc = start_node(robot.folder, robot.env, "through_poses")
    node_ready(c, robot.proc, seen)
    status0, events0 = _arrive(c, "go to the bath via the corridor")
    goal = c.event("goal", events0)
    assert goal["action"] == "navigate_through_poses" and len(goal["poses"]) == 2
    plan = c.plans[-1]
    end = plan.poses[-1].pose.position
    assert goal["poses"][-1] == pytest.approx([end.x, end.y])
    assert [s["place"] for s in c.drive_events(status0, "arrived")] == ["bath"]


def test_a_result_lost_is_asked_for_again_and_counted_once(monkeypatch):
    """Nav2's status says the goal ended but its result never came (a lost service answer): RESULT_AGAIN_S later
    the result is asked for again (not before); when both answers come, the arrival is said once."""
    import rclpy
    from action_msgs.msg import GoalStatus
    from rclpy.task import Future

    from spcotmhp.ros import drive

    context = rclpy.Context()
    rclpy.init(context=context)
    node = rclpy.create_node("result_again", context=context)
    try:
        reports: list[dict] = []
        driver = drive.Driver(node, drive.FOLLOW_PATH, "map", reports.append, lambda: (1.0, 0.0, 0.0))
        run = drive.Run([Leg(0, 1, "bath", (1,), 0.0)], [], np.array([[0.0, 0.0], [1.0, 0.0]]), "go to the bath")
        run.next = 1
        asked: list[Future] = []

        class Handle:
            status = GoalStatus.STATUS_SUCCEEDED

            def get_result_async(self) -> Future:
                asked.append(Future())
                return asked[-1]

        handle = Handle()
        driver.run, run.handle = run, handle
        first = Future()
        first.add_done_callback(lambda f: driver.on_result(run, run.legs[0], handle, f))
        clock = [100.0]
        monkeypatch.setattr(drive.time, "monotonic", lambda: clock[0])
        driver.watch()  # the end is seen
        clock[0] += drive.RESULT_AGAIN_S / 2
        driver.watch()
        assert not asked
        clock[0] += drive.RESULT_AGAIN_S
        driver.watch()
        assert len(asked) == 1
        answer = SimpleNamespace(status=GoalStatus.STATUS_SUCCEEDED, result=None)
        asked[0].set_result(answer)
        first.set_result(answer)  # the first answer came after all
        arrived = [r for r in reports if r.get("event") == "arrived"]
        assert len(arrived) == 1 and arrived[0]["final"] and arrived[0]["place"] == "bath"
        assert driver.run is None
    finally:
        node.destroy_node()
        context.try_shutdown()
