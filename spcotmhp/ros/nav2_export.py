"""Exports of a learned map for Nav2: a Route Server graph and keepout masks for the costmap filters.

``route_graph.geojson`` (nav2_route's GeoJsonGraphFileLoader): a FeatureCollection whose nodes are ``Point``
features at the places' candidate points (the point Algorithm 1 plans to: the place's mean moved to the nearest
cell of its territory the robot fits in), properties ``id``, ``frame`` and ``metadata`` ``{name, words, place}``,
and whose edges are ``MultiLineString`` features along the partial paths of Eq. 27 between connected places
(Figure 3's graph, the planner's ``graph.connected``), one per direction (edges are directed and the two
directions' paths may differ), properties ``id``, ``startid``, ``endid``, ``cost`` (the path's length in metres)
and ``overridable`` false, so that the Route Server's scorers keep that length instead of the straight-line
distance between the nodes. Ids are unique across nodes and edges and at most 65535 (ComputeRoute takes
16-bit ids). The loader reads only the nodes' coordinates and the edges' ids and costs: its dense path joins
nodes with straight lines, which may cross walls between rooms, so send the route's nodes to the planner
server (the README's "On your robot").

``keepout.yaml`` + ``keepout.pgm`` (with places to avoid): a map_server mask of the model's map's size,
resolution and origin, occupied (100) on the territories of the avoided places (the cells the planner blocks
for "avoid the kitchen": :func:`~spcotmhp.planning.avoid.avoided_view`) and free elsewhere; served by a second
map_server with costmap_filter_info_server type 0 (keepout), base 0, multiplier 1 (README.md beside it).

A building's model exports one route graph per floor and the connectors between them
(:func:`spcotmhp.ros.nav2_building.export_building`).
"""

from __future__ import annotations

import json
from collections.abc import Sequence
from pathlib import Path

import numpy as np

from spcotmhp.errors import InstructionError, ModelError, SpcotmhpError
from spcotmhp.metric.map_io import save_map
from spcotmhp.metric.maps import OccupancyMap
from spcotmhp.planning.assemble import path_length
from spcotmhp.planning.planner import HierarchicalPlanner
from spcotmhp.safe_write import build_folder, outside_model, same_file

ROUTE_GRAPH = "route_graph.geojson"
KEEPOUT = "keepout"
EXPORT_FILES = (ROUTE_GRAPH, "README.md", f"{KEEPOUT}.yaml", f"{KEEPOUT}.pgm")
MAX_ID = 65535


def route_graph(planner: HierarchicalPlanner, frame: str = "map") -> dict:
    """The Route Server graph of ``planner``'s places (module docstring) as a GeoJSON dict."""
    graph, model = planner.graph, planner.model
    node_of: dict[int, int] = {}
    for n, k in enumerate(graph.node_place.tolist()):
        node_of.setdefault(int(k), n)  # the first candidate of each place
    places = sorted(node_of)
    features: list[dict] = []
    fid: dict = {}
    for k in places:
        x, y = model.require_map().cell_to_world(graph.to_map(graph.node_cell[node_of[k]]))
        fid[k] = len(features)
        name = planner.shown[k]
        features.append(
            {
                "type": "Feature",
                "geometry": {"type": "Point", "coordinates": [_m(x), _m(y)]},
                "properties": {
                    "id": fid[k],
                    "frame": frame,
                    "metadata": {"name": name, "words": planner.names[k].split(), "place": k},
                },
            }
        )
    for a in places:
        for b in places:
            i, j = node_of[a], node_of[b]
            if a == b or not graph.connected[a, b] or not np.isfinite(graph.w_hat[i, j]):
                continue
            cells = graph.to_map(graph.edge_path(i, j))
            line = [[_m(x), _m(y)] for x, y in model.require_map().cell_to_world(cells)]
            features.append(
                {
                    "type": "Feature",
                    "geometry": {"type": "MultiLineString", "coordinates": [line]},
                    "properties": {
                        "id": len(features),
                        "startid": fid[a],
                        "endid": fid[b],
                        "cost": _m(path_length(cells, model.require_map().resolution)),
                        "overridable": False,
                        "metadata": {"from": planner.shown[a], "to": planner.shown[b]},
                    },
                }
            )
    if len(features) == len(places):
        raise ModelError(
            "no two connected places are joined by a free path: a route graph needs an edge (the "
            "Route Server refuses a graph without)"
        )
    if len(features) - 1 > MAX_ID:
        raise ModelError(f"the route graph has {len(features)} nodes and edges; ids must stay <= {MAX_ID}")
    return {
        "type": "FeatureCollection",
        "name": "spcotmhp",
        "crs": {"type": "name", "properties": {"name": "urn:ogc:def:crs:EPSG::3857"}},
        "features": features,
    }


