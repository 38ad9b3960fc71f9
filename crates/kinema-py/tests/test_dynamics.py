"""Dynamics with Corke's names: rne, inertia, coriolis, gravload, accel (kinema::dynamics underneath).

The values are checked against each other and against a hand-computed arm, not against copies
of the core's own formulas: rne at rest is gravload, accel inverts rne, inertia's columns are rne
of unit accelerations, a batch equals its rows, and the gravity convention is Corke's."""

import numpy as np
import pytest

import kinema

from cli import ROOT, kinema_binary, needs_cli

G = 9.81

# Two unit links about horizontal axes (the base is rolled 90° about x, so joint z axes point
# along world -y), 1 kg each at mid-link. Held out straight along +x, the torques that hold it
# are m g times the lever arms: joint 1 carries 0.5 + 1.5 m, joint 2 0.5 m.
PENDULUM = (ROOT / "crates" / "kinema" / "tests" / "data" / "pendulum2.toml").read_text()


@pytest.fixture(scope="module")
def puma():
    return kinema.Robot.builtin("puma560")


@pytest.fixture()
def pendulum(tmp_path):
    path = tmp_path / "pendulum2.toml"
    path.write_text(PENDULUM)
    return kinema.Robot.from_file(path)


def states(robot, rng, count):
    lo, hi = robot.qlim
    q = rng.uniform(lo, hi, size=(count, robot.n))
    return q, rng.uniform(-2, 2, size=q.shape), rng.uniform(-5, 5, size=q.shape)


def test_hand_computed_arm_and_corkes_gravity_convention(pendulum):
    # Default gravity is Corke's Robot.gravity, [0, 0, -9.81]: the arm is pulled down (-z).
    np.testing.assert_allclose(pendulum.gravload([0, 0]), [G * 2.0, G * 0.5], atol=1e-12)
    np.testing.assert_allclose(pendulum.gravload([0, 0], gravity=[0, 0, -G]), [G * 2.0, G * 0.5], atol=1e-12)
    np.testing.assert_allclose(pendulum.gravload([0, 0], gravity=[0, 0, G]), [-G * 2.0, -G * 0.5], atol=1e-12)
    # Hanging straight down (joint 1 at -90°) needs no torque.
    np.testing.assert_allclose(pendulum.gravload([-np.pi / 2, 0]), [0, 0], atol=1e-12)
    # Stretched, joint 1 moves both links: sum of I_zz + m r² = 0.01 + 0.25 + 0.01 + 2.25.
    assert pendulum.inertia([0, 0])[0, 0] == pytest.approx(2.52, abs=1e-12)


def test_rne_at_rest_is_gravload_and_gravity_is_an_argument(puma):
    rng = np.random.default_rng(26)
    q, _, _ = states(puma, rng, 20)
    zero = np.zeros_like(q)
    np.testing.assert_allclose(puma.rne(q, zero, zero), puma.gravload(q), atol=1e-12)
    np.testing.assert_allclose(puma.gravload(q, gravity=[0, 0, 0]), zero, atol=1e-14)
    # Torques are linear in gravity.
    np.testing.assert_allclose(puma.gravload(q, gravity=[0, 0, -2 * G]), 2 * puma.gravload(q), atol=1e-10)
    assert np.abs(puma.gravload("qz")[1]) > 1.0  # the shoulder holds the arm out


def test_accel_inverts_rne(puma):
    rng = np.random.default_rng(1)
    q, qd, qdd = states(puma, rng, 50)
    tau = puma.rne(q, qd, qdd)
    np.testing.assert_allclose(puma.accel(q, qd, tau), qdd, atol=1e-8)
    for g in ([0, 0, 0], [1.0, -2.0, -9.0]):
        np.testing.assert_allclose(puma.accel(q, qd, puma.rne(q, qd, qdd, gravity=g), gravity=g), qdd, atol=1e-8)


