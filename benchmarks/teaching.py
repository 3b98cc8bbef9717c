"""Teaching that never stalls planning (issue 24): teach latency, and plan latency while teaches are applied.

    python benchmarks/teaching.py                 # supervised 3LDK_06; HTTP service and in-process
    python benchmarks/teaching.py --ros           # also the ROS 2 node (needs the ros2 extra)

In-process (same run, same spots): one teach and the planner after it, with the planning graph updated
incrementally (``PlanningGraph.update``: only new or moved nodes' fields) against a full build (the baseline).
HTTP (`spcotmhp serve` in a subprocess): warm ``POST /teach`` latency; ``POST /plan`` latency unloaded, then while
another client sends teaches without pause (each teach makes a new place; the model grows), and the difference of
the medians. ROS 2 (`spcotmhp ros2` in a subprocess, discovery on this machine only): instruction-to-Path latency
unloaded and while teaches are published without pause. Teach spots are free cells drawn from a seeded stream.
"""

from __future__ import annotations

import argparse
import json
import statistics
import sys
import tempfile
import threading
import time
import warnings
from pathlib import Path

import httpx
import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # the repository root: tests/helpers
from tests.helpers.server import ServerProcess, start_near, supervised_model_dir  # noqa: E402

INSTRUCTIONS = ["go to the kitchen", "go to the bedroom via the corridor", "go to the bath", "go to the toilet"]


def spots(model, n: int, seed: int = 0) -> np.ndarray:
    """``n`` free cells of the robot (inflated cost map finite), drawn from a seeded stream."""
    from spcotmhp.metric.costmap import inflate

    safe = np.argwhere(np.isfinite(inflate(model.map, **model.costmap).log_p))
    pick = np.random.default_rng(seed).choice(len(safe), size=n, replace=False)
    return model.map.cell_to_world(safe[pick])


def name(i: int) -> str:
    return "annex " + "".join(chr(ord("a") + int(d)) for d in str(i))


def in_process(model, xy: np.ndarray) -> dict:
    from spcotmhp.planning.graph_cache import GraphCache
    from spcotmhp.planning.planner import HierarchicalPlanner
    from spcotmhp.teaching.teach import planner_for, teach

    base = HierarchicalPlanner(model)
    base.warm_up()
    inc, full = [], []
    for i, (x, y) in enumerate(xy):
        t0 = time.perf_counter()
        taught = teach(model, [{"x": float(x), "y": float(y), "utterance": f"this is the {name(i)}"}])
        planner_for(taught.model, previous=base, cache=GraphCache())
        inc.append(time.perf_counter() - t0)
        t0 = time.perf_counter()
        taught = teach(model, [{"x": float(x), "y": float(y), "utterance": f"this is the {name(i)}"}])
        planner_for(taught.model, cache=GraphCache())
        full.append(time.perf_counter() - t0)
    return {
        "teach_incremental_ms": 1000 * statistics.median(inc),
        "teach_full_build_ms": 1000 * statistics.median(full),
    }


def http(folder: Path, model, xy: np.ndarray, plans: int) -> dict:
    start = start_near(model)
    bodies = [{"instruction": INSTRUCTIONS[i % len(INSTRUCTIONS)], "start": start} for i in range(plans)]
    with ServerProcess([str(folder)]) as server, httpx.Client(base_url=server.url, timeout=30) as client:
        for b in bodies[:10]:
            client.post("/plan", json=b)

        def plan_latencies() -> list[float]:
            out = []
            for b in bodies:
                t0 = time.perf_counter()
                assert client.post("/plan", json=b).status_code == 200
                out.append(time.perf_counter() - t0)
            return out

        unloaded = plan_latencies()
        teach_times, stop = [], threading.Event()

        def teacher() -> None:
            with httpx.Client(base_url=server.url, timeout=30) as other:
                i = 0
                while not stop.is_set() and i < len(xy):
                    x, y = xy[i]
                    t0 = time.perf_counter()
                    r = other.post("/teach", json={"utterance": f"this is the {name(i)}", "x": x, "y": y})
                    if r.status_code == 200:
                        teach_times.append(time.perf_counter() - t0)
                    i += 1

        worker = threading.Thread(target=teacher)
        worker.start()
        loaded = plan_latencies()
        stop.set()
        worker.join()
    return {
        "teach_median_ms": 1000 * statistics.median(teach_times[1:]),
        "teaches": len(teach_times),
        "plan_unloaded_median_ms": 1000 * statistics.median(unloaded),
        "plan_during_teaches_median_ms": 1000 * statistics.median(loaded),
        "plan_during_teaches_p95_ms": 1000 * float(np.percentile(loaded, 95)),
    }


