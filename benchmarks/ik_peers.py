#!/usr/bin/env python3
"""kinema checked against Pinocchio, roboticstoolbox-python and IK-Geo, and its analytic IK timed
against IK-Geo's, in one process.

    python benchmarks/ik_peers.py [--n 200] [--ik-n 300] [--speed-n 1000] [--repeats 7] [--seed 0] [--quick]

Run it in a venv where `kinema` (crates/kinema-py), `pin` (Pinocchio), `roboticstoolbox-python`,
`ik-geo` and `example-robot-data` are installed; `benchmarks/run_ik_peers.sh` makes such a
throwaway venv and runs this. The script installs nothing. Pinocchio is required (it is the
oracle); a missing toolbox, IK-Geo or example-robot-data is skipped with a printed SKIP line.

1. FK and base-frame Jacobian of kinema against Pinocchio (and the toolbox where it has the
   model) on --n seeded random configurations within kinema's limits, for the built-in robots the
   peers also have (puma560, ur5, panda; Pinocchio reads a URDF written from the robot's TOML DH
   table, as benchmarks/python_vs_peers.py does) and for the serial arms of example-robot-data
   (the same URDF file read by both, the tip link named explicitly). Bound: 1e-12 per element.
2. IK: targets T = kinema fkine(q) of random within-limit q, the same T nudged (1 mm, 1 mrad) and
   T moved out of reach. Every solution kinema returns, from `ik(T)` and `ik(T, all=True)`, is
   checked with Pinocchio's FK (not kinema's): within 1e-6 m and 1e-6 rad of T, and `ik(T)`'s
   also within the limits. "wrong" = a returned solution that misses (must be 0); "refused" = a
   target from a within-limit q that `ik(T)` raised Unreachable on.
3. Speed: all-solutions analytic IK per call, kinema `ik(T, all=True, solver="analytic")` against
   IK-Geo `Robot.<family>(H, P).get_ik(R, t)` on the same targets (IK-Geo's H, P are read from
   kinema's model at q = 0 and checked with IK-Geo's own forward_kinematics); the median over
   --repeats passes of the mean per call over --speed-n targets, the rows interleaved pass by pass.
   Numeric IK against the toolbox's `ik_LM` on a few targets.

Exits 1 if any FK/Jacobian difference exceeds the bound or any wrong solution appears.
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
from collections import Counter
from pathlib import Path

import numpy as np

# the model helpers of the existing peer benchmark (same directory)
sys.path.insert(0, str(Path(__file__).resolve().parent))
from python_vs_peers import DHChain, pose_error  # noqa: E402

import kinema  # noqa: E402  (python_vs_peers has already exited with a message if it is missing)

try:
    import pinocchio as pin
except ImportError as exc:
    sys.exit(f"pinocchio is not importable ({exc}): it is this check's oracle; pip install pin")

FK_BOUND = 1e-12  # per element of T (m, unitless) and J (m/rad, unitless)
IK_TOL = 1e-6  # m and rad
REPO = Path(__file__).resolve().parents[1]

BUILTIN = ["puma560", "ur5", "panda"]
# example-robot-data's serial arms: (label, file under share/example-robot-data/robots, tip link)
ERD_ARMS = [
    ("erd ur3", "ur_description/urdf/ur3_robot.urdf", "tool0"),
    ("erd ur5", "ur_description/urdf/ur5_robot.urdf", "tool0"),
    ("erd ur5 (joint-limited)", "ur_description/urdf/ur5_joint_limited_robot.urdf", "tool0"),
    ("erd ur10", "ur_description/urdf/ur10_robot.urdf", "tool0"),
    ("erd panda", "panda_description/urdf/panda.urdf", "panda_hand_tcp"),
    ("erd kinova j2s6s200", "kinova_description/robots/kinova.urdf", "j2s6s200_end_effector"),
    ("erd xarm7", "xarm_description/urdf/xarm7.urdf", "link_eef"),
    ("erd z1", "z1_description/urdf/z1.urdf", "gripperStator"),
    ("erd so101", "so_arm_description/urdf/so101.urdf", "gripper_frame_link"),
    ("erd talos left arm", "talos_data/robots/talos_left_arm.urdf", "arm_left_7_link"),
]


# --------------------------------------------------------------------------- Pinocchio as the oracle


class PinArm:
    """A Pinocchio model with kinema's joints (by name) and a tip frame. Joints of the Pinocchio
    model that are not on kinema's chain (grippers) stay at their neutral value."""

    def __init__(self, model, tip, joint_names):
        self.model, self.data = model, model.createData()
        self.fid = model.getFrameId(tip, pin.FrameType.BODY)
        if self.fid >= len(model.frames):
            raise RuntimeError(f"Pinocchio has no frame {tip!r}")
        self.q0 = pin.neutral(model)
        self.map = []  # (idx_q, nq, idx_v) per kinema joint
        for name in joint_names:
            jid = model.getJointId(name)
            if jid >= model.njoints:
                raise RuntimeError(f"Pinocchio has no joint {name!r}")
            j = model.joints[jid]
            self.map.append((j.idx_q, j.nq, j.idx_v))

    def q(self, q):
        out = self.q0.copy()
        for v, (iq, nq, _) in zip(q, self.map):
            if nq == 1:
                out[iq] = v
            else:  # continuous joint: (cos, sin)
                out[iq], out[iq + 1] = math.cos(v), math.sin(v)
        return out

    def fkine(self, q):
        pin.framesForwardKinematics(self.model, self.data, self.q(q))
        return self.data.oMf[self.fid].homogeneous.copy()

    def jacob0(self, q):
        J = pin.computeFrameJacobian(self.model, self.data, self.q(q), self.fid, pin.LOCAL_WORLD_ALIGNED)
        return J[:, [iv for _, _, iv in self.map]]


