"""The README's Python quickstart runs as written, on two map files made here."""

import os
import pathlib
import re
import subprocess
import sys

import areamatch

README = pathlib.Path(__file__).parents[2] / "README.md"


def test_readme_python_quickstart(tmp_path):
    text = README.read_text()
    section = text[text.index("## Python"):]
    code = re.search(r"```python\n(.*?)```", section, re.S).group(1)
    b = areamatch.synthetic.generate_building(5)
    robot = areamatch.synthetic.make_robot_map(b, 6, rotation_rad=0.4, translation_m=(1.0, 0.5), explored_fraction=0.7)
    robot.map.save(str(tmp_path / "robot.pgm"))
    b.layout.save(str(tmp_path / "layout.pgm"))
    run = subprocess.run([sys.executable, "-c", code], cwd=tmp_path, capture_output=True, text=True, env=dict(os.environ, PYTHONPATH=str(pathlib.Path(areamatch.__file__).parents[1])))
    assert run.returncode == 0, run.stderr
    assert run.stdout.startswith("rotation ") and re.search(r"area \d+ -> \d+", run.stdout)
