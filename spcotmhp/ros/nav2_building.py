"""Nav2 exports of a building's model: one Route Server graph per floor and the list of connectors between them.

``floor<F>/route_graph.geojson``: floor F's graph as for a single floor (:func:`~spcotmhp.ros.nav2_export.
route_graph` of the floor's planner, in that floor's map frame), plus one node per connector stop on the floor
(metadata ``{connector, kind, stop: true}``) joined both ways to the place whose territory holds the stop, along
the partial path from the stop into that place's candidate point (the reverse direction is the same cells
reversed: the grid's step costs are symmetric), so that the Route Server can route to a stair or lift door.
``connectors.json``: every connector (name, kind, cost_m) with its stops (floor, x, y and ``node``, the stop's id
in that floor's graph; null for a stop no free region with places reaches). A robot switching floors drives the
route to the stop on one floor, rides, loads the next floor's map and graph, and continues from the stop there.
"""

from __future__ import annotations

import json
from collections.abc import Sequence
from pathlib import Path

import numpy as np

from spcotmhp.building.planner import BuildingPlanner
from spcotmhp.building.spec import Connector
from spcotmhp.building.stitch import Endpoint
from spcotmhp.errors import ModelError, SpcotmhpError
from spcotmhp.planning.assemble import path_length
from spcotmhp.planning.planner import HierarchicalPlanner
from spcotmhp.ros.nav2_export import MAX_ID, ROUTE_GRAPH, check_target, route_graph
from spcotmhp.safe_write import build_folder

CONNECTORS = "connectors.json"


def floor_folder(index: int) -> str:
    return f"floor{index}"


def building_route_graphs(bp: BuildingPlanner, frame: str = "map") -> tuple[dict[int, dict], dict]:
    """({floor: route graph GeoJSON}, the connectors document) of the building (module docstring)."""
    graphs: dict[int, dict] = {}
    node_of_stop: dict[int, int] = {}
    for f, planner in bp.floors.items():
        doc = route_graph(planner, frame)
        for stop in bp.stops:
            if stop.floor == f and stop.region == planner.graph.key:
                node_of_stop[stop.id] = _add_stop(doc, planner, stop, bp.bm.spec.connectors[stop.connector])
        graphs[f] = doc
    connectors = [
        {"name": c.name, "kind": c.kind, "cost_m": c.cost_m, "stops": [
            {"floor": s.floor, "x": s.x, "y": s.y, "node": node_of_stop.get(e.id)}
            for s, e in zip(c.stops, [e for e in bp.stops if e.connector == k], strict=True)
        ]}
        for k, c in enumerate(bp.bm.spec.connectors)
    ]  # fmt: skip
    floors = [
        {"index": f.index, "name": f.name, "route_graph": f"{floor_folder(f.index)}/{ROUTE_GRAPH}"}
        for f in bp.bm.spec.floors
    ]
    return graphs, {"building": bp.bm.name, "frame": frame, "floors": floors, "connectors": connectors}


def _point(fid: int, xy, frame: str, metadata: dict) -> dict:
    coords = [round(float(xy[0]), 4), round(float(xy[1]), 4)]
    props = {"id": fid, "frame": frame, "metadata": metadata}
    return {"type": "Feature", "geometry": {"type": "Point", "coordinates": coords}, "properties": props}


def _edge(fid: int, a: int, b: int, line: list, cost: float, metadata: dict) -> dict:
    props = {"id": fid, "startid": a, "endid": b, "cost": cost, "overridable": False, "metadata": metadata}
    return {"type": "Feature", "geometry": {"type": "MultiLineString", "coordinates": [line]}, "properties": props}


