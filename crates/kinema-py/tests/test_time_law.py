"""Standalone time laws: end points, limits, derivatives against finite differences, closed forms, errors."""

import numpy as np
import pytest

import kinema

LIMITS = dict(vmax=0.8, amax=2.0, jmax=20.0)


@pytest.mark.parametrize("profile", ["trapezoid", "scurve", "cubic", "quintic", "linear"])
@pytest.mark.parametrize("distance", [1.0, 0.37, 2.5])
def test_law_from_limits_ends_limits_and_derivatives(profile, distance):
    law = kinema.time_law(profile, distance, **LIMITS)
    assert isinstance(law, kinema.TimeLaw) and law.profile == profile and law.distance == distance
    T = law.duration
    assert T > 0 and np.isclose(sum(law.phase_times), T, rtol=1e-12)
    t = np.linspace(0.0, T, 20001)
    p, v, a, j = law.sample(t)
    assert p.shape == v.shape == a.shape == j.shape == t.shape
    assert p[0] == 0.0 and np.isclose(p[-1], distance, rtol=0, atol=1e-12)
    assert np.all(np.diff(p) >= -1e-15)  # rest to rest (or constant speed): never backwards
    tol = 1 + 1e-9
    assert np.abs(v).max() <= LIMITS["vmax"] * tol
    if profile != "linear":
        assert np.abs(a).max() <= LIMITS["amax"] * tol
    if profile in ("scurve", "quintic"):
        assert np.abs(j).max() <= LIMITS["jmax"] * tol
    # v and a are the derivatives of p and v (central differences, away from the jumps).
    h = t[1] - t[0]
    fd_v = (p[2:] - p[:-2]) / (2 * h)
    assert np.abs(fd_v - v[1:-1]).max() < 1e-3 * max(1.0, distance)
    if profile in ("scurve", "quintic"):  # continuous acceleration
        fd_a = (v[2:] - v[:-2]) / (2 * h)
        assert np.abs(fd_a - a[1:-1]).max() < 1e-2 * max(1.0, distance)
    # The closed-form peaks are the sampled maxima.
    pv, pa, pj = law.peaks
    assert np.isclose(pv, np.abs(v).max(), rtol=1e-3)
    if profile in ("trapezoid", "scurve", "quintic"):
        assert np.isclose(pa, np.abs(a).max(), rtol=1e-3)
    if profile in ("trapezoid", "cubic", "linear"):
        assert pj == np.inf
    if profile == "linear":
        assert pa == np.inf


def test_law_durations_match_closed_forms():
    v, a = 0.8, 2.0
    # Trapezoid with cruise (D ≥ v²/a): T = D/v + v/a; triangle: T = 2·sqrt(D/a).
    assert np.isclose(kinema.time_law("trapezoid", 1.0, vmax=v, amax=a).duration, 1.0 / v + v / a, rtol=1e-14)
    law = kinema.time_law("trapezoid", 0.1, vmax=v, amax=a)
    assert np.isclose(law.duration, 2 * np.sqrt(0.1 / a), rtol=1e-14) and len(law.phase_times) == 2
    ph = kinema.time_law("trapezoid", 1.0, vmax=v, amax=a).phase_times
    assert np.allclose(ph, [v / a, 1.0 / v - v / a, v / a], rtol=1e-14)
    # Cubic: max(1.5 D/v, sqrt(6 D/a)); linear: D/v.
    assert np.isclose(kinema.time_law("cubic", 1.0, vmax=v, amax=a).duration, max(1.5 / v, np.sqrt(6 / a)))
    assert np.isclose(kinema.time_law("linear", 2.0, vmax=v).duration, 2.0 / v)
    # Quintic: s = 10τ³ − 15τ⁴ + 6τ⁵.
    law = kinema.time_law("quintic", duration=2.0)
    tau = np.linspace(0, 1, 11)
    p, *_ = law.sample(2.0 * tau)
    assert np.allclose(p, 10 * tau**3 - 15 * tau**4 + 6 * tau**5, atol=1e-14)