# --------------------------------------------------------------------------- IK-Geo's H, P from kinema


def axes_at_zero(robot):
    """Per joint: unit axis h and a point on it, in the base frame at q = 0, from kinema's jacob0
    (column [v; w] of a revolute joint: v = w x (p_tool - point), so p_tool + w x v is on the axis)."""
    n = robot.n
    T0 = robot.fkine(np.zeros(n))
    J = robot.jacob0(np.zeros(n))
    p = T0[:3, 3]
    hs, pts = [], []
    for i in range(n):
        w, v = J[3:, i], J[:3, i]
        hs.append(w / np.linalg.norm(w))
        pts.append(p + np.cross(hs[-1], v))
    return T0, hs, pts


def line_intersection(a, h, b, k, eps=1e-9):
    """The point where lines (a, h) and (b, k) meet, or None (parallel or skew)."""
    c = np.cross(h, k)
    s = float(np.dot(c, c))
    if s < 1e-18:
        return None
    d = b - a
    t = float(np.dot(np.cross(d, k), c)) / s
    u = float(np.dot(np.cross(d, h), c)) / s
    x, y = a + t * h, b + u * k
    return x if np.linalg.norm(x - y) < eps else None


def geo_hp(robot):
    """IK-Geo's kinematics (H 6x3, P 7x3) of a 6R kinema robot and the tool rotation at q = 0.
    The point chosen on each axis is its intersection with the next axis, else with the previous
    one, else the foot of the perpendicular from the previous point: the zero offsets IK-Geo's
    families (intersecting, spherical wrist) assume come out exactly zero."""
    if robot.n != 6 or robot.joint_types != "RRRRRR":
        raise ValueError("IK-Geo takes 6R arms")
    T0, hs, pts = axes_at_zero(robot)
    o = []
    for i in range(6):
        x = line_intersection(pts[i], hs[i], pts[i + 1], hs[i + 1]) if i < 5 else None
        if x is None and i > 0:
            x = line_intersection(pts[i], hs[i], pts[i - 1], hs[i - 1])
        if x is None:
            prev = o[-1] if o else np.zeros(3)
            x = pts[i] + np.dot(prev - pts[i], hs[i]) * hs[i]
        o.append(x)
    P = [o[0]] + [o[i] - o[i - 1] for i in range(1, 6)] + [T0[:3, 3] - o[5]]
    P = np.array([[0.0 if abs(c) < 1e-12 else c for c in row] for row in P])
    return np.array(hs), P, T0[:3, :3].copy()


