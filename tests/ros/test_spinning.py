"""spcotmhp/ros/spinning.py: the node's spin ends when its context shuts down even with no wake-up, the clean-up
is bounded, and a node started as a background shell job (SIGINT ignored, ros2/rclpy#527) still stops on
``kill -INT``. Skipped without the extra ros2."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import threading
import time
from pathlib import Path

import pytest

rclpy = pytest.importorskip("rclpy")

from rclpy.node import Node  # noqa: E402

from spcotmhp.ros import spinning  # noqa: E402
from spcotmhp.ros.spinning import SPIN_PERIOD_S, bounded_shutdown, spin_until_shutdown  # noqa: E402
from tests.ros.test_node import ros_environment  # noqa: E402

EXE = str(Path(sys.executable).with_name("spcotmhp"))
DOMAIN = str(20 + os.getpid() % 9)


class DeafExecutor:
    """An executor whose waits are never woken: each spin_once sleeps its whole timeout (a lost wake-up)."""

    def __init__(self) -> None:
        self.timeouts: list[float | None] = []

    def add_node(self, node) -> None:
        pass

    def remove_node(self, node) -> None:
        pass

    def spin_once(self, timeout_sec: float | None = None) -> None:
        self.timeouts.append(timeout_sec)
        assert timeout_sec is not None, "an unbounded wait would never end"
        time.sleep(timeout_sec)


@pytest.fixture
def context():
    context = rclpy.Context()
    rclpy.init(context=context)
    yield context
    context.try_shutdown()


def test_a_shutdown_with_no_wake_up_still_ends_the_spin(context):
    node = Node("spin_test_deaf", context=context)
    executor = DeafExecutor()
    thread = threading.Thread(target=spin_until_shutdown, args=(node, executor), daemon=True)
    thread.start()
    time.sleep(2 * SPIN_PERIOD_S)
    assert thread.is_alive()
    context.try_shutdown()
    thread.join(timeout=4 * SPIN_PERIOD_S)
    assert not thread.is_alive() and executor.timeouts and set(executor.timeouts) == {SPIN_PERIOD_S}
    node.destroy_node()


def test_a_real_executor_returns_on_shutdown(context):
    node = Node("spin_test_real", context=context)
    thread = threading.Thread(target=spin_until_shutdown, args=(node,), daemon=True)
    thread.start()
    time.sleep(0.3)
    context.try_shutdown()
    thread.join(timeout=5)
    assert not thread.is_alive()
    node.destroy_node()


class RacedExecutor(DeafExecutor):
    """The signal handler shuts the context between the look at it and the wait set's creation (CI, once)."""

    def __init__(self, context, shut: bool) -> None:
        super().__init__()
        self.context, self.shut = context, shut

    def spin_once(self, timeout_sec: float | None = None) -> None:
        if self.shut:
            self.context.try_shutdown()
        from rclpy.impl.implementation_singleton import rclpy_implementation as _rclpy

        raise _rclpy.RCLError("failed to initialize wait set: the given context is not valid")


def test_a_shutdown_racing_the_wait_set_ends_the_spin_quietly(context):
    node = Node("spin_test_raced", context=context)
    spin_until_shutdown(node, RacedExecutor(context, shut=True))  # returns, raises nothing
    node.destroy_node()


def test_an_rcl_error_with_the_context_valid_is_not_swallowed(context):
    node = Node("spin_test_rcl_error", context=context)
    with pytest.raises(RuntimeError, match="wait set"):
        spin_until_shutdown(node, RacedExecutor(context, shut=False))
    node.destroy_node()


def _python(code: str, timeout: float) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=timeout)


def test_a_stuck_clean_up_ends_the_process_saying_so():
    t0 = time.monotonic()
    done = _python(
        "import time\nfrom spcotmhp.ros.spinning import bounded_shutdown\n"
        "with bounded_shutdown('the test node', 0.5):\n    time.sleep(60)\n",
        timeout=30,
    )
    assert done.returncode == 1 and time.monotonic() - t0 < 20
    assert done.stderr.strip().endswith("the test node did not stop within 0.5 s of the shutdown; exiting")


