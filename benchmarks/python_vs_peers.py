#!/usr/bin/env python3
"""kinema (Python package) against roboticstoolbox-python and Pinocchio, in one process.

    python benchmarks/python_vs_peers.py [--n 100000] [--batch-n 1000000] [--ik-n 1000] [--seed 0] [--quick]

Run it inside a venv where `kinema` is installed (built from crates/kinema-py) and,
optionally, `roboticstoolbox-python`, `pin` and `kinema_bare_call` (the native call
floor, built from benchmarks/bare_call); one that cannot be imported is skipped with
a printed line. `benchmarks/run_peers.sh` makes such a venv and runs this.
The script installs nothing.

What is measured, on `lbr-iiwa-14-r820` and `panda`, with the same seeded random
configurations (uniform within kinema's `robot.qlim`) for every library:

* per-call fkine and jacob0: ns per call of `for q in w: f(q)` in the fastest
  window w of --window calls (default 1000), the --n calls cut into windows and
  passed over --repeats times, gc off, every row timed in turn in each window
  (interleaved); next to the same for the builtin `len(q)`:
  the "bare Python call". The ratio printed is t(f) / t(len), both loop included.
  `np.ndarray.copy(q)` is timed the same way as the floor of any call that returns
  a new numpy array. kinema is also timed writing into a preallocated array,
  `for q in w: f(q, out=T)` (row "kinema `out=`").
* the native call floor (if `kinema_bare_call` is importable): `Bare(n).noop(q)`,
  `.array44(q)` and `.array6n(q)` (also with `out=`) go through kinema's call path
  (PyO3 method, q read and the result array made as crates/kinema-py/src/npio.rs does)
  with no kinematics. kinema is reported against the floor with the same result,
  t(kinema) / t(floor), and "kinematics only" = t(kinema) - t(floor).
* batch fkine of --batch-n configurations: kinema's `fkine_batch(Q)` against a
  per-call list comprehension `[f(q) for q in Q]`; the toolbox loop is timed on
  --loop-sample configurations and extrapolated (printed as such).
* numeric IK on targets T = kinema.fkine(q) of random within-limit q: every
  library's returned q is checked alike with kinema's fkine (position <= 1e-6 m,
  orientation <= 1e-6 rad) and kinema's joint limits; mean wall time per solve.

Before timing, FK and jacob0 of every peer model are compared with kinema's on a
few configurations and the max difference is printed.
"""

from __future__ import annotations

import argparse
import datetime
import gc
import math
import os
import platform
import sys
import time
from pathlib import Path

import numpy as np

try:
    import kinema
except ImportError as exc:  # the one hard requirement
    sys.exit(f"kinema is not importable ({exc}); build it from crates/kinema-py first (see benchmarks/README.md)")

try:
    import tomllib as _toml
except ImportError:  # Python < 3.11
    try:
        import tomli as _toml  # type: ignore[no-redef]
    except ImportError:
        _toml = None

ROBOTS = ["lbr-iiwa-14-r820", "panda"]
TOL = 1e-6  # m and rad, IK success threshold (the same as kinema's IkSolution.success)
REPO = Path(__file__).resolve().parents[1]


# --------------------------------------------------------------------------- small math helpers


def rot_x(a):
    c, s = math.cos(a), math.sin(a)
    return np.array([[1, 0, 0, 0], [0, c, -s, 0], [0, s, c, 0], [0, 0, 0, 1.0]])


def rot_z(a):
    c, s = math.cos(a), math.sin(a)
    return np.array([[c, -s, 0, 0], [s, c, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1.0]])


def trans(x, y, z):
    T = np.eye(4)
    T[:3, 3] = (x, y, z)
    return T


def xyz_rpy_to_T(xyz, rpy):
    """translation, then R = Rz(yaw) Ry(pitch) Rx(roll) (kinema's and URDF's convention)."""
    r, p, y = rpy
    cr, sr, cp, sp, cy, sy = math.cos(r), math.sin(r), math.cos(p), math.sin(p), math.cos(y), math.sin(y)
    T = np.eye(4)
    T[:3, :3] = [
        [cy * cp, cy * sp * sr - sy * cr, cy * sp * cr + sy * sr],
        [sy * cp, sy * sp * sr + cy * cr, sy * sp * cr - cy * sr],
        [-sp, cp * sr, cp * cr],
    ]
    T[:3, 3] = xyz
    return T


def T_to_xyz_rpy(T):
    R = T[:3, :3]
    pitch = math.atan2(-R[2, 0], math.hypot(R[2, 1], R[2, 2]))
    if abs(math.cos(pitch)) < 1e-9:
        raise ValueError("gimbal lock in a fixed DH transform; not supported by this URDF writer")
    return T[:3, 3].copy(), (math.atan2(R[2, 1], R[2, 2]), pitch, math.atan2(R[1, 0], R[0, 0]))


