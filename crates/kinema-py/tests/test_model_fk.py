"""Robot loading, properties and forward kinematics, against values computed
independently of kinema (closed forms, numpy DH products)."""

import numpy as np
import pytest

import kinema
from conftest import ROBOTS, random_q


def scorbot_closed_form(q):
    """Seed 000 eq. (3)-(4), θi = qi, lengths of Tabla I in metres."""
    d1, a1, a2, a3, d5 = 0.349, 0.016, 0.221, 0.221, 0.145
    t1, t2, t3, t4, t5 = q
    s1, c1, s5, c5 = np.sin(t1), np.cos(t1), np.sin(t5), np.cos(t5)
    c2, s2 = np.cos(t2), np.sin(t2)
    c23, s23 = np.cos(t2 + t3), np.sin(t2 + t3)
    c234, s234 = np.cos(t2 + t3 + t4), np.sin(t2 + t3 + t4)
    u = a1 + a2 * c2 + a3 * c23 + d5 * c234
    return np.array(
        [
            [s1 * s5 - s234 * c1 * c5, s1 * c5 + s234 * c1 * s5, c234 * c1, c1 * u],
            [-c1 * s5 - s234 * s1 * c5, s234 * s1 * s5 - c1 * c5, c234 * s1, s1 * u],
            [c234 * c5, -c234 * s5, s234, d1 + a3 * s23 + a2 * s2 + d5 * s234],
            [0.0, 0.0, 0.0, 1.0],
        ]
    )


def test_builtin_and_properties(robots):
    r = robots["puma560"]
    assert r.name == "puma560"
    assert r.n == 6
    assert r.qlim.shape == (2, 6) and r.qlim.dtype == np.float64
    assert np.all(r.qlim[0] <= r.qlim[1])
    assert r.home.shape == (6,)
    assert "home" in r.poses and np.array_equal(r.poses["home"], r.home)
    assert np.array_equal(r.pose("home"), r.home)
    assert len(r.joint_names) == 6 and r.joint_types == "RRRRRR"
    assert "puma560" in repr(r)
    assert set(ROBOTS) <= set(kinema.Robot.builtins())
    assert r == kinema.Robot.builtin("puma560") and r != robots["ur5"]


def test_scorbot_home_matches_seed_000_closed_form(robots):
    r = robots["scorbot-er-v-plus"]
    home = np.radians([0, 90, -90, -90, 0])
    assert np.allclose(r.home, home, atol=1e-15)
    T = r.fkine(r.home)
    assert T.shape == (4, 4) and T.dtype == np.float64
    assert np.allclose(T, scorbot_closed_form(home), atol=1e-12)
    # Upper arm vertical, forearm horizontal, gripper down: flange at
    # x = a1 + a3, z = d1 + a2 - d5.
    assert np.allclose(T[:3, 3], [0.016 + 0.221, 0.0, 0.349 + 0.221 - 0.145], atol=1e-12)


def test_scorbot_random_matches_closed_form(robots):
    r = robots["scorbot-er-v-plus"]
    rng = np.random.default_rng(0)
    for q in random_q(r, rng, 50):
        assert np.allclose(r.fkine(q), scorbot_closed_form(q), atol=1e-12)


def test_fkine_is_rigid_transform(robots):
    rng = np.random.default_rng(1)
    for name in ROBOTS:
        r = robots[name]
        T = r.fkine(random_q(r, rng))
        R = T[:3, :3]
        assert np.allclose(R.T @ R, np.eye(3), atol=1e-12)
        assert np.isclose(np.linalg.det(R), 1.0)
        assert np.array_equal(T[3], [0, 0, 0, 1])


def test_iiwa_home_upright(robots):
    T = robots["lbr-iiwa-14-r820"].fkine(robots["lbr-iiwa-14-r820"].home)
    assert np.isclose(T[2, 3], 0.36 + 0.42 + 0.40 + 0.126, atol=1e-12)


def test_fkine_all(robots):
    rng = np.random.default_rng(2)
    for name in ROBOTS:
        r = robots[name]
        q = random_q(r, rng)
        F = r.fkine_all(q)
        assert F.shape == (r.n + 2, 4, 4)
        assert np.allclose(F[0], np.eye(4))  # built-ins have no base transform
        assert np.array_equal(F[-1], r.fkine(q))


def test_scorbot_link_frames_are_dh_products(robots):
    """fkine_all's link frames equal cumulative standard-DH products (Tabla I)."""
    r = robots["scorbot-er-v-plus"]
    d = [0.349, 0, 0, 0, 0.145]
    a = [0.016, 0.221, 0.221, 0, 0]
    alpha = np.radians([90, 0, 0, 90, 0])
    offset = [0, 0, 0, np.pi / 2, 0]
    q = random_q(r, np.random.default_rng(3))
    F = r.fkine_all(q)
    T = np.eye(4)
    for i in range(5):
        th = q[i] + offset[i]
        ct, st, ca, sa = np.cos(th), np.sin(th), np.cos(alpha[i]), np.sin(alpha[i])
        A = np.array([[ct, -ca * st, sa * st, a[i] * ct], [st, ca * ct, -sa * ct, a[i] * st], [0, sa, ca, d[i]], [0, 0, 0, 1]])
        T = T @ A
        assert np.allclose(F[i + 1], T, atol=1e-12)


@pytest.mark.parametrize("convert", [list, tuple, lambda q: np.repeat(q, 2)[::2], lambda q: np.asfortranarray(q)])
def test_input_forms(robots, convert):
    r = robots["puma560"]
    q = random_q(r, np.random.default_rng(4))
    assert np.array_equal(r.fkine(convert(q)), r.fkine(q))
    assert np.array_equal(r.jacob0(convert(q)), r.jacob0(q))


def test_integer_and_float32_input(robots):
    r = robots["puma560"]
    q = np.array([0, 1, -1, 0, 1, 0])
    assert np.array_equal(r.fkine(q), r.fkine(q.astype(float)))
    q32 = np.array([0.1, 0.2, 0.3, 0.4, 0.5, 0.6], dtype=np.float32)
    assert np.array_equal(r.fkine(q32), r.fkine(q32.astype(np.float64)))


def test_pose_name_as_q(robots):
    r = robots["puma560"]
    assert np.array_equal(r.fkine("home"), r.fkine(r.home))


def test_from_file_toml_equals_builtin(robots):
    import pathlib

    path = pathlib.Path(__file__).resolve().parents[3] / "robots" / "puma560.toml"
    if not path.exists():
        pytest.skip("robots/ directory not next to the crate")
    r = kinema.Robot.from_file(path)
    q = random_q(r, np.random.default_rng(5))
    assert np.array_equal(r.fkine(q), robots["puma560"].fkine(q))
    r2 = kinema.Robot.from_file(str(path))
    assert r2.name == "puma560"
