"""Benchmark: the EN 1991-2 check of all ten HSLM-A trains over the speed series (issue 25's target).

Problem: ``check(BRIDGE, 250 km/h, trains=hslm_a)`` with figures off, as ``tb-exudyn check BRIDGE
--line-speed-kmh 250 --no-figures`` computes it (the finite-element modes, every train's speed series
of 6.4.6.2 refined near its resonances, one integration per train); nothing is written. Targets: at
most 30 s for single_span_32m and 60 s for li_zhu_2011_bridge on 2 cores.

Usage::

    python benchmarks/bench_check.py [--repeat 5] [--bridges single_span_32m li_zhu_2011_bridge]

Prints, per bridge, the median and the minimum wall time over ``repeat`` runs, the rows and the
modes; exits with status 1 if a median exceeds its target.
"""

from __future__ import annotations

import argparse
import statistics
import sys
import time
from pathlib import Path

try:
    import tb_exudyn  # noqa: F401  (installed, or run from the repository root with PYTHONPATH=.)
except ImportError:  # a plain checkout: use the package next to this folder
    sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from tb_exudyn.codes import check  # noqa: E402

TARGETS_S = {"single_span_32m": 30.0, "li_zhu_2011_bridge": 60.0}
LINE_SPEED_KMH = 250.0


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=5)
    parser.add_argument("--bridges", nargs="+", default=list(TARGETS_S))
    args = parser.parse_args(argv)
    failed = False
    for bridge in args.bridges:
        times, result = [], None
        for _ in range(args.repeat):
            t0 = time.perf_counter()
            result = check(bridge, LINE_SPEED_KMH, trains=["hslm_a"])
            times.append(time.perf_counter() - t0)
        med = statistics.median(times)
        target = TARGETS_S.get(bridge)
        verdict = "" if target is None else (f" (target {target:g} s: {'met' if med <= target else 'MISSED'})")
        failed |= target is not None and med > target
        print(f"{bridge}: HSLM-A1 ... A10 at line speed {LINE_SPEED_KMH:g} km/h, {len(result)} rows, modes "
              + ", ".join(f"{f:.3g}" for f in result.mode_frequencies) + " Hz")
        print(f"  median {med:.2f} s, min {min(times):.2f} s over {args.repeat} runs{verdict}")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
