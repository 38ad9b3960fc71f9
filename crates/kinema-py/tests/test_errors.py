"""Bad input raises the right exception, with the core's message text."""

import re

import numpy as np
import pytest

import kinema


def test_hierarchy():
    assert issubclass(kinema.InvalidInput, kinema.KinemaError)
    assert issubclass(kinema.InvalidInput, ValueError)
    assert issubclass(kinema.UnknownRobot, kinema.InvalidInput)
    assert issubclass(kinema.DescriptionError, ValueError)
    assert issubclass(kinema.RobotFileError, OSError)
    assert issubclass(kinema.Unreachable, kinema.KinemaError)
    assert not issubclass(kinema.Unreachable, ValueError)


def test_unknown_robot():
    with pytest.raises(kinema.UnknownRobot, match=r"^unknown robot `r2d2`: .*built-in robots are: .*puma560"):
        kinema.Robot.builtin("r2d2")


def test_wrong_joint_count(robots):
    r = robots["puma560"]
    msg = "robot `puma560` has 6 joints, but 5 joint values were given"
    for f in (r.fkine, r.fkine_all, r.jacob0, r.jacobe, r.manipulability):
        with pytest.raises(kinema.InvalidInput) as e:
            f([0.0] * 5)
        assert str(e.value) == msg
        assert isinstance(e.value, ValueError) and isinstance(e.value, kinema.KinemaError)


def test_nan(robots):
    r = robots["puma560"]
    with pytest.raises(ValueError, match=r"^joint 2 \(`.+`\) of robot `puma560` is NaN; joint values must be finite numbers within ±1e9$"):
        r.fkine([0, np.nan, 0, 0, 0, 0])
    with pytest.raises(kinema.InvalidInput, match=r"is inf"):
        r.jacob0([0, 0, 0, np.inf, 0, 0])


def test_bad_shapes(robots):
    r = robots["puma560"]
    with pytest.raises(kinema.InvalidInput, match=r"use the \*_batch methods"):
        r.fkine(np.zeros((2, 6)))
    with pytest.raises(kinema.InvalidInput, match=r"`q` must have shape \(N,\) .*got shape \(\)"):
        r.fkine(1.0)
    with pytest.raises(kinema.InvalidInput, match=r"`Q` must have shape \(N, 6\) .*got shape \(10, 5\)"):
        r.fkine_batch(np.zeros((10, 5)))
    with pytest.raises(kinema.InvalidInput, match=r"got shape \(6,\)"):
        r.jacob0_batch(np.zeros(6))
    with pytest.raises(kinema.InvalidInput, match=r"cannot be read as an array of float64"):
        r.fkine(["a", "b", "c", "d", "e", "f"])
    with pytest.raises(kinema.InvalidInput, match=r"cannot be read as an array of float64"):
        r.fkine([[0.0, 1.0], [2.0]])
    with pytest.raises(kinema.InvalidInput, match=r"^robot `puma560` has no named pose `nope`; its poses are: "):
        r.fkine("nope")


