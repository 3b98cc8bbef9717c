"""The learn path's speed-ups compute what the code before them computed, bit for bit: each beside the previous
computation, written out here as it was (issue 35: the 16-megapixel learn + precompute)."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from numba import njit

from spcotmhp.errors import MapError
from spcotmhp.learning.territory import posterior_arg_max
from spcotmhp.metric._wavefront import wavefront
from spcotmhp.metric.costmap import (
    COST_TRANSLATION_TABLE,
    FREE_SPACE,
    INSCRIBED_INFLATED_OBSTACLE,
    LETHAL_OBSTACLE,
    NO_INFORMATION,
    CostMapSettings,
    inflate,
    inflation_kernel,
    log_probability,
    static_costs,
)
from spcotmhp.metric.grid_ops import dilate_square, label4, label_sizes, nearest_feature
from spcotmhp.metric.maps import OccupancyMap
from spcotmhp.metric.snap import snap
from spcotmhp.planning.regions import _set_homes
from spcotmhp.planning.territory import grown_territories


def log_probability_before(costs: np.ndarray, occ_map: OccupancyMap) -> np.ndarray:
    """log p(x|m) as it was: the log of every free cell's (100 - cost_ros) / 100."""
    cost_ros = COST_TRANSLATION_TABLE[costs].astype(np.float64)
    free = occ_map.free & (costs < INSCRIBED_INFLATED_OBSTACLE)
    log_p = np.full(costs.shape, -np.inf)
    log_p[free] = np.log((100.0 - cost_ros[free]) / 100.0)
    return log_p


def grown_territories_before(territory: np.ndarray, places: np.ndarray, margin_cells: float) -> dict:
    """The grown territories as they were: each place's cells found over the whole crop."""
    m = max(0, round(margin_cells))
    h, w = territory.shape
    out = {}
    for k in places:
        own = territory == k
        if not own.any():
            continue
        rows, cols = np.flatnonzero(own.any(axis=1)), np.flatnonzero(own.any(axis=0))
        r0, r1 = max(rows[0] - m, 0), min(rows[-1] + m + 1, h)
        c0, c1 = max(cols[0] - m, 0), min(cols[-1] + m + 1, w)
        window = own[r0:r1, c0:c1]
        if m:
            window = dilate_square(window, m)
        out[int(k)] = (int(r0), int(c0), window)
    return out


@settings(max_examples=60, deadline=None)
@given(st.integers(0, 2**32 - 1), st.integers(3, 40), st.integers(3, 40))
def test_log_probability_is_the_per_cell_formula(seed, h, w):
    rng = np.random.default_rng(seed)
    data = rng.choice(np.array([0, 0, 0, 100, -1, 50], dtype=np.int8), size=(h, w))
    occ = OccupancyMap(data=data, resolution=0.05)
    every = rng.integers(0, 256, size=(h, w)).astype(np.uint8)  # every cost, not only those inflation gives
    assert np.array_equal(log_probability(every, occ), log_probability_before(every, occ))
    cm = inflate(occ)
    assert np.array_equal(cm.log_p, log_probability_before(cm.costs, occ))


def test_log_probability_of_each_cost_by_hand():
    occ = OccupancyMap(data=np.zeros((1, 256), dtype=np.int8), resolution=0.05)
    log_p = log_probability(np.arange(256, dtype=np.uint8)[None, :], occ)[0]
    assert log_p[0] == 0.0  # cost 0: p = 1
    assert log_p[252] == np.log((100.0 - 98.0) / 100.0)  # the last cost below the inscribed one: cost_ros 98
    assert np.isneginf(log_p[253:]).all()


def static_costs_before(occ_map: OccupancyMap, track_unknown_space: bool = False) -> np.ndarray:
    """The static layer as it was: three passes of np.where."""
    data = np.asarray(occ_map.data)
    unknown_cost = NO_INFORMATION if track_unknown_space else FREE_SPACE
    costs = np.where(data >= 100, LETHAL_OBSTACLE, FREE_SPACE)
    costs = np.where(data == -1, unknown_cost, costs)
    costs = np.where((data < -1), LETHAL_OBSTACLE, costs)
    return np.ascontiguousarray(costs, dtype=np.uint8)


@pytest.mark.parametrize("track", [False, True])
def test_static_costs_of_every_byte_as_before(track):
    every = np.arange(-128, 128, dtype=np.int8).reshape(16, 16)
    for data in (every, every.T, every.astype(np.int64) * 3):  # int8, not contiguous, another dtype
        occ = OccupancyMap(data=data, resolution=0.05)
        new = static_costs(occ, track)
        assert new.dtype == np.uint8 and np.array_equal(new, static_costs_before(occ, track))


