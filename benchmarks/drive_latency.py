"""Instruction to Nav2 goal: how long from an instruction published on /spcotmhp/instruction until the stand-in
Nav2 (spcotmhp.ros.standin_nav2) accepts the node's FollowPath goal, with `spcotmhp ros2 M --drive follow_path`.

    python benchmarks/drive_latency.py               # the supervised 3LDK_06 model, 40 instructions
    python benchmarks/drive_latency.py --n 100

Needs the extra ros2 and nav2_msgs (`make nav2-msgs`). The node, the stand-in and this client are three processes
on this machine (discovery on localhost, a domain of their own). Baseline in the same run: instruction to the Path
received on /spcotmhp/plan (what the node did before driving). The goal time is the stand-in's clock at acceptance,
the instruction's this process's (one machine, one clock). Each instruction pre-empts the goal before it.
"""

from __future__ import annotations

import argparse
import os
import statistics
import sys
import tempfile
import time
import warnings
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # the repository root: tests/ros helpers

INSTRUCTIONS = ["go to the kitchen", "go to the bedroom via the corridor", "go to the bath", "go to the living"]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--n", type=int, default=40, help="instructions to time (default 40)")
    args = parser.parse_args()
    from spcotmhp.datasets.bundled import load_bundled
    from spcotmhp.learning.supervised import fit_supervised
    from spcotmhp.persistence.io import save_model
    from tests.ros.nav2_client import DriveClient, node_ready, standin, start_node, stop_node

    root = Path(tempfile.mkdtemp(prefix="drive-bench-"))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        folder = save_model(fit_supervised(load_bundled("3LDK_06")), root / "model")
    domain = str(60 + os.getpid() % 30)
    with standin(root, domain, "--speed", "0.5", "--x", "-3.9", "--y", "-3.5", client_class=DriveClient) as c:
        env = {k: os.environ[k] for k in ("ROS_AUTOMATIC_DISCOVERY_RANGE", "ROS_DOMAIN_ID", "ROS_LOG_DIR")}
        proc = start_node(folder, env)
        try:
            node_ready(c, proc)
            to_goal, to_path, to_request = [], [], []
            for i in range(args.n):
                plans, events = len(c.plans), len(c.events)
                sent = time.time()
                c.say.publish(_string(INSTRUCTIONS[i % len(INSTRUCTIONS)]))
                assert c.spin_until(lambda: len(c.plans) > plans)  # noqa: B023
                to_path.append(time.time() - sent)
                goal = c.event("goal", events)
                to_goal.append(goal["t"] - sent)
                to_request.append(goal["received_t"] - sent)
                c.spin_until(lambda: False, 0.3)
        finally:
            stop_node(proc)
    print(f"{args.n} instructions on 3LDK_06, load average {os.getloadavg()[0]:.1f}")
    print(f"{'':38} {'median ms':>10} {'p90 ms':>8} {'max ms':>8}")
    rows = (("instruction -> Path received", to_path), ("instruction -> goal request at server", to_request),
            ("instruction -> goal accepted", to_goal))  # fmt: skip
    for name, xs in rows:
        p90 = sorted(xs)[int(0.9 * (len(xs) - 1))]
        print(f"{name:38} {1e3 * statistics.median(xs):10.1f} {1e3 * p90:8.1f} {1e3 * max(xs):8.1f}")
    print(f"ratio goal / Path (medians): {statistics.median(to_goal) / statistics.median(to_path):.2f}")


def _string(text: str):
    from std_msgs.msg import String

    return String(data=text)


if __name__ == "__main__":
    main()
