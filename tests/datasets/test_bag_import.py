"""Importing robot logs: bags written here with rosbags' own writers (ROS 1, ROS 2 sqlite3 and mcap; all three pose
types), imported, then loaded with load_dataset."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

rosbags = pytest.importorskip("rosbags", reason="rosbags (extra 'ros') is not installed")

from rosbags.rosbag1 import Writer as Writer1
from rosbags.rosbag2 import StoragePlugin
from rosbags.rosbag2 import Writer as Writer2
from rosbags.typesys import Stores, get_typestore

from spcotmhp.datasets import load_dataset
from spcotmhp.datasets.bag_import import BagImportWarning, import_bag, resample_by_arc_length
from spcotmhp.errors import DatasetError
from spcotmhp.metric.map_io import load_map, save_map
from spcotmhp.metric.maps import OccupancyMap

S = 1_000_000_000  # ns per second
POSE_TYPES = [
    "geometry_msgs/msg/PoseWithCovarianceStamped",
    "geometry_msgs/msg/PoseStamped",
    "nav_msgs/msg/Odometry",
]
FORMATS = ["ros1", "ros2-sqlite3", "ros2-mcap"]
# an L-shaped walk, 1 m east then 1 m north, with a stop at the corner (three poses at (1.5, 0.5))
POSES = [(0.0, (0.5, 0.5)), (1.0, (1.5, 0.5)), (1.2, (1.5, 0.5)), (1.4, (1.5, 0.5)), (2.4, (1.5, 1.5))]
# (time s, text): at 0.3 s 0.3 m along the first leg; at 1.25 s standing at the corner; at 2.0 s 0.6 m up the
# second leg; at 3.0 s after the last pose (held there)
UTTERANCES = [
    (0.3, "This is the kitchen."),
    (1.25, "corner kitchen"),
    (2.0, "the corridor"),
    (3.0, "bedroom"),
]
EXPECTED_XY = [(0.8, 0.5), (1.5, 0.5), (1.5, 1.1), (1.5, 1.5)]
EXPECTED_TOKENS = [["this", "is", "the", "kitchen"], ["corner", "kitchen"], ["the", "corridor"], ["bedroom"]]


# ---- writing bags ----------------------------------------------------------------------------------------
def _store(fmt: str):
    return get_typestore(Stores.ROS1_NOETIC if fmt == "ros1" else Stores.ROS2_HUMBLE)


def _header(ts, t: float, frame: str):
    T = ts.types
    stamp = T["builtin_interfaces/msg/Time"](sec=int(t), nanosec=round((t % 1) * 1e9))
    Header = T["std_msgs/msg/Header"]
    if "seq" in Header.__dataclass_fields__:
        return Header(seq=0, stamp=stamp, frame_id=frame)
    return Header(stamp=stamp, frame_id=frame)


def _pose_msg(ts, msgtype: str, t: float, xy, frame: str = "map"):
    T = ts.types
    pose = T["geometry_msgs/msg/Pose"](
        position=T["geometry_msgs/msg/Point"](x=float(xy[0]), y=float(xy[1]), z=0.0),
        orientation=T["geometry_msgs/msg/Quaternion"](x=0.0, y=0.0, z=0.0, w=1.0),
    )
    cov = np.zeros(36)
    if msgtype == "geometry_msgs/msg/PoseStamped":
        return T[msgtype](header=_header(ts, t, frame), pose=pose)
    with_cov = T["geometry_msgs/msg/PoseWithCovariance"](pose=pose, covariance=cov)
    if msgtype == "geometry_msgs/msg/PoseWithCovarianceStamped":
        return T[msgtype](header=_header(ts, t, frame), pose=with_cov)
    twist = T["geometry_msgs/msg/TwistWithCovariance"](
        twist=T["geometry_msgs/msg/Twist"](
            linear=T["geometry_msgs/msg/Vector3"](x=0.0, y=0.0, z=0.0),
            angular=T["geometry_msgs/msg/Vector3"](x=0.0, y=0.0, z=0.0),
        ),
        covariance=cov,
    )
    return T[msgtype](header=_header(ts, t, frame), child_frame_id="base_link", pose=with_cov, twist=twist)


def _grid_msg(ts, occupancy: OccupancyMap, yaw: float = 0.0):
    T = ts.types
    info = T["nav_msgs/msg/MapMetaData"](
        map_load_time=T["builtin_interfaces/msg/Time"](sec=0, nanosec=0),
        resolution=occupancy.resolution,
        width=occupancy.width,
        height=occupancy.height,
        origin=T["geometry_msgs/msg/Pose"](
            position=T["geometry_msgs/msg/Point"](x=occupancy.origin[0], y=occupancy.origin[1], z=0.0),
            orientation=T["geometry_msgs/msg/Quaternion"](
                x=0.0, y=0.0, z=float(np.sin(yaw / 2)), w=float(np.cos(yaw / 2))
            ),
        ),
    )
    return T["nav_msgs/msg/OccupancyGrid"](
        header=_header(ts, 0, "map"), info=info, data=occupancy.data.astype(np.int8).ravel()
    )


def write_bag(path: Path, fmt: str, messages: list[tuple[str, str, float, object]]) -> Path:
    """messages: (topic, msgtype, time s, message) -> a bag at ``path`` (a .bag file or a ROS 2 folder)."""
    ts = _store(fmt)
    if fmt == "ros1":
        path = path.with_suffix(".bag")
        writer = Writer1(path)
        serialize = ts.serialize_ros1
    else:
        plugin = StoragePlugin.MCAP if fmt == "ros2-mcap" else StoragePlugin.SQLITE3
        writer = Writer2(path, version=9, storage_plugin=plugin)
        serialize = ts.serialize_cdr
    with writer:
        conns = {}
        for topic, msgtype, _, _ in messages:
            if topic not in conns:
                conns[topic] = writer.add_connection(topic, msgtype, typestore=ts)
        for topic, msgtype, t, msg in sorted(messages, key=lambda m: m[2]):
            writer.write(conns[topic], round(t * S), serialize(msg, msgtype))
    return path


def teaching_bag(
    tmp_path: Path,
    fmt: str,
    pose_type: str = POSE_TYPES[0],
    frame: str = "map",
    utterances=UTTERANCES,
    grid: OccupancyMap | None = None,
    name: str = "log",
) -> Path:
    ts = _store(fmt)
    string = ts.types["std_msgs/msg/String"]
    msgs = [("/amcl_pose", pose_type, t, _pose_msg(ts, pose_type, t, xy, frame)) for t, xy in POSES]
    msgs += [("/speech", "std_msgs/msg/String", t, string(data=text)) for t, text in utterances]
    if grid is not None:
        msgs.append(("/map", "nav_msgs/msg/OccupancyGrid", 0.0, _grid_msg(ts, grid)))
    return write_bag(tmp_path / name, fmt, msgs)


def small_map() -> OccupancyMap:
    data = np.zeros((30, 40), dtype=np.int8)
    data[0, :] = data[-1, :] = data[:, 0] = data[:, -1] = 100
    data[25:, 30:] = -1
    return OccupancyMap(data=data, resolution=0.1, origin=(-0.5, -0.5, 0.0))


@pytest.fixture
def map_yaml(tmp_path: Path) -> Path:
    (tmp_path / "src").mkdir()
    return save_map(small_map(), tmp_path / "src" / "home.yaml")


# ---- the hand-computed walk ------------------------------------------------------------------------------
@pytest.mark.parametrize("fmt", FORMATS)
@pytest.mark.parametrize("pose_type", POSE_TYPES)
def test_import_places_each_utterance_at_the_interpolated_pose(tmp_path, fmt, pose_type, map_yaml):
    bag = teaching_bag(tmp_path, fmt, pose_type)
    summary = import_bag(bag, tmp_path / "ds", map_yaml=map_yaml)
    d = load_dataset(tmp_path / "ds", lang="en")
    np.testing.assert_allclose(d.positions, EXPECTED_XY, atol=1e-12)
    assert d.tokens == EXPECTED_TOKENS
    # 2 m walked, resampled every 0.1 m: 21 poses; the three poses at the corner become one point
    assert len(d.trajectory) == 21
    np.testing.assert_allclose(
        d.trajectory[[0, 5, 10, 15, 20]],
        [(0.5, 0.5), (1.0, 0.5), (1.5, 0.5), (1.5, 1.0), (1.5, 1.5)],
        atol=1e-12,
    )
    np.testing.assert_allclose(np.hypot(*np.diff(d.trajectory, axis=0).T), 0.1, atol=1e-12)
    # arc lengths of the events: 0.3, 1.0, 1.6 and 2.0 m
    assert d.event_steps.tolist() == [3, 10, 16, 20]
    assert d.map == small_map()
    assert (summary.n_events, summary.n_pose_messages, summary.n_trajectory) == (4, 5, 21)
    assert summary.path_length_m == pytest.approx(2.0)
    assert summary.duration_s == pytest.approx(2.4)


def test_step_zero_keeps_every_pose_and_takes_the_nearest_in_time(tmp_path, map_yaml):
    bag = teaching_bag(tmp_path, "ros1")
    import_bag(bag, tmp_path / "ds", map_yaml=map_yaml, step=0)
    d = load_dataset(tmp_path / "ds")
    np.testing.assert_allclose(d.trajectory, [xy for _, xy in POSES])
    # pose times 0, 1.0, 1.2, 1.4, 2.4 s; utterances at 0.3 -> 0.0 s, 1.25 -> 1.2 s, 2.0 -> 2.4 s, 3.0 -> 2.4 s
    assert d.event_steps.tolist() == [0, 2, 4, 4]
    np.testing.assert_allclose(d.positions, EXPECTED_XY, atol=1e-12)


def test_map_from_the_bags_occupancy_grid(tmp_path):
    for fmt in ("ros1", "ros2-sqlite3"):
        bag = teaching_bag(tmp_path, fmt, grid=small_map(), name=f"log-{fmt}")
        summary = import_bag(bag, tmp_path / f"ds-{fmt}")
        assert load_dataset(tmp_path / f"ds-{fmt}").map == small_map()
        assert summary.map_source == "/map in the bag"


def test_map_with_intermediate_costs_is_saved_exactly(tmp_path):
    grid = small_map()
    grid.data[5:10, 5:10] = 42
    bag = teaching_bag(tmp_path, "ros2-mcap", grid=grid)
    import_bag(bag, tmp_path / "ds")
    assert np.array_equal(load_map(tmp_path / "ds" / "map.yaml").data, grid.data)


def test_ros2_bag_by_metadata_or_storage_file(tmp_path, map_yaml):
    bag = teaching_bag(tmp_path, "ros2-mcap")
    for i, path in enumerate([bag / "metadata.yaml", next(bag.glob("*.mcap"))]):
        import_bag(path, tmp_path / f"ds{i}", map_yaml=map_yaml)
        np.testing.assert_allclose(load_dataset(tmp_path / f"ds{i}").positions, EXPECTED_XY, atol=1e-12)


def test_japanese_utterances_go_to_words_ja(tmp_path, map_yaml):
    bag = teaching_bag(tmp_path, "ros1", utterances=[(0.5, "ここは キッチン"), (2.0, "ろうか")])
    import_bag(bag, tmp_path / "ds", map_yaml=map_yaml, lang="ja")
    d = load_dataset(tmp_path / "ds", lang="ja")
    assert d.tokens == [["ここは", "キッチン"], ["ろうか"]]
    with pytest.raises(DatasetError, match="no words_en column"):
        load_dataset(tmp_path / "ds", lang="en")


def test_resample_by_arc_length_hand_computed():
    traj, marks, along = resample_by_arc_length(np.array([[0, 0], [0.25, 0], [0.25, 0], [0.25, 0.1]]), 0.1)
    np.testing.assert_allclose(along, [0, 0.25, 0.25, 0.35])
    np.testing.assert_allclose(marks, [0, 0.1, 0.2, 0.3, 0.35])
    np.testing.assert_allclose(traj, [[0, 0], [0.1, 0], [0.2, 0], [0.25, 0.05], [0.25, 0.1]], atol=1e-12)
    traj, marks, _ = resample_by_arc_length(np.array([[1.0, 2.0], [1.0, 2.0]]), 0.1)  # never moved
    np.testing.assert_allclose(traj, [[1.0, 2.0]])


# ---- warnings --------------------------------------------------------------------------------------------
def test_poses_in_another_frame_warn(tmp_path, map_yaml):
    bag = teaching_bag(tmp_path, "ros2-sqlite3", "nav_msgs/msg/Odometry", frame="odom")
    with pytest.warns(BagImportWarning, match=r"poses on /amcl_pose are in frame\(s\) odom, not the map frame map"):
        import_bag(bag, tmp_path / "ds", map_yaml=map_yaml)


def test_empty_utterances_are_dropped_with_a_warning(tmp_path, map_yaml):
    bag = teaching_bag(tmp_path, "ros1", utterances=[(0.5, "kitchen"), (1.0, "   "), (2.0, "corridor")])
    with pytest.warns(BagImportWarning, match="skipped 1 empty utterance"):
        import_bag(bag, tmp_path / "ds", map_yaml=map_yaml)
    assert load_dataset(tmp_path / "ds").tokens == [["kitchen"], ["corridor"]]


# ---- errors ----------------------------------------------------------------------------------------------
def test_missing_bag(tmp_path, map_yaml):
    with pytest.raises(DatasetError, match=r"bag .*nope\.bag does not exist"):
        import_bag(tmp_path / "nope.bag", tmp_path / "ds", map_yaml=map_yaml)


@pytest.mark.parametrize("content", [b"#ROSBAG V2.0\n" + bytes(range(256)) * 2, bytes(range(255, -1, -1)) * 2])
def test_corrupt_ros1_bag(tmp_path, map_yaml, content):
    (tmp_path / "bad.bag").write_bytes(content)
    with pytest.raises(DatasetError, match=r"cannot read bag .*bad\.bag: "):
        import_bag(tmp_path / "bad.bag", tmp_path / "ds", map_yaml=map_yaml)
    assert not (tmp_path / "ds").exists()


def test_corrupt_ros2_bag(tmp_path, map_yaml):
    bag = teaching_bag(tmp_path, "ros2-sqlite3")
    next(bag.glob("*.db3")).write_bytes(b"not a database" * 100)
    with pytest.raises(DatasetError, match=r"cannot read bag .*: .*not a database"):
        import_bag(bag, tmp_path / "ds", map_yaml=map_yaml)


def test_folder_or_file_that_is_not_a_bag(tmp_path, map_yaml):
    (tmp_path / "empty").mkdir()
    with pytest.raises(DatasetError, match="folder without metadata.yaml, so not a ROS 2 bag"):
        import_bag(tmp_path / "empty", tmp_path / "ds", map_yaml=map_yaml)
    (tmp_path / "poses.csv").write_text("x,y\n")
    with pytest.raises(DatasetError, match=r"poses\.csv is not a bag: expected a ROS 1 \.bag file"):
        import_bag(tmp_path / "poses.csv", tmp_path / "ds", map_yaml=map_yaml)


def test_absent_topic_lists_the_topics_present(tmp_path, map_yaml):
    bag = teaching_bag(tmp_path, "ros1", "nav_msgs/msg/Odometry")
    with pytest.raises(
        DatasetError,
        match=r"has no pose topic /odom; topics present: /amcl_pose "
        r"\(nav_msgs/msg/Odometry\); /speech \(std_msgs/msg/String\)",
    ):
        import_bag(bag, tmp_path / "ds", pose_topic="/odom", map_yaml=map_yaml)
    with pytest.raises(DatasetError, match=r"has no utterance topic /asr; topics present: /amcl_pose"):
        import_bag(bag, tmp_path / "ds", utterance_topic="/asr", map_yaml=map_yaml)


def test_unsupported_message_types(tmp_path, map_yaml):
    bag = teaching_bag(tmp_path, "ros2-sqlite3")
    with pytest.raises(
        DatasetError,
        match=r"topic /speech carries std_msgs/msg/String, which is not a supported "
        r"pose type; supported: geometry_msgs/msg/PoseStamped, "
        r"geometry_msgs/msg/PoseWithCovarianceStamped, nav_msgs/msg/Odometry",
    ):
        import_bag(bag, tmp_path / "ds", pose_topic="/speech", map_yaml=map_yaml)
    with pytest.raises(
        DatasetError,
        match=r"topic /amcl_pose carries geometry_msgs/msg/PoseWithCovarianceStamped, "
        r"which is not a supported utterance type; supported: std_msgs/msg/String",
    ):
        import_bag(bag, tmp_path / "ds", utterance_topic="/amcl_pose", map_yaml=map_yaml)


def test_utterance_before_the_first_pose(tmp_path, map_yaml):
    ts = _store("ros1")
    msgs = [("/amcl_pose", POSE_TYPES[1], t, _pose_msg(ts, POSE_TYPES[1], t, xy)) for t, xy in POSES[1:]]
    msgs += [
        ("/speech", "std_msgs/msg/String", 0.25, ts.types["std_msgs/msg/String"](data="kitchen")),
        ("/speech", "std_msgs/msg/String", 2.0, ts.types["std_msgs/msg/String"](data="corridor")),
    ]
    bag = write_bag(tmp_path / "early", "ros1", msgs)
    with pytest.raises(
        DatasetError,
        match=r"utterance 'kitchen' was recorded 0\.750 s before the first pose "
        r"\(utterance at 0\.250 s, first pose at 1\.000 s; 1 utterance\(s\) have "
        r"no pose before them\)",
    ):
        import_bag(bag, tmp_path / "ds", map_yaml=map_yaml)


@pytest.mark.parametrize("fmt", ["ros1", "ros2-sqlite3"])
def test_empty_bag(tmp_path, map_yaml, fmt):
    ts = _store(fmt)
    bag = tmp_path / "empty.bag" if fmt == "ros1" else tmp_path / "empty"
    writer = Writer1(bag) if fmt == "ros1" else Writer2(bag, version=9)
    with writer:
        if fmt != "ros1":
            writer.add_connection("/amcl_pose", POSE_TYPES[0], typestore=ts)
    with pytest.raises(DatasetError, match=r"bag .*empty.* is empty \(no messages\)"):
        import_bag(bag, tmp_path / "ds", map_yaml=map_yaml)


def test_topic_without_messages(tmp_path, map_yaml):
    ts = _store("ros2-sqlite3")
    bag = tmp_path / "quiet"
    with Writer2(bag, version=9) as writer:
        writer.add_connection("/amcl_pose", POSE_TYPES[0], typestore=ts)
        conn = writer.add_connection("/speech", "std_msgs/msg/String", typestore=ts)
        writer.write(conn, S, ts.serialize_cdr(ts.types["std_msgs/msg/String"](data="kitchen"), "std_msgs/msg/String"))
    with pytest.raises(DatasetError, match=r"topic /amcl_pose has no messages in bag"):
        import_bag(bag, tmp_path / "ds", map_yaml=map_yaml)


def test_no_map(tmp_path):
    bag = teaching_bag(tmp_path, "ros1")
    with pytest.raises(DatasetError, match=r"no map: the bag has no /map topic; pass --map MAP_YAML"):
        import_bag(bag, tmp_path / "ds")
    assert not (tmp_path / "ds").exists()


def test_rotated_map_topic(tmp_path):
    ts = _store("ros1")
    msgs = [("/amcl_pose", POSE_TYPES[0], t, _pose_msg(ts, POSE_TYPES[0], t, xy)) for t, xy in POSES]
    msgs += [
        ("/speech", "std_msgs/msg/String", 0.5, ts.types["std_msgs/msg/String"](data="kitchen")),
        ("/map", "nav_msgs/msg/OccupancyGrid", 0.0, _grid_msg(ts, small_map(), yaw=0.5)),
    ]
    bag = write_bag(tmp_path / "rot", "ros1", msgs)
    with pytest.raises(DatasetError, match=r"the map on /map is rotated \(origin yaw 0\.5000 rad\)"):
        import_bag(bag, tmp_path / "ds")


def test_no_utterance_words(tmp_path, map_yaml):
    bag = teaching_bag(tmp_path, "ros1", utterances=[(0.5, "  ")])
    with pytest.raises(DatasetError, match="no utterances with words"), pytest.warns(BagImportWarning):
        import_bag(bag, tmp_path / "ds", map_yaml=map_yaml)


def test_refuses_to_overwrite_a_dataset(tmp_path, map_yaml):
    bag = teaching_bag(tmp_path, "ros1")
    import_bag(bag, tmp_path / "ds", map_yaml=map_yaml)
    with pytest.raises(DatasetError, match=r"ds already holds a dataset; give --overwrite"):
        import_bag(bag, tmp_path / "ds", map_yaml=map_yaml)
    (tmp_path / "ds" / "truth.csv").write_text("event,place\n0,0\n")  # from some other dataset
    import_bag(bag, tmp_path / "ds", map_yaml=map_yaml, step=0, overwrite=True)
    assert len(load_dataset(tmp_path / "ds").trajectory) == len(POSES)
    assert not (tmp_path / "ds" / "truth.csv").exists()  # replaced whole, nothing stale
    (tmp_path / "ds" / "notes.txt").write_text("mine")  # not a dataset's file: never replaced
    with pytest.raises(DatasetError, match="files that are not a dataset's"):
        import_bag(bag, tmp_path / "ds", map_yaml=map_yaml, overwrite=True)
    assert (tmp_path / "ds" / "notes.txt").read_text() == "mine"


def test_a_failed_import_leaves_the_old_dataset(tmp_path, map_yaml, monkeypatch):
    import spcotmhp.datasets.bag_import as bi

    bag = teaching_bag(tmp_path, "ros1")
    import_bag(bag, tmp_path / "ds", map_yaml=map_yaml)
    before = {p.name: p.read_bytes() for p in (tmp_path / "ds").iterdir()}

    def broken(*args, **kwargs):
        raise OSError(28, "No space left on device")

    monkeypatch.setattr(bi, "_write_csv", broken)
    with pytest.raises(DatasetError, match="No space left on device"):
        import_bag(bag, tmp_path / "ds", map_yaml=map_yaml, step=0, overwrite=True)
    assert {p.name: p.read_bytes() for p in (tmp_path / "ds").iterdir()} == before
    assert sorted(p.name for p in tmp_path.iterdir() if p.name.startswith(".ds")) == []


def test_a_robot_that_never_moved(tmp_path, map_yaml):
    ts = _store("ros2-sqlite3")
    msgs = [
        ("/amcl_pose", POSE_TYPES[0], 1.0, _pose_msg(ts, POSE_TYPES[0], 1.0, (1.0, 1.0))),
        ("/speech", "std_msgs/msg/String", 2.0, ts.types["std_msgs/msg/String"](data="kitchen")),
        ("/speech", "std_msgs/msg/String", 3.0, ts.types["std_msgs/msg/String"](data="this is the kitchen")),
    ]
    import_bag(write_bag(tmp_path / "still", "ros2-sqlite3", msgs), tmp_path / "ds", map_yaml=map_yaml)
    d = load_dataset(tmp_path / "ds")
    np.testing.assert_allclose(d.trajectory, [(1.0, 1.0)])
    np.testing.assert_allclose(d.positions, [(1.0, 1.0), (1.0, 1.0)])
    assert d.event_steps.tolist() == [0, 0]


def test_bad_step_and_lang(tmp_path, map_yaml):
    bag = teaching_bag(tmp_path, "ros1")
    with pytest.raises(DatasetError, match=r"step must be a finite number of metres >= 0, got -0.1"):
        import_bag(bag, tmp_path / "ds", map_yaml=map_yaml, step=-0.1)
    with pytest.raises(DatasetError, match=r"lang must be 'en' or 'ja', got 'fr'"):
        import_bag(bag, tmp_path / "ds", map_yaml=map_yaml, lang="fr")


# ---- the command line ------------------------------------------------------------------------------------
def _cli(*args: str) -> subprocess.CompletedProcess:
    exe = Path(sys.executable).with_name("spcotmhp")
    cmd = [str(exe)] if exe.exists() else [sys.executable, "-m", "spcotmhp.cli"]
    return subprocess.run(
        cmd + list(args), check=False, capture_output=True, text=True, env={**os.environ, "COLUMNS": "200"}
    )


def test_cli_import_bag(tmp_path, map_yaml):
    bag = teaching_bag(tmp_path, "ros2-mcap", "nav_msgs/msg/Odometry", frame="odom")
    done = _cli(
        "import-bag",
        str(bag),
        "--pose-topic",
        "/amcl_pose",
        "--utterance-topic",
        "/speech",
        "--out",
        str(tmp_path / "ds"),
        "--map",
        str(map_yaml),
        "--step",
        "0.1",
    )
    assert done.returncode == 0, done.stderr
    assert "wrote" in done.stdout and "4 teaching events, 21 trajectory poses (from 5 pose messages" in done.stdout
    assert "warning: poses on /amcl_pose are in frame(s) odom" in done.stderr
    np.testing.assert_allclose(load_dataset(tmp_path / "ds").positions, EXPECTED_XY, atol=1e-12)
    done = _cli(
        "import-bag",
        str(bag),
        "--pose-topic",
        "/odom",
        "--out",
        str(tmp_path / "ds2"),
        "--map",
        str(map_yaml),
    )
    assert done.returncode == 2
    assert done.stderr.startswith("error: bag ") and "has no pose topic /odom; topics present:" in done.stderr
    assert "Traceback" not in done.stderr
