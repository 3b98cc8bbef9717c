"""Planning in a building (the stitched Eq. 28 search): goals on a named floor end there, in the closest instance
(an independent geodesic oracle, spcotmhp/evaluation/building_battery.py); shared names pick the closest over all floors
counting the connectors' costs; segments join at the connectors; floor words; refusals."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

from spcotmhp.building.learn import learn_building, teach_building
from spcotmhp.building.planner import BuildingPlanner
from spcotmhp.building.synthetic import generate_building, lift_only_floor
from spcotmhp.errors import FloorUnreachable, MalformedInstruction, PlaceNotOnFloor, UnknownFloor
from spcotmhp.evaluation.battery import CLOSEST_TOLERANCE_M
from spcotmhp.evaluation.building_battery import BuildingOracle


@pytest.fixture(autouse=True)
def _quiet():
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        yield


@pytest.fixture(scope="module")
def building():
    return generate_building(3, seed=6, n_rooms=5, events_per_room=8)


@pytest.fixture(scope="module")
def bm(building):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return learn_building(building)


@pytest.fixture(scope="module")
def planner(bm):
    return BuildingPlanner(bm)


@pytest.fixture(scope="module")
def oracle(building):
    return BuildingOracle(building)


def starts(oracle, floor):
    """A start at every truth place's position of ``floor``."""
    d = oracle.building.floors[floor]
    return [tuple(d.map.cell_to_world(np.array(p.cell))) for p in oracle.places[floor]]


def check_closest(oracle, plan, floor, xy, name, goal_floor):
    """The plan ends on ``goal_floor`` (None: any) inside a truth instance of ``name`` whose route is within the
    battery's tolerance of the shortest route to an instance there."""
    routes = oracle.routes(floor, xy)
    allowed = [fg for fg in oracle.named(name) if goal_floor is None or fg[0] == goal_floor]
    best = min(routes[fg] for fg in allowed)
    end_floor = plan.segments[-1].floor
    inside = [(end_floor, g) for g in oracle.ends_in(end_floor, plan.segments[-1].path[-1])]
    hit = [fg for fg in inside if fg in allowed]
    assert hit, f"{name} from floor {floor} {xy}: ends on floor {end_floor} in {inside}, allowed {allowed}"
    assert min(routes[fg] for fg in hit) <= best + CLOSEST_TOLERANCE_M, (name, floor, xy, routes, hit)


def test_goal_on_each_floor_ends_there_in_the_closest(planner, oracle, bm):
    for f0 in bm.indices:
        for xy in starts(oracle, f0)[:3]:
            for name in ("kitchen", "bedroom"):
                for goal_floor in bm.indices:
                    plan = planner.plan(f"go to the {name}", xy, f0, goal_floor=goal_floor)
                    assert plan.segments[-1].floor == goal_floor
                    check_closest(oracle, plan, f0, xy, name, goal_floor)


def test_shared_name_picks_the_closest_over_all_floors(planner, oracle, bm):
    for f0 in bm.indices:
        for xy in starts(oracle, f0):
            for name in ("kitchen", "bedroom", "living"):
                check_closest(oracle, planner.plan(f"go to the {name}", xy, f0), f0, xy, name, None)


def test_segments_join_at_the_connectors(planner, oracle, bm):
    lift_only = lift_only_floor(bm.spec)
    other = next(f for f in bm.indices if f != lift_only)
    plan = planner.plan({"goal": {"words": "bedroom", "floor": lift_only}}, starts(oracle, other)[0], other)
    assert [s.floor for s in plan.segments][0] == other and plan.segments[-1].floor == lift_only
    assert plan.rides[-1].kind == "lift"  # only the lift reaches that floor
    res = bm.layout.resolution
    for seg, ride in zip(plan.segments, plan.rides, strict=False):
        assert np.hypot(*(seg.path[-1] - np.array(ride.board[1]))) <= res
    for ride, seg in zip(plan.rides, plan.segments[1:], strict=True):
        assert ride.leave[0] == seg.floor and np.hypot(*(seg.path[0] - np.array(ride.leave[1]))) <= res
    for seg in plan.segments:
        occ = bm.floor_model(seg.floor).require_map()
        assert (occ.data[seg.cells[:, 0], seg.cells[:, 1]] == 0).all()
        assert (np.abs(np.diff(seg.cells, axis=0)).max(axis=1) <= 1).all()
    assert plan.route_m == pytest.approx(plan.length_m + sum(r.cost_m for r in plan.rides))
    text = plan.explanation
    assert f"to floor {lift_only}" in text and "lift 'lift'" in text
    d = plan.to_dict()
    assert [s["floor"] for s in d["segments"]] == [s.floor for s in plan.segments]
    assert d["segments"][-1]["path"][-1] == pytest.approx(plan.segments[-1].path[-1].tolist(), abs=1e-4)


