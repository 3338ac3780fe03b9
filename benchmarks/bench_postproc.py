"""Benchmark: the main job's post-processing (issue 49: figures and report at most 1.5x the run without).

    python benchmarks/bench_postproc.py [--repeat 3] [--scenario li_zhu_2011] [--workers N]

README's main job, ``tb-exudyn run`` (li_zhu_2011, PEM on the batched engine), is run in a child process
with its figures and report and with ``--no-figures``, each into a fresh temporary ``--out``: one
warm-up run first (the compiled code's cache warm, the files in the page cache), then ``--repeat``
pairs, the two variants alternating so that a change of load hits both alike.

Per run: the wall time, the CPU seconds of the command and of every process it started (``resource``'s
children: the PEM's and the figures' workers are reaped before the command ends) and the load average
before it. Then per variant the median wall time and the median CPU seconds, and the ratios "with /
without" of both, measured in this one run; the figures written (PNG files under --out) and the size
of --out with and without them. The target is a wall ratio of at most 1.5 on 2 quiet cores; under load
the wall ratio is not a quiet one (the CPU ratio says what the post-processing costs), and the exit
status is 1 only when the wall ratio misses the target on a machine whose load average stayed below 0.5.
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
TARGET_RATIO = 1.5
QUIET_LOAD = 0.5


def children_cpu() -> float:
    r = resource.getrusage(resource.RUSAGE_CHILDREN)
    return r.ru_utime + r.ru_stime


def folder_size(folder: Path) -> tuple[int, int]:
    """(bytes of every file under ``folder``, PNG files among them)."""
    files = [p for p in folder.rglob("*") if p.is_file()]
    return sum(p.stat().st_size for p in files), sum(p.suffix == ".png" for p in files)


def run_once(scenario: str, figures: bool, workers: int | None) -> dict:
    """One ``tb-exudyn run`` into a fresh folder: wall s, CPU s, load before, bytes, figures, last line."""
    env = {**os.environ, "PYTHONPATH": str(ROOT), "MPLBACKEND": "Agg"}
    with tempfile.TemporaryDirectory(prefix="bench_postproc_") as tmp:
        out = Path(tmp) / "out"
        argv = [sys.executable, "-m", "tb_exudyn", "run", scenario, "--out", str(out), "--no-progress"]
        argv += [] if figures else ["--no-figures"]
        argv += ["--workers", str(workers)] if workers else []
        load = os.getloadavg()[0]
        cpu0, t0 = children_cpu(), time.perf_counter()
        proc = subprocess.run(argv, env=env, capture_output=True, text=True, cwd=tmp)
        wall, cpu = time.perf_counter() - t0, children_cpu() - cpu0
        if proc.returncode != 0:
            raise SystemExit(f"{' '.join(argv)}: exit {proc.returncode}: {proc.stderr.strip()[-2000:]}")
        size, pngs = folder_size(out)
    return {"wall": wall, "cpu": cpu, "load": load, "bytes": size, "figures": pngs,
            "last": proc.stdout.strip().splitlines()[-1]}


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=3, help="pairs of runs (default 3)")
    parser.add_argument("--scenario", default="li_zhu_2011", help="default: li_zhu_2011 (README's main job)")
    parser.add_argument("--workers", type=int, default=None, help="the command's --workers (default: its own)")
    args = parser.parse_args(argv)
    warm = run_once(args.scenario, True, args.workers)
    print(f"warm-up: {warm['wall']:.1f} s wall, {warm['cpu']:.1f} CPU s; {warm['last']}", flush=True)
    runs: dict[bool, list[dict]] = {True: [], False: []}
    for i in range(args.repeat):
        for figures in (False, True):
            r = run_once(args.scenario, figures, args.workers)
            runs[figures].append(r)
            print(f"pair {i + 1}, {'figures+report' if figures else 'no figures    '}: {r['wall']:5.1f} s wall, "
                  f"{r['cpu']:5.1f} CPU s, load average {r['load']:.2f} before, {r['figures']} figures, "
                  f"{r['bytes'] / 1e6:.1f} MB", flush=True)
    med = {f: {k: statistics.median(r[k] for r in runs[f]) for k in ("wall", "cpu", "bytes")} for f in runs}
    wall_ratio, cpu_ratio = med[True]["wall"] / med[False]["wall"], med[True]["cpu"] / med[False]["cpu"]
    loads = [r["load"] for f in runs for r in runs[f]]
    print(f"without figures: median {med[False]['wall']:.1f} s wall, {med[False]['cpu']:.1f} CPU s, "
          f"{med[False]['bytes'] / 1e6:.1f} MB")
    print(f"with figures:    median {med[True]['wall']:.1f} s wall, {med[True]['cpu']:.1f} CPU s, "
          f"{med[True]['bytes'] / 1e6:.1f} MB, {runs[True][-1]['figures']} figures")
    print(f"ratio with/without: wall {wall_ratio:.2f}x (target <= {TARGET_RATIO:g}x), CPU {cpu_ratio:.2f}x; "
          f"post-processing adds {med[True]['wall'] - med[False]['wall']:.1f} s wall, "
          f"{med[True]['cpu'] - med[False]['cpu']:.1f} CPU s; load average {min(loads):.2f} to {max(loads):.2f}")
    quiet = max(loads) < QUIET_LOAD
    if not quiet:
        print(f"(load average reached {max(loads):.2f}: the wall ratio is not a quiet one)")
    return 1 if quiet and wall_ratio > TARGET_RATIO else 0


if __name__ == "__main__":
    sys.exit(main())
