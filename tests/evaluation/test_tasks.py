"""Experiment I task generation: a hand-made corridor home (every l worked out by hand) and the bundled homes."""

import numpy as np
import pytest

from spcotmhp.datasets import load_bundled
from spcotmhp.datasets.dataset import Dataset
from spcotmhp.errors import DatasetError
from spcotmhp.evaluation.tasks import build_places, make_tasks, names_from_words, nearest_free_cell, subset
from spcotmhp.metric.maps import OccupancyMap


def corridor_home(**overrides) -> Dataset:
    """A 3 x 13 all-free grid at 1 m per cell. Places along row 1 (cell centres at x = col + 0.5):
    0 "a" at cols 0-1, 1 "bed" at cols 5-6, 2 "bed" at cols 10-11, 3 "hall" at col 9 (rows 0-2).
    Adjacency is the chain 0 - 1 - 3 - 2."""
    positions = np.array(
        [
            [0.5, 1.5],
            [1.5, 1.5],  # place 0, mean (1.0, 1.5) -> start cell (1, 1)
            [5.5, 1.5],
            [6.5, 1.5],  # place 1, mean (6.0, 1.5) -> (1, 6)
            [10.5, 1.5],
            [11.5, 1.5],  # place 2, mean (11.0, 1.5) -> (1, 11)
            [9.5, 0.5],
            [9.5, 2.5],  # place 3, mean (9.5, 1.5) -> (1, 9)
        ]
    )
    adjacency = np.eye(4, dtype=int)
    for a, b in [(0, 1), (1, 3), (3, 2)]:
        adjacency[a, b] = adjacency[b, a] = 1
    kwargs = {
        "name": "corridor",
        "map": OccupancyMap(np.zeros((3, 13), np.int8), resolution=1.0),
        "positions": positions,
        "tokens": [["a"], ["a"], ["bed"], ["bed"], ["bed"], ["bed"], ["hall"], ["hall"]],
        "truth_place": np.array([0, 0, 1, 1, 2, 2, 3, 3]),
        "adjacency": adjacency,
        "place_names": ["a", "bed", "bed", "hall"],
    }
    kwargs.update(overrides)
    return Dataset(**kwargs)


def by_places(home_tasks):
    return {(t.start_place, t.waypoint_place, t.goal_place): t for t in home_tasks.tasks}


def test_places_regions_and_starts():
    ds = corridor_home()
    places = build_places(ds)
    assert [p.name for p in places] == ["a", "bed", "bed", "hall"]
    assert [p.cell for p in places] == [(1, 1), (1, 6), (1, 11), (1, 9)]
    assert places[3].box.contains(np.array([[9.5, 2.55], [9.5, 2.65]])).tolist() == [True, False]
    # the region is the box (x 9.4..9.6, y 0.4..2.6) grown by the robot's 0.22 m: 2.65 is 0.05 m above it, 2.85
    # 0.25 m, and the corner point (9.75, 2.75) is sqrt(0.15^2 + 0.15^2) = 0.21 m from the box's corner
    assert places[3].region.contains(np.array([[9.5, 2.65], [9.5, 2.85], [9.75, 2.75], [9.77, 2.77]])).tolist() == [
        True,
        False,
        True,
        False,
    ]
    # a mean inside a wall moves to the nearest free cell
    data = np.zeros((3, 13), np.int8)
    data[:, 5:7] = 100  # (1, 6) is blocked; (1, 7) is 1 cell away, (1, 4) 2 cells
    assert nearest_free_cell(corridor_home(map=OccupancyMap(data, 1.0)), np.array([6.6, 1.5])) == (1, 7)


def test_basic_tasks_by_hand():
    ht = make_tasks(corridor_home(), "basic", corridor_home().adjacency)
    tasks = by_places(ht)
    # the non-adjacent ordered pairs, but for those whose start is already a "bed" (l = 0: counted, left out)
    assert sorted((i, j) for i, _, j in tasks) == [(0, 2), (0, 3), (2, 0), (3, 0)]
    assert ht.zero_length == [
        "start 1 -> bed (2): the start is a goal instance",
        "start 2 -> bed (1): the start is a goal instance",
    ]
    # (i, j): (l, the goal place where the shortest reference path ends), to the places' positions at cols 1, 6,
    # 11, 9; each position lies in its place's region (the box + 0.22 m), so the footprint rule's targets are the
    # positions too and both rules give the same l
    expect = {
        (0, 2): (5.0, 1),  # "bed" = places 1 (5 m away) and 2 (10 m)
        (0, 3): (8.0, 3),
        (2, 0): (10.0, 0),
        (3, 0): (8.0, 0),
    }
    for (i, j), (l, goal) in expect.items():
        t = tasks[(i, None, j)]
        assert t.strict_l == pytest.approx(l) and t.l == pytest.approx(l), (i, j)
        assert t.goal_places[t.strict_closest_goal] == t.goal_places[t.closest_goal] == goal, (i, j)
        assert t.closest_goal_via == t.closest_goal and t.strict_closest_goal_via == t.strict_closest_goal
        assert not t.start_in_waypoint
        assert t.goal_words == [t.goal_name]
        assert t.waypoint_place is None and t.waypoint_words == []
    assert tasks[(0, None, 2)].goal_places == (1, 2)
    assert tasks[(0, None, 2)].start_xy == (1.5, 1.5)
    assert ht.no_safe_path == [] and ht.dropped == []


