"""Free regions (planning/regions.py): planning within the start's free region, places seeded by their posterior
in every region their 2-sigma ellipse reaches, and refusals that name the cut. Checked against hand-made homes
and, on generated homes with closed doors and furniture, against a breadth-first oracle over the robot's cells."""

from __future__ import annotations

from functools import cache

import numpy as np
import pytest
from scipy import ndimage

from spcotmhp.datasets.synthetic_furniture import close_doors, furnish
from spcotmhp.datasets.synthetic_plan import generate_floor_plan
from spcotmhp.datasets.synthetic_walk import teaching_walk
from spcotmhp.errors import NoReachablePlace, PlaceCutOff, PlanningError, StartBlocked
from spcotmhp.learning.supervised import fit_supervised
from spcotmhp.metric.costmap import inflate
from spcotmhp.planning.places import mahalanobis2
from spcotmhp.planning.planner import HierarchicalPlanner
from spcotmhp.planning.regions import REACH_SIGMAS, free_regions
from tests.helpers.planning import DOORS, EDGES, NAMES, ROOMS, SHAPE, home_log_p, make_home, world

FOUR = ndimage.generate_binary_structure(2, 1)


def closed_door_home(**settings):
    """The four-room home with the corridor-bedroom #2 door closed: {bedroom #1, corridor} | {kitchen, bedroom #2}."""
    model = make_home(ROOMS, DOORS[:1] + DOORS[2:], NAMES, EDGES, SHAPE)
    return model, HierarchicalPlanner(model, log_p=home_log_p(model.require_map()), **settings)


@pytest.mark.parametrize("dense", [True, False])
def test_a_start_behind_a_closed_door_plans_within_its_region(dense):
    """Dense fields, and the portal graph of building-scale maps (every region's graph)."""
    model, planner = closed_door_home(**({} if dense else {"max_dense_bytes": 0}))
    assert (planner.graph.hier is None) == dense and (planner.graph.regions[2].hier is None) == dense
    occ = model.require_map()
    assert len(planner.graph.regions) == 1  # the second region has its own graph
    plan = planner.plan("go to the kitchen", world(occ, 6, 25))  # in bedroom #2, beside the kitchen
    assert plan.places[-1].label == "kitchen"
    comp, _ = ndimage.label(occ.data == 0, structure=FOUR)
    assert (comp[plan.cells[:, 0], plan.cells[:, 1]] == comp[6, 25]).all()
    bedroom = planner.plan("go to the bedroom", world(occ, 6, 25))
    assert bedroom.places[-1].id == 3  # bedroom #2: bedroom #1 is behind the door
    assert planner.plan("go to the bedroom", world(occ, 6, 5)).places[-1].id == 0


def test_a_place_only_behind_the_door_is_refused_naming_the_cut():
    _, planner = closed_door_home()
    occ = planner.model.require_map()
    with pytest.raises(PlaceCutOff, match=r"the kitchen is not reachable from here \(.*\): the free space is cut"):
        planner.plan("go to the kitchen", world(occ, 6, 5))
    with pytest.raises(PlaceCutOff, match="the corridor is not reachable from here"):
        planner.plan("go to the bedroom via the corridor", world(occ, 6, 25))
    assert issubclass(PlaceCutOff, NoReachablePlace)  # HTTP 409, as before


def pocket_home(mean_in_pocket: bool = True):
    """One 6 x 6 m room (0.1 m cells) with a ring of furniture (inner square 1 m, pieces 0.4 m deep, a 0.2 m gap in
    the bottom one) around its middle, and a second room to the east through a door, with a smaller ring in its
    far corner that no place's 2-sigma ellipse reaches; one Gaussian per room."""
    data = np.full((62, 110), 100, dtype=np.int8)
    data[1:61, 1:61] = 0  # room A
    data[1:61, 62:109] = 0  # room B
    data[25:35, 61] = 0  # a 1 m door
    data[21:39, 21:39] = 100  # the ring's outer box
    data[25:35, 25:35] = 0  # the free square inside
    data[21:25, 29:31] = 0  # a 0.2 m gap: free on the map, closed for a 0.22 m robot
    data[46:58, 95:107] = 100  # the far ring: safe cells around (51.5, 100.5), x 10.05 y 5.15
    data[49:55, 98:104] = 0
    from spcotmhp.learning.model import SpatialConceptModel
    from spcotmhp.metric.maps import OccupancyMap

    occ = OccupancyMap(data=data, resolution=0.1)
    centre = (3.0, 3.0) if mean_in_pocket else (1.6, 4.6)
    mu = np.array([centre, (8.5, 3.1)])
    Sigma = np.array([np.diag([1.0, 1.0]), np.diag([1.2, 1.0])])
    psi = np.array([[0.6, 0.4], [0.4, 0.6]])
    W = np.array([[0.9, 0.1], [0.1, 0.9]])
    return SpatialConceptModel(
        mu=mu, Sigma=Sigma, psi=psi, pi=np.full(2, 0.5), phi=np.eye(2) * 0.8 + 0.1, W=W,
        vocabulary=["living", "kitchen"], map=occ,
    )  # fmt: skip


