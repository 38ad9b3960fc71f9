"""Every script in crates/kinema-py/examples runs and says what it should."""

import os
import pathlib
import subprocess
import sys

import pytest

from cli import kinema_binary

EXAMPLES = pathlib.Path(__file__).resolve().parents[1] / "examples"
SAYS = {
    "01_robot_from_dh.py": "largest difference from the built-in puma560: 0.0",
    "02_ik.py": "shoulder-left/elbow-up",
    "03_trajectory_plot.py": "IK along the line: all found: True",
    "04_collision_scene.py": "random configurations collide",
    "05_viewer.py": "on the same server: True",
}


def test_every_example_is_listed():
    assert sorted(p.name for p in EXAMPLES.glob("*.py")) == sorted(SAYS)


@pytest.mark.parametrize("name", sorted(SAYS))
def test_example_runs(name, tmp_path):
    # The viewer example runs `kinema serve`; BROWSER=true makes `webbrowser` open no tab.
    env = dict(os.environ, MPLBACKEND="Agg", BROWSER="true")
    if name == "05_viewer.py":
        if kinema_binary() is None:
            pytest.skip("the kinema command line is not built (cargo build -p kinema-cli)")
        env["KINEMA_BIN"] = str(kinema_binary())
    done = subprocess.run(
        [sys.executable, str(EXAMPLES / name), str(tmp_path)],
        capture_output=True, text=True, env=env, timeout=300, cwd=tmp_path,
    )
    assert done.returncode == 0, done.stderr
    assert SAYS[name] in done.stdout, done.stdout
    if name == "03_trajectory_plot.py":
        assert {p.name for p in tmp_path.glob("*.png")} == {"puma-lin.png", "puma-lin-joints.png", "puma-lin-cartesian.png"}
