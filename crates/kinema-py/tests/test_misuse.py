"""Seeded random misuse of the whole Python API.

Every call, whatever it is given, either returns or raises one of the exceptions the
package documents: a ``kinema.KinemaError`` (bad input also a ``ValueError``), or the
``TypeError``/``OverflowError`` with which Python refuses an argument of the wrong type or
range. Never pyo3's ``PanicException`` (a ``BaseException``: ``except Exception`` does not
catch it, so a panic in the core would escape a user's error handling), never a crash.

Arguments are drawn per parameter: mostly a valid value, otherwise one from a pool of
malformed ones (wrong length or shape, NaN, ±inf, huge or subnormal numbers, wrong dtypes,
strided, Fortran-ordered and read-only arrays, wrong types). So most calls have one or two
bad arguments among good ones and reach the checks deep inside, not only the first one.
Robot files of the catalogue with a few characters changed go to ``Robot.from_file``.
Results that come back are checked too: arrays of the documented shape and dtype;
trajectories, plans and IK solutions finite, with increasing times.
"""

import math

import numpy as np
import pytest

import kinema
from cli import ROOT

DESCRIPTIONS = sorted((ROOT / "robots").glob("*.toml")) + [ROOT / "crates" / "kinema" / "tests" / "data" / "iiwa14.urdf"]

ALLOWED = (kinema.KinemaError, ValueError, TypeError, OverflowError)
ROBOTS = ["lbr-iiwa-14-r820", "puma560", "scorbot-er-v-plus", "rommel", "scara5", "panda"]
CALLS_PER_ROBOT = 2000

NASTY_SCALARS = [
    0.0, -0.0, -1.0, 1e-300, -1e-300, 5e-324, 1e300, -1e300,
    math.inf, -math.inf, math.nan, 10**30, -(10**30), True, None, "x", "", [], {},
    complex(1.0, 1.0), np.complex128(1.0), np.float32(1.5), np.int64(-3), np.array(2.0), np.array([1.0, 2.0]),
]