@pytest.mark.parametrize("profile", ["trapezoid", "scurve", "cubic", "quintic", "linear"])
def test_law_from_duration(profile):
    law = kinema.time_law(profile, 0.5, duration=3.0)
    assert np.isclose(law.duration, 3.0)
    p, v, _, _ = law.sample([0.0, 1.5, 3.0, 4.0, -1.0])
    assert p[0] == 0.0 and np.isclose(p[2], 0.5) and p[3] == 0.5 and p[4] == 0.0
    assert np.isclose(p[1], 0.25)  # every family is symmetric about T/2
    assert v[3] == 0.0 and v[4] == 0.0
    if profile in ("trapezoid", "scurve"):
        assert np.allclose(law.phase_times[:1], [1.0 if profile == "trapezoid" else 1.0 / 3.0])


def test_sample_shapes_and_times():
    law = kinema.time_law("trapezoid", vmax=1.0, amax=1.0)
    p, v, a, j = law.sample(0.5)
    assert p.shape == () and np.isclose(p, 0.125) and np.isclose(v, 0.5) and np.isclose(a, 1.0)
    grid = np.linspace(0, law.duration, 12).reshape(3, 4)
    assert all(x.shape == (3, 4) for x in law.sample(grid))
    assert law.sample([1, 2])[0].dtype == np.float64  # integers are converted
    t = law.times(0.3)
    assert t[0] == 0.0 and t[-1] == law.duration and np.all(np.diff(t) <= 0.3 + 1e-12) and np.all(np.diff(t) > 0)
    assert "TimeLaw(profile='trapezoid'" in repr(law)
    zero = kinema.time_law("scurve", 0.0, **LIMITS)
    assert zero.duration == 0.0 and zero.peaks == (0.0, 0.0, 0.0)


def test_ptp_uses_the_same_law():
    # PTP with one limit for every joint runs the law of its longest joint move, shared by all joints.
    r = kinema.Robot.builtin("lbr-iiwa-14-r820")
    qf = np.array([1.0, -0.5, 0.3, -1.5, 0.2, 0.9, -0.4])
    dq = qf - r.home
    for profile in ["trapezoid", "scurve", "quintic"]:
        tr = r.ptp("home", qf, 0.01, profile=profile, vmax=0.5, amax=1.0, jmax=10.0)
        dmax = np.abs(dq).max()
        law = kinema.time_law(profile, dmax, vmax=0.5, amax=1.0, jmax=10.0)
        assert np.isclose(tr.duration, law.duration, rtol=1e-12)
        assert np.allclose(tr.phase_times, law.phase_times, rtol=1e-12)
        p, v, _, _ = law.sample(tr.t)
        assert np.allclose(tr.q, r.home + np.outer(p / dmax, dq), atol=1e-12)
        assert np.allclose(tr.qd, np.outer(v / dmax, dq), atol=1e-12)


def test_law_errors():
    with pytest.raises(kinema.InvalidInput, match="unknown profile `bogus`"):
        kinema.time_law("bogus", vmax=1.0, amax=1.0)
    with pytest.raises(kinema.InvalidInput, match="not both"):
        kinema.time_law("trapezoid", duration=1.0, vmax=1.0)
    with pytest.raises(kinema.InvalidInput, match="give either `duration` or the limits"):
        kinema.time_law("trapezoid")
    with pytest.raises(kinema.InvalidInput, match="needs an acceleration limit"):
        kinema.time_law("cubic", vmax=1.0)
    with pytest.raises(kinema.InvalidInput, match="jmax"):
        kinema.time_law("scurve", vmax=1.0, amax=1.0)
    with pytest.raises(ValueError, match="distance"):
        kinema.time_law("trapezoid", -1.0, vmax=1.0, amax=1.0)
    with pytest.raises(ValueError, match="distance"):
        kinema.time_law("trapezoid", float("nan"), duration=1.0)
    with pytest.raises(kinema.InvalidInput, match="vmax"):
        kinema.time_law("trapezoid", vmax=0.0, amax=1.0)
    with pytest.raises(kinema.InvalidInput, match="duration"):
        kinema.time_law("quintic", duration=-2.0)
    law = kinema.time_law("trapezoid", vmax=1.0, amax=1.0)
    with pytest.raises(kinema.InvalidInput, match="NaN"):
        law.sample([0.0, float("nan")])
    with pytest.raises(kinema.InvalidInput):
        law.sample("0.5")
    with pytest.raises(kinema.InvalidInput, match="dt"):
        law.times(0.0)
