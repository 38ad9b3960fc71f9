"""The per-call fast paths (joint vectors read without numpy conversion), `out=`
arguments, and batch results bit-identical to per-call results."""

import numpy as np
import pytest

import kinema
from conftest import ROBOTS, random_q

ALL = ROBOTS + ["panda", "ur5"]
PER_CALL = ("fkine", "jacob0", "jacobe")


def reference(r, name, q):
    """The result for q given as a C-contiguous float64 array."""
    return getattr(r, name)(np.ascontiguousarray(q, dtype=np.float64))


@pytest.mark.parametrize("name", ALL)
def test_joint_vector_forms_give_identical_results(robots, name):
    r = robots[name]
    rng = np.random.default_rng(30)
    for q in random_q(r, rng, 20):
        wide = np.zeros((r.n, 3))
        wide[:, 1] = q
        forms = [
            q.tolist(),
            tuple(q.tolist()),
            wide[:, 1],  # strided view
            q[::-1].copy()[::-1],  # negative stride
            q.astype(">f8"),  # big-endian: general path
            [np.float64(v) for v in q],  # float subclass items: general path
        ]
        for f in PER_CALL + ("manipulability",):
            ref = reference(r, f, q)
            for form in forms:
                assert np.array_equal(getattr(r, f)(form), ref), (f, type(form))
        q32 = q.astype(np.float32)  # other dtypes: general path, converted
        assert np.array_equal(r.fkine(q32), reference(r, "fkine", q32.astype(np.float64)))


def test_integer_and_mixed_lists(robots):
    r = robots["puma560"]
    ints = [0, 1, -1, 2, 0, 3]
    assert np.array_equal(r.fkine(ints), r.fkine(np.array(ints, dtype=float)))
    mixed = (0, 0.5, -1, 2.25, True, 3)  # bool: general path (numpy reads it as 1.0)
    assert np.array_equal(r.jacob0(mixed), r.jacob0(np.array([0, 0.5, -1, 2.25, 1, 3], dtype=float)))
    big = [2**60, 0, 0, 0, 0, 0]  # beyond 2**53: general path; beyond 1e9: refused on both paths
    for q in (big, np.asarray(big, dtype=np.float64)):
        with pytest.raises(kinema.InvalidInput, match=r"joint 1 .* within ±1e9$"):
            r.fkine(q)
    assert np.array_equal(r.fkine(np.arange(6)), r.fkine(np.arange(6, dtype=float)))


def test_fast_path_errors_keep_their_messages(robots):
    r = robots["puma560"]
    msg = "robot `puma560` has 6 joints, but 7 joint values were given"
    for q in ([0.0] * 7, (0.0,) * 7, np.zeros(7), np.zeros((7, 2))[:, 0]):
        for f in (r.fkine, r.jacob0, r.jacobe, r.manipulability, r.fkine_all):
            with pytest.raises(kinema.InvalidInput) as e:
                f(q)
            assert str(e.value) == msg
    for q in ([0.0, 0.0, float("nan"), 0.0, 0.0, 0.0], np.array([0, 0, np.nan, 0, 0, 0.0])[::-1]):
        with pytest.raises(kinema.InvalidInput, match=r"^joint \d \(`.+`\) of robot `puma560` is NaN"):
            r.jacob0(q)
    with pytest.raises(kinema.InvalidInput, match=r"`q` must have shape \(N,\)"):
        r.fkine(np.float64(1.0))
    with pytest.raises(kinema.InvalidInput, match=r"has 6 joints, but 0 joint values"):
        r.fkine([])


def test_more_joints_than_the_fast_path_holds(tmp_path):
    """A 40-joint arm: joint vectors take the general path; results still agree."""
    joints = "".join(f'\n[[joint]]\nname = "j{i}"\nd = 0.01\na = 0.02\nalpha = {(-1) ** i * 30}\nmin = -170\nmax = 170\n' for i in range(40))
    path = tmp_path / "snake.toml"
    home = ", ".join(["10"] * 40)
    path.write_text(
        f'name = "snake"\nsource = "test"\nconvention = "standard"\n[units]\nlength = "m"\nangle = "deg"\n'
        f"{joints}\n[poses]\nhome = [{home}]\n"
    )
    r = kinema.Robot.from_file(path)
    assert r.n == 40
    Q = np.random.default_rng(31).uniform(-1, 1, size=(5, 40))
    T, J = r.fkine_batch(Q), r.jacobe_batch(Q)
    for i, q in enumerate(Q):
        assert np.array_equal(r.fkine(q.tolist()), T[i])
        assert np.array_equal(r.jacobe(q), J[i])
        out = np.empty((6, 40))
        assert r.jacobe(q, out=out) is out and np.array_equal(out, J[i])


