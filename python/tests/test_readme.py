"""The README's Python example runs as written (in a scratch folder, the problems' paths made
absolute), and its install command is the one python/test.sh uses."""

import re

from conftest import ROOT


def python_section() -> str:
    text = (ROOT / "README.md").read_text()
    return text[text.index("\n## Python\n") :].split("\n## ", 2)[1]


def test_readme_example_runs(tmp_path, monkeypatch, capsys):
    code = re.search(r"```python\n(.*?)```", python_section(), re.S).group(1)
    monkeypatch.chdir(tmp_path)
    exec(compile(code.replace('"problems/', f'"{ROOT}/problems/'), "README.md", "exec"), {})
    printed = capsys.readouterr().out.split()
    assert len(printed) == 4  # the three figures of the first print, the twist of the second
    assert abs(float(printed[3]) - float(printed[0])) < 1e-6  # the schedule given back as arrays
    assert sorted(p.name for p in (tmp_path / "out").iterdir()) == [
        "model.urdf",
        "model.xml",
        "problem.csv",
        "problem.json",
        "whole-optimum.csv",
        "whole-optimum.json",
    ]


def test_readme_install_command_is_the_tested_one():
    assert "pip install ./python" in python_section()
    assert "install --quiet --disable-pip-version-check ./python" in (ROOT / "python" / "test.sh").read_text()