def test_inertia_is_symmetric_positive_definite_and_rne_of_unit_accelerations(puma):
    rng = np.random.default_rng(2)
    q, _, _ = states(puma, rng, 20)
    ms = puma.inertia(q)
    assert ms.shape == (20, 6, 6)
    zero = np.zeros(6)
    for qk, m in zip(q, ms):
        np.testing.assert_allclose(m, m.T, atol=1e-12)
        assert np.all(np.linalg.eigvalsh(m) > 0)
        for i in range(6):
            np.testing.assert_allclose(m[:, i], puma.rne(qk, zero, np.eye(6)[i], gravity=[0, 0, 0]), atol=1e-12)
    # rne = M q̈ + C q̇ + g, with C q̇ = rne(q, q̇, 0) without gravity.
    q, qd, qdd = states(puma, rng, 10)
    for k in range(10):
        coriolis = puma.rne(q[k], qd[k], zero, gravity=[0, 0, 0])
        want = puma.inertia(q[k]) @ qdd[k] + coriolis + puma.gravload(q[k])
        np.testing.assert_allclose(puma.rne(q[k], qd[k], qdd[k]), want, atol=1e-10)


def test_coriolis_matrix_times_qd_is_the_velocity_part_of_rne_and_skew_with_mdot(puma):
    rng = np.random.default_rng(4)
    q, qd, _ = states(puma, rng, 10)
    cs = puma.coriolis(q, qd)
    assert cs.shape == (10, 6, 6)
    zero, h = np.zeros(6), 1e-6
    for qk, qdk, c in zip(q, qd, cs):
        np.testing.assert_allclose(c @ qdk, puma.rne(qk, qdk, zero, gravity=[0, 0, 0]), atol=1e-10)
        # dM/dt along qd by central differences; dM/dt - 2C is skew-symmetric.
        mdot = (puma.inertia(qk + h * qdk) - puma.inertia(qk - h * qdk)) / (2 * h)
        n = mdot - 2 * c
        np.testing.assert_allclose(n, -n.T, atol=1e-6)
    np.testing.assert_allclose(puma.coriolis(q[0], qd[0]), cs[0], atol=0)
    with pytest.raises(kinema.InvalidInput):
        puma.coriolis(q[0], qd[0][:5])


def test_one_configuration_or_rows(puma):
    rng = np.random.default_rng(3)
    q, qd, qdd = states(puma, rng, 7)
    tau = puma.rne(q, qd, qdd)
    assert tau.shape == (7, 6) and puma.gravload(q).shape == (7, 6) and puma.accel(q, qd, tau).shape == (7, 6)
    for k in range(7):
        np.testing.assert_array_equal(tau[k], puma.rne(q[k], qd[k], qdd[k]))
        np.testing.assert_array_equal(puma.inertia(q)[k], puma.inertia(q[k]))
        np.testing.assert_array_equal(puma.gravload(q)[k], puma.gravload(q[k]))
    assert puma.rne(list(q[0]), tuple(qd[0]), qdd[0]).shape == (6,)
    assert puma.inertia(q[0]).shape == (6, 6)
    # A named pose is a configuration, as in fkine.
    np.testing.assert_array_equal(puma.gravload("home"), puma.gravload(puma.home))
    # An empty batch is an empty result.
    assert puma.rne(np.zeros((0, 6)), np.zeros((0, 6)), np.zeros((0, 6))).shape == (0, 6)


