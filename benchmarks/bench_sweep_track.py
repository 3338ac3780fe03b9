"""Benchmark: a speed sweep with a track structure, its track solved once (shared) against once per speed.

Problem: one ICE trailer (car15, li_zhu_2011's) over the tests' 10 m span of the VBI-2D girder
(tests/builder/test_track_scenario.py), li_zhu_2011's three irregularities, the ballasted UIC60 track reaching
``--approach`` m before and after the span (track.structure_approach), its modes cut at ``--cutoff`` Hz with the
static correction, PEM at ``--n-freq`` frequencies, swept over ``--speeds`` speeds from 200 km/h on the batched
engine. The speed rule scales the lead-in with the speed; the cut rails are placed by the bridge, so every speed
has the same track-and-deck body, which the sweep's parent solves (its modes and the static correction) and its
workers keep (docs/track.md section 8).

Modes (each a fresh state of this process's track cache, run ``--repeat`` times, the median):

- ``shared``: the sweep as it is (one worker: in this process, the parent's track kept by every speed);
- ``per speed``: every speed solves its own track again (the cache emptied at each speed's task: what a
  sweep did when each speed's lead-in moved the supports), one worker;
- with ``--workers 2`` also ``shared, 2 workers`` (the parent's track sent with the workers' set-up) and
  ``per worker, 2 workers`` (not sent: each worker solves it once for its speeds). CPU seconds of this process
  and its finished children (resource.getrusage), so a pool's spawn and imports are in them.

Usage::

    python benchmarks/bench_sweep_track.py [--speeds 3] [--repeat 3] [--approach 6] [--cutoff 300] [--workers 2]

The defaults are docs/track.md section 8's run (there with ``--repeat 1`` under load); about 3 CPU-minutes.

Prints per mode the median CPU and wall seconds, the track solves in this process and their CPU seconds, and the
saving against ``per speed``.
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

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "tests" / "builder"))


def _scenario(approach: float, cutoff: float, n_freq: int):  # noqa: ANN202
    import tb_exudyn as tbx
    from test_track_scenario import _scenario as tests_case

    li = tbx.load_scenario("li_zhu_2011")
    sc = tests_case(track_mode_max_frequency=cutoff, n_freq=n_freq, freq_min=20.0, freq_max=40.0)
    return sc.replace(train=li.train.replace(vehicles=(li.train.vehicles[1],)), speed_kmh=200.0,
                      track=sc.track.replace(lead_in=10.0, run_out=7.0, structure_approach=approach, taper_length=3.0,
                                             irregularities=li.track.irregularities))


def _cpu() -> float:
    own, kids = resource.getrusage(resource.RUSAGE_SELF), resource.getrusage(resource.RUSAGE_CHILDREN)
    return own.ru_utime + own.ru_stime + kids.ru_utime + kids.ru_stime


def run(mode: str, base, speeds, workers: int) -> tuple[float, float, list[float]]:  # noqa: ANN001
    """(CPU s, wall s, the CPU s of each track solve in this process) of one sweep in ``mode``."""
    from tb_exudyn.methods import sweep
    from tb_exudyn.system import track_bridge

    solves: list[float] = []
    solve, work, share = track_bridge.track_and_deck, sweep.SpeedWorker.work, sweep.shared_tracks

    def counted(*args, **kwargs):  # noqa: ANN002, ANN003, ANN202
        t = time.process_time()
        out = solve(*args, **kwargs)
        solves.append(time.process_time() - t)
        return out

    def fresh(self, built, task):  # noqa: ANN001, ANN202 - every speed its own track
        track_bridge._LAST.clear()
        return work(self, built, task)

    track_bridge._LAST.clear()
    track_bridge.track_and_deck = counted
    if mode.startswith("per speed"):
        sweep.SpeedWorker.work = fresh
    if mode.startswith("per worker"):
        sweep.shared_tracks = lambda *a: ()
    try:
        c0, t0 = _cpu(), time.perf_counter()
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            sweep.run_sweep(base, speeds, engine="batched", workers=workers, progress=False)
        return _cpu() - c0, time.perf_counter() - t0, solves
    finally:
        track_bridge.track_and_deck, sweep.SpeedWorker.work, sweep.shared_tracks = solve, work, share


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--speeds", type=int, default=3)
    p.add_argument("--repeat", type=int, default=3)
    p.add_argument("--approach", type=float, default=6.0)
    p.add_argument("--cutoff", type=float, default=300.0)
    p.add_argument("--n-freq", type=int, default=2)
    p.add_argument("--workers", type=int, default=2)
    a = p.parse_args()
    base = _scenario(a.approach, a.cutoff, a.n_freq)
    speeds = [200.0 + 20.0 * i for i in range(a.speeds)]
    modes = ["shared", "per speed"] + (["shared, 2 workers", "per worker, 2 workers"] if a.workers > 1 else [])
    print(f"car15 on the 10 m span, track {a.approach:g} m beyond it, modes up to {a.cutoff:g} Hz, {a.n_freq} "
          f"frequencies, speeds {speeds} km/h; load {os.getloadavg()[0]:.2f}")
    rows = {}
    for mode in modes:
        w = 2 if "2 workers" in mode else 1
        got = [run(mode, base, speeds, w) for _ in range(a.repeat)]
        cpu, wall = statistics.median(g[0] for g in got), statistics.median(g[1] for g in got)
        solves = got[-1][2]
        rows[mode] = cpu
        print(f"{mode:>24}: CPU {cpu:7.2f} s  wall {wall:7.2f} s  track solves here {len(solves)} "
              f"({sum(solves):.2f} CPU-s; {', '.join(f'{s:.2f}' for s in solves)})")
    print(f"saving, shared against per speed (one worker): {rows['per speed'] - rows['shared']:.2f} CPU-s "
          f"({100 * (1 - rows['shared'] / rows['per speed']):.0f} %); load {os.getloadavg()[0]:.2f}")


if __name__ == "__main__":
    main()
