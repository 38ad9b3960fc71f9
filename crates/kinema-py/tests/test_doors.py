"""One answer per question across the three doors (issue 36): the same request through Python's
``to_dict`` (and ``Robot.fk_dict``, ``manip_dict``, ``ik_dict``, …), through ``kinema … --json`` and
through the HTTP API of ``kinema serve`` gives the same JSON, field for field.

All three write ``kinema-io``'s answer types with serde_json, and Python reads that JSON back with
``json.loads``, so the comparison is exact: strings, integers and every float bit for bit (shortest
round-trip text). Joint values go to the CLI as Python's ``repr`` of each float, which is the
shortest round-trip text too, so each door computes from the same numbers.

Needs the ``kinema`` binary (see ``cli.py``; ``.ci/run`` builds it with ``cargo test --workspace``
before the Python package's tests); skipped with that reason without it. The server is started from
the binary on a free port and stopped when the module's tests are done.
"""

import json
import subprocess
import urllib.request

import numpy as np
import pytest

import kinema
from cli import ROOT, cli_json, kinema_binary, needs_cli
from conftest import random_q

pytestmark = needs_cli

# The doors' answers are compared on these robots; fk, manip and info on every built-in.
IK_ROBOTS = ["puma560", "ur5", "scorbot-er-v-plus"]
PTP_ROBOTS = ["puma560", "panda"]
PROGRAM = """POS a = CART(550mm, -150mm, 400mm, 0deg, 180deg, 0deg)
POS b = CART(550mm, 50mm, 400mm, 0deg, 180deg, 0deg)
PTP a
WAIT 0.5
LIN b
"""


class Server:
    """``kinema serve`` on a free port of 127.0.0.1, answering the JSON API."""

    def __init__(self):
        self.process = subprocess.Popen(
            [str(kinema_binary()), "serve", "--port", "0", "--robot", "puma560"],
            stdout=subprocess.PIPE,
            stderr=subprocess.DEVNULL,
            text=True,
        )
        # Its first line, once it listens: "kinema serve: http://127.0.0.1:PORT/".
        line = self.process.stdout.readline()
        if not line.startswith("kinema serve: http://"):
            self.stop()
            raise RuntimeError(f"kinema serve did not start: {line!r}")
        self.url = line.split(": ", 1)[1].strip().rstrip("/")

    def api(self, method, path, body=None):
        """The JSON answer of ``method path`` with the JSON ``body``; fails on a status other than 200."""
        data = None if body is None else json.dumps(body).encode()
        request = urllib.request.Request(
            self.url + path, data=data, method=method, headers={"Content-Type": "application/json"}
        )
        with urllib.request.urlopen(request, timeout=60) as reply:
            assert reply.status == 200, (method, path, reply.status)
            return json.loads(reply.read())

    def stop(self):
        self.process.terminate()
        try:
            self.process.wait(timeout=10)
        except subprocess.TimeoutExpired:
            self.process.kill()
            self.process.wait()


@pytest.fixture(scope="module")
def server():
    s = Server()
    yield s
    s.stop()


def text(values):
    """Comma-separated shortest round-trip text of numbers: the CLI reads back exactly these values."""
    return ",".join(repr(float(v)) for v in values)


def test_fk_manip_jacobian_and_info_are_one_answer(server):
    rng = np.random.default_rng(36)
    names = kinema.Robot.builtins()
    assert {"puma560", "ur5", "scorbot-er-v-plus", "lbr-iiwa-14-r820"} <= set(names)
    for name in names:
        robot = kinema.Robot.builtin(name)
        for _ in range(2):
            q = [float(v) for v in random_q(robot, rng, margin=0.0)]
            body = {"robot": name, "q": q}
            fk = robot.fk_dict(q)
            assert fk == cli_json(["fk", "--robot", name, "--q", text(q), "--json"]), (name, q)
            assert fk == server.api("POST", "/api/fk", body), (name, q)
            manip = robot.manip_dict(q)
            assert manip == cli_json(["manip", "--robot", name, "--q", text(q), "--json"]), (name, q)
            assert manip == server.api("POST", "/api/manip", body), (name, q)
        # The doors without a server endpoint: the Jacobian and the manipulability along a direction.
        cli = cli_json(["jacobian", "--robot", name, "--q", text(q), "--frame", "tool", "--json"])
        assert robot.jacobian_dict(q, frame="tool") == cli, name
        cli = cli_json(["jacobian", "--robot", name, "--q", text(q), "--analytic", "xyz", "--json"])
        assert robot.jacobian_dict(q, analytic="xyz") == cli, name
        cli = cli_json(["manip", "--robot", name, "--q", text(q), "--direction", "0.0,0.6,0.8", "--json"])
        assert robot.manip_dict(q, direction=[0.0, 0.6, 0.8]) == cli, name
        info = robot.to_dict()
        assert info == cli_json(["info", "--robot", name, "--json"]), name
        assert info == server.api("GET", f"/api/robots/{name}"), name


