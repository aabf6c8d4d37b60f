"""Merging from Python: maps placed in one frame, strangers reported, the CLI's JSON."""

import json
import subprocess

import numpy as np

import areamatch
from conftest import without_timings


def robot_maps(building, count):
    return [areamatch.synthetic.make_robot_map(building, 100 + i, rotation_rad=0.4 * i + 0.3,
                                               translation_m=(0.5 * i, -0.3 * i), explored_fraction=0.6)
            for i in range(count)]


def test_merge_places_every_map(building):
    robots = robot_maps(building, 3)
    result = areamatch.merge([building.layout] + [r.map for r in robots], threads=2)
    assert result.ok and result.reference == 0
    for placed, robot in zip(result.maps[1:], robots):
        assert placed["placed"] and placed["reason"] == ""
        T = placed["T_reference_map"]
        assert np.allclose(T[:2, :2], robot.T_dest_source[:2, :2], atol=0.01)
        assert np.linalg.norm(T[:2, 2] - robot.T_dest_source[:2, 2]) < 0.2
    assert len(result.edges) == 6 and all("used" in e for e in result.edges)
    merged = result.merged
    assert isinstance(merged, areamatch.Map) and merged.resolution == building.layout.resolution
    # The merged map, and below it the legend naming each map's colour.
    picture = np.asarray(result.picture())
    assert picture.shape[1] >= merged.width and picture.shape[0] > merged.height and picture.shape[2] == 3
    assert repr(result).startswith("<areamatch.MergeResult ok, 4 of 4 maps placed, merged ")
    for source, dest, match in result.edge_results():
        assert 0 <= source < 4 and 0 <= dest < 4 and isinstance(match, areamatch.Result)
    assert result.timings["refine_s"] > 0
    # Read natively, with the keys and values of `areamatch merge --json`.
    assert result.edges == result.to_dict()["edges"]
    assert result.timings == result.to_dict()["timings"]
    as_matched = areamatch.merge([building.layout] + [r.map for r in robots], same_side=False, build_merged_map=False)
    assert as_matched.ok and as_matched.timings["refine_s"] == 0


def test_merge_non_rigid(building):
    import pytest
    maps = [building.layout] + [r.map for r in robot_maps(building, 2)]
    rigid = areamatch.merge(maps)
    bent = areamatch.merge(maps, non_rigid=True, bend_length_m=5.0)
    assert rigid.ok and bent.ok
    assert rigid.maps[1]["warp"] is None and bent.maps[0]["warp"] is None
    for placed in bent.maps[1:]:
        # these maps are not bent: the warp may only leave them as they were (within noise)
        assert placed["warp"]["warped_median_m"] <= placed["warp"]["rigid_median_m"] + 0.005
    assert set(bent.double_walls) == {"wall_cells", "doubled_cells", "share"}
    assert bent.to_dict()["merged"]["doubled_wall_cells"] == bent.double_walls["doubled_cells"]
    assert bent.timings["warp_s"] > 0
    with pytest.raises(ValueError, match="non_rigid"):
        areamatch.merge(maps, bend_length_m=5.0)


def test_merge_reports_a_stranger(building):
    stranger = areamatch.synthetic.generate_building(4321, width_m=22.0, height_m=28.0).layout
    result = areamatch.merge([building.layout, robot_maps(building, 1)[0].map, stranger],
                             names=["layout", "robot", "stranger"])
    assert not result.ok
    assert result.maps[1]["placed"] and not result.maps[2]["placed"] and result.maps[2]["reason"]
    assert result.to_dict()["maps"][2]["path"] == "stranger"


def test_merge_errors(building):
    import pytest
    with pytest.raises(ValueError, match="at least two maps"):
        areamatch.merge([building.layout])
    with pytest.raises(ValueError, match="reference"):
        areamatch.merge([building.layout, building.layout], reference=5)
    with pytest.raises(TypeError):
        areamatch.merge([building.layout, "map.yaml"])


def test_merge_equals_the_cli_json(building, cli, tmp_path):
    paths = [building.layout.save(str(tmp_path / "layout.pgm"))]
    for i, robot in enumerate(robot_maps(building, 2)):
        paths.append(robot.map.save(str(tmp_path / f"robot{i}.pgm")))
    out = subprocess.run([cli, "merge", *paths, "--json"], capture_output=True, text=True)
    assert out.returncode == 0, out.stderr
    python = areamatch.merge([areamatch.load_map(p) for p in paths], names=paths, threads=2)
    assert without_timings(python.to_dict()) == without_timings(json.loads(out.stdout))
