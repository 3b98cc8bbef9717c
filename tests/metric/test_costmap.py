"""costmap_2d static + inflation layers, the published OccupancyGrid and the probabilistic cost map."""

from __future__ import annotations

import math
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays
from PIL import Image
from scipy import ndimage

from spcotmhp.errors import MapError
from spcotmhp.metric.costmap import (
    COST_TRANSLATION_TABLE,
    CostMapSettings,
    cell_distance,
    compute_cost,
    inflate,
    static_costs,
)
from spcotmhp.metric.map_io import load_map
from spcotmhp.metric.maps import OccupancyMap

ROOT = Path(__file__).resolve().parents[2]
DATA = ROOT / "spcotmhp" / "data"
ROS_COSTMAPS = sorted((DATA / "sigverse-3ldk").glob("*/costmap_ros.csv"))
SPCOTMHP = Path(sys.executable).with_name("spcotmhp")


def grid(rows: list[str]) -> OccupancyMap:
    """A map from text, first string = top row: '.' free, '#' occupied, '?' unknown (resolution 0.1)."""
    values = {".": 0, "#": 100, "?": -1}
    data = np.array([[values[c] for c in row] for row in rows[::-1]], dtype=np.int8)
    return OccupancyMap(data, 0.1)


# --------------------------------------------------------------------------------- hand-computed values


