"""Spin a node until Ctrl-C or SIGTERM, and stop within a bounded time, always.

``rclpy.spin`` waits with no timeout, so a shutdown whose wake-up is lost leaves the process waiting for ever;
once, under a loaded test run, the node did not end after ``kill -INT`` (the README's ROS 2 block), and rclpy
run in a background shell job is reported to miss SIGINT (ros2/rclpy#527). Where it stuck was not caught, so
both places are bounded: the executor waits at most :data:`SPIN_PERIOD_S` and looks at the context between
waits, and the clean-up after spinning (threads, node, context) runs under a watchdog that ends the process
after :data:`SHUTDOWN_GRACE_S`, saying so, as ``ros2 launch`` escalates a process that outlives its SIGINT.

Ctrl-C and SIGTERM are a request to stop, which the spinning loop reads between two waits (:func:`ros_running`):
never a KeyboardInterrupt, which Python's handler raised wherever the main thread was (a Ctrl-C just after "ready",
docs/ros2.md's blocks started then stopped, left a traceback and exit status 130), and never rclpy's own handler,
which shuts the context down from whichever thread the signal lands on, at any moment: under an executor being
made, whose half-made guard condition and executor then complained from their ``__del__`` (once in a CI run).
"""

from __future__ import annotations

import os
import signal
import sys
import threading
from collections.abc import Iterator
from contextlib import contextmanager

import rclpy
from rclpy.exceptions import NotInitializedException
from rclpy.executors import Executor, ExternalShutdownException, SingleThreadedExecutor
from rclpy.node import Node
from rclpy.signals import SignalHandlerOptions

SPIN_PERIOD_S = 0.5  # the longest wait between two looks at the context: a lost wake-up costs at most this
SHUTDOWN_GRACE_S = 10.0  # clean-up longer than this is stuck (threads joined, DDS participant destroyed)
STOP_SIGNALS = (signal.SIGINT, signal.SIGTERM)  # what rclpy's own handler stops on (SignalHandlerOptions.ALL)
_stop = threading.Event()  # set by a stop signal in ros_running; read by spin_until_shutdown


def stop_requested() -> bool:
    """Whether a Ctrl-C or SIGTERM asked this process to stop (inside :func:`ros_running`)."""
    return _stop.is_set()


def spin_until_shutdown(node: Node, executor: Executor | None = None) -> None:
    """Spin ``node`` on ``executor`` (single-threaded by default) until the context shuts down or Ctrl-C."""
    if executor is None:
        if not rclpy.ok(context=node.context) or stop_requested():
            return  # stopped already (a Ctrl-C at start-up): no executor can be made on a context shut down
        executor = SingleThreadedExecutor(context=node.context)
    executor.add_node(node)
    try:
        while rclpy.ok(context=node.context) and not stop_requested():
            try:
                executor.spin_once(timeout_sec=SPIN_PERIOD_S)
            except RuntimeError:
                # The signal handler may shut the context down between the look above and the wait set's
                # creation; rclpy then raises RCLError (a RuntimeError). That is a shutdown, not a failure.
                if rclpy.ok(context=node.context):
                    raise
    except (KeyboardInterrupt, ExternalShutdownException):
        pass
    finally:
        executor.remove_node(node)


@contextmanager
def bounded_shutdown(what: str, grace_s: float = SHUTDOWN_GRACE_S) -> Iterator[None]:
    """Run the block's clean-up; should it take over ``grace_s``, say so on stderr and end the process (exit 1).

    The watchdog is cancelled when the block ends, so a caller in a test process is never ended by it."""

    def stuck() -> None:
        sys.stderr.write(f"spcotmhp: {what} did not stop within {grace_s:g} s of the shutdown; exiting\n")
        sys.stderr.flush()
        os._exit(1)

    watchdog = threading.Timer(grace_s, stuck)
    watchdog.daemon = True
    watchdog.start()
    try:
        yield
    finally:
        watchdog.cancel()


def quiet_shutdown() -> None:
    """``rclpy.try_shutdown()``, which can race the signal handler's own shutdown (RCLError "rcl_shutdown already
    called", a RuntimeError, between its look and its call): that is a shutdown done, not a failure."""
    try:
        rclpy.try_shutdown()
    except RuntimeError:
        if rclpy.ok():
            raise


@contextmanager
def ros_running() -> Iterator[None]:
    """``rclpy.init()`` for the block, and the shutdown after it, with Ctrl-C (SIGINT) and SIGTERM a request to stop.

    rclpy is initialised without its signal handlers; a Python handler of this block's only notes the request
    (:func:`stop_requested`), which Python runs in the main thread between two of its steps, so nothing is shut
    down under an object being made; :func:`spin_until_shutdown` sees it within SPIN_PERIOD_S and returns, and the
    block's clean-up and this shutdown run in order. Should rclpy still raise on a context shut down under it
    (RuntimeError, NotInitializedException: another handler's shutdown), the block ends as a stop. The previous
    handlers are put back afterwards."""
    _stop.clear()
    previous = {s: signal.signal(s, lambda signum, frame: _stop.set()) for s in STOP_SIGNALS}
    try:
        rclpy.init(signal_handler_options=SignalHandlerOptions.NO)
        yield
    except (RuntimeError, NotInitializedException):  # what rclpy raises on a context shut down
        if rclpy.ok():
            raise
    finally:
        quiet_shutdown()
        for s, handler in previous.items():
            signal.signal(s, handler)
