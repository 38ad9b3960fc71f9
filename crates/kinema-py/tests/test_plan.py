"""Robot.plan (issue 39): a collision-free motion around the fume hood's sash, checked by
Robot.check(scene=), the same path as ``kinema plan --json`` for the same seed, a pose goal, and
errors (colliding start, spent budget, both goals)."""

import time

import numpy as np
import pytest

import kinema
from cli import ROOT, cli_json, needs_cli

HOOD = ROOT / "examples" / "scenes" / "fume-hood.toml"
IIWA = "lbr-iiwa-14-r820"
LEFT = np.radians([-90, 60, 0, 0, 0, 0, 0])
RIGHT = np.radians([90, 60, 0, 0, 0, 0, 0])


@pytest.fixture(scope="module")
def hood():
    return kinema.Scene.from_file(HOOD)


@pytest.fixture(scope="module")
def robot():
    return kinema.Robot.builtin(IIWA)


def test_the_swing_across_the_hood_goes_around_the_sash(robot, hood):
    with pytest.raises(kinema.TrajectoryError, match="sash"):
        traj = robot.ptp(LEFT, RIGHT, 0.01)
        robot.check(traj, scene=hood).raise_if_violations()
    planned = robot.plan(LEFT, RIGHT, scene=hood)
    assert planned.to_dict()["motion"] == "plan"
    report = robot.check(planned, scene=hood)
    assert report.ok, report.violations
    np.testing.assert_array_equal(planned.q[0], LEFT)
    np.testing.assert_array_equal(planned.q[-1], RIGHT)
    vias = planned.to_dict()["plan"]["via_points"]
    assert len(vias) >= 3
    again = robot.plan(LEFT, RIGHT, scene=hood)
    np.testing.assert_array_equal(again.q, planned.q)


@needs_cli
def test_the_cli_plans_the_same_path_for_the_same_seed(robot, hood, tmp_path):
    planned = robot.plan(LEFT, RIGHT, scene=hood, seed=3).to_dict()

    def q(v):
        return ",".join(repr(float(x)) for x in v)

    args = ["plan", "--robot", IIWA, "--scene", str(HOOD), "--from=" + q(LEFT), "--to=" + q(RIGHT), "--seed", "3"]
    answer = cli_json(args + ["--json", "--out", str(tmp_path / "plan.csv")])
    assert answer["plan"]["via_points"] == planned["plan"]["via_points"]
    for key in ("duration", "samples", "profile", "motion"):
        assert answer[key] == planned[key], key


def test_a_pose_goal_ends_on_the_pose(robot, hood):
    target = robot.fkine(RIGHT)
    planned = robot.plan(LEFT, pose=target, scene=hood)
    assert planned.to_dict()["plan"]["goals"] >= 8
    np.testing.assert_allclose(robot.fkine(planned.q[-1]), target, atol=1e-9)
    assert robot.check(planned, scene=hood).ok


def test_errors_name_what_is_wrong(robot, hood):
    folded = np.array([0, 2.0, 0, 0, 0, 0, 0])
    with pytest.raises(kinema.InvalidInput, match="the start configuration collides"):
        robot.plan(folded, RIGHT, scene=hood)
    with pytest.raises(kinema.PlanningError, match="before the limit of 1 iteration"):
        robot.plan(LEFT, RIGHT, scene=hood, max_iterations=1, step=0.01)
    with pytest.raises(kinema.InvalidInput, match="not both"):
        robot.plan(LEFT, RIGHT, pose=robot.fkine(RIGHT), scene=hood)
    with pytest.raises(kinema.InvalidInput, match="time_limit"):
        robot.plan(LEFT, RIGHT, scene=hood, time_limit=0)
    with pytest.raises(kinema.InvalidInput, match="seed"):
        robot.plan(LEFT, RIGHT, scene=hood, seed=-1)
    # Timing options are refused before the search, which would take all of its 30 s.
    for bad in (dict(dt=0.0), dict(speed=0.0), dict(speed=1.5), dict(profile="zigzag"), dict(step=1e-12)):
        started = time.monotonic()
        with pytest.raises(kinema.InvalidInput):
            robot.plan(LEFT, RIGHT, scene=hood, time_limit=30, **bad)
        assert time.monotonic() - started < 5, bad