@pytest.mark.parametrize("name", ALL)
def test_out_per_call(robots, name):
    r = robots[name]
    shapes = {"fkine": (4, 4), "jacob0": (6, r.n), "jacobe": (6, r.n)}
    for q in random_q(r, np.random.default_rng(32), 10):
        for f, shape in shapes.items():
            out = np.full(shape, np.nan)
            res = getattr(r, f)(q, out=out)
            assert res is out
            assert np.array_equal(out, getattr(r, f)(q))
            assert getattr(r, f)(q, None).shape == shape  # out=None: a new array
            assert getattr(r, f)(q.tolist(), out) is out


def test_out_may_alias_q(robots):
    r = robots["lbr-iiwa-14-r820"]
    q = random_q(r, np.random.default_rng(33))
    out = np.zeros((4, 4))
    view = out.reshape(-1)[:7]
    view[:] = q
    assert r.fkine(view, out=out) is out
    assert np.array_equal(out, r.fkine(q))
    J = np.zeros((6, 7))
    J[0] = q
    r.jacob0(J[0], out=J)
    assert np.array_equal(J, r.jacob0(q))


def test_bad_out(robots):
    r = robots["puma560"]
    q = r.home
    cases = [
        ([[0.0] * 4] * 4, r"^`out` must be a numpy array of float64 of shape \(4, 4\), got list$"),
        (np.zeros((4, 4), dtype=np.float32), r"^`out` must have dtype float64, got float32$"),
        (np.zeros((4, 4), dtype=">f8"), r"^`out` must have dtype float64, got >f8$"),
        (np.zeros((4, 4), dtype=np.int64), r"^`out` must have dtype float64, got int64$"),
        (np.zeros((3, 4)), r"^`out` must have shape \(4, 4\), got shape \(3, 4\)$"),
        (np.zeros(16), r"^`out` must have shape \(4, 4\), got shape \(16,\)$"),
        (np.zeros((4, 4), order="F"), r"^`out` must be C-contiguous$"),
        (np.zeros((4, 8))[:, ::2], r"^`out` must be C-contiguous$"),
    ]
    ro = np.zeros((4, 4))
    ro.flags.writeable = False
    cases.append((ro, r"^`out` is read-only$"))
    raw = np.zeros(16 * 8 + 1, dtype=np.uint8)
    unaligned = raw[1:].view(np.float64).reshape(4, 4)
    assert not unaligned.flags.aligned
    cases.append((unaligned, r"^`out` must be aligned$"))
    for out, msg in cases:
        with pytest.raises(kinema.InvalidInput, match=msg) as e:
            r.fkine(q, out=out)
        assert isinstance(e.value, ValueError)
    with pytest.raises(kinema.InvalidInput, match=r"^`out` must have shape \(6, 6\), got shape \(4, 4\)$"):
        r.jacob0(q, out=np.zeros((4, 4)))
    with pytest.raises(kinema.InvalidInput, match=r"^`out` must have shape \(6, 6\), got shape \(6, 7\)$"):
        r.jacobe(q, out=np.zeros((6, 7)))
    # A bad q is reported as before, and out is left alone.
    out = np.full((4, 4), 7.0)
    with pytest.raises(kinema.InvalidInput, match=r"has 6 joints, but 2 joint values"):
        r.fkine([0.0, 0.0], out=out)
    assert np.all(out == 7.0)


@pytest.mark.parametrize("bad", [np.nan, np.inf, -np.inf])
@pytest.mark.parametrize("f", PER_CALL)
def test_non_finite_q_leaves_out_alone(robots, f, bad):
    """The core writes Jacobian rows straight into `out`; it must write nothing for a bad q."""
    r = robots["lbr-iiwa-14-r820"]
    q = np.array(r.home, dtype=float)
    q[3] = bad
    out = np.full((4, 4) if f == "fkine" else (6, 7), 7.0)
    with pytest.raises(kinema.InvalidInput, match=r"^joint 4 \(`A4`\) of robot `lbr-iiwa-14-r820` is (NaN|inf|-inf); joint values must be finite numbers within ±1e9$"):
        getattr(r, f)(q, out=out)
    assert np.all(out == 7.0)
    with pytest.raises(kinema.InvalidInput):
        getattr(r, f)(q)