def keepout_mask(planner: HierarchicalPlanner, avoid: Sequence[str]) -> tuple[OccupancyMap, list[int]]:
    """The keepout mask of the places named in ``avoid`` (each a place's name, e.g. "kitchen") and the places;
    a name that names no place is the planner's InstructionError, saying it was a place to avoid."""
    avoided = np.zeros(planner.model.K, dtype=bool)
    for words in avoid:
        try:
            avoided |= planner.places_named(words)
        except InstructionError as exc:  # places_named reads the words as a goal; here they name a place to avoid
            raise type(exc)(f"place to avoid (--avoid) {words!r}: {str(exc).removeprefix('goal: ')}") from None
    occ = planner.model.require_map()
    data = np.zeros(occ.shape, dtype=np.int8)
    for graph in (planner.graph, *planner.graph.regions.values()):  # the territories in every free region
        (r0, c0), (h, w) = graph.offset, graph.territory.shape
        data[r0 : r0 + h, c0 : c0 + w][np.isin(graph.territory, np.flatnonzero(avoided))] = 100
    mask = OccupancyMap(data=data, resolution=occ.resolution, origin=(occ.origin[0], occ.origin[1], 0.0))
    return mask, [int(k) for k in np.flatnonzero(avoided)]


def export_nav2(
    model_dir: str | Path,
    out: str | Path,
    avoid: Sequence[str] = (),
    frame: str = "map",
    overwrite: bool = False,
) -> str:
    """Write ``out``/route_graph.geojson, README.md and, with ``avoid``, keepout.yaml + keepout.pgm; the folder
    is built beside ``out`` and swapped in. ``out`` must be absent, an empty folder or (with ``overwrite``) an
    earlier export. Returns a one-line summary."""
    from spcotmhp.persistence.io import load_model

    out = Path(out)
    check_target(out, Path(model_dir), overwrite)
    planner = HierarchicalPlanner(load_model(model_dir))
    doc = route_graph(planner, frame)
    mask, avoided = keepout_mask(planner, avoid) if avoid else (None, [])

    def fill(folder: Path) -> None:
        (folder / ROUTE_GRAPH).write_text(json.dumps(doc, ensure_ascii=False), encoding="utf-8")
        if mask is not None:
            save_map(mask, folder / KEEPOUT)
        (folder / "README.md").write_text(readme(frame, [planner.shown[k] for k in avoided]), encoding="utf-8")

    build_folder(out, fill)
    n_nodes = sum(f["geometry"]["type"] == "Point" for f in doc["features"])
    text = f"wrote {out}: route graph of {n_nodes} places and {len(doc['features']) - n_nodes} directed edges"
    if mask is not None:
        text += (
            f"; keepout mask of {', '.join(sorted({planner.shown[k] for k in avoided}))} "
            f"({int((mask.data == 100).sum())} cells)"
        )
    return text


def check_target(out: Path, model_dir: Path, overwrite: bool, allowed: Sequence[str] = EXPORT_FILES) -> None:
    if out.is_symlink() or (out.exists() and not out.is_dir()):
        raise SpcotmhpError(f"--out {out} exists and is not a folder; give a folder")
    if model_dir.exists() and (same_file(out, model_dir) or model_dir.resolve().is_relative_to(out.resolve())):
        raise SpcotmhpError(f"--out {out} would replace the model folder {model_dir}; write elsewhere")
    outside_model(out, model_dir, "--out")
    present = sorted(p.name for p in out.iterdir()) if out.is_dir() else []
    if not present:
        return
    others = [name for name in present if name not in allowed]
    if others:
        raise SpcotmhpError(
            f"--out {out} holds files that are not an export's ({', '.join(others[:5])}); choose an empty or new folder"
        )
    if not overwrite:
        raise SpcotmhpError(f"--out {out} exists; give --overwrite to replace it, or choose another folder")


def _m(value: float) -> float:
    return round(float(value), 4)


def readme(frame: str, avoided: list[str]) -> str:
    """README.md of an export: what the files are and the Nav2 parameters that load them."""
    text = f"""# Nav2 export of a SpCoTMHP model

`{ROUTE_GRAPH}`: Route Server graph (frame `{frame}`). Nodes are the places (metadata `name`, `words`,
`place`); edges follow the learned partial paths between connected places, both directions, `cost` = the path's
length in metres, `overridable: false`. The Route Server joins nodes with straight lines: use the route's
nodes as goals for the planner server rather than its dense path.

```yaml
route_server:
  ros__parameters:
    route_frame: "{frame}"
    graph_filepath: "/path/to/{ROUTE_GRAPH}"
```
"""
    if avoided:
        text += f"""
`{KEEPOUT}.yaml` + `{KEEPOUT}.pgm`: keepout mask (map_server format, the model's map's size, resolution and
origin); occupied = the territories of {", ".join(sorted(set(avoided)))}, free elsewhere. Serve it with a second
map_server and a costmap_filter_info_server with these CostmapFilterInfo parameters:

```yaml
filter_mask_server:
  ros__parameters:
    topic_name: "/keepout_filter_mask"
    yaml_filename: "/path/to/{KEEPOUT}.yaml"
costmap_filter_info_server:
  ros__parameters:
    type: 0                 # keepout
    filter_info_topic: "/costmap_filter_info"
    mask_topic: "/keepout_filter_mask"
    base: 0.0
    multiplier: 1.0
global_costmap:
  global_costmap:
    ros__parameters:
      filters: ["keepout_filter"]
      keepout_filter:
        plugin: "nav2_costmap_2d::KeepoutFilter"
        enabled: true
        filter_info_topic: "/costmap_filter_info"
```
"""
    return text
