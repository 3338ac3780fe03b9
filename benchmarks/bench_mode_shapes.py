"""Benchmark: rail-level mode shapes of 100 modes at 32 wheel positions (target < 50 us).

This evaluation runs at every wheel at every time step of a train-bridge run, so it must be a few
numpy operations. The bridge is the reference study's (models/bridges/li_zhu_2011_bridge.toml),
reduced to its lowest 100 modes; the 32 positions are the axles of a 4-car train spread over the
bridge and its approaches (some are off the bridge, as in a real run).

Usage::

    python benchmarks/bench_mode_shapes.py [--modes 100] [--positions 32] [--repeat 15] [--number 2000]

Prints the median and the minimum over ``repeat`` runs of ``number`` evaluations each, in
microseconds per evaluation, for the evaluator alone and through ModalBridge.rail_shapes; exits
with status 1 if the median through ModalBridge exceeds the target.
"""

from __future__ import annotations

import argparse
import sys
import time
import timeit

from pathlib import Path

import numpy as np

try:
    import tb_exudyn  # noqa: F401  (installed, or run from the repository root with PYTHONPATH=.)
except ImportError:  # a plain checkout: use the package next to this folder
    sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from tb_exudyn.scenario import load_bridge  # noqa: E402
from tb_exudyn.structure import modal_bridge  # noqa: E402

TARGET_US = 50.0


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--modes", type=int, default=100)
    parser.add_argument("--positions", type=int, default=32)
    parser.add_argument("--repeat", type=int, default=15)
    parser.add_argument("--number", type=int, default=2000)
    args = parser.parse_args(argv)

    t0 = time.perf_counter()
    bridge = modal_bridge(load_bridge("li_zhu_2011_bridge"), 1000.0, max_modes=args.modes)
    t_build = time.perf_counter() - t0
    x = np.sort(np.random.default_rng(1).uniform(-10.0, bridge.length + 10.0, args.positions))
    evaluator = bridge.rail_shape_function

    print(f"bridge: {bridge.n_modes} modes up to {bridge.frequencies[-1]:.1f} Hz, "
          f"{args.positions} positions (FE model and modes: {t_build:.2f} s)")
    worst = 0.0
    for label, fn in (("evaluator", lambda: evaluator(x)), ("ModalBridge.rail_shapes", lambda: bridge.rail_shapes(x))):
        times = np.array(timeit.repeat(fn, number=args.number, repeat=args.repeat)) / args.number * 1e6
        print(f"{label:>24}: median {np.median(times):6.1f} us, min {times.min():6.1f} us "
              f"({args.repeat} runs x {args.number})")
        worst = float(np.median(times))
    ok = worst < TARGET_US
    print(f"target < {TARGET_US:g} us: {'met' if ok else 'NOT met'}")
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
