"""Reading a robot's log (a ROS 1 ``.bag`` or a ROS 2 bag, with the ``rosbags`` package) for
:func:`spcotmhp.datasets.bag_import.import_bag`: the poses on one topic, the teaching utterances on another and
the last occupancy grid on a map topic, with the bag's record times (:class:`BagLog`). A bag that is missing,
unreadable, empty or lacks a topic raises one :class:`~spcotmhp.errors.DatasetError` naming the topics present.
"""

from __future__ import annotations

import math
import warnings
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from types import TracebackType
from typing import Any

import numpy as np

from spcotmhp.errors import DatasetError
from spcotmhp.extras import missing_extra
from spcotmhp.metric.maps import OccupancyMap

POSE_TYPES: dict[str, Callable[[Any], Any]] = {
    "geometry_msgs/msg/PoseWithCovarianceStamped": lambda m: m.pose.pose.position,
    "geometry_msgs/msg/PoseStamped": lambda m: m.pose.position,
    "nav_msgs/msg/Odometry": lambda m: m.pose.pose.position,
}
"""Supported pose message types (rosbags' names; ROS 1's ``geometry_msgs/PoseStamped`` reads the same)."""
UTTERANCE_TYPE = "std_msgs/msg/String"
MAP_TYPE = "nav_msgs/msg/OccupancyGrid"


class BagImportWarning(UserWarning):
    """A recoverable problem in a bag (poses in another frame, empty utterances, non-finite poses)."""


@dataclass
class BagLog:
    """What a bag holds for teaching: poses and utterances with record times in nanoseconds.

    Attributes:
        pose_times: (N,) int64 record times of the pose messages, non-decreasing.
        poses: (N, 2) x, y in metres.
        utterance_times: (E,) int64 record times of the utterances, non-decreasing.
        utterances: E texts as published (whitespace collapsed).
        pose_frames: the frame ids the pose messages named.
        map: the last OccupancyGrid on the map topic, if there was one.
        map_frame: that grid's frame id.
        topics: every topic of the bag with its message type (for messages).
    """

    pose_times: np.ndarray
    poses: np.ndarray
    utterance_times: np.ndarray
    utterances: list[str]
    pose_frames: set[str] = field(default_factory=set)
    map: OccupancyMap | None = None
    map_frame: str | None = None
    topics: dict[str, str] = field(default_factory=dict)


def read_bag(
    bag: str | Path,
    pose_topic: str,
    utterance_topic: str,
    map_topic: str | None = None,
    progress: bool = False,
) -> BagLog:
    """Read poses, utterances and (optionally) the last map of a ROS 1 or ROS 2 bag.

    Args:
        bag: a ROS 1 ``.bag`` file, or a ROS 2 bag folder (metadata.yaml + .db3 / .mcap), or its
            metadata.yaml, or a single .db3 / .mcap file.
        pose_topic, utterance_topic: topic names; the pose topic must carry one of :data:`POSE_TYPES`, the
            utterance topic std_msgs/String.
        map_topic: a nav_msgs/OccupancyGrid topic to read the map from (ignored when absent from the bag).
        progress: show a progress bar on stderr.

    Raises:
        DatasetError: the bag is missing, unreadable or empty; a topic is absent (the message lists the topics
            present with their types), has an unsupported type or no messages; a map is not axis-aligned.
    """
    try:
        from rosbags.highlevel import AnyReader
    except ImportError:  # pragma: no cover - the extra is installed in the test environment
        raise DatasetError(missing_extra("importing bags (rosbags)", "ros")) from None
    path = _bag_path(Path(bag))
    try:
        with AnyReader([path]) as reader:
            return _read(reader, path, pose_topic, utterance_topic, map_topic, progress)
    except DatasetError:
        raise
    except Exception as exc:  # noqa: BLE001 - rosbags raises many types for a corrupt file; none may reach the user
        raise DatasetError(f"cannot read bag {bag}: {_reason(exc)}") from None


def _bag_path(path: Path) -> Path:
    if not path.exists():
        raise DatasetError(f"bag {path} does not exist (give a ROS 1 .bag file or a ROS 2 bag folder)")
    if path.is_dir():
        if not (path / "metadata.yaml").is_file():
            raise DatasetError(
                f"{path} is a folder without metadata.yaml, so not a ROS 2 bag (a ROS 2 bag is a "
                "folder with metadata.yaml and .db3 or .mcap files; a ROS 1 bag is a .bag file)"
            )
        return path
    if path.name == "metadata.yaml":
        return path.parent
    if path.suffix.lower() not in (".bag", ".db3", ".mcap"):
        raise DatasetError(
            f"{path} is not a bag: expected a ROS 1 .bag file, a ROS 2 bag folder, or a .db3 / .mcap file"
        )
    return path


def _reason(exc: Exception) -> str:
    text = str(exc).strip() or type(exc).__name__
    if isinstance(exc, UnicodeDecodeError):
        text = "not a bag file (its header is not a rosbag header)"
    return text


