"""The robot's pose for the node: the latest pose on the start topic, put in the plans' frame, checked, or why not.

A pose in another frame is looked up through ``/tf`` and ``/tf_static`` (:mod:`spcotmhp.ros.tf_tree`). When its
transform is not there yet (a tf publisher started after AMCL, or the first ``/tf`` still on its way), the pose
**waits for it up to** ``tf_timeout_s`` (a node option, default TF_TIMEOUT_S): every transform heard meanwhile
retries it, and a one-shot timer at the deadline tries a last time, then rejects the pose with a
``TransformUnavailable`` error status saying how long it waited. No polling: the retries are the /tf messages.
While it waits, no pose is held (an earlier one is never used in its place): instructions and teaching are refused
(``NoValidPose``, saying the pose waits for its transform). A pose not finite or off the model's map is rejected
at once (``PoseRejected``).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any

from spcotmhp.errors import InvalidSettings, NoValidPose, PoseRejected, StartOutsideMap, TransformUnavailable
from spcotmhp.planning.start import locate_start
from spcotmhp.ros.shapes import error_status, quaternion_yaw
from spcotmhp.ros.tf_tree import TransformTree, listen

TF_TIMEOUT_S = 1.0  # tf2's usual lookup timeout in Nav2's nodes (transform_tolerance and the like): ~1 s, not more


class PoseKeeper:
    """The latest valid pose (x, y, yaw) in ``frame`` of an rclpy ``node`` (module docstring); ``model_map``
    gives the map poses must lie on, ``report`` publishes a status dict (a rejection found by a timer)."""

    def __init__(
        self,
        node: Any,
        frame: str,
        model_map: Callable[[], Any],
        report: Callable[[dict], None],
        tf_timeout_s: float = TF_TIMEOUT_S,
    ) -> None:
        if not (math.isfinite(tf_timeout_s) and 0.0 <= tf_timeout_s <= 60.0):
            raise InvalidSettings(f"the tf timeout must be 0 to 60 s, not {tf_timeout_s}")
        self.node, self.frame, self.model_map, self.report = node, frame, model_map, report
        self.tf_timeout_s = tf_timeout_s
        self.pose: tuple[float, float, float] | None = None  # the latest pose, None once one is rejected
        self.rejected: str | None = None  # why the latest pose was rejected
        self.waiting: Any = None  # a pose message waiting for its transform
        self._why_waiting = ""  # the lookup's error while it waits
        self.tf: TransformTree | None = TransformTree()
        if not listen(node, self.tf, heard=self.retry):
            self.tf = None
        self.deadline = node.create_timer(max(tf_timeout_s, 1e-3), self.give_up)
        self.deadline.cancel()

    def take(self, msg: Any) -> None:
        """A pose message heard: keep it, wait for its transform, or drop the pose held and raise PoseRejected."""
        self.pose, self.rejected, self.waiting = None, None, None
        self.deadline.cancel()
        try:
            self.pose = self.checked(msg)
        except TransformUnavailable as exc:
            if self.tf is None or self.tf_timeout_s <= 0:
                self.rejected = str(exc)
                raise
            self.waiting, self.rejected = msg, None
            self._why_waiting = str(exc)
            self.deadline.reset()
        except PoseRejected as exc:
            self.rejected = str(exc)
            raise

    def forget(self, why: str) -> None:
        """Drop the pose held (and any waiting): instructions are refused, naming ``why``, until a new one."""
        self.pose, self.waiting, self.rejected = None, None, why
        self.deadline.cancel()

    def retry(self) -> None:
        """A transform was heard: the waiting pose, if any, is tried again (kept once its chain is there)."""
        if self.waiting is None:
            return
        try:
            self.pose = self.checked(self.waiting)
        except TransformUnavailable as exc:
            self._why_waiting = str(exc)
            return
        except PoseRejected as exc:  # its transform came, and puts it off the map (or not finite)
            self._reject(exc)
            return
        self.waiting = None
        self.deadline.cancel()

    def give_up(self) -> None:
        """The deadline: a last try, then the waiting pose is rejected with TransformUnavailable (a status)."""
        self.deadline.cancel()
        if self.waiting is None:
            return
        self.retry()
        if self.waiting is not None:
            self._reject(TransformUnavailable(f"{self._why_waiting} (waited {self.tf_timeout_s:g} s for it)"))

    def _reject(self, exc: PoseRejected) -> None:
        self.waiting, self.pose, self.rejected = None, None, str(exc)
        self.deadline.cancel()
        self.report(error_status(exc))

    def checked(self, msg: Any) -> tuple[float, float, float]:
        """(x, y, yaw) of a pose message in ``frame``, finite and on the model's map; else PoseRejected."""
        frame = msg.header.frame_id.lstrip("/")
        p, q = msg.pose.pose.position, msg.pose.pose.orientation
        x, y, yaw = p.x, p.y, quaternion_yaw(q.x, q.y, q.z, q.w)
        if frame and frame != self.frame:
            if self.tf is None:
                raise PoseRejected(
                    f"the pose is in frame '{frame}', plans are in '{self.frame}' (no tf here: tf2_msgs is not "
                    f"built; publish the pose in '{self.frame}' or start the node with --frame {frame})"
                )
            x, y, yaw = self.tf.pose_in(self.frame, frame, x, y, yaw)  # TransformUnavailable: no chain heard
        if not all(math.isfinite(v) for v in (x, y, yaw)):
            raise PoseRejected(f"the pose ({x}, {y}, yaw {yaw}) is not finite")
        try:
            locate_start(self.model_map(), (x, y))
        except StartOutsideMap as exc:
            raise PoseRejected(f"the pose is off the model's map: {exc}") from None
        return float(x), float(y), float(yaw)

    def current(self, use: str) -> tuple[float, float, float]:
        """The pose to plan or teach from; NoValidPose when none has arrived, it waits for its transform, or the
        latest was rejected."""
        if self.pose is not None:
            return self.pose
        if self.waiting is not None:
            raise NoValidPose(
                f"the latest robot pose waits up to {self.tf_timeout_s:g} s for its transform to "
                f"'{self.frame}' ({self._why_waiting}); {use} is refused meanwhile (an earlier pose is not used)"
            )
        if self.rejected is not None:
            raise NoValidPose(
                f"the latest robot pose was rejected ({self.rejected}); {use} waits for a valid pose on the "
                "start topic (an earlier pose is not used)"
            )
        raise NoValidPose(
            "no robot pose yet: publish one on the start topic (AMCL's /amcl_pose, PoseWithCovarianceStamped) "
            f"before {use}"
        )
