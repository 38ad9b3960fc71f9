"""kinema.Cell: several robots on a common clock (seed 004 §VIII-E), against numpy and `kinema cell`."""

import csv
import subprocess

import numpy as np
import pytest

import kinema
from cli import ROOT, kinema_binary, needs_cli

CELLS = ROOT / "examples" / "cells"
IIWA = "lbr-iiwa-14-r820"
# The bases of examples/cells/seed004_two_iiwa.toml.
DRAWER_BASE = [1.2, 0.0, 0.0, 0.0, 0.0, np.pi]


def rz(a):
    c, s = np.cos(a), np.sin(a)
    return np.array([[c, -s, 0], [s, c, 0], [0, 0, 1.0]])


def seed_cell(min_distance=0.1):
    cell = kinema.Cell(dt=0.01, min_distance=min_distance)
    for name, base in [("holder", None), ("drawer", DRAWER_BASE)]:
        prg = CELLS / f"seed004_{name}.prg"
        cell.add(name, IIWA, program=prg.read_text(encoding="utf-8"), base=base, filename=prg.name)
    return cell


def test_seed_cell_tools_are_base_times_fk_and_distances_their_norm(robots):
    report = seed_cell().run()
    iiwa = robots[IIWA]
    assert report.names == ["holder", "drawer"] and isinstance(report, kinema.CellReport)
    k = len(report)
    assert report.t.shape == (k,) and report.t[0] == 0.0 and np.all(np.diff(report.t) <= 0.01 + 1e-12)
    for name, (rot, shift) in {"holder": (np.eye(3), np.zeros(3)), "drawer": (rz(np.pi), np.array([1.2, 0, 0]))}.items():
        q, p = report.q[name], report.tool_positions[name]
        assert q.shape == (k, 7) and p.shape == (k, 3) and report.manipulability[name].shape == (k,)
        want = np.array([rot @ iiwa.fkine(qk)[:3, 3] + shift for qk in q])
        assert np.abs(p - want).max() < 1e-12
        assert report.checks[name].ok and isinstance(report.checks[name], kinema.CheckReport)
    d = report.distances[("holder", "drawer")]
    assert np.abs(d - np.linalg.norm(report.tool_positions["holder"] - report.tool_positions["drawer"], axis=1)).max() < 1e-15
    t, dmin = report.closest[("holder", "drawer")]
    assert dmin == d.min() and t == report.t[np.argmin(d)]
    assert report.ok and dmin > 0.1 and report.closer_than_minimum[("holder", "drawer")] == []
    # The holder finishes first and holds its last configuration.
    end = report.ends["holder"]
    assert end < report.ends["drawer"] == report.duration == report.t[-1]
    held = report.q["holder"][report.t >= end]
    assert len(held) > 50 and np.all(held == held[0])


def test_a_minimum_distance_above_the_closest_approach_is_reported():
    report = seed_cell(min_distance=0.2).run()
    assert not report.ok and report.min_distance == 0.2
    spans = report.closer_than_minimum[("holder", "drawer")]
    d = report.distances[("holder", "drawer")]
    inside = np.array([any(a <= t <= b for a, b in spans) for t in report.t])
    assert spans and np.array_equal(inside, d < 0.2)


