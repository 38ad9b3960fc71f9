"""run_program: the example programs give what `kinema run` writes; program properties; diagnostics."""

import _thread
import csv
import subprocess
import sys
import threading
import time

import numpy as np
import pytest

import kinema
from cli import ROOT, kinema_binary

PROGRAMS = ROOT / "examples" / "programs"
EXAMPLES = [
    ("iiwa_draw.prg", "lbr-iiwa-14-r820"),
    ("scara_pick_place.prg", "scara5"),
    ("scorbot_square.prg", "scorbot-er-v-plus"),
]

SEED_003 = """
// seed 003, Fig. 8
HOME 2;
LOOP 2
  MOVEZ -50, 1;
  MOVEXY 100, -50, 2;
  MOVEZ +50, 1;
END
"""


@pytest.mark.parametrize("program,robot", EXAMPLES)
def test_examples_equal_kinema_run(tmp_path, program, robot):
    text = (PROGRAMS / program).read_text(encoding="utf-8")
    plan = kinema.run_program(text, kinema.Robot.builtin(robot), filename=program)
    n = plan.robot.n
    k = len(plan)
    assert isinstance(plan, kinema.Plan) and plan.q.shape == plan.qd.shape == plan.qdd.shape == (k, n)
    assert plan.t[0] == 0.0 and plan.t[-1] == plan.duration and np.all(np.diff(plan.t) > 0)
    lo, hi = plan.robot.qlim
    assert np.all(plan.q >= lo - 1e-9) and np.all(plan.q <= hi + 1e-9)
    starts = [m["start"] for m in plan.motions]
    assert starts == sorted(starts) and plan.motions[-1]["end"] == pytest.approx(plan.duration)
    assert plan.warnings == []
    exe = kinema_binary()
    if exe is None:
        pytest.skip("the kinema command line is not built (cargo build -p kinema-cli); properties checked only")
    out = tmp_path / "signals.csv"
    subprocess.run(
        [str(exe), "run", str(PROGRAMS / program), "--robot", robot, "--out", str(out)],
        check=True,
        capture_output=True,
        timeout=300,
    )
    with out.open(newline="") as f:
        rows = list(csv.reader(f))
    head, data = rows[0], np.array(rows[1:], dtype=float)
    col = {name: i for i, name in enumerate(head)}
    assert data.shape[0] == k
    # The CSV holds 12 decimals.
    assert np.abs(data[:, col["t"]] - plan.t).max() < 1e-11
    for prefix, mine in (("q", plan.q), ("qd", plan.qd), ("qdd", plan.qdd)):
        theirs = data[:, [col[f"{prefix}{i}"] for i in range(1, n + 1)]]
        assert np.abs(theirs - mine).max() < 1e-9 * max(1.0, np.abs(mine).max()), prefix
    # And the tool pose columns are forward kinematics of q with the program's final robot.
    F = plan.robot.fkine_batch(plan.q)
    assert np.abs(data[:, [col["x"], col["y"], col["z"]]] - F[:, :3, 3]).max() < 1e-9


def test_seed_003_program():
    plan = kinema.run_program(SEED_003, "scara5")
    assert plan.duration == pytest.approx(10.0, abs=1e-9)  # 2 + 2 × (1 + 2 + 1)
    assert [m["kind"] for m in plan.motions] == ["HOME"] + ["MOVEZ", "MOVEXY", "MOVEZ"] * 2
    assert [m["line"] for m in plan.motions][:4] == [3, 5, 6, 7]
    assert "HOME" in plan.listing() and plan.listing().startswith("# `scara5`")
    assert np.allclose(plan.q[0], plan.robot.home)
    assert "Plan(7 motion(s)" in repr(plan)
    # dt sets the sample period; the robot may be given by name or as a Robot.
    coarse = kinema.run_program(SEED_003, kinema.Robot.builtin("scara5"), dt=0.1)
    assert np.all(np.diff(coarse.t) <= 0.1 + 1e-12) and len(coarse) < len(plan) / 5


