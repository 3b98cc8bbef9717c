"""docs/ros2.md's launch files, as typed (issue 36: "a launch file that a user can run next to nav2_bringup as is").

ROS 2's ``launch`` package has no wheel, so ``ros2 launch`` cannot run here. What can be checked is everything the
file says: its code runs against the two ``launch`` names it uses, held to their signatures in ROS 2 Jazzy
(``LaunchDescription(initial_entities)``; ``ExecuteProcess(*, cmd, output)``, keyword-only, ``output`` one of
launch's values), ``generate_launch_description()`` gives one ExecuteProcess, and its command, run as ``ros2
launch`` would run it (in the folder the page's commands run in, where ``m06`` is), starts the node: beside the
stand-in Nav2 (which is also AMCL) it plans an instruction, and the driving file's node drives it to the end.
What is not checked: ``ros2 launch`` itself and Nav2 (docs/ros2.md, "Not tested here"). Skipped without the extra
ros2; with it, fails (naming `make nav2-msgs`) when nav2_msgs was not built."""

from __future__ import annotations

import os
import shlex
import shutil
import subprocess
import sys
import types
from pathlib import Path
from typing import Any

import pytest

pytest.importorskip("rclpy")

from tests.ros.nav2_client import EXE, DriveClient, node_ready, standin, stop_node  # noqa: E402
from tests.test_readme import ROOT, parse  # noqa: E402

DOMAIN = str(15 + (os.getpid() + 2) % 5)  # test_drive's range (15..19), not at the same time as its module
START = (-3.9, -3.5)  # the README's start in 3LDK_06
OUTPUTS = ("log", "screen", "both", "own_log")  # launch.actions.ExecuteProcess's accepted ``output`` values
PAGE = parse((ROOT / "docs" / "ros2.md").read_text(encoding="utf-8"))
LAUNCH_FILES = [b for b in PAGE if "generate_launch_description" in b.text]


class LaunchDescription:
    """launch.LaunchDescription's constructor: a list of entities (actions)."""

    def __init__(self, initial_entities: list[Any] | None = None, *, deprecated_reason: str | None = None) -> None:
        self.entities = list(initial_entities or [])


class ExecuteProcess:
    """launch.actions.ExecuteProcess's constructor, for the arguments a launch file may give it (keyword-only)."""

    def __init__(self, *, cmd: list[str], output: str = "log", name: str | None = None, cwd: str | None = None,
                 env: dict | None = None, additional_env: dict | None = None, shell: bool = False,
                 emulate_tty: bool = False) -> None:  # fmt: skip
        assert isinstance(cmd, list) and all(isinstance(a, str) for a in cmd) and cmd, cmd
        assert output in OUTPUTS, output
        self.cmd, self.output, self.cwd, self.shell = cmd, output, cwd, shell


def described(text: str) -> list[ExecuteProcess]:
    """Run a launch file's code with the stand-in ``launch`` names; the actions of its description."""
    launch = types.ModuleType("launch")
    actions = types.ModuleType("launch.actions")
    launch.LaunchDescription = LaunchDescription  # type: ignore[attr-defined]
    actions.ExecuteProcess = ExecuteProcess  # type: ignore[attr-defined]
    launch.actions = actions  # type: ignore[attr-defined]
    saved = {k: sys.modules.get(k) for k in ("launch", "launch.actions")}
    sys.modules.update({"launch": launch, "launch.actions": actions})
    try:
        scope: dict[str, Any] = {"__name__": "spcotmhp_launch"}
        exec(compile(text, "spcotmhp_launch.py", "exec"), scope)  # noqa: S102 - the page's own code
        description = scope["generate_launch_description"]()
    finally:
        for k, v in saved.items():
            sys.modules.pop(k) if v is None else sys.modules.__setitem__(k, v)
    assert isinstance(description, LaunchDescription)
    return description.entities


def test_the_page_has_both_launch_files_and_each_says_why_it_is_not_run():
    assert len(LAUNCH_FILES) == 2
    assert all("ros 2 install" in (b.directive("skip") or "").lower() for b in LAUNCH_FILES)
    assert any("--drive" in b.text for b in LAUNCH_FILES)


@pytest.mark.parametrize("k", range(len(LAUNCH_FILES)), ids=["plans", "drives"][: len(LAUNCH_FILES)])
def test_a_launch_file_starts_the_node_it_describes(k: int, tmp_path: Path, model_3ldk06_dir: Path):
    (process,) = described(LAUNCH_FILES[k].text)
    assert process.output == "screen" and not process.shell and process.cwd is None  # ros2 launch's folder
    assert process.cmd[:2] == ["spcotmhp", "ros2"], process.cmd
    shutil.copytree(model_3ldk06_dir, tmp_path / "m06")  # the page's folder: the model m06 of the README's Tour
    cmd = [EXE, *process.cmd[1:]]  # `spcotmhp` on the PATH of the venv it was installed in
    args = ("--speed", "3.0", "--x", str(START[0]), "--y", str(START[1]))
    with standin(tmp_path, DOMAIN, *args, client_class=DriveClient) as client:
        env = {k: os.environ[k] for k in ("ROS_AUTOMATIC_DISCOVERY_RANGE", "ROS_DOMAIN_ID", "ROS_LOG_DIR")}
        proc = subprocess.Popen(cmd, cwd=tmp_path, env={**os.environ, **env}, stdout=subprocess.PIPE,
                                stderr=subprocess.PIPE, text=True)  # fmt: skip
        try:
            node_ready(client, proc)
            status0, _ = client.tell("go to the bedroom via the corridor")
            plan = lambda: [s for s in client.status[status0:] if s.get("kind") == "plan"]  # noqa: E731
            assert client.spin_until(lambda: bool(plan()) or bool(client.errors(status0))), shlex.join(cmd)
            assert not client.errors(status0) and plan()[0]["ok"], client.errors(status0)
            if "--drive" in process.cmd:
                client.until_drive(status0, "arrived")
                assert client.spin_until(lambda: any(s["final"] for s in client.drive_events(status0, "arrived")))
        finally:
            stop_node(proc)
