"""The robot's body from a Nav2 (or ROS 1 move_base) params YAML, read as costmap_2d reads it.

From the ``global_costmap`` section (``global_costmap: global_costmap: ros__parameters:`` in Nav2, one level in
ROS 1; a file without that section but with ``robot_radius`` or ``footprint`` at its top, as ROS 1's
costmap_common_params.yaml, is read from its top):

* ``footprint``: the string "[[x, y], ...]" as Nav2 writes it (or a YAML list of pairs); "[]" or absent means
  a circle of ``robot_radius``. A footprint that does not parse is refused (Nav2 would log it and fall back to the
  radius; a plan for the wrong body is worse than no plan).
* ``robot_radius`` (default 0.1 m, Nav2's): made costmap_2d's 16-point polygon (``makeFootprintFromRadius``).
* ``footprint_padding`` (default 0.01 m, Nav2's and ROS 1's): added to the polygon (``padFootprint``), so a
  0.30 m ``robot_radius`` has the inscribed radius 0.304 m and the circumscribed 0.314 m that costmap_2d uses.
* The inflation layer: the entry of ``plugins`` whose ``plugin`` (Nav2) or ``type`` (ROS 1) is an InflationLayer
  (without a ``plugins`` list, Nav2's default layer ``inflation_layer``), its ``inflation_radius`` (default 0.55 m)
  and ``cost_scaling_factor`` (default 10). None, two, or a disabled one: refused.

Every value is checked by :mod:`spcotmhp.metric.body` (one :class:`~spcotmhp.errors.RobotBodyError` line naming
the file and the key). Values given as options (``--robot-radius``, ``--footprint``, ``--inflation-radius``,
``--cost-scaling-factor``) override the file's (:func:`resolve_body`).
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from spcotmhp.errors import RobotBodyError
from spcotmhp.metric.body import RobotBody, check_radius, circle, polygon, radius_footprint
from spcotmhp.safe_read import excerpt

MAX_PARAMS_BYTES = 1024 * 1024  # Nav2's full nav2_params.yaml is about 15 KB
NAV2_ROBOT_RADIUS = 0.1
NAV2_FOOTPRINT_PADDING = 0.01
NAV2_INFLATION_RADIUS = 0.55
NAV2_COST_SCALING = 10.0
_PAIR = re.compile(r"\[([^\[\]]*)\]")
_NUMBER = re.compile(r"[-+]?(?:[0-9]+\.?[0-9]*|\.[0-9]+)(?:[eE][-+]?[0-9]+)?")  # what a C++ stream reads whole


@dataclass(frozen=True)
class Nav2Body:
    """What a params file says of the body: a footprint (points) or a radius, the padding, the inflation."""

    footprint: Any  # the points as given (checked by the body), or None: a circle of robot_radius
    robot_radius: object
    padding: object
    inflation_radius: object
    cost_scaling_factor: object
    source: str


def read_nav2_params(path: str | Path) -> Nav2Body:
    """The body's keys of a Nav2 params YAML (module docstring); RobotBodyError on a missing or malformed key."""
    from spcotmhp.safe_read import load_yaml

    where = Path(path)
    doc = load_yaml(where, MAX_PARAMS_BYTES, "Nav2 params file", RobotBodyError)
    params = _costmap_section(doc, where)
    source = f"{where} (global_costmap)"
    raw = params.get("footprint", "[]")
    points = parse_footprint(raw, f"{source}: footprint") if raw not in ("[]", "", None, []) else None
    layer = _inflation_layer(params, source)
    return Nav2Body(
        footprint=points,
        robot_radius=params.get("robot_radius", NAV2_ROBOT_RADIUS),
        padding=params.get("footprint_padding", NAV2_FOOTPRINT_PADDING),
        inflation_radius=layer.get("inflation_radius", NAV2_INFLATION_RADIUS),
        cost_scaling_factor=layer.get("cost_scaling_factor", NAV2_COST_SCALING),
        source=source,
    )


def parse_footprint(raw: object, where: str) -> Any:
    """A footprint as Nav2 writes it, the string "[[x, y], [x, y], ...]" (numbers as C++ streams read them:
    0.3, .3, -3e-1), or a YAML list of [x, y] pairs: the points (checked by :func:`spcotmhp.metric.body.polygon`);
    RobotBodyError when the string does not parse."""
    if not isinstance(raw, str):
        return raw  # a list, or refused by the body's checks
    text = raw.strip()
    inner = text[1:-1] if text.startswith("[") and text.endswith("]") else None
    pairs = _PAIR.findall(inner) if inner is not None else []
    if inner is None or _PAIR.sub("", inner).replace(",", "").strip() or not pairs:
        raise RobotBodyError(f'{where} must be a string "[[x, y], [x, y], ...]" (metres), got {raw[:80]!r}')
    points = []
    for pair in pairs:
        values = [v.strip() for v in pair.split(",")]
        if not all(_NUMBER.fullmatch(v) for v in values):  # float() would also take "1_0", "nan", " inf"
            raise RobotBodyError(f"{where}: [{pair[:80]}] is not two numbers [x, y]")
        points.append([float(v) for v in values])
    return points