def test_a_place_whose_mean_lies_in_a_furniture_pocket_is_planned_to_from_the_room_around_it():
    """Issue 24's case: the living room's own territory is the pocket inside its furniture (its mean lies there), so
    before it had no candidate point where the robot can go; now it has one in the main region too, chosen by its
    posterior, inside its 2-sigma ellipse."""
    model = pocket_home()
    planner = HierarchicalPlanner(model)
    graph, occ = planner.graph, model.require_map()
    living = graph.node_place == 0
    assert living.any()  # a node of the living room in the main region
    node = graph.node_cell[living][0]
    assert graph.main[node[0], node[1]] and graph.territory[node[0], node[1]] == 0
    assert mahalanobis2(graph.centres[node[0], node[1]], model.mu[:1], model.Sigma[:1])[0] <= REACH_SIGMAS**2
    plan = planner.plan("go to the living", world(occ, 30, 90))  # from room B
    assert plan.places[-1].label == "living"
    # from inside the pocket: the living room is where the robot is; the kitchen is cut off
    inside = planner.plan("go to the living", world(occ, 30, 30))
    assert inside.places[-1].label == "living" and np.abs(inside.cells - [30, 30]).max() <= 3
    with pytest.raises(PlaceCutOff):
        planner.plan("go to the kitchen", world(occ, 30, 30))


def test_without_the_pocket_holding_the_mean_the_regions_graph_is_unchanged():
    """When every place's territory is in the main region, the main graph's nodes are today's rule's: the pocket
    (which the living room's 2-sigma ellipse holds) gets a graph of its own and nothing else moves."""
    model = pocket_home(mean_in_pocket=False)
    planner = HierarchicalPlanner(model)
    graph = planner.graph
    assert graph.node_place.tolist() == [0, 1]
    pocket = list(graph.regions.values())
    assert len(pocket) == 1 and pocket[0].node_place.tolist() == [0]


def test_regions_partition_and_seed_cell_by_hand():
    """Two free regions, place 0 with its mean in the left one and a broad Gaussian reaching the right one where
    place 1 is more probable everywhere: place 0's seed on the right is the cell where its posterior is highest
    (the right region's cell nearest place 0), alone."""
    from spcotmhp.learning.model import SpatialConceptModel
    from spcotmhp.metric.maps import OccupancyMap

    free = np.ones((3, 9), dtype=bool)
    free[:, 4] = False
    occ = OccupancyMap(data=np.where(free, 0, 100).astype(np.int8), resolution=1.0)
    model = SpatialConceptModel(
        mu=np.array([[1.5, 1.5], [7.5, 1.5]]), Sigma=np.array([np.eye(2) * 4.0, np.eye(2)]),
        psi=np.full((2, 2), 0.5), pi=np.ones(1), phi=np.full((1, 2), 0.5), W=np.ones((1, 1)), vocabulary=["x"],
        map=occ,
    )  # fmt: skip
    r = free_regions(model, free, occ.cell_centres())
    # place 0 (sd 2) reaches one cell of the right region: (row 1, column 5), at Mahalanobis distance exactly 2
    # ((5.5 - 1.5)^2 / 4 = 4); (0, 5) and (2, 5) are at 4.25. Place 1 is more probable there (-2 against -2 - log 4)
    assert r.home.tolist() == [1, 2]
    expected = np.array([[0, 0, 0, 0, -1, 1, 1, 1, 1], [0, 0, 0, 0, -1, 0, 1, 1, 1], [0, 0, 0, 0, -1, 1, 1, 1, 1]])
    np.testing.assert_array_equal(r.territory, expected)
    assert r.with_places() == [2] and r.fallback == {}


