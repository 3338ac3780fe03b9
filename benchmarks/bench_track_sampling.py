"""Benchmark: 10 km of track profile at 0.05 m spacing (German low vertical, wavelengths 1-120 m).

FFT generator (``fft_profile``, cubic interpolant included): median of 5 runs; target < 1 s.
Harmonic generator (``harmonic_profile``, exact sum) for comparison, with enough frequencies for its
period to exceed the 10 km track, evaluated at the same 200 001 points: one run (it is slow).

Run: python benchmarks/bench_track_sampling.py [--skip-harmonic]
"""

from __future__ import annotations

import math
import statistics
import sys
import time
from pathlib import Path

import numpy as np

try:
    import tb_exudyn.track  # noqa: F401
except ImportError:  # run from a checkout without installing: put the repository root on the path
    sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from tb_exudyn.track import fft_profile, get_spectrum, harmonic_profile, sample_rng

LENGTH, DX, RUNS = 10_000.0, 0.05, 5


def _time(fn) -> float:
    t0 = time.perf_counter()
    fn()
    return time.perf_counter() - t0


def main(skip_harmonic: bool = False) -> None:
    spec = get_spectrum("german_low.vertical")
    band = spec.default_band
    fft_times = [_time(lambda i=i: fft_profile(spec, sample_rng(1, i), LENGTH, DX, band)) for i in range(RUNS)]
    n_points = int(round(LENGTH / DX)) + 1
    fft_median = statistics.median(fft_times)
    print(f"fft_profile: {LENGTH / 1000:g} km at {DX} m ({n_points} points): median of {RUNS} runs "
          f"{fft_median:.3f} s (runs: {', '.join(f'{t:.3f}' for t in fft_times)}); target < 1 s: "
          f"{'PASS' if fft_median < 1.0 else 'FAIL'}")
    if skip_harmonic:
        return
    n_freq = math.ceil((band[1] - band[0]) * LENGTH / (2 * math.pi))  # period 2 pi / d_omega >= LENGTH
    x = np.arange(n_points) * DX
    t_h = _time(lambda: harmonic_profile(spec, sample_rng(1, 0), n_freq, band).value(x))
    print(f"harmonic_profile: {n_freq} frequencies x {n_points} points: 1 run {t_h:.2f} s "
          f"({t_h / fft_median:.0f}x the FFT generator)")


if __name__ == "__main__":
    main(skip_harmonic="--skip-harmonic" in sys.argv)
