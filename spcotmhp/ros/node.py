"""The ``spcotmhp`` ROS 2 node: plans from instructions at the robot's pose and publishes Nav2-ready paths.

Topics (names relative to the node's namespace; with none, ``/spcotmhp/plan`` and so on):

* ``spcotmhp/instruction`` (std_msgs/String, in): a sentence ("go to the bedroom via the corridor") or the
  structured JSON the service accepts (``{"goal": ["bedroom"], "waypoints": [["corridor"]]}``). Planned with
  Algorithm 1 from the latest pose on the start topic.
* ``amcl_pose`` (geometry_msgs/PoseWithCovarianceStamped, in; ``start_topic``): the robot's pose, as AMCL
  publishes it (QoS "best available": transient local when the publisher is, so a node started after AMCL still
  gets its last pose). A pose in another frame is put in ``frame`` through ``/tf`` and ``/tf_static``
  (:mod:`spcotmhp.ros.tf_tree`), waiting up to ``tf_timeout_s`` for its transform (:mod:`spcotmhp.ros.poses`).
  A pose with no transform, not finite or off the model's map is rejected (an
  error status of type ``PoseRejected`` or its ``TransformUnavailable``) and drops the pose held: instructions
  and teaching are then refused
  (``NoValidPose``, naming why) until a valid pose arrives; an earlier pose is never used in its place.
* ``spcotmhp/plan`` (nav_msgs/Path, out, reliable, transient local depth 1): the plan in ``frame``, every pose
  stamped and facing the next, the last keeping the last segment's heading (:mod:`spcotmhp.ros.shapes`).
* ``spcotmhp/status`` (std_msgs/String, out): one JSON object per event: ``kind`` plan (explanation, places with
  roles, length, planning time), error (the one-line error and its type), taught, map (the check of ``/map``),
  heard (what the speech topics heard), drive (with ``drive``).
* ``spcotmhp/places`` (visualization_msgs/MarkerArray, out, transient local): place ellipses, names and
  topological edges, for RViz (late subscribers get it too).
* ``spcotmhp/teach`` (std_msgs/String, in): an utterance taught at the latest pose: learned at once (online
  learning, :mod:`spcotmhp.teaching.teach`; later instructions and the place markers use it; the model folder
  is not rewritten) and, with ``record``, appended to that dataset folder (:mod:`spcotmhp.ros.teaching_log`).
  A teach is applied on a worker thread of its own (the model update and ``PlanningGraph.update``), so that
  instructions keep being planned meanwhile with the planner before it; the new planner is swapped in whole
  when ready. At most ``MAX_PENDING_TEACHES`` wait or run: past that a teach is refused at once (TeachingBusy
  on the status topic). The ``taught`` status says whether it made a new place or joined one.
* ``spcotmhp/questions`` (std_msgs/String, out, transient local): ``{"questions": [...]}`` where an answer would
  help the model most (:mod:`spcotmhp.teaching.questions`), published at start and after every teach; answer one
  at its (x, y) on ``spcotmhp/answer``.
* ``spcotmhp/answer`` (std_msgs/String, in): the answer to a question, said at the latest pose: a teach as on
  ``spcotmhp/teach``, learned as an answer (:mod:`spcotmhp.teaching.answers`: its own segment, and a split of
  its place when the robot's walk says the place is two); the ``taught`` status has ``"answer": true``.
* ``spcotmhp/audio`` (std_msgs/UInt8MultiArray, in) and ``spcotmhp/hypotheses`` (std_msgs/String, in): a spoken
  instruction as PCM chunks, recognised as the CLI's, or an external recogniser's N-best JSON; then served as an
  instruction (:mod:`spcotmhp.ros.hearing`, formats in :mod:`spcotmhp.ros.audio_input`).
* ``map`` (nav_msgs/OccupancyGrid, in): compared with the model's map; a differing size, resolution or origin
  is logged as a warning and reported on the status topic.

With ``drive`` (``--drive follow_path|through_poses``), every plan also becomes Nav2 goals, its progress
``drive`` statuses, "stop" a cancel (:mod:`spcotmhp.ros.drive`).

No message can stop the node: every callback answers a failure on the status topic (bad input as the library's
one-line typed error; anything else as an internal error, also logged).
"""

from __future__ import annotations

import colorsys
import functools
import json
import time
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path as FilePath
from typing import Any

import numpy as np
from geometry_msgs.msg import Point, PoseStamped, PoseWithCovarianceStamped
from nav_msgs.msg import OccupancyGrid, Path
from rclpy.node import Node
from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy
from std_msgs.msg import String
from visualization_msgs.msg import Marker, MarkerArray

