"""The robot's body from Python (issue 37): Scene, collides, distance, collide_dict, collides_batch,
ik(scene=) and check(scene=), checked against each other on seeded configurations and against
``kinema collide --json`` / ``kinema traj check --scene`` field for field."""

import numpy as np
import pytest

import kinema
from cli import ROOT, cli_json, needs_cli
from conftest import random_q

HOOD = ROOT / "examples" / "scenes" / "fume-hood.toml"
IIWA = "lbr-iiwa-14-r820"


@pytest.fixture(scope="module")
def hood():
    return kinema.Scene.from_file(HOOD)


def test_a_scene_reads_its_obstacles(hood):
    assert hood.obstacles == ["bench", "sash", "hood_back", "hood_top"]
    ball = kinema.Scene.from_toml('[[obstacle]]\nname = "ball"\nsphere = { radius = 0.1 }\npose = [0.5, 0, 0.5, 0, 0, 0]\n')
    assert ball.obstacles == ["ball"]
    with pytest.raises(kinema.DescriptionError, match="radius"):
        kinema.Scene.from_toml('[[obstacle]]\nname = "ball"\nsphere = { radius = -1 }\npose = [0, 0, 0, 0, 0, 0]\n')
    with pytest.raises(kinema.RobotFileError):
        kinema.Scene.from_file(ROOT / "no-such-scene.toml")


def test_the_queries_agree_with_each_other(hood):
    robot = kinema.Robot.builtin(IIWA)
    rng = np.random.default_rng(37)
    Q = random_q(robot, rng, 300)
    batch = robot.collides_batch(Q, scene=hood)
    assert batch.shape == (300,) and batch.dtype == np.bool_
    assert 30 < batch.sum() < 270, "a mix of free and colliding configurations"
    for q, hit in zip(Q[:60], batch[:60]):
        assert robot.collides(q, scene=hood) == hit
        answer = robot.collide_dict(q, scene=hood)
        assert answer["collision"] == hit
        assert robot.distance(q, scene=hood) == answer["min_distance"]["distance"]
        assert (robot.distance(q, scene=hood) <= 0.0) == hit
    # A margin only adds collisions; without a scene, only self-collisions remain.
    assert np.all(robot.collides_batch(Q, scene=hood, margin=0.05) >= batch)
    assert np.all(robot.collides_batch(Q) <= batch)


@needs_cli
def test_collide_dict_is_the_cli_answer(hood):
    robot = kinema.Robot.builtin(IIWA)
    rng = np.random.default_rng(5)
    for q in random_q(robot, rng, 8):
        text = ",".join(repr(float(v)) for v in q)
        answer = robot.collide_dict(q, scene=hood, margin=0.01)
        code = 3 if answer["collision"] else 0
        cli = cli_json(["collide", "--robot", IIWA, "--scene", str(HOOD), "--margin", "0.01", "--q", text, "--json"], code)
        assert answer == cli


def test_ik_in_the_fume_hood_turns_the_elbow(hood):
    robot = kinema.Robot.builtin(IIWA)
    T = [0.6, 0.0, 0.3, np.pi, 0.0, 0.0]
    plain = robot.ik(T)
    assert robot.collides(plain.q, scene=hood), "elbow up, the arm hits the sash"
    found = robot.ik(T, scene=hood)
    assert not robot.collides(found.q, scene=hood)
    assert abs(found.q[2]) > 0.5, found.q
    answer = robot.ik_dict(T, all=True, scene=hood)
    assert "collision" in answer["discarded"]["reason"]
    # The batch form keeps the same rule.
    Q, ok, _ = robot.ik_batch(np.array([T]), scene=hood)
    assert ok[0] and not robot.collides(Q[0], scene=hood)
    with pytest.raises(kinema.InvalidInput, match="margin"):
        robot.ik(T, scene=hood, margin=-1.0)


def test_a_motion_through_the_sash_fails_its_check(hood, tmp_path):
    robot = kinema.Robot.builtin(IIWA)
    a = np.array([-np.pi / 2, 1.047, 0, 0, 0, 0, 0])
    b = np.array([np.pi / 2, 1.047, 0, 0, 0, 0, 0])
    assert not robot.collides(a, scene=hood) and not robot.collides(b, scene=hood)
    swing = robot.ptp(a, b, 0.01)
    assert not robot.check(swing).violations
    report = robot.check(swing, scene=hood)
    hits = [v for v in report.violations if v["kind"] == "collision"]
    assert len(hits) == 1 and hits[0]["detail"].endswith("– sash"), hits
    with pytest.raises(kinema.TrajectoryError, match="collision"):
        report.raise_if_violations()


def test_a_program_through_the_sash_is_refused(hood):
    robot = kinema.Robot.builtin(IIWA)
    program = "JVEL 50deg/s\nPTP JOINT(90deg, 60deg, 0, 0, 0, 0, 0)\n"
    start = [-np.pi / 2, 1.047, 0, 0, 0, 0, 0]
    kinema.run_program(program, robot, start=start)
    with pytest.raises(kinema.ProgramError, match="sash"):
        kinema.run_program(program, robot, start=start, scene=hood)


TWO_IIWAS = ROOT / "examples" / "scenes" / "two-iiwas.toml"


@needs_cli
def test_scene_robots_stand_as_obstacles_as_on_the_cli():
    path = TWO_IIWAS
    scene = kinema.Scene.from_file(path)
    assert scene.robots == ["holder", "drawer"]
    holder = scene.robot("holder")
    reach, away = [0, np.pi / 2, 0, 0, 0, 0, 0], [np.pi / 2, np.pi / 2, 0, 0, 0, 0, 0]
    assert holder.collides(reach, scene=scene)
    assert any(p["b"].startswith("drawer/link") for p in holder.collide_dict(reach, scene=scene)["pairs"])
    assert not holder.collides(away, scene=scene)
    assert not holder.collides(np.zeros(7), scene=scene), "not its own obstacle"
    assert kinema.Robot.builtin(IIWA).collides(np.zeros(7), scene=scene), "inside the holder standing there"
    for q, code in ((reach, 3), (away, 0)):
        text = ",".join(repr(float(v)) for v in q)
        cli = cli_json(["collide", "--robot", "holder", "--scene", str(path), "--q", text, "--json"], code)
        assert holder.collide_dict(q, scene=scene) == cli
    with pytest.raises(kinema.InvalidInput, match="nobody"):
        scene.robot("nobody")


def test_queries_alternating_scenes_and_margins_answer_each_their_own(hood):
    """The robot keeps its last check: switching scene or margin between calls must not reuse it."""
    robot = kinema.Robot.builtin(IIWA)
    rng = np.random.default_rng(11)
    Q = random_q(robot, rng, 40)
    fresh = [kinema.Robot.builtin(IIWA) for _ in range(3)]
    expected = [
        fresh[0].collides_batch(Q),
        fresh[1].collides_batch(Q, scene=hood),
        fresh[2].collides_batch(Q, margin=0.05),
    ]
    other = kinema.Scene.from_file(HOOD)
    assert expected[1].any() and not expected[1].all()
    for i, q in enumerate(Q):
        assert robot.collides(q) == expected[0][i]
        assert robot.collides(q, scene=hood) == expected[1][i]
        assert robot.collides(q, margin=0.05) == expected[2][i]
        assert robot.collides(q, scene=other) == expected[1][i]
        assert robot.collides(q, scene=hood, margin=0.0) == expected[1][i]