def pose_error(T, T_target):
    """(position error [m], rotation angle of R_target R^T [rad])."""
    dp = float(np.linalg.norm(T_target[:3, 3] - T[:3, 3]))
    Rd = T_target[:3, :3] @ T[:3, :3].T
    s = 0.5 * math.sqrt((Rd[2, 1] - Rd[1, 2]) ** 2 + (Rd[0, 2] - Rd[2, 0]) ** 2 + (Rd[1, 0] - Rd[0, 1]) ** 2)
    c = 0.5 * (Rd[0, 0] + Rd[1, 1] + Rd[2, 2] - 1.0)
    return dp, math.atan2(s, c)


# --------------------------------------------------------------------------- the robots' DH tables


class DHChain:
    """The DH chain of a kinema robot file (robots/NAME.toml), in m and rad."""

    def __init__(self, path: Path):
        if _toml is None:
            raise RuntimeError("reading robot files needs Python >= 3.11 (tomllib) or the `tomli` package")
        with open(path, "rb") as f:
            doc = _toml.load(f)
        self.name = doc["name"]
        self.convention = doc.get("convention", "standard")
        if self.convention not in ("standard", "modified"):
            raise RuntimeError(f"{path.name}: convention {self.convention!r} is not handled by this script")
        units = doc.get("units", {})
        ls = {"m": 1.0, "mm": 1e-3}[units.get("length", "m")]
        as_ = {"rad": 1.0, "deg": math.pi / 180}[units.get("angle", "rad")]
        self.joints = []
        for j in doc["joint"]:
            if j.get("type", "revolute") != "revolute":
                raise RuntimeError(f"{path.name}: only revolute joints are handled by this script")
            self.joints.append(
                dict(
                    name=j["name"],
                    d=j.get("d", 0) * ls,
                    a=j.get("a", 0) * ls,
                    alpha=j.get("alpha", 0) * as_,
                    offset=j.get("offset", 0) * as_,
                    qlim=(j["min"] * as_, j["max"] * as_),
                )
            )

        def frame(key):
            t = doc.get(key)
            if not t:
                return np.eye(4)
            return xyz_rpy_to_T([v * ls for v in t.get("xyz", [0, 0, 0])], [v * as_ for v in t.get("rpy", [0, 0, 0])])

        self.base = frame("base")
        self.tool = frame("tool")

    def fixed_transforms(self):
        """URDF joint origins: origins[i] places joint i's frame (rotation about its z) in the previous
        link; the last entry places the tool in the last link."""
        origins, pending = [], self.base
        for j in self.joints:
            if self.convention == "standard":  # Rz(q + off) Tz(d) Tx(a) Rx(alpha)
                origins.append(pending)
                pending = rot_z(j["offset"]) @ trans(0, 0, j["d"]) @ trans(j["a"], 0, 0) @ rot_x(j["alpha"])
            else:  # modified: Rx(alpha) Tx(a) Rz(q + off) Tz(d) = Rx Tx Rz(off) Tz(d) Rz(q)
                origins.append(
                    pending @ rot_x(j["alpha"]) @ trans(j["a"], 0, 0) @ rot_z(j["offset"]) @ trans(0, 0, j["d"])
                )
                pending = np.eye(4)
        origins.append(pending @ self.tool)
        return origins

    def urdf(self) -> str:
        """URDF text of the same kinematic chain; the tool frame is the link `tool`."""

        def origin(T):
            xyz, rpy = T_to_xyz_rpy(T)
            f = lambda v: " ".join(repr(float(x)) for x in v)  # noqa: E731
            return f'<origin xyz="{f(xyz)}" rpy="{f(rpy)}"/>'

        origins = self.fixed_transforms()
        out = [f'<robot name="{self.name}">', '  <link name="base"/>']
        parent = "base"
        for i, (j, T) in enumerate(zip(self.joints, origins)):
            lo, hi = j["qlim"]
            out += [
                f'  <link name="link{i + 1}"/>',
                f'  <joint name="{j["name"]}" type="revolute">',
                f'    <parent link="{parent}"/><child link="link{i + 1}"/>',
                f"    {origin(T)}",
                '    <axis xyz="0 0 1"/>',
                f'    <limit lower="{lo!r}" upper="{hi!r}" effort="1" velocity="1"/>',
                "  </joint>",
            ]
            parent = f"link{i + 1}"
        out += [
            '  <link name="tool"/>',
            '  <joint name="tool_joint" type="fixed">',
            f'    <parent link="{parent}"/><child link="tool"/>',
            f"    {origin(origins[-1])}",
            "  </joint>",
            "</robot>",
        ]
        return "\n".join(out) + "\n"


# --------------------------------------------------------------------------- peers


class Peer:
    """A library's model of one robot: fkine(q), jacob0(q) (6×n, base frame, [v; ω]),
    to_matrix(result of fkine) -> 4×4, optional ik(T, i) -> (q or None, self-reported success)."""

    name = "?"
    note = ""
    ik = None
    ik_note = ""
    qlim = None