def ros(folder: Path, model, xy: np.ndarray, plans: int) -> dict:
    """Instruction-to-Path latency of `spcotmhp ros2 FOLDER`, unloaded and while teaches are published."""
    import os
    import subprocess

    import rclpy
    from geometry_msgs.msg import PoseWithCovarianceStamped
    from nav_msgs.msg import Path as PathMsg
    from rclpy.executors import SingleThreadedExecutor
    from rclpy.node import Node
    from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy
    from std_msgs.msg import String

    latched = QoSProfile(depth=1, reliability=ReliabilityPolicy.RELIABLE, durability=DurabilityPolicy.TRANSIENT_LOCAL)
    env = {"ROS_AUTOMATIC_DISCOVERY_RANGE": "LOCALHOST", "ROS_DOMAIN_ID": str(40 + os.getpid() % 50)}
    os.environ.update(env)
    exe = str(Path(sys.executable).with_name("spcotmhp"))
    proc = subprocess.Popen([exe, "ros2", str(folder)], env={**os.environ, **env}, stdout=subprocess.DEVNULL,
                            stderr=subprocess.DEVNULL)  # fmt: skip
    context = rclpy.Context()
    rclpy.init(context=context)
    node = Node("teaching_bench", context=context)
    executor = SingleThreadedExecutor(context=context)
    executor.add_node(node)
    paths: list[float] = []
    taught: list[dict] = []
    node.create_subscription(PathMsg, "/spcotmhp/plan", lambda m: paths.append(time.perf_counter()), latched)
    node.create_subscription(
        String, "/spcotmhp/status", lambda m: taught.append(json.loads(m.data)) if '"taught"' in m.data else None, 50
    )
    pose_pub = node.create_publisher(PoseWithCovarianceStamped, "/amcl_pose", latched)
    ins_pub = node.create_publisher(String, "/spcotmhp/instruction", 10)
    teach_pub = node.create_publisher(String, "/spcotmhp/teach", 10)

    def spin_until(done, timeout: float) -> bool:
        end = time.perf_counter() + timeout
        while time.perf_counter() < end and not done():
            executor.spin_once(timeout_sec=0.005)
        return bool(done())

    try:
        assert spin_until(lambda: ins_pub.get_subscription_count() > 0, 120), "the node did not start"
        pose = PoseWithCovarianceStamped()
        pose.header.frame_id = "map"
        pose.pose.pose.position.x, pose.pose.pose.position.y = start_near(model)
        pose.pose.pose.orientation.w = 1.0
        pose_pub.publish(pose)
        spin_until(lambda: False, 1.0)

        def latencies() -> list[float]:
            out = []
            for i in range(plans):
                n = len(paths)
                t0 = time.perf_counter()
                ins_pub.publish(String(data=INSTRUCTIONS[i % len(INSTRUCTIONS)]))
                assert spin_until(lambda n=n: len(paths) > n, 30), "no path"
                out.append(paths[n] - t0)
            return out

        latencies()  # warm
        unloaded = latencies()
        stop = threading.Event()

        def teacher() -> None:
            i = 0
            while not stop.is_set():
                teach_pub.publish(String(data=f"this is the {name(i)}"))
                i += 1
                time.sleep(0.05)

        worker = threading.Thread(target=teacher)
        worker.start()
        loaded = latencies()
        stop.set()
        worker.join()
        spin_until(lambda: False, 1.0)
    finally:
        node.destroy_node()
        context.try_shutdown()
        proc.terminate()
        proc.wait(20)
    applied = [t for t in taught if t.get("ok")]
    return {
        "unloaded_median_ms": 1000 * statistics.median(unloaded),
        "during_teaches_median_ms": 1000 * statistics.median(loaded),
        "during_teaches_p95_ms": 1000 * float(np.percentile(loaded, 95)),
        "teaches_applied": len(applied),
        "teaches_refused_busy": sum(t.get("type") == "TeachingBusy" for t in taught),
        "teach_update_median_ms": 1000 * statistics.median([t["time_planner_s"] for t in applied]) if applied else None,
    }


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--teaches", type=int, default=20)
    ap.add_argument("--plans", type=int, default=100)
    ap.add_argument("--ros", action="store_true")
    args = ap.parse_args()
    from spcotmhp.persistence.io import load_model

    with tempfile.TemporaryDirectory() as tmp, warnings.catch_warnings():
        warnings.simplefilter("ignore")
        folder = supervised_model_dir("3LDK_06", Path(tmp) / "m")
        model = load_model(folder)
        xy = spots(model, max(args.teaches, 200))
        out = {"in_process": in_process(model, xy[: args.teaches]), "http": http(folder, model, xy, args.plans)}
        if args.ros:
            out["ros2"] = ros(folder, model, xy, args.plans)
    p, h = out["in_process"], out["http"]
    print(json.dumps(out, indent=1))
    if "ros2" in out:
        r = out["ros2"]
        print(
            f"ROS 2: instruction-to-Path median {r['unloaded_median_ms']:.1f} ms unloaded, "
            f"{r['during_teaches_median_ms']:.1f} ms while teaches are applied "
            f"(+{r['during_teaches_median_ms'] - r['unloaded_median_ms']:.1f} ms; {r['teaches_applied']} applied)"
        )
    print(
        f"in-process teach + planner: incremental {p['teach_incremental_ms']:.0f} ms, full build "
        f"{p['teach_full_build_ms']:.0f} ms (ratio {p['teach_full_build_ms'] / p['teach_incremental_ms']:.1f}x)\n"
        f"HTTP: warm /teach median {h['teach_median_ms']:.0f} ms over {h['teaches']} teaches; /plan median "
        f"{h['plan_unloaded_median_ms']:.1f} ms unloaded, {h['plan_during_teaches_median_ms']:.1f} ms during teaches "
        f"(+{h['plan_during_teaches_median_ms'] - h['plan_unloaded_median_ms']:.1f} ms, ratio "
        f"{h['plan_during_teaches_median_ms'] / h['plan_unloaded_median_ms']:.2f})"
    )


if __name__ == "__main__":
    main()
