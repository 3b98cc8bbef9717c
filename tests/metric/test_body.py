"""The robot's body: costmap_2d's radii of a footprint, a Nav2 params file read as costmap_2d reads it, and one
clear line for every malformed or out-of-range value."""

from __future__ import annotations

import math
from pathlib import Path

import pytest
from hypothesis import given
from hypothesis import strategies as st

from spcotmhp.errors import RobotBodyError
from spcotmhp.metric.body import circle, min_max_distances, pad, polygon, radius_footprint
from spcotmhp.metric.costmap import DEFAULT_COSTMAP, CostMapSettings, compute_cost, default_costmap
from spcotmhp.metric.nav2_params import parse_footprint, resolve_body

NAV2 = """global_costmap:
  global_costmap:
    ros__parameters:
      robot_radius: {radius}
{extra}      plugins: ["static_layer", "obstacle_layer", "inflation_layer"]
      static_layer:
        plugin: "nav2_costmap_2d::StaticLayer"
      inflation_layer:
        plugin: "nav2_costmap_2d::InflationLayer"
        cost_scaling_factor: 3.0
        inflation_radius: 0.55
"""


def nav2_file(tmp_path: Path, radius: float = 0.3, extra: str = "", name: str = "nav2_params.yaml") -> Path:
    path = tmp_path / name
    path.write_text(NAV2.format(radius=radius, extra=extra), encoding="utf-8")
    return path


def test_rectangle_radii_by_hand() -> None:
    body = polygon([[0.3, 0.2], [0.3, -0.2], [-0.3, -0.2], [-0.3, 0.2]])
    assert body.inscribed_radius == pytest.approx(0.2)  # the nearest edges, y = +-0.2
    assert body.circumscribed_radius == pytest.approx(math.hypot(0.3, 0.2))  # a corner
    assert body.costmap() == {
        "inscribed_radius": pytest.approx(0.2),
        "inflation_radius": 1.0,
        "cost_scaling_factor": 10.0,
        "circumscribed_radius": pytest.approx(math.hypot(0.3, 0.2)),
    }


def test_off_centre_footprint_measures_from_the_turning_point() -> None:
    # a robot whose centre is 0.1 m behind the middle: nearest edge the back one (0.15 m), farthest the front corners
    body = polygon([[0.45, 0.25], [0.45, -0.25], [-0.15, -0.25], [-0.15, 0.25]])
    assert body.inscribed_radius == pytest.approx(0.15)
    assert body.circumscribed_radius == pytest.approx(math.hypot(0.45, 0.25))


def test_nav2_radius_is_costmap_2d_s_padded_16_gon(tmp_path: Path) -> None:
    unpadded = resolve_body(nav2_file(tmp_path, 0.3, "      footprint_padding: 0.0\n"))
    assert unpadded is not None
    assert unpadded.inscribed_radius == pytest.approx(0.3 * math.cos(math.pi / 16))  # an edge's middle
    assert unpadded.circumscribed_radius == pytest.approx(0.3)
    padded = resolve_body(nav2_file(tmp_path, 0.3))  # Nav2's default footprint_padding, 0.01 m
    assert padded is not None
    assert padded.circumscribed_radius == pytest.approx(
        math.hypot(0.3 * math.sqrt(0.5) + 0.01, 0.3 * math.sqrt(0.5) + 0.01)
    )
    assert 0.30 < padded.inscribed_radius < 0.31
    assert (padded.inflation_radius, padded.cost_scaling_factor) == (0.55, 3.0)


def test_nav2_footprint_string_and_option_overrides(tmp_path: Path) -> None:
    extra = (
        '      footprint: "[[0.35, 0.25], [0.35, -0.25], [-.25, -0.25], [-0.25, 0.25]]"\n      footprint_padding: 0.0\n'
    )
    body = resolve_body(nav2_file(tmp_path, 0.3, extra), inflation_radius=0.8)
    assert body is not None and body.footprint is not None and len(body.footprint) == 4
    assert body.inscribed_radius == pytest.approx(0.25)
    assert body.circumscribed_radius == pytest.approx(math.hypot(0.35, 0.25))
    assert (body.inflation_radius, body.cost_scaling_factor) == (0.8, 3.0)  # the option replaces the file's
    radius = resolve_body(nav2_file(tmp_path, 0.3, extra), robot_radius=0.25)
    assert radius is not None and radius.footprint is None and radius.inscribed_radius == 0.25


def test_no_body_given_keeps_the_model_s() -> None:
    assert resolve_body() is None
    only = resolve_body(inflation_radius=0.5)
    assert only is not None and only.inscribed_radius == DEFAULT_COSTMAP.inscribed_radius


def test_default_body_has_one_home() -> None:
    from spcotmhp.learning.model import SpatialConceptModel

    assert default_costmap() == {"inscribed_radius": 0.22, "inflation_radius": 1.0, "cost_scaling_factor": 10.0}
    assert SpatialConceptModel.__dataclass_fields__["costmap"].default_factory() == default_costmap()  # type: ignore[misc]


