"""Synthetic buildings and robot maps with exact ground truth (the generator of `areamatch generate`).

    b = areamatch.synthetic.generate_building(seed=1)
    robot = areamatch.synthetic.make_robot_map(b, seed=2, rotation_rad=0.5, explored_fraction=0.5)
    result = areamatch.match(robot.map, b.layout)     # compare with robot.T_dest_source
"""

from ._core import _synthetic

SyntheticBuilding = _synthetic.SyntheticBuilding
RobotMap = _synthetic.RobotMap
generate_building = _synthetic.generate_building
make_robot_map = _synthetic.make_robot_map

__all__ = ["SyntheticBuilding", "RobotMap", "generate_building", "make_robot_map"]