@pytest.mark.filterwarnings("error")
def test_values_numpy_would_change_silently_are_refused(robots):
    """numpy's own float64 conversion drops an imaginary part with only a warning and parses
    text as numbers; kinema refuses both instead of computing with something else."""
    r = robots["puma560"]
    q = np.full(6, 0.1)
    for bad in (q + 1j, q.astype(complex), [np.complex128(0.1)] * 6):
        with pytest.raises(kinema.InvalidInput, match=r"^`q` holds complex numbers \(complex128\); joint values and poses are real"):
            r.fkine(bad)
    with pytest.raises(kinema.InvalidInput, match=r"^`Q` holds complex numbers"):
        r.fkine_batch(np.zeros((3, 6), dtype=complex))
    with pytest.raises(kinema.InvalidInput, match=r"^`T` holds complex numbers"):
        r.ik(np.eye(4, dtype=complex))
    with pytest.raises(kinema.InvalidInput, match=r"^`q` cannot be read as an array of float64 numbers: it holds <U3, not numbers"):
        r.fkine(["0.1"] * 6)
    with pytest.raises(kinema.InvalidInput, match=r"it holds datetime64"):
        r.jacob0(np.zeros(6, dtype="datetime64[s]"))
    # Arrays of Python objects: numpy would parse the text and drop the imaginary parts too.
    for bad, what in (
        ([0.1, 0.1, "0.1", 0.1, 0.1, 0.1], r"text \(str\) at flat index 2"),
        ([0.1, 0.1, 0.1, 0.1, b"0.1", 0.1], r"text \(bytes\) at flat index 4"),
        ([0.1, 0.1, 0.1, 0.1, 0.1, 1 + 2j], r"a complex number \(complex\) at flat index 5"),
        (np.array([np.complex64(1)] + [0.1] * 5, dtype=object), r"a complex number \(numpy.complex64\) at flat index 0"),
        ([0.1] * 5 + [np.datetime64("2020-01-01")], r"a date or time \(numpy.datetime64\) at flat index 5"),
        ([np.timedelta64(5, "s")] + [0.1] * 5, r"a date or time \(numpy.timedelta64\) at flat index 0"),
        ([0.1, bytearray(b"0.1")] + [0.1] * 4, r"text \(bytearray\) at flat index 1"),
        ([0.1, memoryview(b"0.1")] + [0.1] * 4, r"text \(memoryview\) at flat index 1"),
        ([0.1] * 3 + [np.array("0.1")] + [0.1] * 2, r"an array of <U3 at flat index 3"),
        ([0.1] * 3 + [np.array(1j)] + [0.1] * 2, r"an array of complex128 at flat index 3"),
    ):
        obj = np.empty(6, dtype=object)
        obj[:] = bad
        with pytest.raises(kinema.InvalidInput, match=r"^`q` holds " + what + "; joint values and poses are real numbers"):
            r.fkine(obj)
    # Scalar arguments: a numpy complex scalar raises TypeError as Python's complex does.
    iiwa = robots["lbr-iiwa-14-r820"]
    T = iiwa.fkine(np.full(7, 0.3))
    for bad in (0.3 + 0j, np.complex128(0.3), np.complex64(0.3)):
        with pytest.raises(TypeError, match=r"^argument 'q3': must be real number, not "):
            iiwa.ik(T, q3=bad)
        with pytest.raises(TypeError, match=r"^argument 'dt': must be real number"):
            r.ptp(r.home, r.home, dt=bad)
    with pytest.raises(TypeError, match=r"^argument 'duration': must be real number"):
        kinema.time_law("trapezoid", duration=np.complex128(1))
    # What numpy converts exactly is still taken: integers, booleans, float32, object arrays of
    # numbers (Python's, numpy's, Fractions and Decimals); numpy's real scalars as arguments.
    from decimal import Decimal
    from fractions import Fraction

    mixed = np.array([0.1, 1, np.float32(0.5), Fraction(1, 3), Decimal("0.25"), True], dtype=object)
    for fine in (np.zeros(6, dtype=np.int32), np.zeros(6, dtype=bool), q.astype(np.float32), q.astype(object), mixed):
        assert r.fkine(fine).shape == (4, 4)
    assert np.array_equal(r.fkine(mixed), r.fkine(mixed.astype(float)))
    for fine in (0.3, np.float64(0.3), np.float32(0.3), np.int64(0), 1, Fraction(3, 10)):
        assert iiwa.ik(T, q3=fine).success


def test_batch_error_names_row(robots):
    r = robots["puma560"]
    Q = np.zeros((100, 6))
    Q[37, 4] = np.nan
    for f in (r.fkine_batch, r.jacob0_batch, r.jacobe_batch):
        with pytest.raises(kinema.InvalidInput, match=r"^configuration 37 of the batch \(counting from 0\): joint 5 "):
            f(Q)


