"""CLI commands of the metric level (maps and cost maps)."""

from __future__ import annotations

import math
from pathlib import Path
from typing import Annotated

import numpy as np
import typer

from spcotmhp.commands import body_options as bo
from spcotmhp.errors import MapError
from spcotmhp.safe_write import atomic_write, check_output

MAX_SETTING = 1e12  # metres (radii) or 1/metres (scaling): larger values overflow the cell arithmetic


def register(app: typer.Typer) -> None:
    """Add the metric-level commands to ``app``."""
    app.command("costmap")(costmap)


def costmap(
    map_yaml: Annotated[Path, typer.Argument(help="ROS map_server YAML file.")],
    out: Annotated[Path, typer.Option("--out", help="CSV file to write (as costmap_ros.csv).")],
    inscribed_radius: Annotated[
        float | None,
        typer.Option(help="Inscribed radius in metres (0.22 when neither this nor --robot-radius is given)."),
    ] = None,
    inflation_radius: bo.InflationRadius = None,
    cost_scaling_factor: bo.CostScaling = None,
    robot_radius: bo.RobotRadius = None,
    nav2_params: bo.Nav2Params = None,
    footprint: bo.Footprint = None,
    track_unknown_space: Annotated[
        bool, typer.Option(help="Keep unknown cells as NO_INFORMATION (-1 in the output) instead of free.")
    ] = False,
    png: Annotated[Path | None, typer.Option(help="Also draw the cost map to this PNG file.")] = None,
    overwrite: Annotated[bool, typer.Option("--overwrite", help="Replace existing output files.")] = False,
) -> None:
    """Inflate a map as ROS costmap_2d does and write the published 0..100 OccupancyGrid as CSV.

    Rows are in OccupancyGrid order (row 0 is the row at the map origin), comma-separated, one row per line.
    Existing files are replaced only with --overwrite, the map's own files never; each file is written whole
    or not at all.
    """
    from spcotmhp.metric.costmap import inflate
    from spcotmhp.metric.map_io import load_map, read_map_yaml

    for name, value in (
        ("inscribed_radius", inscribed_radius),
        ("inflation_radius", inflation_radius),
        ("robot_radius", robot_radius),
        ("cost_scaling_factor", cost_scaling_factor),
    ):
        if value is not None and math.isfinite(value) and abs(value) > MAX_SETTING:
            raise MapError(f"cost map setting {name} must be at most {MAX_SETTING:g}, got {value:g}")
    inputs = [map_yaml] + ([read_map_yaml(map_yaml).image] if Path(map_yaml).is_file() else [])
    check_output(out, overwrite, inputs, MapError, "--out", suffix=".csv")
    if png is not None:
        check_output(png, overwrite, inputs + [out], MapError, "--png", suffix=".png")
    settings = cost_map_settings(
        nav2_params, robot_radius, inscribed_radius, footprint, inflation_radius, cost_scaling_factor
    )
    cost_map = inflate(load_map(map_yaml), track_unknown_space=track_unknown_space, **settings)
    grid = cost_map.to_occupancy_grid()
    atomic_write(out, lambda tmp: write_grid_csv(grid, tmp), MapError)
    if png is not None:
        atomic_write(png, lambda tmp: draw_cost_map(grid, cost_map.map.unknown, tmp), MapError)
    typer.echo(f"wrote {out} ({grid.shape[0]} rows x {grid.shape[1]} columns)", err=True)


def cost_map_settings(
    nav2_params: Path | None,
    robot_radius: float | None,
    inscribed_radius: float | None,
    footprint: str | None,
    inflation_radius: float | None,
    cost_scaling_factor: float | None,
) -> dict:
    """``inflate``'s settings of the costmap command: the radii and settings as given (costmap_2d's ranges), or,
    with --nav2-params or --footprint, the body's (:mod:`spcotmhp.metric.body`; options replace the file's)."""
    from spcotmhp.metric.costmap import DEFAULT_COSTMAP

    if nav2_params is None and footprint is None:
        return {
            "inscribed_radius": inscribed_radius,
            "robot_radius": robot_radius,
            "inflation_radius": DEFAULT_COSTMAP.inflation_radius if inflation_radius is None else inflation_radius,
            "cost_scaling_factor": DEFAULT_COSTMAP.cost_scaling_factor
            if cost_scaling_factor is None
            else cost_scaling_factor,
        }
    if inscribed_radius is not None and robot_radius is not None:
        raise MapError("give either robot_radius or inscribed_radius, not both")
    radius = robot_radius if robot_radius is not None else inscribed_radius
    body = bo.body_from_options(nav2_params, radius, footprint, inflation_radius, cost_scaling_factor)
    assert body is not None  # a file or a footprint was given
    typer.echo(f"body: {body.describe()}", err=True)
    return body.costmap()


def write_grid_csv(grid: np.ndarray, path: Path) -> None:
    """Integers, comma-separated, one grid row per line (newline-terminated), rows in the grid's order."""
    with open(path, "w", encoding="ascii", newline="\n") as handle:
        handle.writelines(",".join(map(str, row.tolist())) + "\n" for row in np.asarray(grid, dtype=np.int64))


def draw_cost_map(grid: np.ndarray, unknown: np.ndarray, path: Path) -> None:
    """A picture with the map's top row first: free white, cost darker red, lethal black, unknown grey."""
    from PIL import Image

    value = np.clip(grid.astype(np.float64), 0, 100) / 100.0
    rgb = np.empty(grid.shape + (3,), dtype=np.float64)
    rgb[..., 0] = 1.0 - 0.25 * value
    rgb[..., 1] = rgb[..., 2] = 1.0 - value
    rgb[grid >= 99] = (0.35, 0.0, 0.0)
    rgb[grid == 100] = (0.0, 0.0, 0.0)
    rgb[unknown | (grid < 0)] = (0.6, 0.6, 0.65)
    Image.fromarray(np.round(rgb[::-1] * 255).astype(np.uint8), mode="RGB").save(path, format="PNG")