def test_waypoints_and_avoidance_on_other_floors(planner, oracle, bm):
    xy = starts(oracle, 1)[0]
    plan = planner.plan({"goal": {"words": "bedroom", "floor": 3}, "waypoints": [{"words": "kitchen", "floor": 2}]},
                        xy, 1)  # fmt: skip
    floors = [s.floor for s in plan.segments]
    assert floors[-1] == 3 and 2 in floors
    k2 = [p for f, p in plan.places if f == 2 and p.role == "waypoint"]
    assert len(k2) == 1 and "kitchen" in k2[0].label
    kitchen2 = [g for g in range(len(oracle.places[2])) if oracle.places[2][g].name == "kitchen"]
    seg2 = next(s for s in plan.segments if s.floor == 2)
    assert any(oracle.places[2][g].region.contains(seg2.path).any() for g in kitchen2)
    avoid = planner.plan({"goal": {"words": "kitchen", "floor": 2}, "avoid": [{"words": "corridor", "floor": 2}]},
                         xy, 1)  # fmt: skip
    seg2 = next(s for s in avoid.segments if s.floor == 2)
    names = planner.floors[2].names
    corridors = [k for k in np.flatnonzero(bm.floor_places(2)) if names[k] == "corridor"]
    graph = planner.floors[2].graph
    crop = graph.to_crop(seg2.cells)
    assert corridors and not np.isin(graph.territory[crop[:, 0], crop[:, 1]], corridors).any()
    assert "avoiding corridor" in avoid.explanation


def test_relative_and_named_floors(planner, oracle, bm):
    xy = starts(oracle, 2)[0]
    assert planner.plan("go to the kitchen", xy, 2, goal_floor="upstairs").segments[-1].floor == 3
    assert planner.plan("go to the kitchen", xy, "first", goal_floor="DOWNSTAIRS").segments[-1].floor == 1
    assert planner.plan("go to the kitchen", xy, 2, goal_floor="Second").segments[-1].floor == 3
    assert planner.plan("go to the kitchen", xy, "2", goal_floor="ground").segments[-1].floor == 1
    with pytest.raises(UnknownFloor, match="above floor 3"):
        planner.plan("go to the kitchen", starts(oracle, 3)[0], 3, goal_floor="upstairs")
    with pytest.raises(UnknownFloor, match="no floor '7'"):
        planner.plan("go to the kitchen", xy, 7)
    with pytest.raises(MalformedInstruction, match="floor"):
        planner.plan({"goal": {"words": "kitchen", "floor": [2]}}, xy, 2)
    with pytest.raises(MalformedInstruction, match="twice"):
        planner.plan({"goal": {"words": "kitchen", "floor": 1}}, xy, 2, goal_floor=3)


def test_a_name_on_one_floor_only(bm, building, oracle):
    d = building.floors[3]
    far = d.map.cell_to_world(np.array(oracle.places[3][0].cell))
    taught, _ = teach_building(bm, [{"x": float(far[0]), "y": float(far[1]), "utterance": "this is the library"}], 3)
    planner = BuildingPlanner(taught)
    xy = starts(oracle, 1)[0]
    plan = planner.plan("go to the library", xy, 1)
    assert plan.segments[-1].floor == 3 and "library" in plan.goal[1].label  # not guessed on floor 1
    with pytest.raises(PlaceNotOnFloor, match=r"floor 2 .*on floors 3 \(second\)"):
        planner.plan("go to the library", xy, 1, goal_floor=2)


def test_a_floor_no_connector_reaches(bm, oracle):
    import dataclasses

    spec = dataclasses.replace(bm.spec, connectors=tuple(c for c in bm.spec.connectors if c.kind != "lift"))
    cut = dataclasses.replace(bm, spec=spec, _views={})
    planner = BuildingPlanner(cut)
    lift_only = lift_only_floor(bm.spec)
    other = next(f for f in bm.indices if f != lift_only)
    with pytest.raises(FloorUnreachable, match=f"reaches floor {lift_only}"):
        planner.plan("go to the kitchen", starts(oracle, other)[0], other, goal_floor=lift_only)
    # with the name on every floor, the goal is on a floor the stairs reach
    assert planner.plan("go to the kitchen", starts(oracle, other)[0], other).segments[-1].floor != lift_only


@pytest.mark.parametrize(
    ("text", "start_floor", "goal_floor"),
    [
        ("go to the bedroom on the second floor", 1, 2),  # "the Nth floor" is the floor of index N
        ("go to the bedroom on floor 3", 1, 3),
        ("go to the bedroom upstairs", 2, 3),
        ("go upstairs to the bedroom", 1, 2),
        ("go to the bedroom downstairs", 2, 1),
        ("go to the kitchen on the top floor", 1, 3),
        ("go to the kitchen on the ground floor", 3, 1),  # the floor named "ground"
        ("go to the bedroom on the floor above", 1, 2),
    ],
)
def test_sentences_name_floors(planner, oracle, text, start_floor, goal_floor):
    xy = starts(oracle, start_floor)[0]
    plan = planner.plan(text, xy, start_floor)
    assert plan.segments[-1].floor == goal_floor and plan.floors[-1] == goal_floor
    check_closest(oracle, plan, start_floor, xy, text.split(" the ")[1].split()[0], goal_floor)