# where the toolbox's own model is not kinema's (found by this check; the strict comparison uses a
# DHRobot built from kinema's TOML instead)
RTB_MODEL_NOTES = {
    "puma560": "rtb models.DH.Puma560() has d1 = 0.67183 m (kinema, after Corke's mdl_puma560: 0.6718 m)",
    "ur5": "rtb models.DH.UR5() has d1 = 0.089459 m (kinema, UR's published CB3 DH: 0.089159 m)",
}

GEO_FAMILIES = ["spherical_two_intersecting", "spherical_two_parallel", "spherical", "three_parallel_two_intersecting",
                "three_parallel", "two_intersecting", "two_parallel", "gen_six_dof"]


# --------------------------------------------------------------------------- small helpers


def rot_axis_angle(axis, angle):
    axis = axis / np.linalg.norm(axis)
    K = np.array([[0, -axis[2], axis[1]], [axis[2], 0, -axis[0]], [-axis[1], axis[0], 0]])
    return np.eye(3) + math.sin(angle) * K + (1 - math.cos(angle)) * K @ K


def nudge(T, rng, dp=1e-3, da=1e-3):
    T = T.copy()
    T[:3, 3] += rng.normal(size=3) * dp / math.sqrt(3)
    T[:3, :3] = rot_axis_angle(rng.normal(size=3), da) @ T[:3, :3]
    return T


def wrap_dist(a, b):
    d = (np.asarray(a) - np.asarray(b) + math.pi) % (2 * math.pi) - math.pi
    return float(np.abs(d).max())


def fmt(x):
    return f"{x:.1e}" if x else "0"


def median_time_per_call(rows, targets, repeats):
    """rows: {label: f(T)}; each pass times every row over all targets in turn (interleaved),
    gc off. Returns {label: (median, min) of the per-pass mean seconds per call}."""
    per = {k: [] for k in rows}
    gc_was = gc.isenabled()
    gc.disable()
    try:
        for _ in range(repeats):
            for k, f in rows.items():
                t0 = time.perf_counter_ns()
                for T in targets:
                    f(T)
                per[k].append((time.perf_counter_ns() - t0) / len(targets) * 1e-9)
    finally:
        if gc_was:
            gc.enable()
    return {k: (float(np.median(v)), min(v)) for k, v in per.items()}


# --------------------------------------------------------------------------- the arms


class Arm:
    def __init__(self, label, robot, pinarm, source, rtb_models=()):
        self.label, self.robot, self.pin, self.source = label, robot, pinarm, source
        self.rtb_models = list(rtb_models)  # (label, model, strict)


def builtin_arms(args, rtb, notes):
    out = []
    for name in BUILTIN:
        robot = kinema.Robot.builtin(name)
        chain = DHChain(args.robots_dir / f"{name}.toml")
        model = pin.buildModelFromXML(chain.urdf())
        p = PinArm(model, "tool", robot.joint_names)
        rtbm = []
        if rtb is not None:
            from spatialmath import SE3

            own = {"puma560": "Puma560", "ur5": "UR5", "panda": "Panda"}[name]
            rtbm.append((f"rtb models.DH.{own}()", getattr(rtb.models.DH, own)(), False))
            cls = rtb.RevoluteDH if chain.convention == "standard" else rtb.RevoluteMDH
            links = [cls(d=j["d"], a=j["a"], alpha=j["alpha"], offset=j["offset"], qlim=np.array(j["qlim"]))
                     for j in chain.joints]
            dh = rtb.DHRobot(links, name=name, base=SE3(chain.base, check=False), tool=SE3(chain.tool, check=False))
            rtbm.append((f"rtb DHRobot from robots/{name}.toml", dh, True))
        out.append(Arm(name, robot, p, f"built-in `{name}`; Pinocchio: URDF written from robots/{name}.toml", rtbm))
    return out