def test_advanced_tasks_by_hand():
    ht = make_tasks(corridor_home(), "advanced", corridor_home().adjacency)
    tasks = by_places(ht)
    # (i, h, j): (l, goal place where the shortest path via the waypoint ends, closest goal from the start) with
    # l = min over instances w, g of d(start, w) + d(w, g) between positions (the footprint targets here too)
    expect = {
        (0, 3, 2): (10.0, 2, 1),  # to the hall 8, then the bed beyond it 2 (from the start the near bed is closest)
        (0, 1, 3): (8.0, 3, 3),
        (0, 2, 3): (8.0, 3, 3),  # "bed" = either bedroom: via place 1, 5 + 3
        (1, 0, 2): (10.0, 1, 1),  # out to "a" 5 and back to the first bedroom 5
        (1, 3, 2): (5.0, 2, 1),  # hall 3, then the far bedroom 2; from the start, its own bedroom
        (2, 1, 0): (10.0, 0, 0),
        (2, 3, 0): (10.0, 0, 0),
        (2, 0, 1): (15.0, 1, 2),  # "a" 10, back to the near bedroom 5
        (2, 3, 1): (4.0, 2, 2),  # out to the hall and back into the same bedroom
        (3, 1, 0): (8.0, 0, 0),
        (3, 2, 0): (8.0, 0, 0),
    }
    assert set(tasks) == set(expect)  # h never in {i, j}; the waypoint's name never the goal's
    for key, (l, via, goal) in expect.items():
        t = tasks[key]
        assert (t.strict_l, t.l) == (pytest.approx(l), pytest.approx(l)), key
        assert t.goal_places[t.strict_closest_goal_via] == t.goal_places[t.closest_goal_via] == via, key
        assert t.goal_places[t.strict_closest_goal] == t.goal_places[t.closest_goal] == goal, key
        assert t.all_words == t.waypoint_words + t.goal_words
    assert tasks[(0, 1, 3)].waypoint_places == (1, 2)
    # the start of place 2 lies in a "bed" region: via "bed" it is set apart; via the hall it is not
    assert tasks[(2, 1, 0)].start_in_waypoint and not tasks[(2, 3, 0)].start_in_waypoint
    assert [t.index for t in ht.tasks] == list(range(len(ht.tasks)))


def test_unreachable_goal_is_dropped_with_reason():
    data = np.zeros((3, 13), np.int8)
    data[:, 8] = 100  # a wall cuts the hall and the far bedroom off
    ht = make_tasks(corridor_home(map=OccupancyMap(data, 1.0)), "basic", corridor_home().adjacency)
    assert (0, None, 3) not in by_places(ht)
    assert ht.dropped == [
        "start 0 -> hall (3): no free-space path reaches a goal-named place",
        "start 2 -> a (0): no free-space path reaches a goal-named place",
        "start 3 -> a (0): no free-space path reaches a goal-named place",
    ]
    assert by_places(ht)[(0, None, 2)].strict_l == pytest.approx(5.0)  # the near bed still counts


def test_bad_inputs():
    with pytest.raises(DatasetError, match="evaluation needs truth.csv"):
        build_places(corridor_home(truth_place=None))
    with pytest.raises(DatasetError, match=r"adjacency is \(3, 3\) but truth.csv has 4 places"):
        make_tasks(corridor_home(), "basic", np.eye(3))
    with pytest.raises(DatasetError, match=r"place\(s\) \[1\] have no teaching event"):
        build_places(corridor_home(truth_place=np.array([0, 0, 2, 2, 2, 2, 3, 3])))
    with pytest.raises(DatasetError, match="places.csv names 2 places but truth.csv uses 4"):
        build_places(corridor_home(place_names=["a", "bed"]))
    with pytest.raises(ValueError, match="task kind must be one of"):
        make_tasks(corridor_home(), "expert", corridor_home().adjacency)


