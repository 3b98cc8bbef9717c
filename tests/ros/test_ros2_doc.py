"""docs/ros2.md runs as typed (issue 36): its shell and Python blocks, read from the page itself (so that page and
test cannot drift), run in page order in one clean folder by the README test's machinery (tests/test_readme.py:
the same ``<!-- readme-test: ... -->`` directives, text blocks listing lines the output must hold, the block's
ROS_DOMAIN_ID replaced by one of this run). What the page assumes from the README's Tour is put in the folder
first: the model ``m06`` (here the supervised fit of 3LDK_06, which has the Tour's place names; the Tour's ``m06``
is an unsupervised fit that takes minutes) and ``examples/`` (``spcotmhp examples``). The launch files are left out
of that run (they need ``ros2 launch``, which has no wheel), each saying so, and run by test_launch_files.py; the
two blocks that start a node running until stopped are started here as typed and stopped with SIGINT. Nothing is
skipped but with the extra ros2 missing."""

from __future__ import annotations

import contextlib
import os
import shutil
import signal
import subprocess
import sys
from pathlib import Path

import pytest

from tests.test_readme import ROOT, Workspace, parse, run_block

pytest.importorskip("rclpy")

DOC = ROOT / "docs" / "ros2.md"
BLOCKS = parse(DOC.read_text(encoding="utf-8"))


def _left_out(k: int) -> bool:
    """A block the page's run leaves out (a skip directive), or a text block showing such a block's output."""
    if BLOCKS[k].lang == "text":
        k = next((j for j in range(k - 1, -1, -1) if BLOCKS[j].runnable), k)
    return BLOCKS[k].directive("skip") is not None


# the blocks left out are run by the tests of their own below and in test_launch_files.py, not skipped here
CHECKED = [k for k, b in enumerate(BLOCKS) if b.lang in ("bash", "python", "text") and not _left_out(k)]


@pytest.fixture(scope="module")
def workspace(tmp_path_factory, model_3ldk06_dir: Path) -> Workspace:
    folder = tmp_path_factory.mktemp("ros2-doc")
    shutil.copytree(model_3ldk06_dir, folder / "m06")
    exe = str(Path(sys.executable).with_name("spcotmhp"))
    subprocess.run([exe, "examples"], cwd=folder, check=True, capture_output=True, timeout=300)
    return Workspace(folder, BLOCKS)


@pytest.mark.parametrize("k", CHECKED, ids=[BLOCKS[k].name for k in CHECKED])
def test_block_runs_as_typed(k: int, workspace: Workspace):
    run_block(workspace, k)


def test_the_drive_client_is_run_and_checked():
    """The stand-in's block is run (not left out) and a text block checks that the robot arrived."""
    drive = next(k for k, b in enumerate(BLOCKS) if "python drive.py" in b.text)
    assert BLOCKS[drive].directive("skip") is None and BLOCKS[drive].directive("needs") == "ros2"
    assert BLOCKS[drive + 1].lang == "text" and '"event": "arrived"' in BLOCKS[drive + 1].text
    assert any(b.directive("file") == "drive.py" for b in BLOCKS[:drive])


def test_the_page_shows_tell_py_as_spcotmhp_examples_writes_it():
    from spcotmhp.datasets.bundled import data_root

    shown = next(b for b in BLOCKS if b.directive("file") == "examples/tell.py")
    assert shown.text == (data_root() / "examples" / "tell.py").read_text(encoding="utf-8")


UNTIL_STOPPED = [k for k, b in enumerate(BLOCKS) if "the node runs until stopped" in (b.directive("skip") or "")]


@pytest.mark.parametrize("k", UNTIL_STOPPED, ids=[BLOCKS[k].name for k in UNTIL_STOPPED])
def test_a_node_that_runs_until_stopped_starts_as_typed_and_stops_on_sigint(k: int, workspace: Workspace):
    """The blocks left out of the run because the node they start runs until stopped (``--drive``, a footprint):
    each is started as typed in the page's folder (after the blocks before it), must say it is ready, and must
    stop cleanly (exit 0) on SIGINT, as Ctrl+C stops it."""
    workspace.run_through(k - 1)
    env = {**workspace.env, "ROS_AUTOMATIC_DISCOVERY_RANGE": "LOCALHOST", "ROS_DOMAIN_ID": str(90 + os.getpid() % 11)}
    proc = subprocess.Popen(["bash", "-e", "-c", BLOCKS[k].text], cwd=workspace.folder, env=env, text=True,
                            stdout=subprocess.PIPE, stderr=subprocess.STDOUT, start_new_session=True)  # fmt: skip
    lines: list[str] = []
    try:
        assert proc.stdout is not None
        for line in proc.stdout:  # until the node says it is ready, or ends
            lines.append(line)
            if "spcotmhp node ready" in line:
                break
        assert any("spcotmhp node ready" in s for s in lines), "".join(lines)[-3000:]
        os.killpg(proc.pid, signal.SIGINT)
        rest, _ = proc.communicate(timeout=60)
        assert proc.returncode == 0, "".join(lines)[-2000:] + rest[-2000:]
    finally:
        with contextlib.suppress(ProcessLookupError):
            os.killpg(proc.pid, signal.SIGKILL)
        proc.wait(10)


def test_every_block_left_out_is_run_by_a_test_of_its_own():
    """No block of the page escapes: each one the run leaves out is a launch file (tests/ros/test_launch_files.py)
    or a node that runs until stopped (the test above)."""
    from tests.ros.test_launch_files import LAUNCH_FILES

    left_out = [k for k, b in enumerate(BLOCKS) if b.directive("skip") is not None]
    launch = [k for k in left_out if any(BLOCKS[k].text == b.text for b in LAUNCH_FILES)]
    assert left_out and sorted(launch + UNTIL_STOPPED) == left_out, (left_out, launch, UNTIL_STOPPED)
