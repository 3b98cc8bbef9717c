"""The joint frame: tiles side by side, exact round trips of points and maps, the floor of a point."""

from __future__ import annotations

import numpy as np
import pytest

from spcotmhp.building.layout import Layout
from spcotmhp.errors import BuildingError, ModelError
from spcotmhp.metric.maps import OccupancyMap


def _maps():
    rng = np.random.default_rng(0)
    a = OccupancyMap(rng.choice(np.array([-1, 0, 100], np.int8), (30, 40)), 0.05, (-1.0, -2.0, 0.0))
    b = OccupancyMap(rng.choice(np.array([-1, 0, 100], np.int8), (50, 20)), 0.05, (3.0, 0.5, 0.0))
    return {3: b, 1: a}


def test_tiles_are_apart_by_the_largest_diagonal():
    lay = Layout.plan(_maps())
    assert lay.indices == [1, 3]
    assert lay.gap == int(np.ceil(np.hypot(50, 20))) + 1
    assert [t.col0 for t in lay.tiles] == [0, 40 + lay.gap]
    assert (lay.height, lay.width) == (50, 40 + lay.gap + 20)


def test_maps_and_points_round_trip():
    maps = _maps()
    lay = Layout.plan(maps)
    joint = lay.stitch(maps)
    for i, m in maps.items():
        assert lay.crop(joint, i) == m
        rows, cols = np.indices(m.shape)
        cells = np.stack([rows.ravel(), cols.ravel()], axis=1)
        xy = m.cell_to_world(cells)
        j = lay.to_joint(i, xy)
        t = lay.tile(i)
        assert (joint.world_to_cell(j) == cells + [0, t.col0]).all()  # the same cell in the joint grid
        assert np.allclose(lay.from_joint(i, j), xy)
        assert (lay.floor_of(j) == i).all()
    gap = lay.tiles[1].col0 - lay.gap  # columns between the tiles are unknown
    assert (joint.data[:, 40 : gap + lay.gap] == -1).all()


def test_points_in_the_gap_belong_to_the_nearest_tile():
    lay = Layout.plan(_maps())
    x_end = 40 * 0.05
    x_next = lay.tiles[1].col0 * 0.05
    pts = np.array([[x_end + 0.1, 0], [x_next - 0.1, 0], [-5.0, 0]])
    assert lay.floor_of(pts).tolist() == [1, 3, 1]


def test_refusals():
    a = OccupancyMap(np.zeros((10, 10), np.int8), 0.05)
    b = OccupancyMap(np.zeros((10, 10), np.int8), 0.1)
    with pytest.raises(BuildingError, match="share one resolution.*floor 1: 0.05 m, floor 2: 0.1 m"):
        Layout.plan({1: a, 2: b})
    long = OccupancyMap(np.zeros((1, 900), np.int8), 0.05)
    with pytest.raises(BuildingError, match="side by side make a grid of"):
        Layout.plan({1: long, 2: long})


def test_the_saved_form_round_trips_and_is_checked():
    lay = Layout.plan(_maps())
    assert Layout.from_dict(lay.to_dict(), "b.json", ModelError) == lay
    doc = lay.to_dict()
    doc["tiles"][1]["col0"] += 1
    with pytest.raises(ModelError, match=r"b.json: layout tiles\[1\] must be"):
        Layout.from_dict(doc, "b.json", ModelError)
    for bad in ({"resolution": -1}, {"gap": 0}, {"tiles": []}, {"extra": 1}):
        with pytest.raises(ModelError, match="b.json: layout"):
            Layout.from_dict({**lay.to_dict(), **bad}, "b.json", ModelError)