from spcotmhp.collector import end_startup
from spcotmhp.errors import SpcotmhpError, TeachingBusy
from spcotmhp.planning.planner import HierarchicalPlanner
from spcotmhp.ros.hearing import Hearing, HearingSettings
from spcotmhp.ros.poses import TF_TIMEOUT_S, PoseKeeper
from spcotmhp.ros.shapes import (
    error_status,
    map_mismatches,
    path_poses,
    path_yaws,
    place_shapes,
    plan_status,
    quaternion_yaw,
    yaw_quaternion,
)
from spcotmhp.ros.spinning import bounded_shutdown, quiet_shutdown, ros_running, spin_until_shutdown
from spcotmhp.ros.teaching_log import TeachingLog
from spcotmhp.ros.worker import BoundedWorker
from spcotmhp.teaching.teach import planner_for, teach

LATCHED = QoSProfile(depth=1, reliability=ReliabilityPolicy.RELIABLE, durability=DurabilityPolicy.TRANSIENT_LOCAL)
MATCH_PUBLISHER = QoSProfile(
    depth=1, reliability=ReliabilityPolicy.BEST_AVAILABLE, durability=DurabilityPolicy.BEST_AVAILABLE
)
EVENTS = QoSProfile(depth=10, reliability=ReliabilityPolicy.RELIABLE, durability=DurabilityPolicy.VOLATILE)
MAX_PENDING_TEACHES = 4  # teaches waiting or running on the teaching thread (each holds a model copy)


@dataclass(frozen=True)
class TeachJob:
    """A teach waiting for the teaching thread: the utterance (``data``, as a String message has) and the pose."""

    data: str
    x: float
    y: float
    answer: bool = False  # said on spcotmhp/answer: it answers one of the questions (teaching.answers)


def answered(kind: str) -> Callable:
    """Wrap a callback so that any failure is answered on the status topic instead of ending the node."""

    def wrap(callback: Callable) -> Callable:
        @functools.wraps(callback)
        def guarded(self: SpcotmhpNode, msg) -> None:
            text = getattr(msg, "data", None)
            try:
                callback(self, msg)
            except SpcotmhpError as exc:
                self.status(error_status(exc, text, kind))
            except Exception as exc:  # noqa: BLE001 - the node must keep serving; the cause is logged
                self.get_logger().error(f"{kind}: internal error {type(exc).__name__}: {exc}")
                self.status(error_status(RuntimeError(f"internal error ({type(exc).__name__}: {exc})"), text, kind))

        return guarded

    return wrap