class Draw:
    """Seeded choices of valid and malformed arguments for one robot."""

    def __init__(self, robot, rng, tmp):
        self.r, self.rng, self.n, self.tmp = robot, rng, robot.n, tmp
        lo, hi = robot.qlim
        self.lo = np.where(np.isfinite(lo), lo, -np.pi)
        self.hi = np.where(np.isfinite(hi), hi, np.pi)

    def bad(self):
        return self.rng.random() < 0.3

    def pick(self, items):
        return items[self.rng.integers(len(items))]

    def q_good(self):
        return self.rng.uniform(self.lo, self.hi)

    def q(self):
        if not self.bad():
            return self.pick([self.q_good(), list(self.q_good()), tuple(self.q_good()), "home"])
        n, q = self.n, self.q_good()
        k = self.rng.integers(n)
        poisoned = q.copy()
        poisoned[k] = self.pick([math.nan, math.inf, -math.inf, 1e300, -1e300, 5e-324, 1e16])
        wide = np.zeros(2 * n)
        wide[::2] = q
        ro = q.copy()
        ro.flags.writeable = False
        return self.pick([
            poisoned, q[:-1], np.append(q, 0.0), np.zeros(0), q.reshape(1, n), q.reshape(n, 1),
            q.astype(np.float32), q.astype(np.int64), q > 0, q.astype(object), q.astype(complex),
            wide[::2], ro, np.asfortranarray(q.reshape(1, n)), [str(v) for v in q], [q, q],
            [[v] for v in q], list(q[:-1]) + [None], "nope", "", None, 1.0, {}, self.pick(NASTY_SCALARS),
        ])

    def scalar(self, good):
        return good if not self.bad() else self.pick(NASTY_SCALARS)

    def path_options(self, kw):
        """lin/circ's resampling and manipulability options, now and then (a tiny max_step
        must be refused at once, not bisected for minutes)."""
        for name, good in (("max_step", 0.01), ("max_angle", 0.05), ("min_manip", 1e-4)):
            if self.rng.random() < 0.2:
                kw[name] = self.scalar(good)

    def Q(self):
        N = int(self.rng.integers(1, 40))
        Q = self.rng.uniform(self.lo, self.hi, size=(N, self.n))
        if not self.bad():
            return Q
        P = Q.copy()
        P[self.rng.integers(N), self.rng.integers(self.n)] = self.pick([math.nan, math.inf, 1e300])
        return self.pick([
            P, Q[:, :-1], np.zeros((0, self.n)), np.zeros((N, 0)), Q[0], Q.reshape(N, self.n, 1),
            Q.astype(np.float32), np.asfortranarray(Q), Q[::2], Q.T, Q.tolist(), "Q", None, 3.0,
        ])

    def out(self, shape):
        if self.rng.random() < 0.5:
            return None
        good = np.empty(shape)
        if not self.bad():
            return good
        ro = np.empty(shape)
        ro.flags.writeable = False
        wrong = list(shape)
        wrong[-1] += 1
        return self.pick([
            np.empty(tuple(wrong)), np.empty(shape, dtype=np.float32), np.empty(shape, dtype=np.int64),
            ro, np.asfortranarray(np.empty(shape)) if len(shape) > 1 and shape[0] > 1 else np.empty(wrong),
            np.empty(tuple(s * 2 for s in shape))[tuple(slice(None, None, 2) for _ in shape)],
            np.empty(shape[::-1]) if shape[0] != shape[-1] else np.empty(wrong), [[0.0] * 4] * 4, "out", 1.0,
        ])

    def pose(self):
        T = self.r.fkine(self.q_good())
        if not self.bad():
            return self.pick([T, list(T[:3, 3]) + [0.1, 0.2, 0.3]])
        S = T.copy()
        i, j = self.rng.integers(4), self.rng.integers(4)
        S[i, j] = self.pick([math.nan, math.inf, 1e300, S[i, j] + 0.5])
        return self.pick([
            S, T[:3], T[:3, :3], np.zeros((4, 4)), 2.0 * T, T.T, T[:3, 3], [1.0] * 5, [1.0] * 7,
            [math.nan] * 6, T.astype(np.float32), T.tolist(), "T", None, 5.0,
        ])

    def motion_start(self):
        """(q0, T, dt) of a Cartesian motion: valid, a few centimetres long, unless drawn bad."""
        qg = self.rng.uniform(0.8 * self.lo + 0.2 * self.hi, 0.2 * self.lo + 0.8 * self.hi)
        T = self.r.fkine(qg)
        T[:3, 3] += self.rng.uniform(-0.03, 0.03, 3)
        q0 = qg if not self.bad() else self.q()
        return q0, T if not self.bad() else self.pose(), self.dt()

    def arc_point(self, q0, T):
        """A point between the start and the end, off their line, unless drawn bad."""
        try:
            with np.errstate(all="ignore"):
                p0 = self.r.fkine(q0)[:3, 3]
                p1 = np.asarray(T, dtype=float)[:3, 3]
                side = np.cross(p1 - p0, self.rng.normal(size=3))
                mid = (p0 + p1) / 2 + 0.3 * np.linalg.norm(p1 - p0) * side / max(np.linalg.norm(side), 1e-12)
        except Exception:  # a bad q0 or T: any point
            return self.point()
        return mid if not self.bad() else self.point()

    def point(self):
        p = self.r.fkine(self.q_good())[:3, 3]
        if not self.bad():
            return p
        return self.pick([p[:2], np.append(p, 1.0), [math.nan, 0.0, 0.0], [1e300] * 3, "p", None, p.tolist()])

    def dt(self):
        return self.scalar(self.pick([0.01, 0.02, 0.05]))

    def limit(self, good):
        if not self.bad():
            return good
        return self.pick([0.0, -1.0, math.nan, math.inf, 1e-300, 1e300, "fast", [good] * 3, np.full(self.n + 1, good)])

    def profile(self):
        return self.pick(["trapezoid", "scurve", "cubic", "quintic", "linear"]) if not self.bad() else self.pick(
            ["", "TRAPEZOID", "bang", None, 3]
        )

    def description_file(self):
        """A robot file of the catalogue, often with a few characters changed, as a path."""
        source = self.pick(DESCRIPTIONS)
        text = source.read_text(encoding="utf-8")
        if self.bad() or self.rng.random() < 0.5:
            chars = list(text)
            for _ in range(int(self.rng.integers(1, 4))):
                k = int(self.rng.integers(len(chars)))
                chars[k] = self.pick(list("[]{}=\"'#,.-0123456789eEanif\n\x00\u00e9 ") + ["nan", "1e999", "inf"])
            text = "".join(chars)
        path = self.tmp / f"arm{self.rng.integers(1 << 30)}{source.suffix}"
        path.write_text(text, encoding="utf-8")
        return self.pick([path, str(path)]) if not self.bad() else self.pick(
            [path, self.tmp / "missing.toml", self.tmp, self.tmp / "arm.txt", "", None, 3]
        )

    def text(self):
        base = self.pick([
            "PTP HOME\nWAIT 0.1s\n",
            "JACC 90 deg/s^2\nPTP JOINT(" + ", ".join(["10deg"] * self.n) + ")\n",
            "HOME 1;\nLOOP 2\n  MOVEZ -50, 1;\n  MOVEXY 100, -50, 1;\n  MOVEZ +50, 1;\nEND\n",
            "LIN REL CART(0mm, 0mm, -10mm)\n",
        ])
        if not self.bad():
            return base
        chars = list(base)
        for _ in range(int(self.rng.integers(1, 6))):
            k = int(self.rng.integers(len(chars) + 1))
            op = self.rng.integers(3)
            if op == 0 and chars:
                del chars[min(k, len(chars) - 1)]
            elif op == 1:
                chars.insert(k, self.pick(list("()\n,;:-+*/^ 0123456789eE.degmsAZ\x00\u00e9\u2212\U0001f916\"'#")))
            else:
                chars.insert(k, self.pick(["1e999", "nan", "inf", "LOOP 1000000000", "END", "WAIT -1s", "9" * 40]))
        return self.pick(["".join(chars), b"PTP HOME", None, 3])