def kinema_peer(robot):
    p = Peer()
    p.name = "kinema"
    p.fkine = robot.fkine
    p.jacob0 = robot.jacob0
    p.to_matrix = lambda T: T

    def ik(T, i):
        try:
            s = robot.ik(T, solver="numeric", seed=i)
        except kinema.Unreachable:
            return None, False
        return s.q, s.success

    p.ik = ik
    p.ik_note = 'robot.ik(T, solver="numeric", seed=i)'
    return p


def rtb_peers(rtb, name, chain):
    """The toolbox's DHRobot (its own model where it has one) and the same robot as an ETS `Robot`
    (the toolbox's compiled fkine/jacob0/ik_LM path)."""
    from spatialmath import SE3

    if name == "panda":
        dh = rtb.models.DH.Panda()
        src = "rtb.models.DH.Panda()"
    else:
        cls = rtb.RevoluteDH if chain.convention == "standard" else rtb.RevoluteMDH
        links = [
            cls(d=j["d"], a=j["a"], alpha=j["alpha"], offset=j["offset"], qlim=np.array(j["qlim"])) for j in chain.joints
        ]
        dh = rtb.DHRobot(links, name=name, base=SE3(chain.base, check=False), tool=SE3(chain.tool, check=False))
        src = f"rtb.DHRobot built from robots/{name}.toml (the toolbox has no iiwa 14)"
    ets = rtb.Robot(dh.ets())
    base_src = src.split(" ")[0]
    out = []
    for label, model, note in (("rtb DHRobot", dh, src), ("rtb ETS Robot", ets, f"rtb.Robot({base_src}.ets())")):
        p = Peer()
        p.name, p.note = label, note
        p.fkine = model.fkine  # returns an SE3
        p.jacob0 = model.jacob0
        p.to_matrix = lambda T: T.A
        out.append(p)

    # IK on the ETS robot: ik_LM's tol bounds E = 0.5 e^T e (e = [position error; angle-axis error]);
    # 1e-14 keeps both parts below 1.5e-7, under the 1e-6 check. Default ilimit/slimit (30 x 100).
    def ik(T, i):
        s = ets.ik_LM(T, tol=1e-14)
        return np.asarray(s.q, dtype=float), bool(s.success)

    out[1].ik = ik
    out[1].ik_note = "ets_robot.ik_LM(T, tol=1e-14): C++ Levenberg-Marquardt, random restarts, joint limits on"
    out[1].qlim = np.asarray(ets.qlim, dtype=float)

    # the toolbox's fastest per-call path: the ETS itself, compiled, raw ndarrays in and out
    raw = dh.ets()
    p = Peer()
    p.name = "rtb ETS.eval"
    p.note = f"{base_src}.ets(): fkine = ets.eval(q) (ndarray), jacob0 = ets.jacob0(q)"
    p.fkine, p.jacob0, p.to_matrix = raw.eval, raw.jacob0, (lambda T: T)
    out.append(p)
    return out


def pin_peer(pin, name, chain, rng):
    model = pin.buildModelFromXML(chain.urdf())
    data = model.createData()
    fid = model.getFrameId("tool")
    lwa = pin.ReferenceFrame.LOCAL_WORLD_ALIGNED
    fk_, upd, jac = pin.forwardKinematics, pin.updateFramePlacement, pin.computeFrameJacobian

    p = Peer()
    p.name = "pin"
    p.note = f"pinocchio.buildModelFromXML(URDF generated from robots/{name}.toml)"

    def fkine(q):
        fk_(model, data, q)
        return upd(model, data, fid)  # an SE3

    def jacob0(q):
        return jac(model, data, q, fid, lwa)

    p.fkine, p.jacob0 = fkine, jacob0
    p.to_matrix = lambda M: M.homogeneous

    lo, hi = model.lowerPositionLimit.copy(), model.upperPositionLimit.copy()
    log6, Jlog6, integrate, local = pin.log6, pin.Jlog6, pin.integrate, pin.ReferenceFrame.LOCAL

    def ik(T, i, it_max=100, restarts=10, eps=1e-9, damp=1e-10):
        # Pinocchio has no IK solver of its own: this is the damped-least-squares CLIK loop of its
        # documentation, on the tool frame, step 1, clamped to the limits, random restarts.
        oMdes = pin.SE3(T[:3, :3].copy(), T[:3, 3].copy())
        for _ in range(restarts):
            q = rng.uniform(lo, hi)
            for _ in range(it_max):
                fk_(model, data, q)
                iMd = upd(model, data, fid).actInv(oMdes)
                err = log6(iMd).vector
                if err @ err < eps * eps:
                    return q, True
                J = -Jlog6(iMd.inverse()) @ jac(model, data, q, fid, local)
                v = -J.T @ np.linalg.solve(J @ J.T + damp * np.eye(6), err)
                q = np.clip(integrate(model, q, v), lo, hi)
        return q, False

    p.qlim = np.vstack([lo, hi])
    p.ik = ik
    p.ik_note = "script's CLIK loop (Pinocchio FK/Jacobian/log6; no Pinocchio IK solver exists), <= 10 x 100 iterations"
    return p


