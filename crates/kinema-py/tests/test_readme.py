"""The Python code blocks of README.md and docs/*.md run as written.

Each ```python block runs in a fresh namespace, in document order. The usage example of
docs/python.md ends by printing the message of a wrong joint count, which is checked.
"""

import pathlib
import re

REPO = pathlib.Path(__file__).resolve().parents[3]


def documents():
    return [REPO / "README.md"] + sorted((REPO / "docs").glob("*.md"))


def test_documented_python_examples_run(capsys):
    ran = []
    for doc in documents():
        blocks = re.findall(r"^```python\n(.*?)^```", doc.read_text(encoding="utf-8"), re.S | re.M)
        for code in blocks:
            exec(compile(code, str(doc), "exec"), {})
        if blocks:
            ran.append(doc.relative_to(REPO).as_posix())
    assert "docs/python.md" in ran and "README.md" in ran, ran
    assert "has 7 joints, but 2 joint values were given" in capsys.readouterr().out