def calls(d):
    """(name, thunk, check) for one random call; check(result) asserts what came back."""
    r, n = d.r, d.n
    kind = d.rng.integers(17)
    if kind == 0:
        q, out = d.q(), d.out((4, 4))
        return "fkine", lambda: r.fkine(q, out=out) if out is not None else r.fkine(q), shape(4, 4)
    if kind == 1:
        q = d.q()
        return "fkine_all", lambda: r.fkine_all(q), shape(n + 2, 4, 4)
    if kind == 2:
        q, out, f = d.q(), d.out((6, n)), d.pick([r.jacob0, r.jacobe])
        return f.__name__, lambda: f(q, out=out) if out is not None else f(q), shape(6, n)
    if kind == 3:
        q, axes = d.q(), d.pick(["all", "trans", "rot"]) if not d.bad() else d.pick(["", "xyz", None, 1])
        return "manipulability", lambda: r.manipulability(q, axes=axes), finite_scalar
    if kind == 4:
        Q = d.Q()
        N = len(Q) if isinstance(Q, (np.ndarray, list)) and np.ndim(Q) == 2 else 1
        f = d.pick([r.fkine_batch, r.jacob0_batch, r.jacobe_batch])
        tail = (4, 4) if f == r.fkine_batch else (6, n)
        out = d.out((N,) + tail)
        return f.__name__, lambda: f(Q, out=out) if out is not None else f(Q), lambda a: shape(N, *tail)(a)
    if kind == 5:
        q0, qf, dt, prof = d.q(), d.q(), d.dt(), d.profile()
        kw = {"vmax": d.limit(1.0), "amax": d.limit(2.0)} if d.rng.random() < 0.5 else {}
        if prof == "scurve" or d.bad():
            kw["jmax"] = d.limit(20.0)
        if d.rng.random() < 0.2:
            kw["duration"] = d.scalar(1.5)
        if d.rng.random() < 0.2:
            kw["speed"] = d.scalar(0.5)
        return "ptp", lambda: r.ptp(q0, qf, dt, profile=prof, **kw), trajectory(n)
    if kind == 6:
        j = int(d.rng.integers(1, n + 1)) if not d.bad() else d.pick([0, n + 1, -1, "1", None])
        e = d.pick(["0.1*sin(2*pi*t)", "t^2/10", "0"]) if not d.bad() else d.pick(
            ["", "sin(", "t/0", "1e999", "nan", "x", "sqrt(-1)", "(" * 300 + "t" + ")" * 300, "\x00"]
        )
        dur, dt = d.scalar(1.0), d.dt()
        return "expr", lambda: r.expr({j: e}, duration=dur, dt=dt), trajectory(n)
    if kind == 7:
        q0, T, dt = d.motion_start()
        kw = dict(vmax=d.limit(0.3), amax=d.limit(1.0))
        if d.rng.random() < 0.3:
            kw["method"] = d.pick(["ik", "rate"]) if not d.bad() else d.pick(["", "jacobian", None])
        if d.rng.random() < 0.3:
            kw["orientation"] = d.pick(["slerp", "rpy"]) if not d.bad() else d.pick(["", "quat", 1])
        if d.rng.random() < 0.3:
            kw["via"] = [d.point()] if not d.bad() else d.pick([[], [[math.nan] * 3], "via", [[0.0] * 2]])
        if d.rng.random() < 0.3:
            kw["blend"] = d.pick(["decel", "none", 0.01]) if not d.bad() else d.pick([-1.0, math.nan, "x", math.inf])
        d.path_options(kw)
        return "lin", lambda: r.lin(q0, T, dt, **kw), trajectory(n)
    if kind == 8:
        q0, T, dt = d.motion_start()
        via = d.arc_point(q0, T)
        kw = dict(vmax=d.limit(0.3), amax=d.limit(1.0))
        d.path_options(kw)
        return "circ", lambda: r.circ(q0, via, T, dt, **kw), trajectory(n)
    if kind in (9, 10):
        T, kw = d.pose(), {}
        if d.rng.random() < 0.4:
            kw["all"] = d.pick([True, False]) if not d.bad() else d.pick([None, "yes", 2])
        if d.rng.random() < 0.4:
            kw["q0"] = d.q()
        if d.rng.random() < 0.4:
            kw["solver"] = d.pick(["auto", "analytic", "numeric"]) if not d.bad() else d.pick(["", "magic", None])
        if d.rng.random() < 0.2:
            kw[d.pick(["q3", "psi"])] = d.scalar(0.3)
        if d.rng.random() < 0.2:
            kw["seed"] = d.scalar(1) if d.bad() else int(d.rng.integers(100))
        if d.rng.random() < 0.25:
            T = None
            kw["position"] = d.point()
            extra = d.pick(["pitch", "roll", "approach", "alpha", None])
            if extra == "approach":
                kw["approach"] = d.pick([[0.0, 0.0, -1.0], [0.0, 0.0, 0.0], [math.nan] * 3, [1.0]])
            elif extra is not None:
                kw[extra] = d.scalar(0.2)
        return "ik", lambda: r.ik(T, **kw), ik_result(n)
    if kind == 11:
        t = np.linspace(0.0, 1.0, 50)
        q = d.rng.uniform(d.lo, d.hi) + 0.1 * np.sin(np.outer(t, np.arange(1, n + 1)))
        if d.bad():
            t, q = d.pick([
                (t[::-1], q), (t[:-1], q), (np.zeros(0), q[:0]), (t, q[:, :-1]), (np.full(50, math.nan), q),
                (t, np.where(q > 0, math.inf, q)), (t, q.T), ("t", q), (t, None), (np.zeros(50), q),
            ])
        kw = {"vmax": d.limit(1.0)} if d.rng.random() < 0.3 else {}
        if d.rng.random() < 0.3:
            kw["min_manip"] = d.scalar(1e-3)
        return "check", lambda: r.check(t, q, **kw), check_report
    if kind == 12:
        prof = d.profile()
        kw = dict(distance=d.scalar(0.5))
        if d.rng.random() < 0.7:
            kw.update(vmax=d.limit(1.0), amax=d.limit(2.0), jmax=d.limit(20.0))
        else:
            kw["duration"] = d.scalar(2.0)
        ts = d.pick([np.linspace(0, 1, 7), [0.1, 0.2], 0.5, np.array([[0.0, 0.1]])]) if not d.bad() else d.pick(
            [np.array([math.nan]), "t", None, np.array([math.inf, -math.inf]), np.zeros(0)]
        )

        def law():
            L = kinema.time_law(prof, **kw)
            p, v, a, j = L.sample(ts)
            assert p.shape == v.shape == a.shape == j.shape == np.shape(ts)
            L.times(d.dt())
            return L

        return "time_law", law, lambda L: math.isfinite(L.duration) or pytest.fail(f"duration {L.duration}")
    if kind == 13:
        text, dt = d.text(), d.dt()
        start = d.q() if d.rng.random() < 0.3 else None
        return "run_program", lambda: kinema.run_program(text, r, dt=dt, start=start), plan(n)
    if kind == 14:
        name = d.pick(["home", "qz", "qr", "ready"]) if not d.bad() else d.pick(["", "nope", None, 3, "home\x00"])
        return "pose", lambda: r.pose(name), shape(n)
    if kind == 15:
        path = d.description_file()
        return "from_file", lambda: kinema.Robot.from_file(path), lambda robot: isinstance(robot, kinema.Robot)
    name = d.pick(kinema.Robot.builtins()) if not d.bad() else d.pick(["", "r2d2", None, 3, "PUMA560", "puma560 "])
    return "builtin", lambda: kinema.Robot.builtin(name), lambda robot: isinstance(robot, kinema.Robot)