@pytest.mark.parametrize("name", ALL)
def test_batches_bit_identical_to_per_call(robots, name):
    """Every row of thousands of random configurations; sizes around the parallel chunk (512)."""
    r = robots[name]
    rng = np.random.default_rng(34)
    for count in (1, 511, 512, 513, 12 * 512 + 17):
        Q = random_q(r, rng, count)
        T, J0, Je = r.fkine_batch(Q), r.jacob0_batch(Q), r.jacobe_batch(Q)
        assert T.shape == (count, 4, 4) and J0.shape == Je.shape == (count, 6, r.n)
        assert np.array_equal(T, np.stack([r.fkine(q) for q in Q]))
        assert np.array_equal(J0, np.stack([r.jacob0(q) for q in Q]))
        assert np.array_equal(Je, np.stack([r.jacobe(q) for q in Q]))
    # Wide joint ranges (out of limits too): still identical.
    Q = rng.uniform(-7, 7, size=(5000, r.n))
    assert np.array_equal(r.fkine_batch(Q), np.stack([r.fkine(q) for q in Q]))


@pytest.mark.parametrize("name", ["lbr-iiwa-14-r820", "puma560"])
def test_batch_out(robots, name):
    r = robots[name]
    Q = random_q(r, np.random.default_rng(35), 5000)
    for f, shape in (("fkine_batch", (5000, 4, 4)), ("jacob0_batch", (5000, 6, r.n)), ("jacobe_batch", (5000, 6, r.n))):
        out = np.full(shape, np.nan)
        assert getattr(r, f)(Q, out=out) is out
        assert np.array_equal(out, getattr(r, f)(Q))
        assert getattr(r, f)(Q.tolist(), out) is out  # converted Q, positional out
    with pytest.raises(kinema.InvalidInput, match=r"^`out` must have shape \(5000, 4, 4\), got shape \(4999, 4, 4\)$"):
        r.fkine_batch(Q, out=np.zeros((4999, 4, 4)))
    with pytest.raises(kinema.InvalidInput, match=r"^`out` must have shape \(5000, 6, \d\), got shape \(5000, 4, 4\)$"):
        r.jacob0_batch(Q, out=np.zeros((5000, 4, 4)))
    with pytest.raises(kinema.InvalidInput, match=r"^`out` must be C-contiguous$"):
        r.fkine_batch(Q, out=np.zeros((5000, 4, 4), order="F"))
    with pytest.raises(kinema.InvalidInput, match=r"^`out` must be a numpy array of float64 of shape \(5000, 4, 4\), got dict$"):
        r.fkine_batch(Q, out={})


def test_batch_out_sharing_memory_with_q(robots):
    r = robots["lbr-iiwa-14-r820"]
    count = 3000
    buf = np.zeros(count * 7 + count * 16)
    Q = buf[: count * 7].reshape(count, 7)
    Q[:] = random_q(r, np.random.default_rng(36), count)
    out = buf[count * 7 - 16 : count * 7 - 16 + count * 16].reshape(count, 4, 4)
    with pytest.raises(kinema.InvalidInput, match=r"^`out` must not share memory with `Q`$"):
        r.fkine_batch(Q, out=out)
    apart = buf[count * 7 :].reshape(count, 4, 4)
    assert r.fkine_batch(Q, out=apart) is apart
    assert np.array_equal(apart, r.fkine_batch(Q))


def test_batch_error_is_the_first_bad_row(robots):
    r = robots["panda"]
    Q = random_q(r, np.random.default_rng(37), 20000)
    Q[15000, 2] = np.inf
    Q[9000, 6] = np.nan
    Q[19999, 0] = np.nan
    for f in (r.fkine_batch, r.jacob0_batch, r.jacobe_batch):
        with pytest.raises(kinema.InvalidInput, match=r"^configuration 9000 of the batch \(counting from 0\): joint 7 "):
            f(Q)
    with pytest.raises(kinema.InvalidInput, match=r"^configuration 9000 of the batch"):
        r.fkine_batch(Q, out=np.zeros((20000, 4, 4)))


def test_reentrant_jacobian(robots):
    """A joint vector whose conversion calls back into kinema while the outer call is under way."""
    r = robots["ur5"]
    q = random_q(r, np.random.default_rng(38))

    class Calls:
        def __array__(self, dtype=None, copy=None):
            r.jacob0(r.home)  # re-enters while the outer call holds its buffer
            return np.array(q, dtype=dtype)

    assert np.array_equal(r.jacob0(Calls()), r.jacob0(q))
    assert np.array_equal(r.jacobe(Calls()), r.jacobe(q))