class SpcotmhpNode(Node):
    """The node (module docstring) around a :class:`HierarchicalPlanner`."""

    def __init__(
        self,
        planner: HierarchicalPlanner,
        frame: str = "map",
        start_topic: str = "amcl_pose",
        log: TeachingLog | None = None,
        drive: str | None = None,
        tf_timeout_s: float = TF_TIMEOUT_S,
        hearing: HearingSettings | None = None,
    ) -> None:
        super().__init__("spcotmhp")
        self.planner, self.frame, self.log = planner, frame, log
        self.poses = PoseKeeper(self, frame, lambda: self.planner.model.require_map(), self.status, tf_timeout_s)
        self.driver = None  # with ``drive``, plans become Nav2 goals (spcotmhp.ros.drive)
        self._centres: tuple[object, dict] = (None, {})
        if drive is not None:
            from spcotmhp.ros.drive import Driver

            self.driver = Driver(self, drive, frame, report=self.status, where=lambda: self.poses.pose)
        self.teacher = BoundedWorker("spcotmhp-teach", MAX_PENDING_TEACHES, lambda n: TeachingBusy(
            f"{n} teaches are waiting or being applied (the limit); teach again shortly"))  # fmt: skip
        self.plan_pub = self.create_publisher(Path, "spcotmhp/plan", LATCHED)
        self.status_pub = self.create_publisher(String, "spcotmhp/status", EVENTS)
        self.places_pub = self.create_publisher(MarkerArray, "spcotmhp/places", LATCHED)
        self.questions_pub = self.create_publisher(String, "spcotmhp/questions", LATCHED)
        self.create_subscription(PoseWithCovarianceStamped, start_topic, self.on_pose, MATCH_PUBLISHER)
        self.create_subscription(String, "spcotmhp/instruction", self.on_instruction, EVENTS)
        self.create_subscription(String, "spcotmhp/teach", self.on_teach, EVENTS)
        self.create_subscription(String, "spcotmhp/answer", self.on_answer, EVENTS)
        self.create_subscription(OccupancyGrid, "map", self.on_map, MATCH_PUBLISHER)
        self.hearing: Hearing | None = None  # spcotmhp/audio and spcotmhp/hypotheses (spcotmhp.ros.hearing)
        if hearing is not None:
            self.hearing = Hearing(self, hearing, lambda: tuple(self.planner.place_words), self.on_heard, self.status,
                                   EVENTS)  # fmt: skip
            self.hearing.warm_up()
        self.places_pub.publish(self.markers())
        self.publish_questions()

    # ---- output ----------------------------------------------------------------------------------------
    def publish_questions(self) -> None:
        from spcotmhp.teaching.questions import questions

        asked = {"questions": questions(self.planner.model)}
        self.questions_pub.publish(String(data=json.dumps(asked, ensure_ascii=False)))

    def status(self, data: dict) -> None:
        self.status_pub.publish(String(data=json.dumps(data, ensure_ascii=False)))

    def markers(self) -> MarkerArray:
        """Place ellipses (namespace places), names (names) and topological edges (edges) in ``frame``."""
        places, edges = place_shapes(self.planner)
        stamp = self.get_clock().now().to_msg()
        out = [Marker(action=Marker.DELETEALL)]
        for p in places:
            r, g, b = colorsys.hsv_to_rgb((p["id"] * 0.618034) % 1.0, 0.65, 0.95)
            shape = Marker(ns="places", id=p["id"], type=Marker.CYLINDER, action=Marker.ADD)
            shape.pose.position.x, shape.pose.position.y = p["centre"]
            _orient(shape.pose.orientation, p["yaw"])
            shape.scale.x, shape.scale.y, shape.scale.z = p["length"], p["width"], 0.02
            shape.color.r, shape.color.g, shape.color.b, shape.color.a = r, g, b, 0.35
            name = Marker(ns="names", id=p["id"], type=Marker.TEXT_VIEW_FACING, action=Marker.ADD, text=p["name"])
            name.pose.position.x, name.pose.position.y = p["centre"]
            name.pose.position.z = 0.5
            name.pose.orientation.w = 1.0
            name.scale.z = 0.35
            name.color.r = name.color.g = name.color.b = name.color.a = 1.0
            out += [shape, name]
        lines = Marker(ns="edges", id=0, type=Marker.LINE_LIST, action=Marker.ADD)
        lines.pose.orientation.w = 1.0
        lines.scale.x = 0.04
        lines.color.r = lines.color.g = lines.color.b = 0.6
        lines.color.a = 0.9
        centre = {p["id"]: p["centre"] for p in places}
        lines.points = [Point(x=centre[k][0], y=centre[k][1], z=0.01) for edge in edges for k in edge]
        if lines.points:
            out.append(lines)
        for m in out:
            m.header.frame_id, m.header.stamp = self.frame, stamp
        return MarkerArray(markers=out)

    def path_message(self, points: np.ndarray, fallback_yaw: float) -> Path:
        msg = Path()
        msg.header.frame_id = self.frame
        msg.header.stamp = self.get_clock().now().to_msg()
        for (x, y), yaw in zip(points, path_yaws(points, fallback_yaw), strict=False):
            pose = PoseStamped()
            pose.header.frame_id, pose.header.stamp = msg.header.frame_id, msg.header.stamp
            pose.pose.position.x, pose.pose.position.y = float(x), float(y)
            _orient(pose.pose.orientation, float(yaw))
            msg.poses.append(pose)
        return msg

    # ---- input -----------------------------------------------------------------------------------------
    @answered("error")
    def on_pose(self, msg: PoseWithCovarianceStamped) -> None:
        """Keep the pose, wait for its transform, or drop the one held and say why (spcotmhp.ros.poses)."""
        self.poses.take(msg)

    def current_pose(self, use: str) -> tuple[float, float, float]:
        """The pose to plan or teach from; NoValidPose when there is none (:meth:`PoseKeeper.current`)."""
        return self.poses.current(use)

    @answered("error")
    def on_instruction(self, msg: String) -> None:
        self.instruct(msg.data, msg.data)

    def on_heard(self, hypotheses: list[tuple[str, float]], source: str) -> None:
        """Serve what was heard on a speech topic (spcotmhp.ros.hearing): as an instruction, its best hypothesis
        naming it in the statuses."""
        self.instruct(hypotheses, hypotheses[0][0])

    def instruct(self, instruction: str | list[tuple[str, float]], text: str) -> None:
        """Plan ``instruction`` (a sentence, the structured JSON or an N-best list; ``text`` says it in the
        statuses) from the robot's pose, publish it, and drive it with ``drive``; "stop" stops the robot."""
        if self.driver is not None and self.driver.stopping(text):
            return
        x, y, yaw = self.current_pose("an instruction")
        planner = self.planner  # the one in place now (a teach may swap in another meanwhile)
        plan = planner.plan(instruction, (x, y))
        points = path_poses(plan.path, plan.cells, (x, y), planner.model.require_map())
        path = self.path_message(points, yaw)
        self.plan_pub.publish(path)
        self.status(plan_status(plan, text, (x, y), points, self.frame))
        if self.driver is not None:
            if self._centres[0] is not planner:  # the places' centres, once per planner (a teach swaps it)
                self._centres = (planner, {p["id"]: p["centre"] for p in place_shapes(planner)[0]})
            self.driver.drive(plan, points, text, self._centres[1], path.poses)

    @answered("taught")
    def on_teach(self, msg: String) -> None:
        """Queue the teach for the teaching thread (module docstring); TeachingBusy when too many wait."""
        self.queue_teach(msg, answer=False)

    @answered("taught")
    def on_answer(self, msg: String) -> None:
        """Queue an answer to one of the questions, a teach learned as :mod:`spcotmhp.teaching.answers` says."""
        self.queue_teach(msg, answer=True)

    def queue_teach(self, msg: String, answer: bool) -> None:
        """Queue a teach at the latest pose for the teaching thread; TeachingBusy when too many wait."""
        x, y, _ = self.current_pose("teaching (an utterance is learned at the robot's pose)")
        self.teacher.submit(self._apply_teach, TeachJob(msg.data, x, y, answer))

    @answered("taught")
    def _apply_teach(self, job: TeachJob) -> None:
        """Learn the teach and update the graph on this (the teaching) thread, then swap the planner in."""
        x, y = job.x, job.y
        taught = teach(self.planner.model, [{"x": x, "y": y, "utterance": job.data, "answer": job.answer}])
        planner, seconds = planner_for(taught.model, self.planner.settings, self.planner)
        event = self.log.append(x, y, job.data) if self.log is not None else None
        self.planner = planner  # one assignment: an instruction uses the old planner or the new one, whole
        self.places_pub.publish(self.markers())
        self.publish_questions()
        self.status(
            {
                "kind": "taught",
                "ok": True,
                "utterance": job.data,
                "answer": job.answer,
                "event": event,
                "x": round(x, 4),
                "y": round(y, 4),
                "dataset": None if self.log is None else str(self.log.folder),
                **taught.summary(),
                "time_planner_s": seconds,
            }
        )

    @answered("map")
    def on_map(self, msg: OccupancyGrid) -> None:
        info = msg.info
        q = info.origin.orientation
        differ = map_mismatches(
            info.width,
            info.height,
            info.resolution,
            (info.origin.position.x, info.origin.position.y, quaternion_yaw(q.x, q.y, q.z, q.w)),
            self.planner.model.require_map(),
        )
        if differ:
            self.get_logger().warning("the map on /map differs from the model's: " + "; ".join(differ))
        self.status({"kind": "map", "ok": not differ, "differences": differ})


