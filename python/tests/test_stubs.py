"""The type stubs name what the module has: every class, function and attribute in _core.pyi
exists at run time, and every public name of the module is in the stubs."""

import ast
import pathlib

import areamatch
from areamatch import _core

STUB = pathlib.Path(areamatch.__file__).with_name("_core.pyi")


def stub_names():
    tree = ast.parse(STUB.read_text())
    names = {}
    for node in tree.body:
        if isinstance(node, ast.ClassDef):
            members = set()
            for item in node.body:
                if isinstance(item, ast.FunctionDef):
                    members.add(item.name)
                elif isinstance(item, ast.AnnAssign):
                    members.add(item.target.id)
            names[node.name] = members
        elif isinstance(node, ast.FunctionDef):
            names[node.name] = None
        elif isinstance(node, ast.AnnAssign):
            names[node.target.id] = None
    return names


def test_stubs_match_the_module():
    names = stub_names()
    for name, members in names.items():
        assert hasattr(_core, name), f"_core.pyi names {name}, the module has none"
        for member in members or ():
            assert hasattr(getattr(_core, name), member), f"_core.pyi names {name}.{member}, the class has none"
    public = {n for n in dir(_core) if not n.startswith("_")} | {"__version__"}
    assert public <= set(names), f"not in _core.pyi: {sorted(public - set(names))}"


def test_pyproject_reads_the_library_version():
    # pip's version comes from version.hpp through the regex in pyproject.toml: check it matches.
    import re

    import pytest
    tomllib = pytest.importorskip("tomllib")  # Python 3.11+

    root = pathlib.Path(__file__).parents[2]
    settings = tomllib.loads((root / "pyproject.toml").read_text())["tool"]["scikit-build"]["metadata"]["version"]
    found = re.search(settings["regex"], (root / settings["input"]).read_text())
    assert found and found.group("value") == areamatch.__version__
