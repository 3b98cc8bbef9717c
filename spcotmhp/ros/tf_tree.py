"""The transform tree of /tf and /tf_static, and poses looked up through it to the map frame (issue 36, item 3).

tf2, tf2_ros and tf2_py have no wheels, so the node keeps the tree itself from the ``tf2_msgs/TFMessage``s it hears
(the message type is built here: ros2/tf2_msgs/README.md). Each child frame has one parent, as in tf2; an edge
keeps its latest transform (the latest, not interpolated in time: what tf2's lookup at time 0 gives, and what a
pose to plan from needs). Rotations are scipy's (``scipy.spatial.transform.Rotation``), a dependency already.
A frame with no chain to the target raises :class:`~spcotmhp.errors.TransformUnavailable`, naming the frames
known; the tree holds at most MAX_FRAMES frames and refuses edges that would close a loop.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np
from scipy.spatial.transform import Rotation

from spcotmhp.errors import TransformUnavailable

MAX_FRAMES = 1000  # a robot's tree has tens of frames; past this a publisher is broken, and memory stays bounded
MAX_NAME = 256  # characters of a frame name (tf2 has no limit; a longer one is not a frame name)


@dataclass(frozen=True)
class Transform:
    """A rigid transform: a point p in the child frame is ``rotation.apply(p) + translation`` in the parent."""

    translation: np.ndarray
    rotation: Rotation

    def __mul__(self, other: Transform) -> Transform:
        return Transform(self.rotation.apply(other.translation) + self.translation, self.rotation * other.rotation)

    def inverse(self) -> Transform:
        inv = self.rotation.inv()
        return Transform(-inv.apply(self.translation), inv)


IDENTITY = Transform(np.zeros(3), Rotation.identity())


@dataclass
class TransformTree:
    """Frames and the latest transform from each to its parent (module docstring)."""

    parent: dict[str, tuple[str, Transform]] = field(default_factory=dict)  # child -> (parent, T_parent_child)

    def add(self, parent: str, child: str, xyz: tuple[float, float, float], xyzw: tuple[float, ...]) -> None:
        """Record ``child``'s transform in ``parent`` (translation, quaternion x y z w). TransformUnavailable for
        a frame name that is empty or too long, a transform not finite, a loop, or a tree past MAX_FRAMES."""
        parent, child = parent.lstrip("/"), child.lstrip("/")  # tf2 drops a leading slash too
        for name in (parent, child):
            if not name or len(name) > MAX_NAME:
                raise TransformUnavailable(f"a frame name must have 1 to {MAX_NAME} characters, not {len(name)}")
        values = np.array([*xyz, *xyzw], dtype=float)
        if not np.isfinite(values).all() or np.linalg.norm(values[3:]) < 1e-9:
            raise TransformUnavailable(f"the transform {parent} -> {child} is not finite or has a zero quaternion")
        if parent == child or child in self._chain(parent)[0]:
            raise TransformUnavailable(f"the transform {parent} -> {child} would close a loop in the tf tree")
        if child not in self.parent and len(self.frames()) >= MAX_FRAMES:
            raise TransformUnavailable(f"the tf tree holds {MAX_FRAMES} frames already; {child!r} is refused")
        self.parent[child] = (parent, Transform(values[:3], Rotation.from_quat(values[3:])))

    def frames(self) -> set[str]:
        return set(self.parent) | {p for p, _ in self.parent.values()}

    def _chain(self, frame: str) -> tuple[list[str], list[Transform]]:
        """The frames from ``frame`` up to its root, and each one's transform to the root (T_root_frame)."""
        names, ups = [frame], [IDENTITY]
        while names[-1] in self.parent:
            up, t = self.parent[names[-1]]
            names.append(up)
            ups.append(t)
        to_root = [IDENTITY] * len(names)
        for i in range(len(names) - 2, -1, -1):
            to_root[i] = to_root[i + 1] * ups[i + 1]
        return names, to_root

    def lookup(self, target: str, source: str) -> Transform:
        """T_target_source: a point in ``source`` mapped into ``target``. TransformUnavailable when no chain."""
        target, source = target.lstrip("/"), source.lstrip("/")
        if target == source:
            return IDENTITY
        known = self.frames()
        for name in (source, target):
            if name not in known:
                heard = ", ".join(sorted(known)[:20]) or "none"
                raise TransformUnavailable(
                    f"no transform from frame {source!r} to {target!r}: {name!r} was not heard on /tf or "
                    f"/tf_static (frames known: {heard})"
                )
        s_names, s_root = self._chain(source)
        t_names, t_root = self._chain(target)
        if s_names[-1] != t_names[-1]:
            raise TransformUnavailable(
                f"frames {source!r} and {target!r} are in two unconnected tf trees (roots {s_names[-1]!r} and "
                f"{t_names[-1]!r})"
            )
        return t_root[0].inverse() * s_root[0]

    def pose_in(self, target: str, source: str, x: float, y: float, yaw: float) -> tuple[float, float, float]:
        """A planar pose in ``source`` as (x, y, yaw) in ``target`` (z dropped; yaw about the target's z axis)."""
        t = self.lookup(target, source)
        p = t.rotation.apply([x, y, 0.0]) + t.translation
        heading = (t.rotation * Rotation.from_euler("z", yaw)).apply([1.0, 0.0, 0.0])
        return float(p[0]), float(p[1]), float(np.arctan2(heading[1], heading[0]))


def feed(tree: TransformTree, message: object) -> list[str]:
    """Record every transform of a ``tf2_msgs/TFMessage`` (from /tf or /tf_static) in ``tree``; the one-line
    error of each transform refused (the others are kept: one broken publisher does not hide the rest)."""
    refused = []
    for ts in message.transforms:  # type: ignore[attr-defined]
        t, q = ts.transform.translation, ts.transform.rotation
        try:
            tree.add(ts.header.frame_id, ts.child_frame_id, (t.x, t.y, t.z), (q.x, q.y, q.z, q.w))
        except TransformUnavailable as e:
            refused.append(str(e))
    return refused


def listen(node: object, tree: TransformTree, heard: Callable[[], None] | None = None) -> bool:
    """Subscribe ``node`` (an rclpy Node) to /tf and /tf_static (latched, as tf2's static broadcaster publishes),
    feeding ``tree`` and then calling ``heard`` (a pose waiting for its transform retries); a refused transform is
    logged. False (nothing subscribed) when tf2_msgs is not built."""
    from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy

    from spcotmhp.ros.tf_types import Tf2MsgsMissing, import_tf_message

    try:
        tf_message = import_tf_message()
    except Tf2MsgsMissing as e:
        node.get_logger().warning(f"no tf: {e}")  # type: ignore[attr-defined]
        return False

    def on_message(message: object) -> None:
        for line in feed(tree, message):
            node.get_logger().warning(f"tf: {line}")  # type: ignore[attr-defined]
        if heard is not None:
            heard()

    static = QoSProfile(depth=100, reliability=ReliabilityPolicy.RELIABLE, durability=DurabilityPolicy.TRANSIENT_LOCAL)
    node.create_subscription(tf_message, "/tf", on_message, 100)  # type: ignore[attr-defined]
    node.create_subscription(tf_message, "/tf_static", on_message, static)  # type: ignore[attr-defined]
    return True
