"""Segmenting and matching from Python: the same answers as the C++ program, errors as exceptions,
and the GIL released while the library works."""

import json
import subprocess
import threading

import numpy as np
import pytest

import areamatch
from conftest import without_timings


def rotation_error_deg(T, truth):
    a = np.degrees(np.arctan2(T[1, 0], T[0, 0]) - np.arctan2(truth[1, 0], truth[0, 0]))
    return abs((a + 180.0) % 360.0 - 180.0)


def test_segment(building):
    graph = areamatch.segment(building.layout)
    assert len(graph.areas) >= 5 and graph.reason == ""
    area = graph.areas[0]
    assert area.polygon.shape[1] == 2 and np.allclose(area.polygon[0], area.polygon[-1])
    assert area.kind in ("room", "corridor") and area.size_m2 > 0.0
    labels = graph.labels()
    assert labels.shape == (building.layout.height, building.layout.width) and labels.dtype == np.int32
    assert set(np.unique(labels)) == {-1} | {a.id for a in graph.areas}
    passage = graph.passages[0]
    assert passage.line.shape == (2, 2) and passage.width_m > 0.0 and passage.kind in ("door", "junction")
    assert graph.to_dict()["areas"][0]["id"] == area.id
    assert np.asarray(graph.picture(building.layout)).shape == (building.layout.height, building.layout.width, 3)


def test_segment_errors_and_empty_maps():
    walls = areamatch.Map.from_array(np.zeros((50, 50), np.uint8), 0.05)
    graph = areamatch.segment(walls)
    assert len(graph.areas) == 0 and "no free cells" in graph.reason
    with pytest.raises(ValueError, match="door_width"):
        areamatch.segment(walls, door_width_m=-1.0)


def test_match_finds_the_truth(robot, building):
    result = areamatch.match(robot.map, building.layout)
    assert result.ok and result.reason == ""
    assert result.T_dest_source.shape == (3, 3) and result.pixel_transform.shape == (2, 3)
    assert rotation_error_deg(result.T_dest_source, robot.T_dest_source) < 0.5
    # The truth maps the robot map's centre to where the result maps it, within a decimetre.
    centre = robot.map.world_from_pixel() @ np.array([robot.map.width / 2, robot.map.height / 2, 1.0])
    assert np.linalg.norm((result.T_dest_source @ centre)[:2] - (robot.T_dest_source @ centre)[:2]) < 0.1
    assert 0.0 <= result.p_correct <= 1.0 and result.evidence["agreement"] > 0.8
    assert result.matched_areas and {"source", "dest"} <= set(result.matched_areas[0])
    first = result.matched_areas[0]
    assert isinstance(first, areamatch.MatchedArea) and first.source == first["source"] and first.dest == first["dest"]
    assert repr(first).startswith("MatchedArea(source=")
    with pytest.raises(AttributeError, match="no field 'nope'"):
        first.nope
    assert result.rejection is None
    assert result.timings["total_s"] > 0.0
    assert np.asarray(result.picture()).ndim == 3


def test_result_parts_are_read_natively_with_the_json_keys_and_values(robot, building):
    result = areamatch.match(robot.map, building.layout)
    as_json = result.to_dict()
    for key in ("evidence", "statistics", "timings", "margin_different", "margin_mirrored"):
        assert getattr(result, key) == as_json[key], key
    assert result.matched_areas == as_json["matched_areas"]
    assert result.rejection is None and "rejection" not in as_json
    # The maps and graphs are the result's own (no copy per access) and keep it alive.
    source = result.source_map
    graph = result.dest_graph
    del result
    assert source.width == robot.map.width and len(graph.areas) > 0


def test_match_reports_progress_and_a_raise_stops_it(robot, building):
    seen = []
    result = areamatch.match(robot.map, building.layout, progress=lambda stage, done, total: seen.append(stage))
    assert result.ok and result.T_dest_source.tolist() == areamatch.match(robot.map, building.layout).T_dest_source.tolist()
    assert seen.count("load") == 2 and seen.count("segment") == 2 and seen[-3:] == ["prepare", "select", "check"]

    class Stop(Exception):
        pass

    def stop(stage, done, total):
        if stage == "select":
            raise Stop("enough")

    with pytest.raises(Stop, match="enough"):
        areamatch.match(robot.map, building.layout, progress=stop)