# --------------------------------------------------------------------------- timing


def windows(qs, window):
    """`qs` cut into consecutive windows of `window` calls (a short remainder is dropped); all of
    `qs` as one window if it is not longer than `window`."""
    if window <= 0 or len(qs) <= window:
        return [qs]
    return [qs[i : i + window] for i in range(0, len(qs) - window + 1, window)]


class Timer:
    """One per-call row: `for q in w: f(q)` (`f(q, out=out)` if `out` is given; `for q in w: pass`
    if `f` is None) on the windows of the first `k` configurations, in `passes` passes."""

    def __init__(self, f, k, passes, out=None):
        self.f, self.k, self.passes, self.out = f, k, passes, out
        self.per = []  # ns per call of each timed window

    def run(self, w):
        f, out = self.f, self.out
        if f is None:
            t0 = time.perf_counter_ns()
            for q in w:
                pass
        elif out is None:
            t0 = time.perf_counter_ns()
            for q in w:
                f(q)
        else:
            t0 = time.perf_counter_ns()
            for q in w:
                f(q, out=out)
        self.per.append((time.perf_counter_ns() - t0) / len(w))

    @property
    def best(self):
        return min(self.per)

    @property
    def median(self):
        return float(np.median(self.per))


def time_interleaved(timers, qs, repeats, window):
    """Times every Timer in `timers` on the same windows of `window` configurations of `qs`,
    interleaved: each pass goes through the windows, and in each window every row is timed in
    turn (a row only on the windows of its first `k` configurations and in its first `passes`
    passes), gc off. A row's time is its fastest window (`Timer.best`): the cost of the call with
    the least of the other processes' load on this shared machine; interleaving exposes every row
    to the same phases of that load (see benchmarks/README.md, "What is compared")."""
    per_timer = [(t, windows(qs[: t.k], window)) for t in timers]
    gc_was = gc.isenabled()
    gc.disable()
    try:
        for rep in range(repeats):
            for i in range(max(len(ws) for _, ws in per_timer)):
                for t, ws in per_timer:
                    if rep < t.passes and i < len(ws):
                        t.run(ws[i])
    finally:
        if gc_was:
            gc.enable()


def time_listcomp(f, qs):
    gc.disable()
    try:
        t0 = time.perf_counter()
        out = [f(q) for q in qs]
        dt = time.perf_counter() - t0
    finally:
        gc.enable()
    del out
    return dt


def fmt_ns(x):
    return f"{x:,.0f}" if x >= 100 else f"{x:.1f}"