def shape(*s):
    def check(a):
        assert isinstance(a, np.ndarray) and a.shape == tuple(s) and a.dtype == np.float64, (type(a), getattr(a, "shape", None))
    return check


def finite_scalar(x):
    assert isinstance(x, float) and x >= 0.0 and math.isfinite(x), x


def trajectory(n):
    def check(tr):
        k = len(tr)
        assert k >= 1 and tr.t.shape == (k,) and tr.q.shape == tr.qd.shape == tr.qdd.shape == (k, n)
        assert np.all(np.isfinite(tr.t)) and np.all(np.isfinite(tr.q)) and np.all(np.diff(tr.t) > 0)
    return check


def ik_result(n):
    def check(res):
        for s in res if isinstance(res, list) else [res]:
            assert isinstance(s, kinema.IkSolution) and s.q.shape == (n,) and np.all(np.isfinite(s.q))
    return check


def check_report(rep):
    assert isinstance(rep, kinema.CheckReport) and isinstance(rep.ok, bool)


def plan(n):
    def check(p):
        assert isinstance(p, kinema.Plan) and p.q.shape == (len(p), n) and np.all(np.isfinite(p.q))
    return check


# A warning from numpy inside a call means a value was changed silently (a complex number's
# imaginary part dropped, say): an error here.
@pytest.mark.filterwarnings("error")
@pytest.mark.parametrize("name", ROBOTS)
def test_random_misuse_raises_documented_exceptions(name, tmp_path):
    robot = kinema.Robot.builtin(name)
    d = Draw(robot, np.random.default_rng(800 + ROBOTS.index(name)), tmp_path)
    returned, raised = 0, {}
    for i in range(CALLS_PER_ROBOT):
        what, thunk, check = calls(d)
        try:
            result = thunk()
        except ALLOWED as e:
            raised[type(e).__name__] = raised.get(type(e).__name__, 0) + 1
            assert str(e), f"call {i} ({what}): {type(e).__name__} with an empty message"
            continue
        except BaseException as e:  # a PanicException, or anything undocumented
            pytest.fail(f"call {i} ({what}) on {name} raised {type(e).__module__}.{type(e).__name__}: {e}")
        check(result)
        returned += 1
    # Both outcomes are exercised: the draws are neither all valid nor all refused.
    assert returned > CALLS_PER_ROBOT // 5 and sum(raised.values()) > CALLS_PER_ROBOT // 5, (returned, raised)
    # Bad values mostly reach the core's checks, not only Python's argument conversion.
    assert raised.get("InvalidInput", 0) > sum(raised.values()) // 3, raised