def test_ik_of_every_solution_is_one_answer(server):
    rng = np.random.default_rng(361)
    for name in IK_ROBOTS:
        robot = kinema.Robot.builtin(name)
        for _ in range(2):
            q = random_q(robot, rng)
            T, pose = robot.fkine(q), robot.fk_dict(q)
            position, rpy = pose["position"], pose["rpy"]
            answer = robot.ik_dict(position + rpy, all=True)
            assert answer["solutions"], (name, pose)
            cli = cli_json(["ik", "--robot", name, "--pose", text(position + rpy), "--all", "--json"])
            assert answer == cli, (name, position, rpy)
            served = server.api("POST", "/api/ik", {"robot": name, "position": position, "rpy": rpy})
            # Which solution a single-answer request returns: only the server lists all and marks it.
            picked = served.pop("picked")
            assert answer == served, (name, position, rpy)
            one = robot.ik(position + rpy)
            assert one.to_dict() == served["solutions"][picked]
            assert robot.ik_dict(position + rpy)["solutions"] == [one.to_dict()]
            # A 4×4 target is the same question.
            assert robot.ik_dict(T, all=True)["solutions"] == [s.to_dict() for s in robot.ik(T, all=True)]


def test_an_unreachable_target_is_one_answer():
    robot = kinema.Robot.builtin("puma560")
    far = [2.0, 0.5, 0.3, 0.0, 0.0, 0.0]
    with pytest.raises(kinema.Unreachable) as e:
        robot.ik(far)
    cli = cli_json(["ik", "--robot", "puma560", "--pose", text(far), "--json"], code=2)
    assert e.value.to_dict() == cli and cli["error"] == "unreachable"
    assert e.value.closest == cli["closest"]


def test_ptp_lin_and_a_program_are_one_answer(server, tmp_path):
    rng = np.random.default_rng(362)
    csv = str(tmp_path / "out.csv")
    for name in PTP_ROBOTS:
        robot = kinema.Robot.builtin(name)
        q0, q1 = ([float(v) for v in random_q(robot, rng)] for _ in range(2))
        summary = robot.ptp(q0, q1, 0.01).to_dict()
        cli = cli_json(["traj", "ptp", "--robot", name, "--from", text(q0), "--to", text(q1), "--out", csv, "--json"])
        assert summary == cli, name
        served = server.api("POST", "/api/traj", {"robot": name, "kind": "ptp", "from": q0, "to": q1})
        # The server adds the samples themselves; the CLI wrote them to the CSV, Python has them as arrays.
        for key in ["t", "q", "qd", "qdd"]:
            assert served.pop(key) is not None, key
        assert summary == served, name

    robot = kinema.Robot.builtin("puma560")
    q0 = [0.1, 0.6, -0.4, 0.2, 0.5, 0.3]
    goal = robot.fk_dict(q0)
    to = [goal["position"][0], goal["position"][1] + 0.05, goal["position"][2] - 0.05] + goal["rpy"]
    summary = robot.lin(q0, to, 0.01, vmax=0.25, amax=1.0).to_dict()
    args = ["traj", "lin", "--robot", "puma560", "--from", text(q0), "--to", text(to), "--vmax", "0.25"]
    assert summary == cli_json(args + ["--amax", "1.0", "--out", csv, "--json"])
    served = server.api("POST", "/api/traj", {"robot": "puma560", "kind": "lin", "from": q0, "position": to[:3],
                                              "rpy": to[3:], "vmax": 0.25, "amax": 1.0})
    for key in ["t", "q", "qd", "qdd"]:
        assert served.pop(key) is not None, key
    assert summary == served

    program = tmp_path / "move.prg"
    program.write_text(PROGRAM)
    plan = kinema.run_program(PROGRAM, "lbr-iiwa-14-r820", filename=str(program)).to_dict()
    cli = cli_json(["run", str(program), "--robot", "lbr-iiwa-14-r820", "--out", csv, "--json"])
    assert plan == cli and [m["kind"] for m in plan["motions"]] == ["PTP", "WAIT", "LIN"]
    served = server.api("POST", "/api/run", {"robot": "lbr-iiwa-14-r820", "program": PROGRAM})
    for key in ["t", "q", "qd", "qdd", "warnings_rendered"]:
        assert served.pop(key) is not None, key
    assert plan == served