@needs_cli
def test_seed_cell_equals_kinema_cell(tmp_path):
    out = tmp_path / "cell.csv"
    r = subprocess.run(
        [str(kinema_binary()), "cell", str(CELLS / "seed004_two_iiwa.toml"), "--out", str(out)],
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert r.returncode == 0, r.stderr
    with out.open(newline="") as f:
        rows = list(csv.reader(f))
    head, data = rows[0], np.array(rows[1:], dtype=float)
    col = {name: i for i, name in enumerate(head)}
    report = seed_cell().run()
    assert data.shape[0] == len(report)
    assert np.abs(data[:, col["t"]] - report.t).max() < 1e-9
    for name in report.names:
        q = data[:, [col[f"{name}_q{j}"] for j in range(1, 8)]]
        assert np.abs(q - report.q[name]).max() < 1e-9
        xyz = data[:, [col[f"{name}_{c}"] for c in "xyz"]]
        assert np.abs(xyz - report.tool_positions[name]).max() < 1e-9
        assert np.abs(data[:, col[f"{name}_manipulability"]] - report.manipulability[name]).max() < 1e-9
    assert np.abs(data[:, col["d_holder_drawer"]] - report.distances[("holder", "drawer")]).max() < 1e-9


def test_trajectories_plans_and_arrays_of_different_lengths(robots):
    ur5, scorbot = robots["ur5"], robots["scorbot-er-v-plus"]
    fast = ur5.ptp("home", [0.5, -1.2, 1.0, -0.5, 1.2, 0.3], 0.01, amax=2.0)
    slow = scorbot.ptp("home", [0.4, 0.3, -0.4, -0.3, 0.5], 0.01, vmax=0.3, amax=1.0)
    assert fast.duration < slow.duration
    base = np.eye(4)
    base[:3, :3], base[:3, 3] = rz(0.5), [1.0, -0.2, 0.1]
    cell = kinema.Cell(dt=0.02).add("ur", ur5, fast).add("sc", "scorbot-er-v-plus", t=slow.t, q=slow.q, base=base)
    assert cell.names == ["ur", "sc"] and len(cell) == 2
    report = cell.run()
    assert report.ends == {"ur": pytest.approx(fast.duration), "sc": pytest.approx(slow.duration)}
    assert report.t[-1] == pytest.approx(slow.duration)
    # On the UR5's own samples (every second one of 10 ms), its q; after its end, its last q.
    for k, t in enumerate(report.t):
        j = min(int(round(t / 0.01)), len(fast) - 1)
        assert np.abs(report.q["ur"][k] - fast.q[j]).max() < 1e-9
    want = np.array([base[:3, :3] @ scorbot.fkine(q)[:3, 3] + base[:3, 3] for q in report.q["sc"]])
    assert np.abs(report.tool_positions["sc"] - want).max() < 1e-12
    # A Plan is a trajectory too.
    plan = kinema.run_program("JACC 90 deg/s^2\nPTP JOINT(0.3rad, -1rad, 1rad, 0, 0.5rad, 0)\n", ur5)
    report = kinema.Cell().add("a", ur5, plan).add("b", ur5, fast, base=[0, 1, 0, 0, 0, 0]).run()
    assert set(report.closest) == {("a", "b")} and report.ok


def test_a_trajectory_breaking_a_limit_is_in_its_check(robots):
    ur5 = robots["ur5"]
    tr = ur5.ptp("home", [0.5, -1.2, 1.0, -0.5, 1.2, 0.3], 0.01, amax=2.0)
    q = tr.q.copy()
    q[20, 0] += 0.5
    report = kinema.Cell().add("a", ur5, t=tr.t, q=q).add("b", ur5, tr, base=[2, 0, 0, 0, 0, 0]).run()
    assert not report.ok and not report.checks["a"].ok and report.checks["b"].ok
    assert report.checks["a"].violations[0]["joint"] == 1
    # The same as Robot.check on the same samples.
    assert report.checks["a"].violations == ur5.check(tr.t, q).violations


def test_bad_cells_raise_the_documented_exceptions(robots):
    ur5 = robots["ur5"]
    tr = ur5.ptp("home", [0.5, -1.2, 1.0, -0.5, 1.2, 0.3], 0.01, amax=2.0)
    with pytest.raises(kinema.InvalidInput, match="`cell` has 0 robots"):
        kinema.Cell().run()
    for kwargs in [{"dt": 0}, {"dt": float("nan")}, {"min_distance": -1}]:
        with pytest.raises(kinema.InvalidInput):
            kinema.Cell(**kwargs)
    cell = kinema.Cell().add("a", ur5, tr)
    with pytest.raises(kinema.InvalidInput, match="names two robots"):
        cell.add("a", ur5, tr)
    with pytest.raises(kinema.InvalidInput, match="one motion"):
        cell.add("b", ur5)
    with pytest.raises(kinema.InvalidInput, match="one motion"):
        cell.add("b", ur5, tr, program="HOME\n")
    with pytest.raises(kinema.InvalidInput, match=r"\(K, 7\)|7"):
        cell.add("b", IIWA, tr)  # six joints' trajectory for a seven-joint robot
    with pytest.raises(kinema.InvalidInput, match="q"):
        cell.add("b", ur5, t=tr.t)
    with pytest.raises(kinema.InvalidInput, match="start"):
        cell.add("b", ur5, tr, start="home")
    with pytest.raises(kinema.InvalidInput, match="base"):
        cell.add("b", ur5, tr, base=[1, 2, 3])
    with pytest.raises(kinema.InvalidInput, match="JointTrajectory"):
        cell.add("b", ur5, [1, 2, 3])
    with pytest.raises(kinema.UnknownRobot):
        cell.add("b", "no-such-robot", tr)
    with pytest.raises(kinema.ProgramError, match="bad.prg:1:6"):
        cell.add("b", ur5, program="WAIT 5mm\n", filename="bad.prg")
    assert cell.names == ["a"]
    assert len(cell.run()) == len(tr)