def erd_arms(args, notes):
    try:
        from importlib.metadata import distribution

        dist = distribution("example-robot-data")
        root = Path(dist.locate_file("cmeel.prefix/share/example-robot-data/robots"))
        if not root.is_dir():
            raise FileNotFoundError(root)
        print(f"example-robot-data {dist.version}: {root}")
    except Exception as exc:  # noqa: BLE001
        print(f"SKIP example-robot-data: not found ({type(exc).__name__}: {exc})")
        notes.append("example-robot-data not installed: its URDFs were not checked")
        return []
    out = []
    for label, rel, tip in ERD_ARMS:
        path = root / rel
        try:
            robot = kinema.Robot.from_file(str(path), tip=tip)
            model = pin.buildModelFromUrdf(str(path))
            p = PinArm(model, tip, robot.joint_names)
        except Exception as exc:  # noqa: BLE001
            print(f"SKIP {label} ({rel}): {type(exc).__name__}: {exc}")
            notes.append(f"{label}: not checked ({type(exc).__name__}: {exc})")
            continue
        out.append(Arm(label, robot, p, f"{rel}, tip `{tip}`"))
    return out


# --------------------------------------------------------------------------- main


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--n", type=int, default=200, help="random configurations for FK/Jacobian per robot (default 200)")
    ap.add_argument("--ik-n", type=int, default=300, help="IK targets of each kind per robot (default 300)")
    ap.add_argument("--speed-n", type=int, default=1000, help="targets per timing pass (default 1000)")
    ap.add_argument("--repeats", type=int, default=7, help="timing passes, median reported (default 7)")
    ap.add_argument("--lm-n", type=int, default=100, help="targets for the numeric IK comparison (default 100)")
    ap.add_argument("--seed", type=int, default=0, help="numpy Generator seed (default 0)")
    ap.add_argument("--quick", action="store_true", help="small sizes for a smoke run")
    ap.add_argument("--robots-dir", type=Path, default=REPO / "robots")
    args = ap.parse_args()
    if args.quick:
        args.n, args.ik_n, args.speed_n, args.repeats, args.lm_n = 20, 20, 100, 3, 10

    started = datetime.datetime.now().astimezone()
    load0 = os.getloadavg()
    print(f"# kinema vs Pinocchio / toolbox / IK-Geo — {started:%Y-%m-%d %H:%M %Z}")
    print(f"python {platform.python_version()}, numpy {np.__version__}, kinema {kinema.__version__}, "
          f"pinocchio {pin.__version__}, {os.cpu_count()} CPUs, load average {load0[0]:.2f}")
    print(f"args: n={args.n} ik_n={args.ik_n} speed_n={args.speed_n} repeats={args.repeats} lm_n={args.lm_n} "
          f"seed={args.seed}")
    try:
        import roboticstoolbox as rtb

        print(f"roboticstoolbox-python {rtb.__version__}")
    except Exception as exc:  # noqa: BLE001
        rtb = None
        print(f"SKIP roboticstoolbox-python ({type(exc).__name__}: {exc})")
    try:
        import ik_geo
        from importlib.metadata import version

        print(f"ik-geo {version('ik-geo')}")
    except Exception as exc:  # noqa: BLE001
        ik_geo = None
        print(f"SKIP ik-geo ({type(exc).__name__}: {exc})")

    notes, failures = [], []
    arms = builtin_arms(args, rtb, notes) + erd_arms(args, notes)
    rng = np.random.default_rng(args.seed)

    # ---------------------------------------------------------------- 1. FK and Jacobian
    rows_fk = []
    print("\n## FK and base-frame Jacobian")
    for arm in arms:
        robot = arm.robot
        lo, hi = robot.qlim
        lo, hi = np.maximum(lo, -2 * math.pi), np.minimum(hi, 2 * math.pi)  # continuous joints: one turn each way
        arm.lo, arm.hi = lo, hi
        Q = np.vstack([robot.home, rng.uniform(lo, hi, size=(args.n, robot.n))])
        reach = 0.0
        dT = dJ = 0.0
        for q in Q:
            T = robot.fkine(q)
            reach = max(reach, float(np.linalg.norm(T[:3, 3])))
            dT = max(dT, float(np.abs(arm.pin.fkine(q) - T).max()))
            dJ = max(dJ, float(np.abs(arm.pin.jacob0(q) - robot.jacob0(q)).max()))
        arm.reach = reach
        ok = dT <= FK_BOUND and dJ <= FK_BOUND
        print(f"{arm.label:<26} n={robot.n} Pinocchio: max|ΔT| {fmt(dT)} max|ΔJ| {fmt(dJ)} {'ok' if ok else 'OVER 1e-12'}"
              f"   [{arm.source}]")
        rows_fk.append((arm.label, robot.n, f"Pinocchio {pin.__version__}", dT, dJ, len(Q), ok, ""))
        if not ok:
            failures.append(f"{arm.label}: kinema vs Pinocchio FK {dT:.1e} / Jacobian {dJ:.1e} > {FK_BOUND}")
        for label, model, strict in arm.rtb_models:
            tT = tJ = 0.0
            for q in Q:
                tT = max(tT, float(np.abs(model.fkine(q).A - robot.fkine(q)).max()))
                tJ = max(tJ, float(np.abs(np.asarray(model.jacob0(q)) - robot.jacob0(q)).max()))
            ok = tT <= FK_BOUND and tJ <= FK_BOUND
            why = ""
            if not ok and not strict:
                why = RTB_MODEL_NOTES.get(arm.label, "the toolbox's own parameters differ")
            print(f"{'':<26} {label}: max|ΔT| {fmt(tT)} max|ΔJ| {fmt(tJ)} "
                  f"{'ok' if ok else ('OVER 1e-12' if strict else 'differs: ' + why)}")
            rows_fk.append((arm.label, robot.n, label, tT, tJ, len(Q), ok, why))
            if strict and not ok:
                failures.append(f"{arm.label}: kinema vs {label} FK {tT:.1e} / Jacobian {tJ:.1e} > {FK_BOUND}")

    # ---------------------------------------------------------------- 2. IK, checked with Pinocchio
    print("\n## IK: every returned solution checked with Pinocchio's FK")
    rows_ik, wrong_cases = [], []
    for arm in arms:
        robot, P = arm.robot, arm.pin
        lo, hi = robot.qlim
        Qs = rng.uniform(arm.lo, arm.hi, size=(args.ik_n, robot.n))
        kinds = [("reachable", [robot.fkine(q) for q in Qs], Qs)]
        kinds.append(("nudged 1 mm / 1 mrad", [nudge(robot.fkine(q), rng) for q in Qs], None))
        far = []
        for q in Qs[: max(1, args.ik_n // 3)]:
            T = robot.fkine(q)
            p = T[:3, 3]
            T[:3, 3] = p / max(float(np.linalg.norm(p)), 1e-9) * 3.0 * arm.reach
            far.append(T)
        kinds.append(("out of reach (3× reach)", far, None))
        for kind, targets, qsrc in kinds:
            c = Counter()
            solvers = Counter()
            worst = 0.0
            for i, T in enumerate(targets):
                # one solution, the default solver choice
                try:
                    s = robot.ik(T, seed=i)
                    sols1 = [s]
                except kinema.Unreachable:
                    sols1 = []
                    c["refused"] += 1
                try:
                    sols_all = robot.ik(T, all=True, seed=i)
                except kinema.Unreachable:
                    sols_all = []
                    c["all: refused"] += 1
                for where, sols in (("ik", sols1), ("all", sols_all)):
                    for s in sols:
                        solvers[f"{s.solver}{' (all)' if where == 'all' else ''}"] += 1
                        q = np.asarray(s.q, dtype=float)
                        ep, eo = pose_error(P.fkine(q), T)
                        inside = bool(np.all(q >= lo - 1e-12) and np.all(q <= hi + 1e-12))
                        c[f"{where}: solutions"] += 1
                        hit = ep <= IK_TOL and eo <= IK_TOL
                        if hit:
                            worst = max(worst, ep, eo)
                        bad = not hit or (where == "ik" and not inside)
                        if inside != s.within_limits:
                            c["within_limits flag disagrees"] += 1
                        if bad:
                            c[f"{where}: wrong"] += 1
                            if len(wrong_cases) < 20:
                                wrong_cases.append(
                                    f"{arm.label} [{kind}] ik({'all=True' if where == 'all' else ''}) solver {s.solver} "
                                    f"branch {s.branch}: q = {np.array2string(q, precision=17, separator=', ')}; "
                                    f"Pinocchio FK misses T by {ep:.2e} m / {eo:.2e} rad (kinema says {s.position_error:.2e} / "
                                    f"{s.orientation_error:.2e}, success {s.success}), within limits {inside}; target T = "
                                    f"{np.array2string(T, precision=17, separator=', ')}")
                if qsrc is not None and sols_all:
                    found = any(wrap_dist(s.q, qsrc[i]) < 1e-6 for s in sols_all)
                    c["all: has the generating q"] += found
            wrong = c["ik: wrong"] + c["all: wrong"]
            tag = "ok" if wrong == 0 else f"{wrong} WRONG"
            print(f"{arm.label:<26} {kind:<24} targets {len(targets)}: ik() refused {c['refused']}, "
                  f"all=True refused {c['all: refused']}, solutions ik {c['ik: solutions']} / all {c['all: solutions']}, "
                  f"wrong {c['ik: wrong']} / {c['all: wrong']}, worst hit {fmt(worst)}; solvers {dict(solvers)} -> {tag}")
            if c["within_limits flag disagrees"]:
                print(f"    within_limits flag disagrees with the limits on {c['within_limits flag disagrees']} solutions")
            rows_ik.append((arm.label, kind, len(targets), c, solvers, worst, qsrc is not None))
            if wrong:
                failures.append(f"{arm.label} [{kind}]: {wrong} wrong IK solutions")
    for w in wrong_cases:
        print("WRONG: " + w)

    # ---------------------------------------------------------------- 3. speed: analytic IK vs IK-Geo
    rows_speed, rows_lm, geo_notes, geo_exact = [], [], [], {}
    speed_arms = [a for a in arms if a.label in ("ur5", "puma560", "erd ur5", "erd ur10", "erd kinova j2s6s200")]
    if ik_geo is not None:
        print("\n## Speed: all-solutions analytic IK per call, kinema vs IK-Geo")
        for arm in speed_arms:
            robot = arm.robot
            try:
                H, Pm, R0 = geo_hp(robot)
            except ValueError as exc:
                print(f"SKIP {arm.label}: {exc}")
                continue
            Qs = rng.uniform(arm.lo, arm.hi, size=(args.speed_n, robot.n))
            targets = [robot.fkine(q) for q in Qs]
            # ik_geo's bindings read and return 3x3 matrices column by column (its forward_kinematics
            # returns R transposed at q != 0): it is given R^T, and its FK's R is read back transposed
            geo_in = [(np.ascontiguousarray((T[:3, :3] @ R0.T).T), np.ascontiguousarray(T[:3, 3])) for T in targets]
            # which IK-Geo families accept this arm and return the target (checked with Pinocchio)
            fams = []
            for fam in GEO_FAMILIES:
                try:
                    g = getattr(ik_geo.Robot, fam)(H, Pm)
                    Rg, tg = g.forward_kinematics(list(Qs[0]))
                    dfk = max(float(np.abs(np.array(Rg).T @ R0 - targets[0][:3, :3]).max()),
                              float(np.abs(np.array(tg) - targets[0][:3, 3]).max()))
                    nsol = nexact = nhave = 0
                    kcheck = min(50, len(targets))
                    for i in range(kcheck):
                        sols = g.get_ik(*geo_in[i])
                        nsol += len(sols)
                        have = False
                        for q, ls in sols:
                            ep, eo = pose_error(arm.pin.fkine(np.asarray(q)), targets[i])
                            if ep <= IK_TOL and eo <= IK_TOL:
                                nexact += 1
                            have |= wrap_dist(q, Qs[i]) < 1e-6
                        nhave += have
                except BaseException as exc:  # noqa: BLE001 - the extension panics on unsupported geometry
                    if isinstance(exc, KeyboardInterrupt):
                        raise
                    geo_notes.append(f"{arm.label}: IK-Geo `{fam}` not usable ({type(exc).__name__}: {str(exc)[:80]})")
                    continue
                usable = dfk < 1e-9 and nhave == kcheck
                msg = (f"{arm.label}: IK-Geo `{fam}`: FK vs kinema {dfk:.1e}; on {kcheck} targets {nsol} solutions, "
                       f"{nexact} within 1e-6 (Pinocchio), generating q found {nhave}/{kcheck} -> "
                       f"{'timed' if usable else 'not timed'}")
                print("  " + msg)
                geo_notes.append(msg)
                if usable:
                    fams.append((fam, g))
                    geo_exact[(arm.label, fam)] = nexact / kcheck
            if not fams:
                continue
            rows = {}
            rows["kinema ik(T, all=True, solver='analytic')"] = lambda T: robot.ik(T, all=True, solver="analytic")
            rows["kinema ik(T) (one solution, auto)"] = lambda T: robot.ik(T)
            gi = {id(T): x for T, x in zip(targets, geo_in)}
            for fam, g in fams:
                rows[f"IK-Geo {fam} get_ik(R, t)"] = (lambda g: lambda T: g.get_ik(*gi[id(T)]))(g)
            ksol = sum(len(robot.ik(T, all=True, solver="analytic")) for T in targets[:200])
            ksolver = Counter(s.solver for T in targets[:50] for s in robot.ik(T, all=True, solver="analytic"))
            gsol = {fam: sum(len(g.get_ik(*x)) for x in geo_in[:200]) for fam, g in fams}
            res = median_time_per_call(rows, targets, args.repeats)
            t_k = res["kinema ik(T, all=True, solver='analytic')"][0]
            for k, (med, best) in res.items():
                sols = ksol if k.startswith("kinema ik(T, all") else (
                    min(200, len(targets)) if k.startswith("kinema ik(T)") else gsol[k.split()[1]])
                print(f"  {arm.label:<10} {k:<52} median {med * 1e6:8.2f} µs  (fastest pass {best * 1e6:.2f})  "
                      f"solutions/call {sols / min(200, len(targets)):.2f}")
                fam = k.split()[1] if k.startswith("IK-Geo") else None
                rows_speed.append((arm.label, k, med, best, sols / min(200, len(targets)),
                                   geo_exact.get((arm.label, fam)),
                                   dict(ksolver) if k.startswith("kinema ik(T, all") else None))
            for fam, _ in fams:
                t_g = res[f"IK-Geo {fam} get_ik(R, t)"][0]
                r = t_k / t_g
                print(f"  {arm.label}: kinema all-solutions ÷ IK-Geo {fam} = {r:.2f}; target ≤ 0.5 -> "
                      f"{'MET' if r <= 0.5 else 'MISSED'}")

    # numeric IK against the toolbox's ik_LM, on the built-ins it has
    if rtb is not None:
        print("\n## Numeric IK: kinema solver='numeric' vs the toolbox's ik_LM (checked with Pinocchio)")
        for arm in arms:
            strict = [m for (_, m, s) in arm.rtb_models if s]
            if not strict:
                continue
            robot = arm.robot
            ets = rtb.Robot(strict[0].ets())
            lo, hi = robot.qlim
            Qs = rng.uniform(arm.lo, arm.hi, size=(args.lm_n, robot.n))
            targets = [robot.fkine(q) for q in Qs]
            np.random.seed(args.seed)
            for label, f in (("kinema ik(T, solver='numeric', seed=i)", lambda T, i: robot.ik(T, solver="numeric", seed=i).q),
                             ("rtb ik_LM(T, tol=1e-14)", lambda T, i: np.asarray(ets.ik_LM(T, tol=1e-14).q, float))):
                ok = 0
                times = []
                for i, T in enumerate(targets):
                    t0 = time.perf_counter()
                    try:
                        q = f(T, i)
                    except kinema.Unreachable:
                        q = None
                    times.append(time.perf_counter() - t0)
                    if q is None:
                        continue
                    ep, eo = pose_error(arm.pin.fkine(q), T)
                    ok += ep <= IK_TOL and eo <= IK_TOL and bool(np.all(q >= lo) and np.all(q <= hi))
                print(f"  {arm.label:<8} {label:<40} success {ok}/{len(targets)}  median {np.median(times) * 1e6:8.1f} µs"
                      f"  mean {np.mean(times) * 1e6:8.1f} µs")
                rows_lm.append((arm.label, label, ok, len(targets), float(np.median(times)), float(np.mean(times))))

    load1 = os.getloadavg()
    wall = (datetime.datetime.now().astimezone() - started).total_seconds()
    print(f"\nload average at end {load1[0]:.2f}; wall time {wall:.0f} s")

    # ---------------------------------------------------------------- Markdown
    print("\n---\n")
    print(f"Measured {started:%Y-%m-%d %H:%M %Z}, Python {platform.python_version()}, kinema {kinema.__version__}, "
          f"Pinocchio {pin.__version__}, {os.cpu_count()} CPUs, load average {load0[0]:.2f} at start / "
          f"{load1[0]:.2f} at end, seed {args.seed}.\n")
    print(f"FK and base-frame Jacobian, max |difference| per element over `home` and {args.n} random configurations "
          f"within kinema's limits (bound {FK_BOUND:.0e}):\n")
    print("| robot | n | against | max ΔT | max ΔJ | within 1e-12 |")
    print("|---|---:|---|---:|---:|---|")
    for label, n, peer, dT, dJ, k, ok, why in rows_fk:
        print(f"| {label} | {n} | {peer} | {fmt(dT)} | {fmt(dJ)} | {'yes' if ok else 'no' + (' — ' + why if why else '')} |")
    print(f"\nIK, {args.ik_n} targets of each kind per robot (out of reach: {max(1, args.ik_n // 3)}); every solution "
          "of `ik(T)` and `ik(T, all=True)` checked with Pinocchio's FK (1e-6 m, 1e-6 rad; `ik(T)`'s also within the "
          "limits):\n")
    print("| robot | targets | n | `ik(T)` refused | `ik(T)` wrong | `all=True` solutions | `all=True` wrong "
          "| generating q among `all=True` | solvers (`ik(T)`; `all=True`) |")
    print("|---|---|---:|---:|---:|---:|---:|---:|---|")
    for label, kind, n, c, solvers, worst, gen in rows_ik:
        s1 = ", ".join(f"{k} {v}" for k, v in solvers.items() if not k.endswith("(all)"))
        s2 = ", ".join(f"{k[:-6]} {v}" for k, v in solvers.items() if k.endswith("(all)"))
        g = f"{c['all: has the generating q']}/{n}" if gen else ""
        print(f"| {label} | {kind} | {n} | {c['refused']} | {c['ik: wrong']} | {c['all: solutions']} "
              f"| {c['all: wrong']} | {g} | {s1}; {s2} |")
    if rows_speed:
        print(f"\nAll-solutions analytic IK per call, µs: median over {args.repeats} passes of the mean over "
              f"{args.speed_n} targets (FK of random within-limit q), rows interleaved pass by pass; the same process "
              "and targets for every row:\n")
        print("| robot | call | µs per call (median) | fastest pass | solutions per call | kinema all-solutions ÷ this |")
        print("|---|---|---:|---:|---:|---:|")
        base = {}
        for label, k, med, best, sols, exact, _ in rows_speed:
            if k.startswith("kinema ik(T, all"):
                base[label] = med
            ex = f" ({exact:.2f} within 1e-6)" if exact is not None else ""
            print(f"| {label} | `{k}` | {med * 1e6:.2f} | {best * 1e6:.2f} | {sols:.2f}{ex} | {base[label] / med:.2f} |")
        print()
        for label, k, med, best, sols, exact, ks in rows_speed:
            if ks:
                print(f"- {label}: kinema's analytic solver(s) on these targets: {ks}")
            if k.startswith("IK-Geo"):
                r = base[label] / med
                print(f"- {label}: kinema all-solutions {base[label] * 1e6:.2f} µs ÷ {k.split()[0]} {k.split()[1]} "
                      f"{med * 1e6:.2f} µs = {r:.2f}; target ≤ 0.5 -> {'MET' if r <= 0.5 else 'MISSED'}")
    if rows_lm:
        print(f"\nNumeric IK, {args.lm_n} targets per robot (success checked with Pinocchio, within kinema's limits):\n")
        print("| robot | call | success | median µs | mean µs |")
        print("|---|---|---:|---:|---:|")
        for label, k, ok, n, med, mean in rows_lm:
            print(f"| {label} | `{k}` | {ok}/{n} | {med * 1e6:.1f} | {mean * 1e6:.1f} |")
    if geo_notes:
        print("\nIK-Geo families tried:\n")
        for s in geo_notes:
            print(f"- {s}")
    for s in notes:
        print(f"- {s}")
    print()
    if failures:
        print("FAILED:")
        for f in failures:
            print(f"- {f}")
        sys.exit(1)
    print("PASSED: every FK/Jacobian difference within 1e-12 and no wrong IK solution")


if __name__ == "__main__":
    main()
