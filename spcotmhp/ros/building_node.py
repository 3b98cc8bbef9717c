"""The ROS 2 node on a building's model: the single-floor node (:mod:`spcotmhp.ros.node`) on the current floor,
which a floor topic switches.

Topics, beyond the single-floor node's (which all speak of the current floor: its places, its map, poses in its
map frame):

* ``spcotmhp/floor`` (std_msgs/String, in): the floor the robot is on now, its index or name ("2", "ground"), as
  whatever runs the lift or the stairs says it. The node switches to that floor: its planner, its place markers,
  its map (published on ``spcotmhp/map``); the pose held is dropped (it was on the other floor's map: plans wait
  for a pose on this one, NoValidPose); and when the route being driven continues on that floor, that floor's
  segment is published on ``spcotmhp/plan`` (from the connector's stop).
* ``spcotmhp/current_floor`` (std_msgs/String, out, transient local): ``{"floor": F, "name": ...}`` after every
  switch and at start.
* ``spcotmhp/map`` (nav_msgs/OccupancyGrid, out, transient local): the current floor's map (the model's), for a
  map_server-less Nav2 or RViz; the node still compares ``map`` with it.
* ``spcotmhp/plan`` (nav_msgs/Path): the current floor's segment of the route only; the ``plan`` status line
  carries the whole route (segments with their floors and lengths, the rides, the explanation saying where the
  robot changes floor), ``next_floor`` the floor the segment leads to (null at the goal's floor).
* ``spcotmhp/teach``: taught on the current floor (:func:`~spcotmhp.building.learn.teach_building`); the building's
  planner is made again on the teaching thread and swapped in whole.
"""

from __future__ import annotations

import json
import time
from collections.abc import Callable
from pathlib import Path as FilePath

import numpy as np
from nav_msgs.msg import OccupancyGrid
from std_msgs.msg import String

from spcotmhp.building.learn import teach_building
from spcotmhp.building.plan import BuildingPlan
from spcotmhp.building.planner import BuildingPlanner
from spcotmhp.metric.body import RobotBody
from spcotmhp.metric.maps import OccupancyMap
from spcotmhp.ros.node import EVENTS, LATCHED, SpcotmhpNode, TeachJob, answered, serve
from spcotmhp.ros.shapes import path_poses
from spcotmhp.ros.spinning import ros_running


class BuildingNode(SpcotmhpNode):
    """The node (module docstring) around a :class:`~spcotmhp.building.planner.BuildingPlanner`."""

    def __init__(self, bp: BuildingPlanner, floor: object, frame: str = "map", start_topic: str = "amcl_pose") -> None:
        self.bp = bp
        self.floor = bp.bm.check_floor(floor)
        self.route: BuildingPlan | None = None
        self.leg = 0
        super().__init__(bp.floors[self.floor], frame=frame, start_topic=start_topic)
        self.floor_pub = self.create_publisher(String, "spcotmhp/current_floor", LATCHED)
        self.map_pub = self.create_publisher(OccupancyGrid, "spcotmhp/map", LATCHED)
        self.create_subscription(String, "spcotmhp/floor", self.on_floor, EVENTS)
        self.publish_floor()

    def publish_floor(self) -> None:
        name = self.bp.bm.spec.floor(self.floor).name
        self.floor_pub.publish(String(data=json.dumps({"floor": self.floor, "name": name}, ensure_ascii=False)))
        self.map_pub.publish(
            grid_message(self.planner.model.require_map(), self.frame, self.get_clock().now().to_msg())
        )

    @answered("floor")
    def on_floor(self, msg: String) -> None:
        """Switch to the floor named (module docstring)."""
        floor = self.bp.bm.check_floor(msg.data.strip())
        changed = floor != self.floor
        self.floor, self.planner = floor, self.bp.floors[floor]
        if changed:
            self.poses.forget(f"the robot changed to floor {floor}: the pose held was on another map")
        self.places_pub.publish(self.markers())
        self.publish_floor()
        status: dict = {"kind": "floor", "ok": True, "floor": floor, "name": self.bp.bm.spec.floor(floor).name}
        route = self.route
        later = (
            []
            if route is None
            else [k for k in range(self.leg + 1, len(route.segments)) if route.segments[k].floor == floor]
        )
        if route is not None and later:
            self.leg = later[0]
            seg = route.segments[self.leg]
            points = path_poses(seg.path, seg.cells, seg.path[0], self.planner.model.require_map())
            self.plan_pub.publish(self.path_message(points, 0.0))
            status.update(segment=self.leg, n_poses=len(points), next_floor=self._next_floor())
        self.status(status)

    def _next_floor(self) -> int | None:
        route = self.route
        if route is None or self.leg + 1 >= len(route.segments):
            return None
        return route.segments[self.leg + 1].floor

    @answered("error")
    def on_instruction(self, msg: String) -> None:
        x, y, yaw = self.current_pose("an instruction")
        bp = self.bp
        plan = bp.plan(msg.data, (x, y), self.floor)
        seg = plan.segments[0]
        points = path_poses(seg.path, seg.cells, (x, y), bp.floors[self.floor].model.require_map())
        self.route, self.leg = plan, 0
        self.plan_pub.publish(self.path_message(points, yaw))
        self.status(route_status(plan, msg.data, (x, y), len(points), self.frame, self._next_floor()))

    @answered("taught")
    def _apply_teach(self, job: TeachJob) -> None:
        """Teach on the current floor, make the building's planner again, swap it in (module docstring)."""
        t0 = time.perf_counter()
        floor = self.floor
        updated, taught = teach_building(
            self.bp.bm, [{"x": job.x, "y": job.y, "utterance": job.data, "answer": job.answer}], floor
        )
        bp = BuildingPlanner(updated, self.bp.settings)
        self.bp, self.planner = bp, bp.floors[self.floor]
        self.places_pub.publish(self.markers())
        self.publish_questions()
        self.status({"kind": "taught", "ok": True, "utterance": job.data, "answer": job.answer, "floor": floor,
                     "x": round(job.x, 4), "y": round(job.y, 4), **taught.summary(),
                     "time_planner_s": time.perf_counter() - t0})  # fmt: skip


