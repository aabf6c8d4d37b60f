"""Fixtures shared by the Python tests: a synthetic building (made by the library's generator, so
the tests need no data files), the CLI and ../shared when the build tells where they are."""

import os
import pathlib

import pytest

import areamatch


@pytest.fixture(scope="session")
def building():
    return areamatch.synthetic.generate_building(7)


@pytest.fixture(scope="session")
def robot(building):
    return areamatch.synthetic.make_robot_map(building, 8, rotation_rad=0.7, translation_m=(1.5, -2.0),
                                              explored_fraction=0.6, wall_noise_m=0.02)


@pytest.fixture(scope="session")
def cli():
    path = os.environ.get("AREAMATCH_CLI", "")
    if not path or not os.path.exists(path):
        pytest.skip("the areamatch program is not built (AREAMATCH_CLI)")
    return path


@pytest.fixture(scope="session")
def shared_dir():
    path = pathlib.Path(os.environ.get("AREAMATCH_SHARED_DIR", "../shared"))
    if not (path / "pairs.json").exists():
        pytest.skip(f"no shared data at {path}")
    return path


def without_timings(d):
    """A result's JSON object less what differs between runs (seconds)."""
    return {k: v for k, v in d.items() if k != "timings"}
