"""What the ROS 2 node publishes, without ROS: headings, ellipses, the map check, the teaching log
(hand-computed cases)."""

from __future__ import annotations

import math
import warnings

import numpy as np
import pytest

from spcotmhp.datasets import load_dataset
from spcotmhp.errors import DatasetError
from spcotmhp.metric.maps import OccupancyMap
from spcotmhp.ros.shapes import (
    ellipse,
    map_mismatches,
    path_poses,
    path_yaws,
    quaternion_yaw,
    yaw_quaternion,
)
from spcotmhp.ros.teaching_log import TeachingLog


def test_headings_face_the_next_distinct_point_and_the_last_keeps_the_last_segment():
    points = [(0, 0), (1, 0), (1, 0), (1, 1), (0, 2), (0, 2)]
    assert np.allclose(
        path_yaws(points), [0, math.pi / 2, math.pi / 2, 3 * math.pi / 4, 3 * math.pi / 4, 3 * math.pi / 4]
    )
    assert np.allclose(path_yaws([(2, 3)], fallback=0.7), [0.7])
    assert np.allclose(path_yaws([(2, 3), (2, 3)], fallback=-1.0), [-1.0, -1.0])


@pytest.mark.parametrize("yaw", [0.0, 0.5, -2.0, math.pi - 1e-9, 3.0])
def test_quaternions_round_trip(yaw):
    q = yaw_quaternion(yaw)
    assert q[0] == q[1] == 0 and math.isclose(q[2] ** 2 + q[3] ** 2, 1.0)
    assert math.isclose(quaternion_yaw(*q), yaw, abs_tol=1e-9)


def test_ellipse_axes_and_heading():
    scale = -2 * math.log(0.05)  # the chi-square 0.95 quantile with 2 degrees of freedom
    length, width, yaw = ellipse(np.diag([4.0, 1.0]))
    assert math.isclose(length, 2 * math.sqrt(4 * scale)) and math.isclose(width, 2 * math.sqrt(scale))
    assert math.isclose(abs(math.cos(yaw)), 1.0, abs_tol=1e-9)
    c, s = math.cos(math.pi / 6), math.sin(math.pi / 6)
    rot = np.array([[c, -s], [s, c]])
    length2, width2, yaw2 = ellipse(rot @ np.diag([4.0, 1.0]) @ rot.T)
    assert math.isclose(length2, length) and math.isclose(width2, width)
    assert math.isclose(math.tan(yaw2), math.tan(math.pi / 6))


def small_map() -> OccupancyMap:
    data = np.zeros((4, 6), dtype=np.int8)
    data[:, 0] = 100
    return OccupancyMap(data=data, resolution=0.5, origin=(-1.0, 2.0, 0.0))


def test_map_mismatches_name_what_differs():
    occ = small_map()
    assert map_mismatches(6, 4, 0.5, (-1.0, 2.0, 0.0), occ) == []
    assert map_mismatches(6, 4, 0.5, (-0.96, 2.04, 0.0), occ) == []  # within a tenth of a cell
    found = map_mismatches(4, 6, 0.05, (-1.0, 2.2, 0.1), occ)
    assert len(found) == 3
    assert found[0].startswith("size 4x6 cells") and found[1].startswith("resolution 0.05 m")
    assert found[2].startswith("origin (-1.000, 2.200, yaw 0.100)")


def test_path_starts_at_the_pose():
    occ = small_map()
    cells = np.array([[0, 1], [0, 2]])
    path = occ.cell_to_world(cells)
    inside = path[0] + [0.1, -0.2]
    assert np.allclose(path_poses(path, cells, inside, occ), [inside, path[1]])
    outside = path[0] + [-0.3, 0.0]  # another cell: put before
    assert np.allclose(path_poses(path, cells, outside, occ), [outside, path[0], path[1]])


def test_teaching_log_writes_a_dataset_and_appends_to_it(tmp_path):
    occ = small_map()
    folder = tmp_path / "taught"
    log = TeachingLog(folder, occ)
    assert sorted(p.name for p in folder.iterdir()) == ["map.pgm", "map.yaml"]
    assert log.append(0.3, 2.6, 'this is the "kitchen", ok') == 0
    assert log.append(1.1, 3.1, "ここは 台所") == 1
    with pytest.raises(DatasetError, match="empty"):
        log.append(0.3, 2.6, " \n ")
    with pytest.raises(DatasetError, match="not finite"):
        log.append(float("nan"), 2.6, "kitchen")
    again = TeachingLog(folder, occ)  # an existing dataset: appended to
    assert again.append(0.8, 2.3, "the bath") == 2
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        en, ja = load_dataset(folder, lang="en"), load_dataset(folder, lang="ja")
    assert en.tokens == [["this", "is", "the", "kitchen", "ok"], [], ["the", "bath"]]
    assert np.allclose(en.positions, [[0.3, 2.6], [1.1, 3.1], [0.8, 2.3]]) and en.map == occ
    assert ja.tokens[1] == ["ここは", "台所"]


def test_teaching_log_refuses_folders_it_would_spoil(tmp_path):
    occ = small_map()
    (tmp_path / "notes").mkdir()
    (tmp_path / "notes" / "todo.txt").write_text("x")
    with pytest.raises(DatasetError, match="no map.yaml"):
        TeachingLog(tmp_path / "notes", occ)
    TeachingLog(tmp_path / "other", OccupancyMap(data=np.zeros((4, 6), np.int8), resolution=0.25))
    with pytest.raises(DatasetError, match="resolution 0.25 m"):
        TeachingLog(tmp_path / "other", occ)
    with pytest.raises(DatasetError, match="does not exist"):
        TeachingLog(tmp_path / "missing" / "taught", occ)