def test_translation_table() -> None:
    t = COST_TRANSLATION_TABLE
    assert t.dtype == np.int8 and t.shape == (256,)
    assert (t[0], t[253], t[254], t[255]) == (0, 99, 100, -1)
    # 1 + (97 * (v - 1)) // 251: v=1 -> 1, v=127 -> 1 + 12222 // 251 = 49, v=243 -> 1 + 23474 // 251 = 94,
    # v=252 -> 98
    assert (t[1], t[127], t[243], t[252]) == (1, 49, 94, 98)
    expected = [0] + [1 + (97 * (v - 1)) // 251 for v in range(1, 253)] + [99, 100, -1]
    assert t.tolist() == expected
    assert np.all(np.diff(t[:255].astype(int)) >= 0)


def test_compute_cost_by_hand() -> None:
    s = CostMapSettings(inscribed_radius=0.22, inflation_radius=1.0, cost_scaling_factor=10.0)
    assert compute_cost(0.0, 0.1, s) == 254
    assert [compute_cost(d, 0.1, s) for d in (1.0, math.sqrt(2), 2.0)] == [253, 253, 253]
    # int(252 * exp(-10 * (d * 0.1 - 0.22))): sqrt5 -> 243.08, 3 -> 113.24, sqrt8 -> 134.3, 4 -> 41.6,
    # 5 -> 15.3
    assert compute_cost(math.sqrt(5), 0.1, s) == 243
    assert compute_cost(3.0, 0.1, s) == 113
    assert compute_cost(math.sqrt(8), 0.1, s) == 134
    assert compute_cost(4.0, 0.1, s) == 41
    assert compute_cost(5.0, 0.1, s) == 15
    assert compute_cost(10.0, 0.1, s) == 0  # 252 * exp(-7.8) = 0.103


def test_cell_distance_is_ceil() -> None:
    assert cell_distance(1.0, 0.1) == 10
    assert cell_distance(1.0, 0.05) == 20
    assert cell_distance(0.25, 0.1) == 3
    assert cell_distance(0.0, 0.1) == 0
    assert cell_distance(-1.0, 0.1) == 0


def test_single_obstacle_by_hand() -> None:
    rows = ["." * 25 for _ in range(25)]
    rows[12] = "." * 12 + "#" + "." * 12
    cm = inflate(grid(rows))
    c = cm.costs
    assert c.dtype == np.uint8 and c.shape == (25, 25)
    assert c[12, 12] == 254
    assert c[12, 13] == c[13, 13] == c[14, 12] == 253  # d = 1, sqrt2, 2 cells: inside 0.22 m
    assert c[13, 14] == c[14, 13] == 243  # sqrt5
    assert c[12, 15] == c[9, 12] == 113  # 3 cells
    assert c[14, 14] == 134  # sqrt8
    assert c[12, 17] == 15  # 5 cells
    assert c[12, 22] == 0 and c[12, 24] == 0  # 10 cells (cost 0) and beyond the radius
    # a single source: every cell's distance is the exact Euclidean one
    rr, cc = np.indices(c.shape)
    d = np.hypot(rr - 12, cc - 12)
    expected = [compute_cost(x, 0.1, cm.settings) if x <= 10 else 0 for x in d.ravel()]
    np.testing.assert_array_equal(c.ravel(), expected)


def test_cost_is_the_maximum_over_obstacles() -> None:
    cm = inflate(grid(["#.....#"]), inflation_radius=0.6)
    # cells 1..5 are 1,2,3,2,1 from the nearer wall: 253, 253, 113, 253, 253
    assert cm.costs[0].tolist() == [254, 253, 253, 113, 253, 253, 254]


def test_inflation_radius_limits_the_spread() -> None:
    row = "#" + "." * 12
    c1 = inflate(grid([row]), inflation_radius=0.3).costs[0]
    assert c1.tolist() == [254, 253, 253, 113] + [0] * 9
    c0 = inflate(grid([row]), inflation_radius=0.0).costs[0]
    assert c0.tolist() == [254] + [0] * 12
    # scaling factor 0: every cell in the radius gets 252, not 0
    c2 = inflate(grid([row]), inflation_radius=0.5, cost_scaling_factor=0.0).costs[0]
    assert c2.tolist() == [254, 253, 253, 252, 252, 252] + [0] * 7


def test_robot_radius_is_the_inscribed_radius() -> None:
    m = grid(["#......"])
    a = inflate(m, robot_radius=0.35)
    assert a.settings.inscribed_radius == 0.35
    assert a.costs[0].tolist()[:5] == [254, 253, 253, 253, int(252 * math.exp(-10 * (0.4 - 0.35)))]
    np.testing.assert_array_equal(a.costs, inflate(m, inscribed_radius=0.35).costs)
    assert inflate(m).settings.inscribed_radius == 0.22


# --------------------------------------------------------------------------------- unknown space


def test_unknown_space_is_free_by_default() -> None:
    m = grid(["#??.."])
    cm = inflate(m)
    assert cm.costs[0].tolist() == [254, 253, 253, 113, 41]
    assert static_costs(m).tolist() == [[254, 0, 0, 0, 0]]


def test_track_unknown_space() -> None:
    m = grid(["#???.", "?????"])
    cm = inflate(m, track_unknown_space=True)
    # unknown cells keep 255 unless the inflated cost reaches 253 (inflate_unknown off)
    assert cm.costs[1].tolist() == [254, 253, 253, 255, 41]  # top row: d = 0, 1, 2, 3, 4
    # bottom row: d = 1, sqrt2 -> 253; sqrt5 -> 243 and sqrt10 -> 96 stay unknown
    assert cm.costs[0].tolist() == [253, 253, 255, 255, 255]
    assert cm.to_occupancy_grid()[0].tolist() == [99, 99, -1, -1, -1]
    inflated = inflate(m, track_unknown_space=True, inflate_unknown=True)
    assert inflated.costs[1].tolist() == [254, 253, 253, 113, 41]
    sqrt17_cost = int(252 * math.exp(-10 * (math.sqrt(17) * 0.1 - 0.22)))  # 36
    assert inflated.costs[0].tolist() == [253, 253, 243, 96, sqrt17_cost]
    assert np.all(np.isneginf(inflated.log_p[m.unknown]))


# --------------------------------------------------------------------------------- probabilistic cost map


def test_log_p_by_hand() -> None:
    m = grid(["#...?."])
    cm = inflate(m, inflation_radius=0.5)
    # costs 254, 253, 253, 113, 41 (unknown, inflated as free), 15 -> ROS 100, 99, 99, 44, 16, 6
    assert cm.costs[0].tolist() == [254, 253, 253, 113, 41, 15]
    assert cm.to_occupancy_grid()[0].tolist() == [100, 99, 99, 44, 16, 6]
    # inscribed cells (ROS 99) get p = 0: the robot's footprint would overlap the obstacle there
    expected = [-np.inf, -np.inf, -np.inf, math.log(0.56), -np.inf, math.log(0.94)]
    np.testing.assert_allclose(cm.log_p[0], expected, rtol=0, atol=1e-12)
    assert cm.free[0].tolist() == [False, False, False, True, False, True]
    np.testing.assert_allclose(cm.p[0], [0, 0, 0, 0.56, 0, 0.94], atol=1e-12)


def test_log_p_on_a_bundled_home() -> None:
    m = load_map(DATA / "sigverse-3ldk" / "3LDK_01" / "map.yaml")
    cm = inflate(m)
    ros = cm.to_occupancy_grid().astype(float)
    assert np.all(np.isneginf(cm.log_p[~m.free]))
    robot = m.free & (ros < 99)  # free, and not within the inscribed radius of an obstacle
    np.testing.assert_allclose(np.exp(cm.log_p[robot]), (100 - ros[robot]) / 100)
    assert np.all(np.isneginf(cm.log_p[m.free & (ros >= 99)])) and (m.free & (ros >= 99)).any()
    assert np.all(cm.log_p[robot] >= math.log(0.02))


# --------------------------------------------------------------------------------- against real ROS output


def agreement(ours: np.ndarray, ros: np.ndarray, mask: np.ndarray) -> dict[str, float]:
    diff = np.abs(ours.astype(int) - ros.astype(int))[mask]
    return {
        "exact": float(np.mean(diff == 0)),
        "within1": float(np.mean(diff <= 1)),
        "within2": float(np.mean(diff <= 2)),
        "max": int(diff.max()),
    }


def test_every_bundled_ros_costmap_is_present() -> None:
    assert len(ROS_COSTMAPS) >= 3


@pytest.mark.parametrize("csv", ROS_COSTMAPS, ids=[p.parent.name for p in ROS_COSTMAPS])
def test_matches_ros_costmap_2d(csv: Path) -> None:
    m = load_map(csv.parent / "map.yaml")
    ros = np.loadtxt(csv, delimiter=",", dtype=int)
    assert ros.shape == m.shape
    cm = inflate(m, inscribed_radius=0.22, inflation_radius=1.0, cost_scaling_factor=10.0)
    ours = cm.to_occupancy_grid()
    stats = agreement(ours, ros, m.free)
    assert stats["within2"] >= 0.995, stats
    # the reproduction is exact, on every cell (ROS ran with unknown space as free, as our default)
    assert stats["exact"] == 1.0, stats
    np.testing.assert_array_equal(ours, ros)


def test_albert_b_costmap_is_consistent() -> None:
    m = load_map(DATA / "albert-b" / "map.yaml")
    cm = inflate(m)
    assert cm.costs.shape == (800, 1184)
    np.testing.assert_array_equal(cm.costs == 254, m.occupied)
    edt = ndimage.distance_transform_edt(~m.occupied)
    assert np.all(cm.costs[(edt > 0) & (edt * 0.05 <= 0.22)] == 253)
    assert np.all(cm.costs[edt > 20] == 0)


@settings(max_examples=40, deadline=None)
@given(
    arrays(
        np.bool_,
        st.tuples(st.integers(3, 30), st.integers(3, 30)),
        elements=st.sampled_from([False] * 12 + [True]),
    )
)
def test_wavefront_never_exceeds_the_exact_distance_cost(walls: np.ndarray) -> None:
    """costmap_2d's wavefront distance is never shorter than the true nearest-obstacle distance, and equal on
    nearly every cell: cost <= the cost from the exact distance transform."""
    m = OccupancyMap(np.where(walls, 100, 0).astype(np.int8), 0.1)
    cm = inflate(m)
    if not walls.any():
        assert np.all(cm.costs == 0)
        return
    d = ndimage.distance_transform_edt(~walls)
    exact = np.array([compute_cost(x, 0.1, cm.settings) if x <= 10 else 0 for x in d.ravel()])
    exact = exact.reshape(d.shape)
    assert np.all(cm.costs <= exact)
    assert np.mean(cm.costs == exact) >= 0.95


# --------------------------------------------------------------------------------- bad settings


@pytest.mark.parametrize(
    "kwargs, message",
    [
        ({"inscribed_radius": -0.1}, "inscribed_radius must be >= 0, got -0.1"),
        ({"inflation_radius": -1.0}, "inflation_radius must be >= 0"),
        ({"cost_scaling_factor": float("nan")}, "cost_scaling_factor must be a finite number, got nan"),
        ({"inflation_radius": float("inf")}, "inflation_radius must be a finite number"),
        (
            {"robot_radius": 0.3, "inscribed_radius": 0.2},
            "give either robot_radius or inscribed_radius, not both",
        ),
        ({"robot_radius": -0.3}, "inscribed_radius must be >= 0"),
    ],
)
def test_bad_settings(kwargs: dict, message: str) -> None:
    with pytest.raises(MapError, match=message):
        inflate(grid(["#."]), **kwargs)


# --------------------------------------------------------------------------------- CLI


def run_cli(*args: str) -> subprocess.CompletedProcess:
    return subprocess.run([str(SPCOTMHP), *args], check=False, capture_output=True, text=True, timeout=300)


def test_cli_reproduces_costmap_ros_csv_byte_for_byte(tmp_path: Path) -> None:
    home = DATA / "sigverse-3ldk" / "3LDK_05"
    out, png = tmp_path / "cm.csv", tmp_path / "cm.png"
    result = run_cli(
        "costmap",
        str(home / "map.yaml"),
        "--inscribed-radius",
        "0.22",
        "--inflation-radius",
        "1.0",
        "--cost-scaling-factor",
        "10",
        "--out",
        str(out),
        "--png",
        str(png),
    )
    assert result.returncode == 0, result.stderr
    assert out.read_bytes() == (home / "costmap_ros.csv").read_bytes()
    with Image.open(png) as img:
        assert img.size == (192, 192) and img.mode == "RGB"


def test_cli_robot_radius_and_unknown(tmp_path: Path) -> None:
    home = DATA / "sigverse-3ldk" / "3LDK_06"
    out = tmp_path / "cm.csv"
    result = run_cli(
        "costmap", str(home / "map.yaml"), "--robot-radius", "0.3", "--track-unknown-space", "--out", str(out)
    )
    assert result.returncode == 0, result.stderr
    text = out.read_text()
    assert text.endswith("\n") and len(text.splitlines()) == 192
    written = np.loadtxt(out, delimiter=",", dtype=int)
    m = load_map(home / "map.yaml")
    expected = inflate(m, robot_radius=0.3, track_unknown_space=True).to_occupancy_grid()
    np.testing.assert_array_equal(written, expected)
    assert np.any(written == -1)


@pytest.mark.parametrize(
    "args, message",
    [
        (["/nonexistent/map.yaml"], "error: map YAML /nonexistent/map.yaml does not exist"),
        (
            ["MAP", "--robot-radius", "0.3", "--inscribed-radius", "0.2"],
            "error: give either robot_radius or inscribed_radius, not both",
        ),
        (
            ["MAP", "--inflation-radius", "-1"],
            "error: cost map setting inflation_radius must be >= 0, got -1.0",
        ),
    ],
)
def test_cli_errors(tmp_path: Path, args: list[str], message: str) -> None:
    yaml_path = str(DATA / "sigverse-3ldk" / "3LDK_01" / "map.yaml")
    args = [yaml_path if a == "MAP" else a for a in args]
    result = run_cli("costmap", *args, "--out", str(tmp_path / "x.csv"))
    assert result.returncode == 2
    assert result.stderr.strip() == result.stderr.strip().splitlines()[0]  # one line
    assert result.stderr.startswith(message)
    assert not (tmp_path / "x.csv").exists()


@pytest.mark.parametrize("option, name", [("--out", "cm.png"), ("--png", "cm.csv"), ("--out", "cm")])
def test_cli_output_names_say_what_is_written(tmp_path: Path, option: str, name: str) -> None:
    """--out writes a CSV and --png a PNG: a name promising the other (or nothing) is refused, nothing written."""
    yaml_path = str(DATA / "sigverse-3ldk" / "3LDK_01" / "map.yaml")
    paths = {"--out": tmp_path / "ok.csv", "--png": tmp_path / "ok.png", option: tmp_path / name}
    result = run_cli("costmap", yaml_path, "--out", str(paths["--out"]), "--png", str(paths["--png"]))
    assert result.returncode == 2
    wanted = ".csv" if option == "--out" else ".png"
    assert result.stderr.strip() == (
        f"error: {option} {tmp_path / name}: this writes a {wanted[1:].upper()} file; give a name ending in {wanted}"
    )
    assert not any(tmp_path.iterdir())


def test_cli_unwritable_output(tmp_path: Path) -> None:
    yaml_path = str(DATA / "sigverse-3ldk" / "3LDK_01" / "map.yaml")
    result = run_cli("costmap", yaml_path, "--out", str(tmp_path / "missing" / "x.csv"))
    assert result.returncode == 2
    target = tmp_path / "missing" / "x.csv"
    assert result.stderr.strip() == f"error: --out {target}: the folder {target.parent} does not exist"


# --------------------------------------------------------------------------------- huge inflation radii


def _uncapped(occ: OccupancyMap, cell_radius: int, settings: CostMapSettings) -> np.ndarray:
    """The wavefront with a kernel of any size (what inflate did before the cap)."""
    from spcotmhp.metric._wavefront import wavefront as _wavefront
    from spcotmhp.metric.costmap import inflation_kernel

    costs = static_costs(occ, settings.track_unknown_space)
    bins, kernel_costs = inflation_kernel(cell_radius, occ.resolution, settings)
    _wavefront(costs, bins, kernel_costs, settings.inflate_unknown)
    return costs


def test_a_huge_inflation_radius_is_capped_at_the_diagonal_with_the_same_costs() -> None:
    from spcotmhp.metric.costmap import max_cell_radius

    occ = grid(["#.......?.", "..........", "....#.....", "..........", ".........#", "....??...."])
    assert max_cell_radius(occ) == math.ceil(math.hypot(6, 10)) == 12
    settings = CostMapSettings(inscribed_radius=0.1, inflation_radius=1e9, cost_scaling_factor=0.5)
    got = inflate(occ, inscribed_radius=0.1, inflation_radius=1e9, cost_scaling_factor=0.5)  # 1e10 cells
    for cells in (12, 13, 40):  # at the cap and well beyond it (uncapped kernels): identical
        np.testing.assert_array_equal(got.costs, _uncapped(occ, cells, settings))
    assert got.settings.inflation_radius == 1e9
    # with a slow decay every cell is inflated: the radius did reach across the whole map
    assert (got.costs > 0).all() and (got.costs < 253).any()


def test_a_huge_inflation_radius_on_a_bundled_home_stays_small() -> None:
    m = load_map(DATA / "albert-b" / "map.yaml")  # 800 x 1184 cells: 1e9 m would be a 2e10-cell kernel
    huge = inflate(m, inflation_radius=1e9, cost_scaling_factor=10.0)
    np.testing.assert_array_equal(huge.costs, inflate(m, inflation_radius=80.0, cost_scaling_factor=10.0).costs)


@pytest.mark.parametrize(
    "distance, resolution, message",
    [
        (float("inf"), 0.1, "a distance in metres must be a finite number, got inf"),
        (float("nan"), 0.1, "a distance in metres must be a finite number, got nan"),
        ("1", 0.1, "a distance in metres must be a finite number, got '1'"),
        (1.0, 0.0, r"the map resolution must be a finite number > 0 \(metres per cell\), got 0.0"),
        (1.0, float("inf"), "the map resolution must be a finite number > 0"),
    ],
)
def test_cell_distance_rejects_bad_numbers(distance: float, resolution: float, message: str) -> None:
    with pytest.raises(MapError, match=message):
        cell_distance(distance, resolution)


def test_inflation_kernel_rejects_a_bad_radius() -> None:
    from spcotmhp.metric.costmap import inflation_kernel

    for bad in (-1, 2.5, True):
        with pytest.raises(MapError, match="the inflation radius in cells must be an integer >= 0, got "):
            inflation_kernel(bad, 0.1, CostMapSettings())


def test_cli_huge_and_non_finite_radii(tmp_path: Path) -> None:
    yaml_path = str(DATA / "sigverse-3ldk" / "3LDK_01" / "map.yaml")
    ok = run_cli("costmap", yaml_path, "--inflation-radius", "1e9", "--out", str(tmp_path / "x.csv"))
    assert ok.returncode == 0, ok.stderr
    assert len((tmp_path / "x.csv").read_text().splitlines()) == 192
    for option, value, message in (
        ("--inflation-radius", "inf", "inflation_radius must be a finite number, got inf"),
        ("--cost-scaling-factor", "nan", "cost_scaling_factor must be a finite number"),
        ("--cost-scaling-factor", "-2", "cost_scaling_factor must be >= 0, got -2.0"),
    ):
        bad = run_cli("costmap", yaml_path, option, value, "--out", str(tmp_path / "y.csv"))
        assert bad.returncode == 2 and bad.stderr.startswith(f"error: cost map setting {message}"), bad.stderr


def test_a_huge_inflation_radius_is_the_whole_map_not_an_overflow() -> None:
    m = grid(["#...?."])
    huge = inflate(m, inflation_radius=1e308)
    whole = inflate(m, inflation_radius=100.0)
    assert (huge.costs == whole.costs).all()
