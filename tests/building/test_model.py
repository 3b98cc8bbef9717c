"""A building's model: places know their floor; a floor's view is an ordinary model of that floor (its map, its
places, psi renormalised over them, the building's concepts and words); floors named by index, name or relation."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

from spcotmhp.building.learn import learn_building
from spcotmhp.building.synthetic import generate_building
from spcotmhp.errors import ModelError, UnknownFloor
from spcotmhp.learning.supervised import fit_supervised


@pytest.fixture(scope="module")
def built():
    b = generate_building(3, seed=3, n_rooms=5, events_per_room=5)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return b, learn_building(b)


def test_places_know_their_floor(built):
    b, bm = built
    floor = bm.place_floor()
    start = 0
    for i in bm.indices:
        n = len(b.floors[i].place_names)
        assert (floor[start : start + n] == i).all()  # supervised: floor i's truth places
        start += n
    assert [int(bm.floor_places(i).sum()) for i in bm.indices] == [len(b.floors[i].place_names) for i in bm.indices]


def test_a_floor_view_is_that_floor(built):
    b, bm = built
    for i in bm.indices:
        view = bm.floor_model(i)
        assert view is bm.floor_model(i)  # made once
        assert view.map == b.floors[i].map
        mine = bm.floor_places(i)
        assert (view.active_places == mine).all()
        assert np.allclose(view.psi[mine].sum(axis=1), 1) and (view.psi[np.ix_(mine, ~mine)] == 0).all()
        assert view.vocabulary == bm.model.vocabulary and np.array_equal(view.W, bm.model.W)
        assert np.array_equal(view.phi, bm.model.phi)  # not renormalised: word terms compare across floors
        # the means in the floor's frame are the floor's own supervised fit's, but for the pull of the prior mean
        # m0 = 0, which lies elsewhere in the joint frame: kappa0 / (kappa0 + n) times the frames' offset
        # fitted with the building's priors (kappa0 scaled to the joint frame, building/learn.py), the difference
        # is kappa0 n / (kappa0 + n) (a a^T - b b^T) / (nu0 + n - 3) in Sigma, a and b a place's mean in the two
        # frames, and kappa0 / (kappa0 + n) times the frames' offset in mu
        alone = fit_supervised(b.floors[i], hyper=bm.model.hyper)
        kappa0 = bm.model.hyper.kappa0
        n = np.bincount(b.floors[i].truth_place).min()
        far = np.abs(bm.layout.to_joint(i, alone.mu)).max()
        assert np.allclose(view.mu[mine], alone.mu, rtol=0, atol=kappa0 / n * far + 1e-9)
        assert np.allclose(view.Sigma[mine], alone.Sigma, rtol=0, atol=2 * kappa0 * far**2 / n + 1e-9)


def test_the_place_prior_weighs_no_more_than_on_one_floor(built):
    b, bm = built
    lay = bm.layout
    corner = max(np.hypot(*(np.abs(t.origin) + 0.1 * np.array(t.shape[::-1]))) for t in lay.tiles)
    joint = 0.1 * np.hypot(lay.height, lay.width)
    assert bm.model.hyper.kappa0 == pytest.approx(1e-3 * (corner / joint) ** 2)
    assert bm.model.hyper.kappa0 * joint**2 == pytest.approx(1e-3 * corner**2)


def test_floors_by_index_name_and_relation(built):
    _, bm = built
    assert bm.check_floor(2) == bm.check_floor("2") == bm.check_floor("First") == 2
    assert bm.resolve_floor("upstairs", 1) == 2 and bm.resolve_floor("downstairs", 3) == 2
    with pytest.raises(UnknownFloor, match=r"no floor '7'.*1 \(ground\), 2 \(first\), 3 \(second\)"):
        bm.check_floor(7)
    with pytest.raises(UnknownFloor, match="no floor lies above floor 3"):
        bm.resolve_floor("upstairs", 3)
    for bad in (True, 2.5, None, "x" * 500):
        with pytest.raises(UnknownFloor):
            bm.check_floor(bad)


def test_the_map_must_be_the_layout(built):
    _, bm = built
    from spcotmhp.building.model import BuildingModel

    b2 = generate_building(2, seed=0, n_rooms=4, events_per_room=2)
    with pytest.raises(ModelError, match="layout's floors"):
        BuildingModel(bm.model, b2.layout(), bm.spec)