def _add_stop(doc: dict, planner: HierarchicalPlanner, stop: Endpoint, connector: Connector) -> int:
    """Append the stop's node and its two edges to ``doc``; returns the node's id."""
    graph, occ = planner.graph, planner.model.require_map()
    features = doc["features"]
    cell = np.array(stop.cell)
    place = int(graph.territory[cell[0], cell[1]])
    nodes = np.flatnonzero(graph.node_place == place)
    if place < 0 or not len(nodes):  # outside every territory: join the nearest candidate point
        nodes = np.array([int(np.argmin(np.hypot(*(graph.node_cell - cell).T)))])
        place = int(graph.node_place[nodes[0]])
    points = [f["properties"] for f in features if f["geometry"]["type"] == "Point"]
    place_id = next(p["id"] for p in points if p["metadata"].get("place") == place)
    sid = len(features)
    meta = {"connector": connector.name, "kind": connector.kind, "stop": True}
    features.append(_point(sid, stop.point, points[0]["frame"], meta))
    cells = np.vstack([stop.escape.reshape(-1, 2), graph.to_map(graph.leg(cell, int(nodes[0])).cells)])
    line = [[round(float(x), 4), round(float(y), 4)] for x, y in occ.cell_to_world(cells)]
    cost = round(float(path_length(cells, occ.resolution)), 4)
    for a, b, coords in ((sid, place_id, line), (place_id, sid, line[::-1])):
        features.append(_edge(len(features), a, b, coords, cost, {"connector": connector.name}))
    if len(features) - 1 > MAX_ID:
        raise ModelError(
            f"floor {stop.floor}'s route graph has {len(features)} nodes and edges; ids must be <= {MAX_ID}"
        )
    return sid


def write_building_export(bp: BuildingPlanner, folder: Path, frame: str) -> tuple[int, int]:
    """Write the per-floor graphs, connectors.json and README.md into ``folder``; returns (floors, connectors)."""
    graphs, connectors = building_route_graphs(bp, frame)
    for f, doc in graphs.items():
        (folder / floor_folder(f)).mkdir()
        (folder / floor_folder(f) / ROUTE_GRAPH).write_text(json.dumps(doc, ensure_ascii=False), encoding="utf-8")
    (folder / CONNECTORS).write_text(json.dumps(connectors, ensure_ascii=False, indent=1), encoding="utf-8")
    (folder / "README.md").write_text(README.format(frame=frame, graph=ROUTE_GRAPH), encoding="utf-8")
    return len(graphs), len(connectors["connectors"])


README = """# Nav2 export of a building's SpCoTMHP model

One Route Server graph per floor, `floorF/{graph}` (frame `{frame}` of that floor's map): the places as nodes,
the learned partial paths between connected places as edges (`cost` in metres, `overridable: false`), and one
node per stair or lift stop on the floor (metadata `connector`, `kind`, `stop: true`) joined both ways to the
place it lies in. `connectors.json` lists the connectors, their cost in metres and, per stop, its floor, its
(x, y) and its node id in that floor's graph.

To go to another floor: route on this floor's graph to the stop's node, ride, load the next floor's map and
graph (`graph_filepath` of the route server, or a route server per floor), and route on from the stop there.
"""


def export_building(
    model_dir: str | Path, out: str | Path, avoid: Sequence[str] = (), frame: str = "map", overwrite: bool = False
) -> str:
    """Write ``out``: a route graph per floor, connectors.json and README.md (module docstring); as
    :func:`~spcotmhp.ros.nav2_export.export_nav2` for a single floor (the folder built beside ``out`` and swapped
    in). Returns a one-line summary."""
    from spcotmhp.building.io import load_building_model

    if avoid:
        raise SpcotmhpError("--avoid (a keepout mask) is for a single floor's model; a building's export has none yet")
    model_dir, out = Path(model_dir), Path(out)
    bm = load_building_model(model_dir)
    check_target(out, model_dir, overwrite, (ROUTE_GRAPH, "README.md", CONNECTORS, *map(floor_folder, bm.indices)))
    planner = BuildingPlanner(bm)
    counts: list[tuple[int, int]] = []
    build_folder(out, lambda folder: counts.append(write_building_export(planner, folder, frame)))
    floors, connectors = counts[0]
    return f"wrote {out}: route graphs of {floors} floors and {connectors} connectors ({CONNECTORS})"
