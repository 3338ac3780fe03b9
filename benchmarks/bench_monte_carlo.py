"""Benchmark: Monte Carlo and PEM on the reference study's verification case (li_zhu_2011_mc_check).

One ICE motor car over one 32 m span at 220 km/h, German low vertical + alignment + cross-level,
time step 1 ms (3.3 s crossing: 3310 steps per run), on a local pool of ``--workers`` processes.

- Monte Carlo: wall time of ``--samples`` samples (default 40; ``--full``: the study's 500), the
  median single-run time over the samples, and the wall time extrapolated linearly to 500 samples.
- PEM: wall time of the sweep on ``--pem-frequencies`` frequencies of the scenario's band
  0.3-60 Hz (default 20, i.e. 120 runs; ``--full``: the scenario's 200, 1200 runs), extrapolated
  linearly to the 200 frequencies (every run costs the same, whatever its frequency).

Each wall time includes starting the pool (spawned processes import Exudyn and build the model)
and the driver's own deterministic run / model build; the extrapolation scales them too, so it
slightly overestimates. Run: python benchmarks/bench_monte_carlo.py [--samples N] [--pem-frequencies M]
[--workers W] [--full]
"""

from __future__ import annotations

import argparse
import os
import sys
import time
import warnings
from pathlib import Path

try:
    import tb_exudyn  # noqa: F401
except ImportError:  # run from a checkout without installing: put the repository root on the path
    sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

import tb_exudyn as tbx
from tb_exudyn.methods import run_monte_carlo
from tb_exudyn.methods import run_pem

FULL_SAMPLES = 500


def main(argv: list[str] | None = None) -> None:
    p = argparse.ArgumentParser(description="Monte Carlo and PEM wall times on li_zhu_2011_mc_check")
    p.add_argument("--samples", type=int, default=40)
    p.add_argument("--pem-frequencies", type=int, default=20)
    p.add_argument("--workers", type=int, default=2)
    p.add_argument("--full", action="store_true", help="500 samples and all 200 PEM frequencies (slow)")
    args = p.parse_args(argv)
    warnings.simplefilter("ignore", UserWarning)
    sc = tbx.load_scenario("li_zhu_2011_mc_check")
    n_full_freq = sc.analysis.n_freq
    n = FULL_SAMPLES if args.full else args.samples
    m = n_full_freq if args.full else args.pem_frequencies

    print(f"{os.cpu_count()} cores; load average before: {os.getloadavg()[0]:.2f} (other processes slow the pool)")
    t0 = time.perf_counter()
    mc = run_monte_carlo(sc, n_samples=n, seed=1, workers=args.workers, progress=False, engine="exudyn")
    t_mc = time.perf_counter() - t0
    run = mc.provenance["sample_run_time_median_s"]
    steps = round(mc.time[-1] / sc.analysis.time_step)
    print(f"Monte Carlo, {sc.name}: {n} samples on {args.workers} workers: {t_mc:.1f} s wall "
          f"({t_mc / n:.3f} s per sample); one run: median {run:.3f} s ({1e6 * run / steps:.0f} us/step, "
          f"{steps} steps)")
    if n != FULL_SAMPLES:
        print(f"  extrapolated to {FULL_SAMPLES} samples: {t_mc * FULL_SAMPLES / n:.0f} s "
              f"({t_mc * FULL_SAMPLES / n / 60:.1f} min)")

    sc_pem = sc.replace(analysis=sc.analysis.replace(n_freq=m))
    t0 = time.perf_counter()
    pem = run_pem(sc_pem, workers=args.workers, progress=False, keep_psd=False, engine="exudyn")
    t_pem = time.perf_counter() - t0
    runs = 2 * pem.provenance["tasks"]
    print(f"PEM, {sc.name}: {m} frequencies x {len(pem.types)} types = {runs} runs on {args.workers} workers: "
          f"{t_pem:.1f} s wall ({t_pem / runs:.3f} s per run)")
    print(f"load average after: {os.getloadavg()[0]:.2f}")
    if m != n_full_freq:
        print(f"  extrapolated to {n_full_freq} frequencies ({runs * n_full_freq // m} runs): "
              f"{t_pem * n_full_freq / m:.0f} s ({t_pem * n_full_freq / m / 60:.1f} min)")


if __name__ == "__main__":
    main()
