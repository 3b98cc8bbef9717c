"""SpCoTMHP on a robot: a ROS 2 node (:mod:`spcotmhp.ros.node`, needs the ``ros2`` extra) and exports for Nav2
(:mod:`spcotmhp.ros.nav2_export`: a Route Server graph and keepout masks; no ROS needed).

The parts that do not talk to ROS (headings of a path, the learned map as drawable shapes, the check of a
published map, the teaching log) live in :mod:`spcotmhp.ros.shapes` and :mod:`spcotmhp.ros.teaching_log` so that
they are usable and testable without rclpy.
"""

from __future__ import annotations

from spcotmhp.errors import SpcotmhpError

ROS2_EXTRA_HINT = "pip install 'spcotmhp[ros2]'"


def require_rclpy() -> None:
    """Raise a one-line :class:`SpcotmhpError` when the ROS 2 Python client is not installed."""
    try:
        import rclpy  # noqa: F401
        from geometry_msgs.msg import PoseWithCovarianceStamped  # noqa: F401
        from nav_msgs.msg import OccupancyGrid, Path  # noqa: F401
        from std_msgs.msg import String  # noqa: F401
        from visualization_msgs.msg import MarkerArray  # noqa: F401
    except ImportError as exc:
        raise SpcotmhpError(
            f"the ROS 2 node needs rclpy and the ROS 2 messages ({exc.name} is missing): {ROS2_EXTRA_HINT}"
        ) from None