def test_match_rejects_another_building(robot):
    other = areamatch.synthetic.generate_building(1234, width_m=24.0, height_m=26.0).layout
    result = areamatch.match(robot.map, other)
    assert not result.ok and result.reason
    assert result.rejection in ("different places", "not sure") and result.reason.startswith(result.rejection + ": ")
    assert result.rejection == result.to_dict()["rejection"] and result.evidence == result.to_dict()["evidence"]


def test_the_agreement_gate_is_configurable(robot):
    other = areamatch.synthetic.generate_building(1234, width_m=24.0, height_m=26.0).layout
    # At min_agreement 0 the gate still needs one map's walls largely unexplained by the other's
    # (gate_max_lower_walls, default 0.7); above 1 it opens whatever the walls.
    gated = areamatch.match(robot.map, other, min_agreement=0.0)
    assert not gated.ok and "gate_max_lower_walls" in gated.reason
    assert areamatch.match(robot.map, other, min_agreement=0.0, gate_max_lower_walls=2.0).ok
    assert areamatch.Matcher(min_agreement=0.0, gate_max_lower_walls=2.0).match(robot.map, other).ok
    with pytest.raises(ValueError, match="gate_max_lower_walls"):
        areamatch.match(robot.map, other, gate_max_lower_walls=-1.0)
    # Where the walls agree both ways the gate's other part (unentered rooms' walls and a margin)
    # is set by name, as `--set` does.
    names = {p["name"] for p in areamatch.parameters()}
    assert {"decision.gate_both_ways_min_occupied", "decision.gate_both_ways_min_margin"} <= names
    off = areamatch.match(robot.map, other, min_agreement=0.0, params={"decision.gate_both_ways_min_occupied": 2.0})
    assert not off.ok
    with pytest.raises(ValueError, match="gate_both_ways_min_occupied"):
        areamatch.match(robot.map, other, params={"decision.gate_both_ways_min_occupied": -1.0})


def test_match_without_areas_is_a_rejection_not_a_crash(building):
    walls = areamatch.Map.from_array(np.zeros((50, 50), np.uint8), 0.05)
    result = areamatch.match(walls, building.layout)
    assert not result.ok and "no areas" in result.reason
    assert result.rejection == "no answer"


def test_threads_default_as_the_program():
    assert areamatch.DEFAULT_THREADS == 2
    assert areamatch.merge.__doc__.startswith("merge(maps, *, reference=0,")
    assert "threads=2" in areamatch.merge.__doc__.split("\n")[0]


def test_match_option_errors(robot, building):
    with pytest.raises(ValueError, match="not both"):
        areamatch.match(robot.map, building.layout, door_width_m=1.0, source_door_width_m=1.0)
    with pytest.raises(ValueError, match="k must be"):
        areamatch.match(robot.map, building.layout, k=0)
    with pytest.raises(TypeError):
        areamatch.match(robot.map, "layout.yaml")


def test_prepared_equals_unprepared(robot, building):
    matcher = areamatch.Matcher()
    layout = matcher.prepare(building.layout)
    robot_prepared = matcher.prepare(robot.map)
    direct = without_timings(areamatch.match(robot.map, building.layout).to_dict())
    assert without_timings(matcher.match(robot.map, layout).to_dict()) == direct
    assert without_timings(matcher.match(robot_prepared, layout).to_dict()) == direct
    assert without_timings(matcher.match(robot.map, building.layout).to_dict()) == direct
    assert len(matcher.match(robot.map, layout).source_graph.areas) == len(robot_prepared.graph.areas)


def test_threads_give_the_same_answer(robot, building):
    one = areamatch.match(robot.map, building.layout, threads=1)
    two = areamatch.match(robot.map, building.layout, threads=2)
    assert without_timings(one.to_dict()) == without_timings(two.to_dict())


def test_equals_the_cli_json(robot, building, cli, tmp_path):
    source = robot.map.save(str(tmp_path / "robot.pgm"))
    dest = building.layout.save(str(tmp_path / "layout.png"))
    out = subprocess.run([cli, "match", source, dest, "--json", "--allow-reflection"], capture_output=True, text=True)
    assert out.returncode in (0, 1), out.stderr
    python = areamatch.match(areamatch.load_map(source), areamatch.load_map(dest), allow_reflection=True)
    assert without_timings(python.to_dict()) == without_timings(json.loads(out.stdout))


