"""Benchmark: the batched PEM engine against the Exudyn engine on the reference study.

(The speed work's side-by-side benchmark against another checkout, the flop rate and the dense
engine are in benchmarks/bench_speed.py.)

    python benchmarks/bench_pem_engines.py [--repeat 3] [--workers 2] [--reduced 2] [--tight]

1. The full reference study (scenario ``li_zhu_2011``: 200 frequencies x 3 irregularity types, all
   channels) with ``run_pem(engine="batched")``: wall time (median of ``--repeat`` runs; the mean,
   Exudyn's deterministic run, is one of the tasks), the CPU seconds of all processes, and the peak
   memory: resident set of the whole process tree (this process and its workers, sampled every
   20 ms; shared libraries count once per process, so this is an upper bound) and this process's
   own peak.
2. The Exudyn engine on a reduced grid (``--reduced`` frequencies, same band, 3 types) on the same
   workers: wall time, seconds per pseudo-run, and the full study's time extrapolated as
   mean run + sweep x (full tasks / reduced tasks), with the ratio to the batched engine.
3. Agreement of the two engines on the reduced grid: the largest difference of sigma(t) and of the
   PSD map of any channel, relative to that channel's largest sigma (PSD: largest PSD value).
   The Exudyn engine runs at the scenario's working amplitude (1e-4 m) with its default Newton
   tolerances; the rigid bodies' nonlinearity makes its result differ from the linear model by a
   few 1e-6 (it scales with the amplitude). ``--tight`` adds a reference of Exudyn pseudo-runs at
   1e-5 m with Newton tolerances 1e-10 / 1e-8 N (the limit of what Newton meets), which the
   acceptance bound of 1e-6 is checked against.

Run it on an otherwise idle machine: the 2-core machine of the measurements in the issue was
shared with other developers' test runs, and the figures printed are medians for that reason.
"""

from __future__ import annotations

import argparse
import math
import os
import resource
import statistics
import threading
import time
import warnings

import numpy as np

from tb_exudyn.scenario import load_scenario
from tb_exudyn.methods import run_pem


class PeakMemory:
    """Peak resident memory of this process and its children, sampled in a thread."""

    def __init__(self, interval: float = 0.02) -> None:
        self.interval, self.peak, self.own_peak, self._stop = interval, 0, 0, threading.Event()
        try:
            import psutil

            self._proc = psutil.Process()
        except ImportError:  # pragma: no cover - psutil is optional
            self._proc = None
        self._thread = threading.Thread(target=self._run, daemon=True)

    def _run(self) -> None:
        while not self._stop.is_set():
            total = own = self._proc.memory_info().rss
            for p in self._proc.children(recursive=True):
                try:
                    total += p.memory_info().rss
                except Exception:  # noqa: BLE001 - a child may just have exited
                    pass
            self.peak, self.own_peak = max(self.peak, total), max(self.own_peak, own)
            self._stop.wait(self.interval)

    def __enter__(self) -> "PeakMemory":
        if self._proc is not None:
            self._thread.start()
        return self

    def __exit__(self, *exc: object) -> None:
        self._stop.set()
        if self._proc is not None:
            self._thread.join()


def _cpu_seconds() -> float:
    """User + system CPU seconds of this process and of its terminated children."""
    own, kids = resource.getrusage(resource.RUSAGE_SELF), resource.getrusage(resource.RUSAGE_CHILDREN)
    return own.ru_utime + own.ru_stime + kids.ru_utime + kids.ru_stime


def agreement(a, b) -> tuple[float, float, str]:  # noqa: ANN001 - RandomResponse
    """Largest |sigma_a - sigma_b| / max sigma_b and |PSD_a - PSD_b| / max PSD_b over channels."""
    es = np.abs(a.std - b.std).max(axis=1) / np.maximum(b.std.max(axis=1), 1e-300)
    ep = np.abs(a.psd - b.psd).max(axis=(1, 2)) / np.maximum(b.psd.max(axis=(1, 2)), 1e-300)
    return float(es.max()), float(ep.max()), b.channels[int(np.argmax(es))]