def test_ptp_wait_and_lin_in_a_program():
    r = kinema.Robot.builtin("lbr-iiwa-14-r820")
    target = np.radians([10, 20, 0, -60, 0, 30, 0])
    text = (
        "JACC 90 deg/s^2\n"
        "PTP JOINT(10deg, 20deg, 0deg, -60deg, 0deg, 30deg, 0deg) IN 2s\n"
        "WAIT 1s\n"
        "VEL 100 mm/s\nACC 500 mm/s^2\n"
        "LIN REL CART(0mm, 0mm, -100mm)\n"
    )
    plan = kinema.run_program(text, r, start="home")
    assert [m["kind"] for m in plan.motions] == ["PTP", "WAIT", "LIN"]
    assert plan.motions[0]["end"] == pytest.approx(2.0) and plan.motions[1]["end"] == pytest.approx(3.0)
    hold = (plan.t >= 2.0 - 1e-12) & (plan.t <= 3.0 + 1e-12)
    assert np.allclose(plan.q[hold], target, atol=1e-12)
    # The LIN goes 100 mm straight down from the PTP's end.
    lin = plan.t >= 3.0 - 1e-12
    P = r.fkine_batch(plan.q[lin])[:, :3, 3]
    top = r.fkine(target)[:3, 3]
    assert np.abs(P[:, :2] - top[:2]).max() < 1e-9
    assert P[-1, 2] == pytest.approx(top[2] - 0.1, abs=1e-9) and np.all(np.diff(P[:, 2]) <= 1e-12)
    # A start configuration other than home.
    other = kinema.run_program("WAIT 0.5s\n", r, start=target)
    assert np.allclose(other.q, target) and other.duration == pytest.approx(0.5)


def test_warnings_do_not_stop_the_program():
    text = "JACC 90 deg/s^2\nPTP JOINT(10deg, 20deg, 0deg, -60deg, 0deg, 30deg, 0deg) BLEND 10mm\n"
    plan = kinema.run_program(text, "lbr-iiwa-14-r820", filename="w.prg")
    assert len(plan.warnings) == 1 and plan.warnings[0].startswith("w.prg:2:")
    assert "warning: BLEND on a PTP is ignored" in plan.warnings[0]


def test_program_errors():
    text = "PTP nowhere\nWAIT 5mm\n"
    with pytest.raises(kinema.ProgramError) as e:
        kinema.run_program(text, "lbr-iiwa-14-r820", filename="prog.prg")
    assert isinstance(e.value, ValueError) and isinstance(e.value, kinema.KinemaError)
    message = str(e.value)
    assert message.startswith("prog.prg:1:5: error: unknown position `nowhere`")
    assert "prog.prg:2:6: error: expected a time (s, ms), found a length (mm, cm, m)" in message
    assert " 2 │ WAIT 5mm" in message and "known positions: home" in message
    assert message.endswith("prog.prg: 2 error(s), 0 warning(s); nothing was run")
    assert e.value.diagnostics == [
        (1, 5, "unknown position `nowhere`"),
        (2, 6, "expected a time (s, ms), found a length (mm, cm, m)"),
    ]
    with pytest.raises(kinema.ProgramError, match=r"^<program>:1:1: error: the sample period must be positive"):
        kinema.run_program("WAIT 1s\n", "scara5", dt=0.0)
    # Unreachable targets and limit violations are diagnostics too.
    with pytest.raises(kinema.ProgramError, match=r"^<program>:1:1: error: LIN cannot be followed: at t = [0-9.]+ s of the path: unreachable target"):
        kinema.run_program("LIN CART(3m, 0m, 0.5m, 0deg, 180deg, 0deg)\n", "lbr-iiwa-14-r820")
    with pytest.raises(kinema.UnknownRobot):
        kinema.run_program("WAIT 1s\n", "no-such-robot")
    with pytest.raises(kinema.InvalidInput, match="`robot` must be a kinema.Robot"):
        kinema.run_program("WAIT 1s\n", 42)
    # A start configuration of the wrong length is the compiler's diagnostic at 1:1 (the CLI rejects it earlier).
    with pytest.raises(kinema.ProgramError, match=r"^<program>:1:1: error: start configuration: .* has 7 joints"):
        kinema.run_program("WAIT 1s\n", "lbr-iiwa-14-r820", start=[0.0, 0.0])
    with pytest.raises(kinema.InvalidInput, match="no-such-pose"):
        kinema.run_program("WAIT 1s\n", "lbr-iiwa-14-r820", start="no-such-pose")


# A program that runs for seconds within every limit of the language: ~500 000 inverse
# kinematics (one per PTP, each to the pose the arm is already at) and no samples.
LONG = (
    "JACC 90 deg/s^2\n"
    "PTP CART(500mm, 0mm, 400mm, 0deg, 180deg, 0deg) IN 1s\n"
    "LOOP 499000\n"
    "  PTP CART(500mm, 0mm, 400mm, 0deg, 180deg, 0deg)\n"
    "END\n"
)


def test_time_limit_stops_a_long_program():
    start = time.monotonic()
    with pytest.raises(kinema.ProgramError, match=r"stopped here: the time budget of 0\.300 s ran out") as e:
        kinema.run_program(LONG, "lbr-iiwa-14-r820", time_limit=0.3)
    assert time.monotonic() - start < 2.0
    # At the LOOP (between passes) or at the PTP in it.
    assert len(e.value.diagnostics) == 1 and e.value.diagnostics[0][0] in (3, 4)
    # No limit, or a generous one, changes nothing for a short program.
    assert kinema.run_program("WAIT 1s\n", "scara5", time_limit=60).duration == pytest.approx(1.0)
    assert kinema.run_program("WAIT 1s\n", "scara5", time_limit=None).duration == pytest.approx(1.0)
    for bad in (-1.0, float("nan"), float("inf")):
        with pytest.raises(kinema.InvalidInput, match="time_limit"):
            kinema.run_program("WAIT 1s\n", "scara5", time_limit=bad)


