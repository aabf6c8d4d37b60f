"""Map assessment from Python: the numbers of `areamatch assess`, refusals as results, bad options
as ValueError."""

import json
import subprocess

import numpy as np
import pytest

import areamatch


def without_timings(d):
    d = dict(d)
    d.pop("timings", None)
    if "match" in d:
        d["match"] = {k: v for k, v in d["match"].items() if k != "timings"}
    if "warp" in d:
        d["warp"] = {k: v for k, v in d["warp"].items() if k != "warp_s"}
    return d


def test_assess_a_robot_map(robot, building):
    a = areamatch.assess(robot.map, building.layout)
    assert a.ok and a.reason == "" and not a.decision_overridden
    assert a.broken_pieces == 0
    assert 0.3 < a.explored_share < 0.95
    d = a.to_dict()
    assert d["rigid_walls"]["map_to_reference"]["median_m"] < 0.05
    assert d["coverage"]["found"] + d["coverage"]["partly_found"] + d["coverage"]["missed"] == len(d["coverage"]["reference_areas"])
    assert np.asarray(a.picture()).shape[2] == 3
    carried = a.warp_points(np.array([[10.0, 12.0], [40.5, 33.0]]))
    assert carried.shape == (2, 2) and np.all(np.isfinite(carried))
    assert "broken pieces" in repr(a)


def test_assess_refuses_another_building_unless_told(robot):
    other = areamatch.synthetic.generate_building(1234, width_m=24.0, height_m=26.0)
    refused = areamatch.assess(robot.map, other.layout)
    assert not refused.ok and "could not be placed" in refused.reason
    with pytest.raises(ValueError, match="not placed"):
        refused.warp_points(np.zeros((1, 2)))
    forced = areamatch.assess(robot.map, other.layout, same_building=True)
    assert forced.ok and forced.decision_overridden


def test_assess_option_errors(robot, building):
    with pytest.raises(ValueError, match="bend_length"):
        areamatch.assess(robot.map, building.layout, bend_length_m=0.0)
    with pytest.raises(ValueError, match="door_width"):
        areamatch.assess(robot.map, building.layout, door_width_m=-1.0)


def test_assess_equals_the_cli_json(robot, building, cli, tmp_path):
    source = robot.map.save(str(tmp_path / "robot.pgm"))
    dest = building.layout.save(str(tmp_path / "layout.png"))
    out = subprocess.run([cli, "assess", source, dest, "--json"], capture_output=True, text=True, check=True).stdout
    python = areamatch.assess(areamatch.load_map(source), areamatch.load_map(dest))
    assert without_timings(json.loads(out)) == without_timings(python.to_dict())
