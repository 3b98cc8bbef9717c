"""Synthetic floor plans and teaching walks: geometry checked on the grid itself, determinism, noise, files."""

from __future__ import annotations

import time

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from scipy import ndimage
from scipy.spatial import cKDTree

from spcotmhp.datasets import load_dataset
from spcotmhp.datasets.synthetic import (
    generate_environment,
    generate_floor_plan,
    teaching_walk,
    write_dataset,
)
from spcotmhp.datasets.synthetic_vocab import ALL_WORDS, CORRIDOR, PLACE_VOCABULARY, TEMPLATES
from spcotmhp.errors import DatasetError

INSCRIBED_RADIUS_M = 0.22
CROSS = ndimage.generate_binary_structure(2, 1)


# ------------------------------------------------------------------------------------------------ grid checks
def room_labels(plan) -> np.ndarray:
    """Each cell's room index (its box), -1 outside every box."""
    labels = np.full(plan.map.shape, -1, dtype=np.int64)
    for room in plan.rooms:
        r0, c0, r1, c1 = room.box
        assert (labels[r0:r1, c0:c1] == -1).all(), f"room {room.index} overlaps another room"
        labels[r0:r1, c0:c1] = room.index
    return labels


def grid_adjacency(plan) -> tuple[np.ndarray, list[tuple[int, int]]]:
    """Room adjacency read off the grid alone: boxes touching directly (open boundaries) or through an opening
    (a component of free cells outside every box) that touches exactly two boxes. Also each opening's size
    (thickness across the wall, width along it) in cells."""
    labels = room_labels(plan)
    n = len(plan.rooms)
    adjacency = np.eye(n, dtype=np.int64)
    for a, b in ((labels[:-1], labels[1:]), (labels[:, :-1], labels[:, 1:])):
        touching = (a >= 0) & (b >= 0) & (a != b)
        adjacency[a[touching], b[touching]] = adjacency[b[touching], a[touching]] = 1
    openings, _count = ndimage.label(plan.map.free & (labels < 0), structure=CROSS)
    sizes = []
    for k, window in enumerate(ndimage.find_objects(openings), start=1):
        grown = tuple(slice(max(s.start - 1, 0), s.stop + 1) for s in window)
        cells = openings[grown] == k
        rim = ndimage.binary_dilation(cells, structure=CROSS) & ~cells
        rooms = np.unique(labels[grown][rim])
        rooms = rooms[rooms >= 0]
        assert len(rooms) == 2, f"opening {k} at {window} touches rooms {rooms.tolist()}, not exactly two"
        adjacency[rooms[0], rooms[1]] = adjacency[rooms[1], rooms[0]] = 1
        sizes.append(tuple(sorted(s.stop - s.start for s in window)))
    return adjacency, sizes