def test_manipulability_axes(robots):
    with pytest.raises(kinema.InvalidInput, match=r"invalid `axes`: `xyz`"):
        robots["puma560"].manipulability(robots["puma560"].home, axes="xyz")


def test_unreachable(robots):
    r = robots["puma560"]
    T = np.eye(4)
    T[:3, 3] = [5.0, 0.0, 0.0]
    with pytest.raises(kinema.Unreachable) as e:
        r.ik(T)
    assert str(e.value).startswith("unreachable target (pieper solver): ")
    assert e.value.solver == "pieper"
    assert e.value.reason and e.value.reason in str(e.value)
    with pytest.raises(kinema.Unreachable, match=r"^unreachable target \(numeric solver\): no solution found"):
        robots["panda"].ik(T)


def test_unreachable_joint_limits(robots):
    """Poses reached only outside the limits: all=True lists them, all=False raises."""
    r = robots["puma560"]
    rng = np.random.default_rng(40)
    lo, hi = r.qlim
    found = 0
    for _ in range(200):
        q = rng.uniform(lo, hi)
        q[2] = hi[2] + rng.uniform(0.2, 0.8)  # elbow beyond its upper limit
        T = r.fkine(q)
        sols = r.ik(T, all=True)
        if any(s.within_limits for s in sols):
            continue
        found += 1
        assert not any(s.success for s in sols)
        with pytest.raises(kinema.Unreachable, match=r"^unreachable target \(pieper solver\): every solution violates a joint limit: "):
            r.ik(T)
    assert found >= 3


def test_ik_bad_target_and_options(robots):
    r = robots["puma560"]
    with pytest.raises(kinema.InvalidInput, match=r"`T` must have shape \(4, 4\)"):
        r.ik(np.eye(3))
    bad = np.eye(4)
    bad[0, 0] = 2.0
    with pytest.raises(kinema.InvalidInput, match=r"not a rigid transform"):
        r.ik(bad)
    nan = np.eye(4)
    nan[0, 3] = np.nan
    with pytest.raises(kinema.InvalidInput, match=r"not a rigid transform"):
        r.ik(nan)
    with pytest.raises(kinema.InvalidInput, match=r"unknown solver `fast`; expected one of: auto, analytic, numeric"):
        r.ik(np.eye(4), solver="fast")
    with pytest.raises(kinema.InvalidInput, match=r"has no analytic solver"):
        robots["panda"].ik(np.eye(4), solver="analytic")
    with pytest.raises(kinema.InvalidInput, match=r"has 6 joints, but 2 joint values"):
        r.ik(r.fkine(r.home), q0=[0.0, 0.0])
    with pytest.raises(kinema.InvalidInput, match=r"not both"):
        robots["lbr-iiwa-14-r820"].ik(np.eye(4), q3=0.0, psi=0.0)
    with pytest.raises(kinema.InvalidInput, match=r"q3 and psi select an analytic solver; drop the numeric solver"):
        robots["lbr-iiwa-14-r820"].ik(np.eye(4), q3=0.0, solver="numeric")
    with pytest.raises(kinema.KinemaError):
        r.ik(r.fkine(r.home), q3=0.0)  # not an iiwa-type arm


def test_files(tmp_path):
    with pytest.raises(kinema.RobotFileError, match=r"^cannot read `.*missing\.toml`"):
        kinema.Robot.from_file(tmp_path / "missing.toml")
    bad = tmp_path / "bad.toml"
    bad.write_text('name = "x"\nconvention = "standard"\n[[joint]]\nd = "oops"\n')
    with pytest.raises(kinema.DescriptionError) as e:
        kinema.Robot.from_file(bad)
    assert re.match(r"^.*bad\.toml:\d+:\d+: ", str(e.value))
    assert isinstance(e.value, ValueError)
    with pytest.raises(kinema.InvalidInput, match=r"tip link only applies to URDF"):
        kinema.Robot.from_file(bad, tip="link6")
