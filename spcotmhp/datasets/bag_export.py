"""Write a dataset's teaching walk as a ROS 1 bag (the inverse of :mod:`spcotmhp.datasets.bag_import`): the
trajectory as geometry_msgs/PoseWithCovarianceStamped on a pose topic, each teaching utterance as
std_msgs/String on an utterance topic at the time the robot stood at its pose. Used to make the small example
bag of ``spcotmhp examples``; needs the ``ros`` extra (rosbags)."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from spcotmhp.datasets.dataset import Dataset
from spcotmhp.errors import DatasetError
from spcotmhp.extras import missing_extra

NS = 1_000_000_000


def write_teaching_bag(
    dataset: Dataset,
    path: str | Path,
    pose_topic: str = "/amcl_pose",
    utterance_topic: str = "/speech",
    speed: float = 0.5,
    every: int = 1,
    frame: str = "map",
) -> Path:
    """Write ``dataset``'s trajectory (every ``every``-th pose, walked at ``speed`` m/s along the poses) and its
    utterances (the tokens joined by spaces, at the time of their ``event_steps`` pose) as a ROS 1 bag.

    Raises:
        DatasetError: the dataset has no trajectory or event steps, or rosbags is not installed.
    """
    try:
        from rosbags.rosbag1 import Writer
        from rosbags.typesys import Stores, get_typestore
    except ImportError:
        raise DatasetError(missing_extra("writing bags (rosbags)", "ros")) from None
    if dataset.trajectory is None or dataset.event_steps is None:
        raise DatasetError(f"{dataset.name} has no trajectory.csv: a bag needs the walk the robot made")
    traj = np.asarray(dataset.trajectory, dtype=float)
    times = np.concatenate([[0.0], np.cumsum(np.hypot(*np.diff(traj, axis=0).T))]) / speed + 1.0
    keep = sorted(set(range(0, len(traj), max(1, every))) | {len(traj) - 1})
    ts = get_typestore(Stores.ROS1_NOETIC)
    T = ts.types

    def header(t: float):
        stamp = T["builtin_interfaces/msg/Time"](sec=int(t), nanosec=round((t % 1) * 1e9) % NS)
        return T["std_msgs/msg/Header"](seq=0, stamp=stamp, frame_id=frame)

    def pose(t: float, xy: np.ndarray):
        p = T["geometry_msgs/msg/Pose"](
            position=T["geometry_msgs/msg/Point"](x=float(xy[0]), y=float(xy[1]), z=0.0),
            orientation=T["geometry_msgs/msg/Quaternion"](x=0.0, y=0.0, z=0.0, w=1.0),
        )
        return T["geometry_msgs/msg/PoseWithCovarianceStamped"](
            header=header(t), pose=T["geometry_msgs/msg/PoseWithCovariance"](pose=p, covariance=np.zeros(36))
        )

    pose_type, string_type = "geometry_msgs/msg/PoseWithCovarianceStamped", "std_msgs/msg/String"
    messages = [(times[i], pose_topic, pose_type, pose(times[i], traj[i])) for i in keep]
    messages += [
        (times[s], utterance_topic, string_type, T[string_type](data=" ".join(tokens)))
        for s, tokens in zip(dataset.event_steps, dataset.tokens, strict=False)
    ]
    out = Path(path)
    if out.is_file() and out.stat().st_size == 0:  # a fresh temporary file (safe_write.atomic_write)
        out.unlink()
    with Writer(out) as writer:
        conns = {
            topic: writer.add_connection(topic, kind, typestore=ts)
            for topic, kind in ((pose_topic, pose_type), (utterance_topic, string_type))
        }
        for t, topic, kind, msg in sorted(messages, key=lambda m: (m[0], m[1] != pose_topic)):
            writer.write(conns[topic], round(t * NS), ts.serialize_ros1(msg, kind))
    return out