def test_window_centres_are_cell_to_world():
    occ = OccupancyMap(data=np.zeros((7, 9), np.int8), resolution=0.037, origin=(-3.3, 12.71, 0.0))
    rr, cc = np.indices((4, 5))
    cells = np.stack([rr + 2, cc + 3], axis=-1)
    assert np.array_equal(occ.window_centres(2, 3, 4, 5), occ.cell_to_world(cells))
    rr, cc = np.indices(occ.shape)
    assert np.array_equal(occ.cell_centres(), occ.cell_to_world(np.stack([rr, cc], axis=-1)))


@settings(max_examples=100, deadline=None)
@given(
    st.integers(0, 2**32 - 1),
    st.integers(1, 30),
    st.integers(1, 30),
    st.integers(1, 6),
    st.sampled_from([0.0, 0.4, 1.0, 2.6]),
)
def test_grown_territories_as_before(seed, h, w, n, margin):
    rng = np.random.default_rng(seed)
    territory = rng.integers(-1, n, size=(h, w))
    places = rng.permutation(np.arange(n + 2))[: rng.integers(0, n + 3)]  # some own no cell
    new, old = grown_territories(territory, places, margin), grown_territories_before(territory, places, margin)
    assert list(new) == list(old)
    for k in old:
        assert new[k][:2] == old[k][:2] and np.array_equal(new[k][2], old[k][2])


@pytest.mark.parametrize("unknown", [False, True])
@settings(max_examples=40, deadline=None)
@given(
    st.integers(0, 2**32 - 1),
    st.integers(1, 70),
    st.integers(1, 70),
    st.sampled_from([1, 3, 8, 30]),
    st.sampled_from([0.0, 0.02, 0.3]),
)
def test_wavefront_is_the_linked_list_one(unknown, seed, h, w, radius, density):
    """Costs equal to the previous kernel's on random maps (unknown cells, both unknown rules, radii beyond the
    map), and one map big enough to need more than one block per bin and growing the block store."""
    rng = np.random.default_rng(seed)
    data = np.where(rng.random((h, w)) < density, 100, 0).astype(np.int8)
    data[rng.random((h, w)) < 0.1] = -1
    occ = OccupancyMap(data=data, resolution=0.05)
    settings_ = CostMapSettings(0.1, radius * 0.05, 3.0, unknown, unknown)
    bins, kernel_costs = inflation_kernel(radius, 0.05, settings_)
    new, old = static_costs(occ, unknown), static_costs(occ, unknown)
    wavefront(new, bins, kernel_costs, unknown)
    wavefront_before(old, bins, kernel_costs, unknown)
    assert np.array_equal(new, old)


def test_wavefront_on_a_big_map_is_the_linked_list_one():
    rng = np.random.default_rng(7)
    data = np.where(rng.random((400, 500)) < 0.002, 100, 0).astype(np.int8)
    data[:, 250] = 100
    occ = OccupancyMap(data=data, resolution=0.05)
    for unknown in (False, True):
        settings_ = CostMapSettings(0.2, 1.0, 10.0, unknown, unknown)
        bins, kernel_costs = inflation_kernel(20, 0.05, settings_)
        new, old = static_costs(occ, unknown), static_costs(occ, unknown)
        wavefront(new, bins, kernel_costs, unknown)
        wavefront_before(old, bins, kernel_costs, unknown)
        assert np.array_equal(new, old)
        assert (new > FREE_SPACE).mean() > 0.5  # most cells reached: many blocks per bin


@njit(cache=True)
def wavefront_before(costs, bins, kernel_costs, inflate_unknown):  # pragma: no cover - numba
    """InflationLayer::updateCosts as it was: one linked list through every entry, flat indices."""
    height, width = costs.shape
    flat = costs.reshape(-1)
    n_bins = bins.max() + 1
    head = np.full(n_bins, -1, np.int64)
    tail = np.full(n_bins, -1, np.int64)
    capacity = 1024
    cell = np.empty(capacity, np.int64)
    source = np.empty(capacity, np.int64)
    nxt = np.empty(capacity, np.int64)
    count = 0
    seen = np.zeros(height * width, np.bool_)
    for index in range(height * width):
        if flat[index] == LETHAL_OBSTACLE:
            if count == capacity:
                capacity *= 2
                cell, source, nxt = _grow_before(cell, source, nxt, capacity)
            cell[count], source[count], nxt[count] = index, index, -1
            if head[0] == -1:
                head[0] = count
            else:
                nxt[tail[0]] = count
            tail[0] = count
            count += 1
    for b in range(n_bins):
        entry = head[b]
        while entry != -1:
            index = cell[entry]
            if not seen[index]:
                seen[index] = True
                src = source[entry]
                my, mx = index // width, index % width
                sy, sx = src // width, src % width
                cost = kernel_costs[abs(mx - sx), abs(my - sy)]
                old = flat[index]
                if old == NO_INFORMATION and (
                    (cost > FREE_SPACE) if inflate_unknown else (cost >= INSCRIBED_INFLATED_OBSTACLE)
                ):
                    flat[index] = cost
                else:
                    flat[index] = max(old, cost)
                for k in range(4):
                    if k == 0:
                        if mx == 0:
                            continue
                        ny, nx = my, mx - 1
                    elif k == 1:
                        if my == 0:
                            continue
                        ny, nx = my - 1, mx
                    elif k == 2:
                        if mx == width - 1:
                            continue
                        ny, nx = my, mx + 1
                    else:
                        if my == height - 1:
                            continue
                        ny, nx = my + 1, mx
                    nindex = ny * width + nx
                    if seen[nindex]:
                        continue
                    nb = bins[abs(nx - sx), abs(ny - sy)]
                    if nb < b:  # beyond the radius (-1), or a bin already passed: std::map never visits it
                        continue
                    if count == capacity:
                        capacity *= 2
                        cell, source, nxt = _grow_before(cell, source, nxt, capacity)
                    cell[count], source[count], nxt[count] = nindex, src, -1
                    if head[nb] == -1:
                        head[nb] = count
                    else:
                        nxt[tail[nb]] = count
                    tail[nb] = count
                    count += 1
            entry = nxt[entry]


