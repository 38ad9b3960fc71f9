"""Robots defined in code: Robot.from_dh (the toolbox's DHRobot) and Robot.from_urdf_string."""

import pathlib

import numpy as np
import pytest

import kinema
from kinema import PrismaticDH, PrismaticMDH, RevoluteDH, RevoluteMDH

REPO = pathlib.Path(__file__).resolve().parents[3]


def dh_standard(theta, d, a, alpha):
    ct, st, ca, sa = np.cos(theta), np.sin(theta), np.cos(alpha), np.sin(alpha)
    return np.array([[ct, -st * ca, st * sa, a * ct], [st, ct * ca, -ct * sa, a * st], [0, sa, ca, d], [0, 0, 0, 1]])


def dh_modified(theta, d, a, alpha):
    ct, st, ca, sa = np.cos(theta), np.sin(theta), np.cos(alpha), np.sin(alpha)
    return np.array([[ct, -st, 0, a], [st * ca, ct * ca, -sa, -sa * d], [st * sa, ct * sa, ca, ca * d], [0, 0, 0, 1]])


def random_pose(rng):
    angles = rng.uniform(-np.pi, np.pi, 3)
    rx, ry, rz = (dh_standard(0, 0, 0, angles[0]), dh_modified(angles[1], 0, 0, np.pi / 2), dh_standard(angles[2], 0, 0, 0))
    T = rx @ ry @ rz
    T[:3, 3] = rng.uniform(-0.5, 0.5, 3)
    return T


def random_arm(rng, modified):
    """Random DH links (both joint kinds, offsets) and the reference FK of those rows."""
    links, rows = [], []
    for _ in range(rng.integers(1, 8)):
        a, alpha, offset, fixed = rng.uniform(-0.6, 0.6), rng.uniform(-np.pi, np.pi), rng.uniform(-1, 1), rng.uniform(-0.6, 0.6)
        if rng.random() < 0.3:
            links.append((PrismaticMDH if modified else PrismaticDH)(theta=fixed, a=a, alpha=alpha, offset=offset, qlim=[-0.5, 0.5]))
            rows.append(lambda q, t=fixed, a=a, al=alpha, o=offset: (t, q + o, a, al))
        else:
            links.append((RevoluteMDH if modified else RevoluteDH)(d=fixed, a=a, alpha=alpha, offset=offset, qlim=[-3, 3]))
            rows.append(lambda q, d=fixed, a=a, al=alpha, o=offset: (q + o, d, a, al))
    return links, rows


@pytest.mark.parametrize("modified", [False, True])
def test_from_dh_fk_matches_the_dh_product(modified):
    rng = np.random.default_rng(38 + modified)
    link = dh_modified if modified else dh_standard
    for _ in range(50):
        links, rows = random_arm(rng, modified)
        base, tool = random_pose(rng), random_pose(rng)
        robot = kinema.Robot.from_dh(links, name="arm", base=base, tool=tool)
        q = rng.uniform(-0.5, 0.5, robot.n)
        expected = base
        for row, qi in zip(rows, q):
            expected = expected @ link(*row(qi))
        expected = expected @ tool
        np.testing.assert_allclose(robot.fkine(q), expected, atol=1e-12)
        assert robot.joint_types == "".join("P" if lk.prismatic else "R" for lk in links)


def test_names_limits_and_poses():
    robot = kinema.Robot.from_dh(
        [RevoluteDH(a=1.0, qlim=[-2, 2], name="shoulder"), PrismaticDH(qlim=(0, 0.3))],
        name="rp",
        poses={"qr": [0.5, 0.1]},
    )
    assert (robot.name, robot.joint_names) == ("rp", ["shoulder", "q2"])
    np.testing.assert_array_equal(robot.qlim, [[-2, 0], [2, 0.3]])
    np.testing.assert_array_equal(robot.home, [0, 0])
    np.testing.assert_array_equal(robot.pose("qr"), [0.5, 0.1])
    free = kinema.Robot.from_dh([RevoluteDH(a=1.0)], poses={"home": [0.25]})
    assert np.all(np.isinf(free.qlim)) and free.home[0] == 0.25
    assert "RevoluteDH(d=0.0, a=1.0" in repr(RevoluteDH(a=1.0))


def test_ik_and_trajectories_work_on_a_code_robot():
    links = [RevoluteDH(d=0.4, alpha=np.pi / 2), RevoluteDH(a=0.5), RevoluteDH(a=0.4)]
    robot = kinema.Robot.from_dh(links, name="rrr")
    q = np.array([0.3, 0.4, -0.6])
    sol = robot.ik(position=robot.fkine(q)[:3, 3], q0=q + 0.05)
    np.testing.assert_allclose(robot.fkine(sol.q)[:3, 3], robot.fkine(q)[:3, 3], atol=1e-9)
    tr = robot.ptp(robot.home, q, 0.05, vmax=1.0, amax=2.0)
    np.testing.assert_allclose(tr.q[-1], q, atol=1e-12)