def _orient(orientation, yaw: float) -> None:
    orientation.x, orientation.y, orientation.z, orientation.w = yaw_quaternion(yaw)


def run_node(
    model_dir: FilePath,
    frame: str = "map",
    start_topic: str = "amcl_pose",
    record: FilePath | None = None,
    progress: Callable[[str], None] = print,
    body: Any = None,
    drive: str | None = None,
    tf_timeout_s: float = TF_TIMEOUT_S,
    hearing: HearingSettings | None = None,
) -> None:
    """Load the model, precompute its planner (for ``body``, a :class:`~spcotmhp.metric.body.RobotBody`, when
    given: :func:`~spcotmhp.planning.body.with_body`), and serve until interrupted (Ctrl-C or SIGTERM); speech
    with ``hearing`` (default settings when None)."""
    from spcotmhp.persistence.io import load_model
    from spcotmhp.planning.body import with_body

    t0 = time.perf_counter()
    model = with_body(load_model(model_dir), body)
    log = TeachingLog(record, model.require_map(), model_dir) if record is not None else None
    planner = HierarchicalPlanner(model)
    planner.warm_up()
    with ros_running():
        node = SpcotmhpNode(planner, frame=frame, start_topic=start_topic, log=log, drive=drive,
                            tf_timeout_s=tf_timeout_s, hearing=hearing or HearingSettings())  # fmt: skip
        progress(
            f"spcotmhp node ready in {time.perf_counter() - t0:.1f} s: {len(place_shapes(planner)[0])} "
            f"places, plans in frame '{frame}' from {node.resolve_topic_name(start_topic)}"
            + (f", teaching recorded in {record}" if record is not None else "")
            + f"; planning graph {planner.graph.info.get('graph_source', 'built')}"
            + (f", driving Nav2 ({drive})" if drive is not None else "")
        )
        serve(node)


def serve(node: SpcotmhpNode) -> None:
    """Spin ``node`` until Ctrl-C or SIGTERM, then stop its threads, destroy it and shut rclpy down, within a
    bounded time (:mod:`spcotmhp.ros.spinning`)."""
    end_startup()
    try:
        spin_until_shutdown(node)
    finally:
        with bounded_shutdown(f"node {node.get_name()!r}"):
            node.teacher.shutdown()
            if node.hearing is not None:
                node.hearing.shutdown()
            node.destroy_node()
            quiet_shutdown()
