"""The Python examples run (the ROS 2 node's ROS-free core included)."""

import importlib.util
import os
import pathlib
import subprocess
import sys

import pytest

import areamatch
from test_ros import message

EXAMPLES = pathlib.Path(os.environ.get("AREAMATCH_EXAMPLES", pathlib.Path(__file__).parents[2] / "examples" / "python"))


def load(name):
    spec = importlib.util.spec_from_file_location(name, EXAMPLES / f"{name}.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_match_maps_example(tmp_path):
    out = tmp_path / "match.png"
    run = subprocess.run([sys.executable, str(EXAMPLES / "match_maps.py"), "--out", str(out)],
                         capture_output=True, text=True, env=dict(os.environ, PYTHONPATH=str(pathlib.Path(areamatch.__file__).parents[1])))
    assert run.returncode == 0, run.stderr
    assert run.stdout.startswith("matched: rotation") and out.stat().st_size > 1000


def test_ros2_node_core():
    node = load("ros2_merge_node")
    b = areamatch.synthetic.generate_building(21)
    robot = areamatch.synthetic.make_robot_map(b, 22, rotation_rad=-0.8, translation_m=(1.0, 2.0), explored_fraction=0.6)
    result, tf = node.merge_messages(message(b.layout), message(robot.map))
    assert result.ok and tf is not None
    translation, q = tf
    assert translation[2] == 0.0 and len(q) == 4
    # Without ROS installed the node says so and exits 2 instead of a traceback.
    if importlib.util.find_spec("rclpy") is None:
        assert node.main() == 2
    else:
        pytest.skip("rclpy installed: the node itself is not started in tests")