def resolve_body(
    nav2_params: str | Path | None = None,
    robot_radius: float | None = None,
    footprint: str | None = None,
    inflation_radius: float | None = None,
    cost_scaling_factor: float | None = None,
) -> RobotBody | None:
    """The body the options give (module docstring): the params file's, each value given as an option replacing
    its own; None when nothing is given (keep the model's body). ``robot_radius`` and ``footprint`` exclude each
    other; a radius given as an option is that exact circle, a footprint as an option is unpadded."""
    if robot_radius is not None and footprint is not None:
        raise RobotBodyError("give either --robot-radius or --footprint, not both (a footprint sets both radii)")
    if nav2_params is None and robot_radius is None and footprint is None:
        if inflation_radius is None and cost_scaling_factor is None:
            return None
        from spcotmhp.metric.costmap import DEFAULT_COSTMAP

        robot_radius = DEFAULT_COSTMAP.inscribed_radius  # the inflation changed, the default robot kept
    base = read_nav2_params(nav2_params) if nav2_params is not None else None
    inflation = (
        inflation_radius
        if inflation_radius is not None
        else (base.inflation_radius if base is not None else _default("inflation_radius"))
    )
    scaling = (
        cost_scaling_factor
        if cost_scaling_factor is not None
        else (base.cost_scaling_factor if base is not None else _default("cost_scaling_factor"))
    )
    if robot_radius is not None:
        return circle(robot_radius, inflation, scaling, "--robot-radius")
    if footprint is not None:
        return polygon(parse_footprint(footprint, "--footprint"), inflation, scaling, "--footprint")
    assert base is not None  # one of the three is given
    if not (isinstance(base.padding, (int, float)) and not isinstance(base.padding, bool) and 0 <= base.padding <= 1):
        raise RobotBodyError(f"{base.source}: footprint_padding must be a number in [0, 1] m, got {base.padding!r}")
    if base.footprint is None:
        points: Any = radius_footprint(check_radius(base.robot_radius, base.source, "robot_radius"))
    else:
        points = base.footprint
    return polygon(points, inflation, scaling, base.source, padding=float(base.padding))


def _default(name: str) -> float:
    from spcotmhp.metric.costmap import DEFAULT_COSTMAP

    return float(getattr(DEFAULT_COSTMAP, name))


def _costmap_section(doc: Any, path: Path) -> dict:
    """The parameters of the global costmap (module docstring)."""
    if not isinstance(doc, dict):
        raise RobotBodyError(f"Nav2 params file {path} must hold a mapping (global_costmap: ...)")
    section = doc.get("global_costmap")
    if section is None:
        if "robot_radius" in doc or "footprint" in doc:
            return doc  # ROS 1's costmap_common_params.yaml
        keys = ", ".join(sorted(str(k) for k in doc)[:8])
        raise RobotBodyError(f"Nav2 params file {path} has no global_costmap section (its top-level keys: {keys})")
    for key in ("global_costmap", "ros__parameters"):
        if isinstance(section, dict) and key in section:
            if not isinstance(section[key], dict):  # else its keys would be missed and Nav2's defaults taken
                raise RobotBodyError(f"Nav2 params file {path}: {key} must be a mapping of parameters")
            section = section[key]
    if not isinstance(section, dict):
        raise RobotBodyError(f"Nav2 params file {path}: global_costmap must be a mapping of parameters")
    return section


def _inflation_layer(params: dict, source: str) -> dict:
    """The inflation layer's parameters (module docstring)."""
    plugins = params.get("plugins")
    if plugins is None:
        return _layer(params, "inflation_layer", source)
    given = [p.get("name") if isinstance(p, dict) else p for p in plugins] if isinstance(plugins, list) else None
    if given is None or not all(isinstance(n, str) for n in given):
        shown = excerpt(plugins if given is None else next(n for n in given if not isinstance(n, str)))
        raise RobotBodyError(f"{source}: plugins must be a list of layer names, got {shown}")
    names = [str(n) for n in given]
    kinds = {p["name"]: p.get("type", "") for p in plugins if isinstance(p, dict)}
    found = []
    for name in names:
        layer = _layer(params, name, source)
        kind = kinds.get(name) or layer.get("plugin", "")
        if isinstance(kind, str) and kind.endswith("InflationLayer"):
            found.append((name, layer))
    if len(found) != 1:
        raise RobotBodyError(
            f"{source}: {'no' if not found else 'more than one'} inflation layer among the plugins "
            f"{', '.join(map(str, names))}; a body needs exactly one (its inflation_radius and cost_scaling_factor), "
            "or give --inflation-radius and --cost-scaling-factor with --robot-radius or --footprint"
        )
    name, layer = found[0]
    enabled = layer.get("enabled", True)
    if not isinstance(enabled, bool):
        raise RobotBodyError(f"{source}: {name}.enabled must be true or false, got {excerpt(enabled)}")
    if not enabled:
        raise RobotBodyError(f"{source}: the inflation layer {name} is disabled (enabled: false)")
    return layer


def _layer(params: dict, name: str, source: str) -> dict:
    """The parameters of the layer ``name`` ({} when absent: Nav2's defaults); a value that is not a mapping is
    refused (its inflation_radius would be missed silently)."""
    layer = params.get(name, {})
    if not isinstance(layer, dict):
        raise RobotBodyError(f"{source}: {name} must be a mapping of the layer's parameters, got {excerpt(layer)}")
    return layer
