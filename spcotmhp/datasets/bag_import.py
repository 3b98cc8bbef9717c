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
header, so the record time is the one clock both topics share. The bag is read by
:mod:`spcotmhp.datasets.bag_reader` (:func:`read_bag`, :class:`BagLog` and :class:`BagImportWarning` are
importable from here as well).
"""

from __future__ import annotations

import csv
import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from spcotmhp.datasets.bag_reader import POSE_TYPES, BagImportWarning, BagLog, read_bag, warn
from spcotmhp.datasets.synthetic import check_dataset_target
from spcotmhp.errors import DatasetError, MapError
from spcotmhp.metric.map_io import load_map, save_map
from spcotmhp.safe_write import build_folder

MAP_FRAME = "map"
__all__ = [  # read_bag, BagLog, BagImportWarning and POSE_TYPES live in bag_reader and are importable from here
    "MAP_FRAME",
    "POSE_TYPES",
    "BagImportWarning",
    "BagLog",
    "ImportSummary",
    "import_bag",
    "metres",
    "read_bag",
    "resample_by_arc_length",
    "teaching_events",
]


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
        warn(f"skipped {len(log.utterances) - len(keep)} empty utterance(s)")
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
        warn(
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