def _read(
    reader: Any, path: Path, pose_topic: str, utterance_topic: str, map_topic: str | None, progress: bool
) -> BagLog:
    topics: dict[str, str] = {}
    for c in reader.connections:
        topics.setdefault(c.topic, c.msgtype)
    if not topics or reader.message_count == 0:
        raise DatasetError(f"bag {path} is empty (no messages)")
    pose_conns = _connections(reader, path, topics, pose_topic, set(POSE_TYPES), "pose")
    utter_conns = _connections(reader, path, topics, utterance_topic, {UTTERANCE_TYPE}, "utterance")
    map_conns = []
    if map_topic and map_topic in topics:
        map_conns = _connections(reader, path, topics, map_topic, {MAP_TYPE}, "map")

    times, xy, frames, u_times, texts, bad_poses = [], [], set(), [], [], 0
    last_map = None
    wanted = pose_conns + utter_conns + map_conns
    total = sum(c.msgcount for c in wanted)
    with _Progress(progress, total, f"reading {path.name}") as advance:
        for conn, t, raw in reader.messages(connections=wanted):
            advance()
            if conn.topic == pose_topic:
                msg = reader.deserialize(raw, conn.msgtype)
                p = POSE_TYPES[conn.msgtype](msg)
                if not (math.isfinite(p.x) and math.isfinite(p.y)):
                    bad_poses += 1
                    continue
                times.append(t)
                xy.append((p.x, p.y))
                frames.add(msg.header.frame_id.lstrip("/"))
            elif conn.topic == utterance_topic:
                u_times.append(t)
                texts.append(" ".join(reader.deserialize(raw, conn.msgtype).data.split()))
            else:
                last_map = raw, conn.msgtype
    if bad_poses:
        warn(f"{pose_topic}: skipped {bad_poses} pose message(s) with a non-finite x or y")
    if not times:
        raise DatasetError(f"topic {pose_topic} has no messages with a finite pose in bag {path}")
    grid, grid_frame = (None, None) if last_map is None else _grid(reader.deserialize(*last_map), map_topic)
    return BagLog(
        pose_times=np.asarray(times, dtype=np.int64),
        poses=np.asarray(xy, dtype=float),
        utterance_times=np.asarray(u_times, dtype=np.int64),
        utterances=texts,
        pose_frames=frames,
        map=grid,
        map_frame=grid_frame,
        topics=topics,
    )


def _connections(reader: Any, path: Path, topics: dict[str, str], topic: str, accepted: set[str], what: str) -> list:
    if topic not in topics:
        present = "; ".join(f"{t} ({ty})" for t, ty in sorted(topics.items()))
        raise DatasetError(f"bag {path} has no {what} topic {topic}; topics present: {present}")
    conns = [c for c in reader.connections if c.topic == topic]
    for c in conns:
        if c.msgtype not in accepted:
            raise DatasetError(
                f"topic {topic} carries {c.msgtype}, which is not a supported {what} type; "
                f"supported: {', '.join(sorted(accepted))}"
            )
    if sum(c.msgcount for c in conns) == 0:
        raise DatasetError(f"topic {topic} has no messages in bag {path}")
    return conns


def _grid(msg: Any, topic: str | None) -> tuple[OccupancyMap, str]:
    """A nav_msgs/OccupancyGrid message -> OccupancyMap (its data is already in OccupancyGrid row order)."""
    info = msg.info
    q = info.origin.orientation
    yaw = math.atan2(2.0 * (q.w * q.z + q.x * q.y), 1.0 - 2.0 * (q.y * q.y + q.z * q.z))
    if abs(yaw) > 1e-9:
        raise DatasetError(
            f"the map on {topic} is rotated (origin yaw {yaw:.4f} rad); only axis-aligned maps "
            "are supported: pass --map with a map_server YAML instead"
        )
    data = np.asarray(msg.data, dtype=np.int8)
    if data.size != info.width * info.height or data.size == 0:
        raise DatasetError(f"the map on {topic} has {data.size} cells but its info says {info.width} x {info.height}")
    grid = data.reshape(info.height, info.width)
    trinary = bool(np.isin(grid, (-1, 0, 100)).all())
    # resolution is a float32 in the message: keep its shortest decimal form (0.05, not 0.0500000007)
    occupancy = OccupancyMap(
        data=grid,
        resolution=float(str(np.float32(info.resolution))),
        origin=(float(info.origin.position.x), float(info.origin.position.y), 0.0),
        mode="trinary" if trinary else "raw",
    )
    return occupancy, msg.header.frame_id.lstrip("/")


class _Progress:
    """A rich progress bar on stderr when ``enabled`` (``advance()`` per message), else a no-op."""

    def __init__(self, enabled: bool, total: int, label: str) -> None:
        self.enabled, self.total, self.label = enabled, total, label

    def __enter__(self) -> Callable[[], None]:
        if not self.enabled:
            return lambda: None
        from rich.console import Console
        from rich.progress import Progress

        self.bar = Progress(console=Console(stderr=True), transient=True)
        self.bar.__enter__()
        task = self.bar.add_task(self.label, total=self.total)
        return lambda: self.bar.advance(task)

    def __exit__(
        self, kind: type[BaseException] | None, exc: BaseException | None, trace: TracebackType | None
    ) -> None:
        if self.enabled:
            self.bar.__exit__(kind, exc, trace)


def warn(message: str) -> None:
    """Emit a :class:`BagImportWarning` (a recoverable problem of the bag)."""
    warnings.warn(BagImportWarning(message), stacklevel=2)