def route_status(plan: BuildingPlan, instruction: str, start, n_poses: int, frame: str, next_floor: int | None) -> dict:
    """The ``plan`` status line of a route across floors: the whole route, and what the published Path holds."""
    d = plan.to_dict()
    return {
        "kind": "plan",
        "ok": True,
        "instruction": instruction,
        "explanation": plan.explanation,
        "understood": plan.instruction.describe(),
        "places": d["places"],
        "segments": [
            {"floor": s["floor"], "length_m": s["length_m"], "n_points": len(s["path"])} for s in d["segments"]
        ],
        "rides": d["rides"],
        "floor": plan.segments[0].floor,
        "next_floor": next_floor,
        "route_m": d["route_m"],
        "length_m": d["length_m"],
        "time_s": round(plan.time_online_s, 4),
        "start": [round(float(v), 4) for v in start[:2]],
        "frame": frame,
        "n_poses": n_poses,
        "notes": list(plan.notes),
    }


def grid_message(occ: OccupancyMap, frame: str, stamp) -> OccupancyGrid:
    """``occ`` as a nav_msgs/OccupancyGrid (row 0 at the origin, as the map's cells; 0 free, 100 occupied, -1
    unknown)."""
    msg = OccupancyGrid()
    msg.header.frame_id, msg.header.stamp = frame, stamp
    msg.info.resolution = float(occ.resolution)
    msg.info.width, msg.info.height = occ.width, occ.height
    msg.info.origin.position.x, msg.info.origin.position.y = float(occ.origin[0]), float(occ.origin[1])
    msg.info.origin.orientation.w = 1.0
    msg.data = np.clip(np.asarray(occ.data, dtype=np.int16), -1, 100).astype(np.int8).ravel().tolist()
    return msg


def run_building_node(
    model_dir: FilePath,
    floor: str | None,
    frame: str = "map",
    start_topic: str = "amcl_pose",
    progress: Callable[[str], None] = print,
    body: RobotBody | None = None,
) -> None:
    """Load the building's model (``body``: every floor planned for that robot body), precompute every floor's
    planner, and serve until interrupted."""
    from spcotmhp.building.io import load_building_model
    from spcotmhp.errors import UnknownFloor

    t0 = time.perf_counter()
    bm = load_building_model(model_dir, body)
    if floor is None:
        if len(bm.indices) > 1:
            raise UnknownFloor(
                f"a building's model needs --floor F, the floor the robot starts on: {bm.spec.describe_floors()}"
            )
        floor = str(bm.indices[0])
    bp = BuildingPlanner(bm)
    for p in bp.floors.values():
        p.warm_up()
    with ros_running():
        node = BuildingNode(bp, floor, frame=frame, start_topic=start_topic)
        progress(
            f"spcotmhp building node ready in {time.perf_counter() - t0:.1f} s: {len(bm.indices)} floors, on floor "
            f"{node.floor}; plans in frame '{frame}' from {node.resolve_topic_name(start_topic)}"
        )
        serve(node)