def tight_reference(scenario, workers: int):  # noqa: ANN001
    """sigma and PSD of the Exudyn engine at a working amplitude of 1e-5 m with Newton tolerances
    1e-10 / 1e-8 (its runs and reduction with tighter settings)."""
    from tb_exudyn.engines.exudyn_runs import SolverSettings

    sc = scenario.replace(analysis=scenario.analysis.replace(pem_amplitude=1e-5))
    r = run_pem(sc, workers=workers, progress=False, engine="exudyn",
                options=SolverSettings(newton_relative_tolerance=1e-10, newton_absolute_tolerance=1e-8))
    return r.std, r.psd


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--repeat", type=int, default=3, help="batched runs of the full study (median reported)")
    parser.add_argument("--workers", type=int, default=2, help="worker processes of both engines")
    parser.add_argument("--reduced", type=int, default=2, help="frequencies of the Exudyn engine's reduced grid")
    parser.add_argument("--tight", action="store_true", help="also the tight-tolerance Exudyn reference (slow)")
    args = parser.parse_args()
    warnings.simplefilter("ignore")

    sc = load_scenario("li_zhu_2011")
    n_types = len(sc.track.irregularities)
    print(f"scenario {sc.name}: {len(sc.train.vehicles)} cars, {sc.speed_kmh:g} km/h, {sc.analysis.n_freq} frequencies "
          f"x {n_types} types, channels {sc.analysis.channels}, {os.cpu_count()} cores, workers {args.workers}")
    print(f"load average before: {os.getloadavg()[0]:.2f} (the machine may be shared: medians below)")

    # 1. batched, full study
    walls, means, peaks, own, cpus = [], [], [], [], []
    for i in range(args.repeat):
        with PeakMemory() as mem:
            c0 = _cpu_seconds()
            t0 = time.perf_counter()
            r = run_pem(sc, workers=args.workers, progress=False, engine="batched")
            walls.append(time.perf_counter() - t0)
            cpus.append(_cpu_seconds() - c0)
        prov, psd_mib = r.provenance, r.psd.nbytes / 2**20
        del r  # not held while the next run computes
        means.append(prov["mean_seconds"])
        peaks.append(mem.peak)
        own.append(mem.own_peak)
        print(f"  batched run {i + 1}: {walls[-1]:.2f} s (of which the Exudyn mean run {means[-1]:.2f} s in a worker), "
              f"CPU {cpus[-1]:.1f} s (this process and its workers), "
              f"peak RSS: process tree {mem.peak / 2**20:.0f} MiB, this process {mem.own_peak / 2**20:.0f} MiB; "
              f"load {os.getloadavg()[0]:.2f}")
    t_batched = statistics.median(walls)
    print(f"batched engine, full study ({prov['columns']} columns = {2 * prov['columns']} pseudo-runs, "
          f"{prov['tasks'] - 1} column slices and the mean): median {t_batched:.2f} s "
          f"(mean run {statistics.median(means):.2f} s); peak memory: process tree {max(peaks) / 2**20:.0f} MiB, "
          f"this process {max(own) / 2**20:.0f} MiB (ru_maxrss {resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024:.0f} MiB); "
          f"PSD map {psd_mib:.0f} MiB")
    print(f"  CPU seconds of a run (median, all processes): {statistics.median(cpus):.1f} s, i.e. "
          f"{statistics.median(cpus) / args.workers:.1f} s of wall time on {args.workers} otherwise idle cores")
    print(f"  components: {prov['components']}")
    if "contact_check" in prov:
        print(f"  contact description check (max relative difference to the coupling): {prov['contact_check']:.1e}")

    # 2. Exudyn engine, reduced grid
    red = sc.replace(analysis=sc.analysis.replace(n_freq=args.reduced))
    t0 = time.perf_counter()
    ref = run_pem(red, workers=args.workers, progress=False, engine="exudyn")
    t_red = time.perf_counter() - t0
    t_mean = ref.provenance["total_time_s"]
    n_red, n_full = ref.provenance["tasks"], sc.analysis.n_freq * n_types
    per_run = (t_red - t_mean) * args.workers / (2 * n_red)
    t_full = t_mean + (t_red - t_mean) * n_full / n_red
    print(f"Exudyn engine, reduced grid ({args.reduced} frequencies, {n_red} tasks = {2 * n_red} runs): {t_red:.1f} s "
          f"(mean run {t_mean:.1f} s), {per_run:.2f} s per pseudo-run on {args.workers} workers")
    print(f"  extrapolated to the full study ({n_full} tasks = {2 * n_full} runs): {t_full:.0f} s = {t_full / 60:.1f} min; "
          f"ratio to the batched engine {t_full / t_batched:.0f}x")

    # 3. agreement on the reduced grid
    bat = run_pem(red, workers=args.workers, progress=False, engine="batched")
    es, ep, worst = agreement(bat, ref)
    print(f"agreement with the Exudyn engine (default tolerances, 1e-4 m): sigma {es:.1e}, PSD {ep:.1e} "
          f"(worst channel {worst})")
    if args.tight:
        t0 = time.perf_counter()
        std, psd = tight_reference(red, args.workers)
        es = float((np.abs(bat.std - std).max(axis=1) / np.maximum(std.max(axis=1), 1e-300)).max())
        ep = float((np.abs(bat.psd - psd).max(axis=(1, 2)) / np.maximum(psd.max(axis=(1, 2)), 1e-300)).max())
        print(f"agreement with Exudyn at 1e-5 m, Newton 1e-10 / 1e-8 ({time.perf_counter() - t0:.0f} s): "
              f"sigma {es:.1e}, PSD {ep:.1e} (acceptance: 1e-6)")
    print(f"load average after: {os.getloadavg()[0]:.2f}")


if __name__ == "__main__":
    main()
