#!/usr/bin/env python3
"""A minimal ROS 2 node: match two maps, publish the transform as TF and the merged map.

    ros2 run ... ros2_merge_node.py   (or: python3 ros2_merge_node.py --ros-args -p ...)

Subscribes to two nav_msgs/OccupancyGrid topics (parameters `map_a`, `map_b`; defaults /map_a and
/map_b, transient local as map_server publishes), and whenever both have arrived and one changed:
places b in a's frame with areamatch.merge, publishes the TF from a's frame to b's (when the match
is rigid) and the merged map on `merged_topic` (default /map_merged) in a's frame.

All the work is done by plain functions of areamatch and areamatch.ros (tested without ROS in
python/tests); this file only wires them to rclpy.
"""

import sys

import areamatch
from areamatch import ros


def merge_messages(msg_a, msg_b, **merge_options):
    """The ROS-free core: two OccupancyGrid messages in, (MergeResult, TF or None) out."""
    a, b = ros.map_from_message(msg_a), ros.map_from_message(msg_b)
    result = areamatch.merge([a, b], names=["a", "b"], **merge_options)
    tf = None
    if result.maps[1]["placed"]:
        try:
            tf = ros.tf_from_matrix(result.maps[1]["T_reference_map"])
        except ValueError:  # a mirrored map: TF cannot carry it (the merged map still shows it)
            tf = None
    return result, tf


def main():
    try:
        import rclpy
        from geometry_msgs.msg import TransformStamped
        from nav_msgs.msg import OccupancyGrid
        from rclpy.node import Node
        from rclpy.qos import DurabilityPolicy, QoSProfile
        from tf2_ros import TransformBroadcaster
    except ImportError as e:
        print(f"ros2_merge_node: ROS 2 Python packages are needed ({e}); source your ROS 2 setup first",
              file=sys.stderr)
        return 2

    class MergeNode(Node):
        def __init__(self):
            super().__init__("areamatch_merge")
            self.declare_parameter("map_a", "/map_a")
            self.declare_parameter("map_b", "/map_b")
            self.declare_parameter("merged_topic", "/map_merged")
            self.declare_parameter("allow_reflection", False)
            latched = QoSProfile(depth=1, durability=DurabilityPolicy.TRANSIENT_LOCAL)
            self.messages = {}
            for key in ("map_a", "map_b"):
                topic = self.get_parameter(key).value
                self.create_subscription(OccupancyGrid, topic, lambda m, k=key: self.received(k, m), latched)
            self.publisher = self.create_publisher(OccupancyGrid, self.get_parameter("merged_topic").value, latched)
            self.tf = TransformBroadcaster(self)

        def received(self, key, msg):
            self.messages[key] = msg
            if len(self.messages) < 2:
                return
            a, b = self.messages["map_a"], self.messages["map_b"]
            result, tf = merge_messages(a, b, allow_reflection=self.get_parameter("allow_reflection").value)
            if not result.ok:
                self.get_logger().warn(f"map b not placed: {result.maps[1]['reason']}")
                return
            if tf is not None:
                t = TransformStamped()
                t.header.stamp = self.get_clock().now().to_msg()
                t.header.frame_id = a.header.frame_id or "map_a"
                t.child_frame_id = b.header.frame_id or "map_b"
                (t.transform.translation.x, t.transform.translation.y, t.transform.translation.z) = tf[0]
                (t.transform.rotation.x, t.transform.rotation.y, t.transform.rotation.z, t.transform.rotation.w) = tf[1]
                self.tf.sendTransform(t)
            fields = ros.message_fields(result.merged)
            out = OccupancyGrid()
            out.header.stamp = self.get_clock().now().to_msg()
            out.header.frame_id = a.header.frame_id or "map_a"
            out.info.width, out.info.height, out.info.resolution = fields["width"], fields["height"], fields["resolution"]
            (out.info.origin.position.x, out.info.origin.position.y, out.info.origin.position.z) = fields["position"]
            (out.info.origin.orientation.x, out.info.origin.orientation.y, out.info.origin.orientation.z,
             out.info.origin.orientation.w) = fields["orientation"]
            out.data = fields["data"]
            self.publisher.publish(out)

    rclpy.init()
    node = MergeNode()
    try:
        rclpy.spin(node)
    finally:
        node.destroy_node()
        rclpy.shutdown()
    return 0


if __name__ == "__main__":
    sys.exit(main())