@njit(cache=True)
def _grow_before(cell, source, nxt, capacity):  # pragma: no cover - numba
    """The three entry arrays copied into arrays of ``capacity`` entries."""
    out = (np.empty(capacity, np.int64), np.empty(capacity, np.int64), np.empty(capacity, np.int64))
    n = cell.shape[0]
    out[0][:n], out[1][:n], out[2][:n] = cell, source, nxt
    return out


@settings(max_examples=60, deadline=None)
@given(st.integers(0, 2**32 - 1), st.integers(1, 40), st.integers(1, 40))
def test_label_sizes_and_homes_as_numpy(seed, h, w):
    rng = np.random.default_rng(seed)
    labels, n = label4(rng.random((h, w)) < 0.6)
    assert np.array_equal(label_sizes(labels, n), np.bincount(labels.ravel(), minlength=n + 1))
    act = np.sort(rng.choice(12, size=5, replace=False))
    base = rng.integers(-1, 5, size=(h, w))  # not one region a place: the last cell in raster order wins
    held = base >= 0
    before = np.zeros(12, dtype=np.int64)
    before[act[base[held]]] = labels[held]
    now = np.zeros(12, dtype=np.int64)
    _set_homes(now, act, base, labels.astype(np.int32))
    assert np.array_equal(now, before)


@settings(max_examples=40, deadline=None)
@given(st.integers(0, 2**32 - 1), st.integers(1, 400), st.integers(1, 9))
def test_most_probable_place_on_threads_is_the_one_thread_answer(seed, n, k):
    rng = np.random.default_rng(seed)
    points = rng.uniform(-5, 5, size=(n, 2))
    mu = rng.uniform(-5, 5, size=(k, 2))
    a = rng.uniform(0.05, 3, size=(k, 2, 2))
    Sigma = a @ a.transpose(0, 2, 1) + 0.01 * np.eye(2)
    prior = np.log(rng.dirichlet(np.ones(k)))
    one = posterior_arg_max(points, mu, Sigma, prior)
    assert np.array_equal(posterior_arg_max(points, mu, Sigma, prior, parallel=True), one)


@settings(max_examples=150, deadline=None)
@given(st.integers(0, 2**32 - 1), st.integers(1, 25), st.integers(1, 25), st.integers(0, 6), st.booleans())
def test_snap_of_cells_in_the_mask_is_the_transform_answer(seed, h, w, n, inside):
    """Cells already in the mask are returned without the feature transform: the same as reading it."""
    rng = np.random.default_rng(seed)
    mask = rng.random((h, w)) < 0.5
    if not mask.any():
        mask[h // 2, w // 2] = True
    pool = np.argwhere(mask) if inside else np.argwhere(np.ones((h, w), bool))
    cells = pool[rng.integers(0, len(pool), size=n)] + (0 if inside else rng.integers(-2, 3, size=(n, 2)))
    idx = nearest_feature(mask)
    rc = np.clip(cells, 0, np.array(mask.shape) - 1)
    before = np.stack([idx[0][rc[:, 0], rc[:, 1]], idx[1][rc[:, 0], rc[:, 1]]], axis=-1).astype(np.int64)
    got = snap(mask, cells)
    assert got.dtype == np.int64 and got.shape == (n, 2) and np.array_equal(got, before)


def test_snap_of_no_cell_onto_an_empty_mask_is_still_refused():
    with pytest.raises(MapError):
        snap(np.zeros((3, 3), bool), np.empty((0, 2), dtype=np.int64))
