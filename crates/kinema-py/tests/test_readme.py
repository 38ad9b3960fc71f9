"""The Python code blocks of README.md and docs/*.md run as written.

Each ```python block runs in a fresh namespace, in document order. The usage example of
docs/python.md ends by printing the message of a wrong joint count, which is checked. The viewer's
example needs the kinema command line (target/{release,debug}/kinema or $KINEMA_BIN).
"""

import pathlib
import re

from cli import kinema_binary, needs_cli

REPO = pathlib.Path(__file__).resolve().parents[3]


def documents():
    return [REPO / "README.md"] + sorted((REPO / "docs").glob("*.md"))


@needs_cli
def test_documented_python_examples_run(capsys, monkeypatch):
    # docs/python.md shows the viewer, which runs `kinema serve`: the one built here.
    monkeypatch.setenv("KINEMA_BIN", str(kinema_binary()))
    monkeypatch.setenv("BROWSER", "true")  # `webbrowser` runs `true`: no tab opens
    ran = []
    for doc in documents():
        blocks = re.findall(r"^```python\n(.*?)^```", doc.read_text(encoding="utf-8"), re.S | re.M)
        for code in blocks:
            exec(compile(code, str(doc), "exec"), {})
        if blocks:
            ran.append(doc.relative_to(REPO).as_posix())
    assert "docs/python.md" in ran and "README.md" in ran, ran
    assert "has 7 joints, but 2 joint values were given" in capsys.readouterr().out
