"""Tell the ROS 2 node `spcotmhp` where the robot is and where to go; print its answer (the README's Tour).

Run it while `spcotmhp ros2 MODEL_DIR` runs, with the extra 'ros2' (no ROS installation needed). It publishes a
pose on /amcl_pose as AMCL would (latched), then an instruction on /spcotmhp/instruction, and prints the first
JSON status the node publishes on /spcotmhp/status (a plan, or an error naming its cause); it says the instruction
again when no answer comes within 5 s (a node just discovered can miss it, or answer before it hears this one).
Arguments: an instruction, then x and y in metres in the map frame (default: the README's start in 3LDK_06).
"""

import sys
import time

import rclpy
from geometry_msgs.msg import PoseWithCovarianceStamped
from rclpy.qos import DurabilityPolicy, QoSProfile
from std_msgs.msg import String

instruction = sys.argv[1] if len(sys.argv) > 1 else "go to the bedroom via the corridor"
x, y = (float(sys.argv[2]), float(sys.argv[3])) if len(sys.argv) > 3 else (-3.9, -3.5)

rclpy.init()
node = rclpy.create_node("tell")
latched = QoSProfile(depth=1, durability=DurabilityPolicy.TRANSIENT_LOCAL)
pose_pub = node.create_publisher(PoseWithCovarianceStamped, "/amcl_pose", latched)  # stands in for AMCL
say = node.create_publisher(String, "/spcotmhp/instruction", 10)
answers: list[String] = []
node.create_subscription(String, "/spcotmhp/status", answers.append, 10)
while say.get_subscription_count() == 0 or pose_pub.get_subscription_count() == 0:
    rclpy.spin_once(node, timeout_sec=0.1)  # wait for the node
pose = PoseWithCovarianceStamped()
pose.header.frame_id = "map"
pose.pose.pose.position.x, pose.pose.pose.position.y = x, y
pose.pose.pose.orientation.w = 1.0
pose_pub.publish(pose)
rclpy.spin_once(node, timeout_sec=0.5)
while not answers:  # the node answers at once; silence means the instruction or its answer was lost: say it again
    say.publish(String(data=instruction))
    said = time.monotonic()
    while not answers and time.monotonic() - said < 5.0:
        rclpy.spin_once(node, timeout_sec=0.1)
print(answers[0].data)
node.destroy_node()
rclpy.shutdown()
