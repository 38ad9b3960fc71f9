"""Batch work on a Dask cluster (``dask.distributed``, an optional dependency imported only here).

Each function splits a batch into contiguous shards the way ``kinema --shard i/n`` does (shard i of
n is rows ``floor((i-1)·N/n)`` to ``floor(i·N/n)``), submits one task per shard to a
``distributed.Client``, and concatenates the answers in order: the result equals the one-process
call's exactly. Robots and scenes travel to the workers pickled by their description (see
docs/python.md, "Pickling"); a worker needs only the mesh files they name.

Example::

    from dask.distributed import Client
    import kinema, kinema.dask

    client = Client("tcp://scheduler:8786")
    robot = kinema.Robot.builtin("lbr-iiwa-14-r820")
    hits = kinema.dask.collides_batch(client, robot, Q, scene=scene)   # == robot.collides_batch(Q, scene=scene)
"""

from __future__ import annotations

from typing import Any, List, Optional, Tuple

import numpy as np


def shard_range(index: int, count: int, length: int) -> Tuple[int, int]:
    """Rows ``[start, end)`` of shard ``index`` (1-based) of ``count`` over ``length`` rows, as
    ``kinema_io::Shard::range``: contiguous blocks, in order, covering every row once."""
    if count < 1 or not 1 <= index <= count:
        raise ValueError(f"shard {index}/{count}: expected i/n with 1 ≤ i ≤ n")
    return length * (index - 1) // count, length * index // count


def _shards(length: int, count: int) -> List[slice]:
    return [slice(*shard_range(i, count, length)) for i in range(1, count + 1)]


def _shard_count(client: Any, shards: Optional[int]) -> int:
    if shards is not None:
        if shards < 1:
            raise ValueError(f"`shards` must be at least 1, got {shards}")
        return shards
    return max(1, len(client.scheduler_info()["workers"]))


def _fkine_shard(robot, Q):
    return robot.fkine_batch(Q)


def _collides_shard(robot, Q, scene, margin):
    return robot.collides_batch(Q, scene=scene, margin=margin)


def _ik_shard(robot, T, position, options):
    return robot.ik_batch(T, position=position, **options)


def _map(client: Any, shards: Optional[int], length: int, task, *, rows: List[Any], shared: Tuple[Any, ...]):
    """The answers of ``task(robot, *row_blocks, *rest)`` per non-empty shard, in shard order, where
    ``shared`` is ``(robot, *rest)`` (the robot scattered once to every worker) and ``rows`` are the
    batch arrays (or None) cut along their first axis."""
    robot, *rest = shared
    parts = [p for p in _shards(length, _shard_count(client, shards)) if p.stop > p.start]
    if not parts:
        return []
    # Not hashed: a key of its own per call, so that releasing an earlier call's copy cannot drop this one.
    robot_future = client.scatter(robot, broadcast=True, hash=False)
    futures = []
    for part in parts:
        blocks = [None if r is None else np.ascontiguousarray(r[part]) for r in rows]
        futures.append(client.submit(task, robot_future, *blocks, *rest, pure=False))
    return client.gather(futures)


def fkine_batch(client: Any, robot, Q, *, shards: Optional[int] = None) -> np.ndarray:
    """``robot.fkine_batch(Q)`` over the cluster: (N, 4, 4). ``shards``: how many tasks (default:
    one per worker)."""
    Q = np.asarray(Q, dtype=np.float64)
    parts = _map(client, shards, len(Q), _fkine_shard, rows=[Q], shared=(robot,))
    return np.concatenate(parts) if parts else robot.fkine_batch(Q)


def collides_batch(
    client: Any, robot, Q, scene=None, margin: float = 0.0, *, shards: Optional[int] = None
) -> np.ndarray:
    """``robot.collides_batch(Q, scene=scene, margin=margin)`` over the cluster: (N,) bools."""
    Q = np.asarray(Q, dtype=np.float64)
    parts = _map(client, shards, len(Q), _collides_shard, rows=[Q], shared=(robot, scene, margin))
    return np.concatenate(parts) if parts else robot.collides_batch(Q, scene=scene, margin=margin)


def ik_batch(client: Any, robot, T=None, *, position=None, shards: Optional[int] = None, **options):
    """``robot.ik_batch(T, position=position, **options)`` over the cluster: ``(Q, ok, solvers)``
    as that call gives them (``options``: its keywords, e.g. ``q0``, ``solver``, ``seed``, ``scene``)."""
    T = None if T is None else np.asarray(T, dtype=np.float64)
    position = None if position is None else np.asarray(position, dtype=np.float64)
    length = len(T) if T is not None else len(position) if position is not None else 0
    parts = _map(client, shards, length, _ik_shard, rows=[T, position], shared=(robot, options))
    if not parts:
        return robot.ik_batch(T, position=position, **options)
    Q = np.concatenate([p[0] for p in parts])
    ok = np.concatenate([p[1] for p in parts])
    solvers = [s for p in parts for s in p[2]]
    return Q, ok, solvers
