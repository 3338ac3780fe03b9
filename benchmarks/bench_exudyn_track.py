"""Benchmark: the Exudyn engine with the track layer against the batched engine, and against itself without it.

Problem: the Yang & Yau sprung mass (5750 kg on 1.595e6 N/m) over a simply supported girder, German low vertical
irregularity, PEM on a linear grid over the upper octave the spectrum reaches (its wavelengths end at 1 m: 24-48 Hz
at 180 km/h, 12-24 Hz at 90 km/h, where the track and the point contact differ), the
channels of tests/engines/test_batched_track.py (the car, the deck and the track at mid-span), one worker:

- ``small``: that test's case: a 10 m span, 6 m of approach, 180 km/h; with ``track.structure =
  "ballasted_uic60"`` the track and the deck are one modal body of 270 modes up to 2 kHz;
- ``yang_yau``: the shipped yang_yau_sprung_mass (25 m span, 10 m of approach and run-out, 90 km/h, 1.8 s);
  with the track 535 modes.

Each case runs with and without the track, on the Exudyn and the batched engine, at ``--freqs`` (two numbers of
frequencies, default 2 and 4): the time per frequency is the difference over the added frequencies (the model,
the modes and the mean run cancel), the fixed part what is left at the smaller number (a first run of each engine, not
measured, takes the imports). Times are CPU seconds of
this process and its children (resource.getrusage) beside the wall time, medians over ``--repeat`` runs; the
load average is printed (the machine may be shared). The batched engine's sigma against the Exudyn engine's at
the larger number of frequencies: max over the channels a random input reaches of max_t |sigma_b - sigma_e| /
max_t sigma_e.

Usage::

    python benchmarks/bench_exudyn_track.py [--cases small yang_yau] [--freqs 2 4] [--repeat 1]
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

import numpy as np

try:
    import tb_exudyn  # noqa: F401  (installed, or run from the repository root with PYTHONPATH=.)
except ImportError:  # a plain checkout: use the package next to this folder
    sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from tb_exudyn import load_scenario, run_pem  # noqa: E402

CHANNELS = ("car1.*", "track.span1.mid.*", "bridge.span1.mid.*")


def scenario(case: str, track: bool, n_freq: int):  # noqa: ANN201
    sc = load_scenario("yang_yau_sprung_mass")
    if case == "small":
        sc = sc.replace(bridge=sc.bridge.replace(spans=(10.0,)),
                        track=sc.track.replace(lead_in=6.0, taper_length=3.0, run_out=0.0)).replace(speed_kmh=180.0)
    f_max = 0.96 * sc.speed  # the spectrum's shortest wavelength, 1 m, passes at v / 1 m
    sc = sc.replace(bridge=sc.bridge.replace(track_height=1.0),
                    track=sc.track.replace(structure="ballasted_uic60" if track else ""),
                    analysis=sc.analysis.replace(freq_min=f_max / 2, freq_max=f_max, n_freq=n_freq, freq_spacing="linear",
                                                 channels=CHANNELS if track else CHANNELS[::2]))
    return sc


def cpu_seconds() -> float:
    own, children = resource.getrusage(resource.RUSAGE_SELF), resource.getrusage(resource.RUSAGE_CHILDREN)
    return own.ru_utime + own.ru_stime + children.ru_utime + children.ru_stime


def timed_pem(sc, engine: str):  # noqa: ANN001, ANN201
    cpu, wall = cpu_seconds(), time.perf_counter()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        result = run_pem(sc, engine=engine, workers=1, progress=False)
    return result, cpu_seconds() - cpu, time.perf_counter() - wall


def agreement(got, ref) -> float:  # noqa: ANN001
    assert got.channel_names == ref.channel_names
    scale = ref.std.max(axis=1)
    live = scale > 1e-12
    return float((np.abs(got.std - ref.std)[live].max(axis=1) / scale[live]).max())


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--cases", nargs="+", default=["small", "yang_yau"], choices=["small", "yang_yau"])
    parser.add_argument("--freqs", nargs=2, type=int, default=[2, 4])
    parser.add_argument("--repeat", type=int, default=1)
    args = parser.parse_args(argv)
    lo, hi = sorted(args.freqs)
    for engine in ("exudyn", "batched"):  # imports and first-use costs, not measured
        timed_pem(scenario("small", False, lo), engine)
    print(f"load average {os.getloadavg()}; CPU and wall seconds, medians of {args.repeat}")
    print(f"{'case':9s} {'track':6s} {'engine':8s} {'modes':>6s} {'fixed CPU':>10s} {'CPU/freq':>9s} "
          f"{'wall/freq':>10s} {'sigma vs exudyn':>16s}")
    for case in args.cases:
        for track in (False, True):
            results = {}
            for engine in ("exudyn", "batched"):
                cpu = {n: [] for n in (lo, hi)}
                wall = {n: [] for n in (lo, hi)}
                for _ in range(args.repeat):
                    for n in (lo, hi):
                        r, c, w = timed_pem(scenario(case, track, n), engine)
                        cpu[n].append(c)
                        wall[n].append(w)
                        if n == hi:
                            results[engine] = r
                c_lo, c_hi = statistics.median(cpu[lo]), statistics.median(cpu[hi])
                w_lo, w_hi = statistics.median(wall[lo]), statistics.median(wall[hi])
                per, per_wall = (c_hi - c_lo) / (hi - lo), (w_hi - w_lo) / (hi - lo)
                modes = results[engine].provenance.get("bridge_modes", "")
                err = "" if engine == "exudyn" else f"{agreement(results['batched'], results['exudyn']):.2e}"
                print(f"{case:9s} {str(track):6s} {engine:8s} {modes!s:>6s} {c_lo - lo * per:10.2f} {per:9.2f} "
                      f"{per_wall:10.2f} {err:>16s}", flush=True)
    print(f"load average {os.getloadavg()}")


if __name__ == "__main__":
    main()