def test_every_problem_is_named_at_once():
    links = [
        RevoluteDH(a=np.nan, qlim=[1, -1]),
        RevoluteMDH(a=1),
        PrismaticDH(offset=np.inf),
    ]
    with pytest.raises(kinema.DescriptionError) as e:
        kinema.Robot.from_dh(links, name="bad", poses={"qz": [0]})
    message = str(e.value)
    assert "5 problems" in message
    for says in (
        "joint[0].a: joint 1 (`q1`): NaN is not a finite number",
        "joint[0].min: joint 1 (`q1`): limits min = 1 and max = -1 are not an interval",
        "joint[1].geometry: joint 2 (`q2`): a modified DH row in a robot described in standard DH",
        "joint[2].offset: joint 3 (`q3`): inf is not a finite number",
        "poses.qz: 1 values, expected one per joint (3)",
    ):
        assert says in message, message


def test_wrong_arguments_are_refused_by_name():
    with pytest.raises(kinema.DescriptionError, match="no joints"):
        kinema.Robot.from_dh([])
    with pytest.raises(kinema.InvalidInput, match=r"`links\[1\]` is not a DH link"):
        kinema.Robot.from_dh([RevoluteDH(), {"a": 1}])
    with pytest.raises(kinema.InvalidInput, match=r"`links\[0\].qlim` must have shape \(2,\)"):
        kinema.Robot.from_dh([RevoluteDH(qlim=[1, 2, 3])])
    with pytest.raises(kinema.InvalidInput, match=r"`links\[0\].a` must be a real number"):
        kinema.Robot.from_dh([RevoluteDH(a="long")])
    with pytest.raises(kinema.InvalidInput, match="`base` is not a rigid transform"):
        kinema.Robot.from_dh([RevoluteDH()], base=np.ones((4, 4)))
    with pytest.raises(kinema.InvalidInput, match="`links` must be a list"):
        kinema.Robot.from_dh("RR")


def test_a_dh_robot_has_no_shapes_to_check():
    robot = kinema.Robot.from_dh([RevoluteDH(a=1)], name="stick")
    with pytest.raises(kinema.DescriptionError, match="robot `stick` is made of DH rows, which have no link shapes"):
        robot.collides([0.0])


def test_from_urdf_string_is_from_file():
    path = REPO / "crates/kinema/tests/data/ur5.urdf"
    text = path.read_text()
    a, b = kinema.Robot.from_urdf_string(text), kinema.Robot.from_file(path)
    q = np.random.default_rng(5).uniform(-2, 2, a.n)
    np.testing.assert_array_equal(a.fkine(q), b.fkine(q))
    assert a.joint_names == b.joint_names
    with pytest.raises(kinema.DescriptionError, match="<string>"):
        kinema.Robot.from_urdf_string("<robot name='x'><link name='a'/>")


TWO_LINKS = """
<robot name="folding">
  <link name="base"><collision><geometry><box size="0.2 0.2 0.5"/></geometry></collision></link>
  <link name="arm"><collision><origin xyz="0.5 0 0"/><geometry><box size="1.0 0.1 0.1"/></geometry></collision></link>
  <link name="forearm"><collision><origin xyz="0.5 0 0"/><geometry><box size="1.0 0.1 0.1"/></geometry></collision></link>
  <joint name="j1" type="revolute"><parent link="base"/><child link="arm"/><origin xyz="0 0 0.2"/>
    <axis xyz="0 0 1"/><limit lower="-3" upper="3" effort="1" velocity="1"/></joint>
  <joint name="j2" type="revolute"><parent link="arm"/><child link="forearm"/><origin xyz="1 0 0"/>
    <axis xyz="0 0 1"/><limit lower="-3.1" upper="3.1" effort="1" velocity="1"/></joint>
</robot>
"""


def test_a_urdf_string_brings_its_collision_shapes():
    robot = kinema.Robot.from_urdf_string(TWO_LINKS)
    assert not robot.collides([0.0, 0.0])
    assert robot.collides([0.0, 3.1])  # the forearm folded back onto the base
    assert robot.distance([0.0, 0.0]) > 0


def test_code_robots_run_in_a_cell():
    """A cell reads each robot's shapes from where it came from: none for DH rows, the URDF string's own."""
    dh = kinema.Robot.from_dh([RevoluteDH(a=1.0, qlim=[-3, 3]), RevoluteDH(a=0.8, qlim=[-3, 3])], name="planar")
    urdf = kinema.Robot.from_urdf_string(TWO_LINKS)
    tr_dh = dh.ptp(dh.home, [0.5, 0.5], 0.05, vmax=1.0, amax=2.0)
    tr_urdf = urdf.ptp(urdf.home, [0.5, 1.0], 0.05, vmax=1.0, amax=2.0)
    report = kinema.Cell(dt=0.05).add("dh", dh, tr_dh).add("urdf", urdf, tr_urdf, base=[3, 0, 0, 0, 0, 0]).run()
    np.testing.assert_allclose(report.tool_positions["urdf"][0], urdf.fkine(urdf.home)[:3, 3] + [3, 0, 0], atol=1e-12)
    np.testing.assert_allclose(report.tool_positions["dh"][-1], dh.fkine([0.5, 0.5])[:3, 3], atol=1e-12)
    assert report.ok and report.bodies == []  # no pair: the DH robot has no shapes to meet the URDF's
