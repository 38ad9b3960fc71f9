"""Robots and scenes pickle by their description (issue 39 item 5): for every way a Robot is made,
``pickle.loads(pickle.dumps(robot))`` gives an equal robot with the same FK, IK and collision answers
on seeded configurations, also in another process after the description file is gone."""

import pickle
import shutil
import subprocess
import sys

import numpy as np
import pytest

import kinema
from cli import ROOT
from conftest import random_q
from test_from_dh import TWO_LINKS

IIWA = "lbr-iiwa-14-r820"
HOOD = ROOT / "examples" / "scenes" / "fume-hood.toml"
TWO_IIWAS = ROOT / "examples" / "scenes" / "two-iiwas.toml"


def round_trip(obj):
    return pickle.loads(pickle.dumps(obj))


def answers(robot, seed, shapes=True, scene=None):
    """The robot's description, and FK, Jacobian, IK and (with shapes) collision answers on seeded q."""
    Q = random_q(robot, np.random.default_rng(seed), 20)
    out = {
        "name": robot.name,
        "joint_names": robot.joint_names,
        "qlim": robot.qlim,
        "poses": sorted(robot.poses),
        "pose_values": [robot.poses[name] for name in sorted(robot.poses)],
        "fk": robot.fkine_batch(Q),
        "jacobian": robot.jacob0_batch(Q),
        "ik": [robot.ik(robot.fkine(q), q0=q).q for q in Q[:3]],
    }
    if shapes:
        out["collides"] = robot.collides_batch(Q, scene=scene)
        out["distance"] = robot.distance(Q[0], scene=scene)
    return out


def assert_same_answers(expected, robot, seed, shapes=True, scene=None):
    """``robot`` (unpickled) gives the answers ``expected`` (a robot, or its answers taken earlier)."""
    if isinstance(expected, kinema.Robot):
        assert robot == expected
        expected = answers(expected, seed, shapes, scene)
    got = answers(robot, seed, shapes, scene)
    assert got.keys() == expected.keys()
    for key in got:
        np.testing.assert_equal(got[key], expected[key], err_msg=key)


def test_a_builtin_robot_round_trips():
    robot = kinema.Robot.builtin(IIWA)
    assert_same_answers(robot, round_trip(robot), 1)


def test_a_toml_file_robot_pickles_as_its_text(tmp_path):
    path = tmp_path / "arm.toml"
    shutil.copy(ROOT / "robots" / f"{IIWA}.toml", path)
    robot = kinema.Robot.from_file(path)
    expected, data = answers(robot, 2), pickle.dumps(robot)
    path.unlink()
    back = pickle.loads(data)
    assert back == robot
    assert_same_answers(expected, back, 2)


def test_a_file_robot_pickles_as_it_was_read_not_as_the_file_is_now(tmp_path):
    path = tmp_path / "arm.toml"
    shutil.copy(ROOT / "robots" / f"{IIWA}.toml", path)
    robot = kinema.Robot.from_file(path)
    expected = answers(robot, 2)
    path.write_text("not a robot description")
    back = pickle.loads(pickle.dumps(robot))
    assert back == robot
    assert_same_answers(expected, back, 2)
    path.unlink()
    assert pickle.loads(pickle.dumps(robot)) == robot


def test_a_urdf_file_robot_keeps_its_tip_and_shapes(tmp_path):
    path = tmp_path / "folding.urdf"
    path.write_text(TWO_LINKS)
    robot = kinema.Robot.from_file(path, tip="forearm")
    expected, data = answers(robot, 3), pickle.dumps(robot)
    path.unlink()
    back = pickle.loads(data)
    assert back == robot
    assert_same_answers(expected, back, 3)
    assert back.collides([0.0, 3.1]) and not back.collides([0.0, 0.0])
    tipped = kinema.Robot.from_urdf_string(TWO_LINKS, tip="arm")
    assert round_trip(tipped).n == 1 == tipped.n


