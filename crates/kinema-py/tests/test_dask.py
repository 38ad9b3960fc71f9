"""kinema.dask on a LocalCluster of two worker processes (issue 39 item 5): each batch split into
contiguous shards as ``--shard i/n`` splits it gives exactly the one-process answer."""

import numpy as np
import pytest

import kinema
import kinema.dask as kd
from cli import ROOT
from conftest import random_q

distributed = pytest.importorskip("distributed", reason="dask.distributed is not installed (ci.sh installs it)")

IIWA = "lbr-iiwa-14-r820"


@pytest.fixture(scope="module")
def client():
    cluster = distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None)
    with distributed.Client(cluster) as c:
        yield c
    cluster.close()


def test_shards_are_the_cli_blocks():
    # kinema_io::Shard::range: floor((i-1)·N/n) .. floor(i·N/n); 7 rows in 3 shards as 2, 2, 3.
    assert [kd.shard_range(i, 3, 7) for i in (1, 2, 3)] == [(0, 2), (2, 4), (4, 7)]
    for length in (0, 1, 5, 1001):
        for count in (1, 2, 3, 8):
            ends = [kd.shard_range(i, count, length) for i in range(1, count + 1)]
            assert ends[0][0] == 0 and ends[-1][1] == length
            assert all(a[1] == b[0] for a, b in zip(ends, ends[1:]))
    with pytest.raises(ValueError):
        kd.shard_range(0, 2, 10)


def test_fk_and_collisions_on_two_workers_equal_one_process(client):
    robot = kinema.Robot.builtin(IIWA)
    hood = kinema.Scene.from_file(ROOT / "examples" / "scenes" / "fume-hood.toml")
    Q = random_q(robot, np.random.default_rng(21), 301)
    np.testing.assert_array_equal(kd.fkine_batch(client, robot, Q), robot.fkine_batch(Q))
    np.testing.assert_array_equal(kd.fkine_batch(client, robot, Q, shards=7), robot.fkine_batch(Q))
    hits = kd.collides_batch(client, robot, Q, scene=hood, margin=0.01, shards=5)
    np.testing.assert_array_equal(hits, robot.collides_batch(Q, scene=hood, margin=0.01))
    assert 0 < hits.sum() < len(Q), "a batch with both answers"
    assert kd.fkine_batch(client, robot, Q[:0]).shape == (0, 4, 4)


def test_ik_on_two_workers_equals_one_process(client):
    iiwa = kinema.Robot.builtin(IIWA)
    Ts = iiwa.fkine_batch(random_q(iiwa, np.random.default_rng(22), 41))
    Ts[::5, 0, 3] += 5.0  # some unreachable
    got, expected = kd.ik_batch(client, iiwa, Ts, shards=3), iiwa.ik_batch(Ts)
    np.testing.assert_array_equal(got[0], expected[0])
    np.testing.assert_array_equal(got[1], expected[1])
    assert got[2] == expected[2] and not got[1].all()
    points = Ts[:10, :3, 3]
    got, expected = kd.ik_batch(client, iiwa, position=points, seed=4), iiwa.ik_batch(position=points, seed=4)
    np.testing.assert_array_equal(got[0], expected[0])
    assert got[2] == expected[2]