def test_a_start_in_the_gap_of_a_ring_leaves_it_into_the_room_first():
    """From an inscribed cell in the ring's gap (row 24: the pocket's robot cells are 2 rows away, the room's 5) the
    escape goes to the room around the ring (within its window), from which every place is reachable; the pocket
    is where the robot goes only when the room is out of reach (start.py)."""
    model = pocket_home()
    planner, occ = HierarchicalPlanner(model), model.require_map()
    plan = planner.plan("go to the kitchen", world(occ, 24, 29))
    assert plan.places[-1].label == "kitchen"
    assert "the path first moves 0.50 m clear" in plan.explanation
    assert planner.graph.main[tuple(planner.graph.to_crop(plan.cells[5]))]


def test_a_start_where_no_place_reaches_is_refused():
    model = pocket_home()
    planner, occ = HierarchicalPlanner(model), model.require_map()
    with pytest.raises(StartBlocked, match="no place reaches the free space around it"):
        planner.plan("go to the kitchen", world(occ, 51, 100))


# ---- generated homes with closed doors and furniture, against a breadth-first oracle ---------------------------


@cache
def furnished(seed: int, doors: int, learned: bool = False):
    rng = np.random.default_rng(seed)
    plan = generate_floor_plan("house", n_rooms=8, seed=rng)
    data = teaching_walk(plan, events_per_room=12, seed=rng)
    furnish(plan, rng, share=1.0)
    close_doors(plan, rng, doors)
    data.map = plan.map
    if learned:  # unsupervised Gibbs learning (a short run: Gaussians that merge or split rooms are welcome here)
        from spcotmhp.learning.gibbs import SpCoTMHP

        model = SpCoTMHP(iterations=30, seed=seed).fit(data).model_
        model.map = model.map if model.map is not None else data.map
    else:
        model = fit_supervised(data)
    return model, HierarchicalPlanner(model)


@pytest.mark.parametrize(
    ("seed", "doors", "learned"),
    [(0, 1, False), (1, 1, False), (2, 2, False), (3, 0, False), (4, 2, False), (5, 1, False), (6, 1, True),
     (7, 2, True)],
)  # fmt: skip
def test_every_place_within_reach_is_planned_and_every_plan_stays_in_its_region(seed, doors, learned):
    """From starts in every free region (the oracle: 4-connected components of the model's robot cells, from
    scipy, not the planner's labels), "go to <name>" is planned whenever some place of that name has a robot cell
    inside its 2-sigma ellipse in the start's component, and every plan stays in that component; a refusal is a
    NoReachablePlace (PlaceCutOff when the name's places lie elsewhere). Supervised and learned parameters."""
    model, planner = furnished(seed, doors, learned)
    occ = model.require_map()
    robot = inflate(occ, **model.costmap).free
    comp, n = ndimage.label(robot, structure=FOUR)
    assert n >= 2  # furniture islands, closed doors
    act = np.flatnonzero(model.active_places)
    inside = {
        int(k): mahalanobis2(occ.cell_centres(), model.mu[k : k + 1], model.Sigma[k : k + 1])[..., 0] <= 4.0
        for k in act
    }
    names = sorted(set(planner.spoken_names(act)))
    rng = np.random.default_rng(seed)
    planned = refused = 0
    for label in range(1, n + 1):
        cells = np.argwhere(comp == label)
        start = cells[rng.integers(len(cells))]
        here = comp == label
        for name in names:
            named = np.flatnonzero(planner.places_named(name.split()))
            reachable = any((inside[int(k)] & here).any() for k in named)
            try:
                plan = planner.plan({"goal": name.split()}, tuple(occ.cell_to_world(start)))
            except PlanningError as exc:
                assert not reachable, f"{name} from {start.tolist()} refused although within reach: {exc}"
                assert isinstance(exc, (NoReachablePlace, StartBlocked)), exc
                if any(planner.planned[named]):
                    assert isinstance(exc, (PlaceCutOff, StartBlocked)), exc
                refused += 1
                continue
            planned += 1
            assert (comp[plan.cells[:, 0], plan.cells[:, 1]] == label).all()
            assert plan.places[-1].id in named
    assert planned > 0 and (refused > 0 or doors == 0)