@pytest.mark.parametrize(
    ("kwargs", "message"),
    [
        ({"footprint": "[[0.3, 0.2], [0.3, -0.2]]"}, "the footprint has 2 points; it must have 3 to 1000"),
        ({"footprint": "[[0.3, 0.2], [0.3, -0.2], [x, 1]]"}, r"\[x, 1\] is not two numbers"),
        ({"footprint": "0.3, 0.2"}, 'must be a string "\\[\\[x, y\\]'),
        ({"footprint": "[[1, 1], [2, 1], [2, 2]]"}, r"the robot's centre \(0, 0\) must lie inside its footprint"),
        ({"footprint": "[[1e9, 1], [-1, 1], [0, -1]]"}, r"footprint point 1 must be two numbers within \+-100 m"),
        ({"robot_radius": 0.0}, r"the robot radius must be a number in \(0, 100\] m, got 0.0"),
        ({"robot_radius": math.nan}, "the robot radius must be a number"),
        (
            {"robot_radius": 0.3, "inflation_radius": 0.2},
            "inflation_radius 0.2 m is below the robot's inscribed radius",
        ),
        ({"robot_radius": 0.3, "cost_scaling_factor": -1.0}, r"cost_scaling_factor must be a number in \[0, 1e\+06\]"),
        ({"robot_radius": 0.3, "footprint": "[[1, 1], [-1, 1], [0, -1]]"}, "either --robot-radius or --footprint"),
    ],
)
def test_bad_options_are_one_line(kwargs: dict, message: str) -> None:
    with pytest.raises(RobotBodyError, match=message) as info:
        resolve_body(**kwargs)
    assert "\n" not in str(info.value)


@pytest.mark.parametrize(
    ("text", "message"),
    [
        ("a: 1\n", "has no global_costmap section"),
        (NAV2.format(radius="wide", extra=""), "robot_radius must be a number in \\(0, 100\\] m"),
        (NAV2.format(radius=0.3, extra='      footprint: "[[0.3, 0.2]"\n'), 'footprint must be a string "\\[\\['),
        (
            NAV2.format(radius=0.3, extra="      footprint_padding: -1\n"),
            r"footprint_padding must be a number in \[0, 1\]",
        ),
        (
            NAV2.replace("nav2_costmap_2d::InflationLayer", "nav2_costmap_2d::VoxelLayer").format(radius=0.3, extra=""),
            "no inflation layer among the plugins static_layer, obstacle_layer, inflation_layer",
        ),
        (
            NAV2.replace(
                "        inflation_radius: 0.55\n", "        inflation_radius: 0.55\n        enabled: false\n"
            ).format(radius=0.3, extra=""),
            "the inflation layer inflation_layer is disabled",
        ),
        (
            NAV2.replace("0.55", "-0.5").format(radius=0.3, extra=""),
            r"inflation_radius must be a number in \[0, 10000\]",
        ),
        ("global_costmap: [1, 2\n", "does not parse"),
    ],
)
def test_bad_params_files_are_one_line(tmp_path: Path, text: str, message: str) -> None:
    path = tmp_path / "p.yaml"
    path.write_text(text, encoding="utf-8")
    with pytest.raises(RobotBodyError, match=message) as info:
        resolve_body(path)
    assert "\n" not in str(info.value) and str(path) in str(info.value)


def test_ros1_common_params_at_the_top(tmp_path: Path) -> None:
    path = tmp_path / "costmap_common_params.yaml"
    path.write_text("footprint: [[0.2, 0.2], [0.2, -0.2], [-0.2, -0.2], [-0.2, 0.2]]\nfootprint_padding: 0.0\n"
                    "inflation_layer:\n  inflation_radius: 0.5\n", encoding="utf-8")  # fmt: skip
    body = resolve_body(path)
    assert body is not None and body.inscribed_radius == pytest.approx(0.2) and body.inflation_radius == 0.5


def test_circumscribed_cost_is_costmap_2d_s() -> None:
    s = CostMapSettings(inscribed_radius=0.2, circumscribed_radius=0.36, cost_scaling_factor=10.0)
    assert s.circumscribed_cost(0.05) == int(252 * math.exp(-10.0 * (0.36 - 0.2)))
    assert CostMapSettings().circumscribed_cost(0.05) == 253  # a circle: its circumscribed radius is inscribed
    assert compute_cost(0.22 / 0.05, 0.05, CostMapSettings()) == 253
    with pytest.raises(Exception, match="circumscribed_radius .* must be at least the inscribed radius"):
        CostMapSettings(inscribed_radius=0.3, circumscribed_radius=0.2)


@given(
    st.lists(st.floats(0.05, 2.0), min_size=3, max_size=12),
    st.floats(0.0, 0.05),
)
def test_radii_of_star_polygons(radii: list[float], padding: float) -> None:
    # a star-shaped polygon about the origin: every vertex at least as far as the inscribed radius, the
    # circumscribed radius is the farthest vertex, and padding never shrinks either
    n = len(radii)
    pts = tuple((r * math.cos(2 * math.pi * i / n), r * math.sin(2 * math.pi * i / n)) for i, r in enumerate(radii))
    low, high = min_max_distances(pts)
    assert low <= min(radii) + 1e-12 and high == pytest.approx(max(radii))
    padded_low, padded_high = min_max_distances(pad(pts, padding))
    assert padded_high >= high - 1e-12 and padded_low >= 0


def test_circle_option_is_that_exact_circle() -> None:
    body = circle(0.3)
    assert body.inscribed_radius == body.circumscribed_radius == 0.3 and body.footprint is None
    assert "circumscribed_radius" not in body.costmap()  # a circle's is its inscribed radius
    assert len(radius_footprint(0.3)) == 16


def test_parse_footprint_accepts_cxx_numbers() -> None:
    assert parse_footprint("[[.3, -2e-1], [+0.3, 0.2], [-0.3,0]]", "x") == [[0.3, -0.2], [0.3, 0.2], [-0.3, 0.0]]