def test_the_gil_is_released_while_matching(building):
    # While one thread matches, another runs Python code: with the GIL held by the match it
    # could not take a single step until the match returned.
    big = areamatch.synthetic.make_robot_map(building, 3, rotation_rad=1.0, resolution=0.02)
    steps = 0
    worker = threading.Thread(target=lambda: [areamatch.match(big.map, building.layout) for _ in range(3)])
    worker.start()
    while worker.is_alive():
        steps += 1
    worker.join()
    assert steps > 1000


def shared_pairs(shared_dir):
    """(manifest folder, pair, program options) of every pair of the shared manifests, with the
    options score.py runs them with: reflection allowed on pairs.json, the pair's door width."""
    out = []
    for manifest, options in (("pairs.json", ["--allow-reflection"]), ("handheld/pairs.json", [])):
        path = shared_dir / manifest
        if path.exists():
            for pair in json.loads(path.read_text())["pairs"]:
                door = ["--door-width", str(pair["door_width_m"])] if "door_width_m" in pair else []
                out.append((path.parent, pair, options + door))
    return out


def test_shared_pairs_equal_the_cli(shared_dir, cli):
    pairs = shared_pairs(shared_dir)
    assert len(pairs) >= 22
    accepted = 0
    for folder, pair, options in pairs:
        source, dest = str(folder / pair["source"]), str(folder / pair["destination"])
        out = subprocess.run([cli, "match", source, dest, "--json", *options], capture_output=True, text=True)
        assert out.returncode in (0, 1), out.stderr
        door = float(options[-1]) if "--door-width" in options else None
        python = areamatch.match(areamatch.load_map(source), areamatch.load_map(dest),
                                 allow_reflection="--allow-reflection" in options, door_width_m=door)
        assert without_timings(python.to_dict()) == without_timings(json.loads(out.stdout)), pair["name"]
        accepted += python.ok
    assert accepted >= 22


def test_any_setting_by_name_equals_the_cli(robot, building, cli, tmp_path):
    # One table of settings (parameters.hpp) for C++, the program's --set and params= here.
    names = {row["name"] for row in areamatch.parameters()}
    assert {"k", "rooms.door_width_m", "refinement.gates_m", "decision.min_agreement"} <= names
    defaults = {row["name"]: row["value"] for row in areamatch.parameters()}
    assert defaults["refinement.gates_m"] == [2.0, 1.2, 0.7, 0.4] and defaults["k"] == 10
    assert {row["name"]: row["value"] for row in areamatch.parameters(paper=True)}["k"] == 3
    params = {"refinement.gates_m": [2, 1, 0.5], "rooms.door_width_m": 1.4, "allow_reflection": True,
              "hypotheses.min_area_overlap": 0.4}
    source = robot.map.save(str(tmp_path / "robot.pgm"))
    dest = building.layout.save(str(tmp_path / "layout.png"))
    out = subprocess.run([cli, "match", source, dest, "--json", "--set", "refinement.gates_m=2,1,0.5",
                          "--set", "rooms.door_width_m=1.4", "--set=allow_reflection=true",
                          "--set", "hypotheses.min_area_overlap=0.4"], capture_output=True, text=True)
    assert out.returncode in (0, 1), out.stderr
    python = areamatch.match(areamatch.load_map(source), areamatch.load_map(dest), params=params)
    assert without_timings(python.to_dict()) == without_timings(json.loads(out.stdout))
    plain = areamatch.match(areamatch.load_map(source), areamatch.load_map(dest))
    assert without_timings(python.to_dict()) != without_timings(plain.to_dict())
    matcher = areamatch.Matcher(params=params)
    assert without_timings(matcher.match(matcher.prepare(areamatch.load_map(source)),
                                         matcher.prepare(areamatch.load_map(dest))).to_dict()) == \
        without_timings(python.to_dict())
    with pytest.raises(ValueError, match="did you mean decision.min_agreement"):
        areamatch.Matcher(params={"decision.min_agrement": 0.9})
    with pytest.raises(ValueError, match="must be true or false"):
        areamatch.match(robot.map, building.layout, params={"refine": "maybe"})
    with pytest.raises(ValueError, match="params must be a dict"):
        areamatch.match(robot.map, building.layout, params=[("k", 3)])
