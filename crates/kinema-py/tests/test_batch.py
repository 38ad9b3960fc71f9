"""Batch forms equal per-call results; threads; the GIL is released while computing."""

import threading
import time
from concurrent.futures import ThreadPoolExecutor

import numpy as np
import pytest

from conftest import ROBOTS, random_q


@pytest.mark.parametrize("name", ROBOTS)
def test_fkine_batch_equals_per_call(robots, name):
    r = robots[name]
    Q = random_q(r, np.random.default_rng(20), 3000)
    T = r.fkine_batch(Q)
    assert T.shape == (3000, 4, 4) and T.dtype == np.float64 and T.flags.c_contiguous
    for i in range(0, 3000, 97):
        assert np.array_equal(T[i], r.fkine(Q[i]))


@pytest.mark.parametrize("name", ROBOTS)
def test_jacobian_batches_equal_per_call(robots, name):
    r = robots[name]
    Q = random_q(r, np.random.default_rng(21), 1000)
    J0 = r.jacob0_batch(Q)
    Je = r.jacobe_batch(Q)
    assert J0.shape == (1000, 6, r.n) and Je.shape == (1000, 6, r.n)
    for i in range(0, 1000, 37):
        assert np.array_equal(J0[i], r.jacob0(Q[i]))
        assert np.array_equal(Je[i], r.jacobe(Q[i]))


def test_batch_input_forms(robots):
    r = robots["puma560"]
    Q = random_q(r, np.random.default_rng(22), 50)
    ref = r.fkine_batch(Q)
    assert np.array_equal(r.fkine_batch(Q.tolist()), ref)
    assert np.array_equal(r.fkine_batch(np.asfortranarray(Q)), ref)
    assert np.array_equal(r.fkine_batch(np.ascontiguousarray(Q.T).T), ref)
    assert r.fkine_batch(np.zeros((0, r.n))).shape == (0, 4, 4)
    assert r.jacob0_batch(np.zeros((0, r.n))).shape == (0, 6, r.n)


def test_threads_do_not_deadlock_and_agree(robots):
    r = robots["lbr-iiwa-14-r820"]
    rng = np.random.default_rng(23)
    batches = [random_q(r, rng, 20000) for _ in range(8)]
    serial = [r.fkine_batch(Q) for Q in batches]
    with ThreadPoolExecutor(max_workers=4) as pool:
        par = list(pool.map(r.fkine_batch, batches))
        jac = list(pool.map(r.jacob0_batch, batches[:2]))
        sols = list(pool.map(lambda Q: r.ik(r.fkine(Q[0]), q0=Q[0]), batches))
    for a, b in zip(serial, par):
        assert np.array_equal(a, b)
    assert np.array_equal(jac[0], r.jacob0_batch(batches[0]))
    assert all(s.success for s in sols)


def test_gil_released_during_batch(robots):
    """A Python thread keeps running while batches compute in another thread.

    If the GIL were held while computing, the Python thread could only run
    between calls (one 5 ms switch interval per call), covering a small
    fraction of the time; with it released it runs nearly all the time.
    """
    r = robots["lbr-iiwa-14-r820"]
    Q = random_q(r, np.random.default_rng(24), 300_000)
    t0 = time.perf_counter()
    r.jacob0_batch(Q)
    once = time.perf_counter() - t0
    reps = max(2, int(np.ceil(0.8 / max(once, 1e-3))))

    done = threading.Event()
    span = []

    def work():
        a = time.perf_counter()
        for _ in range(reps):
            r.jacob0_batch(Q)
        span.append((a, time.perf_counter()))
        done.set()

    stamps = []
    t = threading.Thread(target=work)
    t.start()
    while not done.is_set():
        stamps.append(time.perf_counter())
        sum(range(100))  # plain Python work, needs the GIL
    t.join()
    start, end = span[0]
    inside = np.array([s for s in stamps if start <= s <= end])
    gaps = np.diff(np.concatenate([[start], inside, [end]]))
    short = min(0.02, once / 3)
    covered = gaps[gaps < short].sum() / (end - start)
    assert covered > 0.5, f"Python thread ran {covered:.0%} of the time ({reps} calls of {once * 1e3:.1f} ms)"
