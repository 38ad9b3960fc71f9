"""The README's usage example runs as written."""

import pathlib
import re


def test_readme_example_runs(capsys):
    readme = pathlib.Path(__file__).resolve().parents[1] / "README.md"
    blocks = re.findall(r"```python\n(.*?)```", readme.read_text(encoding="utf-8"), re.S)
    assert blocks
    for code in blocks:
        exec(compile(code, str(readme), "exec"), {})
    assert "has 7 joints, but 2 joint values were given" in capsys.readouterr().out