def check_plan(plan) -> None:
    """Every structural promise of a floor plan, measured on the occupancy grid."""
    m = plan.map
    data = m.data
    assert data.dtype == np.int8 and set(np.unique(data).tolist()) <= {-1, 0, 100}
    # outside unknown, a closed building: every unknown cell connects to the map border
    assert (data[[0, -1], :] == -1).all() and (data[:, [0, -1]] == -1).all()
    unknown, _ = ndimage.label(data == -1, structure=CROSS)
    assert len(np.unique(unknown[data == -1])) == 1, "unknown pocket inside the building"
    # rooms are free, named from the vocabulary; corridors are named corridor
    labels = room_labels(plan)
    assert (data[labels >= 0] == 0).all()
    assert all(room.name in PLACE_VOCABULARY for room in plan.rooms)
    # doors: what the grid connects is exactly the plan's adjacency; openings 1-2 cells deep, >= 0.9 m wide
    adjacency, sizes = grid_adjacency(plan)
    np.testing.assert_array_equal(adjacency, plan.adjacency)
    assert (plan.adjacency == plan.adjacency.T).all() and (np.diag(plan.adjacency) == 1).all()
    for thickness, width in sizes:
        assert thickness == plan.wall_cells in (1, 2)
        assert width * m.resolution >= 0.9 - 1e-9
    # every room reachable from every other on the free grid, and still so for a robot of inscribed radius
    # 0.22 m (the cells costmap_2d leaves below 253)
    free_parts, _ = ndimage.label(m.free, structure=CROSS)
    assert len(np.unique(free_parts[labels >= 0])) == 1
    clear = ndimage.distance_transform_edt(m.free) * m.resolution > INSCRIBED_RADIUS_M
    clear_parts, _ = ndimage.label(clear, structure=CROSS)
    centres = [((r.box[0] + r.box[2]) // 2, (r.box[1] + r.box[3]) // 2) for r in plan.rooms]
    reached = {int(clear_parts[c]) for c in centres}
    assert len(reached) == 1 and 0 not in reached
    # rooms list their doors' cells
    for d in plan.doors:
        for r in d.rooms:
            assert d.cell in plan.rooms[r].doors


def min_clearance(m, xy: np.ndarray) -> np.ndarray:
    """A lower bound of each point's distance to the nearest non-free cell (the cell's square, not its centre)."""
    blocked = m.cell_to_world(np.argwhere(m.data != 0))
    distance, _ = cKDTree(blocked).query(xy)
    return distance - m.resolution / np.sqrt(2)


def check_walk(plan, data, events_per_room: int) -> None:
    m = plan.map
    trajectory, steps = data.trajectory, data.event_steps
    assert trajectory.shape[1] == 2 and len(steps) == data.n_events == len(data.tokens)
    assert (np.diff(steps) >= 0).all() and steps[0] >= 0 and steps[-1] < len(trajectory)
    np.testing.assert_array_equal(data.positions, trajectory[steps])
    assert np.hypot(*np.diff(trajectory, axis=0).T).max() <= 0.15
    assert min_clearance(m, trajectory).min() >= 0.25
    assert min_clearance(m, data.positions).min() >= 0.25
    # each event lies in the box of its true room; every room is taught events_per_room times
    labels = room_labels(plan)
    cells = m.world_to_cell(data.positions)
    np.testing.assert_array_equal(labels[cells[:, 0], cells[:, 1]], data.truth_place)
    np.testing.assert_array_equal(np.bincount(data.truth_place, minlength=len(plan.rooms)), events_per_room)
    names = plan.distinct_names
    assert [names[c] for c in data.truth_concept] == [plan.rooms[p].name for p in data.truth_place]
    # the walk moves only between adjacent rooms (through doors)
    cells = m.world_to_cell(trajectory)
    visited = labels[cells[:, 0], cells[:, 1]]
    visited = visited[visited >= 0]
    changes = visited[np.flatnonzero(np.diff(visited)) + 1]
    sequence = np.concatenate([visited[:1], changes])
    assert (plan.adjacency[sequence[:-1], sequence[1:]] == 1).all()
    assert set(sequence.tolist()) == set(range(len(plan.rooms)))
    np.testing.assert_array_equal(data.adjacency, plan.adjacency)
    assert data.place_names == plan.names and data.lang == "en" and data.features is None


# ---------------------------------------------------------------------------------------------------- sizes
@pytest.fixture(scope="module")
def big_office():
    start = time.perf_counter()
    plan = generate_floor_plan("office", n_rooms=60, size=1000, seed=0)
    built = time.perf_counter()
    data = teaching_walk(plan, seed=0)
    print(
        f"\n1000x1000 office, 60 places: plan {built - start:.3f} s, walk {time.perf_counter() - built:.3f} s, "
        f"{len(data.trajectory)} poses, {data.n_events} events"
    )
    return plan, data


def test_three_room_flat_on_60x60_cells():
    plan = generate_floor_plan("flat", n_rooms=3, size=60, seed=0)
    assert plan.map.shape == (60, 60) and len(plan.rooms) == 3 and plan.kind == "flat"
    assert plan.map.resolution == 0.1
    assert "living" in plan.names
    check_plan(plan)
    check_walk(plan, teaching_walk(plan, seed=0), 15)


def test_office_of_60_places_on_1000x1000_cells(big_office):
    plan, data = big_office
    assert plan.map.shape == (1000, 1000) and len(plan.rooms) == 60
    names = plan.names
    assert names.count(CORRIDOR) >= 3 and names.count("office") >= 10
    assert {"meeting", "printer", "lab"} <= set(names)
    check_plan(plan)
    check_walk(plan, data, 15)


@pytest.mark.parametrize("kind, expected", [("flat", 3), ("house", 11), ("office", 20)])
def test_default_room_counts(kind, expected):
    plan = generate_floor_plan(kind, seed=1)
    assert len(plan.rooms) == expected == plan.adjacency.shape[0]
    check_plan(plan)


def test_house_resembles_a_3ldk_home():
    plan = generate_floor_plan("house", seed=0)
    names = plan.names
    assert names[0] == "entrance" and names.count(CORRIDOR) == 2 and names.count("bedroom") >= 2
    assert {"living", "kitchen", "bath", "toilet"} <= set(names)
    corridors = [r.index for r in plan.rooms if r.is_corridor]
    assert all(plan.adjacency[r.index, corridors + [0]].any() for r in plan.rooms)  # every room off the hall


@pytest.mark.parametrize("kind", ["flat", "house", "office"])
@pytest.mark.parametrize("seed", [0, 1, 2, 3])
def test_plans_and_walks_hold_their_promises(kind, seed):
    plan = generate_floor_plan(kind, seed=seed)
    check_plan(plan)
    check_walk(plan, teaching_walk(plan, events_per_room=4, seed=seed), 4)


@pytest.mark.parametrize("kind", ["flat", "house", "office"])
def test_half_resolution_maps(kind):
    plan = generate_floor_plan(kind, resolution=0.05, seed=5, origin=(-3.5, 2.25))
    assert plan.map.resolution == 0.05 and plan.map.origin == (-3.5, 2.25, 0.0)
    assert all(d.hi - d.lo >= 18 for d in plan.doors if d.w1 > d.w0)  # >= 0.9 m at 0.05 m per cell
    check_plan(plan)
    check_walk(plan, teaching_walk(plan, events_per_room=3, seed=5), 3)


@settings(max_examples=30, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(
    kind=st.sampled_from(["flat", "house", "office"]),
    n=st.integers(0, 12),
    seed=st.integers(0, 10_000),
    wall=st.sampled_from([None, 1, 2]),
)
def test_any_seed_and_room_count_at_the_default_size(kind, n, seed, wall):
    n_rooms = {"flat": 1 + n, "house": 4 + n, "office": 3 + 4 * n}[kind]
    plan = generate_floor_plan(kind, n_rooms=n_rooms, seed=seed, wall_cells=wall)
    assert len(plan.rooms) == n_rooms and (wall is None or plan.wall_cells == wall)
    check_plan(plan)
    check_walk(plan, teaching_walk(plan, events_per_room=2, seed=seed), 2)


# ------------------------------------------------------------------------------------------------ determinism
def assert_same(a, b) -> None:
    np.testing.assert_array_equal(a.map.data, b.map.data)
    assert (a.map.resolution, a.map.origin) == (b.map.resolution, b.map.origin)
    for name in ("positions", "trajectory", "event_steps", "truth_place", "truth_concept", "adjacency"):
        np.testing.assert_array_equal(getattr(a, name), getattr(b, name), err_msg=name)
    assert a.tokens == b.tokens and a.place_names == b.place_names and a.name == b.name


@pytest.mark.parametrize("kind", ["flat", "house", "office"])
def test_same_seed_gives_identical_output(kind):
    one = generate_environment(kind, seed=7, word_noise=0.2, insert_noise=0.2)
    assert_same(one, generate_environment(kind, seed=7, word_noise=0.2, insert_noise=0.2))
    other = generate_environment(kind, seed=8, word_noise=0.2, insert_noise=0.2)
    assert not np.array_equal(one.map.data, other.map.data) or one.tokens != other.tokens
    assert one.name == f"synthetic-{kind}-7"


def test_a_generator_as_seed_gives_the_same_as_its_seed():
    a = generate_floor_plan("house", seed=np.random.default_rng(4))
    b = generate_floor_plan("house", seed=4)
    np.testing.assert_array_equal(a.map.data, b.map.data)
    assert a.names == b.names and a.doors == b.doors


# ------------------------------------------------------------------------------------------------ utterances
def test_no_noise_names_the_room_in_every_utterance(big_office):
    plan, data = big_office
    templates = {tuple(t.split()) for t in TEMPLATES}
    for tokens, place in zip(data.tokens, data.truth_place, strict=False):
        name = plan.rooms[place].name
        assert name in tokens
        assert tuple("{}" if w == name else w for w in tokens) in templates
    # function words are shared across places with different names
    users_of_the = {plan.rooms[p].name for t, p in zip(data.tokens, data.truth_place, strict=False) if "the" in t}
    assert len(users_of_the) >= 5
    assert len({" ".join(t) for t in data.tokens}) >= len(TEMPLATES)


def test_word_noise_replaces_about_that_share_of_place_words(big_office):
    plan, clean = big_office
    changed = {}
    for level in (0.3, 0.5):
        data = teaching_walk(plan, seed=0, word_noise=level)
        np.testing.assert_array_equal(data.trajectory, clean.trajectory)
        wrong = np.array([plan.rooms[p].name not in t for t, p in zip(data.tokens, data.truth_place, strict=False)])
        changed[level] = set(np.flatnonzero(wrong).tolist())
        # 900 events: the share lies within 0.05 of the level (more than 3 standard deviations)
        assert abs(wrong.mean() - level) < 0.05, (level, wrong.mean())
        for k in changed[level]:  # only the place word changed, into another place name
            diff = [(a, b) for a, b in zip(data.tokens[k], clean.tokens[k], strict=False) if a != b]
            assert len(diff) == 1 and diff[0][0] in PLACE_VOCABULARY and diff[0][0] != diff[0][1]
    assert changed[0.3] <= changed[0.5]  # one seed: a higher level only changes more words


def test_insert_noise_adds_one_word():
    plan = generate_floor_plan("house", seed=2)
    clean = teaching_walk(plan, seed=2)
    noisy = teaching_walk(plan, seed=2, insert_noise=0.4)
    grown = np.array([len(a) - len(b) for a, b in zip(noisy.tokens, clean.tokens, strict=False)])
    assert set(grown.tolist()) <= {0, 1} and 0.25 < grown.mean() < 0.55
    assert all(w in ALL_WORDS for t in noisy.tokens for w in t)


# ------------------------------------------------------------------------------------------------ files
@pytest.mark.parametrize("kind", ["flat", "house"])
def test_written_folder_loads_back_equal(tmp_path, kind):
    data = generate_environment(kind, seed=3, word_noise=0.1, insert_noise=0.1)
    folder = write_dataset(data, tmp_path / "env")
    assert folder == tmp_path / "env"
    assert {p.name for p in folder.iterdir()} == {
        "map.yaml",
        "map.pgm",
        "teaching.csv",
        "truth.csv",
        "places.csv",
        "adjacency.csv",
        "trajectory.csv",
    }
    header = (folder / "teaching.csv").read_text().splitlines()[0]
    assert header == "event,x,y,words_ja,words_en,step"
    assert (folder / "trajectory.csv").read_text().startswith("step,x,y\n0,")
    loaded = load_dataset(folder)
    loaded.name = data.name
    assert_same(data, loaded)
    assert load_dataset(folder, lang="ja").tokens == data.tokens  # words_ja holds the same words


@pytest.mark.filterwarnings("ignore::spcotmhp.datasets.DatasetWarning")  # 3LDK_01 has events in walls
def test_written_real_dataset_loads_back_equal(tmp_path):
    from spcotmhp.datasets import load_bundled

    real = load_bundled("3LDK_01")
    loaded = load_dataset(write_dataset(real, tmp_path / "copy"))
    np.testing.assert_array_equal(loaded.positions, real.positions)
    np.testing.assert_array_equal(loaded.adjacency, real.adjacency)
    np.testing.assert_array_equal(loaded.map.data, real.map.data)
    assert loaded.tokens == real.tokens and loaded.place_names == real.place_names
    assert loaded.trajectory is None and not (tmp_path / "copy" / "trajectory.csv").exists()


def test_write_dataset_refuses_a_file(tmp_path):
    target = tmp_path / "taken"
    target.write_text("x")
    with pytest.raises(DatasetError, match="exists and is not a folder"):
        write_dataset(generate_environment("flat"), target)


def test_write_dataset_to_a_folder_that_cannot_be_made(tmp_path):
    with pytest.raises(DatasetError, match=r"cannot write the dataset to /proc/nope/d: "):
        write_dataset(generate_environment("flat"), "/proc/nope/d")
    # a folder holding files that are not a dataset's is never replaced, and is left as it was
    (tmp_path / "d").mkdir()
    (tmp_path / "d" / "notes.txt").write_text("mine")
    with pytest.raises(
        DatasetError,
        match=r"cannot write a dataset to .*/d: the folder holds files that are not a "
        r"dataset's \(notes.txt\)",
    ):
        write_dataset(generate_environment("flat"), tmp_path / "d")
    assert [p.name for p in (tmp_path / "d").iterdir()] == ["notes.txt"]


def test_write_dataset_replaces_a_dataset_whole_and_only_when_asked(tmp_path):
    folder = write_dataset(generate_environment("flat", seed=1), tmp_path / "d")
    (folder / "costmap_ros.csv").write_text("0\n")  # a stale extra of the old dataset
    with pytest.raises(DatasetError, match=r"already holds a dataset; give --overwrite"):
        write_dataset(generate_environment("flat", seed=2), folder, overwrite=False)
    write_dataset(generate_environment("flat", seed=2), folder, overwrite=True)
    assert not (folder / "costmap_ros.csv").exists()
    assert load_dataset(folder).n_events == generate_environment("flat", seed=2).n_events
    assert not [p for p in tmp_path.iterdir() if p.name.startswith(".")]  # no staging folder left


def test_oversized_settings_are_refused_before_the_map_is_drawn(monkeypatch):
    """Audit item 4: a map side, room count or event count over its bound (spcotmhp/limits.py) is refused
    before anything of its size is allocated (the rasteriser is never reached)."""
    from spcotmhp.datasets import synthetic_plan

    def never(*args, **kwargs):
        raise AssertionError("the map was allocated")

    monkeypatch.setattr(synthetic_plan, "_rasterise", never)
    for kwargs in ({"size": 100_000}, {"size": 4500}, {"events_per_room": 10**8}, {"n_rooms": 10**6}):
        with pytest.raises(DatasetError):
            generate_environment("office", **kwargs)


@pytest.mark.parametrize(
    "args, message",
    [
        (["--size", "100000"], "error: a 100000 x 100000 map (size 100000) has 10000000000 pixels, over the cap"),
        (["--size", "4500"], "error: a 4500 x 4500 map (size 4500) has 20250000 pixels, over the cap of 16000000"),
        (["--events-per-room", "100000000"], "error: Invalid value for '--events-per-room'"),
        (["--events-per-room", "100000"], "error: events_per_room (60 rooms x events_per_room is at most 200000"),
        (["--rooms", "100000"], "error: Invalid value for '--rooms'"),
    ],
)
def test_synth_command_bounds(tmp_path, args, message):
    import subprocess
    import sys
    from pathlib import Path

    exe = Path(sys.executable).parent / "spcotmhp"
    cmd = [str(exe), "synth", "office", "--rooms", "60", "--out", str(tmp_path / "o"), *args]
    res = subprocess.run(cmd, capture_output=True, text=True, timeout=120, check=False)
    assert res.returncode == 2 and res.stderr.startswith(message), res.stderr
    assert len(res.stderr.strip().splitlines()) == 1 and not (tmp_path / "o").exists()


def test_synth_command_reports_an_unwritable_folder_in_one_line():
    import subprocess
    import sys
    from pathlib import Path

    exe = Path(sys.executable).parent / "spcotmhp"
    res = subprocess.run(
        [str(exe), "synth", "flat", "--out", "/proc/nope/d"],
        capture_output=True,
        text=True,
        timeout=120,
        check=False,
    )
    assert res.returncode == 2
    assert res.stderr.startswith("error: cannot write the dataset to /proc/nope/d: ") and "Traceback" not in res.stderr


# ------------------------------------------------------------------------------------------------ bad input
@pytest.mark.parametrize(
    "kwargs, message",
    [
        ({"kind": "castle"}, r"unknown floor plan kind 'castle'; accepted: flat, house, office"),
        ({"kind": "house", "n_rooms": 3}, r"n_rooms must be an integer >= 4 for a house, got 3"),
        ({"kind": "flat", "n_rooms": 2.5}, r"n_rooms must be an integer >= 1 for a flat, got 2.5"),
        ({"kind": "flat", "n_rooms": 12, "size": 60}, r"flat: a .* area cannot hold .* rooms .* larger size"),
        ({"kind": "office", "n_rooms": 200, "size": 300}, r"office: .* do not fit"),
        (
            {"kind": "house", "size": 40},
            r"house: .* interior rows cannot hold a corridor and two rows of rooms",
        ),
        ({"kind": "flat", "size": 10}, r"size \(10, 10\) cells is too small for any flat"),
        ({"kind": "flat", "size": (60, 0)}, r"size must be a positive int or \(height, width\) in cells"),
        ({"door_m": 0.5}, r"door width 0.5 m is below 0.6 m"),
        ({"resolution": 0.5}, r"resolution 0.5 m per cell is outside 0.01 .. 0.2"),
        ({"wall_cells": 3}, r"wall_cells must be 1 or 2, got 3"),
        ({"kind": "office", "n_rooms": 1001}, r"n_rooms \(office\) must be an integer in \[\d+, 1000\], got 1001"),
        (
            {"kind": "flat", "size": 100_000},
            r"a 100000 x 100000 map \(size 100000\) has 10000000000 pixels, over the cap of 16000000 of the map loader",
        ),
        ({"kind": "flat", "size": (4000, 4001)}, r"a 4000 x 4001 map \(size \(4000, 4001\)\) has 16004000 pixels"),
        ({"kind": "flat", "size": (10, 10_001)}, r"a 10 x 10001 map is longer than 1000 times its width"),
        (
            {"kind": "office", "n_rooms": 1000},
            r"map \(1000 places of a office at 0.1 m per cell\) has \d+ pixels, over",
        ),
    ],
)
def test_bad_plan_arguments(kwargs, message):
    with pytest.raises(DatasetError, match=message):
        generate_floor_plan(**kwargs)


@pytest.mark.parametrize(
    "kwargs, message",
    [
        ({"lang": "ja"}, r"English only; got lang='ja'"),
        ({"events_per_room": 0}, r"events_per_room .*must be an integer in \[1, \d+\], got 0"),
        ({"events_per_room": 10**8}, r"events_per_room \(\d+ rooms x events_per_room is at most 200000 events\)"),
        ({"step_m": 0.0}, r"step_m must be in \(0, 0.5\] metres, got 0.0"),
        ({"word_noise": 1.5}, r"word_noise is a probability in \[0, 1\], got 1.5"),
        ({"insert_noise": -0.1}, r"insert_noise is a probability in \[0, 1\], got -0.1"),
        (
            {"clearance_m": 0.6},
            r"clearance_m must be in \[0.25, 0.5\] m \(half the narrowest door\), got 0.6",
        ),
    ],
)
def test_bad_walk_arguments(kwargs, message):
    plan = generate_floor_plan("flat", seed=0)
    with pytest.raises(DatasetError, match=message):
        teaching_walk(plan, **kwargs)


def test_walk_reports_rooms_without_a_door():
    plan = generate_floor_plan("flat", n_rooms=3, seed=0)
    plan.doors = []
    missing = sorted(set(range(3)) - {plan.names.index("living")})  # the walk starts in the living room
    with pytest.raises(DatasetError, match=rf"rooms \[{missing[0]}, {missing[1]}\] cannot be reached through"):
        teaching_walk(plan, seed=0)
