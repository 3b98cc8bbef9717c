"""tf2_msgs' TFMessage as built here (ros2/tf2_msgs/README.md), and the check of its type hash against Jazzy's.

``python -m spcotmhp.ros.tf_types`` runs the check (the Makefile does after building): a TFMessage of another ROS
distribution would not match the robot's /tf publishers (DDS peers match only equal hashes).
"""

from __future__ import annotations

import sys

from spcotmhp.errors import SpcotmhpError
from spcotmhp.ros.type_hash import compiled_type_hash

# RIHS01 of tf2_msgs/msg/TFMessage in ROS 2 Jazzy: `ros2 topic info -v /tf` on a Jazzy robot prints it, and
# rosbags' RIHS01 recomputes it from the interface file (ros2/tf2_msgs/README.md)
TF_MESSAGE_HASH = "RIHS01_e369d0f05a23ae52508854b66f6aa0437f3449d652e8cbf22d5abe85d020f087"
BUILD_HINT = "build it with `make nav2-msgs` (ros2/tf2_msgs/README.md)"


class Tf2MsgsMissing(SpcotmhpError):
    """tf2_msgs cannot be imported (not built into this environment), or is not Jazzy's."""


def import_tf_message() -> type:
    """The class tf2_msgs.msg.TFMessage; Tf2MsgsMissing (naming how to build it) when absent or not Jazzy's."""
    try:
        from tf2_msgs.msg import TFMessage
    except ImportError as e:
        raise Tf2MsgsMissing(f"tf2_msgs is not importable ({e}); {BUILD_HINT}") from None
    if compiled_type_hash(TFMessage) != TF_MESSAGE_HASH:
        raise Tf2MsgsMissing(
            f"the tf2_msgs TFMessage importable here is not ROS 2 Jazzy's (its hash differs); {BUILD_HINT}"
        )
    return TFMessage


def main() -> int:
    """Command line: check the built tf2_msgs, one line of result; exit status 1 on failure."""
    try:
        import_tf_message()
    except SpcotmhpError as e:
        print(f"error: {e}", file=sys.stderr)
        return 1
    print("tf2_msgs: TFMessage's type hash equals ROS 2 Jazzy's")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