def test_a_urdf_string_robot_round_trips():
    robot = kinema.Robot.from_urdf_string(TWO_LINKS)
    assert_same_answers(robot, round_trip(robot), 4)


def test_a_dh_robot_keeps_its_rows_named_pose_and_limits():
    links = [
        kinema.RevoluteDH(d=0.3, a=0.1, alpha=np.pi / 2, qlim=[-2.5, 2.5], name="shoulder"),
        kinema.PrismaticDH(theta=0.2, alpha=-np.pi / 2, offset=0.05, qlim=[0.0, 0.4]),
        kinema.RevoluteDH(a=0.7, offset=0.3),
    ]
    base = np.eye(4)
    base[:3, 3] = [0.1, -0.2, 0.5]
    tool = np.eye(4)
    tool[2, 3] = 0.12
    ready = [0.4, 0.1, -1.0]
    robot = kinema.Robot.from_dh(links, name="rpr", base=base, tool=tool, poses={"ready": ready})
    back = round_trip(robot)
    assert_same_answers(robot, back, 5, shapes=False)
    np.testing.assert_array_equal(back.pose("ready"), ready)
    np.testing.assert_array_equal(back.qlim, [[-2.5, 0.0, -np.inf], [2.5, 0.4, np.inf]])
    modified = kinema.Robot.from_dh([kinema.RevoluteMDH(a=0.5), kinema.RevoluteMDH(alpha=0.3, d=0.2)], name="m")
    assert_same_answers(modified, round_trip(modified), 6, shapes=False)


def test_a_scene_and_its_robot_round_trip():
    scene = kinema.Scene.from_file(TWO_IIWAS)
    back_scene = round_trip(scene)
    assert back_scene.robots == scene.robots and back_scene.obstacles == scene.obstacles
    holder = scene.robot("holder")
    back = round_trip(holder)
    assert_same_answers(holder, back, 7, scene=scene)
    assert_same_answers(holder, back, 7, scene=back_scene)
    reach = [0, np.pi / 2, 0, 0, 0, 0, 0]
    assert back.collides(reach, scene=back_scene) and not back.collides(np.zeros(7), scene=back_scene)


def test_a_scene_with_meshes_round_trips():
    hood = kinema.Scene.from_file(HOOD)
    robot = kinema.Robot.builtin(IIWA)
    assert_same_answers(robot, round_trip(robot), 8, scene=round_trip(hood))
    Q = random_q(robot, np.random.default_rng(8), 50)
    np.testing.assert_array_equal(robot.collides_batch(Q, scene=hood), robot.collides_batch(Q, scene=round_trip(hood)))


def test_a_pickled_file_robot_loads_in_another_process_without_the_file(tmp_path):
    path = tmp_path / "arm.toml"
    shutil.copy(ROOT / "robots" / f"{IIWA}.toml", path)
    robot = kinema.Robot.from_file(path)
    Q = random_q(robot, np.random.default_rng(9), 30)
    expected = np.concatenate([robot.fkine_batch(Q).ravel(), robot.collides_batch(Q)])
    (tmp_path / "robot.pickle").write_bytes(pickle.dumps((robot, Q)))
    path.unlink()
    code = (
        "import pickle, sys, numpy as np\n"
        "robot, Q = pickle.loads(open(sys.argv[1], 'rb').read())\n"
        "np.save(sys.argv[2], np.concatenate([robot.fkine_batch(Q).ravel(), robot.collides_batch(Q)]))\n"
    )
    elsewhere = tmp_path / "elsewhere"
    elsewhere.mkdir()
    out = tmp_path / "answers.npy"
    subprocess.run([sys.executable, "-c", code, str(tmp_path / "robot.pickle"), str(out)], cwd=elsewhere, check=True)
    np.testing.assert_array_equal(np.load(out), expected)


def test_a_bad_state_is_named():
    with pytest.raises(kinema.InvalidInput, match="unknown kind `teapot`"):
        kinema.Robot._from_state({"kind": "teapot", "tip": None})
