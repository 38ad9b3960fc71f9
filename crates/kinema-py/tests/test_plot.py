"""Plots: Robot.plot, plot_joints, plot_cartesian (matplotlib, Agg backend, no window)."""

import sys

import matplotlib
import numpy as np
import pytest

import kinema

matplotlib.use("Agg")


@pytest.fixture
def trajectory(robots):
    robot = robots["puma560"]
    return robot, robot.ptp(robot.home, robot.home + 0.4, 0.02, vmax=1.0, amax=2.0)


def test_plot_draws_the_links_where_fk_puts_them(robots, tmp_path):
    robot = robots["puma560"]
    q = np.random.default_rng(7).uniform(-1, 1, robot.n)
    fig = robot.plot(q, file=tmp_path / "arm.png")
    assert (tmp_path / "arm.png").stat().st_size > 1000
    ax = fig.axes[0]
    stick = ax.lines[0]
    xs, ys, zs = stick.get_data_3d()
    np.testing.assert_allclose(np.stack([xs, ys, zs], axis=1), robot.fkine_all(q)[:, :3, 3], atol=1e-12)
    assert len(ax.lines) == 1 + 3 * (robot.n + 2)  # the stick and three axes per frame
    assert len(robot.plot(q, frames=False).axes[0].lines) == 1


def test_plot_of_a_trajectory_draws_several_figures_and_the_path(trajectory):
    robot, tr = trajectory
    ax = robot.plot(tr, frames=False).axes[0]
    assert len(ax.lines) == kinema._plot.FIGURES_PER_TRAJECTORY + 1
    path = np.stack(ax.lines[-1].get_data_3d(), axis=1)
    np.testing.assert_allclose(path, robot.fkine_batch(tr.q)[:, :3, 3], atol=1e-12)
    last = np.stack(ax.lines[-2].get_data_3d(), axis=1)
    np.testing.assert_allclose(last[-1], robot.fkine(tr.q[-1])[:3, 3], atol=1e-12)


def test_curve_plots(trajectory, tmp_path):
    robot, tr = trajectory
    fig = robot.plot_joints(tr, file=tmp_path / "joints.svg")
    assert len(fig.axes) == 3 and (tmp_path / "joints.svg").exists()
    np.testing.assert_array_equal(fig.axes[1].lines[2].get_ydata(), tr.qd[:, 2])
    fig = robot.plot_cartesian(tr)
    position = robot.fkine_batch(tr.q)[:, :3, 3]
    np.testing.assert_allclose(fig.axes[0].lines[1].get_ydata(), position[:, 1], atol=1e-12)
    with pytest.raises(kinema.InvalidInput, match="at least two samples"):
        robot.plot_joints(robot.home)


def test_wrong_shapes_and_missing_matplotlib(robots, monkeypatch):
    robot = robots["puma560"]
    with pytest.raises(kinema.InvalidInput, match=r"must be \(6,\) or \(N, 6\)"):
        robot.plot([0.0, 1.0])
    monkeypatch.setitem(sys.modules, "matplotlib.pyplot", None)
    with pytest.raises(ImportError, match="pip install matplotlib"):
        robot.plot(robot.home)
