"""The ROS 2 glue, without ROS: message-shaped objects in, plain values out."""

import math
import types

import numpy as np
import pytest

import areamatch
from areamatch import ros


def message(map_):
    """A stand-in for nav_msgs/OccupancyGrid with the fields the glue reads."""
    f = ros.message_fields(map_)
    q = types.SimpleNamespace(**dict(zip("xyzw", f["orientation"])))
    p = types.SimpleNamespace(**dict(zip("xyz", f["position"])))
    info = types.SimpleNamespace(width=f["width"], height=f["height"], resolution=f["resolution"],
                                 origin=types.SimpleNamespace(position=p, orientation=q))
    return types.SimpleNamespace(info=info, data=f["data"])


def test_quaternions():
    for yaw in (0.0, 0.5, -2.0, math.pi - 1e-9):
        assert math.isclose(ros.yaw_from_quaternion(*ros.quaternion_from_yaw(yaw)), yaw, abs_tol=1e-9)


def test_message_round_trip():
    b = areamatch.synthetic.generate_building(11)
    robot = areamatch.synthetic.make_robot_map(b, 12, rotation_rad=0.2, explored_fraction=0.5)
    m = robot.map
    rotated = areamatch.Map.from_occupancy_grid(**dict(m.to_occupancy_grid(), origin=(1.0, -2.0, 0.7)))
    for original in (m, rotated):
        back = ros.map_from_message(message(original))
        assert back.cells.tolist() == original.cells.tolist()
        assert np.allclose(back.origin, original.origin)


def test_tf_from_a_match():
    b = areamatch.synthetic.generate_building(11)
    robot = areamatch.synthetic.make_robot_map(b, 12, rotation_rad=0.9, translation_m=(2.0, 1.0), explored_fraction=0.6)
    result = areamatch.match(robot.map, b.layout)
    translation, q = ros.tf_from_matrix(result.T_dest_source)
    assert math.isclose(ros.yaw_from_quaternion(*q), result.rotation, abs_tol=1e-9)
    assert np.allclose(translation[:2], result.translation_m)
    mirrored = np.diag([1.0, -1.0, 1.0])
    with pytest.raises(ValueError, match="mirrored"):
        ros.tf_from_matrix(mirrored)
    with pytest.raises(ValueError, match="scales"):
        ros.tf_from_matrix(np.diag([2.0, 2.0, 1.0]))