def test_a_trajectory_check_and_a_time_law_are_one_answer(tmp_path):
    """`kinema traj check` of a CSV and Robot.check of its columns; the doors without a server endpoint."""
    ur5 = kinema.Robot.builtin("ur5")
    path = tmp_path / "ptp.csv"
    cli_json(["traj", "ptp", "--robot", "ur5", "--from", "home", "--to", "0.5,-1.2,1.0,0.3,0.2,-0.4",
              "--out", str(path), "--json"])
    f = np.genfromtxt(path, delimiter=",", names=True)
    cols = lambda prefix: np.column_stack([f[f"{prefix}{i}"] for i in range(1, 7)])  # noqa: E731
    # The CSV has 12 decimals: the CLI allows for half the last digit in values and times, as here.
    report = ur5.check(f["t"], cols("q"), cols("qd"), cols("qdd"), vmax=0.5, min_manip=0.05,
                       resolution=5e-13, time_resolution=5e-13)
    cli = cli_json(["traj", "check", "--robot", "ur5", str(path), "--vmax", "0.5", "--min-manip", "0.05",
                    "--json"], code=1)
    assert report.to_dict() == cli and not cli["ok"] and cli["violations"]
    assert report.violations == cli["violations"] and report.warnings == cli["warnings"]

    rommel = kinema.Robot.builtin("rommel")
    tr = rommel.expr({1: "0.5*sin(4*pi*t^2/2)", 3: "0.2*t"}, 1.3, dt=0.05, vmax=20.0, amax=400.0)
    cli = cli_json(["traj", "expr", "--robot", "rommel", "--joint", "1", "0.5*sin(4*pi*t^2/2)", "--joint", "3",
                    "0.2*t", "--duration", "1.3", "--dt", "0.05", "--vmax", "20", "--amax", "400",
                    "--out", str(tmp_path / "expr.csv"), "--json"])
    assert tr.to_dict() == cli

    law = kinema.time_law("scurve", 0.5, vmax=1.0, amax=2.0, jmax=20.0)
    cli = cli_json(["traj", "law", "--profile", "scurve", "--distance", "0.5", "--vmax", "1", "--amax", "2",
                    "--jmax", "20", "--dt", "0.05", "--json"])
    assert law.to_dict(dt=0.05) == cli


def test_a_cell_is_one_answer(tmp_path):
    """`kinema cell --json` of a cell file and Cell.run().to_dict() of the same robots and programs."""
    cells = ROOT / "examples" / "cells"
    bases = {"holder": [0.0, 0.0, 0.0, 0.0, 0.0, 0.0], "drawer": [1.2, 0.0, 0.0, 0.0, 0.0, float(np.pi)]}
    cell = kinema.Cell(dt=0.01, min_distance=0.3)
    lines = ["dt = 0.01", "min_distance = 0.3", 'rpy = "zyx"']
    for name, base in bases.items():
        program = cells / f"seed004_{name}.prg"
        cell.add(name, "lbr-iiwa-14-r820", program=program.read_text(encoding="utf-8"), base=base)
        lines += ["[[robot]]", f'name = "{name}"', 'robot = "lbr-iiwa-14-r820"',
                  f"base = {{ xyz = [{text(base[:3])}], rpy = [{text(base[3:])}] }}", f'program = "{program}"']
    path = tmp_path / "cell.toml"
    path.write_text("\n".join(lines) + "\n")
    answer = cell.run().to_dict()
    cli = cli_json(["cell", str(path), "--json"], code=3 if not answer["ok"] else 0)
    # What only a cell file has: its name and the program files.
    assert cli.pop("file") == str(path)
    for robot in cli["robots"]:
        assert robot.pop("program").endswith(".prg")
    assert answer == cli and [p["robots"] for p in answer["pairs"]] == [["holder", "drawer"]]
