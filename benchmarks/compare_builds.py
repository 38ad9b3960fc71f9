#!/usr/bin/env python3
"""Per-call fkine/jacob0 of several kinema builds, interleaved in one process.

    python benchmarks/compare_builds.py A.whl B.whl [...] [--robot NAME] [--n 50000] [--passes 3]

Each argument is a kinema wheel (from `maturin build`); it is unpacked into a
temporary directory as the package `kinema_<i>` (the package imports its
extension module relatively, so several builds load side by side). Every
build's `fkine(q)` and `jacob0(q)` are timed in turn on each window of 1000
configurations, like the per-call rows of python_vs_peers.py, and the fastest
window of each is printed, with `kinema_bare_call`'s native floor when that is
installed (benchmarks/README.md).

Why: from Python, builds of the same FK code have measured up to ~15 % apart
per call (identical instruction counts; code placement). Timed one after the
other, such a build-to-build difference and the machine's drift look like the
effect of a change; timed in the same windows, they do not. The script needs
numpy and installs nothing.
"""

from __future__ import annotations

import argparse
import gc
import importlib
import sys
import tempfile
import time
import zipfile
from pathlib import Path

import numpy as np


def load(wheel: Path, index: int, root: Path):
    """Unpacks `wheel`'s kinema package under `root` as `kinema_<index>` and imports it."""
    with zipfile.ZipFile(wheel) as z:
        members = [m for m in z.namelist() if m.startswith("kinema/")]
        if not members:
            sys.exit(f"{wheel}: no kinema/ package in this wheel")
        for m in members:
            target = root / f"kinema_{index}" / m[len("kinema/"):]
            if m.endswith("/"):
                continue
            target.parent.mkdir(parents=True, exist_ok=True)
            target.write_bytes(z.read(m))
    return importlib.import_module(f"kinema_{index}")


def window_time(f, w, clock=time.perf_counter_ns) -> float:
    t0 = clock()
    for q in w:
        f(q)
    return (clock() - t0) / len(w)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("wheels", nargs="+", type=Path, help="kinema wheels to compare")
    ap.add_argument("--robot", default="lbr-iiwa-14-r820", help="built-in robot (default lbr-iiwa-14-r820)")
    ap.add_argument("--n", type=int, default=50_000, help="configurations (default 50000)")
    ap.add_argument("--passes", type=int, default=3, help="passes over them (default 3)")
    ap.add_argument("--seed", type=int, default=0)
    args = ap.parse_args()
    for w in args.wheels:
        if not w.is_file():
            sys.exit(f"{w}: no such wheel")

    with tempfile.TemporaryDirectory() as tmp:
        sys.path.insert(0, tmp)
        mods = [load(w, i, Path(tmp)) for i, w in enumerate(args.wheels)]
        robots = [m.Robot.builtin(args.robot) for m in mods]
        n = robots[0].n
        lo, hi = np.asarray(robots[0].qlim)
        rng = np.random.default_rng(args.seed)
        configs = [np.ascontiguousarray(lo + (hi - lo) * rng.random(n)) for _ in range(args.n)]
        rows: dict[str, object] = {}
        try:
            import kinema_bare_call

            bare = kinema_bare_call.Bare(n)
            rows["native floor, new 4x4"] = bare.array44
            rows["native floor, new 6xn"] = bare.array6n
        except ImportError:
            print("kinema_bare_call is not installed: no native floor rows")
        for i, r in enumerate(robots):
            rows[f"[{i}] fkine"] = r.fkine
            rows[f"[{i}] jacob0"] = r.jacob0
        best = {k: float("inf") for k in rows}
        gc.disable()
        for _ in range(args.passes):
            for s in range(0, len(configs), 1000):
                w = configs[s : s + 1000]
                for k, f in rows.items():
                    best[k] = min(best[k], window_time(f, w))
        gc.enable()

    print(f"{args.robot}, fastest window of 1000 calls over {args.n} configurations x {args.passes} passes, ns per call")
    for i, w in enumerate(args.wheels):
        print(f"[{i}] {w}")
    for k, t in best.items():
        extra = ""
        floor = best.get("native floor, new 4x4" if k.endswith("fkine") else "native floor, new 6xn")
        if floor and not k.startswith("native"):
            extra = f"  ({t / floor:.2f}x the native floor)"
        print(f"{k:24s} {t:7.1f}{extra}")


if __name__ == "__main__":
    main()