def test_sentences_with_floors_on_several_places(planner, oracle):
    xy = starts(oracle, 2)[0]
    plan = planner.plan("go to the bedroom on the third floor via the kitchen on the first floor", xy, 2)
    floors = [s.floor for s in plan.segments]
    assert floors[0] == 2 and 1 in floors and floors[-1] == 3
    waypoint = [(f, p) for f, p in plan.places if p.role == "waypoint"]
    assert [f for f, _ in waypoint] == [1] and "kitchen" in waypoint[0][1].label
    avoid = planner.plan("go to the bedroom on floor 2 avoiding the corridor on the second floor", xy, 2)
    names = planner.floors[2].names
    corridors = [k for k in np.flatnonzero(bm_places(planner, 2)) if names[k] == "corridor"]
    graph = planner.floors[2].graph
    crop = graph.to_crop(avoid.segments[-1].cells)
    assert not np.isin(graph.territory[crop[:, 0], crop[:, 1]], corridors).any()
    with pytest.raises(UnknownFloor, match="above floor 3"):
        planner.plan("go to the bedroom upstairs", starts(oracle, 3)[0], 3)


def bm_places(planner, floor):
    return planner.bm.floor_places(floor)


@pytest.fixture(scope="module")
def japanese():
    """Two bundled Japanese homes as the floors of one building, stairs between their entrances."""
    from spcotmhp.building.loader import Building
    from spcotmhp.building.spec import BuildingSpec, Connector, FloorSpec, Stop
    from spcotmhp.datasets.bundled import load_bundled
    from spcotmhp.evaluation.tasks import build_places

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        floors = {1: load_bundled("3LDK_01", lang="ja"), 2: load_bundled("3LDK_06", lang="ja")}

    def entrance(d):
        p = next(p for p in build_places(d) if "玄関" in p.name)
        return d.map.cell_to_world(np.array(p.cell))

    (x1, y1), (x2, y2) = entrance(floors[1]), entrance(floors[2])
    stairs = Connector("stairs", "stairs", (Stop(1, float(x1), float(y1)), Stop(2, float(x2), float(y2))), 8.0)
    spec = BuildingSpec("ja-2f", (FloorSpec(1, "1階", "f1"), FloorSpec(2, "2階", "f2")), (stairs,))
    building = Building(spec, floors)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return building, BuildingPlanner(learn_building(building))


@pytest.mark.parametrize("text", ["2階の寝室に行って", "上の階の寝室に行って"])
def test_japanese_floor_phrases(japanese, text):
    building, planner = japanese
    oracle = BuildingOracle(building)
    stop = building.spec.connectors[0].stops[0]
    plan = planner.plan(text, (stop.x, stop.y), 1)
    assert plan.segments[-1].floor == 2 and "寝室" in plan.goal[1].label and len(plan.rides) == 1
    check_closest(oracle, plan, 1, (stop.x, stop.y), "寝室", 2)
    anywhere = planner.plan("寝室に行って", (stop.x, stop.y), 1)
    check_closest(oracle, anywhere, 1, (stop.x, stop.y), "寝室", None)


def test_floors_given_twice_must_agree(planner, oracle):
    xy = starts(oracle, 1)[0]
    same = planner.plan("go to the bedroom on floor 2", xy, 1, goal_floor=2)
    assert same.segments[-1].floor == 2
    with pytest.raises(MalformedInstruction, match="given twice"):
        planner.plan("go to the bedroom on floor 2", xy, 1, goal_floor=3)
    # a floor said for the waypoint and one given for the goal both hold
    plan = planner.plan("go to the bedroom via the kitchen on floor 3", xy, 1, goal_floor=2)
    assert plan.floors == (3, 2) and plan.segments[-1].floor == 2


def test_goal_options_bound_and_revisited_stops(planner, oracle):
    """Options whose route goes back through a stop it used (down the stairs it came up) are scored; an option
    left inexact has a lower bound no shorter than the shortest exact route, and every bound is below the exact
    route of its option (assembled here for all of them)."""
    from spcotmhp.building import options as opts

    xy = starts(oracle, 2)[0]
    plan = planner.plan("go to the kitchen via the bedroom upstairs", xy, 2)
    assert [s.floor for s in plan.segments][:2] == [2, 3]
    assert len(plan.goal_options) == 3 and {o.floor for o in plan.goal_options} == {1, 2, 3}
    exact = [o.route_m for o in plan.goal_options if o.exact]
    assert all(o.route_m >= min(exact) - 1e-9 for o in plan.goal_options if not o.exact)
    seen = []
    real = opts.lower_bound

    def spy(rides, st, alt, parts):
        bound = real(rides, st, alt, parts)
        segs = opts.assemble(st, alt, parts, st.start_cell, np.empty((0, 2), np.int64), planner.fields, True)
        seen.append((bound, opts.route_metres(rides, segs)))
        return bound

    opts.lower_bound = spy
    try:
        planner.plan("go to the kitchen via the bedroom upstairs", xy, 2)
    finally:
        opts.lower_bound = real
    assert seen and all(b <= r + 1e-9 for b, r in seen)
