"""Map: NumPy views, image and nav_msgs/OccupancyGrid conversions, files, errors."""

import numpy as np
import pytest

import areamatch
from areamatch import FREE, OCCUPIED, UNKNOWN, Map


def asymmetric_image():
    """A 4 x 6 image whose rows and columns all differ: a flip would show."""
    image = np.full((4, 6), 254, dtype=np.uint8)  # free
    image[0, :] = 0                               # top row: wall
    image[:, 5] = 205                             # right column: unknown
    image[3, 0] = 0                               # bottom-left cell: wall
    return image


def test_from_array_classifies_like_map_server():
    m = Map.from_array(asymmetric_image(), 0.1, origin=(1.0, 2.0, 0.0))
    assert (m.width, m.height, m.resolution, m.origin) == (6, 4, 0.1, (1.0, 2.0, 0.0))
    cells = m.cells
    assert cells.shape == (4, 6) and cells.dtype == np.uint8
    assert (cells[0, :5] == OCCUPIED).all() and (cells[:, 5] == UNKNOWN).all()
    assert cells[3, 0] == OCCUPIED and cells[2, 2] == FREE
    assert np.array_equal(m.to_image(), asymmetric_image())
    assert m.counts() == {"free": 14, "occupied": 6, "unknown": 4}


def test_cells_is_a_writable_view():
    m = Map.from_array(asymmetric_image(), 0.1)
    m.cells[2, 2] = OCCUPIED
    assert m.cells[2, 2] == OCCUPIED and m.counts()["occupied"] == 7


def test_occupancy_grid_rows_start_at_the_origin(tmp_path):
    # The same map through the PGM/YAML route and through nav_msgs/OccupancyGrid semantics.
    image = asymmetric_image()
    m = Map.from_array(image, 0.1, origin=(1.0, 2.0, 0.3))
    yaml_path = m.save(str(tmp_path / "map.pgm"))
    loaded = areamatch.load_map(yaml_path)
    assert loaded == m
    # By hand, as a ROS publisher fills data: row 0 is the row at the origin (the image's bottom).
    occupancy = np.where(image == 0, 100, np.where(image == 254, 0, -1)).astype(np.int8)
    data = occupancy[::-1, :].reshape(-1)
    ros = Map.from_occupancy_grid(data, 6, 4, 0.1, (1.0, 2.0, 0.3))
    assert ros == loaded
    # data[0] is the cell nearest the origin: its centre lies half a cell from the origin.
    assert data[0] == 100
    centre = ros.world_from_pixel() @ np.array([0.0, 3.0, 1.0])  # image pixel (col 0, row 3)
    c, s = np.cos(0.3), np.sin(0.3)
    assert np.allclose(centre[:2], [1.0 + 0.05 * c - 0.05 * s, 2.0 + 0.05 * s + 0.05 * c])


def test_occupancy_grid_round_trip(robot):
    fields = robot.map.to_occupancy_grid()
    assert set(fields) == {"data", "width", "height", "resolution", "origin"}
    assert fields["data"].dtype == np.int8 and set(np.unique(fields["data"])) <= {-1, 0, 100}
    assert Map.from_occupancy_grid(**fields) == robot.map
    # rclpy hands over int8 lists; the bytes seen unsigned (255 = -1) read the same.
    as_list = dict(fields, data=fields["data"].tolist())
    assert Map.from_occupancy_grid(**as_list) == robot.map
    as_bytes = dict(fields, data=fields["data"].view(np.uint8))
    assert Map.from_occupancy_grid(**as_bytes) == robot.map


def test_occupancy_thresholds_as_map_saver():
    data = np.array([0, 25, 26, 64, 65, 100, -1], dtype=np.int8)
    m = Map.from_occupancy_grid(data, 7, 1, 0.05)
    assert m.cells[0].tolist() == [FREE, FREE, UNKNOWN, UNKNOWN, OCCUPIED, OCCUPIED, UNKNOWN]


