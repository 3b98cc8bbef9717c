"""The robot-body options shared by ``learn``, ``costmap``, ``plan``, ``serve`` and ``ros2``.

``--nav2-params FILE`` reads the body from a Nav2 params YAML (:mod:`spcotmhp.metric.nav2_params`);
``--robot-radius``, ``--footprint``, ``--inflation-radius`` and ``--cost-scaling-factor`` give it directly or
replace the file's values. None of them given: the model's own body (``learn``: the default body, a 0.22 m
circle with inflation 1.0 m and scaling 10). ``plan``, ``serve`` and ``ros2`` given a body plan for it from the
model's stored map without learning again (:func:`spcotmhp.planning.body.with_body`).
"""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING, Annotated

import typer

if TYPE_CHECKING:  # the cost map (numba) is imported by the commands that use it
    from spcotmhp.metric.body import RobotBody

Nav2Params = Annotated[
    Path | None,
    typer.Option(
        "--nav2-params",
        help="Nav2 params YAML: the robot's body from its global_costmap (robot_radius or footprint, "
        "footprint_padding, the inflation layer's inflation_radius and cost_scaling_factor).",
    ),
]
RobotRadius = Annotated[
    float | None, typer.Option("--robot-radius", help="Radius of a circular robot in metres (its inscribed radius).")
]
Footprint = Annotated[
    str | None,
    typer.Option("--footprint", help='Footprint polygon in metres, as Nav2 writes it: "[[x, y], [x, y], ...]".'),
]
InflationRadius = Annotated[
    float | None, typer.Option("--inflation-radius", help="Inflation radius in metres (default 1.0, or the file's).")
]
CostScaling = Annotated[
    float | None,
    typer.Option("--cost-scaling-factor", help="Exponential decay of the inflated cost (default 10, or the file's)."),
]


def body_from_options(
    nav2_params: Path | None,
    robot_radius: float | None,
    footprint: str | None,
    inflation_radius: float | None,
    cost_scaling_factor: float | None,
) -> RobotBody | None:
    """The body the options give, or None (module docstring)."""
    from spcotmhp.metric.nav2_params import resolve_body

    return resolve_body(nav2_params, robot_radius, footprint, inflation_radius, cost_scaling_factor)