# --------------------------------------------------------------------------- main


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--n", type=int, default=100_000, help="calls per per-call timing run (default 100000)")
    ap.add_argument("--rtb-n", type=int, default=10_000, help="calls per per-call run for the toolbox (slow; default 10000)")
    ap.add_argument("--repeats", type=int, default=5, help="per-call timing passes over the configurations (default 5)")
    ap.add_argument("--window", type=int, default=1000,
                    help="calls per timed window; per call = the fastest window (default 1000)")
    ap.add_argument("--batch-n", type=int, default=1_000_000, help="configurations for batch fkine (default 1e6)")
    ap.add_argument("--loop-sample", type=int, default=20_000, help="toolbox loop sample, extrapolated (default 20000)")
    ap.add_argument("--ik-n", type=int, default=1000, help="IK targets per robot (default 1000)")
    ap.add_argument("--seed", type=int, default=0, help="numpy Generator seed (default 0)")
    ap.add_argument("--quick", action="store_true", help="small sizes for a smoke run")
    ap.add_argument("--robots-dir", type=Path, default=REPO / "robots", help="where NAME.toml files are (default repo robots/)")
    args = ap.parse_args()
    if args.quick:
        args.n, args.rtb_n, args.repeats = 5_000, 500, 2
        args.batch_n, args.loop_sample, args.ik_n = 20_000, 1_000, 10

    started = datetime.datetime.now().astimezone()
    load0 = os.getloadavg()
    print(f"# kinema vs peers — {started:%Y-%m-%d %H:%M %Z}")
    print(f"python {platform.python_version()}, numpy {np.__version__}, kinema {kinema.__version__}, "
          f"{os.cpu_count()} CPUs, load average at start {load0[0]:.2f} {load0[1]:.2f} {load0[2]:.2f}")
    print(f"args: n={args.n} rtb_n={args.rtb_n} repeats={args.repeats} window={args.window} batch_n={args.batch_n} "
          f"loop_sample={args.loop_sample} ik_n={args.ik_n} seed={args.seed}")

    try:
        import roboticstoolbox as rtb

        print(f"roboticstoolbox-python {rtb.__version__}")
    except Exception as exc:  # noqa: BLE001 - any import failure means: skip
        rtb = None
        print(f"SKIP roboticstoolbox-python: not importable ({type(exc).__name__}: {exc})")
    try:
        import pinocchio as pin

        print(f"pinocchio {pin.__version__}")
    except Exception as exc:  # noqa: BLE001
        pin = None
        print(f"SKIP pinocchio: not importable ({type(exc).__name__}: {exc})")

    try:
        # the native call floor: a PyO3 module with kinema's per-call path and no kinematics
        # (benchmarks/bare_call, built by run_peers.sh; not part of kinema)
        import kinema_bare_call

        print(f"kinema_bare_call {kinema_bare_call.__version__} (native call floor, benchmarks/bare_call)")
    except Exception as exc:  # noqa: BLE001
        kinema_bare_call = None
        print(f"SKIP kinema_bare_call (native call floor): not importable ({type(exc).__name__}: {exc}); "
              "build it from benchmarks/bare_call (see benchmarks/README.md)")

    rng = np.random.default_rng(args.seed)
    rows_call, rows_floor, rows_batch, rows_ik, notes, verdicts = [], [], [], [], [], []

    # the bare Python call: the same loop around the builtin len() on the same arrays
    for rname in ROBOTS:
        robot = kinema.Robot.builtin(rname)
        lo, hi = robot.qlim
        n = robot.n
        print(f"\n## {rname} ({n} joints)")

        peers = [kinema_peer(robot)]
        chain = None
        if rtb is not None or pin is not None:
            try:
                chain = DHChain(args.robots_dir / f"{rname}.toml")
            except Exception as exc:  # noqa: BLE001
                print(f"SKIP DH table of {rname}: {exc}")
        if rtb is not None and (chain is not None or rname == "panda"):
            try:
                peers += rtb_peers(rtb, rname, chain)
            except Exception as exc:  # noqa: BLE001
                print(f"SKIP roboticstoolbox model of {rname}: {type(exc).__name__}: {exc}")
        if pin is not None and chain is not None:
            try:
                peers.append(pin_peer(pin, rname, chain, np.random.default_rng(args.seed + 1)))
            except Exception as exc:  # noqa: BLE001
                print(f"SKIP pinocchio model of {rname}: {type(exc).__name__}: {exc}")
        for p in peers[1:]:
            print(f"model {p.name}: {p.note}")

        # --- the same chain? FK and jacob0 at home and a few random configurations
        Qv = np.vstack([robot.home, rng.uniform(lo, hi, size=(8, n))])
        good = [peers[0]]
        for p in peers[1:]:
            dT = max(float(np.abs(p.to_matrix(p.fkine(q.copy())) - robot.fkine(q)).max()) for q in Qv)
            dJ = max(float(np.abs(np.asarray(p.jacob0(q.copy())) - robot.jacob0(q)).max()) for q in Qv)
            ok = dT < 1e-9 and dJ < 1e-9
            print(f"check {p.name} vs kinema on {len(Qv)} configurations: max |ΔT| = {dT:.2e}, "
                  f"max |ΔJ| = {dJ:.2e} -> {'same chain' if ok else 'DIFFERENT: excluded from timing'}")
            notes.append(f"{rname}: {p.name} vs kinema max |ΔT| {dT:.1e}, max |ΔJ| {dJ:.1e}")
            if getattr(p, "qlim", None) is not None:
                dq = float(np.abs(p.qlim - robot.qlim).max())
                print(f"      {p.name} joint limits (used by its IK) vs kinema's: max difference {dq:.1e} rad")
            if ok:
                good.append(p)
        peers = good

        # --- per-call fkine / jacob0
        Qc = rng.uniform(lo, hi, size=(args.n, n))
        qs = [row.copy() for row in Qc]
        W = args.window
        # every per-call row, timed interleaved on the same windows (time_interleaved)
        tm = {"empty": Timer(None, args.n, args.repeats), "len": Timer(len, args.n, args.repeats),
              "copy": Timer(np.ndarray.copy, args.n, args.repeats)}
        # the native call floor: kinema's call path (frozen pyclass method, signature (q, out=None),
        # q read and the result array made as crates/kinema-py/src/npio.rs does) without the kinematics
        if kinema_bare_call is not None:
            b = kinema_bare_call.Bare(n)
            tm["noop"] = Timer(b.noop, args.n, args.repeats)
            tm["new44"] = Timer(b.array44, args.n, args.repeats)
            tm["new6n"] = Timer(b.array6n, args.n, args.repeats)
            tm["out44"] = Timer(b.array44, args.n, args.repeats, out=np.empty((4, 4)))
            tm["out6n"] = Timer(b.array6n, args.n, args.repeats, out=np.empty((6, n)))
        for p in peers:
            k = min(args.n, args.rtb_n) if p.name.startswith("rtb") else args.n
            reps = args.repeats if k == args.n else max(1, min(args.repeats, 2))
            tm[(p.name, "fkine")] = Timer(p.fkine, k, reps)
            tm[(p.name, "jacob0")] = Timer(p.jacob0, k, reps)
            if p.name == "kinema":
                tm[("kinema out=", "fkine")] = Timer(robot.fkine, args.n, args.repeats, out=np.empty((4, 4)))
                tm[("kinema out=", "jacob0")] = Timer(robot.jacob0, args.n, args.repeats, out=np.empty((6, n)))
        time_interleaved(list(tm.values()), qs, args.repeats, W)

        t_bare = tm["len"].best
        print(f"per call, ns per call of the fastest (median) window of {min(W, args.n)} calls; "
              f"{args.n} calls × {args.repeats} passes, all rows interleaved window by window:")
        print(f"  empty loop `for q in qs: pass`      {fmt_ns(tm['empty'].best)}")
        print(f"  bare call `len(q)` (builtin)         {fmt_ns(t_bare)} ({fmt_ns(tm['len'].median)})")
        rows_call.append((rname, "bare call `len(q)`", t_bare, None, args.n, None))
        # a reference floor for any call that returns a new numpy array: a C-level copy
        t_copy = tm["copy"].best
        print(f"  numpy `np.ndarray.copy(q)`           {fmt_ns(t_copy)} ({fmt_ns(tm['copy'].median)})"
              f"   = {t_copy / t_bare:.1f}× the bare call")
        rows_call.append((rname, "reference: `np.ndarray.copy(q)`", t_copy, None, args.n, None))
        floor = None
        if kinema_bare_call is not None:
            noop, n44, n6n, o44, o6n = (tm[x] for x in ("noop", "new44", "new6n", "out44", "out6n"))
            floor = {"new": (n44.best, n6n.best), "out": (o44.best, o6n.best)}
            print(f"  native no-op `Bare.noop(q)`          {fmt_ns(noop.best)} ({fmt_ns(noop.median)})"
                  f"   = {noop.best / t_bare:.1f}× the bare call")
            print(f"  native new 4×4 / 6×n `Bare.array44(q)` {fmt_ns(n44.best)} ({fmt_ns(n44.median)}) / "
                  f"`Bare.array6n(q)` {fmt_ns(n6n.best)} ({fmt_ns(n6n.median)})"
                  f"   = {n44.best / t_bare:.1f}× / {n6n.best / t_bare:.1f}× the bare call")
            print(f"  native `out=` 4×4 / 6×n              {fmt_ns(o44.best)} ({fmt_ns(o44.median)}) / "
                  f"{fmt_ns(o6n.best)} ({fmt_ns(o6n.median)})"
                  f"   = {o44.best / t_bare:.1f}× / {o6n.best / t_bare:.1f}× the bare call")
            rows_call.append((rname, "native no-op call `Bare.noop(q)`", noop.best, noop.best, args.n, None))
            rows_call.append((rname, "native call returning a new 4×4 / 6×n `Bare.array44(q)` / `Bare.array6n(q)`",
                              n44.best, n6n.best, args.n, None))
            rows_call.append((rname, "native call writing `out=` 4×4 / 6×n", o44.best, o6n.best, args.n, None))
        for p in peers:
            tf, tj = tm[(p.name, "fkine")], tm[(p.name, "jacob0")]
            f_best, j_best, k, reps = tf.best, tj.best, tf.k, tf.passes
            print(f"  {p.name:<14} fkine {fmt_ns(f_best)} ({fmt_ns(tf.median)})   jacob0 {fmt_ns(j_best)} "
                  f"({fmt_ns(tj.median)})   = {f_best / t_bare:.1f}× / {j_best / t_bare:.1f}× the bare call   "
                  f"[{k} calls × {reps}]")
            rows_call.append((rname, p.name, f_best, j_best, k, "new"))
            if p.name == "kinema":
                tfo, tjo = tm[("kinema out=", "fkine")], tm[("kinema out=", "jacob0")]
                fo_best, jo_best = tfo.best, tjo.best
                print(f"  {'kinema out=':<14} fkine {fmt_ns(fo_best)} ({fmt_ns(tfo.median)})   jacob0 "
                      f"{fmt_ns(jo_best)} ({fmt_ns(tjo.median)})   = {fo_best / t_bare:.1f}× / "
                      f"{jo_best / t_bare:.1f}× the bare call   "
                      f"[f(q, out=preallocated), {args.n} calls × {args.repeats}]")
                rows_call.append((rname, "kinema `out=`", fo_best, jo_best, args.n, "out"))
                for what, t in (("fkine", f_best), ("jacob0", j_best)):
                    r = t / t_bare
                    verdicts.append(f"{rname} per-call {what}: {fmt_ns(t)} ns = {r:.1f}× a bare `len(q)` call "
                                    f"({fmt_ns(t_bare)} ns); target ≤ 1.5× -> {'MET' if r <= 1.5 else 'MISSED'}")
                if floor is None:
                    verdicts.append(f"{rname} per-call fkine/jacob0 against the native call floor: not measured "
                                    "(kinema_bare_call not available)")
                for i, (what, shape, fname) in enumerate(
                    (("fkine", "4×4", "array44"), ("jacob0", "6×n", "array6n")) if floor is not None else ()
                ):
                    for kind, t, how in (("new", (f_best, j_best)[i], f"`{what}(q)`"),
                                         ("out", (fo_best, jo_best)[i], f"`{what}(q, out=…)`")):
                        t_floor = floor[kind][i]
                        r = t / t_floor
                        ref = f"`Bare.{fname}(q{', out=…' if kind == 'out' else ''})`"
                        rows_floor.append((rname, f"kinema {how}", ref, t_floor, t))
                        verdicts.append(
                            f"{rname} per-call {what}{' with `out=`' if kind == 'out' else ''} against the native "
                            f"call floor of the same result ({ref}, "
                            f"{'a new ' + shape if kind == 'new' else shape + ' into `out`'}, {fmt_ns(t_floor)} ns): "
                            f"{fmt_ns(t)} ns = {r:.2f}×; target ≤ 1.5× -> {'MET' if r <= 1.5 else 'MISSED'}; "
                            f"kinematics only {fmt_ns(t - t_floor)} ns")

        # --- batch fkine
        Qb = rng.uniform(lo, hi, size=(args.batch_n, n))
        kb = []
        for _ in range(3):
            t0 = time.perf_counter()
            Tb = robot.fkine_batch(Qb)
            kb.append(time.perf_counter() - t0)
        t_kb = min(kb)
        print(f"batch fkine of {args.batch_n} configurations (best of 3): kinema fkine_batch {t_kb:.3f} s "
              f"({t_kb / args.batch_n * 1e9:.0f} ns per configuration)")
        rows_batch.append((rname, "kinema `fkine_batch(Q)`", t_kb, False, args.batch_n))
        idx = rng.integers(0, args.batch_n, size=min(8, args.batch_n))
        dmax = max(float(np.abs(Tb[i] - robot.fkine(Qb[i])).max()) for i in idx)
        kbo = []  # into a preallocated array (Tb, already written once)
        for _ in range(3):
            t0 = time.perf_counter()
            robot.fkine_batch(Qb, out=Tb)
            kbo.append(time.perf_counter() - t0)
        print(f"  kinema fkine_batch(Q, out=T) (preallocated T, best of 3) {min(kbo):.3f} s "
              f"({min(kbo) / args.batch_n * 1e9:.0f} ns per configuration)")
        rows_batch.append((rname, "kinema `fkine_batch(Q, out=T)` (preallocated T)", min(kbo), False, args.batch_n))
        del Tb
        if dmax > 0:
            print(f"  note: fkine_batch differs from fkine by {dmax:.1e}")
        qb = [row.copy() for row in Qb]
        loops_rtb = []
        for p in peers:
            extrap = p.name.startswith("rtb") and args.loop_sample < args.batch_n
            k = args.loop_sample if extrap else args.batch_n
            t = time_listcomp(p.fkine, qb[:k]) * (args.batch_n / k)
            label = f"{p.name} `[fkine(q) for q in Q]`"
            print(f"  {label:<40} {t:9.3f} s{'  (extrapolated from ' + str(k) + ' calls)' if extrap else ''}"
                  f"   kinema batch is {t / t_kb:.1f}× faster")
            rows_batch.append((rname, label, t, extrap, k))
            if p.name.startswith("rtb"):
                loops_rtb.append((t, p.name, extrap))
        if loops_rtb:
            t, lib, extrap = min(loops_rtb)
            r = t / t_kb
            verdicts.append(f"{rname} batch fkine of {args.batch_n:,}: kinema fkine_batch {t_kb:.3f} s vs the toolbox's "
                            f"fastest per-call loop ({lib}) {t:.1f} s{' (extrapolated)' if extrap else ''} = {r:.0f}×; "
                            f"target ≥ 20× -> {'MET' if r >= 20 else 'MISSED'}")
        else:
            verdicts.append(f"{rname} batch fkine target: not measured (roboticstoolbox-python not available)")
        del qb, Qb

        # --- numeric IK on the same targets
        Qi = rng.uniform(lo, hi, size=(args.ik_n, n))
        targets = [robot.fkine(q) for q in Qi]
        for p in peers:
            if p.ik is None:
                continue
            np.random.seed(args.seed)  # in case a peer draws its restarts from numpy's global generator
            ok = selfok = 0
            times = []
            worst = (0.0, 0.0)
            for i, T in enumerate(targets):
                t0 = time.perf_counter()
                q, s = p.ik(T.copy(), i)
                times.append(time.perf_counter() - t0)
                selfok += bool(s)
                if q is None or not np.all(np.isfinite(q)):
                    continue
                q = np.asarray(q, dtype=float)
                ep, eo = pose_error(robot.fkine(q), T)
                inside = bool(np.all(q >= lo) and np.all(q <= hi))
                if ep <= TOL and eo <= TOL and inside:
                    ok += 1
                    worst = (max(worst[0], ep), max(worst[1], eo))
            mt = float(np.mean(times)) * 1e3
            print(f"  IK {p.name:<14} success {ok}/{len(targets)} ({100 * ok / len(targets):.1f} %, self-reported "
                  f"{selfok}), mean {mt:.3f} ms per solve, median {float(np.median(times)) * 1e3:.3f} ms; "
                  f"worst residual of successes {worst[0]:.1e} m / {worst[1]:.1e} rad   [{p.ik_note}]")
            rows_ik.append((rname, p.name, ok, len(targets), selfok, mt, float(np.median(times)) * 1e3))

    load1 = os.getloadavg()
    print(f"\nload average at end {load1[0]:.2f} {load1[1]:.2f} {load1[2]:.2f}; "
          f"wall time {(datetime.datetime.now().astimezone() - started).total_seconds():.0f} s")

    # --------------------------------------------------------------------------- Markdown
    print("\n---\n")
    print(f"Measured {started:%Y-%m-%d}, Python {platform.python_version()}, {os.cpu_count()} CPUs, "
          f"load average {load0[0]:.2f} at start / {load1[0]:.2f} at end, seed {args.seed}.\n")
    print(f"Per call: ns per call of `for q in w: f(q)` in the fastest window w of {args.window:,} calls "
          f"(all calls × {args.repeats} passes, cut into windows, every row timed in turn in each window; gc off); "
          "ratio \"÷ bare call\" = that time / the same for `len(q)`. `np.ndarray.copy(q)` (a C method returning "
          "a new array) is shown as the floor of any call that returns a fresh numpy array; \"kinema `out=`\" is "
          "`for q in w: f(q, out=T)` with T preallocated. The native rows are `kinema_bare_call.Bare(n)` "
          "(benchmarks/bare_call): kinema's call path (a method of a frozen PyO3 class, signature `(q, out=None)`, "
          "q read and the result array made as crates/kinema-py/src/npio.rs does) and no kinematics; "
          "\"÷ native floor\" = time / the native call with the same result (a new 4×4 / 6×n array, or writing "
          "into `out=` for the `out=` row).\n")
    print("| robot | library | fkine ns/call | jacob0 ns/call | fkine ÷ bare call | jacob0 ÷ bare call "
          "| fkine ÷ native floor | jacob0 ÷ native floor | calls |")
    print("|---|---|---:|---:|---:|---:|---:|---:|---:|")
    bare, native = {}, {}
    for rname, lib, f, j, k, kind in rows_call:
        bare.setdefault(rname, f)  # the first row of each robot is `len(q)`
        if lib.startswith("native call returning"):
            native[(rname, "new")] = (f, j)
        elif lib.startswith("native call writing"):
            native[(rname, "out")] = (f, j)
        fl = native.get((rname, kind)) if kind else None
        cells = [fmt_ns(f), fmt_ns(j) if j is not None else "", f"{f / bare[rname]:.1f}",
                 f"{j / bare[rname]:.1f}" if j is not None else "",
                 f"{f / fl[0]:.2f}" if fl else "", f"{j / fl[1]:.2f}" if fl and j is not None else "", f"{k:,}"]
        print(f"| {rname} | {lib} | {' | '.join(cells)} |")
    if rows_floor:
        print("\nkinema against the native call floor of the same result (issue 8's target read as \"within 1.5× "
              "of a native call's overhead\"); kinematics only = t(kinema) − t(native floor):\n")
        print("| robot | call | native floor (no kinematics) | floor ns/call | kinema ns/call | kinema ÷ floor "
              "| kinematics only ns/call |")
        print("|---|---|---|---:|---:|---:|---:|")
        for rname, call, ref, t_floor, t in rows_floor:
            print(f"| {rname} | {call} | {ref} | {fmt_ns(t_floor)} | {fmt_ns(t)} | {t / t_floor:.2f} "
                  f"| {fmt_ns(t - t_floor)} |")
    print(f"\nBatch fkine of {args.batch_n:,} configurations (loops keep the results in a list):\n")
    print("| robot | method | seconds | ns per configuration | kinema `fkine_batch` faster by |")
    print("|---|---|---:|---:|---:|")
    kb = {}
    for rname, lab, t, extrap, k in rows_batch:
        if lab == "kinema `fkine_batch(Q)`":
            kb[rname] = t
        ex = f" (extrapolated from {k:,})" if extrap else ""
        print(f"| {rname} | {lab}{ex} | {t:.3f} | {t / args.batch_n * 1e9:,.0f} | {t / kb[rname]:.1f}× |")
    if rows_ik:
        print(f"\nNumeric IK, {args.ik_n} targets per robot (FK of random within-limit configurations); success = "
              "kinema's fkine of the returned q within 1e-6 m and 1e-6 rad of the target and q within kinema's limits:\n")
        print("| robot | library | success | self-reported success | mean ms/solve | median ms/solve |")
        print("|---|---|---:|---:|---:|---:|")
        for rname, lib, ok, tot, selfok, mt, md in rows_ik:
            print(f"| {rname} | {lib} | {100 * ok / tot:.1f} % ({ok}/{tot}) | {selfok}/{tot} | {mt:.3f} | {md:.3f} |")
    print("\nTargets (issue 8):\n")
    for v in verdicts:
        print(f"- {v}")
    print("\nModel checks:\n")
    for s in notes:
        print(f"- {s}")


if __name__ == "__main__":
    main()