def test_a_clean_up_in_time_cancels_the_watchdog():
    done = _python(
        "import time\nfrom spcotmhp.ros.spinning import bounded_shutdown\n"
        "with bounded_shutdown('the test node', 0.3):\n    pass\ntime.sleep(1.0)\nprint('still here')\n",
        timeout=30,
    )
    assert done.returncode == 0 and done.stdout.strip() == "still here", done.stderr
    with bounded_shutdown("in this process", 0.2):
        pass
    time.sleep(0.5)  # this test process was not ended


def test_the_grace_is_longer_than_a_wait():
    assert spinning.SHUTDOWN_GRACE_S > 4 * SPIN_PERIOD_S > 0


@pytest.mark.parametrize("stop", [signal.SIGINT, signal.SIGTERM], ids=["SIGINT", "SIGTERM"])
def test_a_background_job_node_stops_on_sigint(tmp_path, model_3ldk06_dir, stop):
    """As ``spcotmhp ros2 m06 &`` in a script: bash starts the job with SIGINT ignored; ``kill -INT`` stops it, and
    so does SIGTERM (what ``ros2 launch`` and systemd send), with exit 0 and no traceback."""
    with ros_environment(tmp_path, DOMAIN) as env:
        proc = subprocess.Popen(
            [EXE, "ros2", str(model_3ldk06_dir)],
            env={**os.environ, **env},
            stdout=subprocess.PIPE,
            stderr=subprocess.STDOUT,
            text=True,
            preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_IGN),
        )
        try:
            assert proc.stdout is not None
            line = proc.stdout.readline()
            assert "spcotmhp node ready" in line, line
            time.sleep(0.5)
            proc.send_signal(stop)
            out, _ = proc.communicate(timeout=30)
            assert proc.returncode == 0 and "Traceback" not in out, out
        finally:
            if proc.poll() is None:
                proc.kill()
                proc.wait(10)


SIGINT_AT = """
import os, signal, sys
import rclpy
from rclpy.node import Node
from spcotmhp.ros.spinning import quiet_shutdown, ros_running, spin_until_shutdown

with ros_running():
    if sys.argv[1] == "before the node":
        os.kill(os.getpid(), signal.SIGINT)
    node = Node("sigint_probe")
    if sys.argv[1] == "before the spin":
        os.kill(os.getpid(), signal.SIGINT)
    spin_until_shutdown(node)  # returns: the context is down
    node.destroy_node()
    quiet_shutdown()
    quiet_shutdown()  # twice, as the node's clean-up and ros_running both do
print("stopped")
"""


@pytest.mark.parametrize("when", ["before the node", "before the spin"])
def test_a_ctrl_c_at_start_up_is_a_quiet_stop(tmp_path, when):
    """A SIGINT anywhere after rclpy.init (a Ctrl-C just after "ready") stops the process with exit 0, nothing on
    stderr: before, Python's KeyboardInterrupt escaped (exit 130), a half-made executor's __del__ complained, or
    the shutdown raced rclpy's ('rcl_shutdown already called')."""
    with ros_environment(tmp_path, DOMAIN) as env:
        done = subprocess.run([sys.executable, "-c", SIGINT_AT, when], env={**os.environ, **env}, capture_output=True,
                              text=True, timeout=60)  # fmt: skip
    assert done.returncode == 0 and done.stdout.strip() == "stopped", done.stderr
    assert "Traceback" not in done.stderr and "Exception ignored" not in done.stderr, done.stderr
    if when == "before the spin":  # the node made (what "ready" says): nothing at all on stderr
        assert done.stderr == "", done.stderr
    # a node made on a context shut down meanwhile: rclpy itself may warn "Failed to fini rosout publisher"