@pytest.mark.parametrize("kwargs, message", [
    (dict(data=np.zeros(5, np.int8), width=2, height=2, resolution=0.05), "has 5 values"),
    (dict(data=np.zeros(4, np.int8), width=2, height=2, resolution=0.0), "resolution"),
    (dict(data=np.zeros(4, np.int8), width=2, height=2, resolution=-1.0), "resolution"),
    (dict(data=np.zeros(4, np.int8), width=0, height=2, resolution=0.05), "positive"),
    (dict(data=np.array([0, 0, 0, 101]), width=2, height=2, resolution=0.05), "got 101 at index 3"),
    (dict(data=np.zeros(4), width=2, height=2, resolution=0.05), "integers"),
])
def test_occupancy_grid_errors(kwargs, message):
    with pytest.raises(ValueError, match=message):
        Map.from_occupancy_grid(**kwargs)


def test_from_array_errors():
    with pytest.raises(ValueError, match="dtype uint8 or uint16"):
        Map.from_array(np.zeros((3, 3)), 0.05)
    with pytest.raises(ValueError, match="two-dimensional"):
        Map.from_array(np.zeros((3, 3, 3), np.uint8), 0.05)
    with pytest.raises(ValueError, match="resolution"):
        Map.from_array(np.zeros((3, 3), np.uint8), float("nan"))


def test_load_errors(tmp_path):
    missing = tmp_path / "missing.yaml"
    with pytest.raises(OSError, match="missing.yaml"):
        areamatch.load_map(str(missing))
    corrupt = tmp_path / "corrupt.png"
    corrupt.write_bytes(b"\x89PNG\r\n\x1a\n not really")
    with pytest.raises(ValueError, match="corrupt.png"):
        areamatch.load_map(str(corrupt))
    Map.from_array(np.full((8, 8), 254, np.uint8), 0.05).save(str(tmp_path / "ok.pgm"))
    with pytest.raises(ValueError, match="resolution"):
        areamatch.load_map(str(tmp_path / "ok.pgm"), resolution=0.0)
    assert areamatch.load_map(str(tmp_path / "ok.pgm"), resolution=0.1).resolution == 0.1


def test_one_error_base(tmp_path):
    # Every library error is an areamatch.Error of its own kind, and still the built-in it was.
    with pytest.raises(areamatch.IoError) as missing:
        areamatch.load_map(str(tmp_path / "missing.yaml"))
    assert isinstance(missing.value, areamatch.Error) and isinstance(missing.value, OSError)
    corrupt = tmp_path / "corrupt.png"
    corrupt.write_bytes(b"\x89PNG\r\n\x1a\n not really")
    with pytest.raises(areamatch.FormatError) as bad_file:
        areamatch.load_map(str(corrupt))
    assert isinstance(bad_file.value, areamatch.Error) and isinstance(bad_file.value, ValueError)
    with pytest.raises(areamatch.ParameterError, match="resolution") as bad_parameter:
        Map.from_array(np.zeros((3, 3), np.uint8), -1.0)
    assert isinstance(bad_parameter.value, ValueError)
    for name in ("Error", "ParameterError", "FormatError", "LimitError", "IoError", "InternalError"):
        assert issubclass(getattr(areamatch, name), areamatch.Error)


def test_paths_and_maps(tmp_path):
    # load_map takes a pathlib.Path as well as a str; match, segment and assess take Maps, and a
    # path passed to them says how to load it.
    Map.from_array(np.full((8, 8), 254, np.uint8), 0.05).save(str(tmp_path / "ok.pgm"))
    loaded = areamatch.load_map(tmp_path / "ok.pgm")
    assert loaded == areamatch.load_map(str(tmp_path / "ok.pgm"))
    with pytest.raises(TypeError, match=r"takes Maps, not paths: load it first, areamatch.load_map\('a.yaml'\)"):
        areamatch.match("a.yaml", loaded)
    with pytest.raises(TypeError, match="areamatch.match takes Maps"):
        areamatch.match(loaded, dest=tmp_path / "ok.pgm")
    with pytest.raises(TypeError, match="areamatch.segment takes Maps"):
        areamatch.segment("a.yaml")
    with pytest.raises(TypeError, match="areamatch.assess takes Maps"):
        areamatch.assess(loaded, "b.yaml")
    assert areamatch.match.__doc__ == areamatch._core.match.__doc__
