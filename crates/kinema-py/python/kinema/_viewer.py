"""The browser viewer from Python: ``Robot.show`` and ``Robot.animate``.

One ``kinema serve`` process per Python process, started by the first call on
127.0.0.1 with a free port and stopped when Python exits. The command line is
``$KINEMA_BIN`` if set, else ``kinema`` on ``PATH`` (``cargo install --path
crates/kinema-cli``). Each call posts the configuration or trajectory to the
server's ``POST /api/view``; the page polls ``GET /api/view`` and shows each
request once, so later calls move the page already open. A call for another
robot or scene starts a new server (and page) in place of the old one.
"""

import atexit
import json
import os
import shutil
import subprocess
import tempfile
import threading
import urllib.error
import urllib.request
import webbrowser

import numpy as np

from ._errors import InvalidInput, KinemaError

_lock = threading.Lock()
_current = None


class Viewer:
    """A running ``kinema serve`` on one robot (and scene). In Jupyter it
    displays the page inline; elsewhere its :attr:`url` opens in a browser."""

    def __init__(self, key, process, url, files):
        self._key = key
        self._process = process
        self._files = files
        self._opened = False
        #: The page, ``http://127.0.0.1:PORT/``.
        self.url = url

    def __repr__(self):
        return f"<kinema viewer at {self.url}>"

    def _repr_html_(self):
        return f'<iframe src="{self.url}" width="100%" height="640" style="border: 0"></iframe>'

    @property
    def pid(self):
        """The server's process id."""
        return self._process.pid

    def running(self):
        """Whether the server is still running."""
        return self._process.poll() is None

    def request(self, path, body=None):
        """The server's JSON answer to ``GET path``, or ``POST path`` with ``body``."""
        data = None if body is None else json.dumps(body).encode()
        headers = {"Content-Type": "application/json"}
        req = urllib.request.Request(self.url + path.lstrip("/"), data=data, headers=headers)
        try:
            with urllib.request.urlopen(req, timeout=30) as res:
                return json.load(res)
        except urllib.error.HTTPError as e:
            message = json.load(e).get("error", str(e))
            raise InvalidInput(message) if e.code in (400, 404, 422) else KinemaError(message) from None

    def shown(self):
        """What the page was last asked to show: ``{version, robot, q}`` or ``{version, robot, t, q}``."""
        return self.request("/api/view")

    def stop(self):
        """Stops the server (also done when Python exits)."""
        if self.running():
            self._process.terminate()
            try:
                self._process.wait(timeout=5)
            except subprocess.TimeoutExpired:
                self._process.kill()
                self._process.wait()
        for f in self._files:
            try:
                os.unlink(f)
            except OSError:
                pass
        self._files = []

    def _open(self, open_browser):
        if open_browser and not self._opened and not _in_jupyter():
            webbrowser.open(self.url)
        self._opened = True


def kinema_command():
    """The ``kinema`` command line: ``$KINEMA_BIN``, else ``kinema`` on ``PATH``."""
    found = os.environ.get("KINEMA_BIN") or shutil.which("kinema")
    if not found or not os.path.exists(found):
        raise FileNotFoundError(
            "the viewer runs `kinema serve`: set KINEMA_BIN to the kinema command line, or put it on PATH "
            "(cargo install --path crates/kinema-cli)"
        )
    return found


def show(robot, q, scene, open_browser):
    """``Robot.show``: ``q`` (already checked) on the page."""
    viewer = _viewer_for(robot, scene)
    viewer.request("/api/view", {"robot": robot.name, "q": list(q)})
    viewer._open(open_browser)
    return viewer


def animate(robot, trajectory, scene, open_browser):
    """``Robot.animate``: the trajectory's samples, checked here, played by the page."""
    if hasattr(trajectory, "t") and hasattr(trajectory, "q"):
        t, q = trajectory.t, trajectory.q
    else:
        try:
            t, q = trajectory
        except (TypeError, ValueError):
            raise InvalidInput("animate expects a JointTrajectory, a Plan or a (t, q) pair") from None
    try:
        t = np.asarray(t, dtype=float)
        q = np.asarray(q, dtype=float)
    except ValueError as e:
        raise InvalidInput(f"animate: t and q must be numbers, q one row of {robot.n} per time ({e})") from None
    if t.ndim != 1 or q.ndim != 2 or len(t) != len(q) or len(t) < 2:
        raise InvalidInput(
            f"animate needs two or more samples, t of shape (N,) and q of shape (N, {robot.n}); "
            f"got t {t.shape} and q {q.shape}"
        )
    if not np.all(np.isfinite(t)) or np.any(np.diff(t) <= 0):
        raise InvalidInput("animate: t must be finite and increasing")
    rows = [robot._viewer_q(row) for row in q]
    viewer = _viewer_for(robot, scene)
    viewer.request("/api/view", {"robot": robot.name, "t": t.tolist(), "q": rows})
    viewer._open(open_browser)
    return viewer


def _viewer_for(robot, scene):
    """The running viewer if it serves this robot and scene, else a new one in its place."""
    global _current
    source = robot._viewer_source()
    scene_source = scene._viewer_source() if scene is not None else None
    key = (json.dumps(source, sort_keys=True), scene_source)
    with _lock:
        if _current is not None and _current._key == key and _current.running():
            return _current
        if _current is not None:
            _current.stop()
            _current = None
        viewer = _start(key, source, scene_source)
        try:
            _check_same_robot(viewer, robot)
        except Exception:
            viewer.stop()
            raise
        _current = viewer
        return viewer


def _start(key, source, scene_source):
    files = []
    spec = source.get("spec") or _temp(source["text"], source["suffix"], files)
    args = [kinema_command(), "serve", "--port", "0", "--robot", spec]
    if source.get("tip"):
        args += ["--tip", source["tip"]]
    if scene_source is not None:
        text, file = scene_source
        args += ["--scene", file if os.path.isfile(file) else _temp(text, ".toml", files)]
    log = tempfile.TemporaryFile()
    process = subprocess.Popen(args, stdout=subprocess.PIPE, stderr=log, stdin=subprocess.DEVNULL)
    first = process.stdout.readline().decode().strip()
    if not first.startswith("kinema serve: "):
        process.wait()
        log.seek(0)
        raise KinemaError(f"`kinema serve` did not start: {log.read().decode().strip() or first}")
    viewer = Viewer(key, process, first[len("kinema serve: "):], files)
    atexit.register(viewer.stop)
    return viewer


def _check_same_robot(viewer, robot):
    """The server's FK of the home configuration must be the robot's (a base or tool set in Python is not sent)."""
    home = robot.home.tolist()
    served = np.array(viewer.request("/api/fk", {"robot": robot.name, "q": home})["T"])
    if not np.allclose(served, robot.fkine(home), atol=1e-9):
        raise InvalidInput(f"the viewer would draw `{robot.name}` differently (its base or tool was changed in Python)")


def _temp(text, suffix, files):
    fd, path = tempfile.mkstemp(prefix="kinema-view-", suffix=suffix)
    with os.fdopen(fd, "w") as f:
        f.write(text)
    files.append(path)
    return path


def _in_jupyter():
    try:
        from IPython import get_ipython
    except ImportError:
        return False
    shell = get_ipython()
    return shell is not None and "IPKernelApp" in shell.config
