"""Benchmark: Monte Carlo of the linear model (batched engine) against the Exudyn Monte Carlo.

For each scenario (default: the verification case li_zhu_2011_mc_check, one car over one span, and
the full reference study li_zhu_2011, four cars over three spans), German low vertical, alignment and
cross-level profiles, seed 1:

- the linear Monte Carlo of ``--samples`` samples (default 500, the study's count) on a local pool
  of ``--workers`` processes: median wall time of ``--repeats`` runs (each starts its pool, builds
  the model in every worker and runs Exudyn's deterministic mean), the peak resident memory of this
  process and of the largest worker;
- the Exudyn Monte Carlo on the first ``--exudyn-samples`` of the same samples (default 8), its wall
  time extrapolated linearly to ``--samples``, and the ratio of the two engines;
- the difference between the engines sample by sample (the samples are the same): max over samples
  and times of |y_linear - y_exudyn| / max_t sigma_exudyn for some key channels. What it measures is
  the Exudyn model's nonlinearity at the sample's amplitude, mostly the geometric stiffness of the
  suspension preload under gravity, which the linear model (linearised about rest) leaves out (see
  docs/findings.md, section 6).

Run: python benchmarks/bench_monte_carlo_linear.py [--scenarios A B] [--samples N] [--repeats R]
[--exudyn-samples M] [--workers W]
"""

from __future__ import annotations

import argparse
import os
import resource
import statistics
import sys
import time
import warnings
from pathlib import Path

try:
    import tb_exudyn  # noqa: F401
except ImportError:  # run from a checkout without installing: put the repository root on the path
    sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

import numpy as np

import tb_exudyn as tbx
from tb_exudyn.methods import run_monte_carlo

KEY_CHANNELS = ("bridge.span1.mid.disp_z", "bridge.span1.mid.disp_y", "bridge.span1.mid.acc_y",
                "car1.body.acc_z", "car1.body.acc_y", "car1.body.disp_rx", "car1.axle1.force_y",
                "car1.axle1.left.force_z")


def _peak_mb() -> tuple[float, float]:
    """Peak resident memory [MB] of this process and of the largest child process so far (Linux: kB)."""
    return (resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024,
            resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss / 1024)


def bench(name: str, n: int, repeats: int, n_exudyn: int, workers: int) -> None:
    sc = tbx.load_scenario(name)
    times = []
    for _ in range(repeats):
        t0 = time.perf_counter()
        lin = run_monte_carlo(sc, n_samples=n, seed=1, workers=workers, progress=False, engine="batched")
        times.append(time.perf_counter() - t0)
    own, child = _peak_mb()
    t_lin = statistics.median(times)
    print(f"\n{name}: {len(lin.channels)} channels, {lin.time.size} output times, "
          f"{round(lin.time[-1] / sc.analysis.time_step)} steps; blocks {lin.provenance['sample_blocks']}")
    print(f"  linear Monte Carlo, {n} samples on {workers} workers: median {t_lin:.2f} s of {repeats} "
          f"({', '.join(f'{t:.2f}' for t in times)}); Exudyn's mean run {lin.provenance['mean_seconds']:.2f} s; "
          f"peak memory: main {own:.0f} MB, largest worker {child:.0f} MB")
    if n_exudyn < 1:
        return
    t0 = time.perf_counter()
    ref = run_monte_carlo(sc, n_samples=max(2, n_exudyn), seed=1, workers=workers, progress=False, keep_samples=True, engine="exudyn")
    t_exu = time.perf_counter() - t0
    m = ref.n_samples
    extrapolated = t_exu * n / m
    print(f"  Exudyn Monte Carlo, {m} samples on {workers} workers: {t_exu:.1f} s (median run "
          f"{ref.provenance['sample_run_time_median_s']:.2f} s), extrapolated to {n}: {extrapolated:.0f} s "
          f"({extrapolated / 60:.1f} min); ratio {extrapolated / t_lin:.0f}x")
    few = run_monte_carlo(sc, n_samples=m, seed=1, workers=1, progress=False, keep_samples=True, engine="batched")
    print(f"  linear minus Exudyn, same {m} samples: max |difference| / max sigma_Exudyn")
    for c in KEY_CHANNELS:
        if c in ref.channels:
            i = ref.index(c)
            d = np.abs(few.samples[:, i] - ref.samples[:, i]).max() / ref.std[i].max()
            print(f"    {c:28s} {d:.2e}")


def main(argv: list[str] | None = None) -> None:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--scenarios", nargs="+", default=["li_zhu_2011_mc_check", "li_zhu_2011"])
    p.add_argument("--samples", type=int, default=500)
    p.add_argument("--repeats", type=int, default=3)
    p.add_argument("--exudyn-samples", type=int, default=8)
    p.add_argument("--workers", type=int, default=2)
    args = p.parse_args(argv)
    warnings.simplefilter("ignore", UserWarning)
    print(f"{os.cpu_count()} cores; load average before: {os.getloadavg()[0]:.2f}")
    for name in args.scenarios:
        bench(name, args.samples, args.repeats, args.exudyn_samples, args.workers)
    print(f"\nload average after: {os.getloadavg()[0]:.2f}")


if __name__ == "__main__":
    main()
