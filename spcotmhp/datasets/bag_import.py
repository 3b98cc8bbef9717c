"""Import a robot's log (a ROS 1 ``.bag`` or a ROS 2 bag) as a dataset folder.

The log gives the robot's pose on one topic (geometry_msgs/PoseWithCovarianceStamped as AMCL publishes,
geometry_msgs/PoseStamped, or nav_msgs/Odometry) and the user's teaching utterances on another
(std_msgs/String, as a speech recogniser publishes them). The dataset folder it writes (layout in
``spcotmhp/data/README.md``) holds:

* ``trajectory.csv`` ``step,x,y``: the path walked, **resampled by arc length every ``step`` metres**
  (0.1 m by default, the spacing the layout asks for), so the time the robot stood still while being taught
  leaves no pile of identical poses; the last pose is always kept. ``step=0`` keeps every pose message instead.
* ``teaching.csv`` ``event,x,y,words_<lang>,step``: one row per utterance, at the pose linearly interpolated at
  the utterance's time (held at the last pose after it: AMCL publishes only when the robot moves), and the
  trajectory step nearest to that point along the path (so steps never decrease).
* ``map.yaml`` + image: the ``map_yaml`` given (loaded and saved again with :mod:`spcotmhp.metric.map_io`), else
  the last nav_msgs/OccupancyGrid on ``map_topic`` in the bag.

Times are the bag's record times of the messages, for poses and utterances alike: std_msgs/String has no
header, so the record time is the one clock both topics share.
"""

from __future__ import annotations

import csv
import math
import warnings
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from types import TracebackType
from typing import Any

import numpy as np

from spcotmhp.datasets.synthetic import check_dataset_target
from spcotmhp.errors import DatasetError, MapError
from spcotmhp.extras import missing_extra
from spcotmhp.metric.map_io import load_map, save_map
from spcotmhp.metric.maps import OccupancyMap
from spcotmhp.safe_write import build_folder

POSE_TYPES: dict[str, Callable[[Any], Any]] = {
    "geometry_msgs/msg/PoseWithCovarianceStamped": lambda m: m.pose.pose.position,
    "geometry_msgs/msg/PoseStamped": lambda m: m.pose.position,
    "nav_msgs/msg/Odometry": lambda m: m.pose.pose.position,
}
"""Supported pose message types (rosbags' names; ROS 1's ``geometry_msgs/PoseStamped`` reads the same)."""
UTTERANCE_TYPE = "std_msgs/msg/String"
MAP_TYPE = "nav_msgs/msg/OccupancyGrid"
MAP_FRAME = "map"


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


@dataclass
class ImportSummary:
    """What :func:`import_bag` wrote."""

    folder: Path
    n_pose_messages: int
    n_trajectory: int
    n_events: int
    path_length_m: float
    duration_s: float
    map_source: str


# ---- reading ---------------------------------------------------------------------------------------------
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
        _warn(f"{pose_topic}: skipped {bad_poses} pose message(s) with a non-finite x or y")
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


def _warn(message: str) -> None:
    warnings.warn(BagImportWarning(message), stacklevel=2)


