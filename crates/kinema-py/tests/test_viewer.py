"""Robot.show and Robot.animate start a real `kinema serve` and post to it;
what the page is asked to show is read back from the server's API."""

import urllib.request

import numpy as np
import pytest

import kinema
from cli import ROOT, kinema_binary, needs_cli

pytestmark = needs_cli


@pytest.fixture(autouse=True)
def kinema_bin(monkeypatch):
    monkeypatch.setenv("KINEMA_BIN", str(kinema_binary()))


def page_is_served(url):
    with urllib.request.urlopen(url, timeout=10) as res:
        return res.status == 200 and b"<html" in res.read().lower()


def test_show_then_animate_reach_one_server_and_its_state_is_what_was_sent():
    robot = kinema.Robot.builtin("lbr-iiwa-14-r820")
    q = np.array([0.3, -0.4, 0.2, 1.1, -0.5, 0.6, 0.1])
    viewer = robot.show(q, open_browser=False)
    assert page_is_served(viewer.url)
    shown = viewer.shown()
    assert shown["robot"] == "lbr-iiwa-14-r820" and "t" not in shown
    np.testing.assert_array_equal(shown["q"], q)

    again = robot.show(robot.home, open_browser=False)
    assert again is viewer and again.pid == viewer.pid
    np.testing.assert_array_equal(viewer.shown()["q"], robot.home)
    assert viewer.shown()["version"] == shown["version"] + 1

    motion = robot.ptp(robot.home, q, 0.01)
    assert robot.animate(motion, open_browser=False) is viewer
    played = viewer.shown()
    np.testing.assert_array_equal(played["t"], motion.t)
    np.testing.assert_array_equal(played["q"][-1], motion.q[-1])
    np.testing.assert_allclose(played["q"][-1], q, atol=1e-12)


def test_animate_takes_a_t_q_pair():
    robot = kinema.Robot.builtin("puma560")
    t = [0.0, 0.5, 1.0]
    q = [robot.home, np.full(6, 0.2), np.full(6, 0.4)]
    viewer = robot.animate((t, q), open_browser=False)
    assert viewer.shown()["robot"] == "puma560"
    np.testing.assert_array_equal(viewer.shown()["q"][2], q[2])


def test_a_robot_from_a_file_is_served_from_that_file():
    robot = kinema.Robot.from_file(ROOT / "robots" / "puma560.toml")
    viewer = robot.show(robot.home, open_browser=False)
    assert viewer.shown()["robot"] == robot.name


def test_bad_joint_values_raise_before_anything_is_sent():
    robot = kinema.Robot.builtin("lbr-iiwa-14-r820")
    viewer = robot.show(robot.home, open_browser=False)
    before = viewer.shown()["version"]
    with pytest.raises(kinema.InvalidInput):
        robot.show(np.zeros(3), open_browser=False)
    with pytest.raises(kinema.InvalidInput):
        robot.show([0, 0, float("nan"), 0, 0, 0, 0], open_browser=False)
    with pytest.raises(kinema.InvalidInput):
        robot.animate(([0.0, 1.0], [robot.home, np.zeros(6)]), open_browser=False)
    with pytest.raises(kinema.InvalidInput):
        robot.animate(([1.0, 0.0], [robot.home, robot.home]), open_browser=False)
    assert viewer.shown()["version"] == before


def test_a_robot_defined_by_dh_rows_is_refused_with_a_reason():
    arm = kinema.Robot.from_dh([kinema.RevoluteDH(a=1.0), kinema.RevoluteDH(a=0.8)], name="planar2")
    with pytest.raises(kinema.InvalidInput, match="DH rows"):
        arm.show([0.0, 0.0], open_browser=False)


def test_the_viewer_displays_inline_in_jupyter():
    robot = kinema.Robot.builtin("puma560")
    viewer = robot.show(robot.home, open_browser=False)
    assert f'src="{viewer.url}"' in viewer._repr_html_()
