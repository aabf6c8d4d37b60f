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


def _split_top_level(text):
    """Splits a parameter list at the commas outside brackets."""
    parts, depth, current = [], 0, ""
    for ch in text:
        if ch in "([{":
            depth += 1
        elif ch in ")]}":
            depth -= 1
        if ch == "," and depth == 0:
            parts.append(current.strip())
            current = ""
        else:
            current += ch
    if current.strip():
        parts.append(current.strip())
    return parts


def _runtime_signatures(obj, name):
    """The parameter lists pybind11 writes at the head of `obj`'s docstring (one per overload):
    names in order, '*' where keyword-only ones begin, 'self' left out."""
    import re
    found = []
    for line in (obj.__doc__ or "").splitlines():
        m = re.match(r"^(?:\d+\. )?" + re.escape(name) + r"\((.*)\) -> ", line)
        if not m:
            continue
        names = []
        for part in _split_top_level(m.group(1)):
            token = part.split(":")[0].split("=")[0].strip()
            if token != "self":
                names.append(token)
        found.append(names)
    return found


def _stub_signature(node):
    a = node.args
    names = [x.arg for x in a.posonlyargs + a.args if x.arg != "self"]
    if a.vararg:
        names.append("*" + a.vararg.arg)
    elif a.kwonlyargs:
        names.append("*")
    names += [x.arg for x in a.kwonlyargs]
    if a.kwarg:
        names.append("**" + a.kwarg.arg)
    return names


def test_stub_signatures_match_the_module():
    # Not only the names: each function's and method's parameters, in order and keyword-only where
    # the module's are (what mypy's stubtest checks; Debian has no stubtest).
    tree = ast.parse(STUB.read_text())
    checked = 0
    for node in tree.body:
        owners = []
        if isinstance(node, ast.FunctionDef):
            owners = [(getattr(_core, node.name), node)]
        elif isinstance(node, ast.ClassDef):
            cls = getattr(_core, node.name)
            owners = [(getattr(cls, item.name), item) for item in node.body
                      if isinstance(item, ast.FunctionDef) and not item.name.startswith("__")]
        for obj, fn in owners:
            runtime = _runtime_signatures(obj, fn.name)
            if not runtime:
                continue  # a property or a plain Python attribute: no pybind11 signature to read
            assert _stub_signature(fn) in runtime, f"_core.pyi {fn.name}{_stub_signature(fn)} is not one of {runtime}"
            checked += 1
    assert checked >= 20, checked


def test_package_stub_signatures_match_the_python_functions():
    # __init__.pyi's own functions (written in Python: inspect reads their signatures).
    import inspect
    tree = ast.parse(pathlib.Path(areamatch.__file__).with_name("__init__.pyi").read_text())
    functions = [node for node in tree.body if isinstance(node, ast.FunctionDef)]
    assert functions
    for fn in functions:
        names, keyword_only = [], False
        for p in inspect.signature(getattr(areamatch, fn.name)).parameters.values():
            if p.kind is p.KEYWORD_ONLY and not keyword_only:
                names.append("*")
                keyword_only = True
            names.append(p.name)
        assert _stub_signature(fn) == names, f"__init__.pyi {fn.name}{_stub_signature(fn)} != {names}"


def test_keywords_with_a_unit_end_in_it():
    # One naming rule (docs/python.md): a keyword that holds a length, an area or an angle ends in
    # its unit (_m, _m2, _rad), as the C++ fields do; map_server's `resolution` keeps its name, and
    # Map.from_occupancy_grid's `width`/`height` are cell counts named as ROS's message names them.
    import inspect
    import re
    measured = re.compile(r"(width|spacing|length|distance|radius|residual|error_scale|translation|rotation|overlap)$")
    seen = set()
    for name in dir(_core):
        obj = getattr(_core, name)
        members = [obj] + ([getattr(obj, m) for m in vars(obj) if not m.startswith("_") or m == "__init__"]
                           if inspect.isclass(obj) else [])
        for member in members:
            for line in (getattr(member, "__doc__", None) or "").splitlines():
                m = re.match(r"^(?:\d+\. )?\w+\((.*)\) -> ", line)
                if m:
                    seen.update(part.split(":")[0].split("=")[0].strip() for part in _split_top_level(m.group(1)))
    for fn in (areamatch.merge,):
        seen.update(inspect.signature(fn).parameters)
    assert {"door_width_m", "bend_length_m", "control_spacing_m"} <= seen
    offending = sorted(k for k in seen if measured.search(k) and k not in ("width", "height"))
    assert not offending, f"keywords with a unit but no unit suffix: {offending}"