def test_bad_input_raises_with_what_was_expected(puma, tmp_path):
    q = np.zeros(6)
    with pytest.raises(kinema.InvalidInput, match=r"`qd` must have shape \(6,\) for one configuration or \(N, 6\)"):
        puma.rne(q, np.zeros(5), q)
    with pytest.raises(kinema.InvalidInput, match=r"`q` must have shape \(6,\).*got shape \(2, 3\)"):
        puma.inertia(np.zeros((2, 3)))
    with pytest.raises(kinema.InvalidInput, match=r"`qdd` has shape \(3, 6\) but `q` has shape \(6,\); give them the same shape"):
        puma.rne(q, q, np.zeros((3, 6)))
    with pytest.raises(kinema.InvalidInput, match=r"`gravity` must have shape \(3,\).*got shape \(2,\)"):
        puma.gravload(q, gravity=[0, -9.81])
    with pytest.raises(kinema.InvalidInput, match=r"`gravity` holds NaN; its three values must be finite"):
        puma.gravload(q, gravity=[0, 0, np.nan])
    with pytest.raises(kinema.InvalidInput, match=r"NaN"):
        puma.gravload([0, np.nan, 0, 0, 0, 0])
    with pytest.raises(kinema.InvalidInput, match=r"`qd` is inf; it must be a finite number"):
        puma.rne(q, [0, 0, np.inf, 0, 0, 0], q)
    # In a batch the error names the row.
    bad = np.zeros((4, 6))
    bad[2, 1] = np.nan
    with pytest.raises(kinema.InvalidInput, match=r"configuration 2"):
        puma.gravload(bad)
    with pytest.raises(kinema.InvalidInput, match=r"`qd` must be an array of numbers, not a string"):
        puma.rne(q, "fast", q)
    with pytest.raises(kinema.InvalidInput, match=r"complex"):
        puma.rne(q, q, q + 1j)
    # A robot without mass properties says which link lacks them.
    massless = tmp_path / "massless.toml"
    massless.write_text(PENDULUM.replace("[joint.inertial]\nmass = 1\ncom = [-0.5, 0, 0]\ninertia = [0.001, 0.01, 0.01, 0, 0, 0]\n", ""))
    r = kinema.Robot.from_file(massless)
    for call in (lambda: r.rne([0, 0], [0, 0], [0, 0]), lambda: r.inertia([0, 0]), lambda: r.gravload([0, 0]),
                 lambda: r.accel([0, 0], [0, 0], [0, 0])):
        with pytest.raises(kinema.KinemaError, match=r"link 1 \(moved by joint `j1`\) has no mass properties"):
            call()


@needs_cli
def test_same_torques_as_kinema_dyn(puma, tmp_path):
    import subprocess

    rng = np.random.default_rng(4)
    q, qd, qdd = states(puma, rng, 5)
    t = np.arange(5) * 0.1
    path = tmp_path / "traj.csv"
    header = ["t"] + [f"{p}{i}" for p in ("q", "qd", "qdd") for i in range(1, 7)]
    rows = np.column_stack([t, q, qd, qdd])
    path.write_text(",".join(header) + "\n" + "\n".join(",".join(repr(float(v)) for v in r) for r in rows) + "\n")
    r = subprocess.run([str(kinema_binary()), "dyn", "-r", "puma560", str(path)], capture_output=True, text=True, timeout=300)
    if "unrecognized subcommand" in r.stderr:
        pytest.skip("the kinema binary predates `kinema dyn`")
    assert r.returncode == 0, r.stderr
    cli = np.loadtxt(r.stdout.splitlines()[1:], delimiter=",")
    np.testing.assert_allclose(cli[:, 1:], puma.rne(q, qd, qdd), atol=1e-8)


def test_results_that_would_overflow_raise_naming_the_inputs(puma):
    """Issue 35 item 6: rne and accel used to return NaN for huge rates; now every answer is
    finite or an InvalidInput naming the result and the largest inputs (seeded, 300 cases)."""
    rng = np.random.default_rng(356)
    answered = refused = 0
    for _ in range(300):
        q = rng.uniform(-1, 1, 6)
        qd, qdd = (rng.choice([-1, 1], 6) * 10.0 ** rng.uniform(-3, 300, 6) for _ in range(2))
        for call in (lambda: puma.rne(q, qd, qdd), lambda: puma.accel(q, qd, qdd), lambda: puma.coriolis(q, qd)):
            try:
                out = np.asarray(call())
            except kinema.InvalidInput as e:
                assert "too large for a finite result" in str(e) and "joint" in str(e)
                refused += 1
            else:
                assert np.all(np.isfinite(out))
                answered += 1
    assert answered > 50 and refused > 50
    with pytest.raises(kinema.InvalidInput, match=r"torque of joint \d.*too large.*q̇"):
        puma.rne(np.zeros(6), [1e200] * 6, np.zeros(6))
