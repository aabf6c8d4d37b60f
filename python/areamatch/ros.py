"""ROS 2 glue that needs no ROS: plain values in, plain values out.

A ROS 2 node (examples/python/ros2_merge_node.py) is a thin shell over these functions, so they
are tested here without rclpy. Conventions: nav_msgs/OccupancyGrid (row 0 of `data` at the
origin, -1 unknown, 0-100 occupancy), geometry_msgs quaternions (x, y, z, w), and TF's meaning of a
transform from `parent` to `child`: the pose of the child frame in the parent frame.
"""

import math

import numpy as np

from ._core import Map


def yaw_from_quaternion(x, y, z, w):
    """The rotation about z of a quaternion (x, y, z, w), radians."""
    return math.atan2(2.0 * (w * z + x * y), 1.0 - 2.0 * (y * y + z * z))


def quaternion_from_yaw(yaw):
    """The quaternion (x, y, z, w) of a rotation by `yaw` radians about z."""
    return (0.0, 0.0, math.sin(yaw / 2.0), math.cos(yaw / 2.0))


def map_from_message(msg, **thresholds):
    """A Map from a nav_msgs/OccupancyGrid message (or anything with .info and .data alike)."""
    info = msg.info
    q = info.origin.orientation
    origin = (info.origin.position.x, info.origin.position.y, yaw_from_quaternion(q.x, q.y, q.z, q.w))
    return Map.from_occupancy_grid(np.asarray(msg.data), info.width, info.height, info.resolution, origin, **thresholds)


def message_fields(map_):
    """What a nav_msgs/OccupancyGrid needs from a Map: width, height, resolution, the origin as
    position (x, y, z) and orientation (x, y, z, w), and `data` as a list of ints (row 0 at the
    origin)."""
    grid = map_.to_occupancy_grid()
    x, y, yaw = grid["origin"]
    return {
        "width": grid["width"],
        "height": grid["height"],
        "resolution": grid["resolution"],
        "position": (x, y, 0.0),
        "orientation": quaternion_from_yaw(yaw),
        "data": grid["data"].tolist(),
    }


def tf_from_matrix(T):
    """Translation (x, y, z) and quaternion (x, y, z, w) of a 3x3 rigid transform, e.g. a match's
    T_dest_source as the TF from the destination map's frame (parent) to the source map's frame
    (child). Raises ValueError for a mirrored or scaled transform, which TF cannot carry."""
    T = np.asarray(T, dtype=float)
    if T.shape != (3, 3):
        raise ValueError(f"expected a 3x3 transform, got shape {T.shape}")
    linear = T[:2, :2]
    det = float(np.linalg.det(linear))
    if det < 0.0:
        raise ValueError("the transform is mirrored (reflected): TF cannot represent it")
    if abs(det - 1.0) > 1e-6:
        raise ValueError(f"the transform scales by {math.sqrt(abs(det)):.6g}: TF carries rigid transforms only")
    yaw = math.atan2(linear[1, 0], linear[0, 0])
    return (float(T[0, 2]), float(T[1, 2]), 0.0), quaternion_from_yaw(yaw)


__all__ = ["yaw_from_quaternion", "quaternion_from_yaw", "map_from_message", "message_fields", "tf_from_matrix"]