def test_names_from_words_prefers_specific_frequent_words():
    tokens = [["this", "is", "kitchen"], ["kitchen"], ["this", "is", "bath"], ["this", "bath"], ["this"]]
    truth = np.array([0, 0, 1, 1, 1])
    # totals: this 4, is 2, kitchen 2, bath 2.  Place 0: kitchen 2^2/2 = 2 > is 1/2 > this 1/4.
    # Place 1: this 3^2/4 = 2.25 > bath 2^2/2 = 2 (a word that dominates one place can win) ...
    assert names_from_words(tokens, truth) == ["kitchen", "this"]
    # ... and one more "bath" there makes it bath 3^2/3 = 3 > this 2.25
    assert names_from_words(tokens + [["bath"]], np.append(truth, 1)) == ["kitchen", "bath"]


def test_subset_is_seeded_and_ordered():
    tasks = make_tasks(corridor_home(), "advanced", corridor_home().adjacency).tasks
    a, b = subset(tasks, 4, seed=3), subset(tasks, 4, seed=3)
    assert [t.index for t in a] == [t.index for t in b]
    assert [t.index for t in a] == sorted(t.index for t in a) and len(a) == 4
    assert subset(tasks, None, 0) == tasks and subset(tasks, 100, 0) == tasks
    with pytest.raises(ValueError, match="max_tasks must be >= 1"):
        subset(tasks, 0, 0)


@pytest.mark.parametrize("home,n_basic", [("3LDK_01", 76), ("3LDK_05", 84), ("3LDK_06", 88)])
def test_bundled_homes_follow_the_protocol(home, n_basic):
    ds = load_bundled(home)
    basic = make_tasks(ds, "basic", ds.adjacency)
    # 11 places: 110 ordered pairs minus the adjacent ones (off-diagonal ones of adjacency.csv), of which the
    # pairs of two places of one name (bedroom to bedroom: l = 0) are counted and left out
    names = [p.name for p in basic.places]
    same = sum(1 for i in range(11) for j in range(11) if i != j and names[i] == names[j] and not ds.adjacency[i, j])
    assert len(basic.tasks) + len(basic.zero_length) == 110 - int(ds.adjacency.sum() - 11) == n_basic
    assert len(basic.zero_length) == same > 0
    assert not basic.dropped and not basic.no_safe_path
    adv = make_tasks(ds, "advanced", ds.adjacency, places=basic.places)
    for t in adv.tasks:
        assert t.start_place != t.goal_place and not ds.adjacency[t.start_place, t.goal_place]
        assert t.waypoint_place not in (t.start_place, t.goal_place)
        assert names[t.waypoint_place] != names[t.goal_place]
        assert ds.map.free[t.start_cell] and np.isfinite(t.l) and t.l > 0 and t.strict_l > 0
        assert t.start_cell == basic.places[t.start_place].cell
        start_in = any(basic.places[k].region.contains(np.array(t.start_xy)) for k in t.waypoint_places)
        assert t.start_in_waypoint == start_in
    per_pair = {
        (i, j): sum(1 for h in range(11) if h not in (i, j) and names[h] != names[j])
        for i in range(11)
        for j in range(11)
        if i != j and not ds.adjacency[i, j]
    }
    assert len(adv.tasks) == sum(per_pair.values())


def test_a_mean_inside_a_pocket_puts_the_position_in_the_region_most_of_the_teaching_lies_in():
    """A ring of furniture around cell (3, 6) holds the mean of place 0's teaching: the robot cell nearest the mean
    is that pocket, cut off from the room; four of the five teaching points' nearest robot cells are in the room
    around it, so the position is the room's cell nearest the mean (one of four at distance 2), not the pocket."""
    data = np.zeros((7, 13), np.int8)
    data[2, 5:8] = data[4, 5:8] = 100
    data[3, 5] = data[3, 7] = 100
    positions = np.array([[6.5, 1.5], [6.5, 5.5], [4.5, 3.5], [8.5, 3.5], [6.5, 3.5], [11.5, 3.5], [12.5, 3.5]])
    ds = corridor_home(
        map=OccupancyMap(data, 1.0),
        positions=positions,
        tokens=[["living"]] * 5 + [["hall"]] * 2,
        truth_place=np.array([0, 0, 0, 0, 0, 1, 1]),
        adjacency=np.eye(2, dtype=int),
        place_names=["living", "hall"],
    )
    places = build_places(ds)
    assert nearest_free_cell(ds, places[0].mean) == (3, 6)  # the pocket
    assert places[0].cell in {(1, 6), (5, 6), (3, 4), (3, 8)}
    assert places[1].cell == nearest_free_cell(ds, places[1].mean) == (3, 12)