# ---- the dataset -----------------------------------------------------------------------------------------
def resample_by_arc_length(poses: np.ndarray, step: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Points every ``step`` metres along the polyline ``poses`` (and its last point).

    Returns:
        (trajectory (T, 2), arc length of each trajectory point (T,), arc length of each input pose (N,)).
    """
    poses = np.asarray(poses, dtype=float)
    seg = np.hypot(*np.diff(poses, axis=0).T)
    along = np.concatenate([[0.0], np.cumsum(seg)])
    total = along[-1]
    marks = np.arange(0.0, total, step) if total > 0 else np.zeros(1)
    if total - marks[-1] > 1e-9:
        marks = np.append(marks, total)
    # interpolate x, y at the marks; np.interp needs increasing abscissae, so drop zero-length segments
    keep = np.concatenate([[True], seg > 0])
    xs = np.interp(marks, along[keep], poses[keep, 0])
    ys = np.interp(marks, along[keep], poses[keep, 1])
    return np.stack([xs, ys], axis=1), marks, along


def teaching_events(log: BagLog, step: float) -> tuple[np.ndarray, np.ndarray, np.ndarray, list[str]]:
    """Trajectory, event positions, event steps and utterance texts from a bag's poses and utterances.

    Each utterance is placed at the pose interpolated linearly in time at its record time (held at the last pose
    after the last message) and gets the trajectory step nearest to it along the path. Empty utterances are
    dropped with a warning.

    Raises:
        DatasetError: no utterances, or an utterance recorded before the first pose.
    """
    if step < 0 or not math.isfinite(step):
        raise DatasetError(f"step must be a finite number of metres >= 0, got {step}")
    keep = [i for i, text in enumerate(log.utterances) if text]
    if len(keep) < len(log.utterances):
        _warn(f"skipped {len(log.utterances) - len(keep)} empty utterance(s)")
    if not keep:
        raise DatasetError("the bag has no utterances with words, so no teaching events")
    u_times = log.utterance_times[keep]
    texts = [log.utterances[i] for i in keep]
    t0 = int(log.pose_times[0])
    early = np.flatnonzero(u_times < t0)
    if len(early):
        i = int(early[0])
        raise DatasetError(
            f"utterance {texts[i]!r} was recorded {(t0 - int(u_times[i])) / 1e9:.3f} s before the first pose "
            f"(utterance at {_stamp(u_times[i])}, first pose at {_stamp(t0)}; {len(early)} utterance(s) have no "
            "pose before them): start recording the pose topic before teaching"
        )
    rel_pose = (log.pose_times - t0).astype(float)
    rel_utt = (u_times - t0).astype(float)
    positions = np.stack([np.interp(rel_utt, rel_pose, log.poses[:, j]) for j in (0, 1)], axis=1)
    if step == 0:
        trajectory = log.poses.copy()
        steps = _nearest(rel_pose, rel_utt)
    else:
        trajectory, marks, along = resample_by_arc_length(log.poses, step)
        steps = _nearest(marks, np.interp(rel_utt, rel_pose, along))
    return trajectory, positions, steps, texts


def _nearest(grid: np.ndarray, values: np.ndarray) -> np.ndarray:
    """Index of the nearest element of the sorted ``grid`` for each value (ties to the earlier one)."""
    if len(grid) == 1:
        return np.zeros(len(values), dtype=np.int64)
    right = np.clip(np.searchsorted(grid, values), 1, len(grid) - 1)
    left = right - 1
    take_right = (grid[right] - values) < (values - grid[left])
    return np.where(take_right, right, left).astype(np.int64)


def _stamp(ns: int | np.integer) -> str:
    return f"{int(ns) / 1e9:.3f} s"


# ---- writing ---------------------------------------------------------------------------------------------
def import_bag(
    bag: str | Path,
    out: str | Path,
    pose_topic: str = "/amcl_pose",
    utterance_topic: str = "/speech",
    map_yaml: str | Path | None = None,
    map_topic: str | None = "/map",
    step: float = 0.1,
    lang: str = "en",
    overwrite: bool = False,
    progress: bool = False,
) -> ImportSummary:
    """Write the dataset folder ``out`` from a bag (module docstring); load it with
    :func:`spcotmhp.datasets.load_dataset` (``lang`` picks the words column: ``words_en`` or ``words_ja``).

    Raises:
        DatasetError: bad bag (see :func:`read_bag`), no map, no utterances or one before the first pose,
            ``out`` holding a dataset already (unless ``overwrite``: the folder is then replaced whole) or files
            that are not a dataset's. MapError: a bad ``map_yaml``.
    """
    if lang not in ("en", "ja"):
        raise DatasetError(f"lang must be 'en' or 'ja', got {lang!r}")
    folder = Path(out)
    check_dataset_target(folder, overwrite)  # before reading the bag
    occupancy = load_map(map_yaml) if map_yaml is not None else None  # fail on a bad map before reading the bag
    log = read_bag(bag, pose_topic, utterance_topic, None if occupancy is not None else map_topic, progress)
    if occupancy is None:
        if log.map is None:
            where = f"no {map_topic} topic" if map_topic else "no map topic given"
            raise DatasetError(f"no map: the bag has {where}; pass --map MAP_YAML (a map_server YAML)")
        occupancy = log.map
    other = sorted(f for f in log.pose_frames if f != (log.map_frame or MAP_FRAME))
    if other:
        _warn(
            f"poses on {pose_topic} are in frame(s) {', '.join(other)}, not the map frame "
            f"{log.map_frame or MAP_FRAME}; the dataset takes them as map coordinates (use a localised pose "
            "topic such as /amcl_pose)"
        )
    trajectory, positions, steps, texts = teaching_events(log, step)

    def fill(staging: Path) -> None:
        try:
            save_map(occupancy, staging / "map.yaml", mode=occupancy.mode)
        except MapError as exc:
            raise DatasetError(f"cannot write the map to {folder}: {exc}") from None
        _write_csv(
            staging / "trajectory.csv",
            ["step", "x", "y"],
            [[t, metres(x), metres(y)] for t, (x, y) in enumerate(trajectory)],
        )
        _write_csv(
            staging / "teaching.csv",
            ["event", "x", "y", f"words_{lang}", "step"],
            [
                [e, metres(x), metres(y), text, int(s)]
                for e, ((x, y), text, s) in enumerate(zip(positions, texts, steps, strict=False))
            ],
        )

    # built beside ``folder`` and swapped in whole: readers see the old dataset or the new one, and no file of
    # the old one (a stale truth.csv) survives next to the new teaching events
    build_folder(folder, fill, DatasetError, f"write the dataset to {folder}")
    return ImportSummary(
        folder=folder,
        n_pose_messages=len(log.poses),
        n_trajectory=len(trajectory),
        n_events=len(texts),
        path_length_m=float(np.hypot(*np.diff(log.poses, axis=0).T).sum()),
        duration_s=float(log.pose_times[-1] - log.pose_times[0]) / 1e9,
        map_source=str(map_yaml) if map_yaml is not None else f"{map_topic} in the bag",
    )


def metres(value: float) -> str:
    """A coordinate in metres for the CSV files, to 0.1 mm (finer than any map cell or pose estimate; the
    interpolation's float noise, 8.1999999995, reads 8.2): the shortest text of the rounded value."""
    return repr(round(float(value), 4) + 0.0)


def _write_csv(path: Path, header: list[str], rows: list[list]) -> None:
    try:
        with path.open("w", newline="", encoding="utf-8") as fh:
            writer = csv.writer(fh, lineterminator="\n")
            writer.writerow(header)
            writer.writerows(rows)
    except OSError as exc:
        raise DatasetError(f"cannot write {path}: {exc.strerror or exc}") from None
