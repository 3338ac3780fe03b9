"""Benchmark: the EN 1991-2 check as an engineer runs it (issues 25, 48).

    python benchmarks/bench_check.py [--cases full stochastic] [--repeat 3] [--workers 2] [--speeds 30]

Each case is the command ``tb-exudyn check ...`` run in a child process (as typed, figures and page
included; its output folder a fresh temporary one), ``--repeat`` times, one at a time:

- ``full``: ``tb-exudyn check li_zhu_2011_bridge --line-speed-kmh 250``: HSLM-A1 ... A10 over the speed
  series of 6.4.6.2 in the three mass cases (lower and upper bound of the ballast, nominal), every
  criterion of EN 1990 A2.4.4 (LM71 / SW/0 deformations, comfort, lateral frequency). Target: 60 s on 2
  cores;
- ``stochastic``: ``tb-exudyn check li_zhu_2011_bridge --line-speed-kmh 250 --trains ice_mttm --stochastic
  --stochastic-speeds V1,...,V30``: ice_mttm's moving-force rows and its stochastic column (one PEM per
  speed, li_zhu_2011's track and analysis) at ``--speeds`` speeds spread evenly over the series (40 m/s
  to 1.2 x 250 km/h). Target: 60 s on 2 cores for 30 speeds.

Per run: the wall time, the CPU seconds of the command and of every process it started (``resource``'s
children: the pool's workers and the compiled code's warm-up are reaped before it ends) and the load
average before it (``os.getloadavg``: a wall time under load is not a quiet one). Then per case the
median and the minimum wall time, the median CPU seconds, and whether the median met its target; exit
status 1 if one did not. Run it on a quiet machine for the numbers docs/en1991.md states.
"""

from __future__ import annotations

import argparse
import os
import resource
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
BRIDGE, LINE_SPEED_KMH = "li_zhu_2011_bridge", 250.0
TARGETS_S = {"full": 60.0, "stochastic": 60.0}


def speeds(n: int) -> list[float]:
    """``n`` speeds evenly over the series' range, 144 km/h (40 m/s) to 1.2 x the line speed [km/h]."""
    low, high = 144.0, 1.2 * LINE_SPEED_KMH
    return [round(low + (high - low) * i / (n - 1), 3) for i in range(n)] if n > 1 else [high]


def command(case: str, out: Path, workers: int | None, n_speeds: int) -> list[str]:
    argv = [sys.executable, "-m", "tb_exudyn", "check", BRIDGE, "--line-speed-kmh", f"{LINE_SPEED_KMH:g}",
            "--out", str(out), "--no-progress"]
    if case == "stochastic":
        argv += ["--trains", "ice_mttm", "--stochastic", "--stochastic-speeds",
                 ",".join(f"{v:g}" for v in speeds(n_speeds))]
    return argv + (["--workers", str(workers)] if workers else [])


def children_cpu() -> float:
    r = resource.getrusage(resource.RUSAGE_CHILDREN)
    return r.ru_utime + r.ru_stime


def run_once(case: str, workers: int | None, n_speeds: int) -> tuple[float, float, float, str]:
    """(wall s, CPU s, load average before, the command's last line)."""
    env = {**os.environ, "PYTHONPATH": str(ROOT), "MPLBACKEND": "Agg"}
    with tempfile.TemporaryDirectory(prefix="bench_check_") as tmp:
        load = os.getloadavg()[0]
        cpu0, t0 = children_cpu(), time.perf_counter()
        proc = subprocess.run(command(case, Path(tmp) / "out", workers, n_speeds), env=env, capture_output=True,
                              text=True)
        wall, cpu = time.perf_counter() - t0, children_cpu() - cpu0
    if proc.returncode != 0:
        raise SystemExit(f"{case}: exit {proc.returncode}: {proc.stderr.strip()[-2000:]}")
    return wall, cpu, load, proc.stdout.strip().splitlines()[-1]


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--cases", nargs="+", default=list(TARGETS_S), choices=list(TARGETS_S))
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--workers", type=int, default=None, help="the command's --workers (default: its own)")
    parser.add_argument("--speeds", type=int, default=30, help="stochastic speeds of the 'stochastic' case")
    args = parser.parse_args(argv)
    failed = False
    for case in args.cases:
        runs = []
        for i in range(args.repeat):
            wall, cpu, load, last = run_once(case, args.workers, args.speeds)
            runs.append((wall, cpu))
            print(f"{case} run {i + 1}: {wall:.1f} s wall, {cpu:.1f} CPU s, load average {load:.2f} before; {last}",
                  flush=True)
        walls = [w for w, _ in runs]
        med, target = statistics.median(walls), TARGETS_S[case]
        failed |= med > target
        print(f"{case}: median {med:.1f} s (min {min(walls):.1f} s), median CPU {statistics.median(c for _, c in runs):.1f} s "
              f"over {args.repeat} runs; target {target:g} s {'met' if med <= target else 'MISSED'}", flush=True)
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