def test_ctrl_c_stops_a_long_program():
    # What Ctrl-C does: SIGINT to the main thread. It is raised at the moment run_program is
    # called (a profile hook sees the call), not after a wall-clock delay: the signal is pending
    # when the call starts, and only run_program's own polling can act on it, so on any machine,
    # however loaded, the interrupt reaches the running program (a timer could fire before the call
    # or, on a slow machine, the 2 s bound on the run could fail; both happened).
    calls = []

    def interrupt_on_call(frame, event, arg):
        if event == "c_call" and getattr(arg, "__name__", None) == "run_program" and not calls:
            calls.append(arg)
            _thread.interrupt_main()

    sys.setprofile(interrupt_on_call)
    try:
        with pytest.raises(KeyboardInterrupt):
            kinema.run_program(LONG, "lbr-iiwa-14-r820")
    finally:
        sys.setprofile(None)
    assert calls == [kinema.run_program], "the interrupt came before the call, not during it"
    # run_program returns only after its worker thread stopped; the interpreter and the library
    # go on working afterwards.
    assert kinema.run_program("WAIT 1s\n", "scara5").duration == pytest.approx(1.0)


def test_other_threads_run_while_a_program_does():
    # The GIL is released: a Python thread counts while the program runs.
    counted = []
    done = threading.Event()

    def count():
        n = 0
        while not done.is_set():
            n += 1
        counted.append(n)

    t = threading.Thread(target=count)
    t.start()
    try:
        with pytest.raises(kinema.ProgramError, match="time budget"):
            kinema.run_program(LONG, "lbr-iiwa-14-r820", time_limit=0.3)
    finally:
        done.set()
        t.join()
    assert counted[0] > 1000


def test_skip_unreachable_leaves_out_a_point_outside_the_workspace():
    """Seed 003 Fig. 9, as kinema run --skip-unreachable: a warning at the
    skipped line, and the same trajectory as the program without it."""
    import pathlib

    src = (pathlib.Path(__file__).resolve().parents[3] / "examples" / "programs" / "seed003_fig9_skip.prg").read_text()
    with pytest.raises(kinema.ProgramError, match="unreachable"):
        kinema.run_program(src, "scara5")
    plan = kinema.run_program(src, "scara5", skip_unreachable=True)
    assert any("skipped" in str(w) for w in plan.warnings)
    without = "".join(line + "\n" for line in src.splitlines() if "2000" not in line)
    reference = kinema.run_program(without, "scara5")
    np.testing.assert_array_equal(plan.q, reference.q)


def test_a_ptp_avoid_goes_around_the_sash_as_kinema_run_does(tmp_path):
    """PTP … AVOID with a scene: the same planned path as `kinema run --scene`, clear of the hood."""
    hood = ROOT / "examples" / "scenes" / "fume-hood.toml"
    scene = kinema.Scene.from_file(hood)
    robot = kinema.Robot.builtin("lbr-iiwa-14-r820")
    text = "JVEL 50deg/s\nPTP JOINT(90deg, 60deg, 0, 0, 0, 0, 0) AVOID\n"
    start = np.radians([-90, 60, 0, 0, 0, 0, 0])
    plan = kinema.run_program(text, robot, start=start, scene=scene)
    np.testing.assert_allclose(plan.q[-1], np.radians([90, 60, 0, 0, 0, 0, 0]), atol=1e-12)
    assert robot.check(plan, scene=scene).ok
    exe = kinema_binary()
    if exe is None:
        pytest.skip("the kinema command line is not built (cargo build -p kinema-cli)")
    program, out = tmp_path / "swing.prg", tmp_path / "swing.csv"
    program.write_text(text)
    start_arg = "--start=" + ",".join(repr(float(x)) for x in start)
    subprocess.run(
        [str(exe), "run", str(program), "--robot", "lbr-iiwa-14-r820", start_arg, "--scene", str(hood), "--out", str(out)],
        check=True,
        capture_output=True,
        timeout=300,
    )
    with out.open(newline="") as f:
        rows = list(csv.reader(f))
    head, data = rows[0], np.array(rows[1:], dtype=float)
    q = data[:, [head.index(f"q{i}") for i in range(1, 8)]]
    assert q.shape == plan.q.shape
    assert np.abs(q - plan.q).max() < 1e-9
